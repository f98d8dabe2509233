"""``patternfit edit``: writes a new file, never the input unless asked, carries the mesh."""

import json

import numpy as np
from typer.testing import CliRunner

from patternfit.cli.main import app
from patternfit.mesh import GarmentMesh, mesh_pattern
from patternfit.pattern import load_pattern, save_pattern

from scenes import two_panels

runner = CliRunner()


def setup(tmp_path):
    p = two_panels()
    save_pattern(p, tmp_path / "p.json", units="cm")
    mesh_pattern(p, triangles=300).save(tmp_path / "p.npz")
    return tmp_path / "p.json", tmp_path / "p.npz"


def test_edit_writes_new_pattern_and_mesh(tmp_path):
    src, mesh = setup(tmp_path)
    before = src.read_bytes()
    r = runner.invoke(app, ["edit", str(src), "edit-curve", "--panel", "A", "--edge", "top",
                            "--dy", "0.05", "--out", str(tmp_path / "q.json"), "--mesh",
                            str(mesh), "--json"])
    assert r.exit_code == 0, r.output
    info = json.loads(r.stdout)
    assert info["mesh"]["inverted_triangles"] == 0 and info["mesh"]["moved_panels"] == ["A"]
    assert src.read_bytes() == before
    q = load_pattern(tmp_path / "q.json")
    assert q.panel("A").edge("top").kind == "quadratic"
    assert json.loads((tmp_path / "q.json").read_text())["units"] == "cm"
    m2 = GarmentMesh.load(tmp_path / "q.npz")
    assert np.array_equal(m2.triangles, GarmentMesh.load(mesh).triangles)


def test_refuses_to_overwrite_input_and_invalid_edits(tmp_path):
    src, _ = setup(tmp_path)
    before = src.read_bytes()
    r = runner.invoke(app, ["edit", str(src), "move-point", "--panel", "A", "--edge", "left",
                            "--dx", "-0.01", "--out", str(src)])
    assert r.exit_code == 2 and "in-place" in r.output
    r = runner.invoke(app, ["edit", str(src), "move-point", "--panel", "A", "--edge", "top",
                            "--dy", "0.05", "--out", str(tmp_path / "r.json")])
    assert r.exit_code == 2 and "--partner" in r.output
    assert not (tmp_path / "r.json").exists()
    r = runner.invoke(app, ["edit", str(src), "spin", "--out", str(tmp_path / "r.json")])
    assert r.exit_code == 2 and "unknown operation" in r.output
    assert src.read_bytes() == before
    r = runner.invoke(app, ["edit", str(src), "move-point", "--panel", "A", "--edge", "left",
                            "--dx", "-0.01", "--in-place"])
    assert r.exit_code == 0, r.output
    assert load_pattern(src).panel("A").edge("left").start[0] == -0.01


def test_dart_insert_rebuilds_mesh(tmp_path):
    src, mesh = setup(tmp_path)
    r = runner.invoke(app, ["edit", str(src), "insert-dart", "--panel", "A", "--dart", "d",
                            "--centre", "0.2,0.3", "--length", "0.2", "--width", "0.03",
                            "--out", str(tmp_path / "d.json"), "--mesh", str(mesh), "--json"])
    assert r.exit_code == 0, r.output
    assert json.loads(r.stdout)["mesh"]["remeshed_panels"] == "all"
    m = GarmentMesh.load(tmp_path / "d.npz")
    assert len(m.loops(0)) == 2
