"""The drape schedule (patternfit.sim.schedule): the plans' phases and settings, and the one
runner, which always gives the solver its own settings back."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from patternfit.body.builtin import load_body
from patternfit.edit import move_edge, update_mesh
from patternfit.sim.placement import place_on_body
from patternfit.sim.schedule import STAGE_ITERATIONS, Phase, Plan, run_plan
from patternfit.sim.settings import SolverSettings
from patternfit.sim.solver import GarmentSolver

from scenes import garment

BASE = SolverSettings(contact_margin=0.003, max_iterations=4000)


# ------------------------------------------------------------------------ plans (no solve)


def test_first_drape_sews_and_relaxes_without_gravity_then_drapes_with_the_base():
    plan = Plan.first_drape(sewing_iterations=900, relax_iterations=250)
    assert plan.names == ("sewing", "relaxing", "draping")
    sew, relax, drape = (p.settings(BASE) for p in plan.phases)
    assert sew.gravity == relax.gravity == (0.0, 0.0, 0.0)
    assert sew.stop_at_weld and sew.max_iterations == 900 and not sew.self_collision
    assert relax.stop == "kinematic" and relax.max_iterations == 250 and relax.self_collision
    assert drape == BASE
    assert [p.needs_weld for p in plan.phases] == [False, True, True]
    # self-collision while sewing when asked; no relaxation when it has no iterations
    assert Plan.first_drape(sewing_self_collision=True).phases[0].settings(BASE).self_collision
    assert Plan.first_drape(relax_iterations=0).names == ("sewing", "draping")
    assert Plan.sewing().names == ("sewing", "relaxing")


def test_staged_redrape_has_a_stage_per_3_cm_capped_at_the_solvers_own_limit():
    assert Plan.staged(0.0).names == ("settling",)
    assert Plan.staged(0.03).names == ("settling",)
    plan = Plan.staged(0.061)
    assert plan.names == ("stage 1 of 3", "stage 2 of 3", "settling")
    assert [p.rest for p in plan.phases] == pytest.approx([1 / 3, 2 / 3, 1.0])
    assert plan.phases[0].settings(BASE).max_iterations == STAGE_ITERATIONS
    assert plan.phases[0].settings(replace_iterations(50)).max_iterations == 50
    assert plan.phases[-1].settings(BASE) == BASE
    with pytest.raises(ValueError, match="change"):
        Plan.staged(float("nan"))
    # a carried start: only the first phase reads the contact back from the force balance
    saved = Plan.staged(0.061, saved=True)
    assert saved.names == plan.names
    assert [p.settings(BASE).saved_rest for p in saved.phases] == [True, False, False]
    assert Plan.staged(0.01, saved=True).phases[0].settings(BASE).saved_rest


def test_a_settle_takes_newton_steps_from_its_first_iteration():
    # a coarse drape carried over or a saved rest is near rest: L-BFGS there only creeps
    for plan in (Plan.settle(), Plan.settle(saved=True)):
        assert plan.phases[0].settings(BASE).newton_after == 0
    assert Plan.settle(saved=True).phases[0].settings(BASE).saved_rest
    assert Plan.redrape().phases[0].settings(BASE).newton_after == BASE.newton_after


def replace_iterations(n):
    return dataclasses.replace(BASE, max_iterations=n)


def test_plans_are_frozen_and_phases_refuse_unknown_settings():
    plan = Plan.settle()
    with pytest.raises(dataclasses.FrozenInstanceError):
        plan.phases = ()
    with pytest.raises(dataclasses.FrozenInstanceError):
        plan.phases[0].overrides = (("gravity", (0.0, 0.0, 0.0)),)
    with pytest.raises(ValueError, match="gravty"):
        Phase("x", "a typo", overrides=(("gravty", (0.0, 0.0, 0.0)),))
    with pytest.raises(ValueError, match="rest"):
        Phase("x", "past the target", rest=1.5)


# ------------------------------------------------------------------------ the runner


@pytest.fixture(scope="module")
def skirt():
    pattern, mesh = garment("skirt", 400)
    body = load_body("female_thin")
    return pattern, mesh, body, body.distance_field(0.005), place_on_body(pattern, mesh, body)


def _solver(skirt):
    _, mesh, _, field, _ = skirt
    return GarmentSolver(mesh.vertices, mesh.triangles, mesh.grain[mesh.triangle_panel],
                         "cotton", seam_pairs=mesh.seam_pairs, body=field, settings=BASE)


class Recorder:
    """A progress callback that notes the phases announced and the settings each ran with,
    and raises ``error`` at iteration ``at`` of phase ``stop_in`` (or when it is announced,
    with ``at`` None)."""

    def __init__(self, solver, stop_in=None, at=None, error=None):
        self.solver, self.stop_in, self.at, self.error = solver, stop_in, at, error
        self.names, self.seen, self.rests = [], {}, {}

    def phase(self, name):
        self.names.append(name)
        if name == self.stop_in and self.at is None:
            raise self.error

    def __call__(self, it, energy, step, elapsed):
        name = self.names[-1]
        self.seen[name] = self.solver.settings
        self.rests[name] = self.solver.model.rest.copy()
        if name == self.stop_in and it == self.at:
            raise self.error


@pytest.fixture(scope="module")
def first_drape(skirt):
    solver = _solver(skirt)
    rec = Recorder(solver)
    run = run_plan(solver, Plan.first_drape(), skirt[4], progress=rec)
    return solver, rec, run


def test_runner_announces_each_phase_runs_it_with_its_settings_and_restores(first_drape):
    solver, rec, run = first_drape
    assert rec.names == ["sewing", "relaxing", "draping"]
    assert [p.name for p in run.phases] == rec.names
    for phase in Plan.first_drape().phases:
        assert rec.seen[phase.name] == phase.settings(BASE)
    assert solver.settings is BASE
    assert run.result.welded and run.result is run.phases[-1].result
    assert run.iterations("sewing", "relaxing") == sum(p.result.iterations
                                                       for p in run.phases[:2])


@pytest.mark.parametrize("error", [RuntimeError("boom"), KeyboardInterrupt()])
def test_a_phase_that_raises_leaves_the_solver_with_its_own_settings(skirt, error):
    """An error in the gravity-free sewing, or a KeyboardInterrupt between two solves (where
    the solver cannot catch it), passes up and the kept solver has gravity again."""
    solver = _solver(skirt)
    at, phase = (5, "sewing") if isinstance(error, RuntimeError) else (None, "relaxing")
    rec = Recorder(solver, stop_in=phase, at=at, error=error)
    with pytest.raises(type(error)):
        run_plan(solver, Plan.first_drape(), skirt[4], progress=rec)
    assert rec.names[-1] == phase
    assert solver.settings is BASE and solver.settings.gravity != (0.0, 0.0, 0.0)


def test_an_interrupted_phase_ends_the_plan_and_restores_the_settings(skirt):
    """A KeyboardInterrupt inside a solve: the solver stops cleanly, the plan ends there."""
    solver = _solver(skirt)
    rec = Recorder(solver, stop_in="sewing", at=5, error=KeyboardInterrupt())
    run = run_plan(solver, Plan.first_drape(), skirt[4], progress=rec)
    assert [p.name for p in run.phases] == ["sewing"] and run.result.interrupted
    assert solver.settings is BASE


def test_staged_redrape_walks_the_rest_shapes_to_the_edit(skirt, first_drape):
    """A 5 cm hem edit in two stages: the first at half the edit and capped, the second at
    the edited rest shapes; the solver keeps those and its own settings."""
    pattern, mesh = skirt[0], skirt[1]
    solver, _, first = first_drape
    old = solver.model.rest.copy()
    edited = update_mesh(pattern, move_edge(pattern, panel="front", edge="hem",
                                            offset=(0.0, -0.05), partner=True), mesh)
    rec = Recorder(solver)
    run = run_plan(solver, Plan.staged(0.05), first.result.x, rest=edited.vertices,
                   progress=rec)
    assert rec.names == ["stage 1 of 2", "settling"]
    np.testing.assert_allclose(rec.rests["stage 1 of 2"], old + 0.5 * (edited.vertices - old))
    np.testing.assert_array_equal(rec.rests["settling"], edited.vertices)
    assert rec.seen["stage 1 of 2"].max_iterations == STAGE_ITERATIONS
    assert run.phases[0].start == "moved" and run.start == "moved"
    assert solver.settings is BASE
    np.testing.assert_array_equal(solver.model.rest, edited.vertices)
    # the plan needs the target rest shapes
    with pytest.raises(ValueError, match="rest"):
        run_plan(solver, Plan.redrape(), run.result.x)
