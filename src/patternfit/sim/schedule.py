"""The drape schedule: which solves a drape runs, in what order and with which settings.

A :class:`Plan` is a frozen tuple of :class:`Phase`\\ s, each one solver run with a few
:class:`SolverSettings` fields changed from the solver's own (no gravity while sewing, an
iteration cap on a re-drape's intermediate stages...) and, for a re-drape, the share of the
way to the edited rest shapes at which it solves. :func:`run_plan` is the one place that
runs them: every drape, re-drape, the design session's staged re-drape and the Newton
engine's sewing go through it. It gives each phase its settings with ``dataclasses.replace``
and always puts the solver's own settings back, also when a phase raises or is interrupted,
so a kept solver never stays in a gravity-free or capped setting.

Lengths in metres; positions (n3, 3) per simulated vertex.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, fields, replace
from typing import Any, Callable

import numpy as np

from ..mesh.transfer import follow_edit
from .checks import depth_mm
from .result import DrapeResult
from .settings import SolverSettings
from .solver import GarmentSolver

#: largest motion of a flat vertex [m] between the stages of a staged re-drape
STAGE_LENGTH = 0.03
#: iteration limit of a staged re-drape's intermediate stages
STAGE_ITERATIONS = 200
#: a re-drape's moved start may lie this far inside the body [mm]: contact pushes such
#: vertices out along the distance field's gradient (the 22K coat's hem lowered 3 cm: 12
#: vertices, 2.7 mm deep; 6.3 mm since the contact acts inside the edges too, and at 5 mm
#: the start fell back to the unmoved state: 1,005 iterations, 44 s, instead of some 300);
#: much deeper, a vertex could be pushed out through the far side of a thin limb (a
#: forearm's radius is some 35 mm)
MOVED_DEPTH_MM = 10.0

_FIELDS = frozenset(f.name for f in fields(SolverSettings))
_NO_GRAVITY = ("gravity", (0.0, 0.0, 0.0))


@dataclass(frozen=True)
class Phase:
    """One solver run of a plan.

    Attributes
    ----------
    name : str
        What the studio and progress show ("sewing", "relaxing", "draping", "settling",
        "stage 1 of 3").
    purpose : str
        Why the phase is there, in a sentence.
    overrides : tuple of (str, value)
        :class:`SolverSettings` fields set for this phase only.
    at_most : int, optional
        Iteration cap: the phase runs at most this many iterations, or the solver's own
        ``max_iterations`` when smaller.
    needs_weld : bool
        Runs only when the phase before it ended with the seams welded (else the plan ends
        there: nothing is sewn to drape).
    rest : float, optional
        Solve at the rest shapes this share of the way from the solver's rest shapes at the
        start of the plan to the plan's target (:func:`run_plan`'s ``rest``), starting from
        the last state moved with the edit; None keeps the rest shapes.
    """

    name: str
    purpose: str
    overrides: tuple[tuple[str, Any], ...] = ()
    at_most: int | None = None
    needs_weld: bool = False
    rest: float | None = None

    def __post_init__(self):
        unknown = sorted({k for k, _ in self.overrides} - _FIELDS)
        if unknown:
            raise ValueError(f"phase {self.name!r}: overrides: not SolverSettings fields: "
                             f"{', '.join(unknown)}")
        if self.at_most is not None and self.at_most < 0:
            raise ValueError(f"phase {self.name!r}: at_most: must be >= 0, got {self.at_most}")
        if self.rest is not None and not 0.0 < self.rest <= 1.0:
            raise ValueError(f"phase {self.name!r}: rest: a share in (0, 1], got {self.rest}")

    def settings(self, base: SolverSettings) -> SolverSettings:
        """The settings this phase runs with: ``base`` with the overrides and the cap."""
        changes = dict(self.overrides)
        if self.at_most is not None:
            changes["max_iterations"] = min(self.at_most,
                                            changes.get("max_iterations", base.max_iterations))
        return replace(base, **changes)


@dataclass(frozen=True)
class Plan:
    """The phases of one drape, run in order by :func:`run_plan`; made by the named
    constructors below."""

    phases: tuple[Phase, ...]

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.phases)

    @classmethod
    def sewing(cls, *, sewing_iterations: int = 1500, relax_iterations: int = 300,
               sewing_self_collision: bool = False) -> "Plan":
        """Sew from the placement and relax the sewn garment, both without gravity: the
        start of a first drape (static or Newton)."""
        sew = Phase(
            "sewing", "close the seams in place; without gravity a garment hanging from open "
            "seams cannot fall off the body while the seam springs stiffen",
            overrides=(_NO_GRAVITY, ("max_iterations", sewing_iterations),
                       ("stop_at_weld", True))
            + (() if sewing_self_collision else (("self_collision", False),)))
        phases = (sew,)
        if relax_iterations > 0:
            phases += (Phase(
                "relaxing", "let the sewn garment relax from the seams' pull, still without "
                "gravity; its end is only the drape's start, so the kinematic rule stops it",
                overrides=(_NO_GRAVITY, ("max_iterations", relax_iterations),
                           ("stop", "kinematic")), needs_weld=True),)
        return cls(phases)

    @classmethod
    def first_drape(cls, *, sewing_iterations: int = 1500, relax_iterations: int = 300,
                    sewing_self_collision: bool = False) -> "Plan":
        """Sew, relax (:meth:`sewing`), then drape under gravity to rest."""
        sewn = cls.sewing(sewing_iterations=sewing_iterations,
                          relax_iterations=relax_iterations,
                          sewing_self_collision=sewing_self_collision)
        return cls(sewn.phases + cls.draping().phases)

    @classmethod
    def draping(cls) -> "Plan":
        """Drape the sewn and relaxed garment under gravity to rest: the last phase of
        :meth:`first_drape`, run alone after a sewing that was checked first."""
        return cls((Phase("draping", "drape the sewn garment under gravity to rest",
                          needs_weld=True),))

    @classmethod
    def settle(cls, *, saved: bool = False) -> "Plan":
        """Drape under gravity from a sewn state (the seams welded before the plan): a
        coarser drape carried over, or (``saved``) a saved rest of this mesh, whose contact
        stiffness is read back from its force balance (``SolverSettings.saved_rest``).

        Newton steps from the first iteration (``newton_after`` 0): such a start is near
        rest already, and L-BFGS there only crept (the 22K coat's fine settle: 825 L-BFGS
        iterations, 7 s, left a residual rms of 8, then 147 Newton steps); the first
        drapes of the Table 2 garments, three samples each, medians: coat 22.8 -> 19.5 s,
        skirt 16.4 -> 13.6 s, trousers 30.0 -> 18.4 s (docs/simulation.md)."""
        overrides = (("newton_after", 0),) + ((("saved_rest", True),) if saved else ())
        return cls((Phase("settling", "drape a sewn state under gravity to rest",
                          overrides=overrides),))

    @classmethod
    def redrape(cls, stages: int = 1, *, stage_iterations: int = STAGE_ITERATIONS,
                saved: bool = False) -> "Plan":
        """Drape again after an edit, reaching the new rest shapes in ``stages`` equal
        steps; the intermediate ones run at most ``stage_iterations``. ``saved``: the
        solver is new and its start a rest carried over from another drape, whose contact
        stiffness the first phase reads back from the force balance (as :meth:`settle`)."""
        if stages < 1:
            raise ValueError(f"stages: must be >= 1, got {stages}")
        phases = [Phase(f"stage {k} of {stages}", "part of the edit's motion: large "
                        "changes at once outrun the lagged self-collision pairs",
                        at_most=stage_iterations, rest=k / stages)
                  for k in range(1, stages)]
        phases.append(Phase("settling", "settle at the edited rest shapes", rest=1.0))
        if saved:
            phases[0] = replace(phases[0], overrides=(("saved_rest", True),))
        return cls(tuple(phases))

    @classmethod
    def staged(cls, change: float, *, saved: bool = False) -> "Plan":
        """:meth:`redrape` in stages of at most ``STAGE_LENGTH`` of flat-vertex motion for
        an edit that moves a flat vertex by up to ``change`` [m]: a garment whose rest
        shapes grew by 12 cm at once (a coat corrected from 65% of its width) expands faster
        than the lagged self-collision pairs follow and crossed itself (7-8 crossing pairs
        on the Table 2 coat and trousers); in three stages of 4 cm, 0 or 1; in four of
        3 cm, 0, and faster than in one. ``saved`` as in :meth:`redrape`."""
        if not math.isfinite(change) or change < 0.0:
            raise ValueError(f"change: expected a finite length >= 0 [m], got {change}")
        return cls.redrape(max(1, int(np.ceil(change / STAGE_LENGTH))), saved=saved)


@dataclass(eq=False)
class PhaseRun:
    """What one phase did: its name, the solver's result, seconds, and for a phase at new
    rest shapes where it started ("given", "moved" or "previous")."""

    name: str
    result: DrapeResult
    seconds: float
    start: str | None = None


@dataclass(eq=False)
class PlanRun:
    """The phases that ran (a plan ends early when a phase is interrupted or leaves the
    seams open before a phase that needs them welded)."""

    phases: list[PhaseRun] = field(default_factory=list)

    @property
    def result(self) -> DrapeResult:
        """The last phase's result: the drape's."""
        return self.phases[-1].result

    @property
    def start(self) -> str | None:
        """Where the last phase at new rest shapes started."""
        starts = [p.start for p in self.phases if p.start is not None]
        return starts[-1] if starts else None

    def iterations(self, *names: str) -> int:
        """Iterations of the phases called ``names``."""
        return sum(p.result.iterations for p in self.phases if p.name in names)

    def seconds(self, *names: str) -> float:
        """Seconds [s] of the phases called ``names``."""
        return sum(p.seconds for p in self.phases if p.name in names)


def run_plan(solver: GarmentSolver, plan: Plan, x0, *, rest=None, start=None,
             progress: Callable | None = None) -> PlanRun:
    """Run the phases of ``plan`` on ``solver`` from ``x0`` ((n3, 3) [m]), each from the
    last one's end.

    Each phase runs with its settings made from the solver's own (``solver.settings`` at the
    call); those are put back when the plan ends, however it ends (a phase that raises, a
    KeyboardInterrupt). A phase interrupted (KeyboardInterrupt in ``progress``) ends the
    plan; so does a phase that leaves the seams open before one that needs them welded.

    Parameters
    ----------
    rest : (n, 2) float, optional
        The target rest shapes [m] of the phases with a ``rest`` share (a re-drape); they
        are set on the solver when the plan ends early too.
    start : (n3, 3) float, optional
        Start of the first phase at new rest shapes instead of the last state moved with
        the edit (see :func:`start_after_edit`).
    progress : callable, optional
        ``progress(iteration, energy [J], step [m], elapsed [s])`` for every iteration (and
        ``residual=`` when it takes one: :func:`~patternfit.sim.solver.solve`); when it has
        a ``phase`` attribute, ``progress.phase(name)`` is called as each phase
        starts.
    """
    base = solver.settings
    old = solver.model.rest
    target = None if rest is None else np.asarray(rest, dtype=np.float64)
    if any(p.rest is not None for p in plan.phases) and target is None:
        raise ValueError("rest: the plan re-drapes to new rest shapes; give them")
    announce = getattr(progress, "phase", None)
    x = x0
    run = PlanRun()
    try:
        for phase in plan.phases:
            if run.phases and (run.result.interrupted
                               or (phase.needs_weld and not run.result.welded)):
                break
            if announce is not None:
                announce(phase.name)
            solver.settings = phase.settings(base)
            how = None
            t = time.perf_counter()
            if phase.rest is not None:
                shape = target if phase.rest == 1.0 else old + phase.rest * (target - old)
                x, how = (start, "given") if start is not None else \
                    start_after_edit(solver, x, shape)
                start = None
                solver.set_rest(shape)
            result = solver.solve(x, resume=how == "moved", progress=progress)
            run.phases.append(PhaseRun(phase.name, result, time.perf_counter() - t, how))
            x = result.x
        if target is not None and not np.array_equal(solver.model.rest, target):
            solver.set_rest(target)  # ended early: the solver holds the edited pattern
    finally:
        solver.settings = base
    return run


def start_after_edit(solver: GarmentSolver, x, rest) -> tuple[np.ndarray, str]:
    """Start of a re-drape at the rest shapes ``rest`` (n, 2) [m] from the state ``x``
    ((n3, 3) [m]) at the solver's current ones, and which it is: "moved" or "previous".

    The state moved with the edit (:func:`patternfit.mesh.transfer.follow_edit`: a lowered
    hem starts lower, where it settles in a fraction of the iterations of a start with the
    new cloth compressed: 15K skirt 1,575 -> 75, 22K coat 675 -> 175), unless that state
    crosses itself more than ``x`` (layers folded flat, e.g. a trouser hem pooled on the
    feet, move through each other: 49 crossed pairs after a 3 cm hem edit of the 20K
    trousers) or enters the body deeper than ``MOVED_DEPTH_MM`` (a panel taken in); then
    ``x`` as it is. (Half or a quarter of the motion crossed less, but settled no faster
    than none of it.)
    """
    x = np.asarray(x, dtype=np.float64)
    if rest.shape != solver.model.rest.shape or np.array_equal(rest, solver.model.rest):
        return x, "previous"
    moved = follow_edit(solver.model.rest, rest, solver.model.triangles, x[solver.model.vertex_map])
    rows = np.zeros_like(x)
    np.add.at(rows, solver.model.vertex_map, moved)
    rows /= np.maximum(np.bincount(solver.model.vertex_map, minlength=len(rows)), 1)[:, None]
    # the crossings and the depth only (the whole checks look for edges through the body
    # too: 2 x 53 ms of the 22K coat's re-drape)
    model = solver.model
    if (solver.crossings(rows) <= solver.crossings(x)
            and depth_mm(model, rows) <= max(depth_mm(model, x), MOVED_DEPTH_MM)):
        return rows, "moved"
    return x, "previous"
