"""Property tests of the generalized barycentric coordinates (METHOD.md section 4)."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from matplotlib.path import Path

from patternfit.coords import max_entropy_coordinates, mean_value_coordinates
from patternfit.coords.mvc import mvc_oriented
from patternfit.coords.polygon import oriented

SETTINGS = settings(max_examples=20, deadline=None)
PRIORS_ALL = ["uniform", "gaussian", "edge", "bisector", "bisector_literal"]


def star(n, inner, seed=0, jitter=0.0):
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 2 * np.pi, 2 * n, endpoint=False) + jitter * rng.uniform(-1, 1, 2 * n) / n
    r = np.where(np.arange(2 * n) % 2 == 0, 1.0, inner)
    return np.stack([r * np.cos(t), r * np.sin(t)], axis=1)


def convex(seed, n=9):
    t = np.sort(np.random.default_rng(seed).uniform(0, 2 * np.pi, n))
    t = np.unique(np.round(t, 3))
    return np.stack([np.cos(t), 0.6 * np.sin(t)], axis=1)


L_SHAPE = np.array([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]], float)
# a bodice-like outline: shoulder slope, armhole, side seam, hem (metres)
GARMENT = np.array([[0, 0], [0.25, 0], [0.26, 0.35], [0.22, 0.42], [0.2, 0.5], [0.21, 0.55],
                    [0.12, 0.6], [0.07, 0.58], [0.0, 0.55]])


def inside(poly, n, seed, holes=()):
    rng = np.random.default_rng(seed)
    lo, hi = poly.min(0), poly.max(0)
    p = rng.uniform(lo, hi, (6 * n, 2))
    keep = Path(poly).contains_points(p)
    for h in holes:
        keep &= ~Path(h).contains_points(p)
    return p[keep][:n]


polygons = st.one_of(
    st.builds(convex, st.integers(0, 10_000)),
    st.builds(star, st.integers(3, 9), st.floats(0.3, 0.8), st.integers(0, 100),
              st.floats(0, 0.5)),
    st.just(L_SHAPE), st.just(GARMENT),
)


@SETTINGS
@given(polygons, st.integers(0, 1000), st.booleans())
def test_mvc_partition_linear_precision_lagrange(poly, seed, flip):
    poly = poly[::-1] if flip else poly
    pts = inside(poly, 40, seed)
    w = mean_value_coordinates([poly], pts)
    assert w.shape == (len(pts), len(poly))
    np.testing.assert_allclose(w.sum(axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(w @ poly, pts, atol=1e-12)
    np.testing.assert_allclose(mean_value_coordinates([poly], poly), np.eye(len(poly)),
                               atol=1e-12)


@SETTINGS
@given(polygons, st.sampled_from(["edge", "bisector", "bisector_literal"]),
       st.integers(0, 1000))
def test_mec_partition_precision_positive(poly, prior, seed):
    pts = inside(poly, 30, seed)
    w, info = max_entropy_coordinates(poly, pts, prior=prior, return_info=True)
    np.testing.assert_allclose(w.sum(axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(w @ poly, pts, atol=1e-10)
    assert (w >= 0).all()
    assert info.converged.all() and info.max_iterations <= 100


@SETTINGS
@given(st.builds(convex, st.integers(0, 10_000)), st.sampled_from(PRIORS_ALL),
       st.integers(0, 1000))
def test_mec_all_priors_on_convex(poly, prior, seed):
    pts = inside(poly, 30, seed)
    w = max_entropy_coordinates(poly, pts, prior=prior)
    np.testing.assert_allclose(w @ poly, pts, atol=1e-10)
    assert (w >= 0).all()


@SETTINGS
@given(st.builds(convex, st.integers(0, 10_000)), st.integers(0, 1000))
def test_mvc_nonnegative_in_convex(poly, seed):
    assert (mean_value_coordinates([poly], inside(poly, 40, seed)) >= 0).all()


@pytest.mark.parametrize("poly", [L_SHAPE, GARMENT, star(5, 0.4)])
@pytest.mark.parametrize("method", ["mvc", "edge", "bisector"])
def test_lagrange_and_linear_along_edges(poly, method):
    def coords(p):
        if method == "mvc":
            return mean_value_coordinates([poly], p)
        return max_entropy_coordinates(poly, p, prior=method)

    np.testing.assert_allclose(coords(poly), np.eye(len(poly)), atol=1e-12)
    n = len(poly)
    t = np.array([0.1, 0.37, 0.5, 0.9])
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        expect = np.zeros((len(t), n))
        expect[:, i], expect[:, (i + 1) % n] = 1 - t, t
        on = a + t[:, None] * (b - a)
        np.testing.assert_allclose(coords(on), expect, atol=1e-12)
        # just inside the edge the coordinates are continuous with the edge values
        normal = np.array([-(b - a)[1], (b - a)[0]]) / np.linalg.norm(b - a)
        sign = 1.0 if Path(poly).contains_point(on[1] + 1e-4 * normal) else -1.0
        near = coords(on + sign * 1e-5 * normal)
        assert np.abs(near - expect).max() < 2e-3


def test_bisector_product_form_has_boundary_properties_literal_does_not():
    """METHOD.md: eq. 15d read literally misses edge linearity; the product form keeps it."""
    poly = star(5, 0.4)
    n = len(poly)
    errs = {}
    for prior in ("bisector", "bisector_literal"):
        worst = 0.0
        for i in range(n):
            a, b = poly[i], poly[(i + 1) % n]
            mid = 0.5 * (a + b)
            normal = np.array([-(b - a)[1], (b - a)[0]]) / np.linalg.norm(b - a)
            w = max_entropy_coordinates(poly, mid + 1e-5 * normal, prior=prior)[0]
            expect = np.zeros(n)
            expect[i] = expect[(i + 1) % n] = 0.5
            worst = max(worst, np.abs(w - expect).max())
        errs[prior] = worst
    assert errs["bisector"] < 1e-3
    assert errs["bisector_literal"] > 0.1


def test_holes_nested_loops():
    outer = np.array([[0, 0], [4, 0], [4, 3], [0, 3]], float)
    hole = np.array([[1, 1], [1.5, 2], [2, 1]], float)   # clockwise already
    hole2 = np.array([[2.8, 1], [3.4, 1], [3.4, 2], [2.8, 2]], float)  # counter-clockwise
    loops = [outer, hole, hole2]
    pts = inside(outer, 60, 3, holes=[hole, hole2])
    w = mean_value_coordinates(loops, pts)
    nodes = np.concatenate(loops)
    assert w.shape == (len(pts), len(nodes))
    np.testing.assert_allclose(w.sum(axis=1), 1, atol=1e-12)
    np.testing.assert_allclose(w @ nodes, pts, atol=1e-12)
    np.testing.assert_allclose(mean_value_coordinates(loops, nodes), np.eye(len(nodes)),
                               atol=1e-12)
    # orientation of each loop as given by the caller does not change the values
    w2 = mean_value_coordinates([outer[::-1], hole[::-1], hole2], pts)
    perm = np.r_[np.arange(4)[::-1], 4 + np.arange(3)[::-1], 7 + np.arange(4)]
    np.testing.assert_allclose(w2[:, perm], w, atol=1e-12)


def test_collinear_line_continuity_and_paper_mode():
    """On the line through a concave corner's edge the coordinates stay continuous
    (robust form) and the paper's two-sided mean (eq. 19) agrees to O(delta^2)."""
    # the line y = 1 through edge (2,1)-(1,1) of the L crosses the interior for x < 1
    p = np.array([[0.5, 1.0], [0.2, 1.0]])
    nodes, nxt, _ = oriented([L_SHAPE])
    robust = mvc_oriented(nodes, nxt, p)
    for h in (1e-4, 1e-6):
        up = mvc_oriented(nodes, nxt, p + [0, h])
        down = mvc_oriented(nodes, nxt, p - [0, h])
        assert np.abs(up - robust).max() < 20 * h and np.abs(down - robust).max() < 20 * h
    errs = [np.abs(mvc_oriented(nodes, nxt, p, line_mode="paper", delta=d) - robust).max()
            for d in (1e-2, 1e-3)]
    assert errs[1] < errs[0] / 50      # second order: 10x smaller offset, ~100x smaller error
    np.testing.assert_allclose(mean_value_coordinates([L_SHAPE], p, line_mode="paper") @ L_SHAPE,
                               p, atol=1e-9)


def test_bad_input_refused():
    with pytest.raises(ValueError, match="points"):
        mean_value_coordinates([L_SHAPE], np.zeros((3, 3)))
    with pytest.raises(ValueError, match="loops"):
        mean_value_coordinates([L_SHAPE[:2]], np.zeros((1, 2)))
    with pytest.raises(ValueError, match="prior"):
        max_entropy_coordinates(L_SHAPE, [[0.5, 0.5]], prior="nope")
    with pytest.raises(ValueError, match="line_mode"):
        mean_value_coordinates([L_SHAPE], [[0.5, 0.5]], line_mode="nope")
    with pytest.raises(ValueError, match="points"):   # outside the hull: no coordinates
        max_entropy_coordinates(L_SHAPE, [[5.0, 5.0]])


@SETTINGS
@given(st.integers(0, 10_000), st.floats(-1, 1), st.floats(-1, 1), st.floats(0, 6.3),
       st.integers(3, 6))
def test_mvc_with_random_hole(seed, cx, cy, turn, k):
    outer = convex(seed, n=14)
    t = turn + np.linspace(0, 2 * np.pi, k, endpoint=False)
    hole = np.array([0.3 * cx, 0.15 * cy]) + 0.12 * np.stack([np.cos(t), np.sin(t)], axis=1)
    if not Path(outer).contains_points(hole).all():
        return
    pts = inside(outer, 40, seed, holes=[hole])
    nodes = np.concatenate([outer, hole])
    w = mean_value_coordinates([outer, hole], pts)
    np.testing.assert_allclose(w.sum(axis=1), 1, atol=1e-11)
    np.testing.assert_allclose(w @ nodes, pts, atol=1e-11)
    np.testing.assert_allclose(mean_value_coordinates([outer, hole], nodes),
                               np.eye(len(nodes)), atol=1e-12)
