"""Peirce's cantilever (ASTM D1388): the overhang at which the tip has bent down 41.5 deg
is twice the bending length ``c = (B / (rho g))^(1/3)``, read against the exact heavy elastica
at several mesh sizes (``patternfit fabric-test cantilever``; docs/fabrics.md). A fabric with
bending friction (KES-F 2HB) reads longer, and is held to the exact strip under the same
friction law.

Units: metres, kilograms, seconds, newtons; ``y`` is up.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, fields
from functools import lru_cache
from pathlib import Path

import numpy as np

from ...arguments import number
from ...errors import FabricError
from ...figures import pyplot
from ..bending_friction import couple
from ..fabrics import Fabric, get_fabric
from ..settings import SolverSettings
from ..solver import GarmentSolver
from .common import (Progress, SolveInfo, _direction, _grain, _plain, _rect_mesh, _save, _say,
                     _solve, _solver_settings)

#: tip angle of Peirce's cantilever test (ASTM D1388) [deg]
PEIRCE_ANGLE = 41.5
#: the most triangles a cantilever strip is meshed with (its width is narrowed beyond) [-]
CANTILEVER_TRIANGLES = 20_000
#: the tip angles [deg] a reading is taken from: overhangs of 0.3-4 bending lengths
ELASTICA_ANGLES = (0.5, 77.0)


@lru_cache(maxsize=64)
def _elastica(lam: float):
    """The heavy inextensible elastica clamped horizontally: ``psi'' = -lam^3 (1 - s)
    cos psi`` on s in [0, 1], ``psi(0) = 0``, ``psi'(1) = 0`` (psi the slope below the
    horizontal, s the arc length over the overhang, ``lam`` = overhang / bending length)."""
    from scipy.integrate import solve_bvp

    q = lam ** 3
    s = np.linspace(0.0, 1.0, 201)
    if lam > 3.0:
        # a long overhang hangs nearly straight down from a short bend at the clamp, which
        # the polynomial guess misses beyond about 4 bending lengths (a strip with strong
        # bending friction is read there): started from a shorter overhang's shape
        guess = _elastica(round(lam / 1.2, 12)).sol(s)
    else:
        guess = np.vstack([q * (s / 2 - s ** 2 / 2 + s ** 3 / 6) * 0.5, np.zeros_like(s)])
    sol = solve_bvp(lambda s, y: np.vstack([y[1], -q * (1 - s) * np.cos(y[0])]),
                    lambda a, b: np.array([a[0], b[1]]), s, guess, tol=1e-9,
                    max_nodes=20000)
    if sol.status != 0:
        raise RuntimeError(f"elastica at overhang/c = {lam}: {sol.message}")
    return sol


@lru_cache(maxsize=256)
def elastica_tip_angle(ratio: float) -> float:
    """Chord angle below the horizontal [deg] from the clamp edge to the tip of a uniform
    heavy strip whose overhang is ``ratio`` bending lengths (exact elastica, by collocation;
    41.487 deg at ``ratio`` = 2, so Peirce's 41.5 deg rule reads the bending length to
    0.02 %)."""
    sol = _elastica(float(ratio))
    s = np.linspace(0.0, 1.0, 4001)
    psi = sol.sol(s)[0]
    x = np.trapezoid(np.cos(psi), s)
    y = np.trapezoid(np.sin(psi), s)
    return float(np.degrees(np.arctan2(y, x)))


def elastica_ratio(angle_deg: float) -> float | None:
    """Inverse of :func:`elastica_tip_angle`: overhang / bending length at which the tip
    chord is ``angle_deg`` below the horizontal (None outside 0.5-77 deg, i.e. overhangs of
    0.3-4 bending lengths)."""
    from scipy.optimize import brentq

    if not ELASTICA_ANGLES[0] <= angle_deg <= ELASTICA_ANGLES[1]:
        return None
    return float(brentq(lambda r: elastica_tip_angle(round(r, 12)) - angle_deg, 0.3, 4.0,
                        xtol=1e-9))


def _curvature(moment, eta: float, a: float, eps: float):
    """Curvature (dimensionless, times c) under the dimensionless moment ``moment`` >= 0 of
    the bending-friction law ``M = k + eta a k / sqrt(a^2 k^2 + eps^2)`` (bisection: the law
    rises at least as fast as k, and its friction part lies in [0, eta))."""
    m = np.maximum(np.asarray(moment, dtype=float), 0.0)
    lo, hi = np.maximum(m - eta, 0.0), m.copy()
    for _ in range(60):
        k = 0.5 * (lo + hi)
        over = k + eta * a * k / np.sqrt((a * k) ** 2 + eps ** 2) > m
        hi = np.where(over, k, hi)
        lo = np.where(over, lo, k)
    return 0.5 * (lo + hi)


@lru_cache(maxsize=256)
def friction_tip_angle(ratio: float, eta: float, a: float, eps: float) -> float:
    """Chord angle below the horizontal [deg] from the clamp edge to the tip of a heavy strip
    ``ratio`` bending lengths c = (B / (rho g))^(1/3) long whose moment is the model's
    bending law with friction (``sim.bending_friction``), loaded from flat:
    ``M = B kappa + HB a (a kappa) / sqrt((a kappa)^2 + eps^2)``, written in units of c and
    ``B / c``: ``eta = HB a c / B``, ``eps`` the stick band times c, ``a`` =
    ``(B_dir / B_geo)^(1/2)``. Without friction (``eta`` = 0) it is
    :func:`elastica_tip_angle`. By collocation on ``psi' = kappa(m)``,
    ``m' = -(ratio - s) cos psi``, ``psi(0) = 0``, ``m(ratio) = 0`` (s in bending lengths)."""
    from scipy.integrate import solve_bvp

    lam = float(ratio)
    s = np.linspace(0.0, lam, 401)
    # start from the frictionless elastica's shape (slopes scaled down by the friction)
    base = _elastica(lam).sol(s / lam)[0] / (1.0 + eta)
    guess = np.vstack([base, 0.5 * (lam - s) ** 2])
    sol = solve_bvp(
        lambda s, y: np.vstack([_curvature(y[1], eta, a, eps), -(lam - s) * np.cos(y[0])]),
        lambda y0, y1: np.array([y0[0], y1[1]]), s, guess, tol=1e-8, max_nodes=50000)
    if sol.status != 0:
        raise RuntimeError(f"cantilever with friction at overhang/c = {lam}: {sol.message}")
    grid = np.linspace(0.0, lam, 8001)
    psi = sol.sol(grid)[0]
    return float(np.degrees(np.arctan2(np.trapezoid(np.sin(psi), grid),
                                       np.trapezoid(np.cos(psi), grid))))


def expected_reading(fab: Fabric, direction: str) -> tuple[float, float]:
    """The bending length [m] Peirce's cantilever reads on ``fab`` along ``direction`` (half
    the overhang at which the tip's chord is at 41.5 deg, corrected to the exact elastica as
    the kit's readings are), and ``(B / (rho g))^(1/3)`` [m]. They are equal without bending
    friction; with it (KES-F 2HB) the strip stays straighter than B alone lets it, and the
    instrument reads a longer bending length, as it would on the real fabric."""
    from scipy.optimize import brentq

    rigidity = fab.bending_warp if direction == "warp" else fab.bending_weft
    c = fab.bending_length if direction == "warp" else fab.bending_length_weft
    law = couple(fab)
    if law is None:
        return c, c
    moment, b_geo, eps = law
    a = math.sqrt(rigidity / b_geo)
    eta, eps_c = moment * a * c / rigidity, eps * c
    target = elastica_ratio(PEIRCE_ANGLE)
    # the friction only stiffens: the overhang at 41.5 deg lies beyond the elastic one
    if friction_tip_angle(round(target, 12), eta, a, eps_c) >= PEIRCE_ANGLE:
        return c, c
    hi = target
    while friction_tip_angle(round(hi, 12), eta, a, eps_c) < PEIRCE_ANGLE:
        hi *= 1.5
        if hi > 50.0:
            raise FabricError(f"its bending friction (bending_hysteresis, KES 2HB) holds a "
                              f"strip straighter than {PEIRCE_ANGLE} deg at every overhang "
                              "up to 50 bending lengths: Peirce's cantilever cannot read it",
                              place=f"fabric '{fab.name}'")
    lam = brentq(lambda r: friction_tip_angle(round(r, 12), eta, a, eps_c) - PEIRCE_ANGLE,
                 target, hi, xtol=1e-9)
    return c * lam / target, c


def peirce_length(overhang: float, angle_deg: float) -> float | None:
    """Peirce's bending length from an overhang [m] and its tip angle [deg]:
    ``c = l (cos(theta/2) / (8 tan theta))^(1/3)`` [m] (an approximation of the elastica:
    1.9 % long at 41.5 deg). None outside :data:`ELASTICA_ANGLES`, where no reading is
    taken (a strip that hardly drooped gave metres)."""
    if not ELASTICA_ANGLES[0] <= angle_deg <= ELASTICA_ANGLES[1]:
        return None
    th = math.radians(angle_deg)
    return overhang * (math.cos(th / 2) / (8 * math.tan(th))) ** (1 / 3)


@dataclass(frozen=True)
class CantileverRun:
    """One simulated overhang.

    ``edge_m`` mesh edge [m], ``overhang_m`` [m], ``tip_angle_deg`` chord angle of the tip
    below the horizontal [deg], ``bending_length_m`` the bending length [m] the exact elastica
    gives for that overhang and angle (None if out of range), ``triangles``, ``solve``.
    """

    edge_m: float
    overhang_m: float
    tip_angle_deg: float
    bending_length_m: float | None
    triangles: int
    solve: SolveInfo

    def to_dict(self) -> dict:
        return _plain({**{f.name: getattr(self, f.name) for f in fields(self)
                          if f.name != "solve"}, "solve": self.solve.to_dict()})


@dataclass(frozen=True)
class CantileverMesh:
    """The ASTM reading at one mesh size: ``edge_m`` [m], ``triangles``, the final
    ``overhang_m`` [m] and ``tip_angle_deg`` [deg] of the search, ``bending_length_m`` [m]
    (that overhang read by the elastica; within the search tolerance it is half the overhang
    at 41.5 deg), ``astm_length_m`` = overhang / 2 [m] as the instrument reads it, and the
    ``runs`` of the search."""

    edge_m: float
    triangles: int
    overhang_m: float
    tip_angle_deg: float
    bending_length_m: float | None
    astm_length_m: float
    runs: tuple[CantileverRun, ...]

    def to_dict(self) -> dict:
        return _plain({**{f.name: getattr(self, f.name) for f in fields(self)
                          if f.name != "runs"}, "runs": [r.to_dict() for r in self.runs]})


@dataclass(frozen=True, eq=False)
class CantileverResult:
    """Peirce's cantilever (ASTM D1388) at several mesh sizes.

    Attributes
    ----------
    fabric, direction : str
        The strip runs along ``direction`` ("warp": the warp rigidity bends it).
    density_kg_m2, rigidity_n_m : float
        rho [kg/m^2] and the bending rigidity B along the strip [N m].
    bending_length_expected_m : float
        What the instrument should read [m]: ``(B / (rho g))^(1/3)``, or with bending
        friction (2HB) the longer reading of the exact strip under the model's friction law
        (:func:`expected_reading`).
    bending_length_elastic_m : float
        ``(B / (rho g))^(1/3)`` [m].
    bending_length_measured_m : float or None
        The finest mesh's reading [m].
    ratio : float or None
        measured / expected [-].
    peirce_length_m : float or None
        Peirce's formula on the finest mesh's final overhang and angle [m]; None when that
        solve did not end at rest or the angle is outside the elastica's range.
    overhang_m, tip_angle_deg : float
        The finest mesh's final overhang [m] and tip angle [deg].
    mesh_change : float or None
        |reading(finest) / reading(next finest) - 1| [-].
    meshes : tuple of CantileverMesh
        Coarse to fine.
    width_m : float
        Strip width [m].
    seconds : float
    tolerance : float
        Largest accepted |ratio - 1| [-].
    """

    fabric: str
    direction: str
    density_kg_m2: float
    rigidity_n_m: float
    bending_length_expected_m: float
    bending_length_elastic_m: float
    bending_length_measured_m: float | None
    ratio: float | None
    peirce_length_m: float | None
    overhang_m: float
    tip_angle_deg: float
    mesh_change: float | None
    meshes: tuple[CantileverMesh, ...]
    width_m: float
    seconds: float
    tolerance: float = 0.05
    #: the finest mesh's flat vertices, triangles and final positions [m] with
    #: ``keep_shape`` (not in ``to_dict``)
    shape: tuple | None = field(default=None, repr=False)

    @property
    def triangles(self) -> int:
        return self.meshes[-1].triangles

    @property
    def converged(self) -> bool:
        """Every mesh's reading comes from a solve at rest (stop rule met, equilibrium check
        passed). The search's earlier solves only choose the next overhang (the reading is
        the last one's, through the exact elastica), so one of them short of rest costs a
        solve, not the result; the JSON keeps how each ended."""
        return all(m.runs[-1].solve.at_rest for m in self.meshes)

    @property
    def failures(self) -> list[str]:
        """Why the test failed, in words (empty when it passed)."""
        out = [f"the {m.triangles}-triangle strip did not reach rest "
               f"({m.runs[-1].solve.describe()})"
               for m in self.meshes if not m.runs[-1].solve.at_rest]
        if len(self.meshes) == 1:
            out.append("one mesh: the reading is not shown to be mesh-converged (two meshes "
                       "or more, coarse to fine)")
        elif self.mesh_change is not None and self.mesh_change > self.tolerance:
            out.append(f"the reading moved by {100 * self.mesh_change:.1f} % from the "
                       f"{self.meshes[-2].triangles}-triangle strip to the finest: not "
                       f"mesh-converged (at most {100 * self.tolerance:g} %)")
        if self.ratio is None:
            out.append(f"tip angle {self.tip_angle_deg:.1f} deg, outside the elastica's "
                       "range: no bending length")
        elif abs(self.ratio - 1.0) > self.tolerance:
            out.append(f"bending length {1e3 * self.bending_length_measured_m:.3g} mm against "
                       f"{1e3 * self.bending_length_expected_m:.3g} mm expected, "
                       f"{100 * (self.ratio - 1.0):+.1f} % (tolerance "
                       f"{100 * self.tolerance:g} %)")
        return out

    @property
    def passed(self) -> bool:
        """Every reading's solve ended at rest, the finest reading is within ``tolerance``
        and moved by no more than that from the next finest mesh's (two meshes at least)."""
        return not self.failures

    def to_dict(self) -> dict:
        d = {f.name: getattr(self, f.name) for f in fields(self)
             if f.name not in ("meshes", "shape")}
        last = self.meshes[-1].runs[-1].solve
        return _plain({"test": "cantilever", **d, "triangles": self.triangles,
                       "mesh_edges_m": [m.edge_m for m in self.meshes],
                       "mesh_triangles": [m.triangles for m in self.meshes],
                       "meshes": [m.to_dict() for m in self.meshes],
                       "residual": last.residual, "stop_reason": last.stop_reason,
                       "converged": self.converged, "passed": self.passed,
                       "failures": self.failures})


def _cantilever_run(fab: Fabric, direction: str, overhang: float, mesh, settings):
    """Solve the strip ``mesh`` = (flat vertices, triangles, its overhang) scaled to
    ``overhang`` [m]: the clamp is x <= 0, the tip the edge x = overhang."""
    v0, t, base = mesh
    v = v0 * (overhang / base)
    pinned = np.flatnonzero(v0[:, 0] <= 1e-12)
    tip = np.flatnonzero(v0[:, 0] >= base - 1e-12)
    solver = GarmentSolver(v, t, _grain(direction, len(t)), fab, pinned=pinned,
                           settings=settings)
    # flat and horizontal: x along the strip, the width along z, gravity along -y
    res = _solve(solver, np.c_[v[:, 0], np.zeros(len(v)), v[:, 1]])
    x = res.x
    angle = float(np.degrees(np.arctan2(-x[tip, 1].mean(), x[tip, 0].mean())))
    ratio = elastica_ratio(angle)
    h = float(np.median(np.linalg.norm(v[t[:, 1]] - v[t[:, 0]], axis=1)))
    return CantileverRun(edge_m=h, overhang_m=overhang, tip_angle_deg=angle,
                         bending_length_m=None if ratio is None else overhang / ratio,
                         triangles=len(t), solve=SolveInfo.of(res, settings)), (v, t, x)


def cantilever_test(fabric: Fabric | str = "cotton_shirting", *, direction: str = "warp",
                    meshes=(6, 12, 24), width: float | None = None,
                    angle_tol: float = 0.25, max_runs: int = 4,
                    settings: SolverSettings | None = None,
                    progress: Progress | None = None, keep_shape: bool = False
                    ) -> CantileverResult:
    """Peirce's cantilever test (ASTM D1388) of ``fabric`` along ``direction``.

    A strip, clamped flat for x <= 0 (the platform; its vertices pinned), overhangs the edge
    by ``l``; the solver finds its rest shape under gravity and the tip's chord angle below
    the horizontal is read. The overhang is searched until that angle is 41.5 deg within
    ``angle_tol`` [deg] (at most ``max_runs`` solves; the next overhang is the one at which
    an exact elastica of the bending length just read would reach 41.5 deg, i.e. a secant
    step in the elastica's own variable), starting from twice the expected bending length.
    The bending length of the last overhang is read with the exact elastica (so the search
    tolerance does not enter); the instrument's reading, overhang / 2, is reported beside
    it. Run at each mesh size in ``meshes`` (edges per bending length (B / (rho g))^(1/3),
    coarse to fine); the finest gives the result and ``mesh_change`` says how far the last
    two differ. The reading is held against :func:`expected_reading`: the elastic bending
    length, or for a fabric with bending friction (2HB) what the same test reads on the exact
    strip under the model's friction law.

    ``width``: strip width [m] (default 25 mm, ASTM D1388's strip; the membrane has no
    Poisson coupling, so the width changes the bending only through the mesh; narrowed where
    the finest mesh would have more than :data:`CANTILEVER_TRIANGLES` triangles).
    ``keep_shape``: keep the finest mesh's final shape for :func:`write_cantilever_picture`.
    """
    t0 = time.perf_counter()
    fab = get_fabric(fabric)
    direction = _direction(direction)
    rigidity = fab.bending_warp if direction == "warp" else fab.bending_weft
    reading, expected = expected_reading(fab, direction)
    width = number(width if width is not None else 0.025, "width", low=1e-3,
                   high=1.0)
    sizes = [number(m, "meshes", low=2, high=60, rule="edges per bending length in 2-60")
             for m in meshes]
    if not sizes:
        raise ValueError("meshes: at least one mesh size")
    # a fabric with a short bending length would make a 25 mm strip huge at the finest
    # mesh: the strip is narrowed to keep it under CANTILEVER_TRIANGLES
    h_min = expected / max(sizes)
    # (Triangle's quality meshes come out ~1.6 times finer than the area bound says)
    width = min(width, CANTILEVER_TRIANGLES * math.sqrt(3) / 4 * h_min ** 2
                / (1.6 * (2.4 * reading + 3 * h_min)))
    # a strip bent under its own weight is bending-dominated: Newton's preconditioner keeps
    # the bending across the edges, or the fine strips creep (docs/fabrics.md)
    settings = _solver_settings(settings, self_collision=False,
                                newton_bending_preconditioner=True)
    target_ratio = elastica_ratio(PEIRCE_ANGLE)
    out, shape = [], None
    for per in sizes:
        h = expected / per
        overhang = 2.0 * reading
        clamp = max(3 * h, 0.2 * overhang)
        v, t = _rect_mesh(overhang + clamp, width, h, x0=-clamp, breaks=(0.0,))
        mesh = (v, t, overhang)
        runs = []
        for _ in range(max_runs):
            _say(progress, f"cantilever: edge {h * 1e3:.1f} mm, overhang "
                           f"{overhang * 1e3:.1f} mm")
            run, shape = _cantilever_run(fab, direction, overhang, mesh, settings)
            runs.append(run)
            if run.bending_length_m is None or abs(run.tip_angle_deg - PEIRCE_ANGLE) <= angle_tol:
                break
            overhang = target_ratio * run.bending_length_m
        last = runs[-1]
        out.append(CantileverMesh(edge_m=run.edge_m, triangles=last.triangles,
                                  overhang_m=last.overhang_m, tip_angle_deg=last.tip_angle_deg,
                                  bending_length_m=last.bending_length_m,
                                  astm_length_m=last.overhang_m / 2, runs=tuple(runs)))
    fin = out[-1]
    measured = fin.bending_length_m
    change = None
    if len(out) > 1 and measured is not None and out[-2].bending_length_m:
        change = abs(measured / out[-2].bending_length_m - 1.0)
    return CantileverResult(
        fabric=fab.name, direction=direction, density_kg_m2=fab.density, rigidity_n_m=rigidity,
        bending_length_expected_m=reading, bending_length_elastic_m=expected,
        bending_length_measured_m=measured,
        ratio=None if measured is None else measured / reading,
        # a strip short of rest has no angle to read: its formula length said nothing
        peirce_length_m=(peirce_length(fin.overhang_m, fin.tip_angle_deg)
                         if fin.runs[-1].solve.at_rest else None),
        overhang_m=fin.overhang_m, tip_angle_deg=fin.tip_angle_deg, mesh_change=change,
        meshes=tuple(out), width_m=width, seconds=time.perf_counter() - t0,
        shape=shape if keep_shape else None)


def write_cantilever_picture(result: CantileverResult, path) -> Path:
    """Side view of the finest mesh's final strip (``cantilever_test(..., keep_shape=True)``)
    with the platform and the 41.5 deg line; returns the path."""
    plt = pyplot()

    shape = result.shape
    if shape is None:
        raise ValueError("result: run cantilever_test(..., keep_shape=True) for a picture")
    v, t, x = shape
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.triplot(x[:, 0] * 1e3, x[:, 1] * 1e3, t, color="tab:blue", lw=0.3)
    lo = v[:, 0].min() * 1e3
    ax.fill_between([lo, 0.0], [-3, -3], [0, 0], color="0.6")
    ell = result.overhang_m * 1e3
    a = math.radians(PEIRCE_ANGLE)
    ax.plot([0, ell * math.cos(a)], [0, -ell * math.sin(a)], "r--", lw=0.8,
            label=f"{PEIRCE_ANGLE}°")
    ax.set_aspect("equal")
    ax.set_xlabel("mm")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(f"cantilever, {result.fabric} ({result.direction}): overhang {ell:.1f} mm, "
                 f"tip {result.tip_angle_deg:.2f}°\nbending length "
                 f"{(result.bending_length_measured_m or 0) * 1e3:.2f} mm measured, "
                 f"{result.bending_length_expected_m * 1e3:.2f} mm expected"
                 + ("" if result.bending_length_expected_m == result.bending_length_elastic_m
                    else f"\nwith its bending friction "
                         f"({result.bending_length_elastic_m * 1e3:.2f} mm without)"),
                 fontsize=9)
    try:
        return _save(fig, path)
    finally:
        plt.close(fig)
