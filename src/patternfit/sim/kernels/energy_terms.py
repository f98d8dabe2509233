"""Numba kernels of the garment's energy terms: value and gradient per term, serial and
deterministic; the membrane's Hessian, and the contact and friction laws' stiffness as
array functions, for the Newton solver.

All lengths in metres, forces in newtons, energies in joules. Every kernel adds its gradient
into ``grad`` (n, 3) and returns its energy, so that one pass over each term gives both.
Kernels are serial on purpose: a fixed summation order makes two runs bit-identical. The
lagged pairs that the repulsion terms take are found in :mod:`.collision`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ...body.sdf import smooth_distance_at

# ---------------------------------------------------------------------------------------
# membrane


#: the strain over which a gathered band's stiffness rises from none to full, at either
#: end of its slack (or over the slack itself where that is smaller) [-]: a C2 energy, so
#: that Newton's model does not jump as a yarn crosses into or out of its slack
SLACK_ROUND = 0.005


@njit(cache=True, nogil=True)
def _half_square(x, h):
    """``max(x, 0)^2 / 2`` with its curvature rising linearly over ``0 < x < h``: value,
    first and second derivative."""
    if x <= 0.0:
        return 0.0, 0.0, 0.0
    if x < h:
        return x * x * x / (6.0 * h), x * x / (2.0 * h), x / h
    return 0.5 * x * x - 0.5 * h * x + h * h / 6.0, x - 0.5 * h, 1.0


@njit(cache=True, nogil=True)
def _gathered(e, k, compression, slack):
    """A yarn of a gathered seam's band at strain ``e`` [-]: energy per rest area [J/m^2],
    tension [N/m] and stiffness [N/m]; ``k`` stretched, none from 0 down to ``-slack`` > 0
    (the gathers taken up), ``k compression`` beyond, the corners rounded over
    ``min(SLACK_ROUND, slack)``."""
    h = min(SLACK_ROUND, slack)
    p, dp, ddp = _half_square(e, h)
    q, dq, ddq = _half_square(-e - slack, h)
    kc = k * compression
    return k * p + kc * q, k * dp - kc * dq, k * ddp + kc * ddq


@njit(cache=True, nogil=True)
def membrane(x, tris, cu, cv, area, k_warp, k_weft, k_shear, compression, slack, grad):
    """Orthotropic membrane (Baraff-Witkin strain measures on the grain frame).

    ``w_u = sum_j cu[t, j] x[tris[t, j]]`` is the image of the unit warp vector (column 1 of
    the deformation gradient F), ``w_v`` that of the weft. Energy per triangle
    ``A (k_u e_u^2 + k_v e_v^2 + k_s s^2) / 2`` with ``e = |w| - 1`` and ``s = w_u . w_v``;
    a stretch stiffness is multiplied by ``compression`` while its strain is negative, so
    that fabric buckles rather than shrinks, and a triangle's warp and weft strains may first
    fall to ``-slack[t, 0]`` and ``-slack[t, 1]`` ((m, 2) [-]) at no cost (a gathered seam's
    band, :mod:`patternfit.sim.gathers`; :func:`_gathered`).
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
        # a gathered band's yarn: its own law in place of k e^2 / 2 (elsewhere the sums
        # above stay as they were, bit for bit)
        if slack[t, 0] > 0.0:
            pu, tu, _ = _gathered(eu, k_warp, compression, slack[t, 0])
            energy += a * (pu - 0.5 * ku * eu * eu)
            fu = a * tu / max(lu, 1e-12)
        if slack[t, 1] > 0.0:
            pv, tv, _ = _gathered(ev, k_weft, compression, slack[t, 1])
            energy += a * (pv - 0.5 * kv * ev * ev)
            fv = a * tv / max(lv, 1e-12)
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


@njit(cache=True, nogil=True)
def quadratic(indptr, indices, data, x, forces, grad):
    """Energy ``x^T Q x / 2 - f . x`` [J] of a quadratic ``Q`` (n x n CSR ``indptr``,
    ``indices``, ``data`` [N/m], acting on each coordinate alike: bending and linear seam
    springs) and the given forces ``f`` (n, 3) [N] at ``x`` (n, 3) [m]; adds ``Q x - f``
    to ``grad``. One pass over ``Q``: SciPy's product, two dot products and the sum took
    three times as long (the 22K coat: 0.65 ms of a 1.32 ms energy, now 0.21 of 0.97)."""
    energy = 0.0
    for i in range(x.shape[0]):
        q0 = 0.0
        q1 = 0.0
        q2 = 0.0
        for p in range(np.uint64(indptr[i]), np.uint64(indptr[i + 1])):
            v = data[p]
            j = np.uint64(indices[p])
            q0 += v * x[j, 0]
            q1 += v * x[j, 1]
            q2 += v * x[j, 2]
        energy += 0.5 * (x[i, 0] * q0 + x[i, 1] * q1 + x[i, 2] * q2) \
            - (forces[i, 0] * x[i, 0] + forces[i, 1] * x[i, 1] + forces[i, 2] * x[i, 2])
        grad[i, 0] += q0 - forces[i, 0]
        grad[i, 1] += q1 - forces[i, 1]
        grad[i, 2] += q2 - forces[i, 2]
    return energy


@njit(cache=True)
def contact_law(pen, k, onset):
    """Contact penalty at the penetration ``pen`` [m] (> 0) into the contact layer, with
    stiffness ``k`` [N/m] reached over the first ``onset`` [m]: (energy [J], normal force
    [N], stiffness [N/m]).

    The stiffness grows linearly from 0 at the layer's edge to ``k`` at ``onset`` deep
    (energy ``k pen^3 / (6 onset)``), then stays ``k`` (``k (pen^2 - onset pen) / 2 + k
    onset^2 / 6``): energy, force and stiffness are continuous, so that Newton's model of a
    vertex on the layer's edge is the same whichever side it lies (a plain ``k pen^2 / 2``
    jumps from 0 to ``k`` there, and a vertex on the edge made Newton's steps alternate
    between full and a 30th: docs/simulation.md). ``onset`` 0: the plain quadratic.
    """
    if pen >= onset:
        return (0.5 * k * pen * (pen - onset) + k * onset * onset / 6.0,
                k * (pen - 0.5 * onset), k)
    s = k / onset
    return s * pen * pen * pen / 6.0, 0.5 * s * pen * pen, s * pen


@njit(cache=True)
def _spared(x, seen, room, i):
    """Whether vertex ``i`` at ``x[i]`` is less than ``room[i]`` [m] from ``seen[i]``, where
    its distance was last looked up: still out of contact (:func:`contact`)."""
    m0 = x[i, 0] - seen[i, 0]
    m1 = x[i, 1] - seen[i, 1]
    m2 = x[i, 2] - seen[i, 2]
    return m0 * m0 + m1 * m1 + m2 * m2 < room[i] * room[i]


@njit(cache=True)
def unspared(x, seen, room):
    """Indices (k,) of the vertices at ``x`` (n, 3) [m] that :func:`contact` would look up
    with the same ``seen`` and ``room``: every other one is out of contact."""
    out = np.empty(x.shape[0], np.int64)
    k = 0
    for i in range(x.shape[0]):
        if not _spared(x, seen, room, i):
            out[k] = i
            k += 1
    return out[:k]


@njit(cache=True, nogil=True)
def contact(x, values, origin, spacing, thickness, stiffness, onset, seen, room, grad):
    """Penalty (:func:`contact_law`, stiffness reached over ``onset`` [m]) on every vertex
    whose distance ``d_i`` (the field's C1 reading, ``body.sdf.smooth_distance_at``: a
    continuous contact force) is below ``h`` = ``thickness``.

    ``stiffness`` (n,) [N/m] is per vertex (area times the contact pressure stiffness).
    ``seen`` (n, 3) [m] and ``room`` (n,) [m] spare the lookups that cannot matter: a vertex
    less than ``room_i`` from ``seen_i``, where it was last looked up, is still beyond ``h``
    (the distance changes by at most ``SDF_SLOPE`` per metre moved). Both are updated here;
    start them at ``inf`` and 0.
    """
    energy = 0.0
    for i in range(x.shape[0]):
        if _spared(x, seen, room, i):
            continue
        d, gx, gy, gz = smooth_distance_at(values, origin, spacing, x[i])
        pen = thickness - d
        seen[i, 0] = x[i, 0]
        seen[i, 1] = x[i, 1]
        seen[i, 2] = x[i, 2]
        room[i] = max(-pen, 0.0) / SDF_SLOPE
        if pen > 0.0:
            e, f, _ = contact_law(pen, stiffness[i], onset)
            energy += e
            grad[i, 0] -= f * gx
            grad[i, 1] -= f * gy
            grad[i, 2] -= f * gz
    return energy


@njit(cache=True)
def _point_stiffness(ids, w, n_edge, base, scale, edge_cap, face_cap, i):
    """Contact stiffness [N/m] of point ``i`` (:func:`point_stiffness`)."""
    cap = edge_cap if i < n_edge else face_cap
    k = 0.0
    for j in range(3):
        v = ids[i, j]
        k += w[i, j] * base[v] * min(scale[v], cap)
    return k


@njit(cache=True)
def point_stiffness(ids, w, n_edge, base, scale, edge_cap, face_cap):
    """Contact stiffness (p,) [N/m] of the contact points at ``sum_j w[k, j] x[ids[k, j]]``
    (``ids``, ``w`` (p, 3)): their vertices' ``base`` (n,) [N/m] times their stiffening
    ``scale`` (n,), capped at ``edge_cap`` for points ``0 ... n_edge - 1`` (inside edges)
    and ``face_cap`` for the rest (inside triangles), weighted."""
    out = np.empty(ids.shape[0])
    for i in range(ids.shape[0]):
        out[i] = _point_stiffness(ids, w, n_edge, base, scale, edge_cap, face_cap, i)
    return out


@njit(cache=True, nogil=True)
def point_contact(x, ids, w, n_edge, base, scale, edge_cap, face_cap, values, origin,
                  spacing, thickness, onset, seen, room, grad):
    """:func:`contact` on the points ``sum_j w[k, j] x[ids[k, j]]`` (``ids``, ``w`` (p, 3))
    between the vertices ``x`` (n, 3) [m], stiffness :func:`point_stiffness`; a point's
    force is shared by its vertices with its weights. ``seen`` (p, 3) and ``room`` (p,)
    as :func:`contact`'s, per point.

    Fused so that the points (10-30 per vertex on a 1-2K mesh) need neither their positions
    nor their stiffness assembled at every energy: on the 3K coat's drape the points took
    0.43 ms an energy, about 1.4 ms assembled. (Skipping a whole edge or triangle
    whose corner's lookup shows it far from the body made the call 0.94 ms: the check
    costs more than the per-point one it spares; the points in contact, looked up at every
    call, are the cost.) The spare-and-look-up block is written out as in :func:`contact`:
    shared through one helper returning the depth and gradient, the 3K coat's energy took
    2.3 times as long (0.55-0.62 -> 1.33-1.52 ms), the same to the bit."""
    energy = 0.0
    p = np.empty(3)
    for i in range(ids.shape[0]):
        for c in range(3):
            p[c] = (w[i, 0] * x[ids[i, 0], c] + w[i, 1] * x[ids[i, 1], c]
                    + w[i, 2] * x[ids[i, 2], c])
        m0 = p[0] - seen[i, 0]
        m1 = p[1] - seen[i, 1]
        m2 = p[2] - seen[i, 2]
        if m0 * m0 + m1 * m1 + m2 * m2 < room[i] * room[i]:
            continue
        d, gx, gy, gz = smooth_distance_at(values, origin, spacing, p)
        pen = thickness - d
        seen[i, 0] = p[0]
        seen[i, 1] = p[1]
        seen[i, 2] = p[2]
        room[i] = max(-pen, 0.0) / SDF_SLOPE
        if pen > 0.0:
            k = _point_stiffness(ids, w, n_edge, base, scale, edge_cap, face_cap, i)
            e, f, _ = contact_law(pen, k, onset)
            energy += e
            for j in range(3):
                v = ids[i, j]
                grad[v, 0] -= w[i, j] * f * gx
                grad[v, 1] -= w[i, j] * f * gy
                grad[v, 2] -= w[i, j] * f * gz
    return energy


def contact_forces(pen, k, onset):
    """:func:`contact_law`'s normal force [N] and stiffness [N/m] for arrays ``pen`` (> 0)
    [m] and ``k`` [N/m]: ((p,), (p,))."""
    pen = np.asarray(pen, dtype=np.float64)
    k = np.asarray(k, dtype=np.float64)
    if onset <= 0.0:
        return k * pen, k.copy()
    ramp = pen < onset
    force = np.where(ramp, 0.5 * k * pen * pen / onset, k * (pen - 0.5 * onset))
    stiff = np.where(ramp, k * pen / onset, k)
    return force, stiff


@njit(cache=True)
def friction_law(m, limit, slip):
    """Friction at the tangential offset ``m`` [m] (>= 0) from the anchor, Coulomb force
    ``limit`` [N] reached at ``slip`` [m]: (energy [J], force / m [N/m], stiffness dF/dm
    [N/m]).

    The force grows with the stiffness ``k0 = 4 limit / (3 slip)`` up to ``slip / 2``; there
    the stiffness falls linearly to 0 at ``slip``, where the force reaches ``limit`` and stays:
    energy, force and stiffness are continuous. (A spring up to ``slip`` then a constant
    force has a stiffness that drops from ``limit / slip`` to 0 at ``slip``, exactly where a
    sliding vertex is re-anchored: some 50 vertices of the 15K skirt switched between the two
    sides at every Newton step and its steps chattered; docs/simulation.md.)
    """
    a = 0.5 * slip
    w = slip - a
    k0 = 2.0 * limit / (a + slip)
    if m <= a:
        return 0.5 * k0 * m * m, k0, k0
    if m < slip:
        t = m - a
        f = k0 * (a + t - 0.5 * t * t / w)
        e = k0 * (0.5 * a * a + a * t + 0.5 * t * t - t * t * t / (6.0 * w))
        return e, f / m, k0 * (1.0 - t / w)
    e_slip = k0 * (0.5 * a * a + a * w + w * w / 3.0)
    return e_slip + limit * (m - slip), limit / m, 0.0


def friction_stiffness(m, limit, slip):
    """:func:`friction_law`'s force / m [N/m] and stiffness [N/m] for arrays ``m`` [m] and
    ``limit`` [N]: ((k,), (k,))."""
    m = np.asarray(m, dtype=np.float64)
    limit = np.asarray(limit, dtype=np.float64)
    a = 0.5 * slip
    w = slip - a
    k0 = 2.0 * limit / (a + slip)
    t = np.clip(m - a, 0.0, w)
    force = np.where(m < slip, k0 * (np.minimum(m, a) + t - 0.5 * t * t / w), limit)
    ratio = np.where(m > 0.0, force / np.maximum(m, 1e-300), k0)
    return ratio, k0 * (1.0 - t / w)


def friction_offset(force, limit, slip):
    """Inverse of :func:`friction_law`: the offset [m] from the anchor at which friction
    pulls with ``force`` [N] (arrays; ``force`` is taken at most ``limit``)."""
    force = np.minimum(np.asarray(force, dtype=np.float64), limit)
    a = 0.5 * slip
    w = slip - a
    k0 = 2.0 * limit / (a + slip)
    lin = force / np.maximum(k0, 1e-300)
    # on the softening part: k0 (a + t - t^2 / (2 w)) = force
    t = w * (1.0 - np.sqrt(np.maximum(1.0 - 2.0 * (lin - a) / w, 0.0)))
    return np.where(lin <= a, lin, a + t)


@njit(cache=True)
def friction(x, idx, anchor, normal, limit, slip, grad):
    """Lagged Coulomb friction on anchored contact vertices.

    Tangential displacement ``u = P (x_i - a_i)`` from the anchor ``a_i`` (``P`` projects out
    the anchor's normal). Energy (:func:`friction_law`): a stiff spring that gives way
    smoothly and reaches the Coulomb force ``limit_i = mu * normal force`` [N] at ``slip``.
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
        e, s, _ = friction_law(m, limit[k], slip)
        energy += e
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
# self-collision: vertex-triangle and edge-edge repulsion


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


# ---------------------------------------------------------------------------------------
# Hessians for the Newton solver (SolverSettings.method = "newton")


@njit(cache=True, nogil=True)
def membrane_hessian(x, tris, cu, cv, area, k_warp, k_weft, k_shear, compression, slack,
                     slots, out):
    """Positive semi-definite Hessian of :func:`membrane`, per triangle: the 9x9 block over
    (corner j, coordinate c) x (corner k, coordinate d), its row-major entry e of triangle t
    added to ``out[slots[81 t + e]]`` (``out`` flat; triangle by triangle, entries in order,
    as ``np.bincount`` would; ``slots = arange(81 m)`` on zeros gives the (m, 81) blocks).

    In the images ``w_u``, ``w_v`` of the warp and weft a stretch term ``psi(|w| - 1)`` with
    tension ``T = psi'`` and stiffness ``K = psi''`` (``k (|w| - 1)^2 / 2``, or
    :func:`_gathered` in a gathered band) has the Hessian ``K w^ w^T + T / |w| (I - w^ w^T)``:
    the transverse part, negative in compression, is clamped at zero; the shear term
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
        if slack[t, 0] > 0.0:  # K (n n^T + T / (K |w|) (I - n n^T)), T > 0 only where K > 0
            _, tension, ku = _gathered(eu, k_warp, compression, slack[t, 0])
            tu = max(tension, 0.0) / (lu * ku) if ku > 0.0 else 0.0
        if slack[t, 1] > 0.0:
            _, tension, kv = _gathered(ev, k_weft, compression, slack[t, 1])
            tv = max(tension, 0.0) / (lv * kv) if kv > 0.0 else 0.0
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
                        out[slots[t * 81 + (j * 3 + c) * 9 + k * 3 + d]] += (
                            uj * uk * Huu[c, d] + uj * vk * Huv[c, d]
                            + vj * uk * Huv[d, c] + vj * vk * Hvv[c, d])
