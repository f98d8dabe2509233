"""Seams of different length sewn with a stated ease (issue 20, item 1): the format's
``ease``, the rule, meshing, drape, saving, GarmentCode gathers, edits."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from scenes import rectangle_panel

from patternfit.constants import limits
from patternfit.mesh import mesh_pattern
from patternfit.pattern import Pattern, PatternError, Seam, SeamSide
from patternfit.pattern.garmentcode import garmentcode_from_dict, garmentcode_to_dict
from patternfit.pattern.io import load_pattern, pattern_from_dict, pattern_to_dict, save_pattern
from patternfit.pattern.validate import check_pattern, check_seams


def eased_tube(ease=0.2):
    """Panels A (0.4 x 0.72 m) and B (0.4 x 0.6 m): A's right edge, 20 % longer, sewn to
    B's left edge (seam ``side``) with ``ease``."""
    return Pattern("tube", (rectangle_panel("A", 0.4, 0.72), rectangle_panel("B", 0.4, 0.6)),
                   (Seam("side", SeamSide("A", "right"), SeamSide("B", "left"), ease=ease),))


def _side_vertices(mesh, seam=0):
    pairs = mesh.seam_pairs[mesh.seam_index == seam]
    return pairs[:, 0], pairs[:, 1]


def _length(x):
    return float(np.linalg.norm(np.diff(x, axis=0), axis=1).sum())


def test_eased_seam_meshes_with_equal_counts_spread_by_arc_length():
    p = eased_tube()
    check_pattern(p)
    m = mesh_pattern(p, triangles=600)
    a, b = _side_vertices(m)
    assert len(set(a.tolist())) == len(set(b.tolist())) == len(a) > 5
    for ids, length in ((a, 0.72), (b, 0.6)):
        step = np.linalg.norm(np.diff(m.vertices[ids], axis=0), axis=1)
        assert np.allclose(step, length / (len(ids) - 1), rtol=1e-9)
        assert abs(_length(m.vertices[ids]) - length) < 1e-9


def test_without_ease_or_beyond_it_or_the_limit_refused():
    with pytest.raises(PatternError, match="seam 'side' joins sides of different length") as e:
        check_pattern(eased_tube(0.0))
    assert e.value.panel == "A" and e.value.edge == "right"
    with pytest.raises(PatternError, match="seam 'side'.*different length"):
        mesh_pattern(eased_tube(0.0), triangles=300)
    with pytest.raises(PatternError, match="beyond the stated 0.1"):
        check_pattern(eased_tube(0.1))
    with pytest.raises(PatternError, match="seam 'side': ease 1.5 is beyond the limit"):
        check_pattern(eased_tube(limits.seam_ease + 0.5))
    for bad in (-0.1, float("nan")):
        with pytest.raises(PatternError, match="seam 'side': ease must be"):
            check_seams(eased_tube(bad))
    # the ease is at most: a smaller difference is fine
    check_pattern(eased_tube(0.5))
    # an imported pattern beyond its ease is kept with a warning
    assert "different length" in check_seams(eased_tube(0.1), unequal="warn")[0]


def test_json_round_trip_keeps_ease(tmp_path):
    p = eased_tube()
    doc = pattern_to_dict(p, units="cm")
    assert doc["seams"][0]["ease"] == 0.2
    back = load_pattern(save_pattern(p, tmp_path / "tube.json", units="cm"))
    assert back.seams == p.seams and back.seams[0].ease == 0.2
    # a seam without ease writes none and reads 0
    plain = pattern_to_dict(replace(p, panels=(rectangle_panel("A", 0.4, 0.6), p.panels[1]),
                                    seams=(replace(p.seams[0], ease=0.0),)))
    assert "ease" not in plain["seams"][0]
    for bad, text in (("0.2", "'ease' must be"), (2.0, "beyond the limit")):
        doc["seams"][0]["ease"] = bad
        with pytest.raises(PatternError, match=text):
            pattern_from_dict(json.loads(json.dumps(doc)))


def test_save_garment_accepts_eased_seams(tmp_path):
    from patternfit.mesh.store import load_garment, save_garment

    p = eased_tube()
    m = mesh_pattern(p, triangles=300)
    p2, m2, _ = load_garment(save_garment(tmp_path / "g", p, m))
    assert p2.seams[0].ease == 0.2 and np.array_equal(m2.seam_pairs, m.seam_pairs)


def _gc_gathered():
    """A GarmentCode skirt panel 52 cm wide gathered 30 % into a 40 cm waistband."""
    def rect(w, h, top_label, bottom_label, y):
        return {"translation": [-w / 2, y, 15], "rotation": [0, 0, 0],
                "vertices": [[0, 0], [w, 0], [w, h], [0, h]],
                "edges": [{"endpoints": [0, 1], "label": bottom_label},
                          {"endpoints": [1, 2]}, {"endpoints": [2, 3], "label": top_label},
                          {"endpoints": [3, 0]}]}
    return {"pattern": {"panels": {"skirt": rect(52, 40, "waist", "hem", 60),
                                   "band": rect(40, 5, "top", "bottom", 100)},
                        "stitches": [[{"panel": "skirt", "edge": 2},
                                      {"panel": "band", "edge": 0}]]},
            "properties": {"curvature_coords": "relative", "units_in_meter": 100}}


def test_garmentcode_gathered_waist_reads_with_ease_and_meshes():
    p = garmentcode_from_dict(_gc_gathered())
    assert p.seams[0].ease == pytest.approx(0.3, abs=1e-3)
    assert p.seams[0].ease >= 0.3  # rounded up: the file's lengths pass
    assert any("ease 0.3" in w for w in p.meta["warnings"])
    m = mesh_pattern(p, triangles=400)
    a, b = _side_vertices(m)
    assert len(set(a.tolist())) == len(set(b.tolist())) == len(a)
    assert abs(_length(m.vertices[a]) - 0.52) < 1e-9
    assert abs(_length(m.vertices[b]) - 0.40) < 1e-9
    # our export writes the stated ease, so it comes back as it was
    q = replace(p, seams=(replace(p.seams[0], ease=0.35),))
    assert garmentcode_from_dict(garmentcode_to_dict(q)).seams == q.seams
    # a ruffle beyond the limit is kept with a warning, and meshing refuses it
    doc = _gc_gathered()
    doc["pattern"]["panels"]["skirt"]["vertices"] = [[0, 0], [90, 0], [90, 40], [0, 40]]
    r = garmentcode_from_dict(doc)
    assert r.seams[0].ease == limits.seam_ease
    # the file states no ease: the refusal names the gather and the limit, not "the stated 1"
    assert any("a 2.25:1 gather, beyond the limit of 2:1" in w for w in r.meta["warnings"])
    assert not any("beyond the stated" in w for w in r.meta["warnings"])
    with pytest.raises(PatternError, match="stitch0"):
        mesh_pattern(r, triangles=300)


def test_edits_keep_the_stated_ease():
    from patternfit.edit.tools import grade, move_edge

    p = eased_tube()
    # grading the whole pattern keeps the ratio
    g = grade(p, None, 1.1, 1.1)
    assert g.seam_side_length(g.seams[0].a) / g.seam_side_length(g.seams[0].b) == \
        pytest.approx(1.2)
    # lengthening the longer side beyond the ease is refused, naming the seam
    with pytest.raises(PatternError, match="seam 'side'"):
        move_edge(p, "A", "top", (0.0, 0.1))
    # shortening it (less gather) is fine
    move_edge(p, "A", "top", (0.0, -0.05))


def _eased_skirt():
    """The built-in skirt with its front 20 % taller (graded about the waist) and every seam
    sewn with ease 0.2: the front's extra length is eased into the back's sides."""
    from patternfit.edit.tools import grade
    from patternfit.pattern.library import build

    p = build("skirt", "M")
    p = replace(p, seams=tuple(replace(s, ease=0.2) for s in p.seams))
    top = max(float(np.max(np.asarray(e.points)[:, 1])) for e in p.panel("front").outline.edges)
    return grade(p, "front", 1.0, 1.2, about=(0.0, top))


def test_eased_skirt_drapes_with_the_ease_sewn_in():
    from patternfit.body.builtin import load_body
    from patternfit.sim.drape import drape

    p = _eased_skirt()
    seam = next(i for i, s in enumerate(p.seams) if s.name == "side_r")
    la, lb = p.seam_side_length(p.seams[seam].a), p.seam_side_length(p.seams[seam].b)
    assert la / lb - 1 > 0.15
    m = mesh_pattern(p, triangles=1000)
    a, b = _side_vertices(m, seam)
    assert len(set(a.tolist())) == len(set(b.tolist())) == len(a)
    d = drape(p, m, load_body("female_thin"), "cotton")
    assert d.passed, d.reasons
    x = d.positions
    assert np.abs(x[m.seam_pairs[:, 0]] - x[m.seam_pairs[:, 1]]).max() < 5e-4
    sewn = _length(x[a])
    print(f"flat a {la * 100:.2f} cm, flat b {lb * 100:.2f} cm, 3D {sewn * 100:.2f} cm")
    assert min(la, lb) < sewn < max(la, lb)
