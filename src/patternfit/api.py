"""The public application layer: the few calls a user scripts with, and that every front end
(the CLI, the studio, ``demo``, ``reproduce``) calls.

A drape in one call::

    import patternfit as pf
    outcome = pf.drape_and_evaluate("skirt", "female_average", "cotton", triangles=1500)
    assert outcome.passed and 0.9 < outcome.fitting_ratio < 1.1
    outcome.write("out/")            # report.json, colour maps, GLB/OBJ, garment/

Lengths are metres, times seconds inside; pattern files state their own units.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from .body.builtin import list_bodies, load_body
from .body.mesh_io import BodyMeshError, load_body_mesh
from .body.model import Body
from .body.sdf import DistanceField
from .defaults import DEFAULTS, Defaults
from .errors import InputError
from .fit.measures import FitMeasures, fit_measures
from .fit.metrics import FitEvaluator, FitResult
from .fit.outputs import write_fit_outputs
from .edit import grade
from .loop.correct import Correction, CorrectionSettings, correct
from .loop.outputs import write_correction_outputs
from .loop.session import DesignSession
from .loop.table2 import ROWS
from .mesh.garment import GarmentMesh
from .mesh.store import load_garment, save_garment
from .mesh.triangulate import mesh_pattern
from .pattern.errors import PatternError
from .pattern.formats import load_any_pattern, save_any_pattern
from .pattern.library import GARMENTS, build
from .pattern.model import Pattern
from .sim.drape import Drape, drape
from .sim.fabrics import (FABRICS, KIT_READINGS, PRESET_SOURCES, Fabric, FabricError,
                          get_fabric, published_drapes)
from .sim.newton_engine import drape_with
from .sim.placement import place_on_body, place_on_cylinders
from .sim.solver import SolverSettings

__all__ = ["BodyMeshError", "Correction", "CorrectionSettings", "DEFAULTS", "Defaults",
           "DesignSession", "FabricError", "FitOutcome", "InputError", "PatternError",
           "correct", "correct_design", "design_session", "drafted_too_small",
           "drape_and_evaluate", "evaluate_saved", "fabric_catalogue", "list_bodies",
           "list_fabrics", "list_garments", "mesh_garment", "place_and_evaluate",
           "placed_fitting_ratio", "read_body", "read_fabric", "read_pattern", "save_any_pattern", "save_garment"]


def list_garments() -> list[str]:
    """Names of the built-in garments."""
    return list(GARMENTS)


def list_fabrics() -> list[str]:
    """Names of the fabric presets."""
    return list(FABRICS)


def fabric_catalogue() -> list[dict]:
    """Every fabric preset, then every published test fabric (``kind`` "preset" or
    "published"), JSON-ready: ``name``, ``constants`` (SI, as :class:`Fabric`),
    ``bending_length_m`` {warp, weft} from the constants, ``(B / (density g))^(1/3)`` [m],
    ``kit``: what the virtual fabric-testing kit read on it (Cusick ``drape_coefficient``
    mean, min, max and ``nodes`` [-]; cantilever ``bending_length`` [m] or None), stored from
    the run named in docs/fabrics.md, or None; ``source``; published ones also
    ``drape_coefficient_measured`` and ``drape_coefficient_reference`` (the source's own
    simulation) [-], ``description`` and ``provenance`` (the source in full)."""
    rows = []
    entries = [(f, "preset", PRESET_SOURCES.get(name, ""), None) for name, f in FABRICS.items()]
    entries += [(p.fabric, "published", p.source, p) for p in published_drapes().values()]
    for fab, kind, source, pub in entries:
        reading = KIT_READINGS.get(fab.name)
        row = {"name": fab.name, "kind": kind, "constants": fab.to_dict(),
               "bending_length_m": {"warp": fab.bending_length,
                                    "weft": fab.bending_length_weft},
               "kit": None if reading is None else reading.to_dict(), "source": source}
        if pub is not None:
            row |= {"description": pub.description, "provenance": pub.provenance,
                    "drape_coefficient_measured": pub.drape_coefficient,
                    "drape_coefficient_reference": pub.drape_coefficient_reference}
        rows.append(row)
    return rows


def read_pattern(source: Pattern | str | Path, *, size: str = DEFAULTS.size) -> Pattern:
    """A pattern: a :class:`Pattern` as is, a built-in garment name (in ``size``), or a file
    in any format patternfit reads (patternfit JSON, GarmentCode JSON, DXF-AAMA).

    Raises :class:`PatternError` naming the file and the place."""
    if isinstance(source, Pattern):
        return source
    name = str(source)
    if name in GARMENTS:
        return build(name, size)
    path = Path(name)
    if not (path.suffix or path.exists()):
        raise PatternError(f"neither a built-in garment ({', '.join(GARMENTS)}) nor a file",
                           file=name)
    return load_any_pattern(path)


def read_body(source: Body | str | Path, *, units: str | None = None) -> Body:
    """A body: a :class:`Body` as is, a built-in body name or alias, or a body mesh file
    (OBJ, PLY, STL, GLB, ...; ``units`` m, cm, mm or in, guessed from its height when None).

    Raises :class:`BodyMeshError` naming the file."""
    if isinstance(source, Body):
        return source
    path = Path(str(source))
    if path.suffix or path.exists():
        return load_body_mesh(path, units=units)
    try:
        return load_body(str(source))
    except ValueError:
        raise BodyMeshError(f"neither a built-in body ({', '.join(list_bodies())}) nor a "
                            "mesh file", file=str(source)) from None


def read_fabric(source: Fabric | str | Path) -> Fabric:
    """A fabric: a :class:`Fabric` as is, a preset name, or a fabric JSON file (SI units).

    Raises :class:`FabricError` naming the file and the field."""
    return get_fabric(source)


def mesh_garment(pattern: Pattern | str, *, triangles: int = DEFAULTS.triangles,
                 size: str = DEFAULTS.size, **options) -> GarmentMesh:
    """The garment mesh of ``pattern`` (a pattern, built-in name or file): every panel
    triangulated to about ``triangles`` triangles in all, seams matched."""
    return mesh_pattern(read_pattern(pattern, size=size), triangles=triangles, **options)


@dataclass(eq=False)
class FitOutcome:
    """A drape and its fit evaluation.

    Attributes
    ----------
    pattern : Pattern
    mesh : GarmentMesh
    body : Body
    fabric : Fabric
    positions : (n, 3) float
        3D state of every flat vertex [m].
    fit : FitResult
        Per-triangle area change, ϖ, stretch.
    drape : Drape or None
        The drape (solver, checks, timing); None for a saved state read back.
    extra : dict
        Report entries the drape adds (``checks``, ``timing``, ``fitting_ratio_placed``...).
    seconds : float
        Wall time of meshing, draping and evaluating [s].
    measures : FitMeasures or None
        Gap [mm], ease at the girths [cm] and contact pressure [kPa]
        (:mod:`patternfit.fit.measures`); None without a body (a saved state read back).
    """

    pattern: Pattern
    mesh: GarmentMesh
    body: Body | None
    fabric: Fabric | None
    positions: np.ndarray
    fit: FitResult
    drape: Drape | None = None
    extra: dict = field(default_factory=dict)
    seconds: float = 0.0
    state: str = "draped"
    measures: FitMeasures | None = None

    @property
    def fitting_ratio(self) -> float:
        """ϖ = ΣS2 / ΣS3 (eq. 2) [-]."""
        return float(self.fit.fitting_ratio)

    @property
    def checks(self) -> dict:
        """The drape's checks (``passed``, vertices inside, seam gap, crossings, equilibrium,
        and whether it rests on the body where its pattern says: ``on_body``; ``reasons``
        says why not); empty for a saved state read back."""
        return self.extra.get("checks", {})

    @property
    def passed(self) -> bool:
        """Whether the result is a fit at all: the drape's checks passed and ϖ is finite."""
        ok = bool(self.checks.get("passed", True))
        return ok and bool(np.isfinite(self.fit.fitting_ratio))

    def write(self, folder, *, pictures: bool = True, progress: Callable | None = None) -> dict:
        """Write every output into ``folder`` (report.json, fit_2d.png/.svg, fit_3d.png,
        garment.glb/.obj, garment/, and with :attr:`measures` sections.png and the report
        keys ``gap_mm``, ``ease_cm``, ``pressure_kpa``) and return the report."""
        body = None if self.body is None else (self.body.vertices, self.body.faces)
        extra = dict(self.extra)
        if self.body is not None:
            extra["body"] = self.body.name
        if self.fabric is not None:
            extra["fabric"] = self.fabric.name
        return write_fit_outputs(folder, self.pattern, self.mesh, self.positions, self.fit,
                                 state=self.state, body=body, pictures=pictures, extra=extra,
                                 progress=progress, measures=self.measures)


def _measures(d: Drape, mesh: GarmentMesh, body: Body, fabric: Fabric) -> FitMeasures:
    """The fit measures of a drape, with the contact law and distance field its solver
    used (the static engine's), else the body's default field and the drape's default
    margin (3 mm)."""
    s = getattr(d.solver, "settings", None)
    s = s if isinstance(s, SolverSettings) else SolverSettings(contact_margin=0.003)
    f = getattr(d.solver, "body", None)
    return fit_measures(mesh.triangles, d.positions, body,
                        f if isinstance(f, DistanceField) else None,
                        reach=max(fabric.thickness, s.contact_margin),
                        stiffness=s.contact_stiffness)


def drape_and_evaluate(pattern: Pattern | str | Path = DEFAULTS.garment,
                       body: Body | str | Path = DEFAULTS.body,
                       fabric: Fabric | str | Path = DEFAULTS.fabric, *,
                       triangles: int = DEFAULTS.triangles, size: str = DEFAULTS.size,
                       units: str | None = None, engine: str = "static",
                       settings: SolverSettings | None = None,
                       clearance: float = DEFAULTS.clearance, device: str | None = None,
                       from_static: bool = False, tight: float = DEFAULTS.tight,
                       loose: float = DEFAULTS.loose, start=None,
                       progress: Callable | None = None) -> FitOutcome:
    """Mesh ``pattern``, place it around ``body``, sew and drape it in ``fabric`` to rest,
    and evaluate the fit.

    Parameters
    ----------
    pattern, body, fabric
        Objects, built-in names or files (see :func:`read_pattern`, :func:`read_body`,
        :func:`read_fabric`).
    triangles : int
        Target triangle count of the garment mesh.
    engine : str
        ``"static"`` (equilibrium, default) or ``"newton"`` (dynamic; optional extra).
    settings : SolverSettings, optional
        Iteration and time limits [s] of the drape.
    clearance : float
        Gap between body and panels at placement [m].
    tight, loose : float
        Area change beyond which a triangle counts as tight / loose [-].
    start : path or (n, 3) float, optional
        Continue from a saved drape instead of placing and sewing: a garment folder as the
        drape writes it (``garment/``: ``pattern.json``, ``mesh.npz``, ``positions.npy``)
        of this same pattern and mesh (:class:`InputError` otherwise), or positions (n, 3)
        [m] of this mesh. The solve starts there with the seams welded (static engine).
    progress : callable, optional
        ``progress(iteration, energy [J], step [m], elapsed [s])``; raising
        KeyboardInterrupt in it stops cleanly with the last state.

    Every drape gets the on-body checks (:mod:`patternfit.sim.onbody`); ``passed`` is
    False and ``checks["reasons"]`` says why when the garment is not on the body where its
    pattern says, whatever ϖ reads.
    """
    t0 = time.perf_counter()
    pat = read_pattern(pattern, size=size)
    b = read_body(body, units=units)
    fab = read_fabric(fabric)
    m = mesh_pattern(pat, triangles=triangles)
    if start is not None:
        if engine != "static":
            raise ValueError("start: a saved drape is continued by the static engine only")
        d = drape(pat, m, b, fab, settings=settings, clearance=clearance,
                  start=_start_state(start, pat, m), progress=progress)
    else:
        d = drape_with(engine, pat, m, b, fab, settings=settings, device=device,
                       from_static=from_static, clearance=clearance, progress=progress)
    if d.onbody is None:  # an engine that does not run them itself
        d.check_on_body(pat, m, b)
    evaluator = FitEvaluator(m, tight=tight, loose=loose)
    extra = d.report_extra()
    extra["fitting_ratio_placed"] = evaluator.metrics(d.placed)[1]
    return FitOutcome(pat, m, b, fab, d.positions, evaluator(d.positions), drape=d,
                      extra=extra, seconds=time.perf_counter() - t0,
                      measures=_measures(d, m, b, fab))


def _start_state(start, pattern: Pattern, mesh: GarmentMesh) -> np.ndarray:
    """Positions (n, 3) [m] of ``mesh`` to start a drape from: ``start`` as is, or read
    from a saved garment folder that must hold a drape of this same pattern and mesh."""
    if not isinstance(start, (str, Path)):
        x = np.asanyarray(start, dtype=np.float64)
        if x.shape != (mesh.n_vertices, 3) or not np.isfinite(x).all():
            raise ValueError(f"start: expected finite positions ({mesh.n_vertices}, 3) of the "
                             f"mesh, got {x.shape}")
        return x
    saved, saved_mesh, x = load_garment(start)
    if x is None:
        raise InputError("holds no 3D state (positions.npy): drape the garment first",
                         file=start)
    if saved != pattern:
        raise InputError(f"holds a drape of another pattern ('{saved.name}', panels "
                         f"{', '.join(p.name for p in saved.panels)}), not of this "
                         f"'{pattern.name}': start from a drape of the same pattern",
                         file=start)
    same = (saved_mesh.vertices.shape == mesh.vertices.shape
            and np.array_equal(saved_mesh.triangles, mesh.triangles)
            and np.array_equal(saved_mesh.seam_pairs, mesh.seam_pairs)
            and np.allclose(saved_mesh.vertices, mesh.vertices, rtol=0.0, atol=1e-9))
    if not same:
        raise InputError(f"holds a mesh of {saved_mesh.n_triangles} triangles "
                         f"({saved_mesh.n_vertices} vertices) that is not this drape's "
                         f"({mesh.n_triangles} triangles): give the triangle count it was "
                         "draped with", file=start)
    return x


def evaluate_saved(folder, *, tight: float = DEFAULTS.tight,
                   loose: float = DEFAULTS.loose) -> FitOutcome:
    """The fit of a saved garment folder's 3D state (``pattern.json``, ``mesh.npz``,
    ``positions.npy``); :class:`InputError` when the folder holds no 3D state."""
    pat, m, x = load_garment(folder)
    if x is None:
        raise InputError("holds no 3D state (positions.npy): place or drape the garment first",
                         file=folder)
    return FitOutcome(pat, m, None, None, x, FitEvaluator(m, tight=tight, loose=loose)(x),
                      state="saved")


def place_and_evaluate(pattern: Pattern | str | Path = "coat", *, triangles: int = 22000,
                       size: str = DEFAULTS.size, tight: float = DEFAULTS.tight,
                       loose: float = DEFAULTS.loose) -> FitOutcome:
    """Mesh ``pattern`` and place it isometrically (every panel rolled onto a cylinder), with
    its fit: ϖ is 100% and the map one neutral colour (the paper's Fig. 8(b))."""
    t0 = time.perf_counter()
    pat = read_pattern(pattern, size=size)
    m = mesh_pattern(pat, triangles=triangles)
    x = place_on_cylinders(pat, m)
    return FitOutcome(pat, m, None, None, x, FitEvaluator(m, tight=tight, loose=loose)(x),
                      seconds=time.perf_counter() - t0, state="placed")


def placed_fitting_ratio(session: DesignSession) -> float:
    """ϖ of the session's current mesh placed around its body before any drape [-]
    (about 1.0: the placement is isometric)."""
    placed = place_on_body(session.pattern, session.mesh, session.body)
    return float(FitEvaluator(session.mesh).metrics(placed)[1])


def design_session(pattern: Pattern | str | Path = DEFAULTS.garment,
                   body: Body | str | Path = DEFAULTS.body,
                   fabric: Fabric | str | Path = DEFAULTS.fabric, *,
                   triangles: int = DEFAULTS.triangles, threshold: float = DEFAULTS.threshold,
                   size: str = DEFAULTS.size, units: str | None = None,
                   relax: float = 1.0) -> DesignSession:
    """A :class:`DesignSession` (edits with the mesh following, undo/redo, drapes, save)
    of ``pattern`` on ``body`` in ``fabric``; see :func:`read_pattern`, :func:`read_body`,
    :func:`read_fabric` for what each may be. ``threshold`` is the ϖ at which the design
    fits [-]; ``relax`` (>= 1) sews the first drape that much wider, then restores the true
    width (for a garment drafted too small to be sewn on the body)."""
    if not (isinstance(threshold, (int, float)) and 0 < threshold <= 1.5):
        raise ValueError(f"threshold: expected a fraction such as 0.9, got {threshold!r}")
    return DesignSession(read_pattern(pattern, size=size), read_body(body, units=units),
                         read_fabric(fabric), triangles, float(threshold), relax=relax)


def drafted_too_small(garment: str = DEFAULTS.garment, size: str | None = None) -> dict:
    """The demo's setup: a built-in garment drafted too small for a body, as in the paper's
    Table 2 row for it (every panel narrowed across the grain; the body, the fabric and the
    sewing width of that row), or narrowed to 80% in a stretch knit on the average woman for
    a garment without a row.

    Returns ``{"pattern", "body", "fabric", "narrow", "relax", "size"}``."""
    row = {r.garment: r for r in ROWS}.get(garment)
    body, narrow, fabric, relax = (row.body, row.narrow, row.fabric, row.relax) if row \
        else (DEFAULTS.body, 0.8, "stretch_knit", 1.0)
    size = size or (row.size if row else DEFAULTS.size)
    pattern = grade(build(garment, size), None, narrow, 1.0)
    return {"pattern": pattern, "body": body, "fabric": fabric, "narrow": narrow,
            "relax": relax, "size": size.upper()}


def correct_design(session: DesignSession, out, *, threshold: float | None = None,
                   max_iterations: int = DEFAULTS.correction_rounds, pictures: bool = True,
                   extra: dict | None = None, progress: Callable | None = None,
                   drape_progress: Callable | None = None,
                   write_progress: Callable | None = None) -> dict:
    """Correct the session's pattern automatically (drape, find the tight regions, move the
    seam corners, re-drape, until ϖ reaches ``threshold`` — the session's when None — or
    ``max_iterations`` rounds) and write the outputs into ``out``: ``pattern.json`` (the
    corrected pattern), ``report.json``, ``before/`` and ``after/`` fit outputs and the
    regions pictures. Returns the report.

    ``progress(iteration)`` is called after each drape is evaluated, ``drape_progress`` goes
    to the solver, ``write_progress(message)`` is called per output written."""
    settings = CorrectionSettings(threshold=session.threshold if threshold is None
                                  else threshold, max_iterations=max_iterations)
    result = correct(session, settings=settings, drape_progress=drape_progress,
                     progress=progress)
    return write_correction_outputs(out, session, result, extra=extra, pictures=pictures,
                                    progress=write_progress)
