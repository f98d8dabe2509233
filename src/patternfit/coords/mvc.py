"""Mean value coordinates for polygons with holes, with the paper's enhancements (Sec. 5.2).

Robust Hormann–Floater (2006) form: no angles and no ``tan``, finite everywhere except on the
boundary itself, where the exact edge interpolation of the paper's eq. (18) is used.
"""

from __future__ import annotations

import numpy as np

from ..constants import tol
from .polygon import as_loops, as_points, boundary_weights, diameter, oriented

LINE_MODES = ("robust", "paper")

#: offset of the two points averaged by eq. (19), as a fraction of the polygon's diameter
PAPER_OFFSET = 1e-4


def _tan_half(sx, sy, r, nxt):
    """tan(alpha_i / 2) of the signed angle at the point in triangle (v, p_i, p_next): (q, n)."""
    a2 = sx * sy[:, nxt] - sy * sx[:, nxt]
    d = sx * sx[:, nxt] + sy * sy[:, nxt]
    rr = r * r[:, nxt]
    with np.errstate(divide="ignore", invalid="ignore"):
        # both forms equal tan(alpha/2); pick the one whose denominator does not cancel
        return np.where(d >= 0, a2 / (rr + d), (rr - d) / a2)


def _raw(nodes, nxt, prv, points):
    """Hormann–Floater weights normalised to sum 1 (no boundary handling): (q, n)."""
    sx = nodes[:, 0] - points[:, 0:1]
    sy = nodes[:, 1] - points[:, 1:2]
    r = np.hypot(sx, sy)
    th = _tan_half(sx, sy, r, nxt)
    with np.errstate(divide="ignore", invalid="ignore"):
        w = (th[:, prv] + th) / r
        return w / w.sum(axis=1, keepdims=True)


def mvc_oriented(nodes, nxt, points, *, line_mode="robust", delta=None):
    """MVC for nodes already oriented (outer loop CCW, holes CW); columns in node order.

    ``delta`` [length] is the offset of the two averaged points in ``line_mode="paper"``
    (default ``PAPER_OFFSET`` times the diameter).
    """
    if line_mode not in LINE_MODES:
        raise ValueError(f"line_mode: expected one of {LINE_MODES}, got {line_mode!r}")
    prv = np.empty_like(nxt)
    prv[nxt] = np.arange(len(nxt))
    eps = tol.merge
    on, wb = boundary_weights(nodes, nxt, points, eps=eps)
    out = np.empty((len(points), len(nodes)))
    out[on] = wb
    free = np.flatnonzero(~on)
    pts = points[free]
    w = _raw(nodes, nxt, prv, pts)
    if line_mode == "paper" and len(pts):
        # eq. (19): on the line through two consecutive nodes, the mean of the coordinates
        # of two points just either side of it
        e = nodes[nxt] - nodes
        le = np.hypot(e[:, 0], e[:, 1])
        sx = nodes[:, 0] - pts[:, 0:1]
        sy = nodes[:, 1] - pts[:, 1:2]
        dist = np.abs(sx * e[:, 1] - sy * e[:, 0]) / le
        hit = dist <= eps
        rows = np.flatnonzero(hit.any(axis=1))
        if len(rows):
            j = np.argmax(hit[rows], axis=1)
            if delta is None:
                delta = PAPER_OFFSET * diameter(nodes)
            normal = np.stack([-e[j, 1], e[j, 0]], axis=1) / le[j, None] * delta
            w[rows] = 0.5 * (_raw(nodes, nxt, prv, pts[rows] + normal)
                             + _raw(nodes, nxt, prv, pts[rows] - normal))
    out[free] = w
    return out


def mean_value_coordinates(loops, points, *, line_mode="robust"):
    """Enhanced mean value coordinates of ``points`` over a polygon with holes.

    Parameters
    ----------
    loops : list of (k, 2) float
        The outer outline first, then inner loops (darts, holes), each in any orientation
        [m]. Consecutive nodes must differ.
    points : (q, 2) float
        Query points [m], normally inside the domain (outside it the weights still sum to 1
        and reproduce the point, but may be negative).
    line_mode : {"robust", "paper"}
        Points on the straight line through two consecutive nodes: ``"robust"`` evaluates
        the Hormann–Floater form, exact there; ``"paper"`` averages the coordinates of two
        points either side of the line (paper eq. 19). Both agree to O(offset^2).

    Returns
    -------
    (q, n) float
        Weights; columns follow the caller's nodes, loops concatenated in the given order.
        Points within ``tol.merge`` of an edge take the edge's linear interpolation
        (paper eq. 18), points on a node that node's unit vector.
    """
    lps = as_loops(loops)
    pts = as_points(points, "points")
    nodes, nxt, order = oriented(lps)
    w = mvc_oriented(nodes, nxt, pts, line_mode=line_mode)
    out = np.empty_like(w)
    out[:, order] = w
    return out
