"""DXF-AAMA / ASTM D6673 reading rules, one per test, on files written here with ezdxf the
way Gerber AccuMark and CLO write them (our writer only where a test reads back what it
wrote).

AccuMark (``shared/AAMA-ASTM.md``): R12, one block per piece and size, the cut line a closed
POLYLINE on layer 1 with every turn point repeated, turn points on layer 2, notches as short
LINEs on layer 4, mirror line 6, grain line 7, internal lines 8, drill holes 13 (POINTs), sew
line 14; piece text ``Piece Name:``, ``SIZE:``, ``QUANTITY:`` (keys in any case); style text
``Style Name:``, ``Sample Size:``, ``Grade Rule Table:``, ``UNITS: ENGLISH`` (inches). CLO:
LWPOLYLINE in millimetres ($INSUNITS 4), curves as dense short segments, no turn points.

Areas are checked against the shoelace formula of the file's own polyline.
"""

from __future__ import annotations

import json
from dataclasses import replace

import ezdxf
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from patternfit import api
from patternfit.constants import tol
from patternfit.geometry import triangle_areas
from patternfit.cli.main import app
from patternfit.mesh import min_angle
from patternfit.mesh.triangulate import mesh_pattern
from patternfit.pattern import PatternError, Seam, SeamSide
from patternfit.pattern.dxf import load_dxf, save_dxf

MM = 0.001


def shoelace(p) -> float:
    """|area| of a closed polygon (k, 2), last point not repeated."""
    p = np.asarray(p, dtype=float)
    q = np.roll(p, -1, axis=0)
    return 0.5 * abs(float(np.sum(p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1])))


def _bezier(c, n):
    t = np.linspace(0, 1, n)[:, None]
    c = np.asarray(c, dtype=float)
    return ((1 - t) ** 3 * c[0] + 3 * (1 - t) ** 2 * t * c[1] + 3 * (1 - t) * t * t * c[2]
            + t ** 3 * c[3])


# -- pieces [mm], each a list of runs from one turn point to the next -------------------------
def half_front(grow: float = 1.0) -> list[np.ndarray]:
    """The right half of a front bodice, centre front on x = 0 (the fold)."""
    g = np.array([grow, 1.0 + 0.5 * (grow - 1.0)])
    return [np.array([(0, 0), (250, 0)]) * g,                                       # hem
            np.array([(250, 0), (250, 300)]) * g,                                   # side
            _bezier([(250, 300), (200, 310), (185, 360), (190, 450)], 12) * g,      # armhole
            np.array([(190, 450), (110, 480)]) * g,                                 # shoulder
            _bezier([(110, 480), (100, 430), (40, 410), (0, 410)], 10) * g,         # neck
            np.array([(0, 410), (0, 0)]) * g]                                       # fold


def sleeve(grow: float = 1.0) -> list[np.ndarray]:
    """An asymmetric sleeve (front cap lower than the back)."""
    g = np.array([grow, 1.0 + 0.5 * (grow - 1.0)])
    return [np.array([(40, 0), (260, 0)]) * g,
            np.array([(260, 0), (320, 420)]) * g,
            _bezier([(320, 420), (260, 560), (120, 590), (0, 430)], 16) * g,
            np.array([(0, 430), (40, 0)]) * g]


def ring(runs) -> np.ndarray:
    return np.concatenate([r[:-1] for r in runs])


def accumark(path, blocks, *, sample=None, scale=25.4, style="STYLE1", table=None):
    """Blocks written as AccuMark writes AAMA: ``blocks`` are dicts with ``name``, ``size``,
    ``quantity``, ``runs`` (cut line [mm]) and optionally ``sew`` (runs), ``notches`` (pairs
    of points), ``fold`` (two points), ``lines``, ``drills``, ``grain`` (the grain line's
    two ends, as the tool writes them: up the piece by default) [mm]; file units mm / ``scale``
    (25.4: inches, ``UNITS: ENGLISH``; 1: ``UNITS: METRIC``)."""
    doc = ezdxf.new("R12")
    msp = doc.modelspace()

    def polyline(blk, runs, layer):
        pts = []
        for r in runs:  # every turn point twice
            pts += [r[0]] + list(r)
        pts = np.array(pts) / scale
        blk.add_polyline2d(np.round(pts, 5).tolist() + [pts[0].round(5).tolist()],
                           dxfattribs={"layer": layer})
        for r in runs:
            blk.add_point(tuple(r[0] / scale), dxfattribs={"layer": "2"})

    for k, b in enumerate(blocks):
        blk = doc.blocks.new(f"{b['name']}-{b.get('size', '')}-{k}")
        polyline(blk, b["runs"], "1")
        if b.get("sew"):
            polyline(blk, b["sew"], "14")
        for a, c in b.get("notches", []):
            blk.add_line(tuple(np.asarray(a) / scale), tuple(np.asarray(c) / scale),
                         dxfattribs={"layer": "4"})
        if b.get("fold") is not None:
            a, c = b["fold"]
            blk.add_line(tuple(np.asarray(a) / scale), tuple(np.asarray(c) / scale),
                         dxfattribs={"layer": "6"})
        for line in b.get("lines", []):
            blk.add_polyline2d((np.asarray(line) / scale).tolist(), dxfattribs={"layer": "8"})
        for d in b.get("drills", []):
            blk.add_point(tuple(np.asarray(d) / scale), dxfattribs={"layer": "13"})
        a, c = b.get("grain", ((100, 100), (100, 300)))
        blk.add_line(tuple(np.asarray(a) / scale), tuple(np.asarray(c) / scale),
                     dxfattribs={"layer": "7"})
        texts = [f"Piece Name: {b['name']}", f"QUANTITY: {b.get('quantity', 1)}",
                 "Category: SHELL"] + ([f"SIZE: {b['size']}"] if b.get("size") else [])
        for j, t in enumerate(texts):
            blk.add_text(t, dxfattribs={"layer": "1", "insert": (2, 2 + j)})
        msp.add_blockref(blk.name, (k * 1000 / scale, 0))
    words = [f"Style Name: {style}", f"UNITS: {'ENGLISH' if scale == 25.4 else 'METRIC'}",
             "Author: ACCUMARK"] + ([f"Sample Size: {sample}"] if sample else []) \
        + ([f"Grade Rule Table: {table}"] if table else [])
    for j, t in enumerate(words):
        msp.add_text(t, dxfattribs={"layer": "1", "insert": (0, -10 - j)})
    doc.saveas(path)
    return path


def clo(path, blocks, *, sample=None):
    """Blocks as CLO writes DXF-AAMA: one LWPOLYLINE per line, many short segments, no turn
    points, millimetres in the header ($INSUNITS 4)."""
    doc = ezdxf.new("R2000")
    doc.header["$INSUNITS"] = 4
    for k, b in enumerate(blocks):
        blk = doc.blocks.new(f"P{k}")
        dense = np.concatenate([np.linspace(r[i], r[i + 1], 6)[:-1] for r in b["runs"]
                                for i in range(len(r) - 1)])
        blk.add_lwpolyline(dense.tolist(), close=True, dxfattribs={"layer": "1"})
        blk.add_text(f"Piece Name: {b['name']}", dxfattribs={"layer": "1"})
        if b.get("size"):
            blk.add_text(f"Size: {b['size']}", dxfattribs={"layer": "1"})
        blk.add_text(f"Quantity: {b.get('quantity', 1)}", dxfattribs={"layer": "1"})
        doc.modelspace().add_blockref(blk.name, (k * 1000, 0))
    if sample:
        doc.modelspace().add_text(f"Sample Size: {sample}", dxfattribs={"layer": "1"})
    doc.saveas(path)
    return path


SIZES = {"34": 0.94, "36": 1.0, "38": 1.06}


def graded(writer, path):
    """A two-piece style in three sizes (36 the sample), every piece a block per size."""
    blocks = [b for s, g in SIZES.items() for b in (
        {"name": "FRONT", "size": s, "runs": half_front(g)},
        {"name": "SLEEVE", "size": s, "runs": sleeve(g)})]
    return writer(path, blocks, sample="36") if writer is clo else \
        writer(path, blocks, sample="36", table="BASIC")


def _min_angle(pattern) -> float:
    m = mesh_pattern(pattern, triangles=1500, min_angle=25)
    return min_angle(m.vertices, m.triangles)


# -- multi-size ---------------------------------------------------------------------------------
@pytest.mark.parametrize("writer", [accumark, clo])
def test_multi_size_file_is_one_pattern_in_the_sample_size(tmp_path, writer):
    p = load_dxf(graded(writer, tmp_path / "g.dxf"))
    assert [q.name for q in p.panels] == ["FRONT", "SLEEVE"]
    assert p.meta["size"] == "36" and p.meta["sizes"] == ["34", "36", "38"]
    assert set(p.meta["grade"]) == {"34", "38"}
    for panel, runs in zip(p.panels, (half_front(1.0), sleeve(1.0))):
        assert panel.area() == pytest.approx(shoelace(ring(runs)) * MM**2, rel=1e-3)
    assert _min_angle(p) >= 25.0 - 1e-6  # as asked


@pytest.mark.parametrize("writer", [accumark, clo])
def test_size_picks_another_size_and_an_unknown_one_is_refused(tmp_path, writer):
    path = graded(writer, tmp_path / "g.dxf")
    p = load_dxf(path, size="38")
    assert p.meta["size"] == "38" and set(p.meta["grade"]) == {"34", "36"}
    for panel, runs in zip(p.panels, (half_front(1.06), sleeve(1.06))):
        assert panel.area() == pytest.approx(shoelace(ring(runs)) * MM**2, rel=1e-3)
    assert api.read_pattern(path, size="34").panel("SLEEVE").area() == pytest.approx(
        shoelace(ring(sleeve(0.94))) * MM**2, rel=1e-3)
    with pytest.raises(PatternError, match="no size '50'.*34, 36, 38") as info:
        load_dxf(path, size="50")
    assert info.value.file == str(path)


def test_size_on_the_command_line(tmp_path):
    path = graded(accumark, tmp_path / "g.dxf")
    runner = CliRunner()
    out = runner.invoke(app, ["convert", str(path), str(tmp_path / "g38.json"), "--size", "38",
                              "--json"])
    assert out.exit_code == 0, out.output
    said = json.loads(out.output)
    assert said["size"] == "38" and said["sizes"] == ["34", "36", "38"]
    p = api.read_pattern(tmp_path / "g38.json")
    assert p.meta["size"] == "38"
    assert p.panel("FRONT").area() == pytest.approx(shoelace(ring(half_front(1.06))) * MM**2,
                                                    rel=1e-3)
    bad = runner.invoke(app, ["mesh", str(path), "--size", "XL", "--out", str(tmp_path / "m")])
    assert bad.exit_code == 2
    assert "g.dxf" in bad.output and "34, 36, 38" in bad.output
    # a JSON file holds one size: another one is refused, not ignored
    bad = runner.invoke(app, ["convert", str(tmp_path / "g38.json"), str(tmp_path / "x.json"),
                              "--size", "34"])
    assert bad.exit_code == 2 and "one size" in bad.output


# -- pairs and folds ----------------------------------------------------------------------------
def test_quantity_two_is_a_left_and_a_mirrored_right_piece(tmp_path):
    path = accumark(tmp_path / "q.dxf", [{"name": "SLEEVE", "quantity": 2, "runs": sleeve()}])
    p = load_dxf(path)
    left, right = p.panels
    assert (left.name, right.name) == ("SLEEVE_L", "SLEEVE_R")
    assert p.meta["pairs"] == {"SLEEVE": ["SLEEVE_L", "SLEEVE_R"]}
    area = shoelace(ring(sleeve())) * MM**2
    assert left.area() == pytest.approx(area, rel=1e-3) and right.area() == \
        pytest.approx(area, rel=1e-3)
    a, b = left.outline.polygon(16), right.outline.polygon(16)
    assert np.allclose(b, a * [-1, 1])  # turned over
    assert left.outline.signed_area() * right.outline.signed_area() < 0
    assert [e.name for e in left.outline.edges] == [e.name for e in right.outline.edges]
    assert right.grainline == pytest.approx((-left.grainline[0], left.grainline[1]))


def test_quantity_one_left_one_right_is_a_pair(tmp_path):
    # Optitex writes a left/right pair as "Quantity: 1,1" (one of each)
    path = accumark(tmp_path / "q.dxf", [{"name": "SLEEVE", "quantity": "1,1",
                                          "runs": sleeve()}])
    p = load_dxf(path)
    assert [q.name for q in p.panels] == ["SLEEVE_L", "SLEEVE_R"]


def test_mirror_line_unfolds_the_half_piece(tmp_path):
    half = half_front()
    path = accumark(tmp_path / "f.dxf", [{"name": "FRONT", "runs": half,
                                          "fold": ((0, 0), (0, 410))}])
    (panel,) = load_dxf(path).panels
    assert panel.area() == pytest.approx(2 * shoelace(ring(half)) * MM**2, rel=1e-3)
    poly = panel.outline.polygon(32)
    assert poly[:, 0].min() == pytest.approx(-0.25, abs=1e-6)
    assert poly[:, 0].max() == pytest.approx(0.25, abs=1e-6)
    # symmetric about the fold, and no edge left along it
    mirrored = poly * [-1, 1]
    d = np.linalg.norm(mirrored[:, None] - panel.outline.polygon(256)[None], axis=2).min(axis=1)
    assert d.max() < 5e-4
    for e in panel.outline.edges:
        assert not (abs(e.start[0]) < 1e-6 and abs(e.end[0]) < 1e-6), e
    assert _min_angle(load_dxf(path)) >= 25.0 - 1e-6  # as asked


def test_a_mirror_line_off_the_boundary_is_refused(tmp_path):
    path = accumark(tmp_path / "f.dxf", [{"name": "FRONT", "runs": half_front(),
                                          "fold": ((100, 50), (100, 300))}])
    with pytest.raises(PatternError, match="mirror line") as info:
        load_dxf(path)
    assert info.value.file == str(path) and "FRONT" in str(info.value)


# -- cut line, sew line, notches, internal lines, drill holes ------------------------------------
def skirt_piece():
    """A panel with its sew line 10 mm inside the cut line at the sides, 30 mm at the hem,
    notched on the cut line at mid side, mid hem and at a corner; a dart leg and its tip."""
    sew = [np.array([(0, 0), (300, 0)]), np.array([(300, 0), (300, 500)]),
           np.array([(300, 500), (0, 500)]), np.array([(0, 500), (0, 0)])]
    cut = [np.array([(-10, -30), (310, -30)]), np.array([(310, -30), (310, 510)]),
           np.array([(310, 510), (-10, 510)]), np.array([(-10, 510), (-10, -30)])]
    notches = [((310, 250), (304, 250)), ((150, -30), (150, -24)), ((310, 510), (305, 505))]
    return {"name": "SKIRT", "runs": cut, "sew": sew, "notches": notches,
            "lines": [[(120, 500), (150, 380), (180, 500)]], "drills": [(150, 390)]}


def test_cut_and_sew_line_both_kept_the_sew_line_is_the_outline(tmp_path):
    path = accumark(tmp_path / "s.dxf", [skirt_piece()], scale=1.0)
    (panel,) = load_dxf(path).panels
    assert panel.area() == pytest.approx(0.3 * 0.5, rel=1e-6)
    assert shoelace(panel.cut_line) == pytest.approx(0.32 * 0.54, rel=1e-6)
    assert _min_angle(load_dxf(path)) >= 25.0 - 1e-6  # as asked
    cut_only = load_dxf(path, prefer_sew=False).panels[0]
    assert cut_only.area() == pytest.approx(0.32 * 0.54, rel=1e-6) and cut_only.cut_line == ()


def test_notches_on_edges_and_turn_points(tmp_path):
    path = accumark(tmp_path / "n.dxf", [skirt_piece()], scale=1.0)
    (panel,) = load_dxf(path).panels
    where = {}
    for n in panel.notches:
        e = panel.edge(n.edge)
        where[tuple(np.round(e.point_at([n.t])[0], 6))] = (n.t, n.kind)
    assert where[(0.3, 0.25)] == (pytest.approx(0.5), "slit")   # mid side, across 10 mm
    assert where[(0.15, 0.0)] == (pytest.approx(0.5), "slit")   # mid hem, across 30 mm
    corner = [n for n in panel.notches if np.allclose(panel.edge(n.edge).start, (0.3, 0.5))]
    assert [n.t for n in corner] == [0.0]                       # the turn point: t = 0
    assert len(panel.notches) == 3


def test_turn_point_notches_of_a_cut_line_only_file(tmp_path):
    runs = sleeve()
    notches = [(r[0], r[0] + (0, 5)) for r in runs]  # AccuMark: a notch on every corner
    (panel,) = load_dxf(accumark(tmp_path / "t.dxf", [{"name": "S", "runs": runs,
                                                       "notches": notches}])).panels
    assert sorted(n.t for n in panel.notches) == [0.0] * 4
    starts = {tuple(np.round(panel.edge(n.edge).start / MM, 3)) for n in panel.notches}
    assert starts == {tuple(np.round(r[0] * 25.4 / 25.4, 3)) for r in runs}


def test_internal_lines_and_drill_holes_are_kept_not_meshed(tmp_path):
    path = accumark(tmp_path / "l.dxf", [skirt_piece()], scale=1.0)
    p = load_dxf(path)
    (panel,) = p.panels
    (line,) = panel.lines
    assert np.allclose(line.points, np.array([(120, 500), (150, 380), (180, 500)]) * MM)
    assert np.allclose(panel.drill_holes, [(0.150, 0.390)])
    assert panel.inner == ()
    m = mesh_pattern(p, triangles=800)
    assert triangle_areas(m.vertices, m.triangles).sum() == pytest.approx(panel.area(),
                                                                          rel=1e-3)  # no holes


# -- writing back ---------------------------------------------------------------------------------
def _everything(tmp_path):
    blocks = []
    for s, g in SIZES.items():
        piece = skirt_piece()
        piece["size"] = s
        piece["runs"] = [r * [g, 1] for r in piece["runs"]]
        piece["sew"] = [r * [g, 1] for r in piece["sew"]]
        blocks += [piece, {"name": "SLEEVE", "size": s, "quantity": 2, "runs": sleeve(g)},
                   {"name": "FRONT", "size": s, "runs": half_front(g),
                    "fold": ((0, 0), (0, 410))}]
    return accumark(tmp_path / "all.dxf", blocks, sample="36", scale=1.0)


def test_write_read_round_trip_keeps_everything(tmp_path):
    p = load_dxf(_everything(tmp_path))
    assert [q.name for q in p.panels] == ["SKIRT", "SLEEVE_L", "SLEEVE_R", "FRONT"]
    skirt, sleeve_l = p.panel("SKIRT"), p.panel("SLEEVE_L")
    seams = (Seam("cap", SeamSide("SLEEVE_L", sleeve_l.outline.edges[2].name),
                  SeamSide("SKIRT", skirt.outline.edges[2].name), ease=0.5),)
    v_notch = replace(skirt.notches[0], kind="v")  # a kind AAMA's layer 4 cannot say
    p = type(p)(p.name, p.panels, seams, p.meta).with_panel(
        replace(skirt, notches=(v_notch, *skirt.notches[1:])))
    back = load_dxf(save_dxf(p, tmp_path / "out.dxf"))
    assert back.panel("SKIRT").notches[0].kind == "v"
    assert back.seams == p.seams and back.seams[0].ease == 0.5
    assert back.meta["sizes"] == p.meta["sizes"] and back.meta["size"] == "36"
    assert back.meta["pairs"] == p.meta["pairs"]
    for a, b in zip(p.panels, back.panels):
        assert a.name == b.name
        assert np.abs(a.outline.polygon(64) - b.outline.polygon(64)).max() < 1e-6
        assert a.notches == b.notches
        assert len(a.cut_line) == len(b.cut_line)
        assert np.allclose(a.cut_line, b.cut_line, atol=1e-9)
        assert [ln.name for ln in a.lines] == [ln.name for ln in b.lines]
        for la, lb in zip(a.lines, b.lines):
            assert np.allclose(la.points, lb.points, atol=1e-9)
        assert np.allclose(a.drill_holes, b.drill_holes, atol=1e-9)
    # every other size comes back too, and reads as the original file's
    bare = save_dxf(p, tmp_path / "bare.dxf", sidecar=False)
    for size in ("34", "38"):
        x, y = load_dxf(tmp_path / "all.dxf", size=size), load_dxf(bare, size=size)
        assert [q.name for q in x.panels] == [q.name for q in y.panels]
        for a, b in zip(x.panels, y.panels):
            assert b.area() == pytest.approx(a.area(), rel=1e-9)
            assert bool(a.cut_line) == bool(b.cut_line) == (a.name == "SKIRT")
            if a.cut_line:
                assert shoelace(b.cut_line) == pytest.approx(shoelace(a.cut_line), rel=1e-9)
            assert len(b.notches) == len(a.notches)


def test_written_file_keeps_the_aama_layers_for_other_cad(tmp_path):
    p = load_dxf(_everything(tmp_path))
    path = save_dxf(p, tmp_path / "out.dxf", sidecar=False)
    doc = ezdxf.readfile(path)
    by_size: dict[str, dict] = {}
    for blk in doc.blocks:
        if blk.name.startswith("*"):
            continue
        words = {t.dxf.text.split(":")[0]: t.dxf.text.split(":", 1)[1].strip()
                 for t in blk if t.dxftype() == "TEXT"}
        by_size.setdefault(words["Size"], {})[words["Piece Name"]] = (blk, words)
    assert set(by_size) == {"34", "36", "38"}
    skirt, words = by_size["36"]["SKIRT"]
    layers = {e.dxf.layer for e in skirt}
    assert {"1", "2", "4", "7", "8", "13", "14"} <= layers
    cut = [e for e in skirt if e.dxftype() == "POLYLINE" and e.dxf.layer == "1"][0]
    sew = [e for e in skirt if e.dxftype() == "POLYLINE" and e.dxf.layer == "14"][0]
    area = [shoelace([tuple(v.dxf.location)[:2] for v in q.vertices]) for q in (cut, sew)]
    assert area == pytest.approx([320 * 540, 300 * 500], rel=1e-6)  # the allowance is there
    _, sleeve_words = by_size["36"]["SLEEVE"]
    assert sleeve_words["Quantity"] == "2"  # one block for the pair
    texts = [e.dxf.text for e in doc.modelspace() if e.dxftype() == "TEXT"]
    assert "Sample Size: 36" in texts and "Units: METRIC" in texts


# -- property: reading rules keep the file's area -------------------------------------------------
@st.composite
def _half(draw):
    """A random half piece [mm] right of the fold x = 0: a star around a centre on the fold."""
    n = draw(st.integers(3, 9))
    size = draw(st.floats(60, 300))
    radii = draw(st.lists(st.floats(0.5, 1.0), min_size=n, max_size=n))
    ang = np.linspace(-np.pi / 2, np.pi / 2, n + 2)[1:-1]
    pts = size * np.column_stack([np.array(radii) * np.cos(ang), np.array(radii) * np.sin(ang)])
    return np.vstack([(0.0, -size * 0.8), pts, (0.0, size * 0.8)])


@settings(max_examples=10, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(half=_half(), repeats=st.lists(st.integers(0, 2), min_size=12, max_size=12),
       scale=st.sampled_from([1.0, 25.4]))
def test_random_halves_unfold_to_the_mirrored_polyline(tmp_path, half, repeats, scale):
    runs = [np.array([a, b]) for a, b in zip(half, np.roll(half, -1, axis=0))]
    # extra repeated points inside runs, as rounding inch files make them
    runs = [np.vstack([r[:1]] * (1 + repeats[k % len(repeats)]) + [r]) for k, r in
            enumerate(runs)]
    path = accumark(tmp_path / "h.dxf", [{"name": "H", "runs": runs,
                                          "fold": (half[-1], half[0])}], scale=scale)
    (panel,) = load_dxf(path).panels
    # fitted within tol.dxf_span of the polyline: the area within perimeter x that
    full = np.vstack([half, half[::-1][1:-1] * [-1, 1]]) * MM
    perimeter = np.linalg.norm(full - np.roll(full, 1, axis=0), axis=1).sum()
    assert abs(panel.area() - shoelace(full)) <= perimeter * tol.dxf_span
    poly = panel.outline.polygon(64)
    assert poly[:, 0].min() == pytest.approx(-poly[:, 0].max(), abs=tol.dxf_span)


# -- bad input ------------------------------------------------------------------------------------
def test_a_quantity_that_is_not_a_count_is_refused_naming_the_piece(tmp_path):
    path = accumark(tmp_path / "q.dxf", [{"name": "CUFF", "quantity": "two", "runs": sleeve()}])
    with pytest.raises(PatternError, match="Quantity: two") as info:
        load_dxf(path)
    assert info.value.file == str(path) and info.value.panel == "CUFF--0"


def test_a_damaged_grade_in_a_pattern_file_is_refused_on_writing(tmp_path):
    p = load_dxf(graded(accumark, tmp_path / "g.dxf"))
    p.meta["grade"]["34"][0]["cut"] = [[0.0, 0.1, 0.2]]  # an odd number of coordinates
    with pytest.raises(PatternError, match="graded size") as info:
        save_dxf(p, tmp_path / "out.dxf")
    assert info.value.file == str(tmp_path / "out.dxf")
    assert not (tmp_path / "out.dxf").exists()


def test_a_piece_with_only_a_sew_line_is_read_on_it(tmp_path):
    doc = ezdxf.new("R12")
    blk = doc.blocks.new("P")
    blk.add_polyline2d([(0, 0), (200, 0), (200, 300), (0, 300)], close=True,
                       dxfattribs={"layer": "14"})
    doc.modelspace().add_blockref("P", (0, 0))
    doc.saveas(tmp_path / "s.dxf")
    for prefer in (True, False):
        (panel,) = load_dxf(tmp_path / "s.dxf", prefer_sew=prefer).panels
        assert panel.area() == pytest.approx(0.06) and panel.cut_line == ()


def test_astm_variant_boundary_and_internal_line_layers(tmp_path):
    doc = ezdxf.new("R12")
    blk = doc.blocks.new("P")
    blk.add_polyline2d([(0, 0), (200, 0), (200, 300), (0, 300)], close=True,
                       dxfattribs={"layer": "84"})
    blk.add_line((50, 50), (50, 250), dxfattribs={"layer": "85"})
    blk.add_text("Piece Name: BACK", dxfattribs={"layer": "1"})
    doc.modelspace().add_blockref("P", (0, 0))
    doc.modelspace().add_text("Units: METRIC", dxfattribs={"layer": "1"})
    doc.saveas(tmp_path / "astm.dxf")
    (panel,) = load_dxf(tmp_path / "astm.dxf").panels
    assert panel.name == "BACK" and panel.area() == pytest.approx(0.06)
    assert np.allclose(panel.lines[0].points, [(0.05, 0.05), (0.05, 0.25)])


def test_another_size_of_our_own_file_reads_as_the_original_and_skips_the_side_file(tmp_path):
    original = _everything(tmp_path)
    out = save_dxf(load_dxf(original), tmp_path / "out.dxf")
    for size in ("34", "38"):
        a, b = load_dxf(original, size=size), load_dxf(out, size=size)
        assert [len(q.outline.edges) for q in a.panels] == \
            [len(q.outline.edges) for q in b.panels]  # merged as another tool's file
        assert b.seams == () and any("describes size 36" in w for w in b.meta["warnings"])
    assert "warnings" not in load_dxf(out).meta


def test_the_piece_limit_counts_the_blocks_of_one_size(tmp_path, monkeypatch):
    import dataclasses

    import patternfit.pattern.dxf as dxf

    monkeypatch.setattr(dxf, "limits", dataclasses.replace(dxf.limits, panels=5))
    square = [np.array([a, b]) for a, b in [((0, 0), (200, 0)), ((200, 0), (200, 300)),
                                            ((200, 300), (0, 300)), ((0, 300), (0, 0))]]
    blocks = [{"name": f"P{k}", "size": s, "runs": square} for s in SIZES for k in range(4)]
    path = accumark(tmp_path / "many.dxf", blocks, sample="34")
    p = load_dxf(path, size="38")  # 12 blocks, 4 a size: within the limit of 5 panels
    assert len(p.panels) == 4 and p.meta["size"] == "38"
    blocks += [{"name": "P9", "size": "36", "runs": square},
               {"name": "ALL", "runs": square}]  # no size: in every size
    accumark(path, blocks, sample="34")
    with pytest.raises(PatternError, match="6 blocks with a boundary in size 36"):
        load_dxf(path)
