"""Numba kernels of the garment energy: value and gradient per term, serial and deterministic.

All lengths in metres, forces in newtons, energies in joules. Every kernel adds its gradient
into ``grad`` (n, 3) and returns its energy, so that one pass over each term gives both.
Kernels are serial on purpose: a fixed summation order makes two runs bit-identical.
"""

from __future__ import annotations

import numpy as np
from numba import njit

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


@njit(cache=True, inline="always")
def _cell(p, origin, spacing, n):
    """Cell index and fraction along one axis, clamped to the grid."""
    q = (p - origin) / spacing
    q = min(max(q, 0.0), n - 1 - 1e-9)
    k = min(int(np.floor(q)), n - 2)
    return k, q - k


@njit(cache=True)
def _trilinear(values, origin, spacing, p):
    """Distance and gradient of the trilinear interpolant at point ``p`` (clamped to the grid)."""
    nx, ny, nz = values.shape
    x0, fx = _cell(p[0], origin[0], spacing, nx)
    y0, fy = _cell(p[1], origin[1], spacing, ny)
    z0, fz = _cell(p[2], origin[2], spacing, nz)
    c000 = values[x0, y0, z0]
    c100 = values[x0 + 1, y0, z0]
    c010 = values[x0, y0 + 1, z0]
    c110 = values[x0 + 1, y0 + 1, z0]
    c001 = values[x0, y0, z0 + 1]
    c101 = values[x0 + 1, y0, z0 + 1]
    c011 = values[x0, y0 + 1, z0 + 1]
    c111 = values[x0 + 1, y0 + 1, z0 + 1]
    c00 = c000 * (1 - fx) + c100 * fx
    c10 = c010 * (1 - fx) + c110 * fx
    c01 = c001 * (1 - fx) + c101 * fx
    c11 = c011 * (1 - fx) + c111 * fx
    c0 = c00 * (1 - fy) + c10 * fy
    c1 = c01 * (1 - fy) + c11 * fy
    d = c0 * (1 - fz) + c1 * fz
    gx = (((c100 - c000) * (1 - fy) + (c110 - c010) * fy) * (1 - fz)
          + ((c101 - c001) * (1 - fy) + (c111 - c011) * fy) * fz)
    gy = (c10 - c00) * (1 - fz) + (c11 - c01) * fz
    gz = c1 - c0
    return d, gx / spacing, gy / spacing, gz / spacing


@njit(cache=True)
def sdf_query(values, origin, spacing, x):
    """Distances (n,) and gradients (n, 3) of the trilinear field at points ``x`` (n, 3)."""
    n = x.shape[0]
    d = np.empty(n)
    g = np.empty((n, 3))
    for i in range(n):
        d[i], g[i, 0], g[i, 1], g[i, 2] = _trilinear(values, origin, spacing, x[i])
    return d, g


@njit(cache=True)
def contact(x, values, origin, spacing, thickness, stiffness, grad):
    """Penalty ``k_i (h - d_i)^2 / 2`` on every vertex whose distance ``d_i`` is below ``h``.

    ``stiffness`` (n,) [N/m] is per vertex (area times the contact pressure stiffness).
    """
    energy = 0.0
    for i in range(x.shape[0]):
        d, gx, gy, gz = _trilinear(values, origin, spacing, x[i])
        pen = thickness - d
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


# ---------------------------------------------------------------------------------------
# vector helpers for L-BFGS: serial loops, so that results do not depend on BLAS threads


@njit(cache=True)
def dot(a, b):
    """Dot product of two flat arrays, summed in index order."""
    acc = 0.0
    for i in range(a.shape[0]):
        acc += a[i] * b[i]
    return acc


@njit(cache=True)
def axpy(alpha, x, y):
    """``y += alpha * x`` in place."""
    for i in range(x.shape[0]):
        y[i] += alpha * x[i]


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


@njit(cache=True)
def _cell_key(ix, iy, iz):
    return (ix * 73856093) ^ (iy * 19349663) ^ (iz * 83492791)


@njit(cache=True)
def _hash_triangles(x, tris, cell, pad):
    """Sorted (key, triangle) entries of every grid cell each padded triangle box touches."""
    m = tris.shape[0]
    count = 0
    lo = np.empty((m, 3), dtype=np.int64)
    hi = np.empty((m, 3), dtype=np.int64)
    for t in range(m):
        for c in range(3):
            a = min(x[tris[t, 0], c], x[tris[t, 1], c], x[tris[t, 2], c]) - pad
            b = max(x[tris[t, 0], c], x[tris[t, 1], c], x[tris[t, 2], c]) + pad
            lo[t, c] = int(np.floor(a / cell))
            hi[t, c] = int(np.floor(b / cell))
        count += (hi[t, 0] - lo[t, 0] + 1) * (hi[t, 1] - lo[t, 1] + 1) * (hi[t, 2] - lo[t, 2] + 1)
    keys = np.empty(count, dtype=np.int64)
    ids = np.empty(count, dtype=np.int64)
    n = 0
    for t in range(m):
        for ix in range(lo[t, 0], hi[t, 0] + 1):
            for iy in range(lo[t, 1], hi[t, 1] + 1):
                for iz in range(lo[t, 2], hi[t, 2] + 1):
                    keys[n] = _cell_key(ix, iy, iz)
                    ids[n] = t
                    n += 1
    order = np.argsort(keys, kind="mergesort")
    return keys[order], ids[order], lo, hi


@njit(cache=True)
def _closest_on_triangle(p, a, b, c):
    """Barycentric coordinates of the point of triangle abc closest to p (Ericson's method)."""
    ab = b - a
    ac = c - a
    ap = p - a
    d1 = ab @ ap
    d2 = ac @ ap
    if d1 <= 0.0 and d2 <= 0.0:
        return 1.0, 0.0, 0.0
    bp = p - b
    d3 = ab @ bp
    d4 = ac @ bp
    if d3 >= 0.0 and d4 <= d3:
        return 0.0, 1.0, 0.0
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        w = d1 / (d1 - d3)
        return 1.0 - w, w, 0.0
    cp = p - c
    d5 = ab @ cp
    d6 = ac @ cp
    if d6 >= 0.0 and d5 <= d6:
        return 0.0, 0.0, 1.0
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        w = d2 / (d2 - d6)
        return 1.0 - w, 0.0, w
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return 0.0, 1.0 - w, w
    den = 1.0 / (va + vb + vc)
    v = vb * den
    w = vc * den
    return 1.0 - v - w, v, w


@njit(cache=True)
def _range(keys, key):
    a = np.searchsorted(keys, key, side="left")
    b = np.searchsorted(keys, key, side="right")
    return a, b


@njit(cache=True)
def near_pairs(x, tris, radius, cell):
    """Vertex-triangle pairs closer than ``radius`` whose closest point is inside the triangle.

    Returns pairs (p, 2) int (vertex, triangle), barycentric (p, 3) and the unit normal
    (p, 3) oriented towards the vertex. Triangles incident to the vertex are skipped.
    """
    keys, ids, _, _ = _hash_triangles(x, tris, cell, radius)
    n = x.shape[0]
    mark = np.full(tris.shape[0], -1, dtype=np.int64)
    out_p = []
    out_b = []
    out_n = []
    for v in range(n):
        p = x[v]
        key = _cell_key(int(np.floor(p[0] / cell)), int(np.floor(p[1] / cell)),
                        int(np.floor(p[2] / cell)))
        a, b = _range(keys, key)
        for e in range(a, b):
            t = ids[e]
            if mark[t] == v:
                continue
            mark[t] = v
            if tris[t, 0] == v or tris[t, 1] == v or tris[t, 2] == v:
                continue
            A = x[tris[t, 0]]
            B = x[tris[t, 1]]
            C = x[tris[t, 2]]
            b0, b1, b2 = _closest_on_triangle(p, A, B, C)
            if b0 <= 1e-9 or b1 <= 1e-9 or b2 <= 1e-9:
                continue
            q = b0 * A + b1 * B + b2 * C
            dv = p - q
            dist = np.sqrt(dv @ dv)
            if dist >= radius:
                continue
            nr = np.cross(B - A, C - A)
            ln = np.sqrt(nr @ nr)
            if ln <= 0.0:
                continue
            nr = nr / ln
            if nr @ dv < 0.0:
                nr = -nr
            out_p.append((v, t))
            out_b.append((b0, b1, b2))
            out_n.append((nr[0], nr[1], nr[2]))
    k = len(out_p)
    pairs = np.empty((k, 2), dtype=np.int64)
    bary = np.empty((k, 3))
    normal = np.empty((k, 3))
    for i in range(k):
        pairs[i, 0], pairs[i, 1] = out_p[i]
        bary[i, 0], bary[i, 1], bary[i, 2] = out_b[i]
        normal[i, 0], normal[i, 1], normal[i, 2] = out_n[i]
    return pairs, bary, normal


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
    keys, ids, lo, hi = _hash_triangles(x, tris, cell, 0.0)
    m = tris.shape[0]
    mark = np.full(m, -1, dtype=np.int64)
    count = 0
    for t in range(m):
        for ix in range(lo[t, 0], hi[t, 0] + 1):
            for iy in range(lo[t, 1], hi[t, 1] + 1):
                for iz in range(lo[t, 2], hi[t, 2] + 1):
                    a, b = _range(keys, _cell_key(ix, iy, iz))
                    for e in range(a, b):
                        s = ids[e]
                        if s <= t or mark[s] == t:
                            continue
                        mark[s] = t
                        shared = False
                        for i in range(3):
                            for j in range(3):
                                if tris[t, i] == tris[s, j]:
                                    shared = True
                        if shared:
                            continue
                        if (lo[t, 0] > hi[s, 0] or lo[s, 0] > hi[t, 0] or lo[t, 1] > hi[s, 1]
                                or lo[s, 1] > hi[t, 1] or lo[t, 2] > hi[s, 2]
                                or lo[s, 2] > hi[t, 2]):
                            continue
                        hit = False
                        for (u, w) in ((0, 1), (1, 2), (2, 0)):
                            if _segment_hits_triangle(x[tris[t, u]], x[tris[t, w]], x[tris[s, 0]],
                                                      x[tris[s, 1]], x[tris[s, 2]]):
                                hit = True
                            if _segment_hits_triangle(x[tris[s, u]], x[tris[s, w]], x[tris[t, 0]],
                                                      x[tris[t, 1]], x[tris[t, 2]]):
                                hit = True
                        if hit:
                            count += 1
    return count
