"""GarmentCode JSON import/export, from small files written by the tests."""

import copy
import json
import math

import numpy as np
import pytest

from patternfit.pattern import Edge, Loop, Panel, Pattern, PatternError, Placement, Seam, SeamSide
from patternfit.pattern import check_pattern
from patternfit.pattern.garmentcode import (euler_xyz_matrix, garmentcode_from_dict,
                                            garmentcode_to_dict, load_garmentcode,
                                            panel_points_3d, save_garmentcode)
from scenes import gathered_past_the_limit


def _square(curv=None, label=None):
    """A 40 x 60 unit panel; its top edge (#2, from (40, 60) to (0, 60)) may be curved."""
    top = {"endpoints": [2, 3]}
    if curv is not None:
        top["curvature"] = curv
    if label:
        top["label"] = label
    return {"translation": [0, 100, 20], "rotation": [0, 0, 0],
            "vertices": [[0, 0], [40, 0], [40, 60], [0, 60]],
            "edges": [{"endpoints": [0, 1], "label": "hem"}, {"endpoints": [1, 2]}, top,
                      {"endpoints": [3, 0]}]}


def _doc(panels, stitches=(), **props):
    return {"pattern": {"panels": panels, "stitches": list(stitches)},
            "parameters": {"p": {"v": 1}}, "parameter_order": ["p"],
            "properties": {"curvature_coords": "relative", "units_in_meter": 100, **props}}


def _top(pattern, panel="front"):
    return pattern.panel(panel).outline.edges[2]


def test_units_and_placement():
    for units, metres in [(100, 0.40), (1000, 0.040), (300, 40 / 300), (10, 4.0)]:
        p = garmentcode_from_dict(_doc({"front": _square()}, units_in_meter=units))
        assert p.panel("front").outline.edges[0].length == pytest.approx(metres)
        assert p.panel("front").placement.translation == pytest.approx(
            (0, 100 / units, 20 / units))
    p = garmentcode_from_dict(_doc({"front": _square()}, units_in_meter=100))
    assert p.panel("front").placement.side == "front"
    # centimetre numbers declared as metres: a 40 m panel is beyond any garment
    with pytest.raises(PatternError, match="beyond"):
        garmentcode_from_dict(_doc({"front": _square()}, units_in_meter=1))
    # a file without units is in centimetres, as GarmentCode assumes
    doc = _doc({"front": _square()})
    del doc["properties"]["units_in_meter"]
    assert garmentcode_from_dict(doc).panel("front").outline.edges[0].length == \
        pytest.approx(0.40)


def test_edge_labels_become_names():
    p = garmentcode_from_dict(_doc({"front": _square(label="neck")}))
    assert [e.name for e in p.panel("front").outline.edges] == ["hem", "e1", "neck", "e3"]
    sq = _square(label="hem")  # duplicate labels get the index
    p = garmentcode_from_dict(_doc({"front": sq}))
    assert [e.name for e in p.panel("front").outline.edges] == ["hem_0", "e1", "hem_2", "e3"]


def test_relative_quadratic_positive_n_is_left_of_edge():
    # the top edge runs from (40, 60) to (0, 60) (direction -x): its left is -y (inwards)
    p = garmentcode_from_dict(_doc({"front": _square({"type": "quadratic",
                                                      "params": [[0.25, 0.1]]})}))
    e = _top(p)
    assert e.kind == "quadratic"
    assert np.allclose(e.points[1], [0.40 - 0.25 * 0.40, 0.60 - 0.1 * 0.40])


def test_old_bare_quadratic_and_flat_params():
    a = garmentcode_from_dict(_doc({"front": _square([0.5, -0.2])}))
    b = garmentcode_from_dict(_doc({"front": _square({"type": "quadratic",
                                                      "params": [[0.5, -0.2]]})}))
    assert a.panel("front") == b.panel("front")
    assert np.allclose(_top(a).points[1], [0.20, 0.60 + 0.2 * 0.40])


def test_cubic_relative_and_absolute():
    rel = garmentcode_from_dict(_doc({"front": _square(
        {"type": "cubic", "params": [[0.3, 0.1], [0.7, -0.1]]})}))
    e = _top(rel)
    assert e.kind == "cubic"
    assert np.allclose(e.points[1:3], [[0.28, 0.56], [0.12, 0.64]])
    absolute = garmentcode_from_dict(_doc({"front": _square(
        {"type": "cubic", "params": [[28, 56], [12, 64]]})}, curvature_coords="absolute"))
    assert np.allclose(_top(absolute).points, e.points)


def test_circle_flags_follow_svg_in_y_up_frame():
    # GarmentCode writes sweep = 1 when the arc's middle lies right of the edge direction
    p = garmentcode_from_dict(_doc({"front": _square({"type": "circle",
                                                      "params": [25, 0, 1]})}))
    e = _top(p)
    mid = e.point_at([0.5])[0]
    assert e.kind == "arc" and e.radius == pytest.approx(0.25)
    assert mid[1] > 0.60  # right of a -x edge is +y: the arc bulges outwards
    h = 0.25 - math.sqrt(0.25**2 - 0.20**2)
    assert mid[1] == pytest.approx(0.60 + h)


def test_circle_large_arc():
    sq = _square({"type": "circle", "params": [25, 1, 1]})
    p = garmentcode_from_dict(_doc({"front": sq}))
    e = _top(p)
    assert e.large_arc
    assert e.length == pytest.approx(0.25 * (2 * math.pi - 2 * math.asin(0.8)))
    assert e.point_at([0.5])[0][1] == pytest.approx(0.60 + 0.25 + math.sqrt(0.25**2 - 0.04))


def test_stitches_reverse_and_right_wrong_round_trip():
    doc = _doc({"front": _square(), "back": {**_square(), "translation": [0, 100, -20]}},
               [[{"panel": "front", "edge": 1}, {"panel": "back", "edge": 3}],
                [{"panel": "front", "edge": 3}, {"panel": "back", "edge": 1}, "right_wrong"]])
    p = garmentcode_from_dict(doc)
    assert p.panel("back").placement.side == "back"
    s0, s1 = p.seams
    assert s0.reverse and not s1.reverse
    assert (s0.a, s0.b) == (SeamSide("front", "e1"), SeamSide("back", "e3"))
    check_pattern(p)
    out = garmentcode_to_dict(p)
    assert out["pattern"]["stitches"] == doc["pattern"]["stitches"]
    assert out["parameters"] == doc["parameters"]
    again = garmentcode_from_dict(out)
    assert again.panels == p.panels and again.seams == p.seams


def test_round_trip_every_curve_form(tmp_path):
    panels = {"q": _square({"type": "quadratic", "params": [[0.4, 0.2]]}),
              "c": _square({"type": "cubic", "params": [[0.3, 0.2], [0.6, -0.15]]}),
              "a": _square({"type": "circle", "params": [30, 0, 0]})}
    p = garmentcode_from_dict(_doc(panels))
    for units in (100, 1000, 39.37):
        path = save_garmentcode(p, tmp_path / "x_specification.json", units_in_meter=units)
        back = load_garmentcode(path)
        assert back.name == "x"
        for a, b in zip(p.panels, back.panels):
            for ea, eb in zip(a.outline.edges, b.outline.edges):
                assert ea.kind == eb.kind and ea.name == eb.name
                assert np.allclose(ea.points, eb.points, atol=1e-12)
                assert ea.length == pytest.approx(eb.length, rel=1e-9)
            assert np.allclose(a.placement.translation, b.placement.translation)


def _our_pattern():
    a = Panel("a", Loop("outline", (
        Edge.line("bottom", (0, 0), (0.4, 0)), Edge.line("right", (0.4, 0), (0.4, 0.6)),
        Edge.quadratic("top", (0.4, 0.6), (0.2, 0.7), (0, 0.6)),
        Edge.line("left", (0, 0.6), (0, 0)))),
        placement=Placement("torso", "front", (0.0, 1.2, 0.15), (0.0, 10.0, 0.0)))
    b = Panel("b", Loop("outline", (
        Edge.line("bottom", (0, 0), (0.4, 0)), Edge.line("right", (0.4, 0), (0.4, 0.3)),
        Edge.line("step", (0.4, 0.3), (0.4, 0.6)),
        Edge.arc("top", (0.4, 0.6), (0, 0.6), 0.3, sweep=True),
        Edge.line("left", (0, 0.6), (0, 0)))))
    # a seam over the upper half of a's right edge: the export must split that edge
    seams = (Seam("half", SeamSide("a", "right", 0.5, 1.0), SeamSide("b", "step")),
             Seam("sides", SeamSide("a", "left"), SeamSide("b", "left", 0.0, 1.0),
                  reverse=False))
    return Pattern("ours", (a, b), seams)


def test_our_pattern_round_trip_splits_partial_seams():
    p = _our_pattern()
    check_pattern(p)
    doc = garmentcode_to_dict(p)
    a_edges = doc["pattern"]["panels"]["a"]["edges"]
    assert len(a_edges) == 5  # right edge split in two
    assert doc["pattern"]["stitches"][1][2] == "right_wrong"
    back = garmentcode_from_dict(json.loads(json.dumps(doc)))
    check_pattern(back)
    assert back.panel("a").outline.length == pytest.approx(p.panel("a").outline.length)
    assert back.panel("b").outline.length == pytest.approx(p.panel("b").outline.length)
    pa = p.panel("a").outline.polygon(32)
    pb = back.panel("a").outline.polygon(32)
    # every point of the original outline lies on the re-imported one
    dist = np.min(np.linalg.norm(pa[:, None] - back.panel("a").outline.polygon(256)[None],
                                 axis=2), axis=1)
    assert dist.max() < 2e-4 and len(pb) > 0
    half = back.seams[0]
    assert back.seam_side_length(half.a) == pytest.approx(0.3)
    assert back.panel("a").placement.rotation == (0.0, 10.0, 0.0)
    assert back.panel("a").placement.translation == pytest.approx((0.0, 1.2, 0.15))


def test_split_cubic_and_arc_keep_the_curve():
    from patternfit.pattern.garmentcode import _split
    for e in (Edge.cubic("c", (0, 0), (0.1, 0.3), (0.3, -0.2), (0.4, 0)),
              Edge.arc("a", (0, 0), (0.4, 0), 0.25, large_arc=True, sweep=False)):
        part = _split(e, 0.25, 0.75)
        assert part.length == pytest.approx(0.5 * e.length, rel=1e-3)
        assert np.allclose(part.point_at([0.5])[0], e.point_at([0.5])[0], atol=1e-4)


def test_euler_convention_matches_maya_xyz():
    r = euler_xyz_matrix([90, 0, 0])
    assert np.allclose(r @ [0, 1, 0], [0, 0, 1])
    r = euler_xyz_matrix([30, 40, 50])
    rx = euler_xyz_matrix([30, 0, 0])
    ry = euler_xyz_matrix([0, 40, 0])
    rz = euler_xyz_matrix([0, 0, 50])
    assert np.allclose(r, rz @ ry @ rx)
    pts = panel_points_3d(Placement(translation=(0, 1, 0), rotation=(0, 180, 0)), [[0.1, 0.2]])
    assert np.allclose(pts, [[-0.1, 1.2, 0.0]])


@pytest.mark.parametrize("mutate, panel, edge, text", [
    (lambda d: d["pattern"]["stitches"].append(
        [{"panel": "front", "edge": 0}, {"panel": "sleeve", "edge": 0}]),
     None, None, "names missing panel 'sleeve'"),
    (lambda d: d["pattern"]["stitches"].append(
        [{"panel": "front", "edge": 0}, {"panel": "front", "edge": 7}]),
     "front", "7", "out of range"),
    (lambda d: d["pattern"]["panels"]["front"]["edges"][2].update(
        curvature={"type": "spline", "params": []}), "front", "e2", "unknown curvature type"),
    (lambda d: d["pattern"]["panels"]["front"]["edges"][1].update(endpoints=[1, 9]),
     "front", "e1", "out of range"),
    (lambda d: d["properties"].update(units_in_meter=0), None, None, "bad units"),
    (lambda d: d["properties"].update(units_in_meter="cm"), None, None, "bad units"),
    # absurd units and sizes, refused before any arithmetic overflows on them
    (lambda d: d["properties"].update(units_in_meter=1e300), None, None, "bad units"),
    (lambda d: d["properties"].update(units_in_meter=1e-300), None, None, "bad units"),
    (lambda d: d["pattern"]["panels"]["front"]["vertices"].__setitem__(0, [1e300, 0]),
     "front", None, "vertex #0 [1e+300, 0] lies"),
    (lambda d: d["pattern"]["panels"]["front"].update(translation=[1e300, 0, 0]),
     "front", None, "translation must lie within"),
])
@pytest.mark.filterwarnings("error")
def test_malformed_files_name_file_panel_edge(tmp_path, mutate, panel, edge, text):
    doc = _doc({"front": _square()})
    mutate(doc)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(PatternError) as info:
        load_garmentcode(path)
    err = info.value
    assert text in str(err) and err.file == str(path)
    assert err.panel == panel and err.edge == edge


def test_open_outline_and_mismatched_seams():
    doc = _doc({"front": _square()})
    doc["pattern"]["panels"]["front"]["edges"][3]["endpoints"] = [3, 1]
    with pytest.raises(PatternError, match="open outline") as info:
        garmentcode_from_dict(doc)
    assert info.value.panel == "front"
    # gathers: different lengths are kept, with a warning
    doc = _doc({"front": _square(), "back": copy.deepcopy(_square())},
               [[{"panel": "front", "edge": 0}, {"panel": "back", "edge": 1}]])
    p = garmentcode_from_dict(doc)
    assert len(p.seams) == 1 and "different length" in p.meta["warnings"][0]


def test_a_gather_beyond_two_to_one_is_refused_naming_the_file(tmp_path):
    """Read, a 2.5:1 gather is kept with a warning; draping it was refused by the mesher,
    naming the panel and edge but not the file."""
    from patternfit import api

    tall = copy.deepcopy(_square())
    tall["vertices"] = [[0, 0], [40, 0], [40, 100], [0, 100]]
    doc = _doc({"front": _square(), "back": tall},
               [[{"panel": "front", "edge": 0}, {"panel": "back", "edge": 1}]])
    path = tmp_path / "gathered_specification.json"
    path.write_text(json.dumps(doc))
    for run in (lambda: api.drape_and_evaluate(path, triangles=300),
                lambda: api.design_session(path, triangles=300)):
        with pytest.raises(PatternError, match="2.5:1 gather") as info:
            run()
        assert info.value.file == str(path)


def test_inner_loops_cannot_be_exported():
    p = _our_pattern()
    hole = Loop("dart", (Edge.line("d0", (0.1, 0.1), (0.2, 0.1)),
                         Edge.line("d1", (0.2, 0.1), (0.15, 0.2)),
                         Edge.line("d2", (0.15, 0.2), (0.1, 0.1))))
    p = p.with_panel(Panel("a", p.panel("a").outline, (hole,)))
    with pytest.raises(PatternError, match="inner loops") as info:
        garmentcode_to_dict(p)
    assert info.value.panel == "a"


def test_builtin_patterns_round_trip_unchanged():
    library = pytest.importorskip("patternfit.pattern.library")
    for name in library.GARMENTS:
        p = library.build(name, "M")
        back = garmentcode_from_dict(json.loads(json.dumps(garmentcode_to_dict(p))))
        assert back.seams == p.seams
        for a, b in zip(p.panels, back.panels):
            assert (a.placement, a.grainline) == (b.placement, b.grainline)
            for ea, eb in zip(a.outline.edges, b.outline.edges, strict=True):
                assert (ea.name, ea.kind) == (eb.name, eb.kind)
                assert np.allclose(ea.points, eb.points, atol=1e-12)


def test_a_file_in_millimetres_without_its_unit_is_said(tmp_path):
    """Without ``units_in_meter`` a file is read in centimetres: one drawn in millimetres
    came in ten times too large, without a word."""
    big = _square()
    big["vertices"] = [[x * 10, y * 10] for x, y in big["vertices"]]
    doc = _doc({"front": big})
    del doc["properties"]["units_in_meter"]
    pattern = garmentcode_from_dict(doc)
    said = " ".join(pattern.meta.get("warnings", []))
    assert "panel 'front' is 6 m across, read in centimetres" in said
    assert "\"units_in_meter\": 1000" in said
    assert not garmentcode_from_dict(_doc({"front": _square()})).meta.get("warnings")


def test_a_gather_past_the_limit_is_warned_of_once_as_such():
    """It was said twice: "sewn in as ease 1" (capped, as if sewn) and then "beyond the
    limit of 2:1", which meshing refuses."""
    spec = gathered_past_the_limit()
    said = [w for w in garmentcode_from_dict(spec).meta["warnings"] if "stitch0" in w]
    assert len(said) == 1 and "2.5:1 gather, beyond the limit of 2:1" in said[0], said


def test_a_misspelt_tag_is_said_and_our_own_keys_damaged_are_refused():
    """A stitch tagged 'wrong_right' was read as no tag without a word (sewn right side to
    right side), and a damaged 'patternfit_seam_ease' or 'patternfit_seam_names' (our
    export's) was dropped, every ease measured afresh."""
    doc = _doc({"front": _square(), "back": {**_square(), "translation": [0, 100, -20]}},
               [[{"panel": "front", "edge": 1}, {"panel": "back", "edge": 3}],
                [{"panel": "front", "edge": 3}, {"panel": "back", "edge": 1}, "wrong_right"]])
    said = garmentcode_from_dict(doc).meta["warnings"]
    assert any("'wrong_right' (stitch #1)" in w and "right_wrong" in w for w in said)
    for key, value in (("patternfit_seam_ease", [-3, 0]), ("patternfit_seam_names", "x"),
                       ("patternfit_seam_names", ["a", "a"])):
        with pytest.raises(PatternError, match=f"'{key}': expected one"):
            garmentcode_from_dict({**doc, key: value})
    good = garmentcode_from_dict({**doc, "patternfit_seam_ease": [0.1, 0.0],
                                  "patternfit_seam_names": ["side", "back"]})
    assert [(s.name, s.ease) for s in good.seams] == [("side", 0.1), ("back", 0.0)]
