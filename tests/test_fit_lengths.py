"""Where a sleeve or trouser leg ends along its limb (the measure), and the hem edit that
gives a risen sleeve its length back: the kimono coat's cuffs move out along the sleeve by
the rise, both sides and both panels alike, seams matched (flat panels laid out as a
drape would hold them: no drape)."""

from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scenes import assert_matched_and_mirrored

from patternfit.fit.body_regions import REGIONS
from patternfit.fit.lengths import MIN_VERTICES, SLICE, limb_ends, risen
from patternfit.loop.correct import apply_moves, finish_moves
from patternfit.loop.lengthen import hem_edges, hem_moves
from patternfit.mesh.triangulate import mesh_pattern
from patternfit.pattern.library import build


def _arm(a, b):
    return SimpleNamespace(landmarks={"arm_axis_left": np.array([a, b], dtype=float)})


def _tube(a, d, length, end, radius, arc=2 * np.pi, start=0.0):
    """A tube of cloth (vertices (n, 3), triangles (m, 3)) around the axis from ``a`` along
    ``d`` (unit), from ``start`` to ``end`` of the arm's ``length``, over ``arc`` [rad]."""
    t = np.linspace(start, end, 30)
    closed = arc >= 2 * np.pi
    phi = np.linspace(0.0, arc, 12, endpoint=not closed)
    n1 = np.array([0.0, 0.0, 1.0])
    n2 = np.cross(d, n1)
    pts = (a + (length * t)[:, None, None] * d
           + radius * (np.cos(phi)[None, :, None] * n1 + np.sin(phi)[None, :, None] * n2))
    cols = 12 if closed else 11
    i, j = np.meshgrid(np.arange(29), np.arange(cols), indexing="ij")
    v00, v01 = i * 12 + j, i * 12 + (j + 1) % 12
    v10, v11 = v00 + 12, v01 + 12
    tri = np.concatenate([np.stack([v00, v10, v11], -1).reshape(-1, 3),
                          np.stack([v00, v11, v01], -1).reshape(-1, 3)])
    return pts.reshape(-1, 3), tri


def _ends(x, tri, a, b):
    region = np.full(len(x), REGIONS.index("forearm_left"))
    return limb_ends(x, tri, region, _arm(a, b))


@settings(max_examples=30, deadline=None)
@given(st.floats(0.3, 0.8), st.floats(0.2, 1.3), st.floats(-1.0, 1.0),
       st.floats(0.02, 0.08))
def test_a_sleeve_ends_where_its_cloth_stops_going_around_the_arm(length, end, tilt,
                                                                  radius):
    # an arm from the shoulder point, tilted down, and a tube of cloth around it
    a = np.array([0.2, 1.4, 0.0])
    d = np.array([np.cos(tilt), -abs(np.sin(tilt)), 0.0])
    x, tri = _tube(a, d, length, end, radius)
    ends = _ends(x, tri, a, a + length * d)
    assert set(ends) == {"sleeve_left"}
    assert ends["sleeve_left"] == pytest.approx(length * (1.0 - end), abs=SLICE)


def test_a_flap_hanging_from_one_side_of_the_arm_is_no_sleeve():
    a, d, length = np.array([0.2, 1.4, 0.0]), np.array([1.0, 0.0, 0.0]), 0.6
    x1, t1 = _tube(a, d, length, 0.5, 0.05)
    x2, t2 = _tube(a, d, length, 1.1, 0.05, arc=np.pi, start=0.5)
    x, tri = np.concatenate([x1, x2]), np.concatenate([t1, t2 + len(x1)])
    assert _ends(x, tri, a, a + length * d)["sleeve_left"] == pytest.approx(0.3, abs=SLICE)


def test_a_limb_with_a_few_vertices_on_it_is_not_covered():
    x = np.zeros((MIN_VERTICES - 1, 3))
    region = np.full(len(x), REGIONS.index("bicep_left"))
    assert limb_ends(x, np.array([[0, 1, 2]]), region, _arm([0, 0, 0], [1, 0, 0])) == {}


def test_only_a_rise_beyond_the_tolerance_counts():
    before = {"sleeve_left": 0.01, "sleeve_right": 0.012}
    after = {"sleeve_left": 0.05, "sleeve_right": 0.03}
    assert risen(before, after, 0.025) == pytest.approx({"sleeve_left": 0.04})
    assert risen(before, {"sleeve_left": -0.02}, 0.025) == {}  # longer is no rise


@pytest.fixture(scope="module")
def coat():
    pattern = build("coat", "M")
    return pattern, mesh_pattern(pattern, triangles=1500)


def _laid_out(mesh):
    """The coat's two panels as a drape holds them seen from the front: the back mirrored,
    so that both panels' left sleeves lie at +x; each vertex's region by its side."""
    x = np.zeros((mesh.n_vertices, 3))
    x[:, :2] = mesh.vertices
    back = mesh.vertex_panel == mesh.panel_names.index("back")
    x[back, 0] *= -1.0
    x[:, 2] = np.where(back, -0.1, 0.1)
    region = np.full(mesh.n_vertices, REGIONS.index("bust"))
    region[x[:, 0] > 0.3] = REGIONS.index("forearm_left")
    region[x[:, 0] < -0.3] = REGIONS.index("forearm_right")
    body = SimpleNamespace(landmarks={
        "arm_axis_left": np.array([[0.25, 0.65, 0.0], [0.6, 0.2, 0.0]]),
        "arm_axis_right": np.array([[-0.25, 0.65, 0.0], [-0.6, 0.2, 0.0]])})
    return x, region, body


def _cuff(pattern, panel, side):
    """The names of the edges starting at the cuff's two corners on ``panel``."""
    names = [e.name for e in pattern.panel(panel).outline.edges]
    k = names.index(f"cuff_{side}")
    return names[k], names[(k + 1) % len(names)]


def test_a_risen_sleeve_is_lengthened_at_its_cuff_by_the_rise(coat):
    pattern, mesh = coat
    x, region, body = _laid_out(mesh)
    rise = 0.05
    offsets = hem_moves(pattern, mesh, x, region, body,
                        {"sleeve_left": rise, "sleeve_right": rise})
    # both panels' cuffs, both ends of each: the corners cuff_* and the next edge start
    assert set(offsets) == {(p, e) for p in ("front", "back")
                            for e in (*_cuff(pattern, p, "l"), *_cuff(pattern, p, "r"))}
    new = apply_moves(pattern, finish_moves(pattern, mesh, offsets))
    assert_matched_and_mirrored(new, ("front", "back"))
    for p in ("front", "back"):
        for s in ("l", "r"):
            old, now = (np.array([pat.panel(p).edge(e).start
                                  for e in _cuff(pattern, p, s)]) for pat in (pattern, new))
            normal = np.array([old[1, 1] - old[0, 1], old[0, 0] - old[1, 0]])
            normal /= np.linalg.norm(normal)
            if normal @ (old.mean(axis=0) - pattern.panel(p).outline.polygon().mean(
                    axis=0)) < 0:
                normal = -normal
            # the cuff moved out along its normal by the rise, and kept its width
            assert (now - old) @ normal == pytest.approx([rise, rise], abs=2e-3)
            assert np.linalg.norm(now[1] - now[0]) == pytest.approx(
                np.linalg.norm(old[1] - old[0]), abs=1e-3)
        # the body's corners did not move
        for e in ("hem", "side_l", "neckline"):
            assert np.allclose(new.panel(p).edge(e).start, pattern.panel(p).edge(e).start)


def test_a_hem_across_both_legs_is_no_limbs_hem(coat):
    # the coat's hem hangs over both thighs, half its points on each: its height is
    # reported (as each leg's end) but it is not lengthened as a trouser leg's would be
    pattern, mesh = coat
    x, region, body = _laid_out(mesh)
    low = x[:, 1] < 0.1
    region[low & (x[:, 0] >= 0)] = REGIONS.index("thigh_left")
    region[low & (x[:, 0] < 0)] = REGIONS.index("thigh_right")
    body.landmarks["leg_axis_left"] = np.array([[0.1, 0.1, 0.0], [0.1, -0.7, 0.0]])
    assert hem_edges(pattern, mesh, x, region, body, "leg_left") == {}
    assert hem_edges(pattern, mesh, x, region, body, "sleeve_left") == {
        "front": "cuff_l", "back": "cuff_l"}
