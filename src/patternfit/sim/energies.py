"""Set-up of the garment energy terms from the flat pattern mesh (SI units: m, kg, N, J).

The flat mesh gives each triangle its rest shape in its panel's frame and its grain (warp)
direction; ``vertex_map`` sends each flat vertex to its simulated 3D vertex (welded seam
pairs share one). From these this module builds, once per rest shape:

- the membrane coefficients: ``w_u = sum_j cu[t, j] x_j`` is the image of the unit warp
  vector of triangle ``t`` (first column of the deformation gradient F in the grain frame),
  ``w_v`` the image of the weft; ``area`` the rest areas;
- the bending matrix: the quadratic bending model of Bergou et al. (2006) on interior
  edges, scaled so that the bending rigidity B [N m] means what it says (see
  ``docs/simulation.md`` and ``_HINGE_SCALE``);
- the constant quadratic part used as the preconditioner (projective-dynamics style).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..geometry import interior_edges

#: hinge weight: B theta^2 l^2 / (A1 + A2) times this gives the energy of a fold. The
#: per-edge mean-curvature reading gives 1.5; measured against the exact isometric bending
#: energy B kappa^2 / 2 per area of a sheet wrapped on a cylinder, that overshoots by a factor
#: 3.2-3.45 on constrained-Delaunay meshes (min angle 25-30 deg, 300-10K triangles), every
#: direction alike; 1.5 / 3.4 makes B [N m] mean what it says (docs/simulation.md).
_HINGE_SCALE = 1.5 / 3.4


@dataclass(frozen=True, eq=False)
class MeshTerms:
    """Everything the energy needs that depends only on the rest shape and the vertex map.

    Attributes
    ----------
    tris : (m, 3) int
        Triangles in simulated-vertex indices.
    cu, cv : (m, 3) float
        Warp and weft coefficients of the deformation gradient [1/m].
    area : (m,) float
        Rest areas [m^2].
    vertex_area : (n3,) float
        A third of the rest area of every incident triangle [m^2].
    hinges : (h, 4) int
        Interior edges: (edge start, edge end, opposite in triangle 1, opposite in triangle 2).
    bending : (n3, n3) sparse
        Bending Hessian Q (energy ``x^T Q x / 2`` per coordinate) [N/m].
    membrane_pd : (n3, n3) sparse
        Rest-state membrane stiffness for the preconditioner [N/m].
    edge_length : float
        Mean rest edge length [m].
    """

    tris: np.ndarray
    cu: np.ndarray
    cv: np.ndarray
    area: np.ndarray
    vertex_area: np.ndarray
    hinges: np.ndarray
    bending: sp.csr_matrix
    membrane_pd: sp.csr_matrix
    edge_length: float


def _grain_frames(rest, tris, grain):
    """Rest corners of every triangle in its grain frame (warp = first axis): (m, 3, 2)."""
    g = grain / np.linalg.norm(grain, axis=1, keepdims=True)
    p = rest[tris]  # (m, 3, 2)
    u = np.einsum("mjk,mk->mj", p, g)
    v = p[..., 1] * g[:, None, 0] - p[..., 0] * g[:, None, 1]
    return np.stack([u, v], axis=2)


def build_terms(rest, tris, grain, vertex_map, n3, *, bend_warp, bend_weft,
                k_warp, k_weft, k_shear) -> MeshTerms:
    """Membrane coefficients, bending matrix and preconditioner stiffness of a flat mesh.

    Parameters
    ----------
    rest : (n, 2) float
        Flat rest positions [m].
    tris : (m, 3) int
        Flat triangles, counter-clockwise.
    grain : (m, 2) float
        Warp direction of each triangle in its panel frame.
    vertex_map : (n,) int
        Simulated vertex of each flat vertex, in ``range(n3)``.
    bend_warp, bend_weft : float
        Bending rigidity for curvature along the warp / the weft [N m].
    k_warp, k_weft, k_shear : float
        Membrane stiffnesses [N/m].
    """
    corners = _grain_frames(rest, tris, grain)
    e1 = corners[:, 1] - corners[:, 0]
    e2 = corners[:, 2] - corners[:, 0]
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    area = 0.5 * np.abs(det)
    # inverse of Dm = [e1 e2]; F = Ds Dm^-1, columns = images of the warp / weft unit vectors
    inv = np.empty((len(tris), 2, 2))
    inv[:, 0, 0] = e2[:, 1] / det
    inv[:, 0, 1] = -e2[:, 0] / det
    inv[:, 1, 0] = -e1[:, 1] / det
    inv[:, 1, 1] = e1[:, 0] / det
    cu = np.stack([-(inv[:, 0, 0] + inv[:, 1, 0]), inv[:, 0, 0], inv[:, 1, 0]], axis=1)
    cv = np.stack([-(inv[:, 0, 1] + inv[:, 1, 1]), inv[:, 0, 1], inv[:, 1, 1]], axis=1)
    vertex_map = np.asarray(vertex_map)
    sim_tris = vertex_map[tris]
    vertex_area = np.bincount(sim_tris.ravel(), weights=np.repeat(area / 3.0, 3), minlength=n3)

    # projective-dynamics-style stiffness: k A c c^T per coordinate
    rows = np.repeat(sim_tris, 3, axis=1).ravel()
    cols = np.tile(sim_tris, (1, 3)).ravel()
    cc = (k_warp + 0.5 * k_shear) * np.einsum("mi,mj->mij", cu, cu) \
        + (k_weft + 0.5 * k_shear) * np.einsum("mi,mj->mij", cv, cv)
    membrane_pd = sp.csr_matrix(((cc * area[:, None, None]).ravel(), (rows, cols)), shape=(n3, n3))

    faces, corners = interior_edges(sim_tris)
    t1, l1, t2, l2 = faces[:, 0], corners[:, 0], faces[:, 1], corners[:, 1]
    # hinge in triangle 1's flat frame: edge p0 -> p1, opposite p2; triangle 2 unfolded across
    i0 = tris[t1, l1]
    i1 = tris[t1, (l1 + 1) % 3]
    i2 = tris[t1, (l1 + 2) % 3]
    P0, P1, P2 = rest[i0], rest[i1], rest[i2]
    edge = P1 - P0
    length = np.linalg.norm(edge, axis=1)
    dA = P2 - P0
    alpha_a = np.einsum("ij,ij->i", dA, edge) / length
    h_a = np.abs(edge[:, 0] * dA[:, 1] - edge[:, 1] * dA[:, 0]) / length
    # match triangle 2's edge ends by simulated vertex: panels joined at a seam may be
    # oriented either way
    ja = tris[t2, l2]
    jb = tris[t2, (l2 + 1) % 3]
    swap = vertex_map[ja] != vertex_map[i0]
    j0 = np.where(swap, jb, ja)
    j1 = np.where(swap, ja, jb)
    j3 = tris[t2, (l2 + 2) % 3]
    Q0, Q1, Q3 = rest[j0], rest[j1], rest[j3]
    edge_b = Q1 - Q0
    len_b = np.linalg.norm(edge_b, axis=1)
    dB = Q3 - Q0
    alpha_b = np.einsum("ij,ij->i", dB, edge_b) / len_b * (length / len_b)
    h_b = np.abs(edge_b[:, 0] * dB[:, 1] - edge_b[:, 1] * dB[:, 0]) / len_b
    k2 = 1.0 / h_a
    k3 = 1.0 / h_b
    k1 = -(alpha_a * k2 + alpha_b * k3) / length
    k0 = -(k2 + k3) - k1
    K = np.stack([k0, k1, k2, k3], axis=1)
    hinge_sim = np.stack([vertex_map[i0], vertex_map[i1], vertex_map[i2], vertex_map[j3]], axis=1)
    # rigidity for curvature across the edge: the edge normal's share of warp and weft
    g = grain[t1] / np.linalg.norm(grain[t1], axis=1, keepdims=True)
    cos_n = (edge[:, 0] * g[:, 1] - edge[:, 1] * g[:, 0]) / length
    bend = bend_warp * cos_n ** 2 + bend_weft * (1.0 - cos_n ** 2)
    weight = _HINGE_SCALE * bend * length ** 2 / (area[t1] + area[t2])
    hr = np.repeat(hinge_sim, 4, axis=1).ravel()
    hc = np.tile(hinge_sim, (1, 4)).ravel()
    hv = (2.0 * weight[:, None, None] * np.einsum("hi,hj->hij", K, K)).ravel()
    bending = sp.csr_matrix((hv, (hr, hc)), shape=(n3, n3))

    edge_length = float(np.mean(np.linalg.norm(e1, axis=1)))
    return MeshTerms(tris=np.ascontiguousarray(sim_tris, dtype=np.int64),
                     cu=np.ascontiguousarray(cu), cv=np.ascontiguousarray(cv),
                     area=area, vertex_area=vertex_area, hinges=hinge_sim,
                     bending=bending, membrane_pd=membrane_pd, edge_length=edge_length)


def spring_matrix(pairs, stiffness: float, n3: int) -> sp.csr_matrix:
    """Hessian of zero-length springs ``k |x_a - x_b|^2 / 2`` between vertex ``pairs`` (k, 2)."""
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    a, b = pairs[:, 0], pairs[:, 1]
    k = np.full(len(pairs), float(stiffness))
    rows = np.r_[a, b, a, b]
    cols = np.r_[a, b, b, a]
    vals = np.r_[k, k, -k, -k]
    return sp.csr_matrix((vals, (rows, cols)), shape=(n3, n3))
