"""Numba kernels of the collision search: dense-grid bucketing, the lagged vertex-triangle and
edge-edge pairs the repulsion terms push apart, and the count of crossed triangle pairs.

Positions in metres. Serial and in a fixed order, so that two runs find the same pairs in
the same order (the solver's results are bit-identical run to run).
"""

from __future__ import annotations

import numpy as np
from numba import njit

#: a dense grid has at most this many cells per item, plus _GRID_BASE; past it the cell
#: grows (a vertex flung far would otherwise ask for a huge grid)
_GRID_PER_ITEM = 16
_GRID_BASE = 65536


@njit(cache=True)
def _grid(x, cell, items):
    """Origin (3,), shape (3,) and cell size [m] of a dense grid over the box of ``x``
    (n, 3), with cells of ``cell`` [m] or larger, at most 16 per item plus 65536."""
    lo = np.empty(3)
    span = np.empty(3)
    for c in range(3):
        lo[c] = x[:, c].min()
        span[c] = x[:, c].max() - lo[c]
    dims = np.empty(3, dtype=np.int64)
    while True:
        for c in range(3):
            dims[c] = int(span[c] / cell) + 1
        if dims[0] * dims[1] * dims[2] <= _GRID_PER_ITEM * items + _GRID_BASE:
            return lo, dims, cell
        cell *= 1.5


@njit(cache=True)
def _cell_range(a, b, lo, cell, dim):
    """First and last grid index along one axis of the interval [a, b] [m], clamped."""
    return max(int((a - lo) / cell), 0), min(int((b - lo) / cell), dim - 1)


@njit(cache=True)
def _bucket_boxes(x, items, cell, pad):
    """Items (rows of vertex indices into ``x``) bucketed in the cells of a dense grid that
    their boxes, grown by ``pad`` [m], touch: returns the grid (origin, shape, cell), the
    per-cell start offsets (cells + 1,) into ``ids``, and ``ids``; each item's box (m, 6)
    (min xyz, max xyz) too. Counting sort: no hashing, no comparison sort."""
    m, w = items.shape
    box = np.empty((m, 6))
    for t in range(m):
        for c in range(3):
            a = x[items[t, 0], c]
            b = a
            for j in range(1, w):
                v = x[items[t, j], c]
                a = min(a, v)
                b = max(b, v)
            box[t, c] = a - pad
            box[t, 3 + c] = b + pad
    lo, dims, cell = _grid(x, cell, m)
    ranges = np.empty((m, 6), dtype=np.int64)
    start = np.zeros(dims[0] * dims[1] * dims[2] + 1, dtype=np.int64)
    for t in range(m):
        for c in range(3):
            ranges[t, c], ranges[t, 3 + c] = _cell_range(box[t, c], box[t, 3 + c], lo[c],
                                                         cell, dims[c])
        for i in range(ranges[t, 0], ranges[t, 3] + 1):
            for j in range(ranges[t, 1], ranges[t, 4] + 1):
                for k in range(ranges[t, 2], ranges[t, 5] + 1):
                    start[(i * dims[1] + j) * dims[2] + k + 1] += 1
    for q in range(1, start.shape[0]):
        start[q] += start[q - 1]
    fill = start[:-1].copy()
    ids = np.empty(start[-1], dtype=np.int64)
    for t in range(m):
        for i in range(ranges[t, 0], ranges[t, 3] + 1):
            for j in range(ranges[t, 1], ranges[t, 4] + 1):
                for k in range(ranges[t, 2], ranges[t, 5] + 1):
                    q = (i * dims[1] + j) * dims[2] + k
                    ids[fill[q]] = t
                    fill[q] += 1
    return lo, dims, cell, start, ids, box, ranges


@njit(cache=True)
def _rows(rows, out):
    """``out`` (k, w) filled from ``rows``, a list of k tuples of w numbers; returned."""
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            out[i, j] = rows[i][j]
    return out


@njit(cache=True)
def _box_pairs(x, items, cell, pad):
    """Pairs (p, 2) of items (rows of ``items``, (m, k) vertex indices) whose boxes, grown
    by ``pad`` [m], overlap; each pair once, lower first, in a fixed order."""
    lo, dims, cell, start, ids, box, ranges = _bucket_boxes(x, items, cell, pad)
    m = items.shape[0]
    mark = np.full(m, -1, dtype=np.int64)
    out = []
    for t in range(m):
        for i in range(ranges[t, 0], ranges[t, 3] + 1):
            for j in range(ranges[t, 1], ranges[t, 4] + 1):
                for k in range(ranges[t, 2], ranges[t, 5] + 1):
                    q = (i * dims[1] + j) * dims[2] + k
                    for e in range(start[q], start[q + 1]):
                        u = ids[e]
                        if u <= t or mark[u] == t:
                            continue
                        mark[u] = t
                        if (box[t, 0] > box[u, 3] or box[u, 0] > box[t, 3]
                                or box[t, 1] > box[u, 4] or box[u, 1] > box[t, 4]
                                or box[t, 2] > box[u, 5] or box[u, 2] > box[t, 5]):
                            continue
                        out.append((t, u))
    return _rows(out, np.empty((len(out), 2), dtype=np.int64))


@njit(cache=True, nogil=True)
def near_pairs(x, tris, radius, cell, root):
    """Vertex-triangle pairs closer than ``radius`` whose projection falls inside the triangle.

    Returns pairs (p, 2) int (vertex, triangle), barycentric (p, 3) and the unit normal
    (p, 3) oriented towards the vertex. Triangles incident to the vertex, or to a vertex
    with the same ``root`` (n,) (the seam partners it is being sewn to), are skipped: the
    seam pulls them together, repulsion must not hold them apart. The vertices are bucketed
    on a dense grid of ``cell`` [m] (one point per vertex, so each is met once per triangle).
    """
    single = np.arange(x.shape[0]).reshape(-1, 1)
    lo, dims, cell, start, order, _, _ = _bucket_boxes(x, single, cell, 0.0)
    out_p = []
    out_b = []
    out_n = []
    for t in range(tris.shape[0]):
        t0, t1, t2 = tris[t, 0], tris[t, 1], tris[t, 2]
        ax, ay, az = x[t0, 0], x[t0, 1], x[t0, 2]
        e1x, e1y, e1z = x[t1, 0] - ax, x[t1, 1] - ay, x[t1, 2] - az
        e2x, e2y, e2z = x[t2, 0] - ax, x[t2, 1] - ay, x[t2, 2] - az
        nx = e1y * e2z - e1z * e2y
        ny = e1z * e2x - e1x * e2z
        nz = e1x * e2y - e1y * e2x
        nn = nx * nx + ny * ny + nz * nz
        if nn <= 0.0:
            continue
        ln = np.sqrt(nn)
        ux, uy, uz = nx / ln, ny / ln, nz / ln
        i0, i1 = _cell_range(min(ax, x[t1, 0], x[t2, 0]) - radius,
                             max(ax, x[t1, 0], x[t2, 0]) + radius, lo[0], cell, dims[0])
        j0, j1 = _cell_range(min(ay, x[t1, 1], x[t2, 1]) - radius,
                             max(ay, x[t1, 1], x[t2, 1]) + radius, lo[1], cell, dims[1])
        k0, k1 = _cell_range(min(az, x[t1, 2], x[t2, 2]) - radius,
                             max(az, x[t1, 2], x[t2, 2]) + radius, lo[2], cell, dims[2])
        r0, r1, r2 = root[t0], root[t1], root[t2]
        for i in range(i0, i1 + 1):
            for j in range(j0, j1 + 1):
                q = (i * dims[1] + j) * dims[2]
                # the cells of one (i, j) column are consecutive: one run of vertices
                for e in range(start[q + k0], start[q + k1 + 1]):
                    v = order[e]
                    px, py, pz = x[v, 0] - ax, x[v, 1] - ay, x[v, 2] - az
                    d = px * ux + py * uy + pz * uz
                    if abs(d) >= radius:
                        continue
                    r = root[v]
                    if r == r0 or r == r1 or r == r2:
                        continue
                    # barycentric coordinates of the projection
                    cx = py * e2z - pz * e2y
                    cy = pz * e2x - px * e2z
                    cz = px * e2y - py * e2x
                    b1 = (cx * nx + cy * ny + cz * nz) / nn
                    cx = e1y * pz - e1z * py
                    cy = e1z * px - e1x * pz
                    cz = e1x * py - e1y * px
                    b2 = (cx * nx + cy * ny + cz * nz) / nn
                    b0 = 1.0 - b1 - b2
                    if b0 <= 1e-9 or b1 <= 1e-9 or b2 <= 1e-9:
                        continue
                    sgn = 1.0 if d >= 0.0 else -1.0
                    out_p.append((v, t))
                    out_b.append((b0, b1, b2))
                    out_n.append((sgn * ux, sgn * uy, sgn * uz))
    k = len(out_p)
    return (_rows(out_p, np.empty((k, 2), dtype=np.int64)), _rows(out_b, np.empty((k, 3))),
            _rows(out_n, np.empty((k, 3))))


@njit(cache=True)
def _segment_closest(x, a, b, c, d):
    """Parameters (s, t) of the nearest points of segments ab and cd and their distance;
    s = -1 when the segments are near parallel (Ericson, Real-Time Collision Detection,
    5.1.9)."""
    d1x, d1y, d1z = x[b, 0] - x[a, 0], x[b, 1] - x[a, 1], x[b, 2] - x[a, 2]
    d2x, d2y, d2z = x[d, 0] - x[c, 0], x[d, 1] - x[c, 1], x[d, 2] - x[c, 2]
    rx, ry, rz = x[a, 0] - x[c, 0], x[a, 1] - x[c, 1], x[a, 2] - x[c, 2]
    aa = d1x * d1x + d1y * d1y + d1z * d1z
    ee = d2x * d2x + d2y * d2y + d2z * d2z
    ff = d2x * rx + d2y * ry + d2z * rz
    cc = d1x * rx + d1y * ry + d1z * rz
    bb = d1x * d2x + d1y * d2y + d1z * d2z
    den = aa * ee - bb * bb
    if den <= 1e-6 * aa * ee:
        return -1.0, 0.0, 0.0
    s = min(max((bb * ff - cc * ee) / den, 0.0), 1.0)
    t = (bb * s + ff) / ee
    if t < 0.0:
        t = 0.0
        s = min(max(-cc / aa, 0.0), 1.0)
    elif t > 1.0:
        t = 1.0
        s = min(max((bb - cc) / aa, 0.0), 1.0)
    px = rx + s * d1x - t * d2x
    py = ry + s * d1y - t * d2y
    pz = rz + s * d1z - t * d2z
    return s, t, np.sqrt(px * px + py * py + pz * pz)


@njit(cache=True)
def near_edge_pairs(x, edges, radius, cell, root):
    """Edge-edge pairs whose nearest points lie inside both edges and closer than ``radius``.

    Vertex-triangle pairs miss two edges crossing each other when every vertex is beside the
    other triangle (sharp folds); these pairs close that gap. Returns pairs (p, 2) int (edge,
    edge), the nearest points' parameters (p, 2) along each edge and the unit direction
    (p, 3) from the second edge's point to the first's. Edges sharing a vertex (or a ``root``,
    the seam partners being sewn) are skipped.
    """
    candidates = _box_pairs(x, edges, cell, 0.5 * radius)
    out_p = []
    out_s = []
    out_n = []
    for k in range(candidates.shape[0]):
        e, f = candidates[k, 0], candidates[k, 1]
        a, b = edges[e, 0], edges[e, 1]
        c, d = edges[f, 0], edges[f, 1]
        if (root[a] == root[c] or root[a] == root[d] or root[b] == root[c]
                or root[b] == root[d]):
            continue
        s, t, dist = _segment_closest(x, a, b, c, d)
        if not (0.0 < s < 1.0 and 0.0 < t < 1.0) or dist >= radius or dist <= 0.0:
            continue
        nx = (x[a, 0] + s * (x[b, 0] - x[a, 0]) - x[c, 0] - t * (x[d, 0] - x[c, 0])) / dist
        ny = (x[a, 1] + s * (x[b, 1] - x[a, 1]) - x[c, 1] - t * (x[d, 1] - x[c, 1])) / dist
        nz = (x[a, 2] + s * (x[b, 2] - x[a, 2]) - x[c, 2] - t * (x[d, 2] - x[c, 2])) / dist
        out_p.append((e, f))
        out_s.append((s, t))
        out_n.append((nx, ny, nz))
    m = len(out_p)
    return (_rows(out_p, np.empty((m, 2), dtype=np.int64)), _rows(out_s, np.empty((m, 2))),
            _rows(out_n, np.empty((m, 3))))


@njit(cache=True)
def _segment_hits(x, p, q, a, b, c):
    """Whether the closed segment from vertex ``p`` to ``q`` crosses the interior of the
    triangle of vertices ``a``, ``b``, ``c`` (positions ``x`` (n, 3); Möller-Trumbore),
    in scalars: with 3-vectors (slices and ``np.cross``) the narrow phase allocated at every
    test and took 23 of the coat's 36 ms a crossing check."""
    d0, d1, d2 = x[q, 0] - x[p, 0], x[q, 1] - x[p, 1], x[q, 2] - x[p, 2]
    e10, e11, e12 = x[b, 0] - x[a, 0], x[b, 1] - x[a, 1], x[b, 2] - x[a, 2]
    e20, e21, e22 = x[c, 0] - x[a, 0], x[c, 1] - x[a, 1], x[c, 2] - x[a, 2]
    h0, h1, h2 = d1 * e22 - d2 * e21, d2 * e20 - d0 * e22, d0 * e21 - d1 * e20
    det = e10 * h0 + e11 * h1 + e12 * h2
    if abs(det) < 1e-18:
        return False
    inv = 1.0 / det
    s0, s1, s2 = x[p, 0] - x[a, 0], x[p, 1] - x[a, 1], x[p, 2] - x[a, 2]
    u = inv * (s0 * h0 + s1 * h1 + s2 * h2)
    if u < 0.0 or u > 1.0:
        return False
    q0, q1, q2 = s1 * e12 - s2 * e11, s2 * e10 - s0 * e12, s0 * e11 - s1 * e10
    v = inv * (d0 * q0 + d1 * q1 + d2 * q2)
    if v < 0.0 or u + v > 1.0:
        return False
    t = inv * (e20 * q0 + e21 * q1 + e22 * q2)
    return 0.0 <= t <= 1.0


@njit(cache=True, nogil=True)
def crossed_pairs(x, tris, cell, root):
    """Triangle pairs (k, 2) int, lower index first, whose surfaces cross each other at
    positions ``x`` (n, 3) [m]; pairs sharing a vertex's ``root`` (n,) int are skipped.
    ``cell`` [m]: grid step of the broad phase (about an edge length)."""
    candidates = _box_pairs(x, tris, cell, 0.0)
    out = []
    for k in range(candidates.shape[0]):
        t, u = candidates[k, 0], candidates[k, 1]
        shared = False
        for i in range(3):
            for j in range(3):
                if root[tris[t, i]] == root[tris[u, j]]:
                    shared = True
        if shared:
            continue
        hit = False
        for (p, q) in ((0, 1), (1, 2), (2, 0)):
            if _segment_hits(x, tris[t, p], tris[t, q], tris[u, 0], tris[u, 1], tris[u, 2]) \
                    or _segment_hits(x, tris[u, p], tris[u, q], tris[t, 0], tris[t, 1],
                                     tris[t, 2]):
                hit = True
                break
        if hit:
            out.append((t, u))
    return _rows(out, np.empty((len(out), 2), dtype=np.int64))


@njit(cache=True)
def intersecting_pairs(x, tris, cell):
    """Number of triangle pairs, sharing no vertex, whose surfaces cross each other."""
    return crossed_pairs(x, tris, cell, np.arange(x.shape[0])).shape[0]
