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

import inspect
import time
import warnings
from fnmatch import fnmatchcase
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from .body.builtin import list_bodies, load_body
from .body.mesh_io import HEIGHT_RANGE, BodyMeshError, load_body_mesh
from .body.model import Body
from .body.sdf import DistanceField
from .body.builtin import list_body_sets
from .body.anny import anny_body_from_girths
from .arguments import array, instance, number
from .arguments import path as path_arg, source as source_arg
from .constants import UNITS, tol
from .defaults import DEFAULTS, Defaults
from .errors import GarmentFileError, InputError
from .fit.measures import GIRTHS, FitMeasures, fit_measures
from .fit.metrics import FitEvaluator, FitResult, fit_bands
from .fit.outputs import write_fit_outputs
from .edit import add_seam, grade, remove_seam, set_seam_ease
from .fit.verdict import Verdict, judge_garment
from .fit.verdict_rules import VerdictRules
from .loop.correct import Correction, CorrectionSettings, correct
from .loop.outputs import write_correction_outputs
from .loop.session import DesignSession
from .loop.table2 import ROWS
from .mesh.garment import GarmentMesh
from .mesh.store import (CONTACT, garment_folder, load_contact, load_garment, save_garment,
                         saved_rest)
from .mesh.triangulate import mesh_pattern
from .pattern.errors import PatternError
from .pattern.formats import load_any_pattern, save_any_pattern
from .pattern.library import GARMENTS, build
from .pattern.model import Pattern, Seam
from .pattern.plausible import check_drapeable_size
from .pattern.validate import check_pattern
from .pattern.seam_suggest import SeamSuggestion, check_sewn
from .pattern.seam_suggest import suggest_seams as _suggest
from .pattern.sizes import SIZE_NAMES
from .sim.drape import (CONTACT_MARGIN, Drape, drape, saved_balance, saved_contact_fault,
                        saved_crossings, without_floor)
from .sim.provenance import (draped_for, not_draped_for, saved_fabric, saved_failure,
                             saved_residual)
from .sim.fabrics import (FABRICS, KIT_READINGS, PRESET_SOURCES, Fabric, FabricError,
                          check_bulk, fabric_names, fabric_with_notes, get_fabric,
                          published_drapes)
from .sim.fabrics import RANGES as FABRIC_RANGES
from .sim.onbody import ON_BODY, area_ratio, saved_state_checks, unchecked_state
from .sim.newton_engine import ENGINES, MISSING as NEWTON_MISSING, drape_with
from .sim.placement import checked_clearance, place_on_body, place_on_cylinders
from .sim.settings import SolverSettings
from .sim.state import SAVED, SavedStateError

__all__ = ["BodyMeshError", "Correction", "CorrectionSettings", "DEFAULTS", "Defaults",
           "DesignSession", "FABRIC_RANGES", "FABRIC_TESTS", "Fabric", "FabricError", "FitOutcome",
           "GIRTHS", "InputError", "PatternError", "SeamSuggestion", "SolverSettings",
           "StartWarning", "Verdict",
           "VerdictRules", "accept_seams", "add_seam", "body_from_measurements", "check_bulk",
           "check_drapeable", "check_sewn",
           "correct", "correct_design", "design_session", "drafted_too_small",
           "describe_fabric", "drape_and_evaluate", "evaluate_drape", "evaluate_saved",
           "fabric_catalogue", "fabric_names", "fresh_drape",
           "fabric_test", "list_bodies", "list_body_sets", "list_engines", "list_fabrics",
           "judge_state", "list_garments", "list_sizes", "mesh_garment", "place_and_evaluate",
           "placed_fitting_ratio", "read_bodies", "read_body", "read_fabric",
           "read_fabric_with_notes", "read_pattern",
           "remove_seam", "save_any_pattern", "save_garment", "seam_table", "set_seam_ease",
           "suggest_seams", "verdict_rules", "with_distance_field", "write_fabric_test_picture",
           "write_pattern"]


class StartWarning(UserWarning):
    """A drape started from a saved one draped on another body (``start=``)."""


def list_garments() -> list[str]:
    """Names of the built-in garments."""
    return list(GARMENTS)


def list_sizes() -> list[str]:
    """Names of the sizes every built-in garment is drafted in (S, M, L, XL)."""
    return list(SIZE_NAMES)


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
        row = _fabric_row(fab, kind, source) | {
            "kit": None if reading is None else reading.to_dict()}
        if pub is not None:
            row |= {"description": pub.description, "provenance": pub.provenance,
                    "drape_coefficient_measured": pub.drape_coefficient,
                    "drape_coefficient_reference": pub.drape_coefficient_reference}
        rows.append(row)
    return rows


#: what a pattern, body or fabric argument may be, for the refusal of anything else
_PATTERN = "a Pattern, a built-in garment name or a pattern file"
_BODY = "a Body, a built-in body name or a body mesh file"
_FABRIC = "a Fabric, a preset name or a fabric file"


def _options(options: dict, inner: Callable, public: str, taken: tuple = ()) -> dict:
    """``options`` when every one is a keyword option of ``inner`` that ``public`` passes on
    (not one of ``taken``, which it sets itself); else the ``TypeError`` Python raises for
    an unknown keyword, naming ``public`` and what it takes instead of an inner function."""
    known = [n for n, q in inspect.signature(inner).parameters.items()
             if q.kind is q.KEYWORD_ONLY and n not in taken]
    for name in options:
        if name not in known:
            raise TypeError(f"{public}() got an unexpected keyword argument {name!r} "
                            f"(options: {', '.join(known)})")
    return options


def _fabric_row(fab: Fabric, kind: str, source: str) -> dict:
    return {"name": fab.name, "kind": kind, "constants": fab.to_dict(),
            "bending_length_m": {"warp": fab.bending_length, "weft": fab.bending_length_weft},
            "kit": None, "source": source}


def describe_fabric(source: Fabric | str | Path) -> dict:
    """A fabric as :func:`read_fabric` reads it (a preset, a published test fabric, an SI
    fabric file, a KES-F / FAST sheet or an ARCSim material converted to SI), as a row of
    :func:`fabric_catalogue`: ``name``, ``kind`` ("file" for a file), ``constants`` (SI),
    ``bending_length_m`` {warp, weft} [m], ``kit`` (the stored kit reading of a preset or
    published fabric, else None) and ``source`` (the file, for a file); a file's row also
    ``assumed``: a sentence for each value the file did not carry (an ARCSim material's
    friction and thickness).

    Raises :class:`FabricError` naming the file and the field."""
    fab, assumed = fabric_with_notes(source_arg(source, Fabric, "fabric", _FABRIC))
    row = {r["name"]: r for r in fabric_catalogue()}.get(fab.name)
    if row is not None and row["constants"] == fab.to_dict():
        return row
    if isinstance(source, Fabric):
        return _fabric_row(fab, "given", "")
    return _fabric_row(fab, "file", str(source)) | {"assumed": list(assumed)}


#: the virtual fabric tests :func:`fabric_test` runs
FABRIC_TESTS = ("strip", "cantilever", "cusick")


def fabric_test(test: str, fabric: Fabric | str | Path = DEFAULTS.fabric, *,
                progress: Callable[[str], None] | None = None, **options):
    """Run virtual fabric test ``test`` (one of :data:`FABRIC_TESTS`) on ``fabric`` (a
    :class:`Fabric`, a preset name or a fabric JSON file) and return its result
    (``.passed``, ``.to_dict()`` in SI units; see ``patternfit.sim.fabric_test``):

    - ``"strip"``: a strip hanging under its own weight, its stretch against
      rho g L^2 / (2k); options ``direction`` ("warp"/"weft"), ``length`` [m].
    - ``"cantilever"``: Peirce's cantilever (ASTM D1388), the bending length against
      (B / (rho g))^(1/3); options ``direction``, ``meshes`` (edges per bending length,
      coarse to fine).
    - ``"cusick"``: the Cusick drape coefficient and nodes; options ``specimen``, ``disc``
      (diameters [m]), ``triangles`` (default: the kit's mesh for the fabric,
      ``fabric_test.cusick_triangles``), ``seeds`` (the perturbed starts).

    ``progress(text)`` is called as the test goes. Long (a Cusick test of 4,000-19,000
    triangles and 5 starts takes minutes); KeyboardInterrupt stops it.
    """
    from .sim import fabric_test as kit

    if test not in FABRIC_TESTS:
        raise ValueError(f"test: expected one of {', '.join(FABRIC_TESTS)}, got {test!r}")
    run = {"strip": kit.strip_test, "cantilever": kit.cantilever_test,
           "cusick": kit.cusick_test}[test]
    return run(read_fabric(fabric), progress=progress,
               **_options(options, run, "fabric_test", ("progress",)))


def write_fabric_test_picture(result, path) -> Path | None:
    """The picture of a :func:`fabric_test` result as a PNG at ``path``: the Cusick test's
    top view, or the cantilever's side view (a cantilever run with ``keep_shape=True``);
    None for a test without one (the strip)."""
    from .sim import fabric_test as kit

    instance(result, (kit.StripResult, kit.CantileverResult, kit.CusickResult), "result",
             "a fabric_test result")
    path = path_arg(path, "path", what="a PNG file path")
    if isinstance(result, kit.CusickResult):
        return kit.write_cusick_picture(result, path)
    if isinstance(result, kit.CantileverResult) and result.shape is not None:
        return kit.write_cantilever_picture(result, path)
    return None


def evaluate_drape(mesh: GarmentMesh, positions: np.ndarray, *, tight: float = 0.02,
                   loose: float = 0.02) -> FitResult:
    """The fit of ``mesh`` draped at ``positions`` ((n, 3) [m], one row per flat vertex):
    area change, warp/weft stretch per triangle and ϖ, as ``DesignSession.evaluate`` gives
    for its current state (``tight``/``loose``: the fit bands [-]). ϖ is infinite for a
    state whose 3D area has collapsed to nothing (a failed drape, never a fit: the on-body
    checks of :func:`drape_and_evaluate` fail it and the studio shows it as failed)."""
    instance(mesh, GarmentMesh, "mesh", "a GarmentMesh (api.mesh_garment)")
    # not required finite: a drape that blew up is evaluated, and fails, as any failed one
    x = array(positions, "positions", shape=(mesh.n_vertices, 3))
    return FitEvaluator(mesh, tight=tight, loose=loose)(x)


def list_engines() -> dict[str, str | None]:
    """The drape engines, each with None when it can run here or the reason it cannot (its
    optional packages missing, with the install command). Nothing is imported: only
    whether the packages are installed is looked up."""
    from importlib.util import find_spec

    return {name: None if name == "static" or all(find_spec(m) for m in ("newton", "warp"))
            else NEWTON_MISSING for name in ENGINES}


def read_pattern(source: Pattern | str | Path, *, size: str | None = None,
                 units: str | None = None) -> Pattern:
    """A pattern: a :class:`Pattern` as is, a built-in garment name (in ``size``, default
    ``Defaults.size``), or a file in any format patternfit reads (patternfit JSON,
    GarmentCode JSON, DXF-AAMA; ``size`` picks a size of a graded DXF, default its sample
    size, and ``units`` overrides a DXF's length unit, see
    :func:`~patternfit.pattern.formats.load_any_pattern`).

    Raises :class:`PatternError` naming the file and the place (a size the file does not
    have: naming the sizes it has)."""
    source_arg(source, Pattern, "pattern", _PATTERN)
    if units is not None and (isinstance(source, Pattern) or str(source) in GARMENTS):
        raise ValueError("units: set for a DXF file only")
    _size(size)
    if isinstance(source, Pattern):
        return source
    name = str(source)
    if name in GARMENTS:
        return build(name, size or DEFAULTS.size)
    if not _names_file(name):
        raise PatternError(f"neither a built-in garment ({', '.join(GARMENTS)}) nor a file",
                           file=name)
    return load_any_pattern(Path(name), size=size, units=units)


def _names_file(source) -> bool:
    """Whether ``source`` (not an object) is read as a file rather than a built-in name:
    it has an ending or exists."""
    path = Path(str(source))
    return bool(path.suffix) or path.exists()


def _size(size) -> None:
    """Refuse a ``size`` that is neither None nor a size name (``""`` too, which was read
    as the default size without a word)."""
    if size is not None and (not isinstance(size, str) or not size.strip()):
        raise ValueError(f"size: expected a size name such as 'M', got {size!r:.40}")


def suggest_seams(pattern: Pattern | str | Path, *, size: str | None = None,
                  min_score: float = DEFAULTS.seam_score) -> list[SeamSuggestion]:
    """Seams suggested for the unsewn outline edges of ``pattern`` (a pattern, built-in
    name or file; ``size`` as :func:`read_pattern`'s: a file's own size when None), best
    first: each a :class:`SeamSuggestion` (``seam``, ``score`` in [0, 1],
    ``reasons`` in words) from lengths (with ease), piece and edge names, notches, grain and
    the outlines' directions (:mod:`patternfit.pattern.seam_suggest`)."""
    min_score = number(min_score, "min_score", low=0.0, high=1.0)  # NaN suggested nothing
    return _suggest(read_pattern(pattern, size=size), min_score=min_score)


def accept_seams(pattern: Pattern, suggestions) -> Pattern:
    """``pattern`` with the suggested seams sewn (:class:`SeamSuggestion` or
    :class:`Seam` items, each added by :func:`add_seam` with its name, ease and
    direction)."""
    instance(pattern, Pattern, "pattern", "a Pattern")
    if isinstance(suggestions, (str, bytes)) or not hasattr(suggestions, "__iter__"):
        raise ValueError(f"suggestions: expected a list of SeamSuggestion or Seam, got "
                         f"{type(suggestions).__name__}")
    for item in suggestions:
        s = item.seam if isinstance(item, SeamSuggestion) else item
        if not isinstance(s, Seam):
            raise ValueError(f"suggestions: expected SeamSuggestion or Seam items, got "
                             f"{type(item).__name__}")
        pattern = add_seam(pattern, s.a, s.b, name=s.name, ease=s.ease, reverse=s.reverse)
    return pattern


def seam_table(pattern: Pattern | str | Path) -> list[dict]:
    """One row per seam of ``pattern`` (a pattern, built-in name or file): ``name``, sides
    ``a``/``b`` (``panel``, ``edge``, ``start``, ``end``, ``length_cm``), ``difference_mm``
    (b - a), ``ratio`` (longer / shorter - 1), the stated ``ease`` and ``reverse``."""
    pattern = read_pattern(pattern)
    rows = []
    for s in pattern.seams:
        la, lb = pattern.seam_side_length(s.a), pattern.seam_side_length(s.b)
        rows.append({"name": s.name, "reverse": s.reverse, "ease": float(s.ease),
                     "a": _side_row(s.a, la), "b": _side_row(s.b, lb),
                     "difference_mm": round((lb - la) * 1000, 2),
                     "ratio": round(max(la, lb) / min(la, lb) - 1.0, 4)})
    return rows


def _side_row(side, length: float) -> dict:
    return {"panel": side.panel, "edge": side.edge, "start": side.start, "end": side.end,
            "length_cm": round(length * 100, 2)}


def write_pattern(pattern: Pattern, out, *, source=None, fmt: str | None = None,
                  units: str = "m", paper: str = "a4") -> list[Path]:
    """Write ``pattern`` to ``out`` (format ``fmt`` or from the ending, ``units`` and
    ``paper`` as :func:`save_any_pattern` takes them; atomically) and return the files
    written; refuses to overwrite ``source``, the file it was read from."""
    instance(pattern, Pattern, "pattern", "a Pattern")
    out = path_arg(out, "out", what="a file path")
    if source is not None and Path(source).exists() and out.exists() and \
            out.resolve() == Path(source).resolve():
        raise InputError("is the input pattern: write the result to another file", file=out)
    return save_any_pattern(pattern, out, fmt=fmt, units=units, paper=paper)


def read_body(source: Body | str | Path, *, units: str | None = None) -> Body:
    """A body: a :class:`Body` as is, a built-in body name or alias, or a body mesh file
    (OBJ, PLY, STL, GLB, ...; ``units`` m, cm, mm or in, guessed from its height when None).

    Raises :class:`BodyMeshError` naming the file."""
    source_arg(source, Body, "body", _BODY)
    if units is not None and (not isinstance(units, str) or units not in UNITS):
        raise ValueError(f"units: expected one of {', '.join(UNITS)}, got {units!r:.40}")
    file = not isinstance(source, Body) and _names_file(source)
    if units is not None and not file:
        raise ValueError("units: set for a body mesh file only")
    if isinstance(source, Body):
        return source
    if file:
        return load_body_mesh(Path(str(source)), units=units)
    try:
        return load_body(str(source))
    except ValueError:
        raise BodyMeshError(f"neither a built-in body ({', '.join(list_bodies())}) nor a "
                            "mesh file", file=str(source)) from None


#: suffixes of the body meshes :func:`read_bodies` takes from a folder
BODY_SUFFIXES = (".obj", ".ply", ".stl", ".off", ".glb", ".gltf", ".npz")


def read_bodies(spec: str | Path, *, units: str | None = None) -> list[Body]:
    """Several bodies: a folder (every body mesh in it, :data:`BODY_SUFFIXES`, sorted by
    name), or comma-separated items, each a body set (:func:`list_body_sets`, such as
    ``population``), a body name or alias, a shell pattern over the names of every set
    (``women_*``) or a mesh file.

    Returns the bodies in order, each once. Raises :class:`BodyMeshError` naming the item
    that is none of these, or a folder without body meshes, and ``ValueError`` when two
    bodies share a name (a batch tells its rows apart by it)."""
    if not isinstance(spec, (str, Path)) or not str(spec).strip():
        # "" is the current folder to Path: every mesh there was read as a body
        raise ValueError(f"bodies: expected a set, names, files or a folder, got {spec!r:.60}")
    path = Path(str(spec))
    if path.is_dir():
        files = sorted(p for p in path.iterdir() if p.suffix.lower() in BODY_SUFFIXES)
        if not files:
            raise BodyMeshError(f"holds no body mesh ({', '.join(BODY_SUFFIXES)})", file=path)
        bodies = [read_body(p, units=units) for p in files]
    else:
        sets = list_body_sets()
        # in the sets' own order (a population runs XS to XXL), not alphabetically
        known = list(dict.fromkeys(n for members in sets.values() for n in members))
        names: list = []
        for item in (s.strip() for s in str(spec).split(",")):
            if not item:
                raise BodyMeshError("an empty body name in the list", file=str(spec))
            if item in sets:
                names += sets[item]
            elif any(c in item for c in "*?["):
                hits = [n for n in known if fnmatchcase(n, item)]
                if not hits:
                    raise BodyMeshError(f"no body name matches; known: {', '.join(known)}",
                                        file=item)
                names += hits
            else:
                names.append(item)
        # units are a mesh file's: the built-in bodies among files keep their own
        files = {n for n in names if _names_file(n)}
        if units is not None and not files:
            raise ValueError("units: set for body mesh files only")
        bodies = [read_body(n, units=units if n in files else None)
                  for n in dict.fromkeys(names)]
    seen: dict[str, int] = {}
    for b in bodies:
        seen[b.name] = seen.get(b.name, 0) + 1
    twice = sorted(n for n, k in seen.items() if k > 1)
    if twice:
        raise ValueError(f"bodies: two bodies named {', '.join(twice)}; rename the files")
    return bodies


def body_from_measurements(*, gender: float, height: float, bust: float, waist: float,
                           hip: float, name: str = "custom") -> Body:
    """An anny body (the optional extra ``patternfit[anny]``) of ``height`` [m] whose bust
    (chest), waist and hip girths [m] add up to the given ones; ``gender`` 0 = male,
    1 = female. Its own girths, in ``measurements``, differ from the given ones by a few
    centimetres (:func:`patternfit.body.anny.anny_body_from_girths` says why). About 7
    anny bodies are built on the way (a minute on a laptop CPU).

    Raises ``ValueError`` naming a measurement out of range, ``ImportError`` saying how to
    install anny when it is missing."""
    number(height, "height", low=HEIGHT_RANGE[0], high=HEIGHT_RANGE[1], unit="m",
           rule=f"expected a standing height in metres within {list(HEIGHT_RANGE)}")
    return anny_body_from_girths(gender=gender, stature=height, bust=bust, waist=waist,
                                 hip=hip, name=name)


def with_distance_field(body: Body) -> Body:
    """``body`` with the distance field that the drape, the placement and the fit measures
    use computed and kept on it, so that a copy sent to another process (pickled, as a
    batch shares it) carries the field instead of building it again. Returns ``body``."""
    instance(body, Body, "body", "a Body (api.read_body)")
    body.distance_field()
    return body


def read_fabric(source: Fabric | str | Path) -> Fabric:
    """A fabric: a :class:`Fabric` as is, a preset name, or a fabric JSON file (SI units, a
    KES-F / FAST measurement sheet in its own units: ``patternfit.sim.fabric_sheets``, or an
    ARCSim material file: ``patternfit.sim.fabric_arcsim``).

    Raises :class:`FabricError` naming the file and the field."""
    return get_fabric(source_arg(source, Fabric, "fabric", _FABRIC))


def read_fabric_with_notes(source: Fabric | str | Path) -> tuple[Fabric, list[str]]:
    """:func:`read_fabric`, and a sentence for each value a fabric file did not carry and was
    assumed (an ARCSim material's friction and thickness); empty for a preset, a published
    fabric, a :class:`Fabric` or a file that carries them all.

    Raises :class:`FabricError` naming the file and the field."""
    fab, assumed = fabric_with_notes(source_arg(source, Fabric, "fabric", _FABRIC))
    return fab, list(assumed)


def mesh_garment(pattern: Pattern | str, *, triangles: int = DEFAULTS.triangles,
                 size: str | None = None, **options) -> GarmentMesh:
    """The garment mesh of ``pattern`` (a pattern, built-in name or file; ``size`` as
    :func:`read_pattern`'s): every panel triangulated to about ``triangles`` triangles in
    all, seams matched. ``options``: ``min_angle`` [degrees] and ``edge_length`` [m] of
    :func:`patternfit.mesh.mesh_pattern`. Returns a :class:`GarmentMesh`: flat ``vertices``
    (n, 2) [m] in each panel's frame, ``triangles`` (m, 3) int, ``triangle_panel`` (m,),
    ``seam_pairs`` (k, 2) of vertices sewn together."""
    return mesh_pattern(read_pattern(pattern, size=size), triangles=triangles,
                        **_options(options, mesh_pattern, "mesh_garment", ("triangles",)))


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
    judgement : Verdict or None
        The fit verdict (:mod:`patternfit.fit.verdict`); None without measures.
    contact : dict or None
        A saved state's contact state read back (``contact.npz``), written with it again
        (a state not at rest read back and written without it passed the next read).
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
    judgement: Verdict | None = None
    contact: dict | None = field(default=None, repr=False)

    @property
    def verdict(self) -> str | None:
        """The overall verdict: "too tight", "tight", "fits", "loose", "too loose", or
        "failed" for a drape that failed its checks; None without a body."""
        return None if self.judgement is None else self.judgement.overall

    @property
    def region_verdicts(self) -> dict:
        """Region → {verdict, ease_cm, pressure_kpa_p95, stretch_p90, area_m2, reason}, as
        ``report.json`` holds them (empty for a failed drape or without a body)."""
        return {} if self.judgement is None else self.judgement.report()["region_verdicts"]

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
    def interrupted(self) -> bool:
        """Whether Ctrl-C (KeyboardInterrupt) stopped the drape before its end: the state is
        the last one reached, neither a result nor a failure of the garment."""
        return bool(self.drape is not None and self.drape.result.interrupted)

    @property
    def passed(self) -> bool | None:
        """Whether the result is a fit at all: the drape's checks passed and ϖ is finite;
        None where nothing checked it (a placement never draped, a saved state read back
        without its body: its report's ``checks.passed`` is null), as falsy as a failure. A
        placement of a skirt that falls 52 cm once draped read True."""
        checked = self.checks.get("passed")
        if checked is None:
            return None
        return bool(checked) and bool(np.isfinite(self.fit.fitting_ratio))

    def write(self, folder, *, pictures: bool = True, progress: Callable | None = None) -> dict:
        """Write every output into ``folder`` (report.json, fit_2d.png/.svg, fit_3d.png,
        garment.glb/.obj, garment/, and with :attr:`measures` sections.png and the report
        keys ``gap_mm``, ``ease_cm``, ``pressure_kpa``; ``pattern_warnings`` when the reader
        warned) and return the report."""
        body = None if self.body is None else (self.body.vertices, self.body.faces)
        extra = dict(self.extra)
        if self.body is not None:
            extra["body"] = self.body.name
        if self.fabric is not None:
            extra["fabric"] = self.fabric.name
        if self.judgement is not None:
            extra.update(self.judgement.report())
        # what the reader noticed (e.g. a seam cycle sewn twisted) travels with the result
        if self.pattern.meta.get("warnings"):
            extra["pattern_warnings"] = list(self.pattern.meta["warnings"])
        return write_fit_outputs(folder, self.pattern, self.mesh, self.positions, self.fit,
                                 state=self.state, body=body, pictures=pictures, extra=extra,
                                 progress=progress, measures=self.measures,
                                 contact=self.contact if self.drape is None
                                 else self.drape.saved_contact(self.mesh))


def _measures(d: Drape, mesh: GarmentMesh, body: Body, fabric: Fabric) -> FitMeasures:
    """The fit measures of a drape, with the contact distance and the grid of the distance
    field its solver used (the static engine's; the body's own field, without the floor
    the solver also meets: a gap is to the body), else the body's default field and the
    drape's default margin (3 mm)."""
    s = getattr(d.solver, "settings", None)
    s = s if isinstance(s, SolverSettings) else SolverSettings(contact_margin=CONTACT_MARGIN)
    f = getattr(d.solver, "body", None)
    return fit_measures(mesh, d.positions, body, fabric,
                        body.distance_field(f.spacing) if isinstance(f, DistanceField)
                        else None, reach=max(fabric.thickness, s.contact_margin))


def verdict_rules(*, pressure_max: float | None = None, stretch_limit: float | None = None,
                  style: str | None = None) -> VerdictRules:
    """The fit verdict's thresholds with these replaced where not None: ``pressure_max``
    [kPa] above which a region is too tight (one below the comfort pressure, 1.3 kPa,
    lowers that to it), the fabric's comfortable ``stretch_limit`` [-], the garment
    ``style`` whose ease ranges apply; ``ValueError`` naming a bad one."""
    rules = VerdictRules()
    comfort = None
    if pressure_max is not None:
        pressure_max = number(pressure_max, "pressure_max", low=0.0, low_open=True,
                              unit="kPa")
        comfort = min(rules.pressure_comfort_kpa, pressure_max)
    return rules.with_options(pressure_max_kpa=pressure_max, pressure_comfort_kpa=comfort,
                              stretch_limit=stretch_limit, style=style)


def drape_and_evaluate(pattern: Pattern | str | Path = DEFAULTS.garment,
                       body: Body | str | Path = DEFAULTS.body,
                       fabric: Fabric | str | Path = DEFAULTS.fabric, *,
                       triangles: int = DEFAULTS.triangles, size: str | None = None,
                       units: str | None = None, engine: str = "static",
                       settings: SolverSettings | None = None,
                       clearance: float = DEFAULTS.clearance, device: str | None = None,
                       from_static: bool = False, tight: float = DEFAULTS.tight,
                       loose: float = DEFAULTS.loose, start=None,
                       progress: Callable | None = None,
                       verdict_rules: VerdictRules | None = None) -> FitOutcome:
    """Mesh ``pattern``, place it around ``body``, sew and drape it in ``fabric`` to rest,
    and evaluate the fit.

    Parameters
    ----------
    pattern, body, fabric
        Objects, built-in names or files (see :func:`read_pattern`, :func:`read_body`,
        :func:`read_fabric`).
    triangles : int
        Target triangle count of the garment mesh.
    size : str, optional
        A built-in garment's size (default ``Defaults.size``) or a graded DXF's (default its
        sample size); see :func:`read_pattern`.
    engine : str
        ``"static"`` (equilibrium, default) or ``"newton"`` (dynamic; optional extra).
    settings : SolverSettings, optional
        Iteration and time limits [s] of the drape.
    clearance : float
        Gap between body and panels at placement [m].
    tight, loose : float
        Area change beyond which a triangle counts as tight / loose [-].
    start : path, FitOutcome or (n, 3) float, optional
        Continue from a saved drape instead of placing and sewing: a garment folder as the
        drape writes it (``garment/``: ``pattern.json``, ``mesh.npz``, ``positions.npy``,
        ``contact.npz``) of this same pattern (:class:`InputError` otherwise), or an
        earlier outcome of this function for the same pattern, each with its own mesh
        (``triangles`` is then not used), or positions (n, 3) [m] of the pattern meshed
        with ``triangles``. The solve starts there with the seams welded (static engine). A
        folder or an outcome carries the drape's contact state, so the solve continues that
        drape (from its rest it stops at once and moves nothing); bare positions do not,
        and each contact's stiffness is read back from the force balance instead.
    progress : callable, optional
        ``progress(iteration, energy [J], step [m], elapsed [s])``; a callback with a
        parameter named ``residual`` also gets ``residual=`` the rms of |F_i| / (m_i g) [-]
        (at rest ≤ 0.01; the static engine only). Raising KeyboardInterrupt in it stops
        cleanly with the last state.
    verdict_rules : VerdictRules, optional
        The thresholds of the fit verdict (pressure, stretch limit, ease ranges' style);
        :class:`VerdictRules` () by default.

    Every drape gets the on-body checks (:mod:`patternfit.sim.onbody`); ``passed`` is
    False and ``checks["reasons"]`` says why when the garment is not on the body where its
    pattern says, whatever ϖ reads.

    A pattern of several pieces without seams between them (or with a piece sewn to
    nothing) is refused before anything is meshed (:func:`check_sewn`, a
    :class:`PatternError` naming the fix ``patternfit seams PATTERN --suggest --accept``);
    a one-piece garment is draped as it is.
    """
    t0 = time.perf_counter()
    checked_clearance(clearance)
    # every option checked before minutes of draping, not by the stage that first uses it
    fit_bands(tight, loose)
    instance(settings, SolverSettings, "settings", "a SolverSettings", optional=True)
    instance(verdict_rules, VerdictRules, "verdict_rules", "api.verdict_rules(...)",
             optional=True)
    if progress is not None and not callable(progress):
        raise ValueError(f"progress: expected a function, got {progress!r:.60}")
    pat = check_drapeable(read_pattern(pattern, size=size), source=pattern)
    b = read_body(body, units=units)
    fab = read_fabric(fabric)
    if start is not None:
        if engine != "static":
            raise ValueError("start: a saved drape is continued by the static engine only")
        x, contact, m = _start_state(start, pat, triangles)
        for other in not_draped_for(contact, b):
            # the start lies where the other body was (11 mm inside a heavier one) and
            # may settle in another rest than a drape from placement (tight, not loose)
            warnings.warn(f"start: the saved drape was draped on {other}; draping on from "
                          "its rest may end in another rest than a drape from the placement",
                          StartWarning, stacklevel=2)
        try:
            d = drape(pat, m, b, fab, settings=settings, clearance=clearance, start=x,
                      start_contact=contact, progress=progress)
        except SavedStateError as e:
            if not isinstance(start, (str, Path)):
                raise
            raise GarmentFileError(f"does not fit this drape's mesh: {e.reason}",
                                   file=garment_folder(start) / CONTACT,
                                   place=f"array '{e.array}'") from None
    else:
        m = mesh_pattern(pat, triangles=triangles)
        d = drape_with(engine, pat, m, b, fab, settings=settings, device=device,
                       from_static=from_static, clearance=clearance, progress=progress)
    if d.onbody is None:  # an engine that does not run them itself
        d.check_on_body(pat, m, b, fab)
    evaluator = FitEvaluator(m, tight=tight, loose=loose)
    extra = d.report_extra()
    extra["fitting_ratio_placed"] = evaluator.metrics(d.placed)[1]
    fit = evaluator(d.positions)
    measures = _measures(d, m, b, fab)
    return FitOutcome(pat, m, b, fab, d.positions, fit, drape=d, extra=extra,
                      seconds=time.perf_counter() - t0, measures=measures,
                      judgement=judge_garment(pat, fit, measures, fab, extra.get("checks"),
                                              verdict_rules))


def _meshable(source, pattern: Pattern) -> Pattern:
    """``pattern``, read from ``source``, once it is known to mesh (:func:`check_pattern`);
    else the :class:`PatternError` names the file (a GarmentCode gather beyond 2:1 was
    refused by the mesher naming only the panel)."""
    try:
        check_pattern(pattern)
    except PatternError as exc:
        if _file_of(source) is None or exc.file is not None:
            raise
        raise exc.located(source) from None
    return pattern


def check_drapeable(pattern: Pattern, *, source=None) -> Pattern:
    """``pattern`` (read from ``source``: a file, a built-in name, or None), once it is
    known to drape: meshable (:func:`check_pattern`), sewn (:func:`check_sewn`) and of a
    garment's size (:func:`~patternfit.pattern.plausible.check_drapeable_size`); else the
    :class:`PatternError` names the file. What ``drape`` refuses before any work (exit 2),
    the batch refuses before its tasks (it drew a failed row for each, exit 0)."""
    instance(pattern, Pattern, "pattern", "a Pattern (api.read_pattern)")
    check_sewn(pattern, source=_file_of(source))
    check_drapeable_size(pattern, source=_file_of(source))
    return _meshable(source, pattern)


def _file_of(source):
    """The file a pattern ``source`` names, None for a pattern or a built-in name."""
    return None if isinstance(source, Pattern) or str(source) in GARMENTS else source


def _threshold(value) -> float:
    """The ϖ at which a design fits [-], in (0, 1.5]; a ``ValueError`` naming it."""
    return number(value, "threshold", low=0.0, low_open=True, high=1.5,
                  rule="expected a fraction such as 0.9")


def _start_state(start, pattern: Pattern, triangles: int):
    """What a drape of ``pattern`` continues from: positions (n, 3) [m], the contact state
    saved with them (named arrays, or None) and their mesh. ``start`` is a saved garment
    folder or an earlier outcome, which must hold a drape of this same pattern and bring
    their own mesh (an edited one included: the correction loop's meshes follow its edits),
    or positions of the pattern meshed with ``triangles``."""
    if isinstance(start, FitOutcome):
        if start.drape is None or not start.pattern.same_cut(pattern):
            raise ValueError("start: an outcome of a drape of this same pattern")
        return np.array(start.positions), _solver_state(start.drape.saved_contact()), \
            start.mesh
    if not isinstance(start, (str, Path)):
        mesh = mesh_pattern(pattern, triangles=triangles)
        x = np.asanyarray(start, dtype=np.float64)
        if x.shape != (mesh.n_vertices, 3) or not np.isfinite(x).all():
            raise ValueError(f"start: expected finite positions ({mesh.n_vertices}, 3) of the "
                             f"mesh, got {x.shape}")
        why = _collapsed(mesh, x)
        if why:
            raise ValueError(f"start: {why}")
        return x, None, mesh
    start = garment_folder(start)
    saved, saved_mesh, x = load_garment(start)
    if x is None:
        raise InputError("holds no 3D state (positions.npy): drape the garment first",
                         file=start)
    if not saved.same_cut(pattern):
        def named(p: Pattern) -> str:
            size = p.meta.get("size")
            return f"'{p.name}'" + (f" size {size}" if size else "")

        if named(saved) == named(pattern) and saved.panels != pattern.panels \
                and [p.name for p in saved.panels] == [p.name for p in pattern.panels]:
            # "another pattern ('skirt' size S ...), not of this 'skirt' size S" said nothing
            raise InputError(f"holds a drape of another version of {named(pattern)} (the "
                             "same pieces in other shapes: edited or corrected since); start "
                             "from its own pattern.json (--pattern), or from a drape of this "
                             "one", file=start)
        raise InputError(f"holds a drape of another pattern ({named(saved)}, panels "
                         f"{', '.join(p.name for p in saved.panels)}), not of this "
                         f"{named(pattern)}: start from a drape of the same pattern",
                         file=start)
    why = _collapsed(saved_mesh, x)
    if why:
        raise InputError(why, file=Path(start) / "positions.npy")
    return x, _solver_state(load_contact(start)), saved_mesh


def _solver_state(contact: dict | None) -> dict | None:
    """A saved contact state a drape can continue, or None when it holds no solver arrays
    (a drape stopped while sewing: continued from its positions alone)."""
    return contact if contact is not None and SAVED[0] in contact else None


def _collapsed(mesh: GarmentMesh, x) -> str | None:
    """Why positions ``x`` (n, 3) [m] of ``mesh`` are no state to continue a drape from
    (their 3D area below the on-body checks' share of the flat area: every vertex at one
    point, a garment flattened), or None."""
    ratio = area_ratio(mesh, x)
    if ratio >= ON_BODY.min_area_ratio:
        return None
    return (f"a collapsed state, not a drape to continue: its 3D area is {ratio * 100:.0f}% "
            f"of the flat pattern's (at least {ON_BODY.min_area_ratio * 100:.0f}%)")


def evaluate_saved(folder, *, tight: float = DEFAULTS.tight,
                   loose: float = DEFAULTS.loose, body: Body | str | Path | None = None,
                   fabric: Fabric | str | Path | None = None, units: str | None = None,
                   verdict_rules: VerdictRules | None = None) -> FitOutcome:
    """The fit of a saved garment folder's 3D state (``pattern.json``, ``mesh.npz``,
    ``positions.npy``); :class:`InputError` when the folder holds no 3D state. With the
    ``body`` it was draped on (and its ``fabric``: None, the one its drape saved in
    ``contact.npz``, else the default), also the state's checks on that body
    (:func:`patternfit.sim.onbody.saved_state_checks`: where it rests, vertices inside,
    seams, cloth edges and triangles through the body, crossed triangle pairs; a state
    that fell, slid, went through the body or was moved off it fails them and its verdict
    says so), the fit measures and the verdict (contact distance the drape's default
    margin). Without a body nothing checks where the state lies: ϖ alone, its checks'
    ``passed`` None ("not checked"), False when its drape said it failed on its own body
    (``contact.npz``'s ``drape_reasons``). A state its drape saved before it came to rest
    (``contact.npz``'s ``at_rest`` false) fails either way; its ``residual_rms`` /
    ``residual_p99`` are the drape's. With a body, one whose contact state is not of these
    positions, this mesh, this body and this fabric (none saved, moved since, the pattern
    edited in place, read on another body or in another fabric:
    ``checks.equilibrium_unknown`` says which) has its balance rebuilt in the fabric
    (:func:`patternfit.sim.drape.saved_balance`, 0.7 s at 22K triangles) and fails when 1 %
    of its vertices are off by more than their weight. The outcome keeps the contact state,
    and writes it with the state again."""
    folder = path_arg(folder, "folder", what="a garment folder")
    pat, m, x = load_garment(folder)
    if x is None:
        raise InputError("holds no 3D state (positions.npy): place or drape the garment first",
                         file=folder)
    fit = FitEvaluator(m, tight=tight, loose=loose)(x)
    # the drape that saved the state said whether it had come to rest, on which body and
    # in which fabric (contact.npz)
    garment = garment_folder(folder)
    file = garment / CONTACT
    contact = load_contact(garment)
    b = None if body is None else read_body(body, units=units)
    own = saved_fabric(contact, file=file)
    fab = read_fabric(fabric) if fabric is not None else own or read_fabric(DEFAULTS.fabric)
    at_rest, unknown = saved_rest(contact, x, mesh=m, file=file,
                                  draped_for=draped_for(b, fab if b is not None else None))
    if at_rest and b is not None:
        # a rest said by a file whose solver arrays are damaged (NaN) is not taken on its
        # word, as drape --start would not take it (its "not at rest" stands)
        fault = saved_contact_fault(m, b, x, contact)
        if fault:
            at_rest, unknown = None, f"its {CONTACT} is damaged ({fault})"
    residual = None if at_rest is None else saved_residual(contact, file=file)
    if at_rest and residual is not None \
            and (residual[0] > tol.rest_rms or residual[1] > tol.rest_p99):
        at_rest = False  # saved "at rest" by a looser rule (rms 0.30): not a rest
    rest = {"at_rest": at_rest, "unknown": unknown, "residual": residual}
    if b is None:
        # what its drape found on its own body, where the contact state is of this state
        failed = None if at_rest is None else saved_failure(contact, file=file)
        return FitOutcome(pat, m, None, None, x, fit, state="saved",
                          extra={"checks": unchecked_state(**rest, failed=failed)},
                          contact=contact)
    assumed = fab.name if fabric is None and own is None else None
    checks = saved_state_checks(pat, m, b, x, balance=lambda: saved_balance(m, b, fab, x),
                                crossings=lambda: saved_crossings(m, b, x),
                                floor=lambda onbody: without_floor(pat, m, b, fab, x, onbody),
                                assumed_fabric=assumed, **rest)
    measures, judgement = judge_state(pat, m, x, fit, b, fab, checks=checks,
                                      verdict_rules=verdict_rules)
    return FitOutcome(pat, m, b, fab, x, fit, state="saved", extra={"checks": checks},
                      measures=measures, judgement=judgement, contact=contact)


def judge_state(pattern: Pattern, mesh: GarmentMesh, positions, fit: FitResult, body: Body,
                fabric: Fabric, *, checks: dict | None = None,
                verdict_rules: VerdictRules | None = None) -> tuple[FitMeasures, Verdict]:
    """The fit measures and verdict of a 3D state of ``pattern`` meshed as ``mesh``:
    ``positions`` (n, 3) [m] on ``body`` in ``fabric``, ``fit`` its evaluation
    (:func:`evaluate_drape`), ``checks`` its drape's checks (None: judged as passed; failed:
    the verdict is "failed"), contact at the drape's default margin (3 mm) or the fabric's
    thickness. About 0.1 s at 1.5K triangles."""
    instance(pattern, Pattern, "pattern", "a Pattern")
    instance(mesh, GarmentMesh, "mesh", "a GarmentMesh")
    positions = array(positions, "positions", shape=(mesh.n_vertices, 3))
    instance(fit, FitResult, "fit", "a FitResult (api.evaluate_drape)")
    instance(body, Body, "body", "a Body")
    instance(fabric, Fabric, "fabric", "a Fabric")
    measures = fit_measures(mesh, positions, body, fabric,
                            reach=max(fabric.thickness, CONTACT_MARGIN))
    return measures, judge_garment(pattern, fit, measures, fabric, checks, verdict_rules)


def place_and_evaluate(pattern: Pattern | str | Path = "coat", *, triangles: int = 22000,
                       size: str | None = None, tight: float = DEFAULTS.tight,
                       loose: float = DEFAULTS.loose) -> FitOutcome:
    """Mesh ``pattern`` (a pattern, built-in name or file, in ``size``) with about
    ``triangles`` triangles and place it isometrically (every panel rolled onto a cylinder),
    with its fit (``tight`` and ``loose``: the map's bands, relative area change [-]): ϖ is
    100% and the map one neutral colour (the paper's Fig. 8(b)). The :class:`FitOutcome`'s
    ``positions`` are (n, 3) [m]; it has no body, fabric or drape."""
    t0 = time.perf_counter()
    fit_bands(tight, loose)
    pat = read_pattern(pattern, size=size)
    m = mesh_pattern(pat, triangles=triangles)
    x = place_on_cylinders(pat, m)
    return FitOutcome(pat, m, None, None, x, FitEvaluator(m, tight=tight, loose=loose)(x),
                      seconds=time.perf_counter() - t0, state="placed")


def placed_fitting_ratio(session: DesignSession) -> float:
    """ϖ of the session's current mesh placed around its body before any drape [-]
    (about 1.0: the placement is isometric)."""
    instance(session, DesignSession, "session", "a DesignSession (api.design_session)")
    placed = place_on_body(session.pattern, session.mesh, session.body)
    return float(FitEvaluator(session.mesh).metrics(placed)[1])


def design_session(pattern: Pattern | str | Path = DEFAULTS.garment,
                   body: Body | str | Path = DEFAULTS.body,
                   fabric: Fabric | str | Path = DEFAULTS.fabric, *,
                   triangles: int = DEFAULTS.triangles, threshold: float = DEFAULTS.threshold,
                   size: str | None = None, units: str | None = None,
                   relax: float = 1.0) -> DesignSession:
    """A :class:`DesignSession` (edits with the mesh following, undo/redo, drapes, save)
    of ``pattern`` on ``body`` in ``fabric``; see :func:`read_pattern`, :func:`read_body`,
    :func:`read_fabric` for what each may be (``size`` a pattern's, ``units`` a body mesh
    file's). Meshed with about ``triangles`` triangles; nothing is draped until the session's
    ``redrape()``. ``threshold`` is the ϖ at which the design fits [-]; ``relax`` (>= 1) sews
    the first drape that much wider, then restores the true width (for a garment drafted
    too small to be sewn on the body). A pattern without seams is taken (sew it in the
    session); :func:`check_drapeable` says whether one drapes."""
    threshold = _threshold(threshold)
    relax = number(relax, "relax", low=1.0, high=10.0, rule="expected a factor of 1 to 10")
    return DesignSession(_meshable(pattern, read_pattern(pattern, size=size)),
                         read_body(body, units=units), read_fabric(fabric), triangles,
                         threshold, relax=relax)


def drafted_too_small(garment: str = DEFAULTS.garment, size: str | None = None) -> dict:
    """The demo's setup: a built-in garment drafted too small for a body, as in the paper's
    Table 2 row for it (every panel narrowed across the grain; the body, the fabric and the
    sewing width of that row), or narrowed to 80% in a stretch knit on the average woman for
    a garment without a row.

    Returns ``{"pattern", "body", "fabric", "narrow", "relax", "size"}``."""
    row = {r.garment: r for r in ROWS}.get(garment)
    body, narrow, fabric, relax = (row.body, row.narrow, row.fabric, row.relax) if row \
        else (DEFAULTS.body, 0.8, "stretch_knit", 1.0)
    _size(size)
    size = size or (row.size if row else DEFAULTS.size)
    pattern = grade(build(garment, size), None, narrow, 1.0)
    return {"pattern": pattern, "body": body, "fabric": fabric, "narrow": narrow,
            "relax": relax, "size": size.upper()}


def correct_design(session: DesignSession, out, *, threshold: float | None = None,
                   max_iterations: int = DEFAULTS.correction_rounds, pictures: bool = True,
                   extra: dict | None = None, progress: Callable | None = None,
                   drape_progress: Callable | None = None,
                   write_progress: Callable | None = None, take_in: bool = False,
                   verdict_rules: VerdictRules | None = None, goal: str = "tight") -> dict:
    """Correct the session's pattern automatically (drape, find the tight regions, move the
    seam corners, re-drape, until ϖ reaches ``threshold`` — the session's when None — and
    no region is too tight by the fit verdict (``verdict_rules``; with ``goal`` "fits" none
    tight either, with ``take_in`` none too loose), or ``max_iterations`` rounds) and write the outputs into ``out``:
    ``pattern.json`` (the corrected pattern), ``report.json`` (with ``verdict`` and
    ``region_verdicts`` of the final drape, and of every iteration), ``before/`` and
    ``after/`` fit outputs and the regions pictures (a correction refused from a failed
    drape, ``report["failed"]``, writes no ``pattern.json`` and no ``after/``). When edits
    were made, the report's ``fresh_drape`` says what the corrected pattern reads draped
    afresh from its placement (:func:`fresh_drape`); when that drape fails its checks,
    ``reached`` is false (the loop's own is ``loop_reached``). Returns the report.

    ``progress(iteration)`` is called after each drape is evaluated, ``drape_progress`` goes
    to the solver, ``write_progress(message)`` is called per output written."""
    # checked before the first drape: max_iterations -1 failed after pattern.json was written
    instance(session, DesignSession, "session", "a DesignSession (api.design_session)")
    out = path_arg(out, "out", what="an output folder")
    if threshold is not None:
        threshold = _threshold(threshold)
    number(max_iterations, "max_iterations", low=0, integer=True)
    instance(verdict_rules, VerdictRules, "verdict_rules", "api.verdict_rules(...)",
             optional=True)
    settings = CorrectionSettings(threshold=session.threshold if threshold is None
                                  else threshold, max_iterations=max_iterations,
                                  take_in=bool(take_in), goal=goal,
                                  rules=verdict_rules or VerdictRules())
    result = correct(session, settings=settings, drape_progress=drape_progress,
                     progress=progress)
    if result.edited:
        fresh = fresh_drape(result.pattern, session, verdict_rules=settings.rules,
                            progress=drape_progress)
        extra = {**(extra or {}), "fresh_drape": fresh}
        if fresh["passed"] is False:
            # the garment made from the pattern failed: no fit reached, whatever the loop
            # read (report.json said "reached" where the CLI exits "fit not reached")
            extra |= {"reached": False, "loop_reached": result.reached}
    return write_correction_outputs(out, session, result, extra=extra, pictures=pictures,
                                    progress=write_progress)


def fresh_drape(pattern: Pattern, session: DesignSession, *,
                verdict_rules: VerdictRules | None = None,
                progress: Callable | None = None) -> dict:
    """ϖ, verdict and checks of ``pattern`` (a correction's result, :attr:`Correction.pattern`)
    meshed anew, placed and draped from the start on ``session``'s body in its fabric, sewn
    as it is (not widened as a session may sew a first drape drafted too small: widened
    1 / 0.6 times, the demo's corrected skirt fell past the hips): what the garment made
    from it reads. The loop's own drapes go on from its first one, where a skirt 40 % too
    narrow stuck 9 cm above the waist: its "too loose" after/ read "too tight" draped afresh.
    Every front end that corrects says this too (the CLI's ``correct`` and ``demo``, the
    studio).

    Returns ``{"fitting_ratio", "verdict", "verdict_reason", "passed", "reasons",
    "equilibrium"}`` (``fitting_ratio`` None where not finite); ``passed`` False (the
    drape failed its checks, ``reasons`` say why) means the correction did not reach a fit,
    whatever its loop read."""
    instance(pattern, Pattern, "pattern", "a Pattern (a correction's result.pattern)")
    instance(session, DesignSession, "session", "a DesignSession (api.design_session)")
    instance(verdict_rules, VerdictRules, "verdict_rules", "api.verdict_rules(...)",
             optional=True)
    fresh = DesignSession(pattern, session.body, session.fabric, session.triangles,
                          session.threshold)
    fresh.redrape(progress=progress)
    st = fresh.state
    fit = FitEvaluator(st.mesh)(st.positions)
    _, verdict = judge_state(st.pattern, st.mesh, st.positions, fit, session.body,
                             fresh.fabric, checks=st.checks,
                             verdict_rules=verdict_rules or VerdictRules())
    said = verdict.report()
    ratio = float(fit.fitting_ratio)
    return {"fitting_ratio": ratio if np.isfinite(ratio) else None,
            "verdict": said.get("verdict"),
            "verdict_reason": said.get("verdict_reason"), "passed": st.checks.get("passed"),
            "reasons": st.checks.get("reasons") or [],
            "equilibrium": st.checks.get("equilibrium")}
