"""Crossed cloth: which vertex of each crossing found by ``kernels.crossed_pairs`` passed
through (the solver untangles them: ``SolverSettings.untangle``).

Lengths in metres. Two triangles are neighbours (never counted as crossed) when they share a
vertex's ``root``: the vertex itself, or while the seams are still open any vertex the weld
will merge with it (the two sides of a closing seam lie on each other).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .kernels.collision import _rows, _segment_hits


@njit(cache=True)
def _side(x, v, a, b, c):
    """Signed distance [m] of vertex ``v`` from the plane of triangle (a, b, c), its
    barycentric coordinates there (3,) and the plane's unit normal (3,)."""
    e1 = x[b] - x[a]
    e2 = x[c] - x[a]
    n = np.cross(e1, e2)
    nn = n @ n
    p = x[v] - x[a]
    bary = np.empty(3)
    if nn <= 0.0:
        bary[:] = 1.0 / 3.0
        return 0.0, bary, n
    bary[1] = np.cross(p, e2) @ n / nn
    bary[2] = np.cross(e1, p) @ n / nn
    bary[0] = 1.0 - bary[1] - bary[2]
    n = n / np.sqrt(nn)
    return p @ n, bary, n


@njit(cache=True)
def wrong_sides(x, tris, crossed):
    """Which vertex of a crossing is on the wrong side, and where it belongs.

    For every edge of one triangle of a crossed pair (k, 2) that pierces the other, the
    endpoint nearer the pierced triangle's plane is taken to have passed through it (a
    shallow crossing). Returns (vertex, triangle) pairs (q, 2) int, the vertex's barycentric
    coordinates in the triangle's plane (q, 3) and the triangle's unit normal turned towards
    the other endpoint (q, 3): the side the vertex belongs on. Pairs may repeat.
    """
    out_p = []
    out_b = []
    out_n = []
    for k in range(crossed.shape[0]):
        for side in range(2):
            t = crossed[k, side]
            u = crossed[k, 1 - side]
            a, b, c = tris[u, 0], tris[u, 1], tris[u, 2]
            for (i, j) in ((0, 1), (1, 2), (2, 0)):
                p, q = tris[t, i], tris[t, j]
                if not _segment_hits(x, p, q, a, b, c):
                    continue
                dp, bp, n = _side(x, p, a, b, c)
                dq, bq, _ = _side(x, q, a, b, c)
                if abs(dp) <= abs(dq):
                    v, bv, s = p, bp, 1.0 if dq >= 0.0 else -1.0
                else:
                    v, bv, s = q, bq, 1.0 if dp >= 0.0 else -1.0
                out_p.append((v, u))
                out_b.append((bv[0], bv[1], bv[2]))
                out_n.append((s * n[0], s * n[1], s * n[2]))
    m = len(out_p)
    return (_rows(out_p, np.empty((m, 2), dtype=np.int64)), _rows(out_b, np.empty((m, 3))),
            _rows(out_n, np.empty((m, 3))))
