"""A virtual fabric-testing kit: the three bench tests a fabric is measured with, run on the
static solver (``GarmentSolver``) and compared with what the fabric's constants predict.

- :func:`strip_test`: a strip hanging from its clamped top edge stretches under its own weight
  by ``rho g L^2 / (2 k)``.
- :func:`cantilever_test`: Peirce's cantilever (ASTM D1388): the overhang at which the tip has
  bent down 41.5 deg is twice the bending length ``c = (B / (rho g))^(1/3)``; run at several
  mesh sizes.
- :func:`cusick_test`: the drape test (BS 5058 / ISO 9073-9): a circular specimen clamped on a
  smaller disc, its drape coefficient and its number of nodes (folds), from several slightly
  perturbed flat starts.

Units: metres, kilograms, seconds, newtons; ``y`` is up. Every function returns a plain result
dataclass whose ``to_dict()`` is JSON-ready (no NaN: a value that could not be measured is
None). See docs/fabrics.md, "Testing a fabric".
"""

from __future__ import annotations

import io
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field, fields, is_dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np
import triangle as tr

from ..arguments import number
from ..constants import GRAVITY
from ..files import atomic_write_bytes
from ..geometry import counter_clockwise, polygon_area, triangle_areas
from .fabrics import Fabric, get_fabric
from .result import DrapeResult
from .settings import SolverSettings
from .solver import GarmentSolver

#: tip angle of Peirce's cantilever test (ASTM D1388) [deg]
PEIRCE_ANGLE = 41.5
#: Cusick drape tester: specimen and support disc diameters of BS 5058 / ISO 9073-9 [m]
CUSICK_SPECIMEN = 0.30
CUSICK_DISC = 0.18
#: the most triangles a cantilever strip is meshed with (its width is narrowed beyond) [-]
CANTILEVER_TRIANGLES = 20_000

Progress = Callable[[str], None]


# ------------------------------------------------------------------------------ helpers


def _quality_mesh(points, segments, max_area: float, *, holes=None):
    """Constrained quality Delaunay mesh (angles >= 30 deg, no Steiner points on the given
    segments) of a planar straight-line graph: (vertices (n, 2), ccw triangles (m, 3))."""
    data = {"vertices": np.asarray(points, float), "segments": np.asarray(segments, np.int64)}
    if holes is not None:
        data["holes"] = holes
    out = tr.triangulate(data, f"pq30a{max_area:.15f}YQ")
    v = out["vertices"].astype(float)
    return v, counter_clockwise(v, out["triangles"].astype(np.int64))


def _ring(radius: float, count: int, phase: float = 0.0) -> np.ndarray:
    a = phase + 2 * np.pi * np.arange(count) / count
    return radius * np.c_[np.cos(a), np.sin(a)]


def _loop_segments(start: int, count: int) -> np.ndarray:
    idx = start + np.arange(count)
    return np.c_[idx, np.roll(idx, -1)]


def _rect_mesh(length: float, width: float, h: float, *, x0: float = 0.0, breaks=()):
    """The rectangle [x0, x0 + length] x [0, width] meshed with edges about ``h`` [m]; the
    long sides are sampled every ``h`` and split at every x in ``breaks`` (so that a clamp
    line is a mesh line)."""
    xs = np.linspace(x0, x0 + length, max(2, round(length / h)) + 1)
    cuts = [b for b in breaks if x0 + h / 3 < b < x0 + length - h / 3]
    for b in cuts:  # a sample near a break moves onto it (no sliver beside the clamp line)
        xs[np.argmin(np.abs(xs - b))] = b
    ny = max(1, round(width / h))
    ys = np.linspace(0.0, width, ny + 1)
    pts = np.r_[np.c_[xs, np.zeros(len(xs))], np.c_[np.full(ny - 1, xs[-1]), ys[1:-1]],
                np.c_[xs[::-1], np.full(len(xs), width)], np.c_[np.full(ny - 1, xs[0]),
                                                               ys[-2:0:-1]]]
    seg = _loop_segments(0, len(pts))
    # interior lines at the breaks keep the clamp edge straight
    extra = []
    for b in cuts:
        i = int(np.flatnonzero((pts[:, 0] == b) & (pts[:, 1] == 0.0))[0])
        j = int(np.flatnonzero((pts[:, 0] == b) & (pts[:, 1] == width))[0])
        extra.append([i, j])
    if extra:
        seg = np.r_[seg, np.array(extra)]
    return _quality_mesh(pts, seg, math.sqrt(3) / 4 * h * h)


def _grain(direction: str, m: int, *, along=(1.0, 0.0)) -> np.ndarray:
    """Per-triangle warp directions (m, 2): the warp along ``along`` for a warp test, across
    it for a weft test."""
    a = np.asarray(along, float)
    g = a if direction == "warp" else np.array([-a[1], a[0]])
    return np.tile(g, (m, 1))


def _direction(direction: str) -> str:
    d = str(direction).strip().lower()
    if d not in ("warp", "weft"):
        raise ValueError(f"direction: expected 'warp' or 'weft', got {direction!r}")
    return d


#: what the kit asks of the solver when no settings are given: a test is read at rest, so
#: the force stop rule (residual |F_i| / (m_i g) rms <= 0.01, p99 <= 0.1) and the full
#: stretch stiffness in compression (both the solver's defaults, stated here so that the kit
#: reads its tests at rest whatever the defaults): with 5 % kept, 20-75 % of a drape test's
#: free area shrank by more than 1 % instead of folding (docs/fabrics.md, "Published drape
#: tests")
AT_REST = {"stop": "force", "compression": 1.0}


def kit_settings(**changes) -> SolverSettings:
    """The solver settings the kit uses by default (:data:`AT_REST` over the solver's
    defaults) with ``changes`` (SolverSettings fields, e.g. ``compression=0.05``) applied.
    Raises ValueError naming an unknown field."""
    known = {f.name for f in fields(SolverSettings)}
    for key, value in changes.items():
        if key not in known:
            raise ValueError(f"settings: unknown solver setting {key!r} (known: "
                             f"{', '.join(sorted(known))})")
        if isinstance(value, float):
            number(value, f"settings {key}")
    return _solver_settings(None, **changes)


def settings_from_pairs(pairs) -> SolverSettings:
    """:func:`kit_settings` from ``KEY=VALUE`` texts (``true``/``false``, a number, or
    text), as the CLI's ``--set`` and the benchmark's ``--setting`` give them. Raises
    ValueError naming the malformed pair or the unknown setting."""
    values = {}
    for item in pairs:
        key, eq, text = str(item).partition("=")
        key, text = key.strip(), text.strip()
        if not eq or not key:
            raise ValueError(f"expected KEY=VALUE, got {item!r}")
        if text.lower() in ("true", "false"):
            values[key] = text.lower() == "true"
            continue
        try:
            values[key] = int(text)
        except ValueError:
            try:
                values[key] = float(text)
            except ValueError:
                values[key] = text
    return kit_settings(**values)


def _solver_settings(settings: SolverSettings | None, **changes) -> SolverSettings:
    """``settings`` (default: the solver's defaults with :data:`AT_REST`) with ``changes``
    applied, each only where the settings have such a field (the solver's knobs are being
    reworked; unknown ones are left out rather than guessed)."""
    if settings is None:
        settings = SolverSettings()
        changes = {**AT_REST, **changes}
    known = {f.name for f in fields(settings)}
    values = {f.name: getattr(settings, f.name) for f in fields(settings)}
    values.update({k: v for k, v in changes.items() if k in known})
    return SolverSettings(**values)


def _plain(value):
    """A JSON-ready copy of ``value`` with non-finite floats as None."""
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.ndarray):
        return [_plain(v) for v in value.tolist()]
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if hasattr(value, "to_dict"):
        return _plain(value.to_dict())
    if is_dataclass(value):
        return _plain({f.name: getattr(value, f.name) for f in fields(value)})
    return str(value)


def residual_of(result: DrapeResult):
    """The force residual the solver reports for its final state, if its result carries one
    (an attribute whose name holds ``residual``, on the result or its checks), else None."""
    for holder in (result, getattr(result, "checks", None)):
        if holder is None:
            continue
        names = ([f.name for f in fields(holder)] if is_dataclass(holder)
                 else [n for n in dir(holder) if not n.startswith("_")])
        found = {n: getattr(holder, n) for n in names if "residual" in n}
        if found:
            return _plain(found if len(found) > 1 else next(iter(found.values())))
    return None


def _balanced(residual, settings) -> bool | None:
    """Whether a reported residual meets the force balance of ``settings`` (its
    ``residual_rms`` / ``residual_p99`` fields, 0.01 and 0.1 where it has none): None when
    no residual was reported."""
    if not isinstance(residual, dict):
        return None
    rms, p99 = residual.get("residual_rms"), residual.get("residual_p99")
    if rms is None and p99 is None:
        return None
    ok = True
    if rms is not None:
        ok &= rms <= getattr(settings, "residual_rms", 0.01)
    if p99 is not None:
        ok &= p99 <= getattr(settings, "residual_p99", 0.1)
    return bool(ok)


@dataclass(frozen=True)
class SolveInfo:
    """How one solve ended: iterations, seconds [s], ``converged`` (the solver's stop rule
    was met), ``equilibrium`` (its checks say the state is at rest), the stop reason, the
    force residual the result reports (None when it carries none) and ``balanced``: whether
    that residual meets the settings' force balance (rms <= 0.01, p99 <= 0.1; None without
    a residual)."""

    iterations: int
    seconds: float
    converged: bool
    equilibrium: bool
    stop_reason: str
    residual: object = None
    balanced: bool | None = None

    @classmethod
    def of(cls, res: DrapeResult, settings=None) -> SolveInfo:
        residual = residual_of(res)
        return cls(int(res.iterations), float(res.seconds), bool(res.converged),
                   bool(res.checks.equilibrium), str(res.stop_reason), residual,
                   _balanced(residual, settings))

    @property
    def at_rest(self) -> bool:
        """Stop rule met, equilibrium check passed and, where known, forces balanced."""
        return self.converged and self.equilibrium and self.balanced is not False

    def to_dict(self) -> dict:
        return _plain({"iterations": self.iterations, "seconds": self.seconds,
                       "converged": self.converged, "equilibrium": self.equilibrium,
                       "stop_reason": self.stop_reason, "residual": self.residual,
                       "balanced": self.balanced, "at_rest": self.at_rest})


def _say(progress: Progress | None, text: str) -> None:
    if progress is not None:
        progress(text)


# ------------------------------------------------------------------------ strip (stretch)


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
    def passed(self) -> bool:
        """The solve ended at rest and the stretch is within ``tolerance`` of the analytic
        one."""
        return bool(self.solve.at_rest and self.ratio is not None
                    and abs(self.ratio - 1.0) <= self.tolerance)

    def to_dict(self) -> dict:
        d = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "solve"}
        return _plain({"test": "strip", **d, "solve": self.solve.to_dict(),
                       "residual": self.solve.residual, "stop_reason": self.solve.stop_reason,
                       "converged": self.solve.at_rest, "passed": self.passed})


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
    res = solver.solve(np.c_[v, np.zeros(len(v))])
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


# ---------------------------------------------------------------- cantilever (bending)


def _elastica(lam: float):
    """The heavy inextensible elastica clamped horizontally: ``psi'' = -lam^3 (1 - s)
    cos psi`` on s in [0, 1], ``psi(0) = 0``, ``psi'(1) = 0`` (psi the slope below the
    horizontal, s the arc length over the overhang, ``lam`` = overhang / bending length)."""
    from scipy.integrate import solve_bvp

    q = lam ** 3
    s = np.linspace(0.0, 1.0, 201)
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

    if not 0.5 <= angle_deg <= 77.0:
        return None
    return float(brentq(lambda r: elastica_tip_angle(round(r, 12)) - angle_deg, 0.3, 4.0,
                        xtol=1e-9))


def peirce_length(overhang: float, angle_deg: float) -> float | None:
    """Peirce's bending length from an overhang [m] and its tip angle [deg]:
    ``c = l (cos(theta/2) / (8 tan theta))^(1/3)`` [m] (an approximation of the elastica:
    1.9 % long at 41.5 deg)."""
    th = math.radians(angle_deg)
    if not 0.0 < th < math.pi / 2:
        return None
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
        ``(B / (rho g))^(1/3)`` [m].
    bending_length_measured_m : float or None
        The finest mesh's reading [m].
    ratio : float or None
        measured / expected [-].
    peirce_length_m : float or None
        Peirce's formula on the finest mesh's final overhang and angle [m].
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
        """Every solve ended at rest (stop rule met, equilibrium check passed)."""
        return all(r.solve.at_rest for m in self.meshes for r in m.runs)

    @property
    def passed(self) -> bool:
        """Every solve ended at rest and the finest reading is within ``tolerance``."""
        return bool(self.converged and self.ratio is not None
                    and abs(self.ratio - 1.0) <= self.tolerance)

    def to_dict(self) -> dict:
        d = {f.name: getattr(self, f.name) for f in fields(self)
             if f.name not in ("meshes", "shape")}
        last = self.meshes[-1].runs[-1].solve
        return _plain({"test": "cantilever", **d, "triangles": self.triangles,
                       "mesh_edges_m": [m.edge_m for m in self.meshes],
                       "mesh_triangles": [m.triangles for m in self.meshes],
                       "meshes": [m.to_dict() for m in self.meshes],
                       "residual": last.residual, "stop_reason": last.stop_reason,
                       "converged": self.converged, "passed": self.passed})


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
    res = solver.solve(np.c_[v[:, 0], np.zeros(len(v)), v[:, 1]])
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
    it. Run at each mesh size in ``meshes`` (edges per expected bending length, coarse to
    fine); the finest gives the result and ``mesh_change`` says how far the last two differ.

    ``width``: strip width [m] (default 25 mm, ASTM D1388's strip; the membrane has no
    Poisson coupling, so the width changes the bending only through the mesh; narrowed where
    the finest mesh would have more than :data:`CANTILEVER_TRIANGLES` triangles).
    ``keep_shape``: keep the finest mesh's final shape for :func:`write_cantilever_picture`.
    """
    t0 = time.perf_counter()
    fab = get_fabric(fabric)
    direction = _direction(direction)
    rigidity = fab.bending_warp if direction == "warp" else fab.bending_weft
    expected = (rigidity / (fab.density * GRAVITY)) ** (1 / 3)
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
                / (1.6 * (2.4 * expected + 3 * h_min)))
    settings = _solver_settings(settings, self_collision=False)
    target_ratio = elastica_ratio(PEIRCE_ANGLE)
    out, shape = [], None
    for per in sizes:
        h = expected / per
        overhang = 2.0 * expected
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
        bending_length_expected_m=expected, bending_length_measured_m=measured,
        ratio=None if measured is None else measured / expected,
        peirce_length_m=peirce_length(fin.overhang_m, fin.tip_angle_deg),
        overhang_m=fin.overhang_m, tip_angle_deg=fin.tip_angle_deg, mesh_change=change,
        meshes=tuple(out), width_m=width, seconds=time.perf_counter() - t0,
        shape=shape if keep_shape else None)


# ---------------------------------------------------------------------- Cusick (drape)


def _disc_mesh(r_specimen: float, r_disc: float, triangles: int):
    """A disc of radius ``r_specimen`` with the support circle ``r_disc`` as a mesh line,
    meshed to about ``triangles`` triangles: (vertices (n, 2), triangles (m, 3), disc outline
    (k, 2))."""
    area = math.pi * r_specimen ** 2
    h = math.sqrt(4 * area / (math.sqrt(3) * triangles))
    for _ in range(4):
        n_out = max(12, round(2 * math.pi * r_specimen / h))
        n_in = max(8, round(2 * math.pi * r_disc / h))
        outer, inner = _ring(r_specimen, n_out), _ring(r_disc, n_in)
        pts = np.r_[outer, inner]
        seg = np.r_[_loop_segments(0, n_out), _loop_segments(n_out, n_in)]
        v, t = _quality_mesh(pts, seg, math.sqrt(3) / 4 * h * h)
        ratio = len(t) / triangles
        if abs(ratio - 1.0) < 0.05:
            break
        h *= math.sqrt(ratio)
    return v, t, inner


def shadow_area(x2: np.ndarray, tris: np.ndarray, pixel: float) -> tuple[float, np.ndarray,
                                                                          tuple]:
    """Area [m^2] of the union of the 2D triangles ``x2[tris]`` by sampling pixel centres
    (side ``pixel`` [m]); also the mask and its (x0, y0) origin."""
    lo = x2.min(axis=0) - 2 * pixel
    hi = x2.max(axis=0) + 2 * pixel
    nx, ny = (np.ceil((hi - lo) / pixel)).astype(int)
    mask = np.zeros((ny, nx), bool)
    P = x2[tris]  # (m, 3, 2)
    # pixel index ranges of each triangle's box
    i0 = np.floor((P[:, :, 0].min(axis=1) - lo[0]) / pixel).astype(int)
    i1 = np.ceil((P[:, :, 0].max(axis=1) - lo[0]) / pixel).astype(int)
    j0 = np.floor((P[:, :, 1].min(axis=1) - lo[1]) / pixel).astype(int)
    j1 = np.ceil((P[:, :, 1].max(axis=1) - lo[1]) / pixel).astype(int)
    for k in range(len(tris)):
        a, b, c = P[k]
        det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
        if abs(det) < 1e-18:
            continue
        xs = lo[0] + (np.arange(i0[k], i1[k]) + 0.5) * pixel
        ys = lo[1] + (np.arange(j0[k], j1[k]) + 0.5) * pixel
        X, Y = np.meshgrid(xs, ys)
        l1 = ((b[1] - c[1]) * (X - c[0]) + (c[0] - b[0]) * (Y - c[1])) / det
        l2 = ((c[1] - a[1]) * (X - c[0]) + (a[0] - c[0]) * (Y - c[1])) / det
        inside = (l1 >= 0) & (l2 >= 0) & (l1 + l2 <= 1)
        mask[j0[k]:j1[k], i0[k]:i1[k]] |= inside
    return float(mask.sum()) * pixel * pixel, mask, (float(lo[0]), float(lo[1]))


def count_nodes(radius: np.ndarray, *, prominence: float) -> int:
    """Number of folds (nodes) of a drape from the projected radius [m] of its hem, in
    order around it: peaks of the periodic profile standing at least ``prominence`` [m]
    above the troughs on both sides."""
    from scipy.signal import find_peaks

    r = np.asarray(radius, float)
    if len(r) < 3 or np.ptp(r) < prominence:
        return 0
    start = int(np.argmin(r))
    ring = np.r_[r[start:], r[:start], r[start]]  # starts and ends at the lowest point
    peaks, _ = find_peaks(ring, prominence=prominence)
    return len(peaks)


@dataclass(frozen=True)
class CusickRun:
    """One start (``seed``) of the drape test: ``drape_coefficient`` [-], ``nodes``,
    ``shadow_area_m2`` [m^2], ``hem_radius_min_m`` / ``hem_radius_max_m`` projected radius of
    the hem [m], ``hem_drop_m`` mean drop of the hem below the disc [m],
    ``compressed_share`` share of the free area whose triangles shrank by more than 1 %
    (cloth that shrinks instead of folding, METHOD.md 5.2), ``crossings`` crossed triangle
    pairs, ``solve``."""

    seed: int
    drape_coefficient: float
    nodes: int
    shadow_area_m2: float
    hem_radius_min_m: float
    hem_radius_max_m: float
    hem_drop_m: float
    compressed_share: float
    crossings: int
    solve: SolveInfo

    def to_dict(self) -> dict:
        return _plain({**{f.name: getattr(self, f.name) for f in fields(self)
                          if f.name != "solve"}, "solve": self.solve.to_dict()})


@dataclass(frozen=True, eq=False)
class CusickResult:
    """The Cusick drape test (BS 5058 / ISO 9073-9) from several perturbed flat starts.

    Attributes
    ----------
    fabric : str
    specimen_diameter_m, disc_diameter_m : float
        [m].
    drape_coefficient : float
        Mean over the starts of ``DC = (A_shadow - A_disc) / (A_specimen - A_disc)`` [-]
        (A_shadow: area of the vertical projection; 0 limp, 1 rigid).
    drape_coefficient_spread : float
        max - min over the starts [-].
    drape_coefficient_std : float
        Standard deviation over the starts [-].
    nodes : float
        Mean number of nodes (folds) [-].
    nodes_min, nodes_max : int
    runs : tuple of CusickRun
    triangles, vertices : int
    perturbation_m : float
        RMS height of the random perturbation of the flat start at the hem [m].
    pixel_m : float
        Pixel of the shadow raster [m].
    seconds : float
    positions : list of (n, 3) arrays
        Final shape of each start [m] (not in ``to_dict``).
    rest, mesh_triangles : arrays
        The flat specimen [m] and its triangles (not in ``to_dict``).
    """

    fabric: str
    specimen_diameter_m: float
    disc_diameter_m: float
    drape_coefficient: float
    drape_coefficient_spread: float
    drape_coefficient_std: float
    nodes: float
    nodes_min: int
    nodes_max: int
    runs: tuple[CusickRun, ...]
    triangles: int
    vertices: int
    perturbation_m: float
    pixel_m: float
    seconds: float
    positions: list = field(default_factory=list, repr=False)
    rest: np.ndarray | None = field(default=None, repr=False)
    mesh_triangles: np.ndarray | None = field(default=None, repr=False)

    @property
    def converged(self) -> bool:
        """Every start ended at rest (stop rule met, equilibrium check passed)."""
        return all(r.solve.at_rest for r in self.runs)

    @property
    def passed(self) -> bool:
        """Every start ended at rest without crossings and every DC lies in [0, 1]."""
        return bool(self.converged and all(r.crossings == 0 and 0.0 <= r.drape_coefficient <= 1.0
                                           for r in self.runs))

    def to_dict(self) -> dict:
        skip = {"runs", "positions", "rest", "mesh_triangles"}
        d = {f.name: getattr(self, f.name) for f in fields(self) if f.name not in skip}
        return _plain({"test": "cusick", **d, "seeds": [r.seed for r in self.runs],
                       "drape_coefficients": [r.drape_coefficient for r in self.runs],
                       "nodes_each": [r.nodes for r in self.runs],
                       "runs": [r.to_dict() for r in self.runs],
                       "residual": [r.solve.residual for r in self.runs],
                       "stop_reasons": [r.solve.stop_reason for r in self.runs],
                       "converged": self.converged, "passed": self.passed})


def _perturbation(v: np.ndarray, r_disc: float, r_spec: float, amplitude: float,
                  seed: int) -> np.ndarray:
    """Heights [m] of a slightly wavy flat specimen: zero on the disc, growing as
    ((r - r_disc) / (r_spec - r_disc))^2 towards the hem, random angular waves 2-12 and a
    little per-vertex noise; RMS ``amplitude`` at the hem."""
    rng = np.random.default_rng(seed)
    r = np.hypot(v[:, 0], v[:, 1])
    th = np.arctan2(v[:, 1], v[:, 0])
    ks = np.arange(2, 13)
    a, b = rng.standard_normal((2, len(ks)))
    wave = (a[None] * np.cos(ks[None] * th[:, None]) + b[None] * np.sin(ks[None] * th[:, None]))
    wave = wave.sum(axis=1) / math.sqrt(len(ks))  # unit RMS
    noise = 0.3 * rng.standard_normal(len(v))
    ramp = np.clip((r - r_disc) / (r_spec - r_disc), 0.0, 1.0) ** 2
    return amplitude * ramp * (wave + noise) / math.sqrt(1.09)


def cusick_test(fabric: Fabric | str = "cotton_shirting", *, specimen: float = CUSICK_SPECIMEN,
                disc: float = CUSICK_DISC, triangles: int = 4000, seeds=(0, 1, 2, 3, 4),
                perturbation: float = 2e-3, pixel: float = 5e-4,
                settings: SolverSettings | None = None,
                progress: Progress | None = None) -> CusickResult:
    """The Cusick drape test of ``fabric``: a circular specimen of diameter ``specimen`` [m]
    clamped between two discs of diameter ``disc`` [m] (every vertex within the disc radius
    is pinned; the disc edge is a circle of mesh vertices), draped under gravity to rest by
    the static solver from each of the flat starts perturbed by ``seeds`` (random waves of
    RMS ``perturbation`` [m] at the hem), meshed with about ``triangles`` triangles.

    Reads, per start: DC = (A_shadow - A_disc) / (A_specimen - A_disc), the shadow being the
    vertical projection rasterised at ``pixel`` [m] (pixel centres; A_specimen and A_disc are
    the areas of the flat mesh and of its disc polygon, so a rigid specimen reads 1 and a limp
    one 0), and the number of nodes: the peaks of the hem's projected radius that stand
    above their neighbouring troughs by at least 10 % of its range and 2 mm.
    """
    t0 = time.perf_counter()
    fab = get_fabric(fabric)
    specimen = number(specimen, "specimen", low=0.02, high=2.0)
    disc = number(disc, "disc", low=0.005, high=2.0)
    if not disc < specimen:
        raise ValueError(f"disc: the disc ({disc} m) must be smaller than the specimen "
                         f"({specimen} m)")
    triangles = int(number(triangles, "triangles", low=50, high=200_000))
    seeds = [int(number(s, "seeds", low=0, high=2**31)) for s in seeds]
    if not seeds:
        raise ValueError("seeds: at least one")
    number(perturbation, "perturbation", low=0.0, high=0.05)
    number(pixel, "pixel", low=1e-5, high=0.01)
    r_spec, r_disc = specimen / 2, disc / 2
    v, t, ring = _disc_mesh(r_spec, r_disc, triangles)
    r = np.hypot(v[:, 0], v[:, 1])
    pinned = np.flatnonzero(r <= r_disc + 1e-9)
    hem = np.flatnonzero(r >= r_spec - 1e-9)
    hem = hem[np.argsort(np.arctan2(v[hem, 1], v[hem, 0]))]
    a_spec = float(triangle_areas(v, t).sum())
    a_disc = abs(polygon_area(ring))
    rest_area = triangle_areas(v, t)
    free_tri = (r[t] > r_disc + 1e-9).any(axis=1)
    solver_settings = _solver_settings(settings)
    runs, positions = [], []
    for i, seed in enumerate(seeds):
        _say(progress, f"cusick: start {i + 1}/{len(seeds)} (seed {seed}), {len(t)} triangles")
        solver = GarmentSolver(v, t, _grain("warp", len(t)), fab, pinned=pinned,
                               settings=solver_settings)
        # flat specimen at y = 0 (the disc's top), x and z in its plane
        x0 = np.c_[v[:, 0], _perturbation(v, r_disc, r_spec, perturbation, seed), v[:, 1]]
        res = solver.solve(x0)
        x = res.x
        if not np.isfinite(x).all():
            raise RuntimeError(f"cusick: the solver returned non-finite positions (seed {seed}, "
                               f"stop reason {res.stop_reason})")
        shadow, _, _ = shadow_area(x[:, [0, 2]], t, pixel)
        dc = (shadow - a_disc) / (a_spec - a_disc)
        hem_r = np.hypot(x[hem, 0], x[hem, 2])
        prom = max(0.1 * float(np.ptp(hem_r)), 2e-3)
        area3 = triangle_areas(x, t)
        shrunk = free_tri & (area3 < 0.99 * rest_area)
        runs.append(CusickRun(
            seed=seed, drape_coefficient=float(dc), nodes=count_nodes(hem_r, prominence=prom),
            shadow_area_m2=shadow, hem_radius_min_m=float(hem_r.min()),
            hem_radius_max_m=float(hem_r.max()), hem_drop_m=float(-x[hem, 1].mean()),
            compressed_share=float(rest_area[shrunk].sum() / rest_area[free_tri].sum()),
            crossings=solver.crossings(x), solve=SolveInfo.of(res, solver_settings)))
        positions.append(x)
    dcs = np.array([r.drape_coefficient for r in runs])
    nodes = np.array([r.nodes for r in runs])
    return CusickResult(
        fabric=fab.name, specimen_diameter_m=specimen, disc_diameter_m=disc,
        drape_coefficient=float(dcs.mean()), drape_coefficient_spread=float(np.ptp(dcs)),
        drape_coefficient_std=float(dcs.std()), nodes=float(nodes.mean()),
        nodes_min=int(nodes.min()), nodes_max=int(nodes.max()), runs=tuple(runs),
        triangles=len(t), vertices=len(v), perturbation_m=perturbation, pixel_m=pixel,
        seconds=time.perf_counter() - t0, positions=positions, rest=v, mesh_triangles=t)


# ------------------------------------------------------------------------------ pictures


def _save(fig, path) -> Path:
    buf = io.BytesIO()
    fig.savefig(buf, format=Path(path).suffix.lstrip(".").lower() or "png", dpi=130)
    return atomic_write_bytes(path, buf.getvalue())


def write_cusick_picture(result: CusickResult, path) -> Path:
    """Top view of every start of ``result`` (the vertical projection seen from above,
    coloured by height, the disc and the flat specimen's outline dashed) as one PNG at
    ``path``; returns the path."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    k = len(result.positions)
    cols = min(k, 5)
    rows = math.ceil(k / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(2.9 * cols + 1.0, 3.0 * rows + 0.5),
                             squeeze=False, layout="constrained")
    t = result.mesh_triangles
    r_spec, r_disc = result.specimen_diameter_m / 2, result.disc_diameter_m / 2
    lim = 1.05 * r_spec
    circle = np.linspace(0, 2 * np.pi, 200)
    for ax, x, run in zip(axes.ravel(), result.positions, result.runs):
        heights = x[t, 1].mean(axis=1)
        order = np.argsort(heights)  # the highest cloth drawn last: it hides what is below
        coll = PolyCollection(x[t[order]][:, :, [0, 2]], array=heights[order] * 1e3,
                              cmap="viridis", edgecolors="face", linewidths=0.2)
        coll.set_clim(-(r_spec - r_disc) * 1e3, 0.0)
        ax.add_collection(coll)
        ax.plot(r_spec * np.cos(circle), r_spec * np.sin(circle), "k--", lw=0.6)
        ax.plot(r_disc * np.cos(circle), r_disc * np.sin(circle), "w-", lw=0.8)
        ax.set_xlim(-lim, lim)
        ax.set_ylim(-lim, lim)
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_title(f"seed {run.seed}: DC {run.drape_coefficient:.3f}, {run.nodes} nodes",
                     fontsize=9)
    for ax in axes.ravel()[k:]:
        ax.axis("off")
    parts = (f"Cusick drape, {result.fabric}", f"DC {result.drape_coefficient:.3f} (spread "
             f"{result.drape_coefficient_spread:.3f}), nodes {result.nodes:.1f}",
             "top view, colour = height [mm]")
    # fewer than three panels are too narrow for the title on one line
    fig.suptitle(("; " if cols >= 3 else "\n").join(parts), fontsize=10)
    fig.colorbar(coll, ax=axes.ravel().tolist(), shrink=0.8, label="height [mm]")
    try:
        return _save(fig, path)
    finally:
        plt.close(fig)


def write_cantilever_picture(result: CantileverResult, path) -> Path:
    """Side view of the finest mesh's final strip (``cantilever_test(..., keep_shape=True)``)
    with the platform and the 41.5 deg line; returns the path."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

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
                 f"{result.bending_length_expected_m * 1e3:.2f} mm expected", fontsize=9)
    try:
        return _save(fig, path)
    finally:
        plt.close(fig)
