"""The bodies a batch drapes: body sets, names and patterns, a folder of meshes written by
another tool (trimesh), and the refusals; the population set spans a size chart."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from patternfit.api import BodyMeshError, list_body_sets, read_bodies, read_body


def test_the_population_spans_womens_and_mens_sizes():
    sets = list_body_sets()
    names = sets["population"]
    assert len(names) >= 10 and not set(names) & set(sets["builtin"])
    assert names[:2] == ["men_xs", "men_s"] or names[:2] == ["women_xs", "women_s"]
    bodies = {b.name: b for b in read_bodies("population")}
    for group in ("women", "men"):
        row = [bodies[n] for n in names if n.startswith(group + "_")]
        assert len(row) >= 5
        girths = np.array([[b.measurements[k] for k in ("bust", "waist", "hip")] for b in row])
        assert (np.diff(girths.sum(axis=1)) > 0.05).all()  # XS to XXL, each one larger
        assert girths[-1, 0] - girths[0, 0] > 0.25  # bust / chest: over 25 cm apart
        for b in row:
            assert len(b.faces) == 26692 and b.to_trimesh().is_watertight


def test_names_patterns_and_sets_each_once():
    got = [b.name for b in read_bodies("female_thin, women_x*, female_thin,builtin")]
    assert got[0] == "female_thin" and len(got) == len(set(got))
    assert {"women_xs", "women_xl", "women_xxl", "male_heavy"} <= set(got)
    with pytest.raises(BodyMeshError, match="no body name matches"):
        read_bodies("kids_*")
    with pytest.raises(BodyMeshError, match="nor a mesh file"):
        read_bodies("female_thin,nobody")


def test_a_folder_of_meshes_written_by_trimesh(tmp_path):
    body = read_body("male_thin")
    mesh = trimesh.Trimesh(body.vertices * 100.0, body.faces, process=False)  # centimetres
    mesh.export(tmp_path / "anna.ply")
    mesh.export(tmp_path / "bert.obj")
    (tmp_path / "notes.txt").write_text("not a body")
    got = read_bodies(tmp_path)
    assert [b.name for b in got] == ["anna", "bert"]
    assert got[0].meta["units"] == "cm"
    assert abs(got[1].measurements["height"] - body.measurements["height"]) < 0.01
    (tmp_path / "sub").mkdir()
    with pytest.raises(BodyMeshError, match="holds no body mesh"):
        read_bodies(tmp_path / "sub")
    mesh.export(tmp_path / "sub" / "anna.stl")
    (tmp_path / "sub" / "anna.ply").write_bytes((tmp_path / "anna.ply").read_bytes())
    with pytest.raises(ValueError, match="two bodies named anna"):
        read_bodies(tmp_path / "sub")


def test_a_shared_body_carries_its_distance_field(monkeypatch):
    import pickle

    from patternfit.api import with_distance_field
    from patternfit.body.sdf import DistanceField

    body = with_distance_field(read_body("female_thin"))
    copy = pickle.loads(pickle.dumps(body))  # what ray.put / a worker's get do

    def no_build(*args, **kwargs):
        raise AssertionError("the field was built again")

    monkeypatch.setattr(DistanceField, "from_mesh", no_build)
    field = copy.distance_field()  # the drape's, the placement's and the measures' field
    assert np.array_equal(field.values, body.distance_field().values)


def test_the_commands_list_a_set_and_refuse_half_measurements():
    import json

    from typer.testing import CliRunner

    from patternfit.cli.main import app

    runner = CliRunner()
    got = runner.invoke(app, ["bodies", "--set", "population", "--json"])
    assert got.exit_code == 0, got.output
    listed = json.loads(got.stdout)["bodies"]
    assert {b["set"] for b in listed} == {"population"} and len(listed) >= 10
    assert runner.invoke(app, ["bodies", "--set", "kids"]).exit_code == 2
    half = runner.invoke(app, ["body", "--from-measurements", "--height", "1.7", "--bust",
                               "0.9", "--out", "b.ply"])
    assert half.exit_code == 2 and "--waist, --hip" in half.output
    stray = runner.invoke(app, ["body", "--hip", "1.0", "--out", "b.ply"])
    assert stray.exit_code == 2 and "--from-measurements" in stray.output
