"""Body meshes, fabric JSON, saved garment folders and fit reports against malformed input.

Every file under ``tests/data/bad/{body,fabric,garment}`` must be refused through the public
loaders with an :class:`InputError` subclass naming the file, never a traceback, and never
be accepted. Random byte mutations of valid files give the same: a result or the reader's
error.
"""

from __future__ import annotations

import dataclasses
import io
import json
from pathlib import Path

import numpy as np
import pytest
import trimesh
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import patternfit.body.mesh_io as mesh_io
import patternfit.files
from patternfit.body import Body, BodyMeshError, load_body, load_body_mesh
from patternfit.body.builtin import save_body
from patternfit.body.measure import LandmarkError
from patternfit.body.mesh_io import body_from_arrays
from patternfit.constants import limits
from patternfit.errors import GarmentFileError, InputError
from patternfit.fit import FitEvaluator, fit_report, write_report
from patternfit.fit.export import export_garment
from patternfit.fit.outputs import write_fit_outputs
from patternfit.mesh import GarmentMesh, mesh_pattern
from patternfit.mesh.store import (MESH, POSITIONS, load_garment, replace_pattern_and_mesh,
                                   save_garment)
from patternfit.pattern import Pattern, PatternError, load_pattern, save_pattern
from patternfit.sim.fabrics import FABRICS, RANGES, Fabric, FabricError, get_fabric, load_fabric

from scenes import rectangle_panel

BAD = Path(__file__).parent / "data" / "bad"
BODIES = sorted((BAD / "body").iterdir())
FABRIC_FILES = sorted((BAD / "fabric").iterdir())
GARMENTS = sorted((BAD / "garment").iterdir())

GOOD_FABRIC = {"density": 0.2, "stretch_warp": 5e3, "stretch_weft": 3e3, "shear": 30,
               "bending": 5e-6, "friction": 0.3, "thickness": 3e-4}


def _refused(load, path, cls):
    """The error ``load(path)`` raises: of ``cls``, an InputError, naming ``path`` (or a file
    inside it)."""
    with pytest.raises(cls) as err:
        load(path)
    exc = err.value
    assert isinstance(exc, InputError)
    assert exc.file is not None and exc.file.startswith(str(path)), str(exc)
    assert str(exc).startswith(exc.file)
    return exc


# -------------------------------------------------------------------------- the corpus
def test_corpus_is_there_and_small():
    assert len(BODIES) >= 25 and len(FABRIC_FILES) >= 25 and len(GARMENTS) >= 35
    for f in [*BODIES, *FABRIC_FILES, *(p for g in GARMENTS for p in g.rglob("*"))]:
        assert f.stat().st_size < 50_000, f


@pytest.mark.parametrize("path", BODIES, ids=lambda p: p.name)
def test_bad_body_refused(path):
    _refused(load_body_mesh, path, BodyMeshError)


@pytest.mark.parametrize("name, place, words", [
    ("sphere.obj", "landmark 'crotch'", "A-pose"),
    ("cube.ply", "landmark 'crotch'", "A-pose"),
    ("cylinder.stl", "landmark 'crotch'", "A-pose"),
    ("sphere_no_landmarks.npz", "landmark 'neck_base'", "missing"),
    ("plane.stl", None, "not a closed surface"),
    ("nan_vertex.obj", None, "NaN"),
    ("face_index_out_of_range.ply", "faces", "out of range"),
    ("face_index_out_of_range.npz", "array 'faces'", "out of range"),
    ("faces_float.npz", "array 'faces'", "kind"),
    ("nan_vertices.npz", "array 'vertices'", "NaN"),
    ("body_inches_times_ten.ply", "units", "millimetres (guessed)"),
    ("body_hundredth_of_inches.obj", "units", "(guessed)"),
    ("not_a_body.npz", "array 'vertices'", "missing"),
    ("pickled_vertices.npz", "array 'vertices'", "pickle"),
    ("truncated.npz", None, "damaged"),
    ("archive.zip", None, "unsupported mesh format"),
    ("empty.obj", None, "empty mesh"),
])
def test_bad_body_says_what_and_where(name, place, words):
    exc = _refused(load_body_mesh, BAD / "body" / name, BodyMeshError)
    assert exc.place == place and words in exc.reason, str(exc)


@pytest.mark.parametrize("path", FABRIC_FILES, ids=lambda p: p.name)
def test_bad_fabric_refused(path):
    exc = _refused(load_fabric, path, FabricError)
    field = path.stem.split("_")[0]
    if field in RANGES or field in ("shear", "name"):
        assert exc.place == f"field '{field}'", str(exc)
    assert _refused(get_fabric, path, FabricError).reason == exc.reason


@pytest.mark.parametrize("path", GARMENTS, ids=lambda p: p.name)
def test_bad_garment_folder_refused(path):
    cls = PatternError if path.name in ("pattern_missing", "pattern_truncated") \
        else GarmentFileError
    exc = _refused(load_garment, path, cls)
    array = {"mesh_missing_triangles": "triangles", "mesh_nan_vertices": "vertices",
             "mesh_triangle_index_out_of_range": "triangles",
             "mesh_triangle_index_negative": "triangles", "mesh_pickled_array": "vertices",
             "mesh_header_lies": "vertices", "mesh_uint64_huge_index": "triangles",
             "mesh_triangle_panel_short": "triangle_panel", "mesh_grain_zero": "grain",
             "mesh_edge_names_bad": "edge_names", "mesh_vertices_scalar": "vertices",
             "mesh_infinite_param": "boundary_param"}.get(path.name)
    if array:
        assert exc.file.endswith(MESH) and exc.place == f"array '{array}'", str(exc)
    if path.name.startswith("positions_"):
        assert exc.file.endswith(POSITIONS), str(exc)


# -------------------------------------------------------------------------- bodies
@pytest.fixture(scope="module")
def body():
    return load_body("male_thin")


def _without_networkx(monkeypatch):
    """A fresh machine: trimesh's networkx-backed repairs raise as there."""
    from trimesh.exceptions import ExceptionWrapper

    missing = ExceptionWrapper(ModuleNotFoundError("No module named 'networkx'"))
    monkeypatch.setattr(trimesh.repair, "nx", missing)
    monkeypatch.setattr(trimesh.graph, "nx", missing)


def test_holes_filled_and_winding_fixed_without_networkx(body, monkeypatch):
    _without_networkx(monkeypatch)
    ring = (body.faces == 5000).any(axis=1)  # one vertex's triangles: a hole of its valence
    flipped = body.faces.copy()
    flipped[::3] = flipped[::3, ::-1]
    for faces in (body.faces[1:], body.faces[~ring], flipped):
        tm = body_from_arrays(body.vertices, faces, up="y").to_trimesh()
        assert tm.is_watertight and tm.is_winding_consistent and tm.volume > 0


def test_units_guessed_and_reported(body, tmp_path):
    path = tmp_path / "inches.ply"
    trimesh.Trimesh(body.vertices / 0.0254, body.faces, process=False).export(path)
    back = load_body_mesh(path, up="y")  # 70 units: cm would say 0.70 m, inches 1.78 m
    assert back.meta["units"] == "in" and back.meta["units_guessed"] is True
    assert back.meta["scale_to_m"] == 0.0254
    assert back.height == pytest.approx(body.height, abs=1e-4)
    given = load_body_mesh(path, units="in", up="y")
    assert given.meta["units"] == "in" and given.meta["units_guessed"] is False
    with pytest.raises(BodyMeshError, match="centimetres") as err:
        load_body_mesh(path, units="cm", up="y")
    assert err.value.place == "units" and err.value.file == str(path)


def test_body_too_many_vertices_or_not_a_file(body, monkeypatch, tmp_path):
    monkeypatch.setattr(mesh_io, "limits", dataclasses.replace(limits, body_vertices=1000))
    with pytest.raises(BodyMeshError, match="limit of 1000"):
        body_from_arrays(body.vertices, body.faces)
    zero = tmp_path / "zero.obj"
    zero.symlink_to("/dev/zero")
    assert _refused(load_body_mesh, zero, BodyMeshError).reason == "not a regular file"


def test_body_refuses_missing_landmarks(body):
    with pytest.raises(LandmarkError, match="crotch") as err:
        Body(body.vertices, body.faces, measurements=body.measurements,
             landmarks={k: v for k, v in body.landmarks.items() if k != "crotch"})
    assert err.value.landmark == "crotch"
    with pytest.raises(LandmarkError, match="waist_height"):
        Body(body.vertices, body.faces, landmarks=body.landmarks,
             measurements={**body.measurements, "waist_height": float("nan")})


def test_saved_body_loads_as_a_mesh_file(body, tmp_path):
    back = load_body_mesh(save_body(body, tmp_path / "me.npz"))
    assert back.measurements == pytest.approx(body.measurements)
    assert np.allclose(back.vertices, body.vertices, atol=1e-6)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data())
def test_mutated_body_mesh_never_crashes(tmp_path_factory, data):
    good = (BAD / "body" / "sphere.obj").read_bytes()
    path = tmp_path_factory.mktemp("body") / "mutated.obj"
    path.write_bytes(_mutate(good, data))
    with pytest.raises(BodyMeshError):  # a mutated sphere is still no body
        load_body_mesh(path)


# -------------------------------------------------------------------------- fabrics
def test_fabric_from_a_device_is_refused():
    for load in (load_fabric, get_fabric):
        exc = _refused(load, Path("/dev/zero"), FabricError)
        assert exc.reason == "not a regular file"


@pytest.mark.parametrize("field, value, words", [
    ("density", 1e30, "plausible range"), ("density", -1.0, "plausible range"),
    ("density", True, "finite number"), ("thickness", 0.5, "0.02 m"),
    ("friction", 3.0, "plausible range"), ("bending", None, "finite number"),
    ("bending", 5.0, "plausible range")])
def test_fabric_errors_carry_file_and_field(tmp_path, field, value, words):
    """Each error names the field as the file wrote it (one "bending" for both yarns
    included: its errors used to name bending_warp)."""
    path = tmp_path / "mine.json"
    path.write_text(json.dumps({**GOOD_FABRIC, field: value}))
    exc = _refused(load_fabric, path, FabricError)
    assert exc.file == str(path) and exc.place == f"field '{field}'" and words in exc.reason
    assert str(path) not in exc.reason


def test_presets_lie_in_the_plausible_ranges():
    for f in FABRICS.values():
        for key, (lo, hi, _) in RANGES.items():
            assert lo <= getattr(f, key) <= hi, (f.name, key)
    with pytest.raises(FabricError, match="field 'density'"):
        Fabric("x", 1e30, 1e3, 1e3, 10, 1e-6, 1e-6, 0.3, 1e-3)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data())
def test_mutated_fabric_json_gives_a_fabric_or_a_fabric_error(tmp_path_factory, data):
    good = json.dumps({"name": "poplin", **GOOD_FABRIC}).encode()
    path = tmp_path_factory.mktemp("fabric") / "mutated.json"
    path.write_bytes(_mutate(good, data))
    try:
        fabric = load_fabric(path)
    except FabricError as exc:
        assert exc.file == str(path)
    else:
        assert all(RANGES[k][0] <= getattr(fabric, k) <= RANGES[k][1] for k in RANGES)


def _mutate(good: bytes, data) -> bytes:
    """``good`` with a few bytes changed and possibly cut short."""
    b = bytearray(good)
    for i, byte in data.draw(st.lists(st.tuples(st.integers(0, len(b) - 1),
                                                st.integers(0, 255)), min_size=1, max_size=6)):
        b[i] = byte
    return bytes(b[:data.draw(st.integers(1, len(b)))])


# -------------------------------------------------------------------------- garments
@pytest.fixture(scope="module")
def square():
    pattern = Pattern("square", (rectangle_panel("front", 0.4, 0.4),))
    mesh = mesh_pattern(pattern, triangles=16)
    return pattern, mesh, np.c_[mesh.vertices, np.zeros(mesh.n_vertices)]


def test_garment_round_trip_and_stale_state_removed(square, tmp_path):
    pattern, mesh, x = square
    save_garment(tmp_path / "g", pattern, mesh, x)
    p2, m2, x2 = load_garment(tmp_path / "g")
    assert m2.panel_names == mesh.panel_names and np.array_equal(m2.triangles, mesh.triangles)
    assert np.array_equal(x2, x)
    save_garment(tmp_path / "g", pattern, mesh)  # a new mesh: the old state is no longer its
    assert load_garment(tmp_path / "g")[2] is None


def test_garment_save_is_one_step(square, tmp_path, monkeypatch):
    pattern, mesh, x = square
    folder = tmp_path / "g"
    save_garment(folder, pattern, mesh, x)
    bigger = Pattern("square", (rectangle_panel("front", 0.5, 0.5),))
    new_mesh = mesh_pattern(bigger, triangles=40)

    def crash(renames, journals):
        raise KeyboardInterrupt  # killed after the journal, before any rename

    monkeypatch.setattr(patternfit.files, "_finish", crash)
    with pytest.raises(KeyboardInterrupt):
        save_garment(folder, bigger, new_mesh, np.c_[new_mesh.vertices,
                                                     np.zeros(new_mesh.n_vertices)])
    monkeypatch.undo()
    p2, m2, x2 = load_garment(folder)  # the next read finishes the write
    assert m2.n_vertices == new_mesh.n_vertices == len(x2)
    assert p2.area() == pytest.approx(bigger.area())


def test_replace_pattern_and_mesh_at_separate_paths(square, tmp_path):
    pattern, mesh, _ = square
    paths = replace_pattern_and_mesh(tmp_path / "a" / "p.json", pattern, tmp_path / "b" / "m.npz",
                                     mesh, units="cm")
    assert [p.name for p in paths] == ["p.json", "m.npz"]
    assert json.loads(paths[0].read_text())["units"] == "cm"
    assert load_pattern(paths[0]).area() == pytest.approx(pattern.area())
    assert GarmentMesh.load(paths[1]).n_triangles == mesh.n_triangles


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data())
def test_mutated_mesh_npz_gives_a_mesh_or_a_garment_error(square, tmp_path_factory, data):
    good = square[1].to_bytes()
    path = tmp_path_factory.mktemp("mesh") / "mutated.npz"
    path.write_bytes(_mutate(good, data))
    try:
        GarmentMesh.load(path)
    except GarmentFileError as exc:
        assert exc.file == str(path)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data())
def test_mutated_positions_give_a_state_or_a_garment_error(square, tmp_path_factory, data):
    pattern, mesh, x = square
    folder = tmp_path_factory.mktemp("garment")
    save_garment(folder, pattern, mesh, x)
    good = (folder / POSITIONS).read_bytes()
    (folder / POSITIONS).write_bytes(_mutate(good, data))
    try:
        _, _, positions = load_garment(folder)
    except GarmentFileError as exc:
        assert exc.file == str(folder / POSITIONS)
    else:
        assert positions.shape == x.shape and np.isfinite(positions).all()


# -------------------------------------------------------------------------- reports
def _strict(text: str):
    def refuse(name):
        raise AssertionError(f"{name} in a report")

    return json.loads(text, parse_constant=refuse)


def test_collapsed_state_is_a_failed_fit_not_infinity(square, tmp_path):
    pattern, mesh, x = square
    with np.errstate(divide="ignore", invalid="ignore"):
        fit = FitEvaluator(mesh)(np.zeros_like(x))  # every triangle of zero 3D area
    assert not np.isfinite(fit.fitting_ratio)
    report = write_fit_outputs(tmp_path / "out", pattern, mesh, x, fit, pictures=False)
    assert report["fitting_ratio"] is None and report["panels"][0]["fitting_ratio"] is None
    checks = report["checks"]
    assert checks["passed"] is False and checks["fit_finite"] is False
    assert {"fitting_ratio", "panels[0].fitting_ratio"} <= set(checks["non_finite"])
    assert _strict((tmp_path / "out" / "report.json").read_text()) == report


def test_good_fit_passes_and_drape_checks_merge(square, tmp_path):
    pattern, mesh, x = square
    fit = FitEvaluator(mesh)(x)
    plain = fit_report(mesh, fit)
    # nothing checked is no pass (a placement never draped read "passed: true"), and every
    # report says what it knows of the rest
    assert plain["checks"] == {"fit_finite": True, "passed": None, "equilibrium": None,
                               "residual_rms": None, "residual_p99": None}
    drape = {"inside_vertices": 0, "max_depth_mm": float("nan"), "passed": True}
    merged = fit_report(mesh, fit, state="draped", extra={"checks": drape})
    assert merged["checks"]["max_depth_mm"] is None and merged["checks"]["passed"] is False
    assert merged["checks"]["non_finite"] == ["checks.max_depth_mm"]
    failed = fit_report(mesh, fit, extra={"checks": {"passed": False}})
    assert failed["checks"]["passed"] is False and failed["checks"]["fit_finite"]
    write_report(merged, tmp_path / "r.json")
    _strict((tmp_path / "r.json").read_text())
    with pytest.raises(ValueError):
        write_report({"fitting_ratio": float("inf")}, tmp_path / "bad.json")


def test_export_refuses_non_finite_positions(square, tmp_path):
    _, mesh, x = square
    y = x.copy()
    y[0, 0] = np.nan
    with pytest.raises(ValueError, match="positions"):
        export_garment(y, mesh.triangles, np.zeros_like(x), tmp_path / "g.obj")
    with pytest.raises(ValueError, match="triangles"):
        export_garment(x, mesh.triangles + 100, np.zeros_like(x), tmp_path / "g.obj")
    assert not (tmp_path / "g.obj").exists()
    export_garment(x, mesh.triangles, np.zeros_like(x), tmp_path / "g.glb")
    assert io.BytesIO((tmp_path / "g.glb").read_bytes()).read(4) == b"glTF"


def test_damaged_distance_field_cache_is_recomputed(tmp_path, monkeypatch):
    from patternfit.body import DistanceField

    monkeypatch.setenv("PATTERNFIT_CACHE", str(tmp_path))
    ball = trimesh.creation.icosphere(1, radius=0.1)
    first = DistanceField.from_mesh(ball.vertices, ball.faces, spacing=0.02, padding=0.02)
    (cached,) = tmp_path.glob("sdf-*.npz")
    for damage in (b"", b"PK\x03\x04" + bytes(40), cached.read_bytes()[:100]):
        cached.write_bytes(damage)
        again = DistanceField.from_mesh(ball.vertices, ball.faces, spacing=0.02, padding=0.02)
        assert np.array_equal(again.values, first.values)


def test_a_body_file_naming_a_pipe_as_its_material_library_is_read(tmp_path):
    """An OBJ's ``mtllib`` naming a named pipe waited on it for ever; what a mesh file names
    is read as every input is (regular files only), and a body needs no material."""
    import os
    import threading

    from patternfit.body.mesh_io import save_body_mesh

    obj = tmp_path / "body.obj"
    save_body_mesh(load_body("female_thin"), obj)
    obj.write_text("mtllib pipe.mtl\n" + obj.read_text())
    os.mkfifo(tmp_path / "pipe.mtl")
    out = {}
    reader = threading.Thread(target=lambda: out.update(body=load_body_mesh(obj)), daemon=True)
    reader.start()
    reader.join(60.0)
    assert not reader.is_alive(), "the reader waited on the pipe"
    assert out["body"].measurements["height"] == pytest.approx(
        load_body("female_thin").measurements["height"], rel=1e-3)


def _without_checks(mesh, **arrays) -> GarmentMesh:
    fields = {k: getattr(mesh, k) for k in mesh.__dataclass_fields__}
    return GarmentMesh(**{**fields, **arrays})


@pytest.mark.parametrize("case", ["another size", "another garment", "shrunk", "pairs",
                                  "twice"])
def test_a_folder_whose_mesh_is_not_of_its_pattern_is_refused(tmp_path, case):
    """Only the panel names were compared: the M skirt's mesh under the L skirt's
    pattern.json, or a dress's mesh under a skirt's, read as that pattern's drape."""
    from patternfit.pattern.library import build

    skirt = build("skirt", "M")
    mesh = mesh_pattern(skirt, triangles=300)
    pattern = skirt
    if case == "another size":
        pattern = build("skirt", "L")
    elif case == "another garment":  # the dress's panels are named as the skirt's
        mesh = mesh_pattern(build("dress", "M"), triangles=300)
    elif case == "shrunk":
        mesh = mesh.with_vertices(mesh.vertices * 0.9)
    elif case == "pairs":  # every pair sewn to one vertex of the front
        one = mesh.panel_vertices(0)[0]
        mesh = _without_checks(mesh, seam_pairs=np.full_like(mesh.seam_pairs, one))
    else:
        mesh = _without_checks(mesh, triangles=np.vstack([mesh.triangles, mesh.triangles[:1]]),
                               triangle_panel=np.r_[mesh.triangle_panel, 0])
    # written as another tool (or a hand) would: save_garment refuses such a pair itself
    skirt_mesh = mesh_pattern(skirt, triangles=300)
    save_garment(tmp_path / "g", skirt, skirt_mesh,
                 np.c_[skirt_mesh.vertices, np.zeros(skirt_mesh.n_vertices)])
    save_pattern(pattern, tmp_path / "g" / "pattern.json")
    (tmp_path / "g" / MESH).write_bytes(mesh.to_bytes())
    np.save(tmp_path / "g" / POSITIONS, np.c_[mesh.vertices, np.zeros(mesh.n_vertices)])
    if case != "twice":  # a mesh built past GarmentMesh's own checks
        with pytest.raises(ValueError, match="^mesh: not a mesh of this pattern"):
            save_garment(tmp_path / "h", pattern, mesh)
    expected = {"twice": "a triangle given twice", "pairs": "is not on"}.get(
        case, "is not a mesh of pattern.json")
    with pytest.raises(GarmentFileError, match=expected):
        load_garment(tmp_path / "g")
    # the folder it was made from, unchanged, reads
    save_garment(tmp_path / "ok", skirt, mesh_pattern(skirt, triangles=300))
    assert load_garment(tmp_path / "ok")[0] == skirt


def test_a_drapes_output_folder_reads_as_its_garment_folder(tmp_path):
    """fit --garment refused the folder a drape writes ("no mesh.npz here"), which drape
    --start took; a mesh.npz there that is no file (a link to /dev/zero) was said missing."""
    from patternfit.pattern.library import build

    skirt = build("skirt", "M")
    mesh = mesh_pattern(skirt, triangles=300)
    save_garment(tmp_path / "out" / "garment", skirt, mesh, np.c_[mesh.vertices,
                                                                  np.zeros(mesh.n_vertices)])
    pattern, _, x = load_garment(tmp_path / "out")
    assert pattern == skirt and x.shape == (mesh.n_vertices, 3)
    (tmp_path / "zero").mkdir()
    (tmp_path / "zero" / MESH).symlink_to("/dev/zero")
    with pytest.raises(GarmentFileError, match="not a regular file"):
        load_garment(tmp_path / "zero")
    # a folder that is not there, or a file, is said to be so ("no mesh.npz here" was said
    # of both)
    with pytest.raises(GarmentFileError, match="nowhere: does not exist"):
        load_garment(tmp_path / "nowhere")
    with pytest.raises(GarmentFileError, match="positions.npy: is a file, not a garment folder"):
        load_garment(tmp_path / "out" / "garment" / "positions.npy")
