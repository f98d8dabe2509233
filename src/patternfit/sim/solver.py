"""Quasi-static garment solver: the static equilibrium of a sewn garment on a body.

Minimises the total potential energy over the 3D vertex positions (METHOD.md section 5):
membrane + bending + gravity + body contact + lagged friction + lagged self-repulsion +
seam springs. L-BFGS, whose initial Hessian is a prefactored sparse Cholesky (cholespy) of
the constant quadratic part plus a contact-stiffness diagonal (METHOD.md 5.1), makes the
large motions; Newton steps on the PSD-projected Hessian of every term, solved by conjugate
gradients preconditioned by a Cholesky factor of a recent Hessian, finish at a force balance
(METHOD.md 5.2). Units: metres, kilograms, seconds, newtons, joules. See
``docs/simulation.md``.

The parts, as Newton (NVIDIA's physics engine) keeps them apart: the frozen cloth model
(``model.py``), the contact and friction state a solve takes in and hands out
(``state.py``), the pure energy, gradient and Hessian (``total_energy.py``), and the
algorithm: :func:`solve` here, with the outer updates (``outer_updates.py``), the factors and
the Newton step (``preconditioners.py``), L-BFGS (``lbfgs.py``) and the stopping rules
(``stop_rule.py``). :class:`GarmentSolver` holds one model, state and set of factors for the
callers that drape and re-drape one garment.
"""

from __future__ import annotations

import inspect
import time
from collections.abc import Callable
from dataclasses import replace
from typing import NamedTuple

import numpy as np

from ..arguments import array
from ..errors import ctrl_c
from . import kernels, outer_updates, total_energy
from .checks import DrapeChecks, compressed_share, crossings, drape_checks
from .lbfgs import LBFGS
from .model import ClothModel
from .outer_updates import can_stiffen, find_pairs, moved_since_pairs
from .preconditioners import Factors, ensure_factor, newton_direction, precondition, set_base
from .result import DrapeResult
from .settings import SolverSettings
from .state import ContactState
from .stop_rule import at_rest, drift, fell, residual, residual_rms, stalled
from .total_energy import ContactLookups


class Solved(NamedTuple):
    """What :func:`solve` hands back: the result, the model at its end (welded when the seams
    were welded on the way) and the state to pass to the next solve."""

    result: DrapeResult
    model: ClothModel
    state: ContactState


def solve(model: ClothModel, state_in: ContactState, x0, *, settings: SolverSettings,
          factors: Factors, forces=None, resume: bool = False,
          progress: Callable[[int, float, float, float], None] | None = None) -> Solved:
    """Minimise the energy of ``model`` from the start positions ``x0``.

    Parameters
    ----------
    model : ClothModel
    state_in : ContactState
        The state the last solve of this garment handed out (``ContactState()`` before the
        first); not written.
    x0 : (n3, 3) float
        Start positions of the simulated vertices [m] (a previous result's ``x`` for a
        warm start after a pattern edit).
    settings : SolverSettings
    factors : Factors
        The Cholesky factors kept from earlier solves of this garment (updated here).
    forces : (n3, 3) float, optional
        Constant external forces on the simulated vertices [N].
    resume : bool
        ``x0`` is the end of the last solve moved a little (by an edit): its contact
        stiffness is kept, the friction anchors move with their vertices and friction
        holds from the first iteration. (A start equal to the last solve's end is
        resumed anyway.)
    progress : callable, optional
        Called after every iteration as ``progress(iteration, energy [J], step [m],
        elapsed [s])``; one with a parameter named ``residual`` also gets
        ``residual=`` the rms of |F_i| / (m_i g) [-] there (rest: ``settings.residual_rms``),
        how far the drape still is from a force balance. Raising KeyboardInterrupt in it
        stops the solve cleanly.

    Returns
    -------
    Solved
        The result, the model at the end and the state handed out.
    """
    t_start = time.perf_counter()
    s = settings
    state = state_in.copy()
    x_full = array(x0, "x0", shape=(None, 3), contiguous=True)
    if len(x_full) != model.n3:
        raise ValueError(f"x0: expected {model.n3} rows, got {len(x_full)}")
    f_ext = np.zeros((model.n3, 3)) if forces is None else \
        array(forces, "forces", shape=(None, 3), contiguous=True)
    if len(f_ext) != model.n3:
        raise ValueError(f"forces: expected {model.n3} rows, got {len(f_ext)}")
    sewing = not model.welded
    k_seam = s.seam_stiffness
    pull = 1.0
    last_gap = np.inf
    # a solve that follows one which ended with friction on (a warm start) keeps its
    # friction anchors and contact stiffness, and friction acts from the first iteration
    held = state.held
    same = held is not None and np.array_equal(x_full, held)
    warm = not sewing and held is not None and (same or resume)
    force_rule = s.stop == "force"
    delay = s.friction_delay
    friction_from = None if sewing else (0 if warm else delay)
    # L-BFGS steps (cheap, the large motions) until the kinematic rule holds, then (force
    # rule) Newton steps, whose Hessian sees the stiff contact and membrane, to the
    # force balance
    newton_on = False
    lookups = None  # the body distance lookups of this state (set up below)
    report_residual = progress is not None and takes_residual(progress)

    def evaluate(x):
        return total_energy.energy(model, state, x, settings=s, lookups=lookups)

    def set_springs(stiffness, pull=1.0):
        springs = outer_updates.set_springs(model, state, settings=s, stiffness=stiffness,
                                            pull=pull)
        set_base(factors, model, springs, settings=s)

    def outer_refresh(x, friction_on, hold=False, frozen=False):
        diag = outer_updates.refresh(model, state, x, settings=s, friction_on=friction_on,
                                     hold=hold, newton=newton_on, lookups=lookups,
                                     frozen=frozen)
        if not newton_on:
            ensure_factor(factors, model, diag, settings=s)

    def lbfgs_precondition(q):
        return precondition(factors, q)

    def to_newton():
        """Switch from L-BFGS to Newton steps (force rule, seams welded, not yet switched);
        whether it switched."""
        nonlocal newton_on
        if sewing or newton_on or s.stop != "force":
            return False
        newton_on = True
        return True

    def setup(x_red, keep, keep_lagged=False):
        nonlocal lookups
        state.forces = model.mass[:, None] * np.asarray(s.gravity)[None, :]
        np.add.at(state.forces, model.group, f_ext)
        state.forces[~model.free] = 0.0
        if not keep:
            state.contact_scale = np.ones(model.n)
            state.anchor_of = np.full((model.n, 3), np.nan)
        # at the weld the vertices are numbered anew: the stiffness of the old numbering
        # would be read until the next refresh (the energy returned at a stop_at_weld was)
        state.contact_k = outer_updates.contact_k(model, state, s)
        if not keep_lagged:
            state.friction_idx = np.zeros(0, np.int64)
            state.pairs = np.zeros((0, 2), np.int64)
            state.edge_pairs = np.zeros((0, 2), np.int64)
            state.pairs_x = None
        # contact lookups start afresh (the reach may differ from the last solve's)
        lookups = ContactLookups.for_model(model, s)
        set_springs(k_seam)
        return x_red

    # a start at the last solve's rest continues it: its lagged terms stay as they were
    # there (friction anchors, self pairs), so its reported force balance is the one it
    # starts from. Searched afresh, the pairs the Newton phase held (a vertex just off its
    # triangle) were lost and the 1.5K coat on male_heavy moved 4.1 mm over 82 iterations;
    # anchored afresh, the sliding contacts moved it 0.5 mm over 10
    lagged = warm and same and state.at_rest
    x = setup(model.reduce(x_full), keep=warm, keep_lagged=lagged)
    if warm and not same:
        # the anchors move with their vertices: friction keeps the force it held
        state.anchor_of += x - model.reduce(held)
    # a cold start with friction on at once (from a saved or coarser rest) is held by
    # static friction where it stands
    outer_refresh(x, friction_on=friction_from == 0, hold=friction_from == 0 and not warm,
                  frozen=lagged)
    energy, grad = evaluate(x)
    lbfgs = LBFGS(s.history)
    # the work of lifting the garment by 10 cm: the energy scale of a warm start, whose
    # own total drop is tiny
    e_scale = 0.1 * float(np.linalg.norm(state.forces.sum(axis=0)))
    it = 0
    last_refresh = 0
    calm = 0
    total_drop = 0.0
    marks = [(0, x.copy())]  # (iteration, positions): the start, then every half window
    converged = interrupted = False
    reason = "iterations"
    try:
        while True:
            limit = ("iterations" if it >= s.max_iterations else
                     "time" if time.perf_counter() - t_start > s.time_limit else None)
            if limit:
                reason = limit
                # a start at rest is at rest whatever the limit: a restart from a reported
                # rest with no iteration to spare read "no equilibrium" at rms 0.004
                if force_rule and not sewing and at_rest(model, grad, s) \
                        and not can_stiffen(model, state, x, settings=s):
                    converged, reason = True, "converged"
                break
            every = s.newton_refresh if newton_on else s.refresh
            if it - last_refresh >= every or (sewing and calm >= s.patience):
                last_refresh = it
                if fell(model, x):
                    reason = "fell"
                    break
                if sewing:
                    gap = model.seam_gap(x)
                    if gap < s.weld_gap:
                        x_full = x[model.group]
                        model = model.welded_model()
                        factors.follow(model)
                        x = setup(model.reduce(x_full), keep=False)
                        marks = [(it, x.copy())]
                        sewing = False
                        friction_from = it + delay
                        lbfgs.reset()
                        if s.stop_at_weld:
                            energy, grad = evaluate(x)
                            reason = "welded"
                            break
                    else:
                        if k_seam >= s.seam_stiffness_max and gap > 0.95 * last_gap:
                            pull *= s.seam_growth
                        last_gap = gap
                        k_seam = min(k_seam * s.seam_growth, s.seam_stiffness_max)
                        set_springs(k_seam, pull)
                outer_refresh(x, friction_on=friction_from is not None and it >= friction_from)
                energy, grad = evaluate(x)
                calm = 0
            if force_rule and not sewing and at_rest(model, grad, s):
                if can_stiffen(model, state, x, settings=s):
                    last_refresh = it - every  # stiffen the contact and go on
                    continue
                converged, reason = True, "converged"
                break
            g = grad.ravel()
            newton_now = newton_on
            if newton_now:
                d = newton_direction(factors, model, state, x, grad, settings=s,
                                     lookups=lookups)
            else:
                d = lbfgs.direction(g, lbfgs_precondition)
            gd = kernels.dot(g, d)
            if not gd < 0.0 and not newton_now:
                lbfgs.reset()
                d = -lbfgs_precondition(g)
                gd = kernels.dot(g, d)
            if not gd < 0.0:
                if to_newton():
                    continue
                converged, reason = stalled(model, sewing, grad, s)
                break
            # a capped step cannot tunnel through the body, nor follow the unbounded
            # descent of a garment that would fall past it
            longest = kernels.max_row_norm(d.reshape(-1, 3))
            alpha = min(1.0, s.max_step / max(longest, 1e-300))
            accepted = False
            # near rest the energy's rounding (its gravity part is large) hides the drop
            noise = 1e-13 * (abs(energy) + e_scale) if force_rule else 0.0
            for tries in range(30):
                x_new = x + alpha * d.reshape(-1, 3)
                e_new, g_new = evaluate(x_new)
                if e_new <= energy + 1e-4 * alpha * gd + noise:
                    accepted = True
                    break
                alpha *= 0.5
            if accepted and newton_now and tries == 0 \
                    and energy - e_new > -0.5 * s.newton_extend * gd \
                    and residual_rms(model, grad) > s.newton_extend_above * s.residual_rms:
                # a full Newton step taken whole that lowered the energy by more than the
                # model's -g.d / 2 (the drop a CG step predicts): the projected Hessian is
                # stiffer than the energy there (cloth that buckles or slides), so try twice
                # as far while that lowers the energy further; where the model holds (near
                # rest) the full step stands, as an extended one threw the stiff directions
                # off again (15K skirt: rms 0.02 -> 0.4 after a 4x step); near rest it is
                # not tried at all (``newton_extend_above``)
                while 2.0 * alpha * longest <= s.max_step:
                    x_try = x + 2.0 * alpha * d.reshape(-1, 3)
                    e_try, g_try = evaluate(x_try)
                    if not e_try < e_new:
                        break
                    alpha *= 2.0
                    x_new, e_new, g_new = x_try, e_try, g_try
            if not accepted:
                if lbfgs.count and not newton_now:
                    lbfgs.reset()
                    continue
                if to_newton():
                    continue
                converged, reason = stalled(model, sewing, grad, s)
                break
            step_vec = x_new - x
            if not newton_now:
                lbfgs.push(step_vec.ravel(), (g_new - grad).ravel())
            drop = energy - e_new
            total_drop += max(drop, 0.0)
            step = kernels.max_row_norm(step_vec)
            x, energy, grad = x_new, e_new, g_new
            it += 1
            if s.self_collision and moved_since_pairs(model, state, x, settings=s):
                find_pairs(model, state, x, settings=s, newton=newton_on)
                energy, grad = evaluate(x)
            if report_residual:
                progress(it, energy, step, time.perf_counter() - t_start,
                         residual=residual_rms(model, grad))
            elif progress is not None:
                progress(it, energy, step, time.perf_counter() - t_start)
            if it % max(s.window // 2, 1) == 0:
                marks = marks[-2:] + [(it, x.copy())]
            small = step < s.step_tol and drop <= s.energy_tol * max(total_drop, e_scale)
            calm = calm + 1 if small else 0
            if not newton_now and calm >= s.patience and not sewing \
                    and drift(x, it, marks, s.window) <= s.drift_tol:
                if can_stiffen(model, state, x, settings=s):
                    last_refresh = it - s.refresh  # stiffen the contact and go on
                    continue
                if to_newton():
                    last_refresh = it - s.newton_refresh  # refresh for Newton's Hessian
                    continue
                converged, reason = True, "converged"
                break
            if not newton_now and it >= s.newton_after and to_newton():
                last_refresh = it - s.newton_refresh
    except (KeyboardInterrupt, SystemError) as exc:
        if not ctrl_c(exc):
            raise
        interrupted, reason = True, "interrupted"
    x_out = x[model.group]
    # remember the end state when friction was on: a solve from exactly here is warm
    state.x = x_out.copy()
    state.friction_on = bool(friction_from is not None and it >= friction_from
                             and not interrupted)
    seconds = time.perf_counter() - t_start
    checks = drape_checks(model, x_out, settings=s, converged=converged,
                          residual=residual(model, grad))
    # the saved state's "at rest" is the checks' equilibrium: with looser settings the
    # solver's own rule read rms 0.30 as converged, contact.npz said at rest, and fit passed
    state.at_rest = bool(force_rule and checks.equilibrium)
    result = DrapeResult(
        x=x_out, vertex_map=model.group[model.vertex_map], welded=model.welded,
        iterations=it, seconds=seconds, converged=converged, interrupted=interrupted,
        stop_reason=reason, energy=float(energy), checks=checks,
        factorizations=factors.count)
    return Solved(result, model, state)


def takes_residual(progress: Callable) -> bool:
    """Whether the callback ``progress`` has a parameter named ``residual`` (the solver then
    passes the residual rms; a callback written for four values keeps getting four)."""
    try:
        return "residual" in inspect.signature(progress).parameters
    except (TypeError, ValueError):  # a callable without a signature Python can read
        return False


class GarmentSolver:
    """Static equilibrium of a garment from its flat pattern mesh: one cloth model, the state
    of its last solve and its factors, for the callers that drape and re-drape one garment.

    Parameters
    ----------
    rest : (n, 2) float
        Flat rest positions of the pattern mesh [m], each panel in its own frame.
    triangles : (m, 3) int
        Flat triangles (counter-clockwise).
    grain : (m, 2) float
        Warp direction of each triangle in its panel frame (need not be unit).
    fabric : Fabric or str
        The fabric (or a preset name / JSON path for :func:`get_fabric`).
    vertex_map : (n,) int, optional
        Simulated 3D vertex of each flat vertex (welded seam pairs share one). Default: the
        identity. ``n3 = vertex_map.max() + 1``.
    seam_pairs : (k, 2) int, optional
        Simulated-vertex pairs to sew: zero-length springs that stiffen by ``seam_growth``
        every ``refresh`` iterations until every gap is under ``weld_gap``; then the pairs
        are welded (one vertex each) and friction is switched on ``friction_delay``
        iterations later.
    body : DistanceField, optional
        Signed distance field of the body [m]; contact keeps vertices ``fabric.thickness``
        (or ``settings.contact_margin`` when larger) away from it.
    pinned : (p,) int, optional
        Simulated vertices held at their start position.
    settings : SolverSettings, optional
        The settings of the next solve (the drape schedule sets them per phase).

    Attributes
    ----------
    model : ClothModel
    state : ContactState
        Handed out by the last solve.
    factors : Factors
    settings : SolverSettings
    """

    def __init__(self, rest, triangles, grain, fabric, *, vertex_map=None, seam_pairs=None,
                 body=None, pinned=None, settings: SolverSettings | None = None):
        self.model = ClothModel.build(rest, triangles, grain, fabric, vertex_map=vertex_map,
                                      seam_pairs=seam_pairs, body=body, pinned=pinned)
        self.settings = settings or SolverSettings()
        self.state = ContactState()
        self.factors = Factors()

    @property
    def factorizations(self) -> int:
        """Cholesky factorisations done by this solver so far."""
        return self.factors.count

    def _use(self, model: ClothModel) -> None:
        self.model = model
        self.factors.follow(model)

    def set_rest(self, rest) -> None:
        """New rest shapes ``rest`` (n, 2) [m] (same topology), e.g. after a pattern edit;
        then ``solve`` from the previous state. The factorisation is kept while the matrix
        is unchanged. Changed shapes leave the state no longer at rest (its balance was of
        the old ones): a solve from its end updates the lagged terms first, as after any
        edit."""
        if not np.array_equal(np.asarray(rest, dtype=np.float64), self.model.rest):
            self.state = replace(self.state, at_rest=False)
        self._use(self.model.with_rest(rest))

    def weld(self) -> None:
        """Join every seam pair into one vertex now, before a solve whose start state has
        its seams closed already (e.g. a coarser drape carried over to this mesh)."""
        if not self.model.welded:
            self._use(self.model.welded_model())

    def solve(self, x0, *, forces=None, resume: bool = False,
              progress: Callable[[int, float, float, float], None] | None = None
              ) -> DrapeResult:
        """:func:`solve` from ``x0`` (n3, 3) [m] with this solver's model, last state,
        factors and settings; keeps the model and state it hands back."""
        out = solve(self.model, self.state, x0, settings=self.settings, factors=self.factors,
                    forces=forces, resume=resume, progress=progress)
        self._use(out.model)
        self.state = out.state
        return out.result

    def checks(self, x, *, converged: bool = False, residual=None) -> DrapeChecks:
        """:func:`checks.drape_checks` of simulated positions ``x`` (n3, 3) [m] with this
        solver's settings."""
        return drape_checks(self.model, x, settings=self.settings, converged=converged,
                            residual=residual)

    def crossings(self, x) -> int:
        """Crossed triangle pairs at simulated positions ``x`` (n3, 3) [m]
        (:func:`checks.crossings`)."""
        return crossings(self.model, x)

    def compressed_share(self, x, strain: float = 0.01) -> float:
        """Share of the rest area compressed by more than ``strain`` at ``x`` (n3, 3) [m]
        (:func:`checks.compressed_share`)."""
        return compressed_share(self.model, x, strain)
