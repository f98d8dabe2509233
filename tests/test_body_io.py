"""Loading body meshes: formats, units, up axis, repair, and the promised refusals."""

import numpy as np
import pytest
import trimesh

from patternfit.body import BodyMeshError, load_body, load_body_mesh, save_body_mesh
from patternfit.body.mesh_io import body_from_arrays


@pytest.fixture(scope="module")
def body():
    return load_body("male_thin")


@pytest.mark.parametrize("suffix", [".ply", ".obj", ".stl", ".glb"])
def test_round_trip(body, tmp_path, suffix):
    path = save_body_mesh(body, tmp_path / f"b{suffix}")
    back = load_body_mesh(path, up="y")
    assert back.height == pytest.approx(body.height, abs=1e-4)
    assert abs(back.measurements["waist"] - body.measurements["waist"]) < 0.02
    assert back.name == "b"


def test_units_and_up_axis_guessed(body, tmp_path):
    v = body.vertices * 100.0  # centimetres ...
    v = np.c_[v[:, 0], -v[:, 2], v[:, 1]]  # ... and Z up
    trimesh.Trimesh(v, body.faces, process=False).export(tmp_path / "cm_zup.ply")
    back = load_body_mesh(tmp_path / "cm_zup.ply")
    assert back.height == pytest.approx(body.height, abs=1e-4)
    assert abs(back.vertices[:, 1].min()) < 1e-9
    assert back.meta["scale_to_m"] == 0.01
    assert abs(back.measurements["hip"] - body.measurements["hip"]) < 0.02
    given = load_body_mesh(tmp_path / "cm_zup.ply", units="cm", up="z")
    assert given.height == pytest.approx(body.height, abs=1e-4)


def test_small_hole_is_filled(body):
    back = body_from_arrays(body.vertices, body.faces[1:], up="y")
    assert back.to_trimesh().is_watertight
    assert back.to_trimesh().volume > 0


def test_inverted_normals_are_fixed(body):
    back = body_from_arrays(body.vertices, body.faces[:, ::-1], up="y")
    assert back.to_trimesh().volume > 0


def test_refusals(body, tmp_path):
    with pytest.raises(BodyMeshError, match="empty"):
        body_from_arrays(np.zeros((0, 3)), np.zeros((0, 3), int))
    bad = body.vertices.copy()
    bad[5] = np.nan
    with pytest.raises(BodyMeshError, match="NaN"):
        body_from_arrays(bad, body.faces)
    with pytest.raises(BodyMeshError, match="absurd size"):
        body_from_arrays(body.vertices * 1e4, body.faces)
    with pytest.raises(BodyMeshError, match="absurd size"):
        body_from_arrays(body.vertices, body.faces, units="mm")
    keep = body.vertices[:, 1] > 1.0  # cut the body in half: a huge hole, not fillable
    half = body.faces[keep[body.faces].all(axis=1)]
    with pytest.raises(BodyMeshError, match="not a closed surface"):
        body_from_arrays(body.vertices, half, up="y")
    with pytest.raises(BodyMeshError, match="no such file"):
        load_body_mesh(tmp_path / "missing.obj")
    (tmp_path / "junk.ply").write_bytes(b"not a mesh at all")
    with pytest.raises(BodyMeshError):
        load_body_mesh(tmp_path / "junk.ply")
    with pytest.raises(ValueError, match="up"):
        body_from_arrays(body.vertices, body.faces, up="w")
    with pytest.raises(ValueError, match="path"):
        save_body_mesh(body, tmp_path / "b.xyz")
