"""``patternfit bodies`` and ``patternfit body`` commands."""

import json

import trimesh
from typer.testing import CliRunner

from patternfit.cli.main import app

runner = CliRunner()


def test_bodies_json_lists_measurements():
    res = runner.invoke(app, ["bodies", "--json"])
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    names = {b["name"] for b in data["bodies"]}
    assert {"male_heavy", "female_thin", "male_thin"} <= names
    assert all(b["measurements_m"]["waist"] > 0.5 for b in data["bodies"])
    assert data["aliases"]["fat man"] == "male_heavy"


def test_bodies_writes_a_mesh(tmp_path):
    out = tmp_path / "fat.ply"
    res = runner.invoke(app, ["bodies", "fat man", "--out", str(out)])
    assert res.exit_code == 0, res.output
    mesh = trimesh.load(out, process=False)
    assert mesh.is_watertight and 1.7 < mesh.extents[1] < 1.9


def test_unknown_body_fails_clearly():
    res = runner.invoke(app, ["bodies", "giant"])
    assert res.exit_code == 2
    assert "female_thin" in res.output


def test_help():
    for cmd in ("bodies", "body"):
        assert runner.invoke(app, [cmd, "--help"]).exit_code == 0
