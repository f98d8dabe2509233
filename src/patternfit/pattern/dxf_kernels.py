"""Compiled inner loops of the DXF curve fitting (:mod:`.dxf_curves`): the distance from
points to a densified polyline, and the Levenberg-Marquardt steps of the cubic fit.

Both compute what their NumPy/SciPy forms computed (a k-d tree on the densified points, a
fit step of einsums), without building the densified points or the per-step arrays: reading a
multi-size AccuMark export spent most of its time there.
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["farthest_from_densified", "refine_cubic"]

#: polyline segments grouped per bounding box in the nearest-point search [-]
_CHUNK = 16


@numba.njit(cache=True, nogil=True)
def _nearest_in_chunk(x, y, p, steps, lo, hi, best):
    """Smallest squared distance [m^2] (or ``best`` when none is smaller) from (x, y) to the
    points that split segments ``lo`` to ``hi - 1`` of polyline ``p`` into ``steps`` equal
    parts (ends included)."""
    for j in range(lo, hi):
        ax, ay = p[j, 0], p[j, 1]
        dx, dy = p[j + 1, 0] - ax, p[j + 1, 1] - ay
        n = steps[j]
        dd = dx * dx + dy * dy
        t = 0.0
        if dd > 0.0:
            t = min(1.0, max(0.0, ((x - ax) * dx + (y - ay) * dy) / dd))
        f = np.round(t * n) / n  # collinear points: the nearest is nearest along the line
        ex, ey = ax + f * dx - x, ay + f * dy - y
        d2 = ex * ex + ey * ey
        if d2 < best:
            best = d2
    return best


@numba.njit(cache=True, nogil=True)
def farthest_from_densified(q, p, step):
    """Largest distance [m] from a point of ``q`` (n, 2) [m] to the nearest point of the
    polyline ``p`` (k, 2) [m] densified so that no point is more than ``step`` [m] from the
    next (each segment split into ``ceil(length / step)`` equal parts).

    Segments are grouped in bounding boxes; a group is searched only when its box is nearer
    than the nearest point found so far, starting from the group that held the last one."""
    k = p.shape[0] - 1
    if k == 0:  # a single point
        worst = 0.0
        for i in range(q.shape[0]):
            worst = max(worst, math.hypot(q[i, 0] - p[0, 0], q[i, 1] - p[0, 1]))
        return worst
    steps = np.empty(k, np.int64)
    for j in range(k):
        length = math.hypot(p[j + 1, 0] - p[j, 0], p[j + 1, 1] - p[j, 1])
        steps[j] = max(1, int(math.ceil(length / step)))
    m = (k + _CHUNK - 1) // _CHUNK
    box = np.empty((m, 4))
    for c in range(m):
        lo, hi = c * _CHUNK, min(k, (c + 1) * _CHUNK) + 1
        box[c, 0], box[c, 1] = p[lo:hi, 0].min(), p[lo:hi, 1].min()
        box[c, 2], box[c, 3] = p[lo:hi, 0].max(), p[lo:hi, 1].max()
    worst, hint = 0.0, 0
    for i in range(q.shape[0]):
        x, y = q[i, 0], q[i, 1]
        best = _nearest_in_chunk(x, y, p, steps, hint * _CHUNK,
                                 min(k, (hint + 1) * _CHUNK), np.inf)
        for c in range(m):
            if c == hint:
                continue
            gx = max(box[c, 0] - x, 0.0, x - box[c, 2])
            gy = max(box[c, 1] - y, 0.0, y - box[c, 3])
            if gx * gx + gy * gy < best:
                found = _nearest_in_chunk(x, y, p, steps, c * _CHUNK,
                                          min(k, (c + 1) * _CHUNK), best)
                if found < best:
                    best, hint = found, c
        worst = max(worst, best)
    return math.sqrt(worst)


@numba.njit(cache=True, nogil=True)
def _cost(c, t, p):
    """Sum of squared distances [m^2] between the cubic Bézier ``c`` (4, 2) at ``t`` (k,)
    and ``p`` (k, 2)."""
    total = 0.0
    for i in range(p.shape[0]):
        ti = t[i]
        u = 1.0 - ti
        w0, w1, w2, w3 = u * u * u, 3.0 * u * u * ti, 3.0 * u * ti * ti, ti * ti * ti
        ex = w0 * c[0, 0] + w1 * c[1, 0] + w2 * c[2, 0] + w3 * c[3, 0] - p[i, 0]
        ey = w0 * c[0, 1] + w1 * c[1, 1] + w2 * c[2, 1] + w3 * c[3, 1] - p[i, 1]
        total += ex * ex + ey * ey
    return total


@numba.njit(cache=True, nogil=True)
def refine_cubic(c, t, p, lam, iterations, stall, exact):
    """Levenberg-Marquardt steps on the inner control points of the cubic Bézier ``c``
    (4, 2) [m] and the curve parameters ``t`` (k,) [-] of the points ``p`` (k, 2) [m] (ends
    fixed), the parameters eliminated by a Schur complement; ``lam`` [m^2] the starting
    damping. Stops after ``iterations`` steps, or when a step improves the squared error
    [m^2] by less than ``stall`` of it or brings it below ``exact``. Returns the new
    ``c`` and ``t``."""
    c, t = c.copy(), t.copy()
    k = p.shape[0]
    now = _cost(c, t, p)
    hct = np.empty((k, 4))
    ht = np.empty(k)
    gt = np.empty(k)
    c_new, t_new = c.copy(), t.copy()
    for _ in range(iterations):
        hcc = np.zeros((4, 4))
        gc = np.zeros(4)
        for i in range(1, k - 1):
            ti = t[i]
            u = 1.0 - ti
            w0, w1, w2, w3 = u * u * u, 3.0 * u * u * ti, 3.0 * u * ti * ti, ti * ti * ti
            rx = w0 * c[0, 0] + w1 * c[1, 0] + w2 * c[2, 0] + w3 * c[3, 0] - p[i, 0]
            ry = w0 * c[0, 1] + w1 * c[1, 1] + w2 * c[2, 1] + w3 * c[3, 1] - p[i, 1]
            a, b, e = 3.0 * u * u, 6.0 * u * ti, 3.0 * ti * ti
            dx = a * (c[1, 0] - c[0, 0]) + b * (c[2, 0] - c[1, 0]) + e * (c[3, 0] - c[2, 0])
            dy = a * (c[1, 1] - c[0, 1]) + b * (c[2, 1] - c[1, 1]) + e * (c[3, 1] - c[2, 1])
            # d residual / d (c1x, c1y, c2x, c2y): x rows [w1, 0, w2, 0], y rows [0, w1, 0, w2]
            hcc[0, 0] += w1 * w1
            hcc[0, 2] += w1 * w2
            hcc[2, 2] += w2 * w2
            gc[0] += w1 * rx
            gc[1] += w1 * ry
            gc[2] += w2 * rx
            gc[3] += w2 * ry
            hct[i, 0], hct[i, 1], hct[i, 2], hct[i, 3] = w1 * dx, w1 * dy, w2 * dx, w2 * dy
            ht[i] = dx * dx + dy * dy + lam
            gt[i] = dx * rx + dy * ry
        hcc[1, 1], hcc[3, 3] = hcc[0, 0], hcc[2, 2]
        hcc[2, 0] = hcc[1, 3] = hcc[3, 1] = hcc[0, 2]
        schur = hcc.copy()
        rhs = gc.copy()
        for a in range(4):
            schur[a, a] += lam
        for i in range(1, k - 1):
            for a in range(4):
                rhs[a] -= hct[i, a] * gt[i] / ht[i]
                for b in range(4):
                    schur[a, b] -= hct[i, a] * hct[i, b] / ht[i]
        dc = -np.linalg.solve(schur, rhs)
        for a in range(2):
            c_new[1, a] = c[1, a] + dc[a]
            c_new[2, a] = c[2, a] + dc[2 + a]
        for i in range(1, k - 1):
            step = -(gt[i] + hct[i, 0] * dc[0] + hct[i, 1] * dc[1] + hct[i, 2] * dc[2]
                     + hct[i, 3] * dc[3]) / ht[i]
            t_new[i] = min(1.0, max(0.0, t[i] + step))
        new = _cost(c_new, t_new, p)
        if new < now:
            done = now - new < stall * max(now, 1e-300) or new < exact
            c[:], t[:] = c_new, t_new
            now, lam = new, lam / 3
            if done:
                break
        else:
            lam *= 4
    return c, t
