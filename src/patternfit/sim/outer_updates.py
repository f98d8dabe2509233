"""The outer updates of a solve, every ``SolverSettings.refresh`` iterations (every
``newton_refresh`` in Newton steps): they write the lagged terms of the
:class:`~patternfit.sim.state.ContactState` (SI units: m, N).

- :func:`set_springs`: the seam springs' stiffness and pull while sewing;
- :func:`refresh`: contact stiffness, friction anchors (:func:`anchors`) and self-collision
  pairs (:func:`find_pairs`, :func:`untangle`);
- :func:`moved_since_pairs`, :func:`can_stiffen`: whether the pairs or the contact need an
  update.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from . import kernels
from .crossings import wrong_sides
from .energies import spring_matrix
from .model import ClothModel
from .settings import SolverSettings
from .state import MAX_CONTACT_SCALE, ContactState
from .threads import both, threads_for
from .total_energy import (ContactLookups, contact_base, distance, edge_points, edge_stiffness,
                           energy)


def set_springs(model: ClothModel, state: ContactState, *, settings: SolverSettings,
                stiffness: float, pull: float = 1.0) -> sp.csr_matrix:
    """Seam springs of ``stiffness`` [N/m] (bounded by ``pull`` x ``settings.seam_pull``'s
    contact force) into ``state`` while the seams are open; none once welded. Returns the
    springs' part of the L-BFGS preconditioner (n, n) [N/m]."""
    s = settings
    Q = model.terms.bending
    # the preconditioner leaves bending out: next to the membrane it is small, and its
    # wider stencil doubled the factor's fill (22K coat: 3.1 -> 1.4 ms a solve, and as
    # many iterations or fewer on the three garments)
    Qpre = sp.csr_matrix(Q.shape)
    state.seam_limit = None
    if not model.welded and len(model.seam_pairs):
        pairs = model.group[model.seam_pairs]
        if s.seam_pull > 0:
            # bounded pull (kernels.seam_springs): the preconditioner gets the secant
            # stiffness of a pull over seam_precond_gap at most
            kc = s.contact_stiffness * model.terms.vertex_area
            state.seam_a = np.ascontiguousarray(pairs[:, 0])
            state.seam_b = np.ascontiguousarray(pairs[:, 1])
            state.seam_limit = pull * s.seam_pull * np.minimum(kc[pairs[:, 0]], kc[pairs[:, 1]])
            state.seam_k = float(stiffness)
            k_pre = min(stiffness, float(np.median(state.seam_limit)) / s.seam_precond_gap)
            Qpre = Qpre + spring_matrix(pairs, k_pre, model.n)
        else:
            Qpre = spring_matrix(pairs, stiffness, model.n)
            Q = Q + Qpre
    state.quadratic = Q.tocsr()
    return Qpre.tocsr()


def refresh(model: ClothModel, state: ContactState, x, *, settings: SolverSettings,
            friction_on: bool, hold: bool = False, newton: bool = False,
            lookups: ContactLookups | None = None, frozen: bool = False) -> np.ndarray:
    """Contact stiffness, friction anchors and self-collision pairs of ``state`` at solved
    positions ``x`` (n, 3) [m]. ``hold``: new contacts are anchored so that friction balances
    the tangential force on them (up to the Coulomb limit) instead of where they are (see
    :func:`anchors`); ``newton``: in the Newton phase (:func:`find_pairs`); ``frozen``: the
    lagged terms stay as they are (a solve that continues one at its rest: refreshed there,
    a sliding contact is anchored again and the force balance reported moves). Returns the
    contact diagonal (n,) [N/m] of the L-BFGS preconditioner."""
    s = settings
    n = model.n
    diag = np.zeros(n)
    reach = model.reach(s)
    if not frozen:
        state.friction_idx = np.zeros(0, np.int64)
    if hold and not frozen and s.saved_rest and model.body is not None:
        # the repulsion of the self pairs scales with the contact stiffness: find them first
        if s.self_collision:
            find_pairs(model, state, x, settings=s, newton=newton)
        state.contact_scale = saved_contact_scale(model, state, x, settings=s)
    if model.body is not None:
        d, g = distance(model, x)
        pts = edge_points(model, s)
        d_pts = distance(model, pts.matrix @ x)[0]
        if not frozen:
            # a vertex found inside the body (or deeper than half the contact margin, where
            # the true surface may lie) gets a stiffer contact (x4, up to 4^6), and so do
            # the two of an edge point found there (their points' up to EDGE_CONTACT_SCALE)
            inside = d < model.floor(s)
            inside[pts.ids[d_pts < model.floor(s)].ravel()] = True
            state.contact_scale[inside] = np.minimum(state.contact_scale[inside] * 4.0,
                                                     MAX_CONTACT_SCALE)
        state.contact_k = contact_k(model, state, s)
        near = d < reach + s.contact_band
        diag[near] = s.contact_precond * state.contact_k[near]
        on = d_pts < reach + s.contact_band
        w = pts.w[on]
        k = edge_stiffness(model, state, s)[on]
        np.add.at(diag, pts.ids[on].ravel(), (s.contact_precond * k[:, None] * w * w).ravel())
    else:
        state.contact_k = contact_k(model, state, s)
    if frozen:
        return diag
    if s.self_collision and moved_since_pairs(model, state, x, settings=s):
        find_pairs(model, state, x, settings=s, newton=newton)
    if model.body is not None and friction_on and model.fabric.friction > 0:
        # the Coulomb limit of a vertex is mu times the normal force it carries: its own
        # contact's and its share of its edges' points' (with its own alone, a tight
        # 900-triangle skirt, whose polygon touches the hips at its edges' middles, slid
        # off), and it acts across that force's direction (a vertex 2-5 cm off the feet
        # of too long trousers, held across its own field normal against the push of its
        # edge points on the foot, was re-anchored at every update and never balanced)
        pen = reach - d
        own = pen > 0
        push = np.zeros((n, 3))
        push[own] = kernels.contact_forces(pen[own], state.contact_k[own],
                                           s.contact_onset)[0][:, None] * g[own]
        pen_pts = reach - d_pts
        on = pen_pts > 0
        if on.any():
            f_pts = kernels.contact_forces(pen_pts[on], edge_stiffness(model, state, s)[on],
                                           s.contact_onset)[0]
            g_pts = distance(model, pts.matrix[on] @ x)[1]
            push += pts.matrix[on].T @ (f_pts[:, None] * g_pts)
        normal = np.linalg.norm(push, axis=1)
        idx = np.flatnonzero((normal > 0) & model.free)
        nrm = push[idx] / normal[idx, None]
        state.friction_normal = np.ascontiguousarray(nrm)
        state.friction_limit = model.fabric.friction * normal[idx]
        # the gradient of every other term (friction is off here): what friction holds
        held = energy(model, state, x, settings=s, lookups=lookups)[1][idx] if hold else None
        state.friction_anchor = anchors(state, x, idx, nrm, held, settings=s)
        state.friction_idx = idx
    return diag


def saved_contact_scale(model: ClothModel, state: ContactState, x, *,
                        settings: SolverSettings) -> np.ndarray:
    """Contact stiffness scales (n,) [-] that balance the saved rest ``x`` (n, 3) [m]: for each
    vertex the power of 4 (1 ... ``MAX_CONTACT_SCALE``, the values the stiffening gives) whose
    contact force leaves the least force on it, friction off (it acts along the surface,
    the contact across it); 1 where no scale changes that force (out of contact).

    A saved drape keeps positions, not the stiffness its contacts grew to: read back at 1,
    the 3K coat on male_heavy started from its rest with a residual rms of 1,597 (17
    contacts had been stiffened, one x16) and moved 1.4 mm over 132 iterations."""
    s = settings
    saved = state.contact_scale
    best = np.ones(model.n)
    least = None
    try:
        for j in range(int(round(np.log(MAX_CONTACT_SCALE) / np.log(4.0))) + 1):
            state.contact_scale = np.full(model.n, 4.0 ** j)
            state.contact_k = contact_k(model, state, s)
            grad = energy(model, state, x, settings=s)[1]
            left = np.einsum("ij,ij->i", grad, grad)
            if least is None:
                least = left
                continue
            # strictly less, by more than rounding: out of contact every scale leaves the same
            better = left < least * (1.0 - 1e-9)
            best[better] = 4.0 ** j
            least = np.minimum(least, left)
    finally:
        state.contact_scale = saved
    return best


def contact_k(model: ClothModel, state: ContactState, settings: SolverSettings) -> np.ndarray:
    """Contact stiffness (n,) [N/m] of every vertex: pressure stiffness x vertex area x the
    state's scale."""
    return contact_base(model, settings) * state.contact_scale


def anchors(state: ContactState, x, idx, normal, grad=None, *,
            settings: SolverSettings) -> np.ndarray:
    """Friction anchors (k, 3) [m] of the contact vertices ``idx`` (k,) at solved positions
    ``x`` (n, 3) [m], the body's unit normals there ``normal`` (k, 3); they are also written
    to ``state.anchor_of`` (NaN elsewhere). Needs ``state.friction_limit`` of ``idx``.

    A vertex that sticks (tangential offset from its anchor below the slip distance) keeps
    its anchor, so static friction holds instead of creeping one slip distance per update;
    one that slides is re-anchored a slip distance behind, at the Coulomb limit; a new
    contact is anchored where it is, or, given ``grad`` (k, 3) [N] (the gradient of the other
    terms at those vertices), where friction balances its tangential part up to the Coulomb
    limit (a start taken from a saved rest: static friction held it there, and anchored in
    place it would first have to slip to carry that force; the 1.5K skirt restarted from its
    rest moved 5.4 mm).
    """
    slip = settings.friction_slip
    held = state.anchor_of[idx]
    new = x[idx].copy()
    if grad is not None:
        # friction cancels the tangential gradient g_t at the offset -g_t / |g_t| times
        # the offset where its force is |g_t| (kernels.friction_offset: at most slip)
        gt = grad - np.einsum("ij,ij->i", grad, normal)[:, None] * normal
        g = np.linalg.norm(gt, axis=1)
        m = kernels.friction_offset(g, state.friction_limit, slip)
        new += (m / np.maximum(g, 1e-300))[:, None] * gt
    has = ~np.isnan(held[:, 0])
    u = x[idx] - held
    u -= np.einsum("ij,ij->i", u, normal)[:, None] * normal
    m = np.linalg.norm(u, axis=1)
    stick = has & (m <= slip)
    new[stick] = held[stick]
    slide = has & (m > slip)
    new[slide] = x[idx][slide] - slip * u[slide] / m[slide, None]
    state.anchor_of[:] = np.nan
    state.anchor_of[idx] = new
    return np.ascontiguousarray(new)


def find_pairs(model: ClothModel, state: ContactState, x, *, settings: SolverSettings,
               newton: bool = False):
    """Vertex-triangle and edge-edge pairs of ``state`` within the detection radius at solved
    positions ``x`` (n, 3) [m] (lagged self-collision); ``newton``: in the Newton phase,
    where the last search's pairs that this one lost are kept (:func:`hold_pairs`)."""
    if not settings.self_collision:
        return
    detect = model.detect(settings)
    held = (state.pairs, state.bary, state.pair_normal) if newton and len(state.pairs) \
        else None
    tris = model.terms.tris
    # grid cells of the search radius for the vertices (a 20K mesh: 9.6 ms, 11.9 at
    # twice that), twice the radius for the edges' boxes; the crossings that untangling
    # needs are searched at the same time (as long again)
    crossings = model.welded and settings.untangle
    crossed, (state.pairs, state.bary, state.pair_normal) = both(
        lambda: kernels.crossed_pairs(x, tris, model.terms.edge_length, model.root)
        if crossings else None,
        lambda: kernels.near_pairs(x, tris, detect, detect, model.root),
        threads=threads_for(model.n))
    if held is not None:
        hold_pairs(model, state, x, *held, detect=detect)
    # edges cross each other only where two sheets are near: search the edges of the
    # vertex-triangle pairs' vertices and triangles (a tenth of the 20K trousers' edges)
    near = np.zeros(model.n, bool)
    near[state.pairs[:, 0]] = True
    near[tris[state.pairs[:, 1]]] = True
    state.near_edges = np.ascontiguousarray(model.edges[near[model.edges].any(axis=1)])
    state.edge_pairs, state.edge_st, state.edge_normal = kernels.near_edge_pairs(
        x, state.near_edges, detect, 2 * detect, model.root)
    state.pairs_x = x.copy()
    if crossings:
        untangle(model, state, x, crossed)


def hold_pairs(model: ClothModel, state: ContactState, x, pairs, bary, normal, *,
               detect: float):
    """Keep the vertex-triangle pairs of the last search (``pairs`` (p, 2) int, ``bary``
    (p, 3), ``normal`` (p, 3)) whose vertex the new search paired with nothing while it is
    still within the detection radius ``detect`` [m] on its side of the pair's normal
    (Newton phase). A vertex pressed between a fold and the body had its pair found at one
    search and lost at the next (its projection just off the triangle): its repulsion came
    and went, a residual of 29,000 x its weight at each return (22K coat, hem re-drape: 8
    returns, each settled in 5-10 Newton steps)."""
    ids = np.c_[pairs[:, 0], model.terms.tris[pairs[:, 1]]]
    w = np.c_[np.ones(len(pairs)), -bary]
    d = np.einsum("pc,pc->p", normal, np.einsum("pj,pjc->pc", w, x[ids]))
    paired = np.zeros(model.n, bool)
    paired[state.pairs[:, 0]] = True
    # (not one whose vertex has passed to the other side: untangling turns those)
    keep = ~paired[pairs[:, 0]] & (d > 0.0) & (d < detect)
    if keep.any():
        state.pairs = np.ascontiguousarray(np.r_[state.pairs, pairs[keep]])
        state.bary = np.ascontiguousarray(np.r_[state.bary, bary[keep]])
        state.pair_normal = np.ascontiguousarray(np.r_[state.pair_normal, normal[keep]])


def untangle(model: ClothModel, state: ContactState, x, crossed):
    """Turn the self-collision pairs of ``state`` towards undoing the crossings ``crossed``
    (``kernels.crossed_pairs``: (c, 2) triangle pairs) at solved positions ``x`` (n, 3)
    [m]: each vertex that passed through a triangle
    (``crossings.wrong_sides``) gets a pair with that triangle whose normal points back to
    the side it came from (replacing the pair the search made, which would hold it where it
    is), and the edge pairs around a crossing, which would hold it too, are dropped until it
    is undone."""
    tris = model.terms.tris
    if not len(crossed):
        return
    vt, bary, normal = wrong_sides(x, tris, crossed)
    _, first = np.unique(vt[:, 0] * len(tris) + vt[:, 1], return_index=True)
    vt, bary, normal = vt[first], bary[first], normal[first]
    keep = ~np.isin(state.pairs[:, 0] * len(tris) + state.pairs[:, 1],
                    vt[:, 0] * len(tris) + vt[:, 1])
    state.pairs = np.ascontiguousarray(np.r_[state.pairs[keep], vt])
    state.bary = np.ascontiguousarray(np.r_[state.bary[keep], bary])
    state.pair_normal = np.ascontiguousarray(np.r_[state.pair_normal[keep], normal])
    near = np.zeros(model.n, bool)
    near[tris[crossed].ravel()] = True
    ok = ~near[state.near_edges[state.edge_pairs].reshape(len(state.edge_pairs), 4)].any(axis=1)
    state.edge_pairs = np.ascontiguousarray(state.edge_pairs[ok])
    state.edge_st = np.ascontiguousarray(state.edge_st[ok])
    state.edge_normal = np.ascontiguousarray(state.edge_normal[ok])


def moved_since_pairs(model: ClothModel, state: ContactState, x, *,
                      settings: SolverSettings) -> bool:
    """Whether two vertices may have closed half the detection margin since the pair search
    (solved positions ``x`` (n, 3) [m]); True before the first search (a garment of one
    panel sewn to nothing starts its solve without one)."""
    if state.pairs_x is None:
        return True
    margin = model.detect(settings) - model.self_gap(settings)
    return kernels.max_relative_move(x, state.pairs_x) > 0.25 * margin


def can_stiffen(model: ClothModel, state: ContactState, x, *,
                settings: SolverSettings) -> bool:
    """Whether a vertex is inside the body (or deeper than half the contact margin) at solved
    positions ``x`` (n, 3) [m] with its contact stiffness not yet at the cap."""
    if model.body is None:
        return False
    d, _ = distance(model, x)
    return bool(((d < model.floor(settings))
                 & (state.contact_scale < MAX_CONTACT_SCALE)).any())
