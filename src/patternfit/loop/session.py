"""The design session: body, fabric, pattern, its mesh, the last drape and the fit, with the
edit history (METHOD.md section 1: drape → evaluate → edit → re-drape).

Every state of the history keeps its pattern, its mesh and, once draped, its 3D positions,
so undo restores exactly what was there. A saved session is a folder of immutable files:
each state written once into its own folder, a snapshot file listing the history, and a
``current`` file naming the snapshot, replaced in one rename (see :meth:`DesignSession.save`).
"""

from __future__ import annotations

import io
import os
import re
import shutil
import time
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from .. import edit as tools
from ..body.builtin import list_bodies, load_body, read_body, save_body
from ..constants import limits
from ..defaults import DEFAULTS
from ..edit import grade
from ..errors import InputError, SessionError
from ..files import (atomic_write_bytes, atomic_write_text, dumps_finite_json, read_json_file,
                     read_npy, read_npz)
from ..fit.metrics import FitEvaluator, FitResult
from ..mesh.garment import GarmentMesh
from ..mesh.store import contact_bytes, save_garment
from ..mesh.transfer import transfer
from ..mesh.triangulate import mesh_pattern
from ..pattern.errors import PatternError
from ..pattern.io import load_pattern
from ..pattern.library import build
from ..pattern.model import Pattern
from ..pattern.plausible import check_drapeable_size
from ..pattern.seam_suggest import check_sewn
from ..sim.drape import Drape, drape, redrape
from ..sim.fabrics import Fabric, get_fabric
from ..sim.schedule import Plan
from ..sim.state import SavedStateError

#: the editing tools a session applies by name (``patternfit.edit``)
EDIT_OPS = ("move_point", "move_edge", "edit_curve", "lengthen", "grade", "insert_dart",
            "move_dart", "resize_dart", "add_seam", "remove_seam", "set_seam_ease")

SNAPSHOT_FORMAT = "patternfit-session"
#: the layout :meth:`DesignSession.save` writes; version 1 (a full copy of every state per
#: snapshot) is still read
SNAPSHOT_VERSION = 2
#: the folder of a saved session that holds one folder per state
STATES = "states"
_SNAPSHOT = re.compile(r"snapshot-(\d+)(\.json)?")
_KEY = re.compile(r"[0-9a-f]{32}")
_POSITIONS = re.compile(r"positions-[0-9a-f]{32}\.npy")
_START_REST = re.compile(r"start-rest-[0-9a-f]{32}\.npy")
_CONTACT = re.compile(r"contact-[0-9a-f]{32}\.npz")
_BODY = re.compile(r"body-[0-9a-f]{32}\.npz")


class SessionWarning(UserWarning):
    """Something of a saved session that could not be used and was done without (a state's
    contact state missing or damaged), said rather than refusing the session."""


def _new_key() -> str:
    return os.urandom(16).hex()

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
        The drape's checks as the report holds them (``Drape.report_extra()["checks"]``:
        the solver's and the on-body checks, ``passed`` for both, ``reasons``).
    start_rest : (n, 2) float or None
        Before the state's first drape: the flat rest shapes [m] at which ``positions``
        (the start of that drape, an earlier state's drape) rest, once known; None after
        the drape. See :meth:`DesignSession.next_start`.
    contact : dict or None
        The contact state of the drape that made ``positions`` (``Drape.saved_contact``),
        saved beside them in the fit outputs (a correction's ``before/`` had none, and a
        drape continued from it took 2-12 iterations where a rest takes 0) and in a saved
        session (a session read back re-draped its draped states cold, from the placement).
    key : str
        The name of the state's folder in a saved session (random, fixed for the state's
        life: pattern and mesh are never replaced, so the folder is written once).
    """

    label: str
    edit: dict | None
    pattern: Pattern
    mesh: GarmentMesh
    positions: np.ndarray | None = None
    fitting_ratio: float | None = None
    checks: dict | None = None
    start_rest: np.ndarray | None = field(default=None, repr=False)
    contact: dict | None = field(default=None, repr=False)
    key: str = field(default_factory=_new_key, repr=False)
    # (positions array, its file name): a re-drape replaces the array (never edits it in
    # place), so a new array object is what needs a new file
    _stored_positions: tuple | None = field(default=None, repr=False)
    _stored_start_rest: tuple | None = field(default=None, repr=False)
    _stored_contact: tuple | None = field(default=None, repr=False)


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
        ϖ at which the design counts as fitting (METHOD.md section 1; ``DEFAULTS.threshold``).
    relax : float
        Width factor (>= 1) of the cold drape of the starting pattern (the history's first
        state): the garment is sewn and draped with every panel widened across by
        ``relax`` about its centre, then its true rest shape is restored and the drape
        solved again warm. A garment drafted much too small cannot be sewn around the body
        directly (the seams squeeze it off the body); 1.0 sews it as it is. An edited
        pattern whose mesh had to be re-meshed starts from the drape before the edit,
        carried over (:meth:`next_start`), or cold as it is when there is none (its edits
        made it fit better, and a narrow-by-``relax`` grading of it need not keep its seams
        matched).
    """

    pattern: Pattern
    body: Any
    fabric: Fabric | str = DEFAULTS.fabric
    triangles: int = DEFAULTS.triangles
    threshold: float = DEFAULTS.threshold
    history: list[State] = field(default_factory=list)
    position: int = 0
    _drape: Drape | None = field(default=None, repr=False)
    relax: float = 1.0
    _stored_body: tuple | None = field(default=None, repr=False)  # (body, its file name)

    def __post_init__(self):
        self.fabric = get_fabric(self.fabric)
        if not (np.isfinite(self.relax) and self.relax >= 1.0):
            raise ValueError(f"relax: must be a factor >= 1, got {self.relax!r}")
        if not self.history:
            self.history = [State("start", None, self.pattern,
                                  mesh_pattern(self.pattern, triangles=self.triangles))]
        self.pattern = self.history[self.position].pattern

    @classmethod
    def new(cls, *, garment: str = DEFAULTS.garment, size: str = DEFAULTS.size,
            body: str = DEFAULTS.body, fabric: str = DEFAULTS.fabric,
            triangles: int = DEFAULTS.triangles, threshold: float = DEFAULTS.threshold,
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

    def next_start(self) -> str:
        """Where :meth:`redrape` will start the current state's drape:

        - ``"warm"``: from the last drape, whose solver goes on (the mesh kept its
          topology);
        - ``"carried"``: from an earlier state's drape carried over to this state's mesh
          (:attr:`State.start_rest`: a panel was re-meshed by the edit, or the last drape
          is of another mesh), reaching the edited rest shapes in stages;
        - ``"continued"``: from the state's own drape (one made before an undo or redo, or
          read back from a saved session), with its contact state when it was kept
          (:attr:`State.contact`), as ``patternfit drape --start`` goes on from a saved
          drape: from a rest it stops at once;
        - ``"relaxed"``: the history's first state of a session with ``relax`` > 1;
        - ``"cold"``: placed, sewn and draped from the pattern.
        """
        st = self.state
        own = st.positions is not None and st.fitting_ratio is not None \
            and st.start_rest is None
        if own and (self._drape is None
                    or not np.array_equal(self._drape.positions, st.positions)):
            # a state undone or redone to holds its own drape: re-draped warm from the last
            # (another state's rest shapes and contacts), its rest moved 4-8 mm over 150-220
            # iterations
            return "continued"
        if (self._drape is not None
                and np.array_equal(self._drape.solver.model.triangles, st.mesh.triangles)
                and _sewing(self._drape.pattern) == _sewing(st.pattern)):
            return "warm"
        if st.positions is not None and st.start_rest is not None:
            return "carried"
        if st.positions is not None and st.fitting_ratio is not None:
            return "continued"
        if self.relax > 1.0 and self.position == 0:
            return "relaxed"
        return "cold"

    def redrape(self, *, progress: Callable | None = None) -> Drape:
        """Drape the current state from where :meth:`next_start` says: warm-started from the
        last drape when the mesh kept its topology, from an earlier drape carried over when
        a panel was re-meshed, from the placement otherwise. Records ϖ and the checks in
        the history. A pattern of several pieces not sewn together, or with a piece no
        garment has (:func:`~patternfit.pattern.seam_suggest.check_sewn`,
        :func:`~patternfit.pattern.plausible.check_drapeable_size`), is refused. Ctrl-C in
        the solve raises KeyboardInterrupt with nothing of the stopped drape recorded."""
        st = self.state
        check_sewn(st.pattern)
        check_drapeable_size(st.pattern)
        how = self.next_start()
        if how == "warm":
            result = self._staged_redrape(st.mesh, st.positions, progress, st.start_rest)
        elif how == "carried":
            result = drape(st.pattern, st.mesh, self.body, self.fabric, start=st.positions,
                           start_rest=st.start_rest, progress=progress)
        elif how == "continued":
            try:
                result = drape(st.pattern, st.mesh, self.body, self.fabric,
                               start=st.positions, start_contact=st.contact,
                               progress=progress)
            except SavedStateError as exc:
                # the contact state is a help, not the state: without it the drape goes on
                # from the positions and reads the contacts back from the force balance
                # (it failed every drape of the state, naming no file)
                warnings.warn(SessionWarning(
                    f"the saved contact state of '{st.label}' does not fit its mesh "
                    f"({exc}): its drape goes on from its positions, the contact rebuilt"),
                    stacklevel=2)
                st.contact = None
                result = drape(st.pattern, st.mesh, self.body, self.fabric,
                               start=st.positions, progress=progress)
        elif how == "relaxed":
            wide_pattern, wide_mesh = _widened(st.pattern, st.mesh, self.relax)
            first = _finished(drape(wide_pattern, wide_mesh, self.body, self.fabric,
                                    progress=progress))
            # the true rest shapes are reached in stages, as after a large edit: in one step
            # from 1 / 0.6 of the width the force stop ran out of iterations (the demo)
            self._drape = first
            result = self._staged_redrape(st.mesh, first.result.x, progress)
            result.placed = first.placed
            result.seconds += first.seconds
            result.timing = {**first.timing, "relaxed_sewing_seconds": first.seconds}
        else:
            result = drape(st.pattern, st.mesh, self.body, self.fabric, progress=progress)
        self._drape = _finished(result)
        st.positions, st.start_rest = result.positions, None
        st.contact = result.saved_contact(st.mesh)
        st.fitting_ratio = FitEvaluator(st.mesh).metrics(result.positions)[1]
        st.checks = result.report_extra()["checks"]  # solver and on-body checks, reasons
        return result

    def saved_contact(self, state: State) -> dict | None:
        """The contact state to save beside ``state``'s positions
        (:meth:`~patternfit.sim.drape.Drape.saved_contact`, kept from the drape that made
        them), so that a drape started from them continues that one; None when not known
        (not draped here: a state read back from a saved session)."""
        return state.contact

    def _staged_redrape(self, mesh: GarmentMesh, start, progress, start_rest=None) -> Drape:
        """Warm re-drape to the rest shapes of ``mesh`` in stages
        (:meth:`patternfit.sim.schedule.Plan.staged`: at most ``schedule.STAGE_LENGTH`` of flat-vertex
        motion each), from the last drape moved with the edit, or from ``start`` when that
        is another drape of the mesh: moved from ``start_rest``, the flat shapes it rests at,
        when they are known (an edit made after an undo), else as it is."""
        if np.array_equal(start, self._drape.positions):
            start = None
        origin = self._drape.solver.model.rest if start is None or start_rest is None \
            else start_rest
        change = float(np.linalg.norm(mesh.vertices - origin, axis=1).max(initial=0.0))
        return redrape(self._drape, mesh, start=start,
                       start_rest=None if start is None else start_rest,
                       plan=Plan.staged(change), progress=progress)

    # -- editing -------------------------------------------------------------------------
    def apply(self, op: str, *, label: str | None = None, cache=None, **args):
        """Apply the editing tool ``op`` (one of ``EDIT_OPS``) with ``args`` (lengths [m]).

        The mesh follows through the generalized barycentric coordinates when the edit keeps
        the panels' edges (re-meshing only panels whose quality demands it); an edit that
        adds edges (a new dart) re-meshes the garment. The 3D state is kept as the start of
        the next re-drape; ϖ is unknown until then. Returns the mesh update's report, or
        None after a re-mesh. Redo history beyond the current state is dropped. ``cache``:
        an ``edit.CoordinateCache`` of the current mesh (the studio's live drag keeps one:
        the edit then needs no coordinates computed again).
        """
        if op not in EDIT_OPS:
            raise ValueError(f"op: unknown edit {op!r} (known: {', '.join(EDIT_OPS)})")
        new_pattern = getattr(tools, op)(self.state.pattern, **args)
        return self.apply_pattern(new_pattern, label=label or _describe(op, args),
                                  edit={"op": op, "args": args}, cache=cache)

    def apply_pattern(self, new_pattern: Pattern, *, label: str, edit: dict | None = None,
                      min_angle: float | None = None, cache=None):
        """Make ``new_pattern`` (an edit of the current pattern made elsewhere, e.g. by the
        automatic correction) the next state; the mesh follows as in :meth:`apply`, its
        panels re-meshed when their smallest angle falls below ``min_angle`` [degrees]
        (default: ``edit.update_mesh``'s); ``cache`` as in :meth:`apply`.

        The current state's 3D positions go with the edit as the next drape's start. When a
        panel was re-meshed they are carried over to the new mesh through the flat panels
        (:func:`~patternfit.mesh.transfer.transfer` from the old mesh moved with the edit),
        with the flat shapes they rest at (:attr:`State.start_rest`): re-draped from the
        placement instead, the 22K Table 2 coat's fourth let-out took minutes and twice
        ended crossing itself and the body."""
        old = self.state
        report = None
        quality = {} if min_angle is None else {"min_angle": float(min_angle)}
        if cache is not None and cache.mesh is not old.mesh:
            cache = None  # built for another state's mesh
        # the flat shapes the current positions rest at: its own drape's, or its start's
        rest = old.mesh.vertices if old.fitting_ratio is not None else old.start_rest
        try:
            mesh, report = tools.update_mesh(old.pattern, new_pattern, old.mesh, cache=cache,
                                             return_report=True, **quality)
        except PatternError:
            mesh, report = mesh_pattern(new_pattern, triangles=self.triangles), None
        if report is None or old.positions is None:
            positions, start_rest = None, None
        elif np.array_equal(mesh.triangles, old.mesh.triangles):
            positions, start_rest = old.positions, rest
        elif rest is None or report.moved_mesh is None:
            positions, start_rest = None, None
        else:
            both = transfer(report.moved_mesh, np.hstack([old.positions, rest]), mesh)
            positions, start_rest = both[:, :3], both[:, 3:]
        del self.history[self.position + 1:]
        self.history.append(State(label, edit, new_pattern, mesh, positions,
                                  start_rest=start_rest))
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
        """Save the session into ``folder``; a save after an edit writes only what is new.

        Each state is written once into ``states/<key>/`` (pattern and mesh, into a hidden
        folder renamed into place when complete; each drape of it as its own positions
        file, with its contact state, :attr:`State.contact`, and a carried start's flat
        shapes, :attr:`State.start_rest`, beside it), the body
        once as ``body-<key>.npz``; then a snapshot file lists the history,
        then ``current`` is replaced to name it (one rename), then the files no longer named
        are removed. A save killed at any point leaves the previous session loadable.
        """
        folder = Path(folder)
        (folder / STATES).mkdir(parents=True, exist_ok=True)
        if self._stored_body is None or self._stored_body[0] is not self.body:
            self._stored_body = (self.body, f"body-{_new_key()}.npz")
        if not (folder / self._stored_body[1]).is_file():
            save_body(self.body, folder / self._stored_body[1])
        meta = {"format": SNAPSHOT_FORMAT, "version": SNAPSHOT_VERSION,
                "body": self._stored_body[1], "fabric": vars(self.fabric),
                "triangles": self.triangles, "threshold": self.threshold, "relax": self.relax,
                "position": self.position,
                "states": [_store_state(folder / STATES, s) for s in self.history]}
        name = f"snapshot-{time.time_ns()}.json"
        atomic_write_text(folder / name, dumps_finite_json(meta, indent=1))
        atomic_write_text(folder / "current", name + "\n")
        _remove_unnamed(folder, name, meta)
        return folder

    @classmethod
    def load(cls, folder) -> "DesignSession":
        """Load a session saved by :meth:`save`: the snapshot ``current`` names or, when
        that is missing or does not load, the newest snapshot that loads completely.
        Nothing is deleted. Raises :class:`~patternfit.errors.SessionError` naming the file
        at fault when no snapshot loads."""
        folder = Path(folder)
        snapshots = sorted((p.name for p in _snapshots(folder)),
                           key=lambda n: int(_SNAPSHOT.fullmatch(n).group(1)), reverse=True)
        try:
            named = (folder / "current").read_text(encoding="utf-8").strip()
        except (OSError, UnicodeDecodeError):
            named = None
        if named in snapshots:
            snapshots.remove(named)
            snapshots.insert(0, named)
        if not snapshots:
            raise SessionError("not a saved design session (no snapshot)", file=folder)
        errors = []
        for name in snapshots:
            try:
                return cls._load_snapshot(folder, name)
            except SessionError as exc:
                errors.append(exc)
        raise errors[0]

    @classmethod
    def _load_snapshot(cls, folder: Path, name: str) -> "DesignSession":
        v1 = (folder / name).is_dir()
        meta_file = folder / name / "session.json" if v1 else folder / name
        meta = read_json_file(meta_file, error=SessionError)
        bad = _bad_meta(meta, v1)
        if bad:
            raise SessionError(bad, file=meta_file)
        if v1:
            body_file = folder / name / "body.npz" if meta["body"] == "body.npz" else None
        else:
            body_file = folder / meta["body"]
        with _as_session_error(body_file or meta_file):
            body = load_body(meta["body"]) if body_file is None else read_body(body_file)
        with _as_session_error(meta_file):
            fabric = Fabric(**meta["fabric"])
        history = []
        for i, row in enumerate(meta["states"]):
            d = folder / name / f"state-{i:03d}" if v1 else folder / STATES / row["key"]
            with _as_session_error(d / "pattern.json"):
                pattern = load_pattern(d / "pattern.json")
            with _as_session_error(d / "mesh.npz"):
                mesh = GarmentMesh.load(d / "mesh.npz")
            file = ("positions.npy" if row["draped"] else None) if v1 else row["positions"]
            positions = None if file is None else _load_array(d / file, (mesh.n_vertices, 3))
            rest_file = None if v1 else row.get("start_rest")
            start_rest = None if rest_file is None else _load_array(d / rest_file,
                                                                    (mesh.n_vertices, 2))
            contact_file = None if v1 else row.get("contact")
            contact = None if contact_file is None else _saved_contact(d / contact_file,
                                                                       row["label"])
            contact_file = None if contact is None else contact_file
            st = State(row["label"], row["edit"], pattern, mesh, positions,
                       row["fitting_ratio"], row["checks"], start_rest, contact)
            if not v1:  # a version-1 state is copied into the new layout by the next save
                st.key = row["key"]
                st._stored_positions = None if file is None else (positions, file)
                st._stored_start_rest = None if rest_file is None else (start_rest, rest_file)
                st._stored_contact = None if contact_file is None else (contact, contact_file)
            history.append(st)
        with _as_session_error(meta_file):
            session = cls(history[meta["position"]].pattern, body, fabric, meta["triangles"],
                          meta["threshold"], history, meta["position"],
                          relax=meta.get("relax", 1.0))
        if not v1:
            session._stored_body = (body, meta["body"])
        return session


def holds_session(folder) -> bool:
    """Whether ``folder`` holds a saved session (complete or not): :meth:`DesignSession.load`
    either loads it or says why not; starting a new one there would replace its history."""
    folder = Path(folder)
    return ((folder / "current").exists() or (folder / STATES).exists()
            or any(True for _ in _snapshots(folder)))


def _snapshots(folder: Path):
    return (p for p in folder.glob("snapshot-*") if _SNAPSHOT.fullmatch(p.name))


def _store_state(states: Path, s: State) -> dict:
    """Write what of state ``s`` is not yet in ``states``; its row of the snapshot."""
    d = states / s.key
    if not d.is_dir():
        part = states / f".{s.key}-{_new_key()}.part"
        save_garment(part, s.pattern, s.mesh)  # the garment folder's own checks and layout
        os.rename(part, d)
    row = {"key": s.key, "label": s.label, "edit": s.edit, "fitting_ratio": s.fitting_ratio,
           "checks": s.checks, "positions": None}
    if s.positions is not None:
        s._stored_positions = _store_array(d, "positions", s.positions, s._stored_positions)
        row["positions"] = s._stored_positions[1]
        if s.start_rest is not None:
            s._stored_start_rest = _store_array(d, "start-rest", s.start_rest,
                                                s._stored_start_rest)
            row["start_rest"] = s._stored_start_rest[1]
        if s.contact is not None:
            s._stored_contact = _store_once(d, "contact-{}.npz", s.contact, s._stored_contact,
                                            contact_bytes)
            row["contact"] = s._stored_contact[1]
    return row


def _saved_contact(file: Path, label: str) -> dict | None:
    """A state's saved contact state (``contact-<key>.npz``), or None with a
    :class:`SessionWarning` when it is missing or damaged: it only lets a drape go on from
    the state's own rest at once, and one lost file made the whole session unloadable (the
    studio would not start on its folder)."""
    try:
        return read_npz(file, limit=limits.mesh_bytes, error=SessionError)
    except SessionError as exc:
        warnings.warn(SessionWarning(f"{exc}: the drape of '{label}' will go on from its "
                                     "positions, its contact rebuilt"), stacklevel=3)
        return None


def _store_array(d: Path, prefix: str, values: np.ndarray, stored: tuple | None) -> tuple:
    """Write ``values`` into ``d`` as ``<prefix>-<key>.npy`` (:func:`_store_once`)."""
    def npy(values) -> bytes:
        buf = io.BytesIO()
        np.save(buf, np.asarray(values, dtype=np.float64), allow_pickle=False)
        return buf.getvalue()
    return _store_once(d, prefix + "-{}.npy", values, stored, npy)


def _store_once(d: Path, name: str, value, stored: tuple | None, to_bytes) -> tuple:
    """Write ``to_bytes(value)`` into ``d`` as ``name`` with a new key in its ``{}`` unless
    ``stored`` (the (value, file name) written last) is of this very object: a drape
    replaces its arrays and its contact state, never edits them in place. Returns the new
    (value, file name)."""
    if stored is None or stored[0] is not value:
        stored = (value, name.format(_new_key()))
    if not (d / stored[1]).is_file():
        atomic_write_bytes(d / stored[1], to_bytes(value))
    return stored


def _remove_unnamed(folder: Path, keep: str, meta: dict) -> None:
    """Remove the snapshots other than ``keep`` and the files its ``meta`` does not name
    (states dropped from the history, superseded drapes, parts of killed saves)."""
    for p in _snapshots(folder):
        if p.name != keep:
            shutil.rmtree(p) if p.is_dir() else p.unlink(missing_ok=True)
    for p in [*folder.glob("body-*.npz"), *folder.glob(".*.tmp")]:
        if p.name != meta["body"]:
            p.unlink(missing_ok=True)
    named = {row["key"]: {"pattern.json", "mesh.npz", row["positions"], row.get("start_rest"),
                          row.get("contact")}
             for row in meta["states"]}
    for d in (folder / STATES).iterdir():
        if d.name not in named:
            shutil.rmtree(d, ignore_errors=True)
            continue
        for p in d.iterdir():
            if p.name not in named[d.name]:
                p.unlink(missing_ok=True)


def _bad_meta(meta, v1: bool) -> str | None:
    """What is wrong with a snapshot's record, or None."""
    if not isinstance(meta, dict) or meta.get("format") != SNAPSHOT_FORMAT:
        return "not a saved design session"
    if meta.get("version") != (1 if v1 else SNAPSHOT_VERSION):
        return f"unknown session version {meta.get('version')!r}"
    kinds = {"body": str, "fabric": dict, "triangles": int, "threshold": (int, float),
             "relax": (int, float), "position": int, "states": list}
    for key, kind in kinds.items():
        value = meta.get(key, 1.0) if key == "relax" else meta.get(key)
        if isinstance(value, bool) or not isinstance(value, kind):
            return f"field '{key}': missing or of the wrong type"
    known = meta["body"] in [*list_bodies(), "body.npz"] if v1 else _BODY.fullmatch(meta["body"])
    if not known:
        return "field 'body': neither a built-in body nor a body file of this session"
    if not 0 <= meta["position"] < len(meta["states"]):
        return f"field 'position': {meta['position']} is outside the history"
    for i, row in enumerate(meta["states"]):
        if not isinstance(row, dict) or not isinstance(row.get("label"), str) \
                or not isinstance(row.get("edit"), (dict, type(None))) \
                or not isinstance(row.get("checks"), (dict, type(None))) \
                or isinstance(row.get("fitting_ratio"), bool) \
                or not isinstance(row.get("fitting_ratio"), (int, float, type(None))):
            return f"state {i}: label, edit, fitting_ratio or checks missing or wrong"
        if v1:
            if not isinstance(row.get("draped"), bool):
                return f"state {i}: field 'draped' missing or wrong"
        elif not (isinstance(row.get("key"), str) and _KEY.fullmatch(row["key"])) or not (
                row.get("positions") is None
                or isinstance(row["positions"], str) and _POSITIONS.fullmatch(row["positions"])):
            return f"state {i}: field 'key' or 'positions' missing or wrong"
        elif row.get("start_rest") is not None and not (
                row["positions"] is not None and isinstance(row["start_rest"], str)
                and _START_REST.fullmatch(row["start_rest"])):
            return f"state {i}: field 'start_rest' wrong"
        elif row.get("contact") is not None and not (
                row["positions"] is not None and isinstance(row["contact"], str)
                and _CONTACT.fullmatch(row["contact"])):
            return f"state {i}: field 'contact' wrong"
    return None


@contextmanager
def _as_session_error(file: Path):
    """Turns the refusal of a saved file (by its reader, or by the class it makes) into a
    SessionError naming it."""
    try:
        yield
    except InputError as exc:
        raise SessionError(exc.reason, file=exc.file or file, place=exc.place) from None
    except (ValueError, TypeError) as exc:
        raise SessionError(f"cannot be used ({exc})", file=file) from None


def _load_array(path: Path, shape: tuple) -> np.ndarray:
    """A saved state's positions (n, 3) or start rest shapes (n, 2) [m], checked."""
    x = read_npy(path, limit=limits.positions_bytes, error=SessionError)
    if x.dtype.kind != "f" or x.shape != shape or not np.isfinite(x).all():
        what = "positions" if shape[1] == 3 else "flat rest shapes"
        raise SessionError(f"expected finite {shape} {what}, got {x.dtype} {x.shape}",
                           file=path)
    return x.astype(np.float64)


def _finished(result: Drape) -> Drape:
    """``result``, unless Ctrl-C stopped its solve (which then returns its last state): a
    session records no stopped drape and the loop edits from none, so the interrupt goes
    on to the caller."""
    if result.result.interrupted:
        raise KeyboardInterrupt
    return result


def _widened(pattern: Pattern, mesh: GarmentMesh, factor: float):
    """Pattern and mesh (same topology) with every panel widened by ``factor`` along x of
    its flat frame about its outline's centroid (as ``edit.grade`` does)."""
    v = mesh.vertices.copy()
    for i, name in enumerate(mesh.panel_names):
        c = pattern.panel(name).outline.polygon().mean(axis=0)
        ids = mesh.panel_vertices(i)
        v[ids, 0] = c[0] + factor * (v[ids, 0] - c[0])
    return grade(pattern, None, factor, 1.0), mesh.with_vertices(v)


def _sewing(pattern: Pattern | None):
    """What a drape's solver sews of ``pattern``: its seams' sides and directions (an
    edited seam's ease changes no rest length)."""
    return None if pattern is None else [(s.a, s.b, s.reverse) for s in pattern.seams]


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
