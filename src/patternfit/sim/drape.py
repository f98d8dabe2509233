"""The drape stage: place the garment mesh around the body, sew and solve for rest.

Takes the flat :class:`GarmentMesh`, a body and a fabric; returns the 3D state of every flat
vertex (both copies of a sewn pair end at the same point), the checks and the timing.
"""

from __future__ import annotations

import json
import time
import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from ..constants import tol
from ..defaults import DEFAULTS
from ..mesh.garment import GarmentMesh
from ..mesh.transfer import transfer
from ..mesh.triangulate import mesh_pattern
from ..pattern.model import Pattern
from . import total_energy
from .checks import crossing_reasons, crossings, inside_reason, seam_gap_reason, through_body
from .fabrics import Fabric, get_fabric
from .gathers import GatherWarning, oblique_gathers
from .onbody import (ON_BODY, OnBodyChecks, OnBodySettings, anchor_line, floor_checked,
                     on_body_checks, on_the_floor)
from .placement import MAX_CLEARANCE, place_on_body
from .provenance import DRAPE_REASONS, not_draped_for, saved_provenance
from .schedule import Plan, PlanRun, run_plan
from .result import DrapeResult
from .settings import SolverSettings
from .solver import GarmentSolver
from .state import ContactState, SavedStateError
from .stop_rule import cone_residual

#: least distance kept from the body by default [m] (see ``drape``'s ``contact_margin``)
CONTACT_MARGIN = 0.003

#: extra clearance [m] of the placements a garment is sewn from again, in turn, when its
#: sewn state crosses itself or lies through the body. Where the seams close through the
#: body or the cloth depends on the start more than on the mesh: the built-in shirt's
#: sleeves, rolled down the arm to clear the torso's cloth, close their cuffs over the
#: hands' mittens, and from 3 cm 5 of 9 sewn states of the shirt at 1.5-2.5K on three male
#: bodies had crossed pairs or edges through the body, 3 of 6 at 3.5K on six bodies; of 9
#: such states, 7 were clean when sewn from 4.5 or 6 cm (docs/simulation.md)
RESEW_CLEARANCES = (0.015, 0.03)


@dataclass(eq=False)
class Drape:
    """A draped garment.

    Attributes
    ----------
    positions : (n, 3) float
        3D position of every flat vertex [m].
    placed : (n, 3) float
        The isometric placement the solve started from [m].
    result : DrapeResult
        The solver's result (simulated vertices, checks, iterations, seconds).
    solver : GarmentSolver
        Kept for a warm re-drape after an edit (:func:`redrape`).
    seconds : float
        Wall time of placement and solve [s].
    onbody : OnBodyChecks or None
        Whether the garment rests on the body where its pattern says
        (:func:`patternfit.sim.onbody.on_body_checks`); every drape of :func:`drape` and
        :func:`redrape` carries it (another engine's drape gets it from
        :meth:`check_on_body`).
    pattern, body
        What :meth:`check_on_body` checked against (kept for a re-drape's check).
    """

    positions: np.ndarray
    placed: np.ndarray
    result: DrapeResult
    solver: GarmentSolver
    seconds: float
    timing: dict = field(default_factory=dict)
    onbody: OnBodyChecks | None = None
    pattern: Pattern | None = None
    body: object = None

    @property
    def checks(self):
        """The solver's checks (:class:`DrapeChecks`); :attr:`passed` adds the on-body ones."""
        return self.result.checks

    def check_on_body(self, pattern: Pattern, mesh: GarmentMesh, body,
                      fabric: Fabric | str | None = None) -> OnBodyChecks:
        """Run the on-body checks of this drape of ``mesh`` (made from ``pattern``) on
        ``body``, keep them in :attr:`onbody` and return them. A drape that passed them
        resting on the floor is continued without it in ``fabric`` (None: its solver's),
        :func:`without_floor`, and fails when its top then slides away from its anchor."""
        self.pattern, self.body = pattern, body
        self.onbody = on_body_checks(pattern, mesh, body, self.positions)
        if fabric is None:
            fabric = getattr(getattr(self.solver, "model", None), "fabric", None)
        if fabric is not None and on_the_floor(self.onbody):
            t = time.perf_counter()
            self.onbody = without_floor(pattern, mesh, body, fabric, self.positions,
                                        self.onbody)
            self.timing["without_floor_seconds"] = time.perf_counter() - t
        return self.onbody

    def saved_contact(self, mesh: GarmentMesh | None = None) -> dict[str, np.ndarray] | None:
        """The contact state at :attr:`positions` to save beside them
        (:meth:`ContactState.saved_arrays`, ``save_garment(contact=...)``), with what it is
        a state of (:func:`provenance.saved_provenance`: the positions', the drape's
        ``mesh``'s, the body's and the fabric's digests, the fabric), the residual's rms and
        p99 when known and why it failed its checks (:attr:`reasons`), or None when the solver did not end at them (another engine's
        drape); one that ended before the seams were welded keeps no solver arrays."""
        held = self.solver.state.x
        if held is None or held.shape != self.positions.shape \
                or not np.array_equal(held, self.positions):
            return None
        c = self.result.checks
        residual = {} if c.residual_rms is None else {
            "residual_rms": np.asarray(c.residual_rms), "residual_p99": np.asarray(c.residual_p99)}
        # stopped while sewing, its solver arrays are the unwelded model's: a drape
        # continued from them (which welds at once) refused them ("expected shape (770),
        # got (840,)"); what it says of itself (not at rest, why) is kept
        state = self.solver.state.saved_arrays() if self.solver.model.welded \
            else {"at_rest": np.asarray(False)}
        return {**state, **residual,
                **saved_provenance(self.positions, mesh, self.body, self.solver.model.fabric),
                DRAPE_REASONS: np.array(json.dumps(self.reasons))}

    @property
    def reasons(self) -> list[str]:
        """Why the drape failed, in words (on-body reasons first); empty when it passed."""
        out = list(self.onbody.reasons) if self.onbody is not None else []
        return out + solver_reasons(self.result.checks, self.result.stop_reason,
                                    getattr(self.solver, "settings", None))

    @property
    def passed(self) -> bool:
        """The one verdict of a drape: the solver's checks passed and the garment rests on
        the body where its pattern says (on-body checks not yet run count as passed)."""
        return bool(self.result.checks.passed
                    and (self.onbody is None or self.onbody.passed))

    def report_extra(self) -> dict:
        """``checks`` and ``timing`` entries for ``report.json``: the solver's checks, the
        on-body checks, ``solver_passed``, ``passed`` (both) and ``reasons`` (why not, in
        words)."""
        r = self.result
        onbody = self.onbody.to_dict() if self.onbody is not None else {}
        return {"checks": {**r.checks.to_dict(), **onbody, "solver_passed": r.checks.passed,
                           "passed": self.passed, "reasons": self.reasons,
                           "stop_reason": r.stop_reason},
                "timing": {"seconds": self.seconds,
                           "iterations": r.iterations + self.timing.get("sewing_iterations", 0)
                           + self.timing.get("coarse_iterations", 0),
                           "engine": "static", **self.timing}}


def solver_reasons(checks, stop_reason: str | None = None,
                   settings: SolverSettings | None = None) -> list[str]:
    """The solver's failed checks (:class:`DrapeChecks`) in words; empty when they passed.
    An equilibrium not reached says how far its residual is from ``settings``' rest (the
    defaults when None)."""
    rest = settings if isinstance(settings, SolverSettings) else SolverSettings()
    if checks.passed:
        return []
    out = [inside_reason(checks.inside_vertices, checks.max_depth_mm),
           seam_gap_reason(checks.seam_gap_max_mm),
           *crossing_reasons(checks.edges_in_body, checks.faces_in_body,
                             checks.self_intersections)]
    if not checks.equilibrium:
        said = [f"stopped: {stop_reason}"] if stop_reason else []
        if checks.residual_rms is not None and checks.residual_p99 is not None:
            # how far from a balance, not only that it is not one
            said.append(f"residual rms {checks.residual_rms:.3g}, p99 "
                        f"{checks.residual_p99:.3g} of a vertex's weight; at rest at most "
                        f"{min(rest.residual_rms, tol.rest_rms):g} and "
                        f"{min(rest.residual_p99, tol.rest_p99):g}")
        out.append("no equilibrium" + (f" ({'; '.join(said)})" if said else ""))
    return [r for r in out if r] or ["the solver's checks failed"]


def _grain_per_triangle(mesh: GarmentMesh) -> np.ndarray:
    return mesh.grain[mesh.triangle_panel]


def drape(pattern: Pattern, mesh: GarmentMesh, body, fabric: Fabric | str = DEFAULTS.fabric, *,
          settings: SolverSettings | None = None, clearance: float = DEFAULTS.clearance,
          spacing: float = 0.005,
          placed=None, start=None, start_contact=None, start_rest=None,
          sewing_iterations: int = 1500,
          relax_iterations: int = 300,
          contact_margin: float = CONTACT_MARGIN, sewing_self_collision: bool = False,
          coarse: int | None = 2000, progress=None) -> Drape:
    """Place, sew and drape ``mesh`` on ``body`` to static equilibrium.

    The solves follow :meth:`patternfit.sim.schedule.Plan.first_drape` (sew, relax, drape;
    ``timing["phases"]`` names those that ran), or :meth:`~patternfit.sim.schedule.Plan.settle`
    from ``start`` or a coarse drape.

    The sewn and relaxed state is checked before the drape under gravity: one that crosses
    itself or has cloth through the body (no repulsion undoes such a tangle) is sewn again
    from a placement ``RESEW_CLEARANCES`` farther out (1.5 cm, then 3 cm), and the first
    clean one, or else the one with the fewest faults, is draped (a garment at its file's
    own 3D placement, which no clearance moves, or a given ``placed``, is sewn once). When
    every sewing closed its seams with faults, each placement is sewn again with
    self-collision on (``timing["sewing_self_collision"]`` when that one is draped).
    ``timing["sewing_attempts"]`` counts the sewings and ``timing["sewing_clearance"]`` [m]
    is the placement's clearance when it is not ``clearance``.

    Parameters
    ----------
    pattern : Pattern
        The pattern ``mesh`` was made from (panel parts and sides drive the placement).
    mesh : GarmentMesh
    body : patternfit.body.Body
    fabric : Fabric or str
        A fabric or a preset name / JSON path.
    settings : SolverSettings, optional
    clearance : float
        Gap between body and panels at placement [m].
    spacing : float
        Grid step of the body's distance field [m].
    placed : (n, 3) float, optional
        A start state instead of the automatic placement (e.g. an imported 3D placement),
        sewn and relaxed like a placement (once: it is not placed again).
    start : (n, 3) float, optional
        A sewn state of ``mesh`` to continue from (a saved drape's ``positions.npy``): the
        seams are welded at once and the drape under gravity starts there, with friction
        on from the first iteration; no placement, sewing, relaxation or coarse stage.
        ``timing["start"]`` is then ``"saved"``. Without ``start_contact`` the stiffness
        each contact had grown to is read back from the force balance
        (``SolverSettings.saved_rest``).
    start_contact : mapping of str to array, optional
        The contact state saved with ``start`` (``contact.npz``:
        :meth:`~patternfit.sim.state.ContactState.saved_arrays` of the drape that ended
        there): the solve continues that drape, so from its rest it stops at once and
        moves nothing; one saved on another body or in another fabric (its digests,
        :func:`~patternfit.sim.provenance.not_draped_for`) is not taken for a rest here: its
        lagged terms (friction limits and anchors, self pairs) are updated first.
        :class:`~patternfit.sim.state.SavedStateError` when it does not fit ``mesh``.
    start_rest : (n, 2) float, optional
        The flat rest shapes [m] at which ``start`` rests when they are not ``mesh``'s own:
        a drape of the pattern before an edit carried over to the re-meshed edited one
        (:meth:`patternfit.loop.DesignSession.apply_pattern`). The drape then reaches
        ``mesh.vertices`` from them in stages, as a re-drape does
        (:meth:`~patternfit.sim.schedule.Plan.staged`); ``timing["start"]`` is
        ``"carried"``. A carried start that crosses itself (new triangles across the old
        drape's folds: no repulsion undoes a crossing once made) or lies through the body
        deeper than ``CARRIED_DEPTH_MM`` is dropped for a cold drape,
        ``timing["carried_faults"]`` saying how many faults it had.
    sewing_iterations : int
        Iteration limit of the sewing phase (no gravity), which ends once the seams are
        closed and welded.
    relax_iterations : int
        Iteration limit of the gravity-free relaxation of the sewn garment that follows;
        then the drape under gravity.
    sewing_self_collision : bool
        Self-collision while the seams close (it is on in the relaxation and the drape).
        Off by default: the pair search ran nearly every iteration while the panels moved
        (the 22K coat sewed in 42 s with it, 8 s without) and the checks after the drape
        found no more crossings without it (coat and skirt 0, trousers fewer). When the
        seams do not close without it, the garment is sewn again from the placement with
        it (``timing["sewing_retried"]`` says so).
    contact_margin : float
        Least distance kept from the body [m] (the fabric's thickness if larger): the
        trilinear distance field departs from the true surface by up to about half a grid
        step, so a margin of that size keeps the cloth off the real body mesh (sets
        ``settings.contact_margin``; see :class:`SolverSettings`).
    coarse : int or None
        A mesh of more than three times this many triangles is first draped whole (placed,
        sewn, relaxed and draped) as a mesh of about this many triangles of the same
        pattern; that equilibrium, carried to ``mesh`` through the flat panels
        (:func:`patternfit.mesh.transfer.transfer`), starts the drape of ``mesh`` with its
        seams welded. Sewing and the large motions run at the coarse size, where an
        iteration is ten times cheaper, and the fine solve only settles the detail (the
        15K skirt: 8.6 s instead of 25 s, the same ϖ). None: always drape directly.
    progress : callable, optional
        ``progress(iteration, energy [J], step [m], elapsed [s])``, with ``residual=`` the
        residual rms [-] when it has a parameter of that name; raising KeyboardInterrupt in
        it stops cleanly with the last state.
    """
    t0 = time.perf_counter()
    fabric = get_fabric(fabric)
    t = time.perf_counter()
    field_ = body.contact_field(spacing)
    t_sdf = time.perf_counter() - t
    faults = 0
    if start_contact is not None and start_contact.get("at_rest") is not None \
            and not_draped_for(start_contact, body, fabric):
        # a rest on another body or in another fabric is no rest here: its friction limits
        # and anchors are updated before the first step (kept frozen as a continuation, a
        # skirt held by cotton's friction "rested" in a frictionless fabric, rms 3.9 there)
        start_contact = {**start_contact, "at_rest": np.asarray(False)}
    if start is not None:
        d = _drape_from(mesh, fabric, field_, np.asanyarray(start, dtype=np.float64),
                        replace(settings or SolverSettings(), contact_margin=contact_margin),
                        progress, start_contact, start_rest)
        if isinstance(d, Drape):
            d.seconds = time.perf_counter() - t0
            d.timing["distance_field_seconds"] = t_sdf
            d.check_on_body(pattern, mesh, body)
            return d
        faults = d
    for seam, angle in oblique_gathers(mesh):
        warnings.warn(GatherWarning(
            f"seam '{seam}' is gathered at about {angle:g} degrees to the grain: there the "
            "gathers free the cloth across the seam as well, so the drape near it is loose "
            "(a skirt gathered on the bias slid off; docs/simulation.md, 'Gathers finer than "
            "the mesh')"), stacklevel=2)
    x0 = place_on_body(pattern, mesh, body, clearance=clearance) if placed is None \
        else np.asanyarray(placed, dtype=np.float64)
    settings = replace(settings or SolverSettings(), contact_margin=contact_margin)
    options = dict(settings=settings, clearance=clearance, spacing=spacing,
                   sewing_iterations=sewing_iterations, relax_iterations=relax_iterations,
                   contact_margin=contact_margin, sewing_self_collision=sewing_self_collision)
    if coarse and mesh.n_triangles > 3 * coarse:
        d = _coarse_to_fine(pattern, mesh, body, fabric, field_, x0, coarse, options,
                            t0, t_sdf, progress)
        d.check_on_body(pattern, mesh, body)
        if faults:
            d.timing["carried_faults"] = faults
        return d
    timing = {"distance_field_seconds": t_sdf, "sewing_seconds": 0.0, "sewing_iterations": 0}
    if faults:
        timing["carried_faults"] = faults
    gaps = (None,) if placed is not None else \
        tuple(dict.fromkeys(min(clearance + extra, MAX_CLEARANCE)
                            for extra in (0.0,) + RESEW_CLEARANCES))
    # when every sewing closed its seams but crossed itself or the body, each placement is
    # sewn again with the cloth kept apart while it sews (the trousers XL on female_thin at
    # 3K, whose too-long hems start on the floor: 6 crossed pairs at best without, clean
    # with it from 4.5 cm); not sooner: the shirt at 3.5-4K on the six bodies, so sewn from
    # the second try on, passed 8 of 12 against 10 of 12. (Seams that do not close are
    # sewn again with it at once, ``_sew``.)
    kept_apart = {**options, "sewing_self_collision": True}
    best, attempt, sewn = None, 0, []
    for gap, sewing in [(gap, options) for gap in gaps] + [(gap, kept_apart) for gap in gaps]:
        if sewing is kept_apart and (options["sewing_self_collision"] or best[0][0]):
            break  # kept apart already, or nothing welded (``_sew`` tried it)
        if attempt and gap is not None:
            x0 = place_on_body(pattern, mesh, body, clearance=gap)
        if any(np.array_equal(x0, x) and sewing is o for x, o in sewn):
            continue  # the file's own 3D placement, which no clearance moves
        attempt += 1
        sewn.append((x0, sewing))
        solver, run = _sew(mesh, fabric, field_, x0, settings, sewing, timing, progress)
        if run.result.interrupted:
            best = (None, solver, run, x0, gap, sewing)
            break
        tangles = _start_faults(solver, run.result.x) if run.result.welded else None
        rank = (tangles is None, tangles or 0)  # welded first, then the fewest faults
        if best is None or rank < best[0]:
            best = (rank, solver, run, x0, gap, sewing)
        if tangles == 0:
            break
    _, solver, run, x0, gap, sewing = best
    timing["sewing_attempts"] = attempt
    if gap is not None and gap != clearance:
        timing["sewing_clearance"] = gap
    if sewing is not options:
        timing["sewing_self_collision"] = True
    result = run.result
    if result.welded and not result.interrupted:
        settled = run_plan(solver, Plan.draping(), result.x, progress=progress)
        run.phases.extend(settled.phases)
        result = settled.result
    timing["phases"] = [p.name for p in run.phases]
    d = Drape(positions=result.x[solver.model.vertex_map], placed=x0, result=result, solver=solver,
              seconds=time.perf_counter() - t0, timing=timing)
    d.check_on_body(pattern, mesh, body)
    return d


def _sew(mesh: GarmentMesh, fabric: Fabric, field_, x0: np.ndarray, settings, options,
         timing: dict, progress) -> tuple[GarmentSolver, PlanRun]:
    """Sew ``mesh`` from the placement ``x0`` (n, 3) [m] and relax it without gravity
    (:meth:`Plan.sewing`): a new solver and its run; the sewing's seconds and iterations are
    added to ``timing``."""
    for self_collision in (options["sewing_self_collision"], True):
        solver = GarmentSolver(mesh.vertices, mesh.triangles, _grain_per_triangle(mesh),
                               fabric, seam_pairs=mesh.seam_pairs, body=field_,
                               settings=settings)
        plan = Plan.sewing(sewing_iterations=options["sewing_iterations"],
                           relax_iterations=options["relax_iterations"],
                           sewing_self_collision=self_collision)
        run = run_plan(solver, plan, x0, progress=progress)
        timing["sewing_seconds"] += run.seconds("sewing", "relaxing")
        timing["sewing_iterations"] += run.iterations("sewing", "relaxing")
        if run.result.welded or run.result.interrupted or self_collision:
            break
        # the seams did not close: panels pulled round the body caught on it and folded
        # through each other where nothing kept them apart (the 2K GarmentCode shirt on
        # male_average: 1,500 iterations unwelded, 58 crossed pairs); sewn again from the
        # placement with self-collision, it welds in 750 and rests with none
        timing["sewing_retried"] = "seams not closed without self-collision"
    return solver, run


def _drape_from(mesh: GarmentMesh, fabric: Fabric, field_, x: np.ndarray, settings,
                progress, contact=None, rest=None) -> Drape | int:
    """Drape under gravity from a sewn state ``x`` (n, 3) [m] of ``mesh``, seams welded, with
    the contact state saved there (``contact``, :meth:`ContactState.saved_arrays`) when
    given; ``x`` rests at the flat shapes ``rest`` (n, 2) [m] when given, and the drape
    reaches ``mesh``'s own from them in stages; or, when such an ``x`` crosses itself or
    lies through the body deeper than ``CARRIED_DEPTH_MM``, nothing is draped and the count
    of those faults is returned."""
    if x.shape != (mesh.n_vertices, 3) or not np.isfinite(x).all():
        raise ValueError(f"start: expected finite ({mesh.n_vertices}, 3) positions, "
                         f"got {x.shape}")
    if rest is not None:
        rest = np.asanyarray(rest, dtype=np.float64)
        if rest.shape != (mesh.n_vertices, 2) or not np.isfinite(rest).all():
            raise ValueError(f"start_rest: expected finite ({mesh.n_vertices}, 2) flat "
                             f"positions [m], got {rest.shape}")
    solver = GarmentSolver(mesh.vertices if rest is None else rest, mesh.triangles,
                           _grain_per_triangle(mesh), fabric, seam_pairs=mesh.seam_pairs,
                           body=field_, settings=replace(settings, friction_delay=0))
    solver.weld()
    if contact is not None:
        solver.state = ContactState.from_saved(contact, n=solver.model.n,
                                               n_triangles=len(solver.model.terms.tris), x=x)
    if rest is None:
        result = run_plan(solver, Plan.settle(saved=True), x, progress=progress).result
    else:
        faults = _start_faults(solver, x, depth=CARRIED_DEPTH_MM * 1e-3)
        if faults:
            return faults
        change = float(np.linalg.norm(mesh.vertices - rest, axis=1).max(initial=0.0))
        result = run_plan(solver, Plan.staged(change, saved=True), x, rest=mesh.vertices,
                          progress=progress).result
    return Drape(positions=result.x[solver.model.vertex_map], placed=x, result=result, solver=solver,
                 seconds=0.0, timing={"start": "saved" if rest is None else "carried"})


def _saved_solver(mesh: GarmentMesh, body, fabric: Fabric, positions, *, spacing: float,
                  contact_margin: float = CONTACT_MARGIN, floor: bool = True,
                  max_iterations: int = 0) -> tuple[np.ndarray, GarmentSolver]:
    """The finite positions (n, 3) [m] of a saved 3D state of ``mesh`` and a solver of it
    on ``body`` (and the floor under it, unless ``floor`` is False) in ``fabric``, its seams
    welded as its drape's were, not run; each of its solves runs ``max_iterations`` at
    most."""
    x = np.asanyarray(positions, dtype=np.float64)
    if x.shape != (mesh.n_vertices, 3) or not np.isfinite(x).all():
        raise ValueError(f"positions: expected finite ({mesh.n_vertices}, 3) positions, "
                         f"got {x.shape}")
    settings = SolverSettings(max_iterations=max_iterations, contact_margin=contact_margin,
                              friction_delay=0)
    field_ = body.contact_field(spacing) if floor else body.distance_field(spacing)
    solver = GarmentSolver(mesh.vertices, mesh.triangles, _grain_per_triangle(mesh),
                           get_fabric(fabric), seam_pairs=mesh.seam_pairs, body=field_,
                           settings=settings)
    solver.weld()
    return x, solver


def without_floor(pattern: Pattern, mesh: GarmentMesh, body, fabric: Fabric | str, positions,
                  onbody: OnBodyChecks, *, settings: OnBodySettings = ON_BODY,
                  spacing: float = 0.005, contact_margin: float = CONTACT_MARGIN
                  ) -> OnBodyChecks:
    """``onbody`` (the on-body checks of ``positions`` (n, 3) [m], a rest of ``mesh`` on
    ``body`` in ``fabric`` whose cloth touches the floor) with what the garment does once
    the floor is taken away (:func:`~patternfit.sim.onbody.floor_checked`).

    A garment hung from the waist or neck must stay there without the floor: the solve is
    continued from ``positions`` against the body's own distance field
    (``body.distance_field``, not ``contact_field``), ``settings.floor_chunk`` iterations at
    a time, to at most ``settings.floor_iterations``; it ends at rest, when the anchor line
    (:func:`~patternfit.sim.onbody.anchor_line`) leaves ``anchor_tolerance`` of the
    landmark, or when a chunk moved it by less than ``floor_held`` [m]. Where the body
    carries it, its hem drops a few mm and it comes to rest (the built-in trousers on the
    women: at most 1.6 cm, within 150 iterations); where the floor carried it, it slides
    down (trousers 1.5 times too wide on female_average: past 10 cm below the waist in 150
    iterations, still sliding; 12.7 cm once at rest). Contact stiffness is read back from
    the force balance, as for a saved rest. The positions are not changed. Ctrl-C in it
    raises KeyboardInterrupt: a check stopped half-way is no check."""
    s = settings
    line = anchor_line(pattern, mesh, band=s.top_band)
    if not len(line) or onbody.anchor_height_mm is None:
        return onbody
    landmark = onbody.landmark_height_mm * 1e-3
    x, solver = _saved_solver(mesh, body, fabric, positions, spacing=spacing,
                              contact_margin=contact_margin, floor=False,
                              max_iterations=s.floor_chunk)
    start = float(x[line, 1].mean())
    top, iterations, held, state = start, 0, False, x
    while iterations < s.floor_iterations:
        result = run_plan(solver, Plan.settle(saved=iterations == 0), state).result
        iterations += result.iterations
        state = result.x
        if result.interrupted:  # stopped half-way, it had passed as held
            raise KeyboardInterrupt
        now = float(state[solver.model.vertex_map[line], 1].mean())
        moved, top = top - now, now
        if result.stop_reason == "fell" or abs(top - landmark) > s.anchor_tolerance:
            break
        if result.converged or abs(moved) < s.floor_held:
            held = True
            break
    return floor_checked(onbody, top - landmark, start - top, iterations, held, s)


def saved_contact_fault(mesh: GarmentMesh, body, positions, contact, *,
                        spacing: float = 0.005) -> str | None:
    """Why the saved contact state ``contact`` (named arrays, ``contact.npz``) of the 3D state
    ``positions`` (n, 3) [m] of ``mesh`` on ``body`` cannot be the one a drape continues (an
    array missing, of another shape or kind, out of range, NaN: what ``drape --start``
    refuses), in words naming the array; None when it can. ``fit`` took a file so damaged
    for the rest it said it was."""
    x, solver = _saved_solver(mesh, body, get_fabric(DEFAULTS.fabric), positions,
                              spacing=spacing)
    try:
        ContactState.from_saved(contact, n=solver.model.n,
                                n_triangles=len(solver.model.terms.tris), x=x)
    except SavedStateError as exc:
        return f"array '{exc.array}': {exc.reason}"
    return None


def saved_crossings(mesh: GarmentMesh, body, positions, *, spacing: float = 0.005
                    ) -> dict[str, int]:
    """What a drape's checks count through the body and across the cloth, for a saved 3D
    state ``positions`` (n, 3) [m] of ``mesh`` read back on ``body`` (``patternfit fit
    --body``): ``edges_in_body``, ``faces_in_body`` (:func:`~patternfit.sim.checks.
    through_body`) and ``self_intersections`` (crossed triangle pairs, seams welded as the
    drape's). Read back, a drape that failed with 6 cloth edges through the body passed as
    a fit. 0.05 s at 1.5K triangles."""
    x, solver = _saved_solver(mesh, body, get_fabric(DEFAULTS.fabric), positions,
                              spacing=spacing)
    edges, faces = through_body(solver.model, x)
    return {"edges_in_body": edges, "faces_in_body": faces,
            "self_intersections": crossings(solver.model, x)}


def saved_balance(mesh: GarmentMesh, body, fabric: Fabric | str, positions, *,
                  spacing: float = 0.005, contact_margin: float = CONTACT_MARGIN
                  ) -> tuple[float, float, float]:
    """Residual (rms, 99th percentile, largest) of |F_i| / (m_i g) [-] over the free
    vertices of the 3D state ``positions`` (n, 3) [m] of ``mesh`` on ``body`` in
    ``fabric``, for a state whose contact state is not known (a saved state without its
    ``contact.npz``).

    What the drape's residual takes from its contact state (each contact's stiffness and
    friction anchor, the self-repulsion pairs it held) is not known, so the body is let push
    as it may: where it touches a vertex (its own or its edges' and triangles' contact
    points within reach, the contact pushing as the body's surface does there; a coarse
    triangle over a shoulder touches in its middle, its corners 15 cm off the body) it may
    add any force along that push and, along the surface, a friction
    force up to ``fabric.friction`` times that (Coulomb's cone); F_i is what remains of the
    cloth's own force (membrane, bending, seams, gravity, the self-repulsion of the pairs
    found at ``positions``) once the cone takes its nearest point to it, all of it where
    the body does not touch. Vertices pressed to another layer of the cloth
    (:func:`_layered`), whose force the drape's held pairs carried, are left out. A rest
    reads about its drape's residual; a state moved off its rest (lifted or shifted by a
    centimetre, stretched, stopped early, one vertex pulled off) leaves the vertices that
    held it, or all of them, off by many times their weight. The state is not moved. 0.1 s
    at 1.5K triangles, 0.7 s at 22K."""
    fab = get_fabric(fabric)
    x, solver = _saved_solver(mesh, body, fab, positions, spacing=spacing,
                              contact_margin=contact_margin)
    # a solve of no iteration sets up what the energy needs (gravity, the self pairs)
    run_plan(solver, Plan.settle(saved=True), x)
    model, state = solver.model, solver.state.copy()
    state.friction_idx = np.zeros(0, np.int64)
    xr = model.reduce(x)
    # the cloth alone (its terms rebuilt once: 0.13 s at 22K)
    bodiless = replace(model, body=None)
    cloth = total_energy.energy(bodiless, state, xr, settings=solver.settings)[1]
    touch = total_energy.energy(model, state, xr, settings=solver.settings)[1] - cloth
    return cone_residual(model, -cloth, -touch, fab.friction,
                         leave_out=_layered(bodiless, state, xr, cloth, solver.settings))


def _layered(bodiless, state, x, cloth, settings) -> np.ndarray:
    """(n,) bool: the solved vertices pressed to another layer of the cloth at ``x`` (n, 3)
    [m]: pushed by a self-repulsion pair of ``state`` (``cloth`` the gradient of
    ``bodiless``, the model without its body, with them), or a vertex-triangle pair's
    within twice the gap kept (one the drape held, its projection just off the triangle,
    which the search at ``x`` lost). Not the pairs the search finds up to its detection
    radius: a vertex pulled 5 cm off a rest was paired with its own cloth an edge away, and
    left out."""
    bare = state.copy()
    bare.pairs = np.zeros((0, 2), np.int64)
    bare.edge_pairs = np.zeros((0, 2), np.int64)
    pushed = total_energy.energy(bodiless, bare, x, settings=settings)[1]
    out = np.any(pushed != cloth, axis=1)
    tris = bodiless.terms.tris[state.pairs[:, 1]]
    d = np.einsum("pc,pc->p", state.pair_normal,
                  x[state.pairs[:, 0]] - np.einsum("pj,pjc->pc", state.bary, x[tris]))
    close = np.abs(d) < 2 * bodiless.self_gap(settings)
    out[state.pairs[close, 0]] = True
    out[tris[close].ravel()] = True
    return out


def _start_faults(solver: GarmentSolver, x, *, depth: float = tol.penetration) -> int:
    """Crossed triangle pairs plus cloth edges and faces deeper than ``depth`` [m] in the
    body of a start ``x`` (n3, 3) [m] of the drape under gravity: a sewn state, or one
    carried to ``solver``'s mesh from another (a coarser drape, or the drape before a
    re-meshing edit)."""
    return solver.crossings(x) + sum(through_body(solver.model, x, depth=depth))


#: a carried start (``drape(start_rest=...)``) may have cloth edges or faces this far inside
#: the body [mm]: a new edge across the old drape's triangles is a chord of a chord, and on
#: a convex part of the body it dips by its sagitta (1.5K trousers and dress after a
#: re-meshed edit: one edge 1.1-1.4 mm deep), which the edge contact pushes out; deeper
#: ones lie across a limb (the 1.5K coat: 4-23 mm), where the push may go either way
CARRIED_DEPTH_MM = 3.0

#: coarse sizes tried, as multiples of ``coarse``, until one's equilibrium carried to the
#: fine mesh neither crosses itself nor lies across the body: fine triangles near a coarse
#: fold folded flat (the trousers' fork) can cut through each other although every fine
#: vertex lies on the coarse surface, and no repulsion undoes a crossing once made (20K
#: trousers: 55 crossed pairs from a 2K start, none from 1.5K or 3K); a thumb can poke
#: through the face of a coarse triangle, clear of its vertices and edges, and the fine
#: edges across that face then lie through it, held there by their edge contact (the 22K
#: Table 2 coat: 8 fine edges through the thumb from a 2K start, 3 at rest)
_COARSE_TRIES = (1.0, 1.5, 0.75)


def _coarse_to_fine(pattern, mesh, body, fabric, field_, x0, coarse, options, t0, t_sdf,
                    progress) -> Drape:
    """Drape a coarse mesh of ``pattern`` whole, then settle ``mesh`` from its equilibrium."""
    # the start is an equilibrium with friction: friction holds from the first iteration
    # (delayed, the whole garment slid for the first hundred)
    solver = GarmentSolver(mesh.vertices, mesh.triangles, _grain_per_triangle(mesh), fabric,
                           seam_pairs=mesh.seam_pairs, body=field_,
                           settings=replace(options["settings"], friction_delay=0))
    solver.weld()
    t = time.perf_counter()
    timing = {"distance_field_seconds": t_sdf, "coarse_iterations": 0}
    # the coarse drape only starts the fine one: the kinematic rule stops it
    options = {**options, "settings": replace(options["settings"], stop="kinematic")}
    best = None
    for share in _COARSE_TRIES:
        small = mesh_pattern(pattern, triangles=int(share * coarse))
        first = drape(pattern, small, body, fabric, placed=transfer(mesh, x0, small),
                      coarse=None, progress=progress, **options)
        timing.update(coarse_triangles=small.n_triangles, coarse_seconds=time.perf_counter() - t)
        timing["coarse_iterations"] += first.result.iterations + first.timing["sewing_iterations"]
        if not first.result.welded or first.result.interrupted:
            # nothing sewn to carry over: report the coarse state, not a fit of the fine mesh
            return Drape(positions=transfer(small, first.positions, mesh), placed=x0,
                         result=replace(first.result, x=transfer(small, first.result.x, mesh),
                                        vertex_map=np.arange(mesh.n_vertices)), solver=solver,
                         seconds=time.perf_counter() - t0, timing=timing)
        start = transfer(small, first.positions, mesh)
        faults = _start_faults(solver, start)
        if best is None or faults < best[0]:
            best = (faults, start, small.n_triangles)
        if faults == 0:
            break
    _, start, timing["coarse_triangles"] = best
    result = run_plan(solver, Plan.settle(), start, progress=progress).result
    return Drape(positions=result.x[solver.model.vertex_map], placed=x0, result=result, solver=solver,
                 seconds=time.perf_counter() - t0, timing=timing)


def redrape(previous: Drape, mesh: GarmentMesh, *, start=None, start_rest=None,
            pattern: Pattern | None = None, plan: Plan | None = None, progress=None) -> Drape:
    """Drape again after an edit that kept the mesh topology (new rest shapes only); the
    factorisation is reused when it can be.

    The solve starts from ``start`` ((n3, 3) [m] per simulated vertex) when given; else from
    the previous equilibrium moved with the edit, or as it is when the moved state crosses
    itself or enters the body (:func:`patternfit.sim.schedule.start_after_edit`).
    ``timing["start"]`` says which: "given", "moved" or "previous" (of the last phase).
    ``start_rest`` ((n, 2) [m]) are the flat shapes at which ``start`` rests when it is not
    ``previous``'s (an older drape of the same mesh, after an undo): the solver takes them
    as its rest shapes first, and ``start`` is moved with the edit from them as the previous
    equilibrium would be. ``plan`` (default :meth:`Plan.redrape() <patternfit.sim.schedule.Plan.redrape>`, one
    step) may reach the new rest shapes in stages (:meth:`~patternfit.sim.schedule.Plan.staged`).
    The on-body checks run against ``pattern`` (the edited pattern; the previous drape's
    when None: an edit keeps the panels' parts and the anchor) and the previous body.
    """
    t0 = time.perf_counter()
    solver = previous.solver
    x0 = previous.result.x
    if start is not None:
        start = np.asanyarray(start, dtype=np.float64)
        if start_rest is not None:
            solver.set_rest(start_rest)
            x0, start = start, None
    run = run_plan(solver, plan or Plan.redrape(), x0, rest=mesh.vertices,
                   start=start, progress=progress)
    result = run.result
    d = Drape(positions=result.x[solver.model.vertex_map], placed=previous.placed, result=result,
              solver=solver, seconds=time.perf_counter() - t0,
              timing={"start": run.start, "phases": [p.name for p in run.phases]})
    pattern = pattern if pattern is not None else previous.pattern
    if pattern is not None and previous.body is not None:
        d.check_on_body(pattern, mesh, previous.body)
    return d
