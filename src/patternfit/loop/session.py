"""The design session: body, fabric, pattern, its mesh, the last drape and the fit, with the
edit history (METHOD.md section 1: drape → evaluate → edit → re-drape).

Every state of the history keeps its pattern, its mesh and, once draped, its 3D positions,
so undo restores exactly what was there. Saving is atomic: a session folder holds complete
snapshots and a ``current`` file naming the last one, replaced in one rename.
"""

from __future__ import annotations

import io
import json
import shutil
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ..body.builtin import list_bodies, load_body, read_body, save_body
from ..files import atomic_write_bytes, atomic_write_text, json_default
from ..fit.metrics import FitEvaluator, FitResult
from ..mesh.garment import GarmentMesh
from ..mesh.triangulate import mesh_pattern
from ..pattern.errors import PatternError
from ..pattern.io import load_pattern, save_pattern
from ..pattern.library import build
from ..pattern.model import Pattern
from ..sim.drape import Drape, drape, redrape
from ..sim.fabrics import Fabric, get_fabric

#: the editing tools a session applies by name (``patternfit.edit``)
EDIT_OPS = ("move_point", "move_edge", "edit_curve", "lengthen", "grade", "insert_dart",
            "move_dart", "resize_dart")

SNAPSHOT_FORMAT = "patternfit-session"

#: largest motion of a flat vertex [m] between the stages of a warm re-drape
STAGE_LENGTH = 0.03
#: iteration limit of a warm re-drape's intermediate stages
STAGE_ITERATIONS = 200


@dataclass(eq=False)
class State:
    """One entry of the history: the pattern after an edit (or the start), its mesh, and
    the drape and fit once computed.

    Attributes
    ----------
    label : str
        What was done, in words ("start", "lengthen front: +2.0 cm").
    edit : dict or None
        The edit as applied: ``{"op": name, "args": {...}}`` (lengths in metres).
    pattern : Pattern
    mesh : GarmentMesh
    positions : (n, 3) float or None
        3D state of every flat vertex [m], once draped.
    fitting_ratio : float or None
        ϖ of ``positions``.
    checks : dict or None
        The drape's checks (``DrapeChecks.to_dict()`` plus ``passed``).
    """

    label: str
    edit: dict | None
    pattern: Pattern
    mesh: GarmentMesh
    positions: np.ndarray | None = None
    fitting_ratio: float | None = None
    checks: dict | None = None


@dataclass(eq=False)
class DesignSession:
    """A garment being designed on one body in one fabric.

    Parameters
    ----------
    pattern : Pattern
    body : patternfit.body.Body
    fabric : Fabric or str
        A fabric or preset name.
    triangles : int
        Target triangle count of the garment mesh.
    threshold : float
        ϖ at which the design counts as fitting (METHOD.md section 1; default 0.90).
    relax : float
        Width factor (>= 1) of the cold drape of the starting pattern (the history's first
        state): the garment is sewn and draped with every panel widened across by
        ``relax`` about its centre, then its true rest shape is restored and the drape
        solved again warm. A garment drafted much too small cannot be sewn around the body
        directly (the seams squeeze it off the body); 1.0 sews it as it is. An edited
        pattern whose mesh had to be re-meshed is draped cold as it is (its edits made it
        fit better, and a narrow-by-``relax`` grading of it need not keep its seams
        matched).
    """

    pattern: Pattern
    body: Any
    fabric: Fabric | str = "cotton"
    triangles: int = 3000
    threshold: float = 0.90
    history: list[State] = field(default_factory=list)
    position: int = 0
    _drape: Drape | None = field(default=None, repr=False)
    relax: float = 1.0

    def __post_init__(self):
        self.fabric = get_fabric(self.fabric)
        if not (np.isfinite(self.relax) and self.relax >= 1.0):
            raise ValueError(f"relax: must be a factor >= 1, got {self.relax!r}")
        if not self.history:
            self.history = [State("start", None, self.pattern,
                                  mesh_pattern(self.pattern, triangles=self.triangles))]
        self.pattern = self.history[self.position].pattern

    @classmethod
    def new(cls, *, garment: str = "skirt", size: str = "M", body: str = "female_average",
            fabric: str = "cotton", triangles: int = 3000, threshold: float = 0.90,
            relax: float = 1.0, **options) -> "DesignSession":
        """A session on a built-in garment (``options`` go to its drafting function) and a
        built-in body."""
        return cls(build(garment, size, **options), load_body(body), fabric, triangles,
                   threshold, relax=relax)

    # -- the current state ---------------------------------------------------------------
    @property
    def state(self) -> State:
        return self.history[self.position]

    @property
    def mesh(self) -> GarmentMesh:
        return self.state.mesh

    @property
    def positions(self) -> np.ndarray | None:
        return self.state.positions

    def evaluate(self, *, tight: float = 0.02, loose: float = 0.02) -> FitResult:
        """Fit of the current 3D state; raises ``RuntimeError`` before the first drape."""
        if self.state.positions is None:
            raise RuntimeError("nothing draped yet: call redrape() first")
        return FitEvaluator(self.mesh, tight=tight, loose=loose)(self.state.positions)

    def redrape(self, *, progress: Callable | None = None) -> Drape:
        """Drape the current state: warm-started from the last drape when the mesh kept its
        topology, from the placement otherwise. Records ϖ and the checks in the history."""
        st = self.state
        same = (self._drape is not None
                and np.array_equal(self._drape.solver.triangles, st.mesh.triangles))
        if same:
            result = self._staged_redrape(st.mesh, st.positions, progress)
        elif self.relax > 1.0 and self.position == 0:
            wide_pattern, wide_mesh = _widened(st.pattern, st.mesh, self.relax)
            first = drape(wide_pattern, wide_mesh, self.body, self.fabric, progress=progress)
            result = redrape(first, st.mesh, start=first.result.x, progress=progress)
            result.placed = first.placed
            result.seconds += first.seconds
            result.timing = {**first.timing, "relaxed_sewing_seconds": first.seconds}
        else:
            result = drape(st.pattern, st.mesh, self.body, self.fabric, progress=progress)
        self._drape = result
        st.positions = result.positions
        st.fitting_ratio = FitEvaluator(st.mesh).metrics(result.positions)[1]
        st.checks = {**result.checks.to_dict(), "passed": result.checks.passed}
        return result

    def _staged_redrape(self, mesh: GarmentMesh, start, progress) -> Drape:
        """Warm re-drape to the rest shapes of ``mesh``, reached in stages of at most
        ``STAGE_LENGTH`` of flat-vertex motion, the intermediate ones solved for at most
        ``STAGE_ITERATIONS``: a garment whose rest shapes grew by 12 cm at once (a coat
        corrected from 65% of its width) expands faster than the solver's lagged
        self-collision pairs follow and crossed itself (7-8 crossing pairs on the Table 2
        coat and trousers); in three stages of 4 cm, 0 or 1; in four of 3 cm, 0, and
        faster than in one."""
        solver = self._drape.solver
        old = solver.rest
        if np.array_equal(start, self._drape.positions):
            # the last drape itself: redrape starts from it moved with the edit
            start = None
        change = float(np.linalg.norm(mesh.vertices - old, axis=1).max(initial=0.0))
        stages = max(1, int(np.ceil(change / STAGE_LENGTH)))
        full, previous, seconds = solver.settings, self._drape, 0.0
        try:
            solver.settings = replace(full, max_iterations=min(STAGE_ITERATIONS,
                                                               full.max_iterations))
            for k in range(1, stages):
                previous = redrape(previous, mesh.with_vertices(old + k / stages
                                                                * (mesh.vertices - old)),
                                   start=start, progress=progress)
                start, seconds = None, seconds + previous.seconds
                if previous.result.interrupted:
                    break
        finally:
            solver.settings = full
        result = redrape(previous, mesh, start=start, progress=progress)
        result.seconds += seconds
        return result

    # -- editing -------------------------------------------------------------------------
    def apply(self, op: str, *, label: str | None = None, **args):
        """Apply the editing tool ``op`` (one of ``EDIT_OPS``) with ``args`` (lengths [m]).

        The mesh follows through the generalized barycentric coordinates when the edit keeps
        the panels' edges (re-meshing only panels whose quality demands it); an edit that
        adds edges (a new dart) re-meshes the garment. The 3D state is kept as the start of
        the next re-drape; ϖ is unknown until then. Returns the mesh update's report, or
        None after a re-mesh. Redo history beyond the current state is dropped.
        """
        from .. import edit as tools

        if op not in EDIT_OPS:
            raise ValueError(f"op: unknown edit {op!r} (known: {', '.join(EDIT_OPS)})")
        new_pattern = getattr(tools, op)(self.state.pattern, **args)
        return self.apply_pattern(new_pattern, label=label or _describe(op, args),
                                  edit={"op": op, "args": args})

    def apply_pattern(self, new_pattern: Pattern, *, label: str, edit: dict | None = None,
                      min_angle: float | None = None):
        """Make ``new_pattern`` (an edit of the current pattern made elsewhere, e.g. by the
        automatic correction) the next state; the mesh follows as in :meth:`apply`, its
        panels re-meshed when their smallest angle falls below ``min_angle`` [degrees]
        (default: ``edit.update_mesh``'s)."""
        from .. import edit as tools

        old = self.state
        report = None
        quality = {} if min_angle is None else {"min_angle": float(min_angle)}
        try:
            mesh, report = tools.update_mesh(old.pattern, new_pattern, old.mesh,
                                             return_report=True, **quality)
            positions = old.positions if np.array_equal(mesh.triangles,
                                                         old.mesh.triangles) else None
        except PatternError:
            mesh, positions = mesh_pattern(new_pattern, triangles=self.triangles), None
        del self.history[self.position + 1:]
        self.history.append(State(label, edit, new_pattern, mesh, positions))
        self.position += 1
        self.pattern = new_pattern
        return report

    def undo(self) -> State:
        """Go back one state (pattern, mesh and 3D state exactly as they were)."""
        if self.position == 0:
            raise IndexError("nothing to undo")
        self.position -= 1
        self.pattern = self.state.pattern
        return self.state

    def redo(self) -> State:
        """Go forward again after :meth:`undo`."""
        if self.position + 1 >= len(self.history):
            raise IndexError("nothing to redo")
        self.position += 1
        self.pattern = self.state.pattern
        return self.state

    def summary(self) -> list[dict]:
        """The history as rows: label, edit, ϖ, whether it is the current state."""
        return [{"index": i, "label": s.label, "edit": s.edit,
                 "fitting_ratio": s.fitting_ratio, "current": i == self.position}
                for i, s in enumerate(self.history)]

    # -- files ---------------------------------------------------------------------------
    def save(self, folder) -> Path:
        """Save the whole session (every state) into ``folder``, atomically.

        A new snapshot folder is written completely, then the ``current`` file is replaced
        to name it (one rename), then older snapshots are removed: a save killed at any
        point leaves the previous session loadable.
        """
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        snap = folder / f"snapshot-{time.time_ns()}"
        snap.mkdir()
        body_ref = self.body.name if self.body.name in list_bodies() else "body.npz"
        if body_ref == "body.npz":
            save_body(self.body, snap / "body.npz")
        states = []
        for i, s in enumerate(self.history):
            d = snap / f"state-{i:03d}"
            save_pattern(s.pattern, d / "pattern.json")
            s.mesh.save(d / "mesh.npz")
            if s.positions is not None:
                buf = io.BytesIO()
                np.save(buf, s.positions)
                atomic_write_bytes(d / "positions.npy", buf.getvalue())
            states.append({"label": s.label, "edit": s.edit, "fitting_ratio": s.fitting_ratio,
                           "checks": s.checks, "draped": s.positions is not None})
        meta = {"format": SNAPSHOT_FORMAT, "version": 1, "body": body_ref,
                "fabric": vars(self.fabric), "triangles": self.triangles,
                "threshold": self.threshold, "relax": self.relax, "position": self.position,
                "states": states}
        atomic_write_text(snap / "session.json", json.dumps(meta, indent=1, default=json_default))
        atomic_write_text(folder / "current", snap.name + "\n")
        for old in folder.glob("snapshot-*"):
            if old.name != snap.name:
                shutil.rmtree(old, ignore_errors=True)
        return folder

    @classmethod
    def load(cls, folder) -> "DesignSession":
        """Load a session saved by :meth:`save`."""
        folder = Path(folder)
        try:
            snap = folder / (folder / "current").read_text().strip()
            meta = json.loads((snap / "session.json").read_text())
        except (OSError, json.JSONDecodeError) as exc:
            raise PatternError(f"not a saved design session ({exc})", file=folder) from None
        if meta.get("format") != SNAPSHOT_FORMAT:
            raise PatternError("not a saved design session", file=folder)
        body = read_body(snap / "body.npz") if meta["body"] == "body.npz" \
            else load_body(meta["body"])
        history = []
        for i, s in enumerate(meta["states"]):
            d = snap / f"state-{i:03d}"
            positions = np.load(d / "positions.npy") if s["draped"] else None
            history.append(State(s["label"], s["edit"], load_pattern(d / "pattern.json"),
                                 GarmentMesh.load(d / "mesh.npz"), positions,
                                 s["fitting_ratio"], s["checks"]))
        return cls(history[meta["position"]].pattern, body, Fabric(**meta["fabric"]),
                   meta["triangles"], meta["threshold"], history, meta["position"],
                   relax=meta.get("relax", 1.0))


def _widened(pattern: Pattern, mesh: GarmentMesh, factor: float):
    """Pattern and mesh (same topology) with every panel widened by ``factor`` along x of
    its flat frame about its outline's centroid (as ``edit.grade`` does)."""
    from ..edit import grade

    v = mesh.vertices.copy()
    for i, name in enumerate(mesh.panel_names):
        c = pattern.panel(name).outline.polygon().mean(axis=0)
        ids = mesh.panel_vertices(i)
        v[ids, 0] = c[0] + factor * (v[ids, 0] - c[0])
    return grade(pattern, None, factor, 1.0), mesh.with_vertices(v)


def _describe(op: str, args: dict) -> str:
    """A short label for an edit: lengths shown in centimetres."""
    parts = []
    for k, v in args.items():
        if isinstance(v, (list, tuple, np.ndarray)) and np.asarray(v).dtype.kind == "f":
            parts.append(f"{k}=({', '.join(f'{c * 100:+.1f}' for c in np.ravel(v))}) cm")
        elif isinstance(v, float) and k in ("amount", "length", "width"):
            parts.append(f"{k}={v * 100:+.1f} cm")
        else:
            parts.append(f"{k}={v}")
    return f"{op} " + ", ".join(parts)
