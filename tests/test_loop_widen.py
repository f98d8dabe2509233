"""Letting out a too-tight region where the corner moves across the grain cannot reach it:
a kimono coat stretched at a sleeve's root is widened at its overarm seam and shoulder
point, one stretched across the shoulders (off every side seam) at its shoulder points;
both sides alike, seams matched (flat panels stretched as a drape would: no drape)."""

import numpy as np
import pytest
from scenes import assert_matched_and_mirrored

from patternfit.loop.correct import apply_moves, finish_moves
from patternfit.loop.symmetry import mirrored_triangles
from patternfit.loop.widen import let_out_moves, opening_moves
from patternfit.mesh.triangulate import mesh_pattern
from patternfit.pattern.library import build
from patternfit.pattern.validate import check_pattern


@pytest.fixture(scope="module")
def coat():
    pattern = build("coat", "M")
    return pattern, mesh_pattern(pattern, triangles=1500)


def _stretch(mesh, panel, inside, factor, about):
    """Flat positions (n, 3) with the vertices of ``panel`` where ``inside(xy)`` stretched
    across (x) by ``factor`` about x = ``about`` [m], and the triangles all inside."""
    x = np.zeros((mesh.n_vertices, 3))
    x[:, :2] = mesh.vertices
    on = (mesh.vertex_panel == mesh.panel_names.index(panel)) & inside(mesh.vertices)
    x[on, 0] = about + factor * (x[on, 0] - about)
    return x, np.flatnonzero(on[mesh.triangles].all(axis=1))


def _let_out(pattern, mesh, x, region, tool=let_out_moves):
    tris = mirrored_triangles(pattern, mesh, region)
    new = apply_moves(pattern, finish_moves(pattern, mesh, tool(
        pattern, mesh, x, tris, target=0.0)))
    check_pattern(new)
    assert_matched_and_mirrored(new, ("front", "back"))
    return new


def _corner(pattern, panel, edge):
    return np.asarray(pattern.panel(panel).edge(edge).start)


def test_a_tight_sleeve_root_is_let_out_at_the_overarm_and_underarm(coat):
    pattern, mesh = coat
    # the front's left sleeve root (beyond the armpit, above its height) 25 % too wide
    armpit = _corner(pattern, "front", "underarm_l")
    x, region = _stretch(mesh, "front", lambda v: (v[:, 0] > armpit[0])
                         & (v[:, 1] > armpit[1] - 0.1), 1.25, armpit[0])
    new = _let_out(pattern, mesh, x, region)

    def moved(corner):
        return _corner(new, "front", corner) - _corner(pattern, "front", corner)

    # the overarm seam's two ends go out along its normal (up and out: the shoulder
    # raised and extended), the armpit down (the underarm deepened) ...
    for corner in ("shoulder_l", "overarm_l"):
        assert moved(corner)[0] > 0.007 and moved(corner)[1] > 0.007
    assert moved("underarm_l")[1] < -0.005
    # ... the body below the armpit stays (no let-out at the hem for a sleeve)
    for corner in ("side_l", "hem"):
        assert np.allclose(moved(corner), 0.0, atol=1e-3)
    # the right sleeve alike, and the back sewn to them
    assert moved("overarm_r")[0] < -0.007
    assert not np.allclose(new.panel("back").outline.polygon(),
                           pattern.panel("back").outline.polygon())


def test_tight_shoulders_are_let_out_at_the_shoulder_points(coat):
    pattern, mesh = coat
    # across the front's upper chest, between the shoulder points, off every side seam
    point = _corner(pattern, "front", "shoulder_l")
    x, region = _stretch(mesh, "front", lambda v: (np.abs(v[:, 0]) < 0.6 * point[0])
                         & (v[:, 1] > point[1] - 0.12), 1.2, 0.0)
    new = _let_out(pattern, mesh, x, region)
    moved = _corner(new, "front", "shoulder_l") - point
    assert moved[0] > 0.01  # the shoulder point goes out...
    assert np.allclose(_corner(new, "front", "neckline"), _corner(pattern, "front", "neckline"),
                       atol=2e-3)  # ... and the neck stays


def test_a_neck_opening_too_small_is_widened_at_the_neck_points(coat):
    pattern, mesh = coat
    # the front stretched 15 % across around its neckline, 12 cm each side, 15 cm down
    neck = _corner(pattern, "front", "neckline")  # the left neck point
    x, region = _stretch(mesh, "front", lambda v: (np.abs(v[:, 0]) < 0.12)
                         & (v[:, 1] > neck[1] - 0.15), 1.15, 0.0)
    assert not opening_moves(pattern, mesh, x, region, target=0.2)  # within the target
    new = _let_out(pattern, mesh, x, region, tool=opening_moves)

    def moved(panel, corner):
        return _corner(new, panel, corner) - _corner(pattern, panel, corner)

    left, right = moved("front", "neckline"), moved("front", "shoulder_r")
    # both neck points go out across the grain, alike: 15 % of the band's 24 cm less
    # the neck hole's share, split in two
    assert 0.005 < left[0] < 0.02 and right[0] == pytest.approx(-left[0], abs=1e-4)
    assert abs(left[1]) < 1e-3
    # the back's neck points follow, so the shoulder seams still match (checked above)
    assert abs(moved("back", "neckline")[0]) > 0.002
    # the shoulder points stay
    for corner in ("shoulder_l", "overarm_r"):
        assert np.allclose(moved("front", corner), 0.0, atol=1e-3)
