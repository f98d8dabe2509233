"""Numba kernels of the garment energy: value and gradient per term, serial and deterministic.

All lengths in metres, forces in newtons, energies in joules. Every kernel adds its gradient
into ``grad`` (n, 3) and returns its energy, so that one pass over each term gives both.
Kernels are serial on purpose: a fixed summation order makes two runs bit-identical.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..body.sdf import sdf_query  # noqa: F401  (the solver's distance lookup)
from ..body.sdf import trilinear_at as _trilinear

# ---------------------------------------------------------------------------------------
# membrane


@njit(cache=True)
def membrane(x, tris, cu, cv, area, k_warp, k_weft, k_shear, compression, grad):
    """Orthotropic membrane (Baraff-Witkin strain measures on the grain frame).

    ``w_u = sum_j cu[t, j] x[tris[t, j]]`` is the image of the unit warp vector (column 1 of
    the deformation gradient F), ``w_v`` that of the weft. Energy per triangle
    ``A (k_u e_u^2 + k_v e_v^2 + k_s s^2) / 2`` with ``e = |w| - 1`` and ``s = w_u . w_v``;
    a stretch stiffness is multiplied by ``compression`` while its strain is negative, so
    that fabric buckles rather than shrinks.
    """
    energy = 0.0
    for t in range(tris.shape[0]):
        a0, a1, a2 = tris[t, 0], tris[t, 1], tris[t, 2]
        u0, u1, u2 = cu[t, 0], cu[t, 1], cu[t, 2]
        v0, v1, v2 = cv[t, 0], cv[t, 1], cv[t, 2]
        wux = u0 * x[a0, 0] + u1 * x[a1, 0] + u2 * x[a2, 0]
        wuy = u0 * x[a0, 1] + u1 * x[a1, 1] + u2 * x[a2, 1]
        wuz = u0 * x[a0, 2] + u1 * x[a1, 2] + u2 * x[a2, 2]
        wvx = v0 * x[a0, 0] + v1 * x[a1, 0] + v2 * x[a2, 0]
        wvy = v0 * x[a0, 1] + v1 * x[a1, 1] + v2 * x[a2, 1]
        wvz = v0 * x[a0, 2] + v1 * x[a1, 2] + v2 * x[a2, 2]
        lu = np.sqrt(wux * wux + wuy * wuy + wuz * wuz)
        lv = np.sqrt(wvx * wvx + wvy * wvy + wvz * wvz)
        eu = lu - 1.0
        ev = lv - 1.0
        s = wux * wvx + wuy * wvy + wuz * wvz
        ku = k_warp if eu > 0.0 else k_warp * compression
        kv = k_weft if ev > 0.0 else k_weft * compression
        a = area[t]
        energy += 0.5 * a * (ku * eu * eu + kv * ev * ev + k_shear * s * s)
        fu = a * ku * eu / max(lu, 1e-12)
        fv = a * kv * ev / max(lv, 1e-12)
        fs = a * k_shear * s
        gux = fu * wux + fs * wvx
        guy = fu * wuy + fs * wvy
        guz = fu * wuz + fs * wvz
        gvx = fv * wvx + fs * wux
        gvy = fv * wvy + fs * wuy
        gvz = fv * wvz + fs * wuz
        for j in range(3):
            i = tris[t, j]
            cj = cu[t, j]
            dj = cv[t, j]
            grad[i, 0] += cj * gux + dj * gvx
            grad[i, 1] += cj * guy + dj * gvy
            grad[i, 2] += cj * guz + dj * gvz
    return energy


# ---------------------------------------------------------------------------------------
# body contact and friction


#: bound on the slope of the trilinear distance interpolant [m/m]: each partial derivative is
#: a blend of grid differences of a 1-Lipschitz distance, so |grad| <= sqrt(3); 2 leaves room
#: for the seam between the exact band and the upsampled far field
SDF_SLOPE = 2.0


@njit(cache=True)
def contact(x, values, origin, spacing, thickness, stiffness, seen, room, grad):
    """Penalty ``k_i (h - d_i)^2 / 2`` on every vertex whose distance ``d_i`` is below ``h``.

    ``stiffness`` (n,) [N/m] is per vertex (area times the contact pressure stiffness).
    ``seen`` (n, 3) [m] and ``room`` (n,) [m] spare the lookups that cannot matter: a vertex
    less than ``room_i`` from ``seen_i``, where it was last looked up, is still beyond ``h``
    (the distance changes by at most ``SDF_SLOPE`` per metre moved). Both are updated here;
    start them at ``inf`` and 0.
    """
    energy = 0.0
    for i in range(x.shape[0]):
        m0 = x[i, 0] - seen[i, 0]
        m1 = x[i, 1] - seen[i, 1]
        m2 = x[i, 2] - seen[i, 2]
        if m0 * m0 + m1 * m1 + m2 * m2 < room[i] * room[i]:
            continue
        d, gx, gy, gz = _trilinear(values, origin, spacing, x[i])
        pen = thickness - d
        seen[i, 0] = x[i, 0]
        seen[i, 1] = x[i, 1]
        seen[i, 2] = x[i, 2]
        room[i] = max(-pen, 0.0) / SDF_SLOPE
        if pen > 0.0:
            k = stiffness[i]
            energy += 0.5 * k * pen * pen
            f = k * pen
            grad[i, 0] -= f * gx
            grad[i, 1] -= f * gy
            grad[i, 2] -= f * gz
    return energy


@njit(cache=True)
def friction(x, idx, anchor, normal, limit, slip, grad):
    """Lagged Coulomb friction on anchored contact vertices.

    Tangential displacement ``u = P (x_i - a_i)`` from the anchor ``a_i`` (``P`` projects out
    the anchor's normal). Energy ``mu_lambda_i f(|u|)`` with ``f(u) = u^2 / (2 slip)`` below
    ``slip`` and ``u - slip / 2`` above: a stiff spring that gives way at the Coulomb force
    ``limit_i = mu * normal force`` [N].
    """
    energy = 0.0
    for k in range(idx.shape[0]):
        i = idx[k]
        u = np.empty(3)
        for c in range(3):
            u[c] = x[i, c] - anchor[k, c]
        un = u[0] * normal[k, 0] + u[1] * normal[k, 1] + u[2] * normal[k, 2]
        for c in range(3):
            u[c] -= un * normal[k, c]
        m = np.sqrt(u[0] ** 2 + u[1] ** 2 + u[2] ** 2)
        if m < slip:
            energy += limit[k] * m * m / (2.0 * slip)
            s = limit[k] / slip
        else:
            energy += limit[k] * (m - 0.5 * slip)
            s = limit[k] / m
        for c in range(3):
            grad[i, c] += s * u[c]
    return energy


@njit(cache=True)
def seam_springs(x, a, b, stiffness, limit, grad):
    """Zero-length seam springs with a bounded pull between vertices ``a[k]`` and ``b[k]``.

    Energy ``k g^2 / 2`` for a gap ``g`` below ``r_k = limit_k / k`` and ``limit_k (g - r_k / 2)``
    beyond: the spring [N/m] near closing, a constant pull ``limit_k`` [N] when far apart, so
    that body contact (which grows without bound) wins and an edge slides round the body
    rather than being dragged through it.
    """
    energy = 0.0
    for j in range(a.shape[0]):
        i, k = a[j], b[j]
        d0 = x[i, 0] - x[k, 0]
        d1 = x[i, 1] - x[k, 1]
        d2 = x[i, 2] - x[k, 2]
        g = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        r = limit[j] / stiffness
        if g <= r:
            energy += 0.5 * stiffness * g * g
            s = stiffness
        else:
            energy += limit[j] * (g - 0.5 * r)
            s = limit[j] / g
        grad[i, 0] += s * d0
        grad[i, 1] += s * d1
        grad[i, 2] += s * d2
        grad[k, 0] -= s * d0
        grad[k, 1] -= s * d1
        grad[k, 2] -= s * d2
    return energy


# ---------------------------------------------------------------------------------------
# vector helpers for L-BFGS: serial loops, so that results do not depend on BLAS threads


@njit(cache=True)
def dot(a, b):
    """Dot product of two flat arrays, in a fixed order: four running sums over the
    indices modulo 4 (so that the adds pipeline: 2.8x faster than one sum), then added."""
    n = a.shape[0]
    m = n - n % 4
    s0 = s1 = s2 = s3 = 0.0
    for i in range(0, m, 4):
        s0 += a[i] * b[i]
        s1 += a[i + 1] * b[i + 1]
        s2 += a[i + 2] * b[i + 2]
        s3 += a[i + 3] * b[i + 3]
    for i in range(m, n):
        s0 += a[i] * b[i]
    return (s0 + s1) + (s2 + s3)


@njit(cache=True)
def axpy(alpha, x, y):
    """``y += alpha * x`` in place."""
    for i in range(x.shape[0]):
        y[i] += alpha * x[i]


@njit(cache=True)
def lbfgs_back(S, Y, rho, count, head, q, alphas):
    """First loop of the L-BFGS two-loop recursion over a ring of ``count`` pairs, newest
    (slot ``head - 1``) first: ``q`` is overwritten, ``alphas[k]`` kept for the second."""
    size = S.shape[0]
    for k in range(count):
        i = (head - 1 - k) % size
        a = rho[i] * dot(S[i], q)
        alphas[k] = a
        axpy(-a, Y[i], q)


@njit(cache=True)
def lbfgs_forward(S, Y, rho, count, head, r, alphas):
    """Second loop of the two-loop recursion, oldest pair first; ``r`` is overwritten."""
    size = S.shape[0]
    for k in range(count - 1, -1, -1):
        i = (head - 1 - k) % size
        axpy(alphas[k] - rho[i] * dot(Y[i], r), S[i], r)


@njit(cache=True)
def max_row_norm(a):
    """Largest Euclidean norm of the rows of ``a`` (n, 3)."""
    best = 0.0
    for i in range(a.shape[0]):
        v = a[i, 0] * a[i, 0] + a[i, 1] * a[i, 1] + a[i, 2] * a[i, 2]
        if v > best:
            best = v
    return np.sqrt(best)


@njit(cache=True)
def max_relative_move(x, x0):
    """Largest displacement [m] of a row from ``x0`` to ``x`` (n, 3) once the mean
    displacement is taken out."""
    n = x.shape[0]
    m0 = m1 = m2 = 0.0
    for i in range(n):
        m0 += x[i, 0] - x0[i, 0]
        m1 += x[i, 1] - x0[i, 1]
        m2 += x[i, 2] - x0[i, 2]
    m0 /= n
    m1 /= n
    m2 /= n
    best = 0.0
    for i in range(n):
        d0 = x[i, 0] - x0[i, 0] - m0
        d1 = x[i, 1] - x0[i, 1] - m1
        d2 = x[i, 2] - x0[i, 2] - m2
        v = d0 * d0 + d1 * d1 + d2 * d2
        if v > best:
            best = v
    return np.sqrt(best)


# ---------------------------------------------------------------------------------------
# self-collision


@njit(cache=True)
def self_repulsion(x, tris, pairs, bary, normal, radius, stiffness, grad):
    """Lagged vertex-triangle repulsion.

    Pair ``p`` = (vertex, triangle) keeps the barycentric coordinates and the unit normal
    (pointing to the vertex's side) found when the pair was made; the signed distance
    ``d = n . (x_v - sum_j b_j x_j)`` is pushed above ``radius`` by ``k_v (r - d)^2 / 2``.
    """
    energy = 0.0
    for p in range(pairs.shape[0]):
        v = pairs[p, 0]
        t = pairs[p, 1]
        d = 0.0
        for c in range(3):
            q = x[v, c]
            for j in range(3):
                q -= bary[p, j] * x[tris[t, j], c]
            d += normal[p, c] * q
        pen = radius - d
        if pen > 0.0:
            k = stiffness[v]
            energy += 0.5 * k * pen * pen
            f = k * pen
            for c in range(3):
                grad[v, c] -= f * normal[p, c]
                for j in range(3):
                    grad[tris[t, j], c] += f * bary[p, j] * normal[p, c]
    return energy


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


@njit(cache=True)
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
def edge_repulsion(x, edges, pairs, st, normal, radius, stiffness, grad):
    """Lagged edge-edge repulsion: the distance ``d = n . (p(s) - q(t))`` between the points
    found at the pair's making, along its direction then, is pushed above ``radius`` by
    ``k (r - d)^2 / 2`` with ``k`` the mean of the four vertices' ``stiffness`` [N/m]."""
    energy = 0.0
    w = np.empty(4)
    v = np.empty(4, dtype=np.int64)
    for p in range(pairs.shape[0]):
        e, f = pairs[p, 0], pairs[p, 1]
        v[0], v[1], v[2], v[3] = edges[e, 0], edges[e, 1], edges[f, 0], edges[f, 1]
        s, t = st[p, 0], st[p, 1]
        w[0], w[1], w[2], w[3] = 1.0 - s, s, t - 1.0, -t
        d = 0.0
        for c in range(3):
            q = 0.0
            for j in range(4):
                q += w[j] * x[v[j], c]
            d += normal[p, c] * q
        pen = radius - d
        if pen > 0.0:
            k = 0.25 * (stiffness[v[0]] + stiffness[v[1]] + stiffness[v[2]] + stiffness[v[3]])
            energy += 0.5 * k * pen * pen
            force = k * pen
            for j in range(4):
                for c in range(3):
                    grad[v[j], c] -= force * w[j] * normal[p, c]
    return energy


@njit(cache=True)
def _segment_hits_triangle(p, q, a, b, c):
    """Whether the closed segment pq crosses the interior of triangle abc (Möller-Trumbore)."""
    d = q - p
    e1 = b - a
    e2 = c - a
    h = np.cross(d, e2)
    det = e1 @ h
    if abs(det) < 1e-18:
        return False
    inv = 1.0 / det
    s = p - a
    u = inv * (s @ h)
    if u < 0.0 or u > 1.0:
        return False
    qq = np.cross(s, e1)
    v = inv * (d @ qq)
    if v < 0.0 or u + v > 1.0:
        return False
    t = inv * (e2 @ qq)
    return 0.0 <= t <= 1.0


@njit(cache=True)
def intersecting_pairs(x, tris, cell):
    """Number of triangle pairs, sharing no vertex, whose surfaces cross each other."""
    candidates = _box_pairs(x, tris, cell, 0.0)
    count = 0
    for k in range(candidates.shape[0]):
        t, u = candidates[k, 0], candidates[k, 1]
        shared = False
        for i in range(3):
            for j in range(3):
                if tris[t, i] == tris[u, j]:
                    shared = True
        if shared:
            continue
        hit = False
        for (p, q) in ((0, 1), (1, 2), (2, 0)):
            if _segment_hits_triangle(x[tris[t, p]], x[tris[t, q]], x[tris[u, 0]],
                                      x[tris[u, 1]], x[tris[u, 2]]):
                hit = True
            if _segment_hits_triangle(x[tris[u, p]], x[tris[u, q]], x[tris[t, 0]],
                                      x[tris[t, 1]], x[tris[t, 2]]):
                hit = True
        if hit:
            count += 1
    return count


# ---------------------------------------------------------------------------------------
# Hessians for the Newton solver (SolverSettings.method = "newton")


@njit(cache=True)
def membrane_hessian(x, tris, cu, cv, area, k_warp, k_weft, k_shear, compression, out):
    """Positive semi-definite Hessian of :func:`membrane`, per triangle: ``out`` (m, 81) holds
    the 9x9 block over (corner j, coordinate c) x (corner k, coordinate d), row-major.

    In the images ``w_u``, ``w_v`` of the warp and weft the stretch term
    ``k (|w| - 1)^2 / 2`` has the Hessian ``k (w^ w^T + max(e, 0) / |w| (I - w^ w^T))``: the
    transverse part, negative in compression, is clamped at zero; the shear term
    ``k_s s^2 / 2`` keeps its Gauss-Newton part ``k_s a a^T`` (``a = (w_v, w_u)``) and drops
    ``k_s s`` times an indefinite coupling. Exact where every yarn is stretched and the shear
    is zero; a PSD bound otherwise (Newton then takes a descent step).
    """
    Huu = np.empty((3, 3))
    Hvv = np.empty((3, 3))
    Huv = np.empty((3, 3))
    wu = np.empty(3)
    wv = np.empty(3)
    for t in range(tris.shape[0]):
        a0, a1, a2 = tris[t, 0], tris[t, 1], tris[t, 2]
        for c in range(3):
            wu[c] = cu[t, 0] * x[a0, c] + cu[t, 1] * x[a1, c] + cu[t, 2] * x[a2, c]
            wv[c] = cv[t, 0] * x[a0, c] + cv[t, 1] * x[a1, c] + cv[t, 2] * x[a2, c]
        lu = max(np.sqrt(wu[0] ** 2 + wu[1] ** 2 + wu[2] ** 2), 1e-12)
        lv = max(np.sqrt(wv[0] ** 2 + wv[1] ** 2 + wv[2] ** 2), 1e-12)
        eu = lu - 1.0
        ev = lv - 1.0
        ku = k_warp if eu > 0.0 else k_warp * compression
        kv = k_weft if ev > 0.0 else k_weft * compression
        a = area[t]
        tu = max(eu, 0.0) / lu
        tv = max(ev, 0.0) / lv
        for c in range(3):
            for d in range(3):
                eye = 1.0 if c == d else 0.0
                nu = wu[c] * wu[d] / (lu * lu)
                nv = wv[c] * wv[d] / (lv * lv)
                Huu[c, d] = a * (ku * (nu + tu * (eye - nu)) + k_shear * wv[c] * wv[d])
                Hvv[c, d] = a * (kv * (nv + tv * (eye - nv)) + k_shear * wu[c] * wu[d])
                Huv[c, d] = a * k_shear * wv[c] * wu[d]
        for j in range(3):
            uj = cu[t, j]
            vj = cv[t, j]
            for k in range(3):
                uk = cu[t, k]
                vk = cv[t, k]
                for c in range(3):
                    for d in range(3):
                        out[t, (j * 3 + c) * 9 + k * 3 + d] = (
                            uj * uk * Huu[c, d] + uj * vk * Huv[c, d]
                            + vj * uk * Huv[d, c] + vj * vk * Hvv[c, d])
