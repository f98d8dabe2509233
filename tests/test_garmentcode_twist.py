"""A GarmentCode file whose stitches sew the cloth into a twisted (one-sided) surface is read
with a warning naming the seams (GarmentCode's own ``standing_lapel`` is such a file)."""

import itertools
import json

import pytest

from patternfit.pattern.formats import load_any_pattern
from patternfit.pattern.library import build
from patternfit.pattern.orientation import twisted_cycles, twisted_seams

GARMENTS = ("skirt", "trousers", "dress", "coat", "shirt", "gathered_skirt")


def _band(tmp_path, tags, *, clockwise=()):
    """Three 20 x 10 cm panels sewn into a ring (each one's right edge to the next one's
    left edge) as GarmentCode writes them; ``tags[i]`` is the third entry of stitch i
    (``"right_wrong"`` or None); panels in ``clockwise`` are drawn the other way round."""
    panels = {}
    for i in range(3):
        v = [[0, 0], [20, 0], [20, 10], [0, 10]]
        if i in clockwise:
            v = v[::-1]
        panels[f"p{i}"] = {"vertices": v,
                           "edges": [{"endpoints": [k, (k + 1) % 4]} for k in range(4)],
                           "translation": [20.0 * i, 100.0, 10.0],
                           "rotation": [0.0, 0.0, 0.0]}
    # edge 1 is the right side and edge 3 the left one, drawn either way round
    stitches = [[{"panel": f"p{i}", "edge": 1}, {"panel": f"p{(i + 1) % 3}", "edge": 3}]
                + ([tag] if tag else []) for i, tag in enumerate(tags)]
    path = tmp_path / "band_specification.json"
    path.write_text(json.dumps({"pattern": {"panels": panels, "stitches": stitches},
                                "properties": {"units_in_meter": 100}}))
    return load_any_pattern(path)


def _warned(pattern) -> list:
    return [w for w in pattern.meta.get("warnings", []) if "twisted" in w]


def test_a_ring_sewn_right_side_to_right_side_is_not_twisted(tmp_path):
    p = _band(tmp_path, [None, None, None])
    assert twisted_seams(p) == [] and _warned(p) == []


@pytest.mark.parametrize("tags,twisted", [
    (["right_wrong", None, None], True),  # one panel turned over on one side only: Moebius
    (["right_wrong", "right_wrong", None], False),  # turned over, and back
    (["right_wrong"] * 3, True),
])
def test_an_odd_number_of_turns_round_the_ring_is_twisted(tmp_path, tags, twisted):
    p = _band(tmp_path, tags)
    assert bool(twisted_seams(p)) == twisted
    w = _warned(p)
    assert len(w) == int(twisted)
    if twisted:
        assert "right_wrong" in w[0] and any(n in w[0] for n in twisted_seams(p))


@pytest.mark.parametrize("turned", list(itertools.product([False, True], repeat=3)))
def test_every_tagging_of_the_ring_is_twisted_exactly_when_it_turns_an_odd_number_of_times(
        tmp_path, turned):
    p = _band(tmp_path, ["right_wrong" if t else None for t in turned])
    cycles = twisted_cycles(p)
    assert bool(cycles) == (sum(turned) % 2 == 1)
    assert all(sorted(c) == ["stitch0", "stitch1", "stitch2"] for c in cycles.values())


@pytest.mark.parametrize("tag_at", [0, 1, 2])
def test_the_warning_names_every_seam_of_the_twisted_cycle_and_corrects_none(tmp_path, tag_at):
    """Parity says a cycle is twisted, not which of its seams is wrong: re-sewing any one of
    them untwists the ring, so the reader names all three and keeps the file's stitches."""
    tags = [None] * 3
    tags[tag_at] = "right_wrong"
    p = _band(tmp_path, tags)
    cycles = twisted_cycles(p)
    assert len(cycles) == 1
    (closing, seams), = cycles.items()
    assert seams[0] == closing and sorted(seams) == ["stitch0", "stitch1", "stitch2"]
    assert all(n in _warned(p)[0] for n in seams)
    assert [s.reverse for s in p.seams] == [t is None for t in tags]
    for k in range(3):
        fixed = list(tags)
        fixed[k] = None if tags[k] else "right_wrong"
        assert twisted_cycles(_band(tmp_path, fixed)) == {}


@pytest.mark.parametrize("tags", [[None] * 3, ["right_wrong", None, None],
                                  ["right_wrong", "right_wrong", None]])
def test_drawing_a_panel_clockwise_changes_nothing(tmp_path, tags):
    """GarmentCode draws its back panels clockwise: both of the panel's seams then join its
    edges the other way round, and the ring is as twisted as before."""
    plain = bool(twisted_seams(_band(tmp_path, tags)))
    assert bool(twisted_seams(_band(tmp_path, tags, clockwise=(1,)))) == plain
    assert bool(twisted_seams(_band(tmp_path, tags, clockwise=(0, 2)))) == plain


@pytest.mark.parametrize("name", GARMENTS)
def test_the_built_in_garments_are_not_twisted(name):
    assert twisted_seams(build(name)) == []


def test_the_readers_warning_travels_into_the_report(tmp_path):
    # a drape's report.json carries what the reader warned of, so a failure has its cause
    from patternfit import api
    p = _band(tmp_path, ["right_wrong", None, None])
    report = api.place_and_evaluate(p, triangles=300).write(tmp_path / "out", pictures=False)
    assert report["pattern_warnings"] == p.meta["warnings"]
    assert "pattern_warnings" not in api.place_and_evaluate(
        _band(tmp_path, [None] * 3), triangles=300).write(tmp_path / "ok", pictures=False)


@pytest.mark.parametrize("name", ["skirt.dxf", "skirt.json"])
def test_a_dxf_side_file_or_our_json_sewn_twisted_is_said_too(tmp_path, name):
    """Only the GarmentCode reader said so: the built-in skirt with one side seam turned in
    its DXF side file (or its JSON) read without a word and draped with 457 crossed pairs."""
    from dataclasses import replace

    from patternfit.pattern.formats import save_any_pattern

    skirt = build("skirt", "M")
    assert not _warned(load_any_pattern(save_any_pattern(skirt, tmp_path / name)[0]))
    turned = replace(skirt, seams=(replace(skirt.seams[0], reverse=not skirt.seams[0].reverse),
                                   *skirt.seams[1:]))
    assert twisted_seams(turned)
    w = _warned(load_any_pattern(save_any_pattern(turned, tmp_path / name)[0]))
    assert len(w) == 1 and "'reverse'" in w[0] and skirt.seams[0].name in w[0]
    # a GarmentCode file so sewn, kept as our JSON, keeps its warning and gets no second
    gc = load_any_pattern(save_any_pattern(turned, tmp_path / "t_specification.json")[0])
    assert len(_warned(gc)) == 1
    again = _warned(load_any_pattern(save_any_pattern(gc, tmp_path / "t.json")[0]))
    assert again == _warned(gc)
