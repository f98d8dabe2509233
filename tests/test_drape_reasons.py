"""A drape that stops short of rest says how far from it: "no equilibrium (stopped:
iterations)" left the user nothing to act on (a GarmentCodeData dress stuck at a residual
4,000 times the limit read the same as one a few iterations short)."""

import re

import patternfit.api as api
from patternfit.sim.settings import SolverSettings


def test_no_equilibrium_says_its_residual_and_the_rest_it_misses():
    outcome = api.drape_and_evaluate("skirt", "female_average", "cotton", triangles=300,
                                     settings=SolverSettings(max_iterations=40))
    said = [r for r in outcome.checks["reasons"] if r.startswith("no equilibrium")]
    assert said and not outcome.passed
    found = re.search(r"residual rms ([0-9.e+-]+), p99 ([0-9.e+-]+) of a vertex's weight; "
                      r"at rest at most 0\.01 and 0\.1", said[0])
    assert found, said[0]
    rms = outcome.checks["residual_rms"]
    assert abs(float(found.group(1)) - rms) <= 1e-2 * rms and rms > 0.01
