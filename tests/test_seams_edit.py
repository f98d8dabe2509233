"""Seam editing tools (issue 20 item 3): add, remove, state the ease; through a session."""

from dataclasses import replace

import pytest

from patternfit.constants import limits
from patternfit.edit import add_seam, grade, remove_seam, set_seam_ease
from patternfit.pattern import PatternError, SeamSide, check_pattern
from patternfit.pattern.library import build


def unsewn(garment="skirt"):
    p = build(garment, "M")
    return p, replace(p, seams=())


def test_add_seam_restores_a_removed_seam_with_measured_ease_zero():
    p, bare = unsewn()
    s = p.seams[0]
    out = add_seam(bare, s.a, {"panel": s.b.panel, "edge": s.b.edge}, name=s.name)
    assert out.seams == (s,)
    assert out.seams[0].ease == 0.0
    check_pattern(out)
    assert bare.seams == ()  # the input is never modified


def test_add_seam_default_name_and_dict_sides():
    _, bare = unsewn()
    out = add_seam(bare, {"panel": "front", "edge": "side_r", "start": 0, "end": 1},
                   {"panel": "back", "edge": "side_r"})
    assert out.seams[0].name == "front.side_r+back.side_r"
    assert out.seams[0].a == SeamSide("front", "side_r", 0.0, 1.0)


def test_add_seam_measures_ease_of_unequal_sides():
    _, bare = unsewn()
    tall = grade(bare, "front", 1.0, 1.2)
    out = add_seam(tall, SeamSide("front", "side_r"), SeamSide("back", "side_r"))
    la, lb = (out.seam_side_length(x) for x in (out.seams[0].a, out.seams[0].b))
    assert out.seams[0].ease == pytest.approx(la / lb - 1, abs=1e-4)
    assert out.seams[0].ease >= la / lb - 1
    check_pattern(out)


def test_add_seam_refuses_a_gather_beyond_the_limit_naming_both_lengths():
    _, bare = unsewn()
    with pytest.raises(PatternError) as err:
        add_seam(bare, SeamSide("front", "hem"), SeamSide("back", "hip_r"), name="x")
    text = str(err.value)
    assert "'x'" in text and "64.0" in text and "21.5" in text
    assert f"{limits.seam_ease:g}" in text


def test_add_seam_refuses_a_stated_ease_too_small_and_a_bad_ease():
    _, bare = unsewn()
    tall = grade(bare, "front", 1.0, 1.2)
    with pytest.raises(PatternError, match="different length"):
        add_seam(tall, SeamSide("front", "side_r"), SeamSide("back", "side_r"), ease=0.01)
    for bad in (-0.1, float("nan"), limits.seam_ease + 0.5, "0.1"):
        with pytest.raises(PatternError, match="ease"):
            add_seam(tall, SeamSide("front", "side_r"), SeamSide("back", "side_r"), ease=bad)


def test_add_seam_refuses_a_span_already_sewn_and_bad_sides():
    p, _ = unsewn()
    with pytest.raises(PatternError, match="already sewn by seam 'side_r'"):
        add_seam(p, SeamSide("front", "side_r", 0.5, 1.0), SeamSide("back", "hem"))
    with pytest.raises(PatternError, match="no edge|has no edge"):
        add_seam(p, SeamSide("front", "nope"), SeamSide("back", "hem"))
    with pytest.raises(PatternError, match="start"):
        add_seam(p, {"panel": "front", "edge": "hem", "start": 0.7, "end": 0.2},
                 SeamSide("back", "hem"))
    with pytest.raises(PatternError, match="already exists"):
        add_seam(p, SeamSide("front", "hem"), SeamSide("back", "hem"), name="side_r")
    with pytest.raises(PatternError, match="overlap"):
        add_seam(p, SeamSide("front", "hem", 0, 0.6), SeamSide("front", "hem", 0.4, 1))


def test_add_seam_on_free_parts_of_a_sewn_edge():
    _, bare = unsewn()
    half = add_seam(bare, SeamSide("front", "hem", 0.0, 0.5), SeamSide("back", "hem", 0.5, 1))
    both = add_seam(half, SeamSide("front", "hem", 0.5, 1.0), SeamSide("back", "hem", 0, 0.5))
    assert len(both.seams) == 2


def test_remove_and_set_ease():
    p, _ = unsewn()
    out = remove_seam(p, "hip_r")
    assert [s.name for s in out.seams] == [s.name for s in p.seams if s.name != "hip_r"]
    with pytest.raises(PatternError, match="no seam 'zz'.*side_r"):
        remove_seam(p, "zz")
    eased = set_seam_ease(p, "hip_r", 0.08)
    assert {s.name: s.ease for s in eased.seams}["hip_r"] == 0.08
    tall = grade(replace(p, seams=()), "front", 1.0, 1.2)
    tall = add_seam(tall, SeamSide("front", "side_r"), SeamSide("back", "side_r"), name="s")
    with pytest.raises(PatternError, match="seam 's' refused"):
        set_seam_ease(tall, "s", 0.0)


def test_session_records_and_undoes_seam_edits():
    from patternfit.loop.session import EDIT_OPS, DesignSession
    from patternfit.body.builtin import load_body

    assert {"add_seam", "remove_seam", "set_seam_ease"} <= set(EDIT_OPS)
    p = build("skirt", "M")
    session = DesignSession(p, load_body("female_average"), "cotton", triangles=600)
    session.apply("remove_seam", name="hip_r")
    assert "hip_r" not in session.mesh.seam_names
    session.apply("add_seam", a={"panel": "front", "edge": "hip_r"},
                  b={"panel": "back", "edge": "hip_r", "start": 0.0, "end": 1.0}, name="hip_r")
    assert "hip_r" in session.mesh.seam_names
    assert session.state.edit == {"op": "add_seam", "args": {
        "a": {"panel": "front", "edge": "hip_r"},
        "b": {"panel": "back", "edge": "hip_r", "start": 0.0, "end": 1.0}, "name": "hip_r"}}
    session.apply("set_seam_ease", name="hip_r", ease=0.05)
    assert {s.name: s.ease for s in session.pattern.seams}["hip_r"] == 0.05
    session.undo()
    session.undo()
    assert [s.name for s in session.pattern.seams] == [s.name for s in p.seams
                                                       if s.name != "hip_r"]
    assert "hip_r" not in session.mesh.seam_names


def test_mesh_update_refuses_changed_seams():
    from patternfit.edit import update_mesh
    from patternfit.mesh.triangulate import mesh_pattern

    p = build("skirt", "M")
    m = mesh_pattern(p, triangles=400)
    with pytest.raises(PatternError, match="changed the seams"):
        update_mesh(p, remove_seam(p, "hip_r"), m)
    # an ease changes no vertex pairing: the mesh follows
    out = update_mesh(p, set_seam_ease(p, "hip_r", 0.05), m)
    assert out.n_vertices == m.n_vertices
