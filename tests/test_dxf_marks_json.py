"""The marks a DXF brings (notches; internal lines, drill holes, cut line) in the JSON format."""

import json
from dataclasses import replace

import numpy as np
import pytest

from patternfit.pattern import InnerLine, Notch, PatternError, pattern_from_dict, pattern_to_dict
from patternfit.pattern.library import build


def _notched():
    p = build("skirt", "M")
    panel = p.panels[0]
    side = panel.outline.edges[1].name
    return p.with_panel(replace(panel, notches=(Notch(side, 0.5), Notch(side, 0.0, "v")))), side


def test_notches_round_trip_through_json():
    p, _ = _notched()
    back = pattern_from_dict(json.loads(json.dumps(pattern_to_dict(p, units="cm"))))
    assert back.panels[0].notches == p.panels[0].notches
    assert back.panels[1].notches == ()


@pytest.mark.parametrize("change, words", [
    ({"edge": "nope"}, "does not have"),
    ({"t": 1.5}, "outside [0, 1]"),
    ({"t": -0.01}, "outside [0, 1]"),
    ({"t": "half"}, "must be"),
])
def test_bad_notches_are_refused_naming_the_panel(change, words):
    p, _ = _notched()
    d = pattern_to_dict(p)
    d["panels"][0]["notches"][0].update(change)
    with pytest.raises(PatternError, match=words.replace("[", r"\[").replace("]", r"\]")) as info:
        pattern_from_dict(d)
    assert info.value.panel == p.panels[0].name


def test_lines_drill_holes_and_cut_line_round_trip_in_the_file_units():
    p = build("skirt", "M")
    panel = p.panels[0]
    box = panel.outline.polygon(8)
    lo, hi = box.min(axis=0) - 0.01, box.max(axis=0) + 0.01
    marked = replace(panel, lines=(InnerLine("dart", [(0.0, 0.1), (0.02, 0.3), (0.04, 0.1)]),),
                     drill_holes=((0.02, 0.28),),
                     cut_line=((lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1])))
    p = p.with_panel(marked)
    d = json.loads(json.dumps(pattern_to_dict(p, units="cm")))
    assert np.allclose(d["panels"][0]["drill_holes"], [[2.0, 28.0]])
    back = pattern_from_dict(d).panels[0]
    assert back.lines[0].name == "dart"
    for a, b in ((back.lines[0].points, marked.lines[0].points),
                 (back.drill_holes, marked.drill_holes), (back.cut_line, marked.cut_line)):
        assert np.allclose(a, b, rtol=0, atol=1e-12) and len(a) == len(b)
    assert "lines" not in pattern_to_dict(build("skirt", "M"))["panels"][0]


@pytest.mark.parametrize("key, value, words", [
    ("lines", [{"name": "l", "points": [[0, 0]]}], "at least 2 points"),
    ("cut_line", [[0, 0], [1, 0]], "at least 3 points"),
    ("drill_holes", [[0, "x"]], "must be a number"),
])
def test_bad_marks_are_refused_naming_the_panel(key, value, words):
    d = pattern_to_dict(build("skirt", "M"))
    d["panels"][1][key] = value
    with pytest.raises(PatternError, match=words) as info:
        pattern_from_dict(d)
    assert info.value.panel == d["panels"][1]["name"]


def test_a_notch_on_an_edge_the_panel_lost_is_refused_before_writing(tmp_path):
    from patternfit.pattern import save_pattern

    p = build("skirt", "M")
    lost = p.with_panel(replace(p.panels[0], notches=(Notch("gone", 0.5),)))
    with pytest.raises(PatternError, match="'gone'") as info:
        save_pattern(lost, tmp_path / "p.json")
    assert info.value.panel == p.panels[0].name and not (tmp_path / "p.json").exists()
    from patternfit.pattern.dxf import save_dxf

    with pytest.raises(PatternError, match="'gone'"):
        save_dxf(lost, tmp_path / "p.dxf")
    assert not (tmp_path / "p.dxf").exists()
