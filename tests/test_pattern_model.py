import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patternfit.pattern import Edge, Loop, Panel, Pattern, PatternError, Seam, SeamSide, \
    load_pattern, pattern_to_dict, save_pattern
from patternfit.pattern.library import GARMENTS, build
from patternfit.pattern.sizes import SIZE_NAMES


def test_edge_lengths_and_points():
    line = Edge.line("l", (0, 0), (3, 4))
    assert line.length == pytest.approx(5.0)
    arc = Edge.arc("a", (1, 0), (0, 1), 1.0)
    assert arc.length == pytest.approx(math.pi / 2)
    assert arc.point_at([0.5])[0] == pytest.approx([math.sqrt(0.5)] * 2)
    big = Edge.arc("b", (1, 0), (0, 1), 1.0, large_arc=True)
    assert big.length == pytest.approx(3 * math.pi / 2)
    cubic = Edge.cubic("c", (0, 0), (0, 1), (1, 1), (1, 0))
    pts = cubic.point_at(np.linspace(0, 1, 11))
    steps = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    assert steps == pytest.approx(np.full(10, steps.mean()), rel=0.01)  # even in arc length
    assert cubic.reversed().point_at([0.25])[0] == pytest.approx(cubic.point_at([0.75])[0])


def test_arc_mirror_keeps_shape():
    arc = Edge.arc("a", (1, 0), (0, 1), 1.0)
    m = arc.transformed(np.diag([-1.0, 1.0]))
    assert m.point_at([0.5])[0] == pytest.approx([-math.sqrt(0.5), math.sqrt(0.5)])
    with pytest.raises(ValueError, match="similarity"):
        arc.transformed(np.diag([2.0, 1.0]))


def test_pattern_is_immutable_and_edits_return_new(two_rectangles):
    p = two_rectangles
    with pytest.raises(AttributeError):
        p.name = "x"
    panel = p.panel("A")
    new = p.with_panel(panel.with_edge(Edge.line("bottom", (0, 0), (0.5, 0))))
    assert new is not p and new.panel("B") is p.panel("B")


@pytest.mark.parametrize("units", ["m", "cm", "mm", "in"])
def test_round_trip(tmp_path, units):
    for name in GARMENTS:
        p = build(name, "L")
        path = save_pattern(p, tmp_path / f"{name}.json", units=units)
        q = load_pattern(path)
        assert json.loads(path.read_text())["units"] == units
        if units == "m":
            assert q == p
        else:
            for a, b in zip(p.panels, q.panels):
                assert a.name == b.name
                for ea, eb in zip(a.outline.edges, b.outline.edges):
                    assert ea.name == eb.name and ea.kind == eb.kind
                    assert np.allclose(ea.points, eb.points, atol=1e-12)
            assert q.seams == p.seams


def _write(tmp_path, doc, name="bad.json"):
    path = tmp_path / name
    path.write_text(json.dumps(doc))
    return path


def _doc(tmp_path):
    return pattern_to_dict(build("skirt", "M"), units="cm")


def test_error_open_outline(tmp_path):
    doc = _doc(tmp_path)
    doc["panels"][0]["outline"]["edges"][1]["points"][0][0] += 1.0  # 1 cm gap
    with pytest.raises(PatternError) as exc:
        load_pattern(_write(tmp_path, doc))
    msg = str(exc.value)
    assert "bad.json" in msg and "panel 'front'" in msg and "open outline" in msg
    assert exc.value.edge == doc["panels"][0]["outline"]["edges"][0]["name"]


@pytest.mark.parametrize("where", ["panel", "edge", "seam"])
def test_a_name_with_a_control_character_is_refused(tmp_path, where):
    """An escape sequence in a name acted on the terminal, and the mesh file joins edge
    names with \\x1f."""
    doc = _doc(tmp_path)
    bad = "side\x1b[2J"
    if where == "panel":
        old, doc["panels"][0]["name"] = doc["panels"][0]["name"], bad
        for side in (s[k] for s in doc["seams"] for k in ("a", "b")):
            side["panel"] = bad if side["panel"] == old else side["panel"]
    elif where == "edge":
        doc["panels"][0]["outline"]["edges"][0]["name"] = bad
    else:
        doc["seams"][0]["name"] = bad
    with pytest.raises(PatternError, match=r"name .* holds a control character \('\\x1b'"):
        load_pattern(_write(tmp_path, doc))


@pytest.mark.parametrize("anchor", ["bust", 3, None, ["waist"]])
def test_an_anchor_other_than_the_neck_or_the_waist_is_refused(tmp_path, anchor):
    """A strapless top given meta.anchor "bust" was read as hung from the waist without a
    word, draped round the belly and passed."""
    doc = _doc(tmp_path)
    doc["meta"] = {"anchor": anchor}
    with pytest.raises(PatternError, match=r"meta 'anchor'.*expected 'waist' or 'neck'") as e:
        load_pattern(_write(tmp_path, doc))
    assert str(tmp_path) in str(e.value)
    doc["meta"] = {"anchor": "neck"}
    assert load_pattern(_write(tmp_path, doc)).anchor == "neck"


def test_error_self_intersection(tmp_path):
    doc = {"format": "patternfit-pattern", "version": 1, "units": "m", "panels": [
        {"name": "bow", "outline": {"edges": [
            {"name": "a", "type": "line", "points": [[0, 0], [1, 1]]},
            {"name": "b", "type": "line", "points": [[1, 1], [1, 0]]},
            {"name": "c", "type": "line", "points": [[1, 0], [0, 1]]},
            {"name": "d", "type": "line", "points": [[0, 1], [0, 0]]}]}}]}
    with pytest.raises(PatternError, match=r"panel 'bow'.*self-intersecting"):
        load_pattern(_write(tmp_path, doc))


def test_error_missing_edge_and_panel(tmp_path):
    doc = _doc(tmp_path)
    doc["seams"][0]["b"]["edge"] = "nope"
    with pytest.raises(PatternError, match=r"bad.json: panel 'back', edge 'nope'.*missing edge"):
        load_pattern(_write(tmp_path, doc))
    doc = _doc(tmp_path)
    doc["seams"][0]["a"]["panel"] = "sleeve"
    with pytest.raises(PatternError, match=r"bad.json: seam '.*' names missing panel 'sleeve'$"):
        load_pattern(_write(tmp_path, doc))


def test_error_seam_length_mismatch(tmp_path):
    doc = _doc(tmp_path)
    doc["seams"][0]["b"]["range"] = [0.0, 0.9]
    with pytest.raises(PatternError, match="different length") as exc:
        load_pattern(_write(tmp_path, doc))
    assert "tolerance" in str(exc.value)


def test_error_nan_and_bad_json(tmp_path):
    doc = _doc(tmp_path)
    text = json.dumps(doc).replace("[", "[NaN, ", 1)
    bad = tmp_path / "nan.json"
    doc["panels"][1]["outline"]["edges"][2]["points"][1][1] = float("nan")
    _write(tmp_path, doc, "nan.json")
    # NaN is no JSON number: refused while parsing, at its line and column
    with pytest.raises(PatternError, match=r"nan.json: not valid JSON \(line \d+, column \d+: "
                                           r"NaN"):
        load_pattern(bad)
    (tmp_path / "broken.json").write_text(text[:50])
    with pytest.raises(PatternError, match=r"broken.json: not valid JSON \(line 1"):
        load_pattern(tmp_path / "broken.json")


def test_error_units_and_format(tmp_path):
    doc = _doc(tmp_path)
    doc["units"] = "furlong"
    with pytest.raises(PatternError, match="unknown units"):
        load_pattern(_write(tmp_path, doc))
    with pytest.raises(PatternError, match="not a patternfit pattern"):
        load_pattern(_write(tmp_path, {"panels": []}))


def test_save_is_atomic_and_refuses_invalid(tmp_path, two_rectangles):
    path = save_pattern(two_rectangles, tmp_path / "p.json")
    before = path.read_text()
    bad = Pattern("bad", two_rectangles.panels,
                  (Seam("s", SeamSide("A", "right"), SeamSide("B", "bottom")),))
    with pytest.raises(PatternError):
        save_pattern(bad, path)
    assert path.read_text() == before
    assert [p.name for p in tmp_path.iterdir()] == ["p.json"]  # no temporary left behind


def test_inner_loop_must_be_inside():
    outer = Loop("outline", [Edge.line("a", (0, 0), (1, 0)), Edge.line("b", (1, 0), (1, 1)),
                             Edge.line("c", (1, 1), (0, 1)), Edge.line("d", (0, 1), (0, 0))])
    hole = Loop("dart", [Edge.line("h1", (0.8, 0.5), (1.3, 0.4)),
                         Edge.line("h2", (1.3, 0.4), (1.3, 0.6)),
                         Edge.line("h3", (1.3, 0.6), (0.8, 0.5))])
    from patternfit.pattern import check_pattern
    with pytest.raises(PatternError, match="not inside"):
        check_pattern(Pattern("p", (Panel("x", outer, (hole,)),)))


@pytest.mark.parametrize("name", list(GARMENTS))
def test_builtin_garments_sewable_in_all_sizes(name):
    areas = []
    for size in SIZE_NAMES:
        p = build(name, size)  # validated: closed, no self-intersection, seams match
        assert p.meta["size"] == size
        for seam in p.seams:
            la, lb = p.seam_side_length(seam.a), p.seam_side_length(seam.b)
            # equal sides, or the longer within the seam's stated ease (a cap, a gather)
            assert max(la, lb) - min(la, lb) * (1 + seam.ease) < 1e-3, seam.name
        areas.append(p.area())
        # every panel edge is either sewn or a free edge (hem, waist, neckline, cuff...)
        for panel in p.panels:
            assert panel.outline.signed_area() != 0
    assert areas == sorted(areas)  # bigger sizes take more fabric


def test_builtin_panel_counts():
    assert [len(build(n).panels) for n in ("coat", "skirt", "trousers", "dress")] == [2, 2, 4, 2]


@settings(max_examples=30, deadline=None)
@given(garment=st.sampled_from(sorted(GARMENTS)), units=st.sampled_from(["m", "cm", "mm", "in"]),
       shift=st.floats(1e-4, 0.05))
def test_a_pattern_read_back_is_the_same_cut_and_an_edited_one_is_not(tmp_path_factory,
                                                                      garment, units, shift):
    from dataclasses import replace

    from patternfit.pattern.formats import save_any_pattern
    from patternfit.api import read_pattern

    p = build(garment, "M")
    path = tmp_path_factory.mktemp("cut") / "p.json"
    save_any_pattern(p, path, units=units)
    assert read_pattern(path).same_cut(p)
    first = p.panels[0]
    moved = first.outline.edges[0].transformed(np.eye(2), np.array([shift, 0.0]))
    edited = replace(p, panels=(replace(first, outline=replace(
        first.outline, edges=(moved, *first.outline.edges[1:]))), *p.panels[1:]))
    assert not edited.same_cut(p) and not p.same_cut(replace(p, name="other"))
