"""The total energy the solver minimises, its gradient and its PSD-projected Hessian, as pure
functions of the cloth model, the contact state and the positions (SI units: m, N, J).

Energy (METHOD.md section 5): membrane + bending + gravity and external forces + body
contact (at the vertices and at points inside the edges) + lagged friction + seam springs + lagged self-repulsion (vertex-triangle and
edge-edge). Nothing here writes the model or the state; the rest-shape terms come from
``energies.py``, each term's loop from ``kernels/energy_terms.py``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from . import kernels
from .model import ClothModel
from .settings import SolverSettings
from .state import EDGE_CONTACT_SCALE, FACE_CONTACT_SCALE, ContactState
from .threads import both, threads_for


@dataclass(eq=False)
class ContactLookups:
    """Where each vertex's body distance was last looked up, ``seen`` (n, 3) [m], and how far
    it may move from there and still be out of contact, ``room`` (n,) [m]
    (``kernels.contact``); ``edge_seen`` (p, 3) and ``edge_room`` (p,) the same for the
    edge contact points (:meth:`ClothModel.edge_points`). It only spares lookups: an energy
    computed with it equals one computed with fresh lookups, bit for bit."""

    seen: np.ndarray
    room: np.ndarray
    edge_seen: np.ndarray
    edge_room: np.ndarray

    @classmethod
    def fresh(cls, n: int, points: int = 0) -> "ContactLookups":
        """No lookup made yet for ``n`` vertices and ``points`` edge contact points."""
        return cls(np.full((n, 3), np.inf), np.zeros(n), np.full((points, 3), np.inf),
                   np.zeros(points))

    @classmethod
    def for_model(cls, model: ClothModel, settings: SolverSettings) -> "ContactLookups":
        """No lookup made yet for ``model``'s vertices and edge contact points."""
        return cls.fresh(model.n, len(edge_points(model, settings).ids))

    def unspared(self, x) -> np.ndarray:
        """Indices (k,) of the vertices at ``x`` (n, 3) [m] that ``kernels.contact`` would
        look up (``kernels.unspared``, its own test): every other one is out of contact."""
        return kernels.unspared(x, self.seen, self.room)


def edge_points(model: ClothModel, settings: SolverSettings):
    """The edge contact points of ``model`` under ``settings.edge_contact``."""
    return model.edge_points(settings.edge_contact)


def edge_stiffness(model: ClothModel, state: ContactState,
                   settings: SolverSettings) -> np.ndarray:
    """Contact stiffness (p,) [N/m] of the edge and face points: their vertices' (weighted,
    ``kernels.point_stiffness``), stiffened no more than ``EDGE_CONTACT_SCALE`` times. A
    straight edge across a concave crease (an armpit) cannot leave the body whatever pushes
    it: stiffened as far as its vertices may be (4^6), the underarm points of the 1.5K
    coat pushed a vertex with 10 kN, its friction limit grew to 6.8 kN and a let-out
    re-drape blew up; never stiffened, the 3K shirt kept 4 edges 1.5 mm deep at its cuffs.
    A point inside a triangle is never stiffened (``FACE_CONTACT_SCALE``): a triangle
    across the underarm has several, and stiffened to 16 times they pushed the let-out
    coat's sleeves apart."""
    pts = edge_points(model, settings)
    return kernels.point_stiffness(pts.ids, pts.w, pts.n_edge, contact_base(model, settings),
                                   state.contact_scale, EDGE_CONTACT_SCALE, FACE_CONTACT_SCALE)


def contact_base(model: ClothModel, settings: SolverSettings) -> np.ndarray:
    """Unstiffened contact stiffness (n,) [N/m] of each vertex: the contact pressure
    stiffness times its area."""
    return settings.contact_stiffness * model.terms.vertex_area


def distance(model: ClothModel, x):
    """Distances (n,) [m] and gradients (n, 3) of the body's field as contact sees it (the
    field's C1 reading, ``body.sdf.smooth_sdf_query``) at solved positions ``x`` (n, 3) [m]."""
    body = model.body
    return kernels.smooth_sdf_query(body.values, body.origin, body.spacing, x)


def energy(model: ClothModel, state: ContactState, x, *, settings: SolverSettings,
           lookups: ContactLookups | None = None) -> tuple[float, np.ndarray]:
    """Total energy [J] and its gradient (n, 3) [N] at solved positions ``x`` (n, 3) [m]
    (zero on pinned vertices), with the lagged terms of ``state``.

    Reads ``settings.compression``, ``friction_slip`` and ``self_gap``. ``lookups``: a
    cache of body distance lookups from earlier calls on the same state (updated here; it
    never changes the result); None looks every vertex up.
    """
    t = model.terms
    fab = model.fabric
    if lookups is None and model.body is not None:
        lookups = ContactLookups.for_model(model, settings)
    elif lookups is not None and (len(lookups.room), len(lookups.edge_room)) != (
            len(x), len(edge_points(model, settings).ids)):
        # the kernel writes them unchecked
        raise ValueError(f"lookups: made for {len(lookups.room)} vertices and "
                         f"{len(lookups.edge_room)} edge points, not this model's "
                         "(ContactLookups.for_model)")
    grad = np.zeros_like(x)
    touch = np.zeros_like(x) if model.body is not None else None

    def cloth() -> float:  # membrane, bending and the given forces, into grad
        e = kernels.membrane(x, t.tris, t.cu, t.cv, t.area, fab.stretch_warp,
                             fab.stretch_weft, fab.shear, settings.compression,
                             model.gather_slack, grad)
        Q = state.quadratic
        if Q.format != "csr":
            Q = Q.tocsr()
        if Q.shape != (len(x), len(x)):  # the kernel reads it unchecked
            raise ValueError(f"state.quadratic: {Q.shape[0]} x {Q.shape[1]}, not "
                             f"{len(x)} x {len(x)}")
        e += kernels.quadratic(Q.indptr, Q.indices, Q.data, x, state.forces, grad)
        if model.bend_friction is not None:
            e += model.bend_friction.energy(x, grad)
        return e

    def body_contact() -> float:  # the vertices' and the edge and face points', into touch
        if model.body is None:
            return 0.0
        body = model.body
        e = kernels.contact(x, body.values, body.origin, body.spacing, model.reach(settings),
                            state.contact_k, settings.contact_onset, lookups.seen,
                            lookups.room, touch)
        pts = edge_points(model, settings)
        if len(pts.ids):
            e += kernels.point_contact(x, pts.ids, pts.w, pts.n_edge,
                                       contact_base(model, settings), state.contact_scale,
                                       EDGE_CONTACT_SCALE, FACE_CONTACT_SCALE, body.values,
                                       body.origin, body.spacing, model.reach(settings),
                                       settings.contact_onset, lookups.edge_seen,
                                       lookups.edge_room, touch)
        return e

    # the two groups write apart and are summed in a fixed order: the same bits on one
    # thread or two
    e_contact, e = both(body_contact, cloth, threads=threads_for(len(x)))
    e += e_contact
    if touch is not None:
        grad += touch
    if len(state.friction_idx):
        e += kernels.friction(x, state.friction_idx, state.friction_anchor,
                              state.friction_normal, state.friction_limit,
                              settings.friction_slip, grad)
    if state.seam_limit is not None:
        e += kernels.seam_springs(x, state.seam_a, state.seam_b, state.seam_k,
                                  state.seam_limit, grad)
    gap = model.self_gap(settings)
    if len(state.pairs):
        e += kernels.self_repulsion(x, t.tris, state.pairs, state.bary, state.pair_normal,
                                    gap, state.contact_k, grad)
    if len(state.edge_pairs):
        e += kernels.edge_repulsion(x, state.near_edges, state.edge_pairs, state.edge_st,
                                    state.edge_normal, gap, state.contact_k, grad)
    grad[~model.free] = 0.0
    return e, grad


class HessianPattern(NamedTuple):
    """The fixed sparsity of the 3n x 3n Hessian (membrane, bending and every vertex's 3x3
    block) and each term's slots in it (:func:`hessian_pattern`)."""

    tris: np.ndarray          # (m, 3) the triangles it was made for
    indptr: np.ndarray        # (3n + 1,) CSR row starts
    indices: np.ndarray       # CSR column indices
    membrane_slots: np.ndarray
    bending_slots: np.ndarray
    block_slots: np.ndarray
    #: the vertex pairs that share a triangle (and each vertex with itself; with
    #: ``bending`` also the bending's pairs) as an n x n CSR pattern, (n + 1,) row starts and
    #: sorted columns: the pattern the Newton preconditioner keeps
    near_indptr: np.ndarray
    near_indices: np.ndarray
    bending: bool = False


def hessian_pattern(model: ClothModel, *, bending: bool = False) -> HessianPattern:
    """The Hessian's sparsity for ``model``'s triangles and bending matrix; made once per
    mesh topology (the solver keeps it while ``fits_pattern`` holds). ``bending``: the
    preconditioner's pattern keeps the bending's pairs too
    (``SolverSettings.newton_bending_preconditioner``)."""
    n = model.n
    n3 = 3 * n
    tris = model.terms.tris
    dof = (3 * tris[:, :, None] + np.arange(3)).reshape(-1, 9)  # (m, 9)
    r_mem = np.repeat(dof, 9, axis=1).ravel()
    c_mem = np.tile(dof, (1, 9)).ravel()
    Q = model.terms.bending.tocoo()
    r_b = (3 * Q.row[:, None] + np.arange(3)).ravel()
    c_b = (3 * Q.col[:, None] + np.arange(3)).ravel()
    vd = 3 * np.arange(n)[:, None] + np.arange(3)
    r_d = np.repeat(vd, 3, axis=1).ravel()
    c_d = np.tile(vd, (1, 3)).ravel()
    keys = np.concatenate([r_mem * n3 + c_mem, r_b * n3 + c_b, r_d * n3 + c_d])
    uniq, slot = np.unique(keys, return_inverse=True)
    rows, cols = uniq // n3, uniq % n3
    indptr = np.searchsorted(rows, np.arange(n3 + 1)).astype(np.int32)
    indices = cols.astype(np.int32)
    k1, k2 = len(r_mem), len(r_mem) + len(r_b)
    slot = slot.astype(np.int32)
    pairs = [(tris[:, :, None] * n + tris[:, None, :]).ravel(), np.arange(n) * (n + 1)]
    if bending:
        pairs.append(Q.row.astype(np.int64) * n + Q.col)
    near = np.unique(np.concatenate(pairs))
    near_indptr = np.searchsorted(near // n, np.arange(n + 1)).astype(np.int32)
    return HessianPattern(tris.copy(), indptr, indices, slot[:k1], slot[k1:k2], slot[k2:],
                          near_indptr, (near % n).astype(np.int32), bending)


def fits_pattern(pattern: HessianPattern | None, model: ClothModel, *,
                 bending: bool = False) -> bool:
    """Whether ``pattern`` is the Hessian sparsity of ``model``'s bending matrix, with the
    preconditioner's pattern ``bending`` asks for."""
    return pattern is not None and len(pattern.bending_slots) == 3 * model.terms.bending.nnz \
        and pattern.bending == bending


def hessian(model: ClothModel, state: ContactState, x, *, settings: SolverSettings,
            pattern: HessianPattern, lookups: ContactLookups | None = None) -> sp.csr_matrix:
    """PSD-projected Hessian (3n x 3n CSR) [N/m] of the energy at solved positions ``x``
    (n, 3) [m] with the lagged terms of ``state``, plus the regulariser m / newton_dt^2;
    pinned rows and columns are identity. ``pattern``: :func:`hessian_pattern` of
    ``model``. ``lookups``: the energy's lookup cache of the same state (read only: the
    distance is looked up only where it may be in contact; the same matrix, bit for bit);
    None looks every vertex up. The sum of :func:`hessian_parts`."""
    H, extra = hessian_parts(model, state, x, settings=settings, pattern=pattern,
                             lookups=lookups)
    return H if extra is None else (H + extra).tocsr()


def hessian_parts(model: ClothModel, state: ContactState, x, *, settings: SolverSettings,
                  pattern: HessianPattern, lookups: ContactLookups | None = None
                  ) -> tuple[sp.csr_matrix, sp.csr_matrix | None]:
    """:func:`hessian` in two parts (3n x 3n CSR each) [N/m]: the terms within ``pattern``'s
    fixed sparsity (membrane, bending, every vertex's block, the body contact of the points
    inside edges and triangles) and the rest (self-repulsion pairs, bending friction), or
    None when there is none. With every vertex free the first one's entries are
    ``pattern``'s, in its order (pinned vertices' rows and columns are made identity). Kept
    apart, a Newton step does not copy the whole Hessian to add a few pairs (the 22K coat:
    some 3 ms of a 13 ms assembly)."""
    s = settings
    t = model.terms
    f = model.fabric
    n = model.n
    data = np.zeros(len(pattern.indices))

    def membrane():
        kernels.membrane_hessian(x, t.tris, t.cu, t.cv, t.area, f.stretch_warp,
                                 f.stretch_weft, f.shear, s.compression, model.gather_slack,
                                 pattern.membrane_slots, data)

    def the_rest():  # per vertex: the regulariser, contact, friction; the other matrices
        blocks = np.zeros((n, 3, 3))
        blocks += (model.mass / s.newton_dt ** 2)[:, None, None] * np.eye(3)
        points = None
        if model.body is not None:
            near = np.arange(n) if lookups is None else lookups.unspared(x)
            d, g = distance(model, x[near])
            hit = d < model.reach(s)
            on = near[hit]
            _, k_on = kernels.contact_forces(model.reach(s) - d[hit], state.contact_k[on],
                                             s.contact_onset)
            blocks[on] += k_on[:, None, None] * g[hit, :, None] * g[hit, None, :]
            points = edge_contact_blocks(model, state, x, settings=s, lookups=lookups)
        if len(state.friction_idx):
            idx, nrm = state.friction_idx, state.friction_normal
            P = np.eye(3)[None] - nrm[:, :, None] * nrm[:, None, :]
            u = np.einsum("kij,kj->ki", P, x[idx] - state.friction_anchor)
            m = np.linalg.norm(u, axis=1)
            ratio, k = kernels.friction_stiffness(m, state.friction_limit, s.friction_slip)
            uh = u / np.maximum(m, 1e-300)[:, None]
            uu = uh[:, :, None] * uh[:, None, :]
            np.add.at(blocks, idx, ratio[:, None, None] * (P - uu) + k[:, None, None] * uu)
        friction = None if model.bend_friction is None else model.bend_friction.hessian(x, n)
        return blocks, points, (friction, pair_hessian(model, state, x, settings=s))

    # the membrane's kernel runs while the rest is assembled (they write apart)
    _, (blocks, points, extras) = both(membrane, the_rest, threads=threads_for(n))
    kernels.scatter_hessian(t.bending.data, pattern.bending_slots, blocks,
                            pattern.block_slots, data)
    if points is not None:
        bad = kernels.scatter_points(pattern.indptr, pattern.indices, *points, data)
        if bad >= 0:
            raise ValueError(f"edge point {bad}: its vertices share no triangle")
    n3 = 3 * n
    H = sp.csr_matrix((data, pattern.indices, pattern.indptr), shape=(n3, n3))
    extra = None
    for e in extras:
        if e is not None:
            extra = e if extra is None else extra + e
    if not model.free.all():
        fd = sp.diags(np.repeat(model.free, 3).astype(float))
        H = (fd @ H @ fd + sp.diags(1.0 - fd.diagonal())).tocsr()
        extra = None if extra is None else (fd @ extra @ fd).tocsr()
    return H, extra


def pair_hessian(model: ClothModel, state: ContactState, x, *, settings: SolverSettings):
    """Gauss-Newton Hessian (3n x 3n CSR) [N/m] of the self-repulsion pairs
    (k w w^T n n^T) at solved positions ``x`` (n, 3) [m], or None when no pair pushes."""
    parts = []
    gap = model.self_gap(settings)
    if len(state.pairs):
        v, tri = state.pairs[:, 0], state.pairs[:, 1]
        ids = np.c_[v, model.terms.tris[tri]]
        w = np.c_[np.ones(len(v)), -state.bary]
        d = np.einsum("pc,pc->p", state.pair_normal, np.einsum("pj,pjc->pc", w, x[ids]))
        on = gap - d > 0
        if on.any():
            parts.append((ids[on], w[on], state.pair_normal[on], state.contact_k[v[on]]))
    if len(state.edge_pairs):
        e, f = state.edge_pairs[:, 0], state.edge_pairs[:, 1]
        ids = np.c_[state.near_edges[e], state.near_edges[f]]
        st = state.edge_st
        w = np.c_[1.0 - st[:, 0], st[:, 0], st[:, 1] - 1.0, -st[:, 1]]
        d = np.einsum("pc,pc->p", state.edge_normal, np.einsum("pj,pjc->pc", w, x[ids]))
        on = gap - d > 0
        if on.any():
            parts.append((ids[on], w[on], state.edge_normal[on],
                          state.contact_k[ids[on]].mean(axis=1)))
    return weighted_blocks(parts, model.n) if parts else None


def edge_contact_blocks(model: ClothModel, state: ContactState, x, *,
                        settings: SolverSettings, lookups: ContactLookups | None = None):
    """The edge and face points in body contact at solved positions ``x`` (n, 3) [m], as
    :func:`kernels.scatter_points` adds their Hessian (k w w^T g g^T, g the field's
    gradient): (ids (p, j), w (p, j), g (p, 3), k (p,) [N/m]), or None when no point is in
    contact. ``lookups``: the energy's cache (read only)."""
    s = settings
    pts = edge_points(model, s)
    if not len(pts.ids):
        return None
    p = pts.matrix @ x
    near = (np.arange(len(p)) if lookups is None
            else kernels.unspared(p, lookups.edge_seen, lookups.edge_room))
    d, g = distance(model, p[near])
    hit = d < model.reach(s)
    if not hit.any():
        return None
    on = near[hit]
    k = edge_stiffness(model, state, s)[on]
    _, k_on = kernels.contact_forces(model.reach(s) - d[hit], k, s.contact_onset)
    return (np.ascontiguousarray(pts.ids[on]), np.ascontiguousarray(pts.w[on]),
            np.ascontiguousarray(g[hit]), k_on)


def weighted_blocks(parts, n: int) -> sp.csr_matrix:
    """Sum (3n x 3n CSR) of the rank-one terms k (w (x) v)(w (x) v)^T of ``parts``: tuples
    (ids (p, j) vertices, w (p, j) their weights, v (p, 3) a direction, k (p,) [N/m])."""
    rows, cols, vals = [], [], []
    for ids, w, nrm, k in parts:
        dof = (3 * ids[:, :, None] + np.arange(3)).reshape(len(ids), -1)
        wn = (w[:, :, None] * nrm[:, None, :]).reshape(len(ids), -1)
        rows.append(np.repeat(dof, dof.shape[1], axis=1).ravel())
        cols.append(np.tile(dof, (1, dof.shape[1])).ravel())
        vals.append((k[:, None, None] * wn[:, :, None] * wn[:, None, :]).ravel())
    n3 = 3 * n
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows),
                                                 np.concatenate(cols))), shape=(n3, n3))
