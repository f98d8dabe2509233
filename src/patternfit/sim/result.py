"""The outcome of a solve (:class:`DrapeResult`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .checks import DrapeChecks


@dataclass(frozen=True, eq=False)
class DrapeResult:
    """Outcome of a solve (:func:`patternfit.sim.solver.solve`).

    Attributes
    ----------
    x : (n3, 3) float
        Simulated vertex positions [m] (welded pairs coincide).
    vertex_map : (n,) int
        Flat vertex -> simulated vertex after welding (both sides of a welded pair map to
        the same index).
    welded : bool
        Whether the seam springs were closed and welded during this or an earlier solve.
    iterations : int
    seconds : float
    converged : bool
    interrupted : bool
        Stopped by KeyboardInterrupt; ``x`` is the last accepted state.
    stop_reason : str
        "converged", "iterations", "time", "interrupted", "stalled", "fell" (every vertex
        below the body's distance field: :func:`~patternfit.sim.stop_rule.fell`) or
        "welded" (with ``SolverSettings.stop_at_weld``).
    energy : float
        Total energy at ``x`` [J].
    checks : DrapeChecks
    factorizations : int
        Cholesky factorisations done by this solver object so far.
    """

    x: np.ndarray
    vertex_map: np.ndarray
    welded: bool
    iterations: int
    seconds: float
    converged: bool
    interrupted: bool
    stop_reason: str
    energy: float
    checks: DrapeChecks
    factorizations: int = 0
