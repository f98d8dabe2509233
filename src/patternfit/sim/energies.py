"""Set-up of the garment energy terms from the flat pattern mesh (SI units: m, kg, N, J).

The flat mesh gives each triangle its rest shape in its panel's frame and its grain (warp)
direction; ``vertex_map`` sends each flat vertex to its simulated 3D vertex (welded seam
pairs share one). From these this module builds, once per rest shape:

- the membrane coefficients: ``w_u = sum_j cu[t, j] x_j`` is the image of the unit warp
  vector of triangle ``t`` (first column of the deformation gradient F in the grain frame),
  ``w_v`` the image of the weft; ``area`` the rest areas;
- the bending matrix: each triangle's curvature tensor recovered from the fold vectors of
  its interior edges (Bergou et al. 2006's hinge vectors, exact for every quadratic surface
  on any mesh) and an orthotropic plate energy on it with the fabric's warp and weft
  rigidities (``_bending_matrix``; docs/simulation.md, "Bending");
- the constant quadratic part used as the preconditioner (projective-dynamics style).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..geometry import interior_edges

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
    bend_local : (m, 6, 6) float
        Each triangle's share of Q over its six bending vertices [N/m]:
        ``x_t^T bend_local[t] x_t`` per coordinate is twice its bending energy, i.e.
        ``A_t (B_warp K_uu^2 + B_weft K_vv^2 + 2 B_twist K_uv^2)``.
    bend_ids : (m, 6) int
        Those six vertices (its corners, then the opposite corner across each edge; a free
        edge repeats corner 0 with zero weight).
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
    bend_local: np.ndarray
    bend_ids: np.ndarray


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
    corners_g = _grain_frames(rest, tris, grain)
    e1 = corners_g[:, 1] - corners_g[:, 0]
    e2 = corners_g[:, 2] - corners_g[:, 0]
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
    hinge_sim = np.stack([sim_tris[faces[:, 0], corners[:, 0]],
                          sim_tris[faces[:, 0], (corners[:, 0] + 1) % 3],
                          sim_tris[faces[:, 0], (corners[:, 0] + 2) % 3],
                          sim_tris[faces[:, 1], (corners[:, 1] + 2) % 3]], axis=1)
    bending, bend_local, bend_ids = _bending_matrix(rest, tris, corners_g, vertex_map, n3,
                                                    faces, corners, area,
                                                    bend_warp=bend_warp, bend_weft=bend_weft)

    edge_length = float(np.mean(np.linalg.norm(e1, axis=1)))
    return MeshTerms(tris=np.ascontiguousarray(sim_tris, dtype=np.int64),
                     cu=np.ascontiguousarray(cu), cv=np.ascontiguousarray(cv),
                     area=area, vertex_area=vertex_area, hinges=hinge_sim,
                     bending=bending, membrane_pd=membrane_pd, edge_length=edge_length,
                     bend_local=bend_local, bend_ids=bend_ids)


#: eigenvalues of a triangle's fold matrix below this share of its largest are left free
#: (see ``_bending_matrix``)
_FOLD_CUTOFF = 1e-3


def _bending_matrix(rest, tris, corners_g, vertex_map, n3, faces, corners, area, *,
                    bend_warp, bend_weft):
    """Bending Hessian Q [N/m] (energy ``x^T Q x / 2`` per coordinate) of a flat rest mesh,
    with each triangle's 6 x 6 share of it and its six vertices (``MeshTerms.bend_local``,
    ``bend_ids``).

    Every side of an interior edge, seen from triangle ``t``, gives a hinge vector
    ``k . x`` over (edge start, edge end, t's opposite corner, the other triangle's opposite
    corner unfolded into t's plane), k the affine null vector scaled so that ``|k . x|`` is
    the fold angle (Bergou et al. 2006). On a quadratic height field
    ``z = (K_uu u^2 + K_vv v^2) / 2 + K_uv u v`` (u along t's warp) that fold is exactly
    ``m . (K_uu, K_vv, K_uv)`` with ``m = k . (u^2/2, v^2/2, u v)`` at the four corners, so
    the three sides of an interior triangle give its curvature tensor exactly on any mesh;
    the triangle stores ``A_t / 2 (B_warp K_uu^2 + B_weft K_vv^2 + 2 B_twist K_uv^2)``
    (no Poisson coupling; ``B_twist = sqrt(B_warp B_weft)``, Huber's rule for orthotropic
    plates, so a bend at angle phi to the warp has rigidity
    ``(sqrt(B_warp) cos^2 phi + sqrt(B_weft) sin^2 phi)^2``). A triangle with a free edge
    takes the least energy the folds it has allow (the free edge's fold is left open, the
    natural condition of a free edge). The edge-by-edge hinge energy this replaces has a
    bending Poisson ratio of -1/3 on any near-equilateral mesh, which let a cantilever strip
    curl and read its rigidity 8-18 % low (docs/fabrics.md).
    """
    m = len(tris)
    # both sides of every interior edge: (triangle, its edge, other triangle, its edge)
    t = np.r_[faces[:, 0], faces[:, 1]]
    j = np.r_[corners[:, 0], corners[:, 1]]
    o = np.r_[faces[:, 1], faces[:, 0]]
    oj = np.r_[corners[:, 1], corners[:, 0]]
    A = corners_g[t, j]
    P1 = corners_g[t, (j + 1) % 3]
    C = corners_g[t, (j + 2) % 3]
    edge = P1 - A
    length = np.linalg.norm(edge, axis=1)
    e_hat = edge / length[:, None]
    dc = C - A
    alpha_c = np.einsum("ij,ij->i", dc, e_hat)
    perp = dc - alpha_c[:, None] * e_hat
    h_c = np.linalg.norm(perp, axis=1)
    n_hat = perp / h_c[:, None]
    # the other triangle's opposite corner, from its own rest shape (it may lie in another
    # panel, joined at a seam, oriented either way)
    fa = tris[t, j]
    oa, ob = tris[o, oj], tris[o, (oj + 1) % 3]
    swap = vertex_map[oa] != vertex_map[fa]
    Ao = rest[np.where(swap, ob, oa)]
    Bo = rest[np.where(swap, oa, ob)]
    od = tris[o, (oj + 2) % 3]
    eo = Bo - Ao
    lo = np.linalg.norm(eo, axis=1)
    do = rest[od] - Ao
    alpha_d = np.einsum("ij,ij->i", do, eo) / lo * (length / lo)
    h_d = np.abs(eo[:, 0] * do[:, 1] - eo[:, 1] * do[:, 0]) / lo
    D = A + alpha_d[:, None] * e_hat - h_d[:, None] * n_hat
    k2 = 1.0 / h_c
    k3 = 1.0 / h_d
    k1 = -(alpha_c * k2 + alpha_d * k3) / length
    k0 = -(k2 + k3) - k1
    K = np.stack([k0, k1, k2, k3], axis=1)  # (s, 4)
    pts = np.stack([A, P1, C, D], axis=1)  # (s, 4, 2), t's grain frame
    quad = np.stack([pts[..., 0] ** 2 / 2, pts[..., 1] ** 2 / 2, pts[..., 0] * pts[..., 1]],
                    axis=2)
    fold = np.einsum("si,sik->sk", K, quad)  # (s, 3): fold per unit (K_uu, K_vv, K_uv)

    # per triangle, in edge order (a missing side is a zero row), over six local vertices:
    # its corners 0-2 and the opposite corner across each edge 3-5
    Kt = np.zeros((m, 3, 6))
    Kt[t, j, j] = k0
    Kt[t, j, (j + 1) % 3] = k1
    Kt[t, j, (j + 2) % 3] = k2
    Kt[t, j, 3 + j] = k3
    ids = np.concatenate([vertex_map[tris], vertex_map[tris[:, :1]].repeat(3, axis=1)], axis=1)
    ids[t, 3 + j] = vertex_map[od]
    Mt = np.zeros((m, 3, 3))
    Mt[t, j] = fold
    twist = np.sqrt(bend_warp * bend_weft)
    d_inv = np.array([1.0 / bend_warp, 1.0 / bend_weft, 1.0 / (2.0 * twist)])
    # least plate energy given the folds: E = theta^T (M D^-1 M^T)^+ theta / 2 per area. A
    # missing side is a zero row; so is, in effect, a curvature the folds cannot see (six
    # points on one conic, e.g. two lines through a grid: no fold for it), left free by the
    # pseudo-inverse's cut-off rather than made nearly rigid by a tiny eigenvalue (on
    # quality meshes the smallest eigenvalue is >= 0.03 of the largest for 95 % of the
    # triangles)
    N = np.einsum("tea,a,tfa->tef", Mt, d_inv, Mt)
    H = np.linalg.pinv(N, rcond=_FOLD_CUTOFF, hermitian=True) * area[:, None, None]
    local = np.einsum("tef,tei,tfk->tik", H, Kt, Kt)  # (m, 6, 6)
    rows = np.repeat(ids, 6, axis=1).ravel()
    cols = np.tile(ids, (1, 6)).ravel()
    Q = sp.coo_matrix((local.ravel(), (rows, cols)), shape=(n3, n3)).tocsr()
    Q.eliminate_zeros()
    return Q, local, np.ascontiguousarray(ids, dtype=np.int64)


def spring_matrix(pairs, stiffness: float, n3: int) -> sp.csr_matrix:
    """Hessian of zero-length springs ``k |x_a - x_b|^2 / 2`` between vertex ``pairs`` (k, 2)."""
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    a, b = pairs[:, 0], pairs[:, 1]
    k = np.full(len(pairs), float(stiffness))
    rows = np.r_[a, b, a, b]
    cols = np.r_[a, b, b, a]
    vals = np.r_[k, k, -k, -k]
    return sp.csr_matrix((vals, (rows, cols)), shape=(n3, n3))
