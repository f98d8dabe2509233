"""Body contact on a C1 (quadratic B-spline) reading of the body's distance field.

The trilinear interpolant of the grid (``body.sdf.trilinear_at``) is continuous, but its
gradient jumps across every cell face. A vertex pressed hard against the body (cloth pulled
tight over a shoulder) then sits on a face where the contact force turns by a few percent,
and no position balances the membrane's pull: the 2K coat on the heavy man kept one vertex
at 46-225 times its weight of residual force for thousands of Newton steps while the line
search found no descent. The quadratic B-spline of the same grid values has a continuous
gradient, so the contact force is continuous and the force balance exists.

The B-spline smooths the grid: its value is ``d + h^2/8 lap(d)`` to second order, with ``h``
the grid step and ``lap(d)`` the sum of the body surface's principal curvatures, i.e. about
0.1 mm outward on a 5 cm limb at a 5 mm grid, small against the 3 mm contact margin.

Distances in metres, negative inside the body; the grid is ``values[i, j, k]`` at the point
``origin + spacing * (i, j, k)`` (as ``body.sdf.DistanceField``).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .kernels import SDF_SLOPE


@njit(cache=True, inline="always")
def _axis(p, origin, spacing, n):
    """Nearest node (its lower neighbour is the stencil's first node, clamped so that the
    three-node stencil lies in the grid), offset ``t`` in [-1/2, 1/2] grid steps from it
    (beyond the clamp: the grid's end), and the squared distance beyond the grid [m^2]."""
    q = (p - origin) / spacing
    out = 0.0
    if q < 0.0:
        out = (q * spacing) ** 2
        q = 0.0
    elif q > n - 1:
        out = ((q - (n - 1)) * spacing) ** 2
        q = float(n - 1)
    i = min(max(int(np.floor(q + 0.5)), 1), n - 2)
    t = min(max(q - i, -0.5), 0.5)
    return i - 1, t, out


@njit(cache=True, inline="always")
def _weights(t, w, dw):
    """Quadratic B-spline weights of the three nodes around offset ``t`` and their
    derivatives [per grid step]."""
    w[0] = 0.5 * (0.5 - t) ** 2
    w[1] = 0.75 - t * t
    w[2] = 0.5 * (0.5 + t) ** 2
    dw[0] = t - 0.5
    dw[1] = -2.0 * t
    dw[2] = t + 0.5


@njit(cache=True)
def smooth_distance_at(values, origin, spacing, p):
    """Distance [m] and gradient (x, y, z) of the quadratic B-spline of the grid at ``p``
    (3,); beyond the grid, the distance to the grid is added (as the trilinear lookup)."""
    nx, ny, nz = values.shape
    i0, tx, ox = _axis(p[0], origin[0], spacing, nx)
    j0, ty, oy = _axis(p[1], origin[1], spacing, ny)
    k0, tz, oz = _axis(p[2], origin[2], spacing, nz)
    wx = np.empty(3)
    wy = np.empty(3)
    wz = np.empty(3)
    dx = np.empty(3)
    dy = np.empty(3)
    dz = np.empty(3)
    _weights(tx, wx, dx)
    _weights(ty, wy, dy)
    _weights(tz, wz, dz)
    d = 0.0
    gx = 0.0
    gy = 0.0
    gz = 0.0
    for a in range(3):
        for b in range(3):
            for c in range(3):
                v = values[i0 + a, j0 + b, k0 + c]
                d += wx[a] * wy[b] * wz[c] * v
                gx += dx[a] * wy[b] * wz[c] * v
                gy += wx[a] * dy[b] * wz[c] * v
                gz += wx[a] * wy[b] * dz[c] * v
    d += np.sqrt(ox + oy + oz)
    return d, gx / spacing, gy / spacing, gz / spacing


@njit(cache=True)
def smooth_sdf_query(values, origin, spacing, x):
    """Distances (n,) [m] and gradients (n, 3) of the B-spline field at points ``x`` (n, 3)."""
    n = x.shape[0]
    d = np.empty(n)
    g = np.empty((n, 3))
    p = np.empty(3)
    for i in range(n):
        p[0], p[1], p[2] = x[i, 0], x[i, 1], x[i, 2]
        d[i], g[i, 0], g[i, 1], g[i, 2] = smooth_distance_at(values, origin, spacing, p)
    return d, g


@njit(cache=True)
def contact(x, values, origin, spacing, thickness, stiffness, seen, room, grad):
    """Penalty ``k_i (h - d_i)^2 / 2`` on every vertex whose B-spline distance ``d_i`` is
    below ``h`` [m]; adds its gradient to ``grad`` (n, 3) and returns the energy [J].

    ``stiffness`` (n,) [N/m] per vertex. ``seen`` (n, 3) [m] and ``room`` (n,) [m] spare
    the lookups that cannot matter: a vertex less than ``room_i`` from ``seen_i``, where it
    was last looked up, is still beyond ``h`` (the B-spline's slope is bounded like the
    trilinear one's: each partial derivative blends grid differences). Both are updated
    here; start them at ``inf`` and 0.
    """
    energy = 0.0
    p = np.empty(3)
    for i in range(x.shape[0]):
        m0 = x[i, 0] - seen[i, 0]
        m1 = x[i, 1] - seen[i, 1]
        m2 = x[i, 2] - seen[i, 2]
        if m0 * m0 + m1 * m1 + m2 * m2 < room[i] * room[i]:
            continue
        p[0], p[1], p[2] = x[i, 0], x[i, 1], x[i, 2]
        d, gx, gy, gz = smooth_distance_at(values, origin, spacing, p)
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
