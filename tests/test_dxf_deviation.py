"""The compiled deviation of a fitted edge from the file's polyline (pattern/dxf_kernels.py)
against the direct form it replaced: both polylines densified, a k-d tree of each queried."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.spatial import cKDTree

from patternfit.pattern.dxf_curves import _DENSE, _fit_cubic, deviation
from patternfit.pattern.edges import Edge


def _densified(p: np.ndarray, step: float) -> np.ndarray:
    """``p`` (k, 2) with every segment split into ceil(length / step) equal parts."""
    seg = np.diff(p, axis=0)
    n = np.maximum(1, np.ceil(np.linalg.norm(seg, axis=1) / step).astype(np.int64))
    return np.vstack([p[:-1][j] + np.outer(np.arange(n[j]) / n[j], seg[j])
                      for j in range(len(seg))] + [p[-1:]])


def slow_deviation(edge: Edge, p: np.ndarray) -> float:
    """Largest distance [m] from the edge's samples to the densified polyline and from the
    polyline's vertices to the densified samples, by k-d trees."""
    length = max(edge.length, float(np.sum(np.linalg.norm(np.diff(p, axis=0), axis=1))))
    n = int(min(20000, max(16, math.ceil(length / _DENSE))))
    curve = edge.point_at(np.linspace(0.0, 1.0, n + 1))
    d1, _ = cKDTree(_densified(p, _DENSE)).query(curve)
    d2, _ = cKDTree(_densified(curve, _DENSE)).query(p)
    return float(max(d1.max(), d2.max()))


_coord = st.floats(-0.3, 0.3, allow_nan=False)
_point = st.tuples(_coord, _coord)


@st.composite
def _edge_and_polyline(draw):
    """A line, quadratic, cubic or arc up to ~0.6 m long [m] and a polyline along it (the
    edge's points moved by up to 2 mm, repeats and backtracks included) or anywhere."""
    kind = draw(st.sampled_from(["line", "quadratic", "cubic", "arc"]))
    a, b = np.array(draw(_point)), np.array(draw(_point))
    if np.linalg.norm(b - a) < 1e-3:
        b = a + np.array([0.05, 0.0])
    if kind == "line":
        edge = Edge.line("e", a, b)
    elif kind == "quadratic":
        edge = Edge.quadratic("e", a, draw(_point), b)
    elif kind == "cubic":
        edge = Edge.cubic("e", a, draw(_point), draw(_point), b)
    else:
        chord = float(np.linalg.norm(b - a))
        edge = Edge.arc("e", a, b, chord / 2 * draw(st.floats(1.0, 4.0)),
                        large_arc=draw(st.booleans()), sweep=draw(st.booleans()))
    k = draw(st.integers(2, 60))
    if draw(st.booleans()):
        p = edge.point_at(np.sort(draw(st.lists(st.floats(0, 1), min_size=k, max_size=k))))
        noise = draw(st.lists(st.floats(-2e-3, 2e-3), min_size=2 * k, max_size=2 * k))
        p = p + np.reshape(noise, (k, 2))
    else:
        p = np.array(draw(st.lists(_point, min_size=k, max_size=k)))
    return edge, np.ascontiguousarray(p, dtype=np.float64)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_edge_and_polyline())
def test_compiled_deviation_equals_the_direct_form(case):
    edge, p = case
    assert abs(deviation(edge, p) - slow_deviation(edge, p)) < 1e-9


def test_a_fitted_cubic_of_an_accumark_curve_stays_within_the_span_tolerance():
    # a curve drawn as AccuMark draws one: points 1.5 mm apart, each turn point repeated
    c = np.array([(0.0, 0.0), (0.05, 0.02), (0.12, 0.15), (0.1, 0.25)])
    t = np.linspace(0, 1, 180)[:, None]
    p = ((1 - t) ** 3 * c[0] + 3 * (1 - t) ** 2 * t * c[1] + 3 * (1 - t) * t * t * c[2]
         + t ** 3 * c[3])
    edge, point_error = _fit_cubic("e", p)
    assert point_error < 1e-6
    assert np.allclose(edge.start, p[0]) and np.allclose(edge.end, p[-1])
    assert slow_deviation(edge, p) < 5e-4


def test_a_single_point_polyline_is_measured_to_that_point():
    edge = Edge.line("e", (0.0, 0.0), (0.3, 0.4))
    p = np.array([[0.0, 0.0]])
    assert abs(deviation(edge, p) - 0.5) < 1e-12
