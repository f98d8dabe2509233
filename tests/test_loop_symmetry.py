"""Left/right symmetry of the correction's edits: a move asked on one side is shared with
its mirror image (the mean of both sides), left/right panels are mirrors but front and back
are not, and a region's triangles gain their mirror images, so that a drape at rest a
little askew is edited alike on both sides."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patternfit.loop.correct import apply_moves, finish_moves
from patternfit.loop.symmetry import mirrored_triangles, mirrors, symmetric_moves
from patternfit.loop.widen import let_out_moves
from patternfit.mesh.triangulate import mesh_pattern
from patternfit.pattern.library import build
from patternfit.pattern.validate import check_pattern


@pytest.fixture(scope="module")
def dress():
    pattern = build("dress", "M")
    return pattern, mesh_pattern(pattern, triangles=800)


def _is_mirror_symmetric(poly) -> bool:
    axis = 0.5 * (poly[:, 0].min() + poly[:, 0].max())
    mirrored = poly * [-1.0, 1.0] + [2 * axis, 0.0]
    return np.linalg.norm(mirrored[:, None] - poly[None], axis=2).min(axis=1).max() < 1e-4


def test_left_and_right_are_mirrors_front_and_back_are_not(dress):
    pattern, mesh = dress
    assert {(m.a, m.b) for m in mirrors(pattern, mesh)} == {("front", "front"),
                                                            ("back", "back")}
    trousers = build("trousers", "M")
    pairs = {(m.a, m.b) for m in mirrors(trousers, mesh_pattern(trousers, triangles=600))}
    assert pairs == {("front_r", "front_l"), ("back_r", "back_l")}


@given(dx=st.floats(-0.03, 0.03), dy=st.floats(-0.03, 0.03))
@settings(max_examples=25, deadline=None)
def test_a_move_on_one_side_becomes_the_mean_of_both_sides(dress, dx, dy):
    pattern, mesh = dress
    out = symmetric_moves(pattern, mesh, {("front", "hem"): np.array([dx, dy])})
    # hem starts at the front's lower left corner, skirt_side_l at its lower right
    assert out[("front", "hem")] == pytest.approx([dx / 2, dy / 2], abs=1e-12)
    assert out[("front", "skirt_side_l")] == pytest.approx([-dx / 2, dy / 2], abs=1e-12)
    assert not any(panel == "back" for panel, _ in out)


def test_mirrored_legs_get_mirrored_moves():
    trousers = build("trousers", "M")
    mesh = mesh_pattern(trousers, triangles=600)
    out = symmetric_moves(trousers, mesh, {("front_r", "waist"): np.array([0.02, 0.01]),
                                           ("front_l", "crotch"): np.array([0.0, 0.01])})
    # front_r's waist corner and front_l's crotch corner are mirror images
    assert out[("front_r", "waist")] == pytest.approx([0.01, 0.01])
    assert out[("front_l", "crotch")] == pytest.approx([-0.01, 0.01])


def test_a_regions_triangles_gain_their_mirror_images(dress):
    pattern, mesh = dress
    front = mesh.panel_triangles(mesh.panel_names.index("front"))
    c = mesh.vertices[mesh.triangles[front]].mean(axis=1)
    axis = float(np.median(pattern.panel("front").outline.polygon()[:, 0]))
    right = front[(c[:, 0] > axis + 0.05) & (c[:, 1] > 0.3) & (c[:, 1] < 0.5)]
    both = mirrored_triangles(pattern, mesh, right)
    cb = mesh.vertices[mesh.triangles[both]].mean(axis=1)
    assert set(right) <= set(both)
    assert np.all(mesh.triangle_panel[both] == mesh.triangle_panel[right[0]])
    left = cb[cb[:, 0] < axis]
    assert len(left) == pytest.approx(len(right), rel=0.25)
    assert left[:, 0].min() == pytest.approx(2 * axis - c[right, 0].max(), abs=0.03)


def test_a_stretch_on_one_side_is_let_out_on_both(dress):
    pattern, mesh = dress
    # the front's skirt stretched 15% across on its right half only (a drape at rest askew)
    x = np.zeros((mesh.n_vertices, 3))
    x[:, :2] = mesh.vertices
    front = mesh.vertex_panel == mesh.panel_names.index("front")
    axis = float(np.median(pattern.panel("front").outline.polygon()[:, 0]))
    side = front & (mesh.vertices[:, 0] > axis) & (mesh.vertices[:, 1] < 0.4)
    x[side, 0] = axis + 1.15 * (x[side, 0] - axis)
    c = mesh.vertices[mesh.triangles].mean(axis=1)
    region = np.flatnonzero((mesh.triangle_panel == mesh.panel_names.index("front"))
                            & (c[:, 0] > axis) & (c[:, 1] < 0.4))
    tris = mirrored_triangles(pattern, mesh, region)
    offsets = let_out_moves(pattern, mesh, x, tris, target=0.0)
    new = apply_moves(pattern, finish_moves(pattern, mesh, offsets))
    check_pattern(new)
    for name in ("front", "back"):
        assert _is_mirror_symmetric(new.panel(name).outline.polygon())
    grown = np.ptp(new.panel("front").outline.polygon()[:, 0]) - \
        np.ptp(pattern.panel("front").outline.polygon()[:, 0])
    assert grown > 0.01  # let out, on both sides
