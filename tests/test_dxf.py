"""DXF-AAMA import and export, on files written by the tests."""

import json
import math

import ezdxf
import numpy as np
import pytest
from typer.testing import CliRunner

from patternfit.cli.main import app
from patternfit.pattern import Edge, Loop, Panel, Pattern, PatternError, Placement, Seam, SeamSide
from patternfit.pattern.dxf import load_dxf, save_dxf, sidecar_path


def _outline_distance(a: Loop, b: Loop) -> float:
    """Symmetric Hausdorff distance between two loops' dense polygons [m]."""
    pa, pb = a.polygon(256), b.polygon(256)
    d = np.linalg.norm(pa[:, None] - pb[None], axis=2)
    return float(max(d.min(axis=1).max(), d.min(axis=0).max()))


def _pattern() -> Pattern:
    front = Panel("front", Loop("outline", (
        Edge.quadratic("hem", (0, 0), (0.2, -0.03), (0.4, 0)),
        Edge.line("side", (0.4, 0), (0.4, 0.5)),
        Edge.cubic("neck", (0.4, 0.5), (0.3, 0.42), (0.1, 0.62), (0, 0.5)),
        Edge.line("centre", (0, 0.5), (0, 0)))),
        inner=(Loop("dart", (Edge.line("d0", (0.15, 0.1), (0.25, 0.1)),
                             Edge.line("d1", (0.25, 0.1), (0.2, 0.3)),
                             Edge.line("d2", (0.2, 0.3), (0.15, 0.1)))),),
        grainline=(0.0, 1.0), placement=Placement("torso", "front", (0, 1.1, 0.1), (0, 0, 0)))
    back = Panel("back", Loop("outline", (
        Edge.line("hem", (0, 0), (0.4, 0)),
        Edge.line("centre", (0.4, 0), (0.4, 0.5)),
        Edge.arc("bump", (0.4, 0.5), (0.2, 0.5), 0.12, large_arc=True, sweep=True),
        Edge.line("top", (0.2, 0.5), (0, 0.5)),
        Edge.line("side", (0, 0.5), (0, 0)))), grainline=(1.0, 1.0))
    seams = (Seam("side", SeamSide("front", "side"), SeamSide("back", "side")),
             Seam("part", SeamSide("front", "centre", 0.0, 0.5),
                  SeamSide("back", "centre", 0.5, 1.0), reverse=False))
    return Pattern("test", (front, back), seams, {"size": "M"})


def test_round_trip_preserves_outline_names_and_seams(tmp_path):
    p = _pattern()
    path = save_dxf(p, tmp_path / "t.dxf")
    assert sidecar_path(path).exists()
    back = load_dxf(path)
    assert [q.name for q in back.panels] == ["front", "back"]
    for a, b in zip(p.panels, back.panels):
        assert [e.name for e in a.outline.edges] == [e.name for e in b.outline.edges]
        assert [e.kind for e in a.outline.edges] == [e.kind for e in b.outline.edges]
        assert _outline_distance(a.outline, b.outline) < 1e-4  # 0.1 mm
        for la, lb in zip(a.inner, b.inner):
            assert _outline_distance(la, lb) < 1e-4 and la.name == lb.name
        assert np.allclose(a.grainline, b.grainline, atol=1e-6)
        assert a.placement == b.placement
    assert back.seams == p.seams
    arc = back.panel("back").edge("bump")
    assert arc.large_arc and arc.radius == pytest.approx(0.12, abs=1e-6)


def test_file_is_r12_without_layout_blocks_and_metric(tmp_path):
    path = save_dxf(_pattern(), tmp_path / "t.dxf", sidecar=False)
    text = path.read_text()
    assert "*Model_Space" not in text and "$ACADVER" not in text
    doc = ezdxf.readfile(path)
    blocks = [b.name for b in doc.blocks if not b.name.startswith("*")]
    assert blocks == ["front", "back"]
    layers = {e.dxf.layer for e in doc.blocks["front"]}
    assert {"1", "2", "3", "4", "7", "11"} <= layers
    texts = [e.dxf.text for e in doc.modelspace() if e.dxftype() == "TEXT"]
    assert "Units: METRIC" in texts
    assert any(e.dxf.text == "Piece Name: front" for e in doc.blocks["front"]
               if e.dxftype() == "TEXT")


def test_without_side_file_convert_offers_the_seam_suggestion(tmp_path):
    """Without a side file the DXF has no seams: ``convert`` offers the seams that
    :mod:`patternfit.pattern.seam_suggest` finds from the notches kept on the panels, and
    names the command that sews them."""
    p = _pattern()
    path = save_dxf(p, tmp_path / "t.dxf", sidecar=False)
    back = load_dxf(path)
    assert back.seams == () and "suggested_seams" not in back.meta
    # front 'side' is edge 1, back 'side' is edge 4: equal length and notched alike
    assert [n.t for n in back.panel("front").notches if n.edge == "e1"] == \
        [pytest.approx(0.5, abs=0.01)]
    result = CliRunner().invoke(app, ["convert", str(path), str(tmp_path / "t.json"), "--json"])
    assert result.exit_code == 0, result.output
    pairs = {frozenset([(s["a"]["panel"], s["a"]["edge"]), (s["b"]["panel"], s["b"]["edge"])])
             for s in json.loads(result.output)["suggested_seams"]}
    assert frozenset([("front", "e1"), ("back", "e4")]) in pairs
    text = CliRunner().invoke(app, ["convert", str(path), str(tmp_path / "t2.json")]).output
    said = " ".join(text.split())
    assert "patternfit seams" in said and "--suggest --accept" in said


def _hand_made(path, *, units="ENGLISH", sew=False):
    """A piece drawn as loose LINEs (no turn points) in inches, optional sew line."""
    doc = ezdxf.new("R12")
    blk = doc.blocks.new("P1")
    sq = [(0, 0), (10, 0), (10, 20), (0, 20)]
    for a, b in zip(sq, sq[1:] + sq[:1]):
        blk.add_line(a, b, dxfattribs={"layer": "1"})
    if sew:
        inner = [(0.5, 0.5), (9.5, 0.5), (9.5, 19.5), (0.5, 19.5)]
        blk.add_polyline2d(inner, close=True, dxfattribs={"layer": "14"})
    blk.add_line((5, 5), (5, 15), dxfattribs={"layer": "7"})
    blk.add_text("Piece Name: sleeve", dxfattribs={"layer": "1", "insert": (2, 2)})
    doc.modelspace().add_blockref("P1", (0, 0))
    doc.modelspace().add_text(f"Units: {units}", dxfattribs={"layer": "1"})
    doc.saveas(path)
    return path


def test_foreign_file_units_corners_and_sew_line(tmp_path):
    p = load_dxf(_hand_made(tmp_path / "h.dxf"))
    (panel,) = p.panels
    assert panel.name == "sleeve" and len(panel.outline.edges) == 4
    assert panel.outline.length == pytest.approx(60 * 0.0254)
    assert panel.grainline == pytest.approx((0.0, 1.0))
    p = load_dxf(_hand_made(tmp_path / "m.dxf", units="METRIC"))
    assert p.panels[0].outline.length == pytest.approx(0.060)
    p = load_dxf(_hand_made(tmp_path / "s.dxf", sew=True))
    assert p.panels[0].outline.length == pytest.approx(56 * 0.0254)
    p = load_dxf(tmp_path / "s.dxf", prefer_sew=False, units="cm")
    assert p.panels[0].outline.length == pytest.approx(0.60)


def test_polyline_without_turn_points_is_refit_as_smooth_edges(tmp_path):
    doc = ezdxf.new("R12")
    blk = doc.blocks.new("round")
    theta = np.linspace(0, math.pi, 91)
    arc = np.column_stack([100 * np.cos(theta), 100 * np.sin(theta)])  # mm, half disc
    blk.add_polyline2d(arc.tolist(), close=True, dxfattribs={"layer": "1"})
    doc.modelspace().add_blockref("round", (0, 0))
    doc.saveas(tmp_path / "r.dxf")
    (panel,) = load_dxf(tmp_path / "r.dxf").panels
    kinds = sorted(e.kind for e in panel.outline.edges)
    assert kinds == ["arc", "line"]
    assert panel.outline.length == pytest.approx(0.1 * math.pi + 0.2, rel=1e-4)


def test_dxf_without_pieces_is_refused(tmp_path):
    doc = ezdxf.new("R12")
    doc.modelspace().add_line((0, 0), (1, 1))
    doc.saveas(tmp_path / "empty.dxf")
    with pytest.raises(PatternError, match="no pattern pieces") as info:
        load_dxf(tmp_path / "empty.dxf")
    assert info.value.file == str(tmp_path / "empty.dxf")
    (tmp_path / "junk.dxf").write_text("not a dxf at all")
    with pytest.raises(PatternError) as info:
        load_dxf(tmp_path / "junk.dxf")
    assert info.value.file == str(tmp_path / "junk.dxf")


def test_side_file_errors_and_edge_indices(tmp_path):
    path = save_dxf(_pattern(), tmp_path / "t.dxf")
    side = json.loads(sidecar_path(path).read_text())
    side["seams"][0]["a"]["edge"] = 1  # index into the outline: 'side'
    sidecar_path(path).write_text(json.dumps(side))
    assert load_dxf(path).seams[0].a.edge == "side"
    side["panels"]["front"]["edges"] = ["a", "b"]
    sidecar_path(path).write_text(json.dumps(side))
    with pytest.raises(PatternError, match="names 2 edges") as info:
        load_dxf(path)
    assert info.value.panel == "front"
    side = json.loads(json.dumps(side))
    side["panels"]["front"]["edges"] = ["hem", "side", "neck", "centre"]
    side["seams"][0]["b"]["panel"] = "cuff"
    sidecar_path(path).write_text(json.dumps(side))
    with pytest.raises(PatternError, match="names missing panel 'cuff'") as info:
        load_dxf(path)
    # the panel is what is missing, not the place of the fault
    assert info.value.panel is None and info.value.file == str(sidecar_path(path))


def test_builtin_patterns_round_trip(tmp_path):
    library = pytest.importorskip("patternfit.pattern.library")
    for name in library.GARMENTS:
        p = library.build(name, "M")
        back = load_dxf(save_dxf(p, tmp_path / f"{name}.dxf"))
        assert back.seams == p.seams
        for a, b in zip(p.panels, back.panels):
            assert [e.kind for e in a.outline.edges] == [e.kind for e in b.outline.edges]
            assert _outline_distance(a.outline, b.outline) < 1e-4


def test_seams_of_unequal_length_travel_as_warnings(tmp_path):
    p = _pattern()
    gathered = Seam("gather", SeamSide("front", "hem"), SeamSide("back", "top"))
    p = Pattern(p.name, p.panels, p.seams + (gathered,), p.meta)
    back = load_dxf(save_dxf(p, tmp_path / "g.dxf"))
    assert back.seams == p.seams
    assert any("gather" in w and "different length" in w for w in back.meta["warnings"])


def test_notches_point_into_the_fabric():
    from patternfit.pattern.dxf import notch_marks

    p = _pattern()
    dart = p.panel("front").inner[0]
    p = Pattern(p.name, p.panels, p.seams + (
        Seam("dart", SeamSide("front", "d0"), SeamSide("front", "d1")),), p.meta)
    from matplotlib.path import Path as MplPath
    for pname, _, at, inner in notch_marks(p, length=0.004):
        panel = p.panel(pname)
        tip = at + 0.5 * (inner - at)
        assert MplPath(panel.outline.polygon(64)).contains_point(tip)
        assert not MplPath(dart.polygon(8)).contains_point(tip)


def test_a_side_files_unit_is_read_or_refused(tmp_path):
    """A side file saying "units": "cm" had its placements read as metres, without a word;
    an unknown unit is refused naming the side file and the field."""
    p = _pattern()
    path = save_dxf(p, tmp_path / "u.dxf")
    side = tmp_path / "u.seams.json"
    data = json.loads(side.read_text())
    data["units"] = "cm"
    moved = data["panels"]["front"]["placement"]
    moved["translation"] = [100 * v for v in moved["translation"]]
    side.write_text(json.dumps(data))
    back = load_dxf(path)
    assert back.panel("front").placement.translation == pytest.approx(
        p.panel("front").placement.translation)
    data["units"] = "furlong"
    side.write_text(json.dumps(data))
    with pytest.raises(PatternError, match="side file 'units' 'furlong'") as info:
        load_dxf(path)
    assert "u.seams.json" in str(info.value)


@pytest.mark.parametrize("change, words", [
    (lambda d: d.update(version=9), "unsupported version 9"),
    (lambda d: d["panels"].update(ghost={}), "describes 'ghost', which the DXF does not hold"),
    (lambda d: d.update(seam=[]), "unknown key 'seam'.*did you mean 'seams'"),
    (lambda d: d["panels"]["front"].update(grain_line=[1, 0]),
     "unknown key 'grain_line'.*did you mean 'grainline'"),
    (lambda d: d["seams"][0].update(reversed=False), "unknown key 'reversed'")])
def test_a_side_file_the_reader_would_misread_is_refused(tmp_path, change, words):
    """A side file of another version, describing a piece the DXF lacks or with a misspelt
    key was read as if it said nothing (a seam's "reversed": false read as reverse true)."""
    path = save_dxf(_pattern(), tmp_path / "v.dxf")
    side = tmp_path / "v.seams.json"
    data = json.loads(side.read_text())
    change(data)
    side.write_text(json.dumps(data))
    with pytest.raises(PatternError, match=words) as info:
        load_dxf(path)
    assert "v.seams.json" in str(info.value)
