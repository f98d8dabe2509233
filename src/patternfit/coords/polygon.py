"""Polygon helpers shared by the coordinate solvers: input checks, loop orientation, and
the exact boundary values (a point on an edge interpolates the edge's two end nodes).

Coordinates are in any consistent length unit (metres in patternfit).
"""

from __future__ import annotations

import numba
import numpy as np

from ..arguments import array
from ..geometry import polygon_area


def as_points(points, name: str) -> np.ndarray:
    """``points`` coerced to a finite (q, 2) float64 array (one point (2,) as (1, 2));
    ``ValueError`` naming ``name`` (:func:`patternfit.arguments.array`)."""
    if np.shape(points) == (2,):
        points = np.asanyarray(points, dtype=np.float64)[None]
    return array(points, name, shape=(None, 2), finite=True)


def as_loops(loops, name: str = "loops") -> list[np.ndarray]:
    """Loops coerced to (k, 2) arrays of at least 3 distinct nodes enclosing some area."""
    if isinstance(loops, np.ndarray) and loops.ndim == 2:
        loops = [loops]
    out = []
    for k, loop in enumerate(loops):
        p = as_points(loop, f"{name}[{k}]")
        if len(p) < 3:
            raise ValueError(f"{name}[{k}]: a loop needs at least 3 nodes, got {len(p)}")
        # coincident consecutive nodes make an edge of no direction (0/0 in every formula)
        gap = np.linalg.norm(p - np.roll(p, -1, axis=0), axis=1)
        if np.any(gap <= 1e-12 * diameter(p)):
            raise ValueError(f"{name}[{k}]: two consecutive nodes coincide")
        if abs(polygon_area(p)) <= 0.0:
            raise ValueError(f"{name}[{k}]: loop encloses no area")
        out.append(p)
    if not out:
        raise ValueError(f"{name}: need at least one loop")
    return out


def oriented(loops: list[np.ndarray]):
    """Nodes of all loops, outer loop counter-clockwise and inner loops clockwise.

    Returns
    -------
    nodes : (n, 2) float
        Loops concatenated in the solver's orientation.
    nxt : (n,) int
        Index of the next node along the same loop.
    order : (n,) int
        ``nodes[j]`` is the caller's node ``order[j]`` (caller order = loops concatenated).
    """
    nodes, nxt, order, start = [], [], [], 0
    for k, p in enumerate(loops):
        n = len(p)
        idx = np.arange(n)
        want_ccw = k == 0
        if (polygon_area(p) > 0) != want_ccw:
            idx = idx[::-1]
        nodes.append(p[idx])
        order.append(start + idx)
        nxt.append(start + (np.arange(n) + 1) % n)
        start += n
    return np.concatenate(nodes), np.concatenate(nxt), np.concatenate(order)


def diameter(nodes: np.ndarray) -> float:
    """Length of the bounding-box diagonal of ``nodes`` (k, 2)."""
    return float(np.linalg.norm(nodes.max(axis=0) - nodes.min(axis=0)))


@numba.njit(cache=True, nogil=True)
def _nearest_edge(nodes, nxt, points, eps):  # pragma: no cover - compiled
    """Per point: index of an edge within ``eps`` (-1 if none) and the projection parameter."""
    q, n = points.shape[0], nodes.shape[0]
    hit = np.full(q, -1, dtype=np.int64)
    par = np.zeros(q)
    for k in range(q):
        px, py = points[k, 0], points[k, 1]
        for i in range(n):
            j = nxt[i]
            ax, ay = nodes[i, 0] - px, nodes[i, 1] - py
            ex, ey = nodes[j, 0] - nodes[i, 0], nodes[j, 1] - nodes[i, 1]
            t = min(max(-(ax * ex + ay * ey) / (ex * ex + ey * ey), 0.0), 1.0)
            gx, gy = ax + t * ex, ay + t * ey
            if gx * gx + gy * gy <= eps * eps:
                hit[k] = i
                par[k] = t
                break
    return hit, par


def boundary_weights(nodes: np.ndarray, nxt: np.ndarray, points: np.ndarray, *, eps: float):
    """Exact coordinates of points lying on the boundary (eq. 18 of the paper).

    A point within ``eps`` of edge (i, nxt[i]) gets ``1 - t`` on node i and ``t`` on the next
    node, ``t`` its projection parameter; a point on a node gets that node's unit vector.

    Returns
    -------
    on : (q,) bool
        Which points lie on the boundary.
    weights : (on.sum(), n) float
        Their coordinates, columns in the order of ``nodes``.
    """
    hit, par = _nearest_edge(nodes, nxt.astype(np.int64), np.ascontiguousarray(points),
                             float(eps))
    on = hit >= 0
    rows = np.flatnonzero(on)
    w = np.zeros((len(rows), len(nodes)))
    j, t = hit[rows], par[rows]
    w[np.arange(len(rows)), j] += 1.0 - t
    w[np.arange(len(rows)), nxt[j]] += t
    return on, w
