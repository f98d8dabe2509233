"""Editing tools (pure Pattern -> Pattern) and their refusals."""

import numpy as np
import pytest

from patternfit.edit import (edit_curve, grade, insert_dart, lengthen, move_dart, move_edge,
                             move_point, resize_dart)
from patternfit.pattern import PatternError
from patternfit.pattern.validate import check_pattern

from scenes import two_panels


def corner(p, panel, edge):
    return p.panel(panel).edge(edge).start


def test_move_point_free_corner_is_pure():
    p = two_panels()
    q = move_point(p, "A", "left", (-0.02, 0.03))
    np.testing.assert_allclose(corner(q, "A", "left"), [-0.02, 0.63])
    np.testing.assert_allclose(q.panel("A").edge("top").end, [-0.02, 0.63])
    np.testing.assert_allclose(corner(p, "A", "left"), [0, 0.6])     # input untouched
    check_pattern(q)


def test_seamed_corner_refused_or_partner_matched():
    p = two_panels()
    with pytest.raises(PatternError, match="partner=True"):
        move_point(p, "A", "top", (0.0, 0.05))   # A's top-right corner: lengthens A.right
    q = move_point(p, "A", "top", (0.0, 0.05), partner=True)
    assert abs(q.seam_side_length(q.seams[0].a) - q.seam_side_length(q.seams[0].b)) < 1e-6
    # the top of A's right side meets the top of B's left side: that corner moved up
    np.testing.assert_allclose(corner(q, "B", "left"), [0, 0.65], atol=1e-6)
    np.testing.assert_allclose(corner(q, "B", "bottom"), [0, 0], atol=1e-12)


def test_move_edge_neighbours_follow():
    p = two_panels()
    q = move_edge(p, "A", "left", (-0.03, 0.0))
    np.testing.assert_allclose(q.panel("A").edge("top").end, [-0.03, 0.6])
    np.testing.assert_allclose(q.panel("A").edge("bottom").start, [-0.03, 0.0])
    assert q.panel("A").area() == pytest.approx(p.panel("A").area() + 0.03 * 0.6)


def test_edit_curve_turns_line_into_curve_and_refuses_crossing():
    p = two_panels()
    q = edit_curve(p, "A", "top", (0.0, 0.05))
    e = q.panel("A").edge("top")
    assert e.kind == "quadratic"
    np.testing.assert_allclose(e.points[1], [0.2, 0.65])
    assert q.panel("A").area() > p.panel("A").area()
    with pytest.raises(PatternError, match="self-intersecting"):
        edit_curve(p, "A", "top", (0.0, -2.0))
    with pytest.raises(ValueError, match="offset"):
        edit_curve(p, "A", "top", (0.0, np.nan))


def test_lengthen_between_two_points_with_partner():
    p = two_panels()
    q = lengthen(p, "A", (0.2, 0.0), (0.2, 0.6), 0.05, partner=True)
    assert q.panel("A").edge("right").length == pytest.approx(0.65)
    assert q.seam_side_length(q.seams[0].b) == pytest.approx(0.65, abs=1e-6)
    s = lengthen(p, "A", (0.0, 0.3), (0.4, 0.3), -0.1)          # narrower: no seam changes
    assert s.panel("A").edge("bottom").length == pytest.approx(0.3)


def test_grade_whole_pattern_and_arc_refusal():
    p = two_panels()
    q = grade(p, None, 1.1, 1.1)
    assert q.area() == pytest.approx(p.area() * 1.21)
    with pytest.raises(PatternError, match="partner"):
        grade(p, "A", 1.0, 1.2)
    with pytest.raises(PatternError, match="grading refused"):
        grade(two_panels(arc=True), "A", 1.0, 1.2, partner=True)
    with pytest.raises(ValueError, match="sx"):
        grade(p, "A", -1.0, 1.0)


@pytest.mark.parametrize("shape, n_seams", [("diamond", 2), ("triangle", 1)])
def test_dart_insert_move_resize(shape, n_seams):
    p = two_panels()
    q = insert_dart(p, "A", "d1", (0.2, 0.3), length=0.2, width=0.04, shape=shape)
    assert len(q.panel("A").inner) == 1 and len(q.seams) == 1 + n_seams
    for s in q.seams[1:]:   # the legs are sewn and equally long
        assert q.seam_side_length(s.a) == pytest.approx(q.seam_side_length(s.b))
    area = q.panel("A").area()
    r = move_dart(q, "A", "d1", (0.05, 0.1))
    assert r.panel("A").area() == pytest.approx(area)
    np.testing.assert_allclose(r.panel("A").inner[0].edges[0].start, [0.25, 0.5])
    w = resize_dart(q, "A", "d1", width=0.08, length=0.25)
    assert w.panel("A").area() < area
    with pytest.raises(PatternError, match="inside"):
        move_dart(q, "A", "d1", (0.3, 0.0))
    with pytest.raises(PatternError, match="exists"):
        insert_dart(q, "A", "d1", (0.2, 0.3), length=0.1, width=0.02)
    with pytest.raises(PatternError, match="no dart"):
        move_dart(q, "A", "zz", (0.0, 0.0))


def test_tools_refuse_results_that_are_no_garment():
    from patternfit.constants import limits

    p = two_panels()
    # the strongest grading allowed either way is accepted, and nothing beyond it
    assert grade(p, None, 1 / limits.edit_scale, 1 / limits.edit_scale).area() == \
        pytest.approx(p.area() / limits.edit_scale ** 2)
    assert grade(p, "A", limits.edit_scale, 1.0, partner=True).panel("A").area() == \
        pytest.approx(p.panel("A").area() * limits.edit_scale)
    for sx in (1e300, 0.0, -1.0, 1 / limits.edit_scale / 1.01, np.inf):
        with pytest.raises(PatternError, match="sx: expected a number in") as info:
            grade(p, "A", sx, 1.0)
        assert info.value.panel == "A"
    # shortened past its own length: the panel turns inside out, with or without partner
    for partner in (False, True):
        with pytest.raises(PatternError, match=r"amount=-10 m.*inside out") as info:
            lengthen(p, "A", (0.2, 0.0), (0.2, 0.6), -10.0, partner=partner)
        assert info.value.panel == "A"
    # shortened to a sliver: collapsed
    with pytest.raises(PatternError, match="collapses"):
        lengthen(p, "A", (0.2, 0.0), (0.2, 0.6), -0.598, partner=True)
    # offsets that leave the pattern's extent, or could not be computed with
    for op in (lambda d: move_edge(p, "A", "top", d, partner=True),
               lambda d: move_point(p, "A", "left", d),
               lambda d: edit_curve(p, "A", "top", d)):
        with pytest.raises(PatternError, match="offset: expected a 2-vector") as info:
            op((0.0, 1e30))
        assert info.value.panel == "A"
    with pytest.raises(PatternError, match=r"offset=\(0, 25\) m.*beyond the limit"):
        move_edge(p, "B", "top", (0.0, 25.0))
    with pytest.raises(PatternError, match="no such panel") as info:
        move_edge(p, "Z", "top", (0.0, 0.1))
    assert info.value.panel == "Z"
    with pytest.raises(PatternError, match="control: a quadratic edge") as info:
        edit_curve(p, "A", "top", (0.0, 0.1), control=2)


def test_dart_tools_check_their_arguments():
    p = two_panels()
    for kw, name in ((dict(length=1e30, width=0.02), "length"),
                     (dict(length=0.1, width=0.0), "width"),
                     (dict(length=0.1, width=0.02, axis=(0.0, 0.0)), "axis"),
                     (dict(length=0.1, width=0.02, shape="star"), "shape")):
        with pytest.raises(PatternError, match=name) as info:
            insert_dart(p, "A", "d", (0.2, 0.3), **kw)
        assert info.value.panel == "A"
    q = insert_dart(p, "A", "d", (0.2, 0.3), length=0.2, width=0.04)
    with pytest.raises(PatternError, match="offset"):
        move_dart(q, "A", "d", (1e30, 0.0))
    with pytest.raises(PatternError, match="width"):
        resize_dart(q, "A", "d", width=-0.01)
