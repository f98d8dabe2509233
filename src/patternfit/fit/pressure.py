"""Clothing pressure from the force balance of a drape at rest.

At rest the forces on a cloth vertex resting on the body balance: membrane, bending,
gravity, friction and the body's contact force. The contact force is what the body feels,
so its normal part over the vertex area is the clothing pressure. It is read here from the
other forces, not from the solver's contact penalty: the penalty's force is
``stiffness × depth``, and the solver stiffens it where it found vertices inside the body,
so reading it back from the depth depends on solver internals (docs/fit-correction.md,
"Pressure"). The membrane law is the solver's (Baraff–Witkin strains along warp and weft,
``patternfit.sim.kernels.membrane``) with the fabric's stiffnesses, compressed yarns
carrying nothing (they buckle); bending is left out (its forces are three orders smaller
at the curvatures of a body). For a band stretched around a cylinder this is Laplace's law,
pressure = tension × curvature. SI units inside; pressures out in kPa.
"""

from __future__ import annotations

import numpy as np

from ..constants import GRAVITY


def grain_coefficients(flat_vertices, triangles, grain) -> tuple[np.ndarray, np.ndarray]:
    """Per triangle, the weights (m, 3) that give the images of the unit warp and weft
    vectors from its three corners: ``w_u = Σ_j cu[t, j] x[tris[t, j]]`` (the deformation
    gradient times the grain direction). ``flat_vertices`` (n, 2) [m], ``grain`` (m, 2)
    unit vectors per triangle."""
    v = np.asanyarray(flat_vertices, dtype=np.float64)
    t = np.asanyarray(triangles, dtype=np.int64)
    g = np.asanyarray(grain, dtype=np.float64)
    c = np.stack([-g[:, 1], g[:, 0]], axis=1)
    dm = np.stack([v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]], axis=2)
    inv = np.linalg.inv(dm)
    out = []
    for d in (g, c):
        k = np.einsum("mij,mj->mi", inv, d)  # weights of corners 1 and 2
        out.append(np.stack([-k.sum(axis=1), k[:, 0], k[:, 1]], axis=1))
    return out[0], out[1]


def membrane_forces(positions, triangles, cu, cv, rest_area, k_warp: float, k_weft: float,
                    k_shear: float) -> np.ndarray:
    """Force of the stretched membrane on every vertex (n, 3) [N]: minus the gradient of
    ``Σ A (k_u e_u² + k_v e_v² + k_s s²) / 2`` with ``e = |w| − 1`` counted only where it is
    positive (a compressed yarn buckles) and ``s = w_u · w_v``; ``k`` [N/m], ``rest_area``
    (m,) [m²], ``positions`` (n, 3) [m]."""
    x = np.asanyarray(positions, dtype=np.float64)
    t = np.asanyarray(triangles, dtype=np.int64)
    wu = np.einsum("mj,mjc->mc", cu, x[t])
    wv = np.einsum("mj,mjc->mc", cv, x[t])
    lu = np.maximum(np.linalg.norm(wu, axis=1), 1e-12)
    lv = np.maximum(np.linalg.norm(wv, axis=1), 1e-12)
    eu = np.maximum(lu - 1.0, 0.0)
    ev = np.maximum(lv - 1.0, 0.0)
    s = np.einsum("mc,mc->m", wu, wv)
    a = np.asanyarray(rest_area, dtype=np.float64)
    gu = (a * k_warp * eu / lu)[:, None] * wu + (a * k_shear * s)[:, None] * wv
    gv = (a * k_weft * ev / lv)[:, None] * wv + (a * k_shear * s)[:, None] * wu
    grad = np.zeros_like(x)
    for j in range(3):
        np.add.at(grad, t[:, j], cu[:, j:j + 1] * gu + cv[:, j:j + 1] * gv)
    return -grad


def force_balance_pressure(positions, triangles, cu, cv, rest_area, fabric, normals,
                           vertex_area, contact) -> np.ndarray:
    """Clothing pressure per vertex [kPa]: the part of the membrane force and the weight
    that presses each ``contact`` vertex onto the body, along the body's outward unit
    ``normals`` (n, 3), over its ``vertex_area`` (n,) [m²]; 0 off the contact area and
    where the cloth pulls away. ``fabric``: its ``stretch_warp``, ``stretch_weft``,
    ``shear`` [N/m] and ``density`` [kg/m²]."""
    f = membrane_forces(positions, triangles, cu, cv, rest_area, fabric.stretch_warp,
                        fabric.stretch_weft, fabric.shear)
    f[:, 1] -= fabric.density * GRAVITY * np.asanyarray(vertex_area, dtype=np.float64)
    push = -np.einsum("nc,nc->n", f, np.asanyarray(normals, dtype=np.float64))
    a = np.asanyarray(vertex_area, dtype=np.float64)
    ok = np.asanyarray(contact, dtype=bool) & (a > 0)
    p = np.zeros(len(a))
    p[ok] = np.maximum(push[ok], 0.0) / a[ok]
    return p / 1000.0
