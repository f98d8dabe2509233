"""The Cusick drape test (BS 5058 / ISO 9073-9): a circular specimen clamped on a smaller
disc, its drape coefficient and its number of nodes (folds), from several slightly perturbed
flat starts (``patternfit fabric-test cusick``; docs/fabrics.md).

Units: metres, kilograms, seconds, newtons; ``y`` is up.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from ...arguments import number
from ...figures import pyplot
from ...geometry import triangle_areas
from ..fabrics import Fabric, get_fabric
from ..settings import SolverSettings
from ..solver import GarmentSolver
from .common import (Progress, SolveInfo, _grain, _loop_segments, _plain, _quality_mesh, _ring,
                     _save, _say, _solve, _solver_settings)

#: Cusick drape tester: specimen and support disc diameters of BS 5058 / ISO 9073-9 [m]
CUSICK_SPECIMEN = 0.30
CUSICK_DISC = 0.18

#: the kit's mesh: at least this many triangle edges per bending length of the fabric's
#: softer direction. Linear triangles lock (cannot fold) where a fold is only a few edges
#: wide, and the folds of a drape are a few bending lengths wide: the light published wovens
#: (c = 7.4-7.7 mm) read 1.15-1.5 times their drape coefficient at 4K triangles (6.4 mm edges,
#: 1.2 per c) and settle from 2.3 per c on (petrak_m2: 0.182 at 16K, 0.183 at 24K); the
#: stiffer ones move by 3 % from 2.5 to 3.6 per c (petrak_m6 0.350 at 8K, 0.359 at 16K);
#: docs/fabrics.md, "The kit's mesh"
CUSICK_EDGES_PER_BENDING_LENGTH = 2.5
#: a mesh is noted as coarser than that rule below this share of it: the mesher meets its
#: triangle count within some 5 % (so within some 2.5 % in edges per bending length), and
#: the kit's own mesh read "2.5 edges per bending length, against the kit's 2.5" (2.494)
CUSICK_COARSE_NOTE = 0.95
#: ... but never fewer triangles than this (stiff fabrics: their folds are wide anyway) nor
#: more (petrak_m2 at 24K: 21 s CPU a start on a 2-core machine, 46 s wall at load 4; the
#: solver stops at its 300 s wall-clock limit, so a finer default would fail on a busy one)
CUSICK_TRIANGLES = (4000, 24000)
#: the mesh check (``cusick_test(mesh_check=True)``): the first start's drape coefficient
#: on twice the triangles may differ by this much [-], a tenth of the span of the
#: published woven fabrics' coefficients (0.22-0.55, docs/fabrics.md, "Measured against")
CUSICK_MESH_TOLERANCE = 0.03
#: the fewest vertices on the support disc's edge with which a drape is read at all: an
#: inscribed 24-gon has 98.9 % of the circle's area (an octagon, what 54 triangles gave on
#: the 30 cm specimen, 90 %), and its corners stand 15 deg apart, closer than the folds of
#: the most nodes measured (11, 33 deg apart), two corners a fold; with fewer the corners
#: set the folds and the test reads the mesh, not the fabric (docs/fabrics.md, "The kit's
#: mesh") [-]
CUSICK_DISC_OUTLINE = 24


def cusick_triangles(fabric: Fabric | str, specimen: float = CUSICK_SPECIMEN) -> int:
    """The kit's triangle count for the Cusick test of ``fabric`` on a specimen of diameter
    ``specimen`` [m]: edges of at most 1 / ``CUSICK_EDGES_PER_BENDING_LENGTH`` of the
    fabric's smaller bending length (warp or weft) [m], within ``CUSICK_TRIANGLES``."""
    low, high = CUSICK_TRIANGLES
    return int(min(max(math.ceil(_wanted_triangles(fabric, specimen)), low), high))


def _wanted_triangles(fabric: Fabric | str, specimen: float) -> float:
    """Equilateral triangles of edge ``1 / CUSICK_EDGES_PER_BENDING_LENGTH`` of the
    fabric's smaller bending length on a specimen of diameter ``specimen`` [m]."""
    fab = get_fabric(fabric)
    specimen = number(specimen, "specimen", low=0.02, high=2.0)
    h = min(fab.bending_length, fab.bending_length_weft) / CUSICK_EDGES_PER_BENDING_LENGTH
    return 4 * math.pi * (specimen / 2) ** 2 / (math.sqrt(3) * h * h)


def _disc_mesh(r_specimen: float, r_disc: float, triangles: int):
    """A disc of radius ``r_specimen`` with the support circle ``r_disc`` as a mesh line,
    meshed to about ``triangles`` triangles: (vertices (n, 2), triangles (m, 3))."""
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
    return v, t


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
    mesh_check_triangles : int or None
        With the mesh check: the triangles of the finer specimen the first start was
        draped again on.
    mesh_change : float or None
        With the mesh check: that start's drape coefficient there minus on the test's mesh
        [-].
    mesh_check_at_rest : bool or None
        With the mesh check: whether that solve ended at rest (a change read off a solve
        still moving says nothing).
    mesh_capped : bool
        The kit chose the mesh and its cap (``CUSICK_TRIANGLES``) left it coarser than
        ``CUSICK_EDGES_PER_BENDING_LENGTH`` edges per bending length: without a mesh check
        that passed, the test fails (the folds of a fabric that limp lock on it).
    edges_per_bending_length : float or None
        The mesh's edges per bending length of the fabric's softer direction [-] (the
        equilateral edge of its triangle count, as the kit's rule counts it).
    disc_outline_vertices : int or None
        Vertices on the support disc's edge [-]; fewer than ``CUSICK_DISC_OUTLINE`` fail
        the test.
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
    mesh_check_triangles: int | None = None
    mesh_change: float | None = None
    mesh_check_at_rest: bool | None = None
    mesh_capped: bool = False
    edges_per_bending_length: float | None = None
    disc_outline_vertices: int | None = None

    @property
    def converged(self) -> bool:
        """Every start ended at rest (stop rule met, equilibrium check passed)."""
        return all(r.solve.at_rest for r in self.runs)

    @property
    def failures(self) -> list[str]:
        """Why the test failed, in words, per start (empty when it passed)."""
        out = []
        for r in self.runs:
            if not r.solve.at_rest:
                out.append(f"start {r.seed} did not reach rest ({r.solve.describe()})")
            if r.crossings:
                out.append(f"start {r.seed} folded through itself ({r.crossings} crossed "
                           "triangle pairs)")
            if not 0.0 <= r.drape_coefficient <= 1.0:
                out.append(f"start {r.seed}: drape coefficient {r.drape_coefficient:.3g} "
                           "outside [0, 1]")
        if self.mesh_check_at_rest is False:
            out.append(f"the mesh check's start on {self.mesh_check_triangles} triangles did "
                       "not reach rest")
        if self.mesh_capped and self.mesh_change is None:
            out.append(f"mesh too coarse for the fabric: the kit's {self.triangles} triangles "
                       f"(its most) give fewer than {CUSICK_EDGES_PER_BENDING_LENGTH:g} edges "
                       "per bending length, where its folds lock; check it with --mesh-check "
                       "or give more --triangles")
        if self.mesh_change is not None and abs(self.mesh_change) > CUSICK_MESH_TOLERANCE:
            out.append(f"not mesh-converged: start {self.runs[0].seed}'s drape coefficient "
                       f"moved by {self.mesh_change:+.3f} from {self.triangles} to "
                       f"{self.mesh_check_triangles} triangles (at most "
                       f"{CUSICK_MESH_TOLERANCE:g}): the mesh locks the fabric's folds")
        if (self.disc_outline_vertices is not None
                and self.disc_outline_vertices < CUSICK_DISC_OUTLINE):
            out.append(f"mesh too coarse for the instrument: the support disc's edge has "
                       f"{self.disc_outline_vertices} vertices on {self.triangles} triangles "
                       f"(at least {CUSICK_DISC_OUTLINE}), so its corners, not the fabric, "
                       "set the folds; give more --triangles")
        return out

    @property
    def notes(self) -> list[str]:
        """What the result does not fail for and a reader should know, in words: a mesh
        given coarser than the kit's rule (``CUSICK_EDGES_PER_BENDING_LENGTH``), which is
        the user's choice (a mesh the kit chose that coarse fails, :attr:`failures`)."""
        e = self.edges_per_bending_length
        if e is None or e >= CUSICK_COARSE_NOTE * CUSICK_EDGES_PER_BENDING_LENGTH \
                or self.mesh_capped:
            return []
        return [f"coarse mesh: {e:.2g} edges per bending length, against the kit's "
                f"{CUSICK_EDGES_PER_BENDING_LENGTH:g} (the default of --triangles): its folds "
                "may lock or go unresolved and the drape coefficient be far off"
                + ("; check it with --mesh-check" if self.mesh_change is None else "")]

    @property
    def passed(self) -> bool:
        """Every start ended at rest without crossings, every DC lies in [0, 1], a mesh the
        kit's cap left too coarse was checked, the disc's edge has ``CUSICK_DISC_OUTLINE``
        vertices at least and, with the mesh check, the first start's moved by at most
        ``CUSICK_MESH_TOLERANCE`` on the finer mesh."""
        return not self.failures

    def to_dict(self) -> dict:
        skip = {"runs", "positions", "rest", "mesh_triangles"}
        d = {f.name: getattr(self, f.name) for f in fields(self) if f.name not in skip}
        return _plain({"test": "cusick", **d, "seeds": [r.seed for r in self.runs],
                       "drape_coefficients": [r.drape_coefficient for r in self.runs],
                       "nodes_each": [r.nodes for r in self.runs],
                       "runs": [r.to_dict() for r in self.runs],
                       "residual": [r.solve.residual for r in self.runs],
                       "stop_reasons": [r.solve.stop_reason for r in self.runs],
                       "converged": self.converged, "passed": self.passed,
                       "failures": self.failures, "notes": self.notes})


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
                disc: float = CUSICK_DISC, triangles: int | None = None, seeds=(0, 1, 2, 3, 4),
                perturbation: float = 2e-3, pixel: float = 5e-4,
                settings: SolverSettings | None = None, mesh_check: bool = False,
                progress: Progress | None = None) -> CusickResult:
    """The Cusick drape test of ``fabric``: a circular specimen of diameter ``specimen`` [m]
    clamped between two discs of diameter ``disc`` [m] (every vertex within the disc radius
    is pinned; the disc edge is a circle of mesh vertices), draped under gravity to rest by
    the static solver from each of the flat starts perturbed by ``seeds`` (random waves of
    RMS ``perturbation`` [m] at the hem), meshed with about ``triangles`` triangles (None:
    :func:`cusick_triangles`, fine enough for the fabric's folds by its bending length).
    With ``mesh_check``, the first start is draped again on twice the triangles and the
    change of its drape coefficient reported (``mesh_change``; beyond
    ``CUSICK_MESH_TOLERANCE`` the test fails): a stiff membrane locks the folds of linear
    triangles that its bending length alone says are fine enough (a KES-F silk read 0.65
    at 6.5K triangles and 0.50 at 16K).

    Reads, per start: DC = (A_shadow - A_disc) / (A_specimen - A_disc), each area the
    vertical projection rasterised at ``pixel`` [m] (pixel centres): of the draped
    specimen, of its disc's triangles and of the flat specimen, so that a rigid specimen
    reads 1 and a limp one 0 whatever the raster's error (against the exact areas, a 2 cm
    specimen on a 0.5 cm disc read 1.007 flat), and the number of nodes: the peaks of the
    hem's projected radius that stand above their neighbouring troughs by at least 10 % of
    its range and 2 mm.
    """
    t0 = time.perf_counter()
    fab = get_fabric(fabric)
    specimen = number(specimen, "specimen", low=0.02, high=2.0)
    disc = number(disc, "disc", low=0.005, high=2.0)
    if not disc < specimen:
        raise ValueError(f"disc: the disc ({disc} m) must be smaller than the specimen "
                         f"({specimen} m)")
    capped = triangles is None and _wanted_triangles(fab, specimen) > CUSICK_TRIANGLES[1]
    if triangles is None:
        triangles = cusick_triangles(fab, specimen)
    triangles = int(number(triangles, "triangles", low=50, high=200_000))
    if isinstance(seeds, (str, bytes)) or not hasattr(seeds, "__iter__"):
        raise ValueError(f"seeds: expected a list of integers such as (0, 1, 2), got "
                         f"{seeds!r:.40}")
    seeds = [number(s, "seeds", low=0, high=2**31, integer=True) for s in seeds]
    if not seeds:
        raise ValueError("seeds: at least one")
    number(perturbation, "perturbation", low=0.0, high=0.05)
    number(pixel, "pixel", low=1e-5, high=0.01)
    spec = _Specimen.make(specimen / 2, disc / 2, triangles, pixel)
    solver_settings = _solver_settings(settings)
    runs, positions = [], []
    for i, seed in enumerate(seeds):
        _say(progress, f"cusick: start {i + 1}/{len(seeds)} (seed {seed}), {len(spec.t)} "
                       "triangles")
        run, x = _drape_start(spec, fab, seed, perturbation, pixel, solver_settings)
        runs.append(run)
        positions.append(x)
    finer = change = calm = None
    if mesh_check:
        fine = _Specimen.make(specimen / 2, disc / 2, min(2 * triangles, 200_000), pixel)
        finer = len(fine.t)
        _say(progress, f"cusick: mesh check, start 1 (seed {seeds[0]}) on {finer} triangles")
        again, _ = _drape_start(fine, fab, seeds[0], perturbation, pixel, solver_settings)
        change = again.drape_coefficient - runs[0].drape_coefficient
        calm = again.solve.at_rest
    dcs = np.array([r.drape_coefficient for r in runs])
    nodes = np.array([r.nodes for r in runs])
    return CusickResult(
        fabric=fab.name, specimen_diameter_m=specimen, disc_diameter_m=disc,
        drape_coefficient=float(dcs.mean()), drape_coefficient_spread=float(np.ptp(dcs)),
        drape_coefficient_std=float(dcs.std()), nodes=float(nodes.mean()),
        nodes_min=int(nodes.min()), nodes_max=int(nodes.max()), runs=tuple(runs),
        triangles=len(spec.t), vertices=len(spec.v), perturbation_m=perturbation,
        pixel_m=pixel, seconds=time.perf_counter() - t0, positions=positions, rest=spec.v,
        mesh_triangles=spec.t, mesh_check_triangles=finer, mesh_change=change,
        mesh_check_at_rest=calm, mesh_capped=capped,
        edges_per_bending_length=CUSICK_EDGES_PER_BENDING_LENGTH
        * math.sqrt(len(spec.t) / _wanted_triangles(fab, specimen)),
        disc_outline_vertices=int(np.sum(np.abs(np.hypot(spec.v[:, 0], spec.v[:, 1])
                                                - spec.r_disc) < 1e-9)))


@dataclass(frozen=True)
class _Specimen:
    """A meshed Cusick specimen: flat vertices (n, 2) and triangles [m], the pinned (disc)
    and hem vertices (the hem by angle), the triangles' flat areas, which triangles are
    free, and the rasterised areas of the flat specimen and of the disc [m^2]."""

    v: np.ndarray
    t: np.ndarray
    r_disc: float
    r_spec: float
    pinned: np.ndarray
    hem: np.ndarray
    rest_area: np.ndarray
    free_tri: np.ndarray
    a_spec: float
    a_disc: float

    @classmethod
    def make(cls, r_spec: float, r_disc: float, triangles: int, pixel: float) -> "_Specimen":
        v, t = _disc_mesh(r_spec, r_disc, triangles)
        r = np.hypot(v[:, 0], v[:, 1])
        hem = np.flatnonzero(r >= r_spec - 1e-9)
        free_tri = (r[t] > r_disc + 1e-9).any(axis=1)
        return cls(v, t, r_disc, r_spec, np.flatnonzero(r <= r_disc + 1e-9),
                   hem[np.argsort(np.arctan2(v[hem, 1], v[hem, 0]))], triangle_areas(v, t),
                   free_tri, shadow_area(v, t, pixel)[0], shadow_area(v, t[~free_tri], pixel)[0])


def _drape_start(spec: _Specimen, fab: Fabric, seed: int, perturbation: float, pixel: float,
                 settings: SolverSettings) -> tuple[CusickRun, np.ndarray]:
    """One start of the Cusick test on ``spec``: its reading and final positions (n, 3) [m]."""
    solver = GarmentSolver(spec.v, spec.t, _grain("warp", len(spec.t)), fab,
                           pinned=spec.pinned, settings=settings)
    v = spec.v
    # flat specimen at y = 0 (the disc's top), x and z in its plane
    x0 = np.c_[v[:, 0], _perturbation(v, spec.r_disc, spec.r_spec, perturbation, seed), v[:, 1]]
    res = _solve(solver, x0)
    x = res.x
    if not np.isfinite(x).all():
        raise RuntimeError(f"cusick: the solver returned non-finite positions (seed {seed}, "
                           f"stop reason {res.stop_reason})")
    shadow, _, _ = shadow_area(x[:, [0, 2]], spec.t, pixel)
    dc = (shadow - spec.a_disc) / (spec.a_spec - spec.a_disc)
    hem_r = np.hypot(x[spec.hem, 0], x[spec.hem, 2])
    prom = max(0.1 * float(np.ptp(hem_r)), 2e-3)
    area3 = triangle_areas(x, spec.t)
    shrunk = spec.free_tri & (area3 < 0.99 * spec.rest_area)
    run = CusickRun(
        seed=seed, drape_coefficient=float(dc), nodes=count_nodes(hem_r, prominence=prom),
        shadow_area_m2=shadow, hem_radius_min_m=float(hem_r.min()),
        hem_radius_max_m=float(hem_r.max()), hem_drop_m=float(-x[spec.hem, 1].mean()),
        compressed_share=float(spec.rest_area[shrunk].sum()
                               / spec.rest_area[spec.free_tri].sum()),
        crossings=solver.crossings(x), solve=SolveInfo.of(res, settings))
    return run, x


def write_cusick_picture(result: CusickResult, path) -> Path:
    """Top view of every start of ``result`` (the vertical projection seen from above,
    coloured by height, the disc and the flat specimen's outline dashed) as one PNG at
    ``path``; returns the path."""
    plt = pyplot()
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

