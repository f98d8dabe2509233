"""The hanging strip: a strip hanging from its clamped top edge stretches under its own
weight by ``rho g L^2 / (2 k)`` (``patternfit fabric-test strip``; docs/fabrics.md).

Units: metres, kilograms, seconds, newtons; ``y`` is up.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, fields

import numpy as np

from ...arguments import number
from ...constants import GRAVITY
from ..fabrics import Fabric, get_fabric
from ..settings import SolverSettings
from ..solver import GarmentSolver
from .common import (Progress, SolveInfo, _direction, _grain, _plain, _rect_mesh, _say,
                     _solve, _solver_settings)


@dataclass(frozen=True)
class StripResult:
    """A strip hanging under its own weight from its clamped top edge.

    Attributes
    ----------
    fabric : str
    direction : str
        "warp" or "weft": the yarn direction the strip hangs along.
    length_m, width_m : float
        Strip size [m].
    density_kg_m2 : float
        Areal density rho [kg/m^2].
    stiffness_n_m : float
        Tensile stiffness k along the hanging direction [N/m].
    elongation_measured_m : float or None
        Mean drop of the bottom edge [m].
    elongation_expected_m : float
        ``rho g L^2 / (2 k)`` [m] (exact for this membrane: the tension at a height is the
        weight below it, ``k e``).
    ratio : float or None
        measured / expected [-].
    strain_top : float
        Strain at the clamp, ``rho g L / k`` [-] (the largest in the strip).
    width_change : float or None
        Mean relative width change at mid-height [-] (the membrane has no Poisson coupling:
        about 0).
    triangles, vertices : int
    solve : SolveInfo
    seconds : float
        Wall time of the whole test [s].
    tolerance : float
        Largest accepted |ratio - 1| [-].
    """

    fabric: str
    direction: str
    length_m: float
    width_m: float
    density_kg_m2: float
    stiffness_n_m: float
    elongation_measured_m: float | None
    elongation_expected_m: float
    ratio: float | None
    strain_top: float
    width_change: float | None
    triangles: int
    vertices: int
    solve: SolveInfo
    seconds: float
    tolerance: float = 0.05

    @property
    def failures(self) -> list[str]:
        """Why the test failed, in words (empty when it passed)."""
        out = []
        if not self.solve.at_rest:
            out.append(f"the strip did not reach rest ({self.solve.describe()})")
        if self.ratio is None:
            out.append("no elongation could be read")
        elif abs(self.ratio - 1.0) > self.tolerance:
            out.append(f"elongation {100 * (self.ratio - 1.0):+.1f} % off the analytic one "
                       f"(tolerance {100 * self.tolerance:g} %)")
        return out

    @property
    def passed(self) -> bool:
        """The solve ended at rest and the stretch is within ``tolerance`` of the analytic
        one."""
        return not self.failures

    def to_dict(self) -> dict:
        d = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "solve"}
        return _plain({"test": "strip", **d, "solve": self.solve.to_dict(),
                       "residual": self.solve.residual, "stop_reason": self.solve.stop_reason,
                       "converged": self.solve.at_rest, "passed": self.passed,
                       "failures": self.failures})


def strip_test(fabric: Fabric | str = "cotton_shirting", *, direction: str = "warp",
               length: float = 0.5, width: float = 0.05, edge: float | None = None,
               settings: SolverSettings | None = None,
               progress: Progress | None = None) -> StripResult:
    """Hang a ``length`` x ``width`` [m] strip of ``fabric`` from its clamped top edge (its
    top row of vertices pinned) under gravity and compare its stretch with
    ``rho g L^2 / (2 k)``, ``k`` the stiffness along ``direction`` ("warp" or "weft").

    ``edge``: mesh edge length [m] (default ``width / 6``). ``settings``: solver settings
    (default the solver's own; self-collision is switched off, a flat strip in tension cannot
    touch itself).
    """
    t0 = time.perf_counter()
    fab = get_fabric(fabric)
    direction = _direction(direction)
    length = number(length, "length", low=1e-3, high=10.0)
    width = number(width, "width", low=1e-3, high=10.0)
    h = number(edge if edge is not None else width / 6, "edge", low=width / 200,
               high=width, rule="must be between width / 200 and width")
    # flat rest: x across, y along the strip (bottom y = 0, clamp y = L); warp along y
    v, t = _rect_mesh(width, length, h)
    k = fab.stretch_warp if direction == "warp" else fab.stretch_weft
    grain = _grain(direction, len(t), along=(0.0, 1.0))
    top = np.flatnonzero(v[:, 1] >= length - 1e-12)
    bottom = np.flatnonzero(v[:, 1] <= 1e-12)
    solver = GarmentSolver(v, t, grain, fab, pinned=top,
                           settings=_solver_settings(settings, self_collision=False))
    _say(progress, f"strip: {len(t)} triangles")
    res = _solve(solver, np.c_[v, np.zeros(len(v))])
    x = res.x
    expected = fab.density * GRAVITY * length ** 2 / (2 * k)
    measured = float(-x[bottom, 1].mean())
    mid = np.abs(v[:, 1] - length / 2) < h / 2
    left, right = mid & (v[:, 0] <= 1e-12), mid & (v[:, 0] >= width - 1e-12)
    wchange = (float(x[right, 0].mean() - x[left, 0].mean()) / width - 1.0
               if left.any() and right.any() else None)
    return StripResult(
        fabric=fab.name, direction=direction, length_m=length, width_m=width,
        density_kg_m2=fab.density, stiffness_n_m=k, elongation_measured_m=measured,
        elongation_expected_m=expected, ratio=measured / expected,
        strain_top=fab.density * GRAVITY * length / k, width_change=wchange,
        triangles=len(t), vertices=len(v), solve=SolveInfo.of(res, solver.settings),
        seconds=time.perf_counter() - t0)

