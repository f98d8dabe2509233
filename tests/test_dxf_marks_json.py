"""The marks a DXF brings (notches; internal lines, drill holes, cut line) in the JSON format."""

import json
from dataclasses import replace

import pytest

from patternfit.pattern import Notch, PatternError, pattern_from_dict, pattern_to_dict
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
