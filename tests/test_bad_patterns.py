"""Pattern files against malformed input: patternfit JSON, GarmentCode, DXF-AAMA and its side
file.

Every file under ``tests/data/bad/{pattern,dxf,garmentcode}`` must be refused through the
format-dispatching loader with a :class:`PatternError` (an :class:`InputError`) naming the file
(the side file, for a DXF whose side file is at fault), and meshing must never be reached.
Outlines that crash Triangle (a zero-width spike, a pinch) are meshed in a subprocess with
every check but the mesher's last one switched off, so that a regression fails a test instead
of killing pytest. Random polygons and random mutations of valid files check the rest.
"""

from __future__ import annotations

import copy
import json
import math
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from patternfit.constants import limits
from patternfit.errors import InputError
from patternfit.mesh import triangulate
from patternfit.pattern.dxf_curves import loop_from_points
from patternfit.mesh.triangulate import mesh_pattern
from patternfit.pattern import (Edge, Loop, Panel, Pattern, PatternError, Seam, SeamSide,
                                check_pattern, pattern_from_dict, pattern_to_dict)
from patternfit.pattern.dxf import load_dxf, save_dxf, sidecar_path
from patternfit.pattern.formats import load_any_pattern
from patternfit.pattern.garmentcode import garmentcode_from_dict, garmentcode_to_dict
from patternfit.pattern.validate import check_polygons

from scenes import rectangle_panel

BAD = Path(__file__).parent / "data" / "bad"
CORPUS = sorted(p for d in ("pattern", "dxf", "garmentcode") for p in (BAD / d).iterdir()
                if not p.name.endswith(".seams.json"))  # side files come with their DXF
FEW = settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _refused(load, path) -> PatternError:
    """The error ``load(path)`` raises: a PatternError (an InputError) naming ``path``
    first."""
    with pytest.raises(PatternError) as err:
        load(path)
    exc = err.value
    assert isinstance(exc, InputError)
    assert exc.file == str(path) and str(exc).startswith(str(path)), str(exc)
    return exc


@pytest.fixture
def no_triangle(monkeypatch):
    """Triangle replaced by a function that fails the test: meshing must not be reached."""
    def refuse(*args, **kwargs):
        raise AssertionError("Triangle was called")
    monkeypatch.setattr(triangulate.tr, "triangulate", refuse)


def _square_pattern() -> Pattern:
    """Two 40 x 60 cm panels sewn along one side, one with a triangular hole."""
    hole = Loop("hole", [Edge.line("h0", (0.1, 0.1), (0.2, 0.1)),
                         Edge.line("h1", (0.2, 0.1), (0.15, 0.2)),
                         Edge.line("h2", (0.15, 0.2), (0.1, 0.1))])
    a = rectangle_panel("A", 0.4, 0.6)
    a = Panel("A", a.outline, (hole,))
    b = rectangle_panel("B", 0.4, 0.6)
    b = b.with_edge(Edge.quadratic("top", (0.4, 0.6), (0.2, 0.65), (0.0, 0.6)))
    return Pattern("squares", (a, b), (Seam("side", SeamSide("A", "right"),
                                            SeamSide("B", "left")),), {"size": "M"})


# -------------------------------------------------------------------------- the corpus
def test_corpus_is_there_and_small():
    kinds = {d: len(list((BAD / d).iterdir())) for d in ("pattern", "dxf", "garmentcode")}
    assert kinds["pattern"] >= 25 and kinds["dxf"] >= 25 and kinds["garmentcode"] >= 15
    for d in kinds:
        for f in (BAD / d).iterdir():
            assert f.stat().st_size < 50_000, f
    for side in (BAD / "dxf").glob("*.seams.json"):
        assert side.with_name(side.name.removesuffix(".seams.json") + ".dxf").exists(), side


@pytest.fixture(scope="module")
def compiled_reader():
    """The DXF reader's compiled curve fitting, compiled (or loaded from numba's cache) once
    before the refusals are timed: a fresh checkout compiles it on its first curve."""
    t = np.linspace(0.0, 0.5 * np.pi, 40)
    arc = np.c_[0.3 * np.cos(t), 0.3 * np.sin(t) ** 1.5]
    loop_from_points(np.r_[arc, [[0.0, 0.0]]], np.r_[arc[[0, -1]], [[0.0, 0.0]]], "warm",
                     "w", foreign=True)


@pytest.mark.parametrize("path", CORPUS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_corpus_file_refused_naming_the_file(path, no_triangle, compiled_reader):
    side = sidecar_path(path)
    named = side if path.suffix == ".dxf" and side.exists() else path  # its side file is bad
    started = time.perf_counter()
    with pytest.raises(PatternError) as err:
        mesh_pattern(load_any_pattern(path), triangles=2000)
    exc = err.value
    assert isinstance(exc, InputError) and exc.reason
    assert exc.file == str(named) and str(exc).startswith(str(named)), str(exc)
    assert time.perf_counter() - started < 2.0  # refused before any large work


@pytest.mark.parametrize("name, words", [
    ("pattern/spike.json", r"panel 'front', edge 'e3': self-intersecting outline: .*edge 'e3' "
                           r"doubles back on edge 'e2' \(a zero-width spike\) at \[0\.8, 0\.2\]"),
    ("pattern/pinch.json", r"edge 'e1' meets edge 'e5' at a point \(a pinch\) at \[0\.4, 0\.4\]"),
    ("pattern/touch.json", r"edge 'e0' touches edge 'e3' at \[0\.3, 0\]"),
    ("pattern/cubic_fold.json", r"edge 'fold' doubles back on itself"),
    ("pattern/bowtie.json", r"edge 'e0' crosses edge 'e2'"),
    ("pattern/hole_touches_outline.json", r"inner loop 'hole0' is not inside the outline"),
    ("pattern/holes_cross.json", r"inner loop 'hole0' is not apart from inner loop 'hole1'"),
    ("pattern/hole_in_hole.json", r"inner loop 'hole1' lies inside inner loop 'hole0'"),
    ("pattern/coords_1e200.json", r"beyond the limit of 20 m"),
    ("pattern/arc_huge_radius.json", r"edge 'a': loop 'outline' reaches .* beyond the limit"),
    ("pattern/panels_over_limit.json", r"501 panels, more than the limit of 500"),
    ("pattern/reverse_string.json", r"seam 'side': 'reverse' must be true or false, got 'false'"),
    ("pattern/large_arc_string.json", r"edge 'a': arc: 'large_arc' must be true or false"),
    ("pattern/seams_not_list.json", r"'seams' must be a list, got 5"),
    ("pattern/meta_list.json", r"'meta' must be an object"),
    ("pattern/seam_side_string.json", r"seam 'side': each side must be an object"),
    ("pattern/seam_name_number.json", r"seam #0: 'name' must be a string, got 7"),
    ("pattern/units_list.json", r"'units' must be a string"),
    ("pattern/big_integer.json", r"out of range"),
    ("pattern/deep_nesting.json", r"nested deeper than 64"),
    ("pattern/non_utf8.json", r"not UTF-8 text \(byte \d+: 0xe4\)"),
    ("pattern/placement_part_unknown.json", r"panel 'front': placement: part must be one of "
                                            r"torso, .*got 'nosuch'"),
    ("pattern/placement_side_unknown.json", r"panel 'front': placement: side must be one of "
                                            r".*got 'sideways'"),
    ("pattern/placement_rotation_huge.json", r"panel 'front': placement: rotation angles must "
                                             r"lie within ±360 degrees"),
    ("garmentcode/rotation_huge_specification.json", r"panel 'front'.*rotation angles must"),
    ("garmentcode/duplicate_panel_specification.json", r"line \d+: the key \"front\" "
                                                       r"appears twice in one object"),
    ("garmentcode/spike_specification.json", r"zero-width spike"),
    ("garmentcode/units_tiny_specification.json", r"bad units: .units_in_meter. 1e-300"),
    ("garmentcode/panel_order_nested_specification.json", r"'panel_order' must be a list"),
    ("garmentcode/hint_part_number_specification.json", r"'part' must be a string, got 3"),
    ("dxf/spike_polyline.dxf", r"panel 'front', edge 'e3': .*zero-width spike"),
    ("dxf/pinch_lwpolyline_r2000.dxf", r"\(a pinch\)"),
    ("dxf/circle_huge.dxf", r"panel 'front': CIRCLE entity \(handle 6\) reaches 1e\+09 m"),
    ("dxf/bulge_huge.dxf", r"POLYLINE entity .* beyond the limit of 20 m"),
    ("dxf/ellipse_huge_r2000.dxf", r"ELLIPSE entity .* beyond the limit"),
    ("dxf/truncated.dxf", r"cannot read DXF: DXFStructureError"),
    ("dxf/binary_garbage.dxf", r"not a DXF file"),
    ("dxf/side_seam_side_empty.dxf", r"seams\.json: seam 's': each side must be an object"),
    ("dxf/side_edge_names_numbers.dxf", r"seams\.json: panel 'front': .*must be a non-empty "
                                        r"string, got 1"),
    ("dxf/side_non_utf8.dxf", r"seams\.json: not UTF-8"),
])
def test_corpus_errors_say_what_and_where(name, words):
    with pytest.raises(PatternError, match=words):
        load_any_pattern(BAD / name)


def test_device_posing_as_a_pattern_is_refused(tmp_path):
    for suffix in (".json", ".dxf"):
        link = tmp_path / f"zero{suffix}"
        link.symlink_to("/dev/zero")
        assert _refused(load_any_pattern, link).reason == "not a regular file"


# -------------------------------------------------------------------------- Triangle
CRASHERS = ["pattern/spike.json", "pattern/pinch.json", "pattern/overlap.json",
            "garmentcode/spike_specification.json", "dxf/spike_polyline.dxf",
            "dxf/pinch_lwpolyline_r2000.dxf", "dxf/touch_lines.dxf"]
_UNCHECKED_MESH = r"""
import sys
from patternfit.mesh import triangulate
from patternfit.pattern.dxf_curves import loop_from_points
from patternfit.pattern import PatternError, dxf, garmentcode, io

# read and mesh with every check off but the mesher's check of its own boundary samples
for module, name in [(io, "check_pattern"), (dxf, "check_pattern"),
                     (garmentcode, "check_imported"), (triangulate, "check_pattern")]:
    setattr(module, name, lambda *args, **kwargs: [])
from patternfit.pattern.formats import load_any_pattern
for path in sys.argv[1:]:
    pattern = load_any_pattern(path)
    for _ in range(20):  # a pinch crashed Triangle in about one run of twenty
        try:
            triangulate.mesh_pattern(pattern, triangles=500)
        except PatternError as exc:
            assert "cannot be meshed at this resolution" in str(exc), exc
        else:
            raise SystemExit(f"{path}: meshed")
print("refused", len(sys.argv) - 1)
"""


def test_crash_prone_outlines_never_reach_triangle():
    paths = [str(BAD / n) for n in CRASHERS]
    run = subprocess.run([sys.executable, "-c", _UNCHECKED_MESH, *paths], capture_output=True,
                         text=True, timeout=120)
    assert run.returncode == 0, (run.returncode, run.stdout, run.stderr[-3000:])
    assert f"refused {len(paths)}" in run.stdout


@pytest.mark.parametrize("kwargs, words", [
    ({"triangles": 1e23}, "triangles: must be a whole number from 1 to"),
    ({"triangles": 0}, "triangles: must be a whole number"),
    ({"triangles": math.nan}, "triangles: must be a whole number"),
    ({"triangles": True}, "triangles: must be a whole number"),
    ({"triangles": "2000"}, "triangles: must be a whole number"),
    ({"triangles": 300.5}, "triangles: must be a whole number"),
    ({"edge_length": 1e-9}, "edge_length: .* more than the limit"),
    ({"edge_length": math.inf}, "edge_length: must be a positive number"),
    ({"edge_length": math.nan}, "edge_length: must be a positive number"),
    ({"edge_length": -0.01}, "edge_length: must be a positive number"),
])
def test_mesh_arguments_are_bounded(two_rectangles, no_triangle, kwargs, words):
    with pytest.raises(ValueError, match=words):
        mesh_pattern(two_rectangles, **kwargs)


def test_valid_pattern_still_meshes(two_rectangles):
    mesh = mesh_pattern(two_rectangles, triangles=400)
    assert abs(mesh.n_triangles / 400 - 1) < 0.1
    assert mesh_pattern(_square_pattern(), edge_length=0.05).n_triangles > 0


# -------------------------------------------------------------------------- the geometry test
def _ring(*pts):
    return np.array(pts, dtype=float) * 0.01


def _names(*rings):
    """Segment names: a0, a1, ... on the first ring, b0, ... on the second."""
    return [[f"{'abcdefgh'[n]}{k}" for k in range(len(r))] for n, r in enumerate(rings)]


@pytest.mark.parametrize("rings, words", [
    ([_ring((0, 0), (10, 0), (10, 5), (0, 5)), _ring((2, 0), (4, 0), (3, 1))],
     r"inner loop 'inner' is not inside the outline: edge 'a0' runs along edge 'b0' "
     r"\(they overlap\)"),
    ([_ring((0, 0), (10, 0), (10, 5), (6, 5), (5, 5e-5), (4, 5), (0, 5))],  # 0.5 um apart
     r"self-intersecting outline: in loop 'outline', edge 'a0' touches edge 'a3'"),
    ([_ring((0, 0), (4, 0), (4, 4), (8, 4), (8, 8), (4, 8), (4, 4), (0, 4))],
     r"edge 'a1' meets edge 'a5' at a point \(a pinch\) at \[0\.04, 0\.04\]"),
    ([_ring((0, 0), (4, 0), (4, 2), (8, 2), (4, 2), (4, 4), (0, 4))],
     r"edge 'a3' doubles back on edge 'a2' \(a zero-width spike\) at \[0\.08, 0\.02\]"),
    ([_ring((0, 0), (4, 0), (4, 4), (0, 4)), _ring((1, 1), (2, 1), (1.5, 2)),
      _ring((1.5, 1.5), (3, 1.5), (3, 3))],
     r"inner loop 'inner' is not apart from inner loop 'inner2': edge 'b1' crosses"),
    ([_ring((0, 0), (4, 0), (4, 4), (4, 4), (0, 4))], r"repeats the point \[0\.04, 0\.04\]"),
    ([_ring((0, 0), (4, 0))], r"fewer than three points"),
    ([_ring((0, 0), (4, 0), (math.nan, 1))], r"NaN"),
    ([_ring((0, 0), (4e5, 0), (0, 1))], r"reaches 4e\+03 m from the origin, beyond"),
])
def test_check_polygons_names_the_contact(rings, words):
    names = ["outline", "inner", "inner2"][:len(rings)]
    with pytest.raises(PatternError, match=words) as err:
        check_polygons(rings, _names(*rings), names, panel="p")
    assert err.value.panel == "p" and err.value.edge is not None


def _exact_contact(rings) -> bool:
    """Brute-force reference on integer points: any two segments that meet, except
    neighbours meeting only at their shared point; a repeated point."""
    segs = []
    for r, ring in enumerate(rings):
        n = len(ring)
        for k in range(n):
            p, q = ring[k], ring[(k + 1) % n]
            if p == q:
                return True
            segs.append((r, k, n, p, q))

    def orient(a, b, c):
        v = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        return (v > 0) - (v < 0)

    def on(a, b, c):  # c on segment a-b, given collinear
        return min(a[0], b[0]) <= c[0] <= max(a[0], b[0]) and \
            min(a[1], b[1]) <= c[1] <= max(a[1], b[1])

    def meet(p, q, r, s):  # closed segments p-q and r-s have a point in common
        o1, o2, o3, o4 = orient(p, q, r), orient(p, q, s), orient(r, s, p), orient(r, s, q)
        if o1 != o2 and o3 != o4:
            return True
        return (o1 == 0 and on(p, q, r)) or (o2 == 0 and on(p, q, s)) or \
            (o3 == 0 and on(r, s, p)) or (o4 == 0 and on(r, s, q))

    for x in range(len(segs)):
        for y in range(x + 1, len(segs)):
            (ra, ka, na, p, q), (rb, kb, _, r, s) = segs[x], segs[y]
            if ra == rb and (kb == (ka + 1) % na or ka == (kb + 1) % na):
                if kb != (ka + 1) % na:
                    p, q, r, s = r, s, p, q
                u, v = (q[0] - p[0], q[1] - p[1]), (s[0] - r[0], s[1] - r[1])
                if u[0] * v[1] - u[1] * v[0] == 0 and u[0] * v[0] + u[1] * v[1] < 0:
                    return True  # the second doubles back on the first
            elif meet(p, q, r, s):
                return True
    return False


_points = st.lists(st.tuples(st.integers(0, 6), st.integers(0, 6)), min_size=3, max_size=9)


@FEW
@given(st.lists(_points, min_size=1, max_size=3))
def test_polygon_check_agrees_with_brute_force(rings):
    arrays = [np.array(r, dtype=float) * 0.01 for r in rings]
    try:
        check_polygons(arrays, _names(*arrays), [f"l{k}" for k in range(len(rings))])
    except PatternError:
        assert _exact_contact(rings)
    else:
        assert not _exact_contact(rings)


def _cubic_ring(n: int, wiggle: float) -> Panel:
    """A disc of radius 0.5 m whose outline is ``n`` cubic edges bulging by ``wiggle``."""
    ang = np.linspace(0, 2 * np.pi, n + 1)
    pts = np.column_stack([np.cos(ang), np.sin(ang)]) * 0.5
    pts[-1] = pts[0]
    edges = []
    for i in range(n):
        a, b = pts[i], pts[i + 1]
        d = b - a
        side = np.array([-d[1], d[0]]) * wiggle
        edges.append(Edge.cubic(f"c{i}", a, a + d / 3 + side, a + 2 * d / 3 - side, b))
    return Panel("disc", Loop("outline", edges))


@pytest.mark.parametrize("crossing", [False, True])
def test_many_curves_checked_in_little_time_and_memory(crossing):
    panel = _cubic_ring(500, 0.3)  # 12000 segments: the all-pairs test needed > 4 GiB
    if crossing:  # one edge loops out across the disc and beyond its far side
        e = panel.outline.edges[250]
        a, b = e.start, e.end
        panel = panel.with_edge(Edge.cubic(e.name, a, -2 * a, -2 * b, b))
    tracemalloc.start()
    started = time.perf_counter()
    try:
        check_pattern(Pattern("disc", (panel,)))
    except PatternError as exc:
        assert crossing and "crosses edge 'c250'" in str(exc), str(exc)
    else:
        assert not crossing
    took = time.perf_counter() - started
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert took < 1.5 and peak < 100e6, (took, peak)


def test_sizes_refused_before_anything_is_built():
    doc = pattern_to_dict(_square_pattern(), units="cm")
    many = copy.deepcopy(doc)
    many["panels"][0]["outline"]["edges"] = [{}] * (limits.edges_per_pattern + 1)
    with pytest.raises(PatternError, match="edges, more than the limit of 50000"):
        pattern_from_dict(many)
    with pytest.raises(PatternError, match="polyline segments, more than the limit"):
        check_pattern(Pattern("disc", (_cubic_ring(limits.segments_per_panel // 24 + 1, 0.1),)))
    gc = garmentcode_to_dict(Pattern("p", (rectangle_panel("A", 0.4, 0.6),)))
    gc["pattern"]["panels"] = {f"p{k}": gc["pattern"]["panels"]["A"]
                               for k in range(limits.panels + 1)}
    with pytest.raises(PatternError, match="501 panels"):
        garmentcode_from_dict(gc)


def _r12(blocks: dict[str, list[str]]) -> str:
    """A minimal DXF R12 file, as many CAD exporters write one: a BLOCKS section of the
    given blocks (each a list of entities as tag text), no header or tables."""
    out = ["  0\nSECTION\n  2\nBLOCKS\n"]
    for name, entities in blocks.items():
        out += [f"  0\nBLOCK\n  8\n1\n  2\n{name}\n 70\n0\n 10\n0\n 20\n0\n 30\n0\n",
                *entities, "  0\nENDBLK\n  8\n1\n"]
    return "".join(out + ["  0\nENDSEC\n  0\nEOF\n"])


def _polyline(pts) -> str:
    head = "  0\nPOLYLINE\n  8\n1\n 66\n1\n 10\n0\n 20\n0\n 30\n0\n 70\n1\n"
    return head + "".join(f"  0\nVERTEX\n  8\n1\n 10\n{x}\n 20\n{y}\n 30\n0\n"
                          for x, y in pts) + "  0\nSEQEND\n  8\n1\n"


def test_dxf_entity_and_piece_counts_are_capped(tmp_path):
    square = _polyline([(0, 0), (400, 0), (400, 600), (0, 600)])
    points = [f"  0\nPOINT\n  8\n2\n 10\n{k * 0.01}\n 20\n1\n 30\n0\n"
              for k in range(limits.segments_per_panel)]
    (tmp_path / "points.dxf").write_text(_r12({"P": [square, *points]}))
    exc = _refused(load_dxf, tmp_path / "points.dxf")
    assert exc.panel == "P" and "20001 entities, more than the limit" in exc.reason
    (tmp_path / "pieces.dxf").write_text(_r12({f"P{k}": [square]
                                               for k in range(limits.panels + 1)}))
    assert "501 blocks with a boundary" in _refused(load_dxf, tmp_path / "pieces.dxf").reason
    (tmp_path / "ok.dxf").write_text(_r12({"P": [square]}))
    assert load_dxf(tmp_path / "ok.dxf").panels[0].outline.length == pytest.approx(2.0)


# -------------------------------------------------------------------------- mutations
_json_values = st.recursive(
    st.none() | st.booleans() | st.integers(-10**30, 10**30) | st.text(max_size=4)
    | st.floats(allow_nan=False, allow_infinity=False),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=4), inner,
                                                                 max_size=3),
    max_leaves=6)


def _mutated(doc, data):
    """``doc`` with up to three values somewhere inside replaced by arbitrary JSON, or
    removed."""
    doc = copy.deepcopy(doc)
    for _ in range(data.draw(st.integers(1, 3))):
        parent, key = None, None
        node = doc
        while isinstance(node, (dict, list)) and node and data.draw(st.integers(0, 3)):
            keys = sorted(node) if isinstance(node, dict) else range(len(node))
            parent, key = node, data.draw(st.sampled_from(list(keys)))
            node = node[key]
        if parent is None:
            continue
        if isinstance(parent, dict) and data.draw(st.booleans()):
            del parent[key]
        else:
            parent[key] = data.draw(_json_values)
    return doc


@FEW
@given(st.data())
def test_mutated_pattern_json_gives_a_pattern_or_a_pattern_error(tmp_path_factory, data):
    doc = _mutated(pattern_to_dict(_square_pattern(), units="cm"), data)
    path = tmp_path_factory.mktemp("json") / "mutated.json"
    path.write_text(json.dumps(doc))
    try:
        load_any_pattern(path)
    except PatternError as exc:
        assert exc.file == str(path)


@FEW
@given(st.data())
def test_mutated_garmentcode_gives_a_pattern_or_a_pattern_error(tmp_path_factory, data):
    doc = _mutated(garmentcode_to_dict(Pattern("p", _square_pattern().panels[1:])), data)
    path = tmp_path_factory.mktemp("gc") / "mutated_specification.json"
    path.write_text(json.dumps(doc))
    try:
        load_any_pattern(path)
    except PatternError as exc:
        assert exc.file == str(path)


@pytest.fixture(scope="module")
def dxf_files(tmp_path_factory):
    path = save_dxf(_square_pattern(), tmp_path_factory.mktemp("dxf") / "good.dxf")
    return path.read_text(), json.loads(sidecar_path(path).read_text())


@FEW
@given(data=st.data())
def test_mutated_dxf_gives_a_pattern_or_a_pattern_error(dxf_files, tmp_path_factory, data):
    lines = dxf_files[0].splitlines(keepends=True)
    for _ in range(data.draw(st.integers(1, 4))):
        k = data.draw(st.integers(0, len(lines) - 1))
        lines[k] = data.draw(st.sampled_from(["0\n", "-1e300\n", "nan\n", "POLYLINE\n", "",
                                              "\x00\xff\n", "1e12\n", "  10\n", "SEQEND\n"]))
    cut = data.draw(st.integers(1, len(lines)))
    path = tmp_path_factory.mktemp("dxf") / "mutated.dxf"
    path.write_text("".join(lines[:cut]), errors="surrogateescape")
    try:
        load_dxf(path)
    except PatternError as exc:
        assert exc.file == str(path)


@FEW
@given(data=st.data())
def test_mutated_side_file_gives_a_pattern_or_a_pattern_error(dxf_files, tmp_path_factory,
                                                              data):
    folder = tmp_path_factory.mktemp("side")
    (folder / "good.dxf").write_text(dxf_files[0])
    side = sidecar_path(folder / "good.dxf")
    side.write_text(json.dumps(_mutated(dxf_files[1], data)))
    try:
        load_dxf(folder / "good.dxf")
    except PatternError as exc:
        assert exc.file in (str(side), str(folder / "good.dxf"))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data(), key=st.sampled_from(["reversed", "grain_line", "rotaton", "Name",
                                            "radius2", "comment", "ranges"]))
def test_a_key_the_format_does_not_have_is_refused_naming_it(tmp_path_factory, data, key):
    """A misspelt key was skipped for its default without a word: a seam's "reversed":
    false was read as reverse true, a panel's "grain_line" left the grain at [0, 1]."""
    from patternfit.pattern import load_pattern, pattern_to_dict
    from patternfit.pattern.library import build

    doc = pattern_to_dict(build("skirt", "M"), units="cm")
    panel = doc["panels"][0]
    objects = [doc, panel, panel["placement"], panel["outline"], panel["outline"]["edges"][0],
               doc["seams"][0], doc["seams"][0]["a"]]
    target = data.draw(st.sampled_from(objects))
    target[key] = False
    path = tmp_path_factory.mktemp("keys") / "p.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(InputError, match=f"unknown key '{key}'") as info:
        load_pattern(path)
    assert str(path) in str(info.value)


@pytest.mark.parametrize("mark", ["lines", "drill_holes", "cut_line"])
def test_a_mark_beyond_the_extent_is_refused(tmp_path, mark):
    """A drill hole 1e7 m out was read, and written to a DXF that the DXF reader refused."""
    from patternfit.pattern import load_pattern, pattern_to_dict
    from patternfit.pattern.library import build

    doc = pattern_to_dict(build("skirt", "M"))
    far = [[0.0, 0.1], [1e7, 0.2], [0.1, 0.3]]
    doc["panels"][0][mark] = [{"name": "l", "points": far}] if mark == "lines" else far
    path = tmp_path / "far.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(InputError, match="beyond the limit of 20 m") as info:
        load_pattern(path)
    assert str(path) in str(info.value) and "panel 'front'" in str(info.value)


@pytest.mark.parametrize("garment, unit, words", [
    ("skirt", "mm", "read in millimetres (its 'units': 'mm')"),
    ("coat", "in", "read in inches (its 'units': 'in')")])
def test_a_json_pattern_of_implausible_size_is_warned_of_as_other_formats_are(
        tmp_path, garment, unit, words):
    """A skirt in cm stated as "mm" (6.4 cm wide) read without a word as patternfit JSON,
    where the DXF and GarmentCode readers warn; at its true units, nothing is said."""
    from patternfit.pattern.formats import load_any_pattern, save_any_pattern
    from patternfit.pattern.library import build

    path = tmp_path / "p.json"
    save_any_pattern(build(garment, "M"), path, units="cm")
    assert not load_any_pattern(path).meta.get("warnings")
    doc = json.loads(path.read_text())
    path.write_text(json.dumps({**doc, "units": unit}))
    read = load_any_pattern(path)
    said = read.meta["warnings"]
    assert said and all(words in w and 'set "units": "cm" in the file' in w for w in said)
    # written again in metres, it is read in metres: the warning is of this reading, not
    # the earlier one (kept, it said "set units cm", which would make it 100 times larger)
    save_any_pattern(read, path, units="m")
    again = load_any_pattern(path).meta.get("warnings") or []
    assert not any(words in w for w in again)
    assert all("read in metres" in w for w in again)
