"""The studio's server-side state: one design session, its save folder, the drape running in
the background and the live-drag coordinate cache.

Every change goes through :class:`Studio` under one lock, so two browser tabs on the same
session cannot interleave half-done edits; the session's ``revision`` counts changes. Every
state-changing request may name the revision its tab last saw: one that names an older
revision is refused (:class:`StaleRevision`, HTTP 409) and changes nothing, so a tab that
missed another tab's edit is told to reload instead of stacking its change (or its undo) on
an edit it has not seen.
Body and fabric are chosen by preset name or by an uploaded file, never by a path.
"""

from __future__ import annotations

import itertools
import math
import os
import shutil
import tempfile
import threading
import time
import zlib
from collections import OrderedDict
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from .. import api
from .. import edit as tools
from ..body.builtin import list_bodies
from ..body.mesh_io import body_notes
from ..defaults import DEFAULTS
from ..edit import CoordinateCache, update_mesh
from ..errors import InputError, SessionError
from ..files import atomic_write_text, dumps_finite_json, read_json_file
from ..fit.report import failure
from ..loop.session import holds_session
from ..pattern.errors import PatternError
from ..pattern.library import GARMENTS
from ..pattern.sizes import SIZE_NAMES
from ..sim.fabrics import FABRICS
from ..sim.settings import SolverSettings
from .jobs import Background, Refused
from .payload import Views
from .words import describe_edit, designer_message

#: triangle count of a new session's garment mesh unless asked otherwise
#: what an upload may be, with the file endings each kind is read from
UPLOAD_SUFFIXES = {"pattern": (".json", ".dxf"),
                   "body": (".obj", ".ply", ".stl", ".glb", ".off", ".npz"),
                   "fabric": (".json",)}
#: the editing tools the live drag preview accepts (they keep the mesh topology)
DRAG_OPS = ("move_point", "move_edge", "edit_curve", "move_dart")
#: the drape engines a studio session can take: the design session drapes with the static
#: (quasi-static) solver only; ``api.list_engines()`` lists the others and whether installed
ENGINES = ("static",)
#: the phases of a drape, as ``patternfit.sim.schedule`` names them (each one solver run):
#: a drape from the placement sews (no gravity, until the seams weld), relaxes the sewn
#: garment (no gravity) and drapes under gravity; a mesh larger than three times the coarse
#: size does those three on a coarse mesh and then settles the fine one from it; a re-drape
#: of a draped mesh (the same topology) only settles, in stages.
PHASE_WORDS = {"sewing": "closing the seams", "relaxing": "relaxing the sewn garment",
               "draping": "draping under gravity", "settling": "settling"}
#: iterations a phase is expected to take, to spread the bar within it (a phase's end is
#: seen when the solver starts its next run: the bar then jumps to that phase's start)
_PHASE_ITERATIONS = {"sewing": 150, "relaxing": 300, "draping": 600, "settling": 300}
#: states whose drag coordinates are kept (the current one and the last few undone)
COORDINATE_STATES = 4
#: the longest the background saver waits for the page's payloads of a change to be made
#: before it writes the change [s] (both want the CPU the page is waiting on)
SAVE_DEFER = 2.0
#: ``patternfit.sim.drape.drape``'s default coarse size [triangles]
_COARSE = 2000
#: why a change, or another drape, is refused while a drape runs
_DRAPING = "a drape is running: stop it first, or wait for it to finish"


class StaleRevision(Exception):
    """A change sent by a tab that had not seen the session's latest revision (HTTP 409)."""

    def __init__(self, seen: int, current: int):
        self.seen, self.current = seen, current
        super().__init__(
            f"not applied: the session was changed in another tab (it is at version "
            f"{current}, this tab shows version {seen}); reload this tab to see the current "
            "session, then make your change again")


class DrapeStopped(Exception):
    """Raised in the solver's progress callback when Stop was pressed. Not a
    KeyboardInterrupt, which the solver catches and turns into a result: this one leaves the
    drape before the session records anything of it."""


def drape_plan(session) -> list[tuple[str, float]]:
    """The phases the next ``session.redrape()`` runs, with their expected cost (iterations
    times triangles), following ``DesignSession.redrape`` and ``patternfit.sim.drape``."""
    n = session.state.mesh.n_triangles
    how = session.next_start()
    if how in ("warm", "carried", "continued"):
        return [("settling", _PHASE_ITERATIONS["settling"] * n)]
    size = _COARSE if n > 3 * _COARSE else n
    plan = [(name, _PHASE_ITERATIONS[name] * size) for name in ("sewing", "relaxing", "draping")]
    if size != n or how == "relaxed":
        plan.append(("settling", _PHASE_ITERATIONS["settling"] * n))
    return plan


class DrapeTracker:
    """Turns the solver's progress callbacks of one drape into phases, a monotone fraction
    and an iteration count that never goes back (the solver counts each run from 1).

    ``begin(session)`` before each drape; ``enter(name)`` as the drape's runner starts a
    phase; ``update(iteration)`` for each callback."""

    def __init__(self):
        self.plan: list[tuple[str, float]] = []
        self.index = 0           # the phase running
        self.last = 0            # the solver's iteration count in the current run
        self.done = 0            # iterations of the finished runs
        self.fraction = 0.0      # of this drape, monotone, < 1 until it finished
        self.previous = None     # the session's last drape before this one, and its rest
        self.rest = None

    def begin(self, session) -> None:
        self.plan = drape_plan(session)
        self.index, self.last, self.done, self.fraction = 0, 0, 0, 0.0
        self.previous = getattr(session, "_drape", None)
        self.rest = None if self.previous is None else self.previous.solver.model.rest.copy()

    @property
    def phase(self) -> str | None:
        return self.plan[self.index][0] if self.plan else None

    def enter(self, name: str) -> None:
        """The drape's runner starts phase ``name`` (a re-drape's stages belong to its
        settling): the bar moves to that phase of the plan; back to it when it ran before
        (a tangled sewing is sewn again from farther out, ``drape``'s ``RESEW_CLEARANCES``:
        the bar waits, the fraction never goes back). A drape phase the plan did not foresee
        (a carried start refused for its faults is draped cold: sewing, relaxing, draping)
        is put into the plan where it runs, weighed like the plan's own; any other name
        moves the bar on by one."""
        key = "settling" if name.startswith("stage ") else name
        names = [n for n, _ in self.plan]
        started = self.done + self.last > 0
        self.done += self.last
        self.last = 0
        if key in names[self.index:]:
            self.index = names.index(key, self.index)
        elif key in names:
            self.index = names.index(key)
        elif key in _PHASE_ITERATIONS and names:
            per = sum(w for _, w in self.plan) / sum(_PHASE_ITERATIONS[n] for n in names)
            self.index += started
            self.plan.insert(self.index, (key, per * _PHASE_ITERATIONS[key]))
        elif started and names:
            self.index = min(self.index + 1, len(names) - 1)

    def update(self, it: int) -> None:
        if it <= self.last:  # the solver started its next run: the next phase
            self.done += self.last
            self.index = min(self.index + 1, len(self.plan) - 1)
        self.last = it
        if not self.plan:
            return
        total = sum(w for _, w in self.plan)
        before = sum(w for _, w in self.plan[:self.index])
        name, weight = self.plan[self.index]
        within = 1.0 - math.exp(-it / _PHASE_ITERATIONS[name])
        self.fraction = max(self.fraction, min(0.99, (before + weight * within) / total))

    @property
    def iterations(self) -> int:
        return self.done + self.last

    def abandon(self, session) -> None:
        """After a stopped drape: the session keeps its last drape; a staged re-drape had
        already given that drape's solver the new rest shapes, which are put back."""
        prev = self.previous
        if prev is not None and getattr(session, "_drape", None) is prev \
                and not np.array_equal(prev.solver.model.rest, self.rest):
            prev.solver.set_rest(self.rest)


@dataclass
class DrapeJob:
    """The drape running in the background thread, as the progress endpoint reports it."""

    running: bool = False
    stop: bool = False
    iteration: int = 0
    energy: float = float("nan")
    step: float = float("nan")
    #: rms of |F_i| / (m_i g) [-] at the last iteration: how far from rest (at rest <= 0.01)
    residual: float = float("nan")
    elapsed: float = 0.0
    fraction: float = 0.0
    error: str | None = None
    finished: float | None = None
    kind: str = "drape"
    rounds: list = field(default_factory=list)
    result: dict | None = None
    #: the drape was stopped: nothing of the stopped drape was recorded
    stopped: bool = False
    #: drapes a correction makes at most (1 for a drape), to spread the bar over them
    drapes: int = 1
    tracker: DrapeTracker = field(default_factory=DrapeTracker, repr=False)

    def as_dict(self) -> dict:
        t = self.tracker
        return {"running": self.running, "iteration": self.iteration,
                "energy": _finite(self.energy), "step": _finite(self.step),
                "residual": _finite(self.residual),
                "residual_rest": RESIDUAL_REST,
                "elapsed": self.elapsed, "fraction": self.fraction, "error": self.error,
                "stopping": self.stop and self.running, "stopped": self.stopped,
                "kind": self.kind, "rounds": self.rounds, "result": self.result,
                "phases": [name for name, _ in t.plan], "phase": t.phase,
                "phase_index": t.index, "phase_iteration": t.last}


#: the residual rms at which the studio's drapes count as at rest (they run on the defaults)
RESIDUAL_REST = SolverSettings().residual_rms


def _finite(x):
    return float(x) if x is not None and math.isfinite(x) else None


class Studio:
    """One design session kept in ``folder`` (created, or continued when it holds one).

    A folder whose saved session does not load (every snapshot damaged) is refused with a
    :class:`~patternfit.errors.SessionError` rather than started afresh: a new session would
    replace its history.

    Parameters
    ----------
    folder : path
        The session folder; everything the studio writes goes inside it.
    """

    def __init__(self, folder):
        self.folder = Path(folder).resolve()
        self.folder.mkdir(parents=True, exist_ok=True)
        self.lock = threading.RLock()
        self.revision = 0
        self._drapes = Background(DrapeJob(), "patternfit-drape")
        #: the coordinates of recent states' meshes (state key -> CoordinateCache), newest
        #: last: drags, the edit a drag ends in, and undo back to a state reuse them
        self._coords: OrderedDict[str, CoordinateCache] = OrderedDict()
        self._warming: threading.Thread | None = None
        #: what the page draws of recent states (made once each, see _warm); ``_drawn`` is
        #: set once the current state's are made
        self.views = Views()
        self._drawn = threading.Event()
        self._drawn.set()
        # the background saver of edits (see _save)
        self._save_lock = threading.Lock()
        self._save_pending = False
        self._saver: threading.Thread | None = None
        #: why the last background save failed (None: saved)
        self.save_error: str | None = None
        self.info: dict = {}
        self.session: api.DesignSession | None = None
        #: keys of the states whose last drape was stopped (their ϖ stays unknown)
        self.stopped: set[str] = set()
        #: what ``GET /api/state`` answers, rebuilt after every change so that reading it
        #: never waits for the lock a long change holds
        self.summary: dict | None = None
        if holds_session(self.folder / "session"):
            self.session = api.DesignSession.load(self.folder / "session")
            self.info = self._read_info()
            self._publish()
            self._warm()

    # -- session life --------------------------------------------------------------------
    def _read_info(self) -> dict:
        p = self.folder / "studio.json"
        if not p.exists():
            return {}
        info = read_json_file(p, error=SessionError)
        if not isinstance(info, dict):
            raise SessionError("expected a JSON object", file=p)
        return info

    def _save(self, *, later: bool = False) -> None:
        """Count the change and write the session (only its new states). ``later``: the
        writing is left to the background saver, so that an edit's answer does not wait for
        the disk (a 22K mesh takes ~0.4 s to compress); :meth:`flush` waits for it."""
        self.revision += 1
        self._publish()
        self._warm()
        if later:
            with self._save_lock:
                self._save_pending = True
                if self._saver is None:
                    self._saver = threading.Thread(target=self._save_loop, daemon=True,
                                                   name="patternfit-save")
                    self._saver.start()
        else:
            self._write()

    def _write(self) -> None:
        with self.lock:
            self.session.save(self.folder / "session")
            atomic_write_text(self.folder / "studio.json", dumps_finite_json(self.info))

    def _save_loop(self) -> None:
        while True:
            self._drawn.wait(SAVE_DEFER)  # the page's payloads first
            with self._save_lock:
                if not self._save_pending:
                    self._saver = None
                    return
                self._save_pending = False
            try:
                self._write()
                self.save_error = None
            except Exception as exc:  # shown in the page (the session stays in memory)
                self.save_error = f"the session could not be saved: {designer_message(exc)}"
            self._publish()

    def flush(self) -> None:
        """Wait until every change is written to the session folder."""
        while True:
            with self._save_lock:
                saver = self._saver
            if saver is None:
                return
            saver.join()

    # -- the coordinates of drags ----------------------------------------------------------
    def coordinates(self, state) -> CoordinateCache:
        """The coordinate cache of ``state``'s mesh (made on first use, with the panels that
        recent states' meshes have alike; the others are computed when first dragged, or
        beforehand by :meth:`_warm`)."""
        with self.lock:
            cache = self._coords.pop(state.key, None)
            if cache is None or cache.mesh is not state.mesh:
                cache = CoordinateCache(state.mesh)
                # the panels an edit left alone keep the coordinates of the state before
                for other in reversed(self._coords.values()):
                    cache.adopt(other)
            self._coords[state.key] = cache
            while len(self._coords) > COORDINATE_STATES:
                self._coords.popitem(last=False)
            return cache

    def _warm(self) -> None:
        """Make what the page asks for next in the background: the current state's 2D and
        3D payloads (the page fetches them right after a change), then its coordinates (on a
        22K coat about 1-2 s a panel), so that the first drag after an edit, an undo or a
        new session does not wait for them; it gives way as soon as a drape starts."""
        state = self.session.state
        cache = self.coordinates(state)
        job = self.job
        self._drawn.clear()

        def run():
            try:
                # the garment only after a drape: an edit keeps the drape shown
                for kind in ("geometry", "garment3d")[:1 + (state.fitting_ratio is not None)]:
                    self.views.get(kind, state).binary()
            except Exception:  # pragma: no cover - the page's own request reports it
                pass
            finally:
                self._drawn.set()
            for panel in range(len(cache.mesh.panel_names)):
                if self.job is not job or job.running:
                    return
                cache.get(panel)

        self._warming = threading.Thread(target=run, daemon=True, name="patternfit-coords")
        self._warming.start()

    def _publish(self) -> None:
        s = self.session
        info = self.info
        self.summary = {
            "revision": self.revision, "info": dict(info), "fabric": s.fabric.name,
            "triangles": s.triangles, "threshold": s.threshold, "position": s.position,
            # what the page's session fields show (a reload restores them from here)
            "fields": {"garment": info.get("garment", s.pattern.name),
                       "size": info.get("size", DEFAULTS.size),
                       "body": info.get("body", s.body.name),
                       "fabric": info.get("fabric", s.fabric.name),
                       # sessions saved before the engine had a name said "default"
                       "engine": {"default": "static"}.get(info.get("engine"),
                                                          info.get("engine", ENGINES[0])),
                       "triangles": s.triangles},
            "history": [{**{k: r[k] for k in ("index", "label", "fitting_ratio", "current")},
                         "failed": failure(s.history[r["index"]].checks),
                         "stopped": self._was_stopped(s.history[r["index"]])}
                        for r in s.summary()],
            "fitting_ratio": s.state.fitting_ratio, "draped": s.positions is not None,
            # the 3D state shown is the drape before an edit (ϖ unknown): maps "not re-draped"
            "maps_stale": s.positions is not None and s.state.fitting_ratio is None,
            # which drape the 3D state is (the page fetches the garment when it changes)
            "drape_id": None if s.positions is None else _drape_id(s.positions),
            "checks": s.state.checks, "failed": failure(s.state.checks),
            "stopped": self._was_stopped(s.state),
            "can_undo": s.position > 0, "save_error": self.save_error,
            "can_redo": s.position + 1 < len(s.history)}

    def _was_stopped(self, state) -> bool:
        return state.fitting_ratio is None and state.key in self.stopped

    def check_revision(self, revision: int | None) -> None:
        """Refuse a change from a tab that saw ``revision`` when the session is past it
        (:class:`StaleRevision`); None: a client that does not say (not the page)."""
        if revision is not None and revision != self.revision:
            raise StaleRevision(revision, self.revision)

    def current(self):
        """The session's current history state, read without waiting for the lock (a state's
        pattern and mesh are never replaced; its positions only by a whole new array)."""
        s = self.session
        return (s if s is not None else self.ensure()).state

    def ensure(self) -> api.DesignSession:
        """The session, starting the default one (built-in skirt) when there is none."""
        with self.lock:
            if self.session is None:
                self.new()
            return self.session

    def new(self, *, garment: str = DEFAULTS.garment, size: str = DEFAULTS.size,
            body: str = DEFAULTS.body, fabric: str = DEFAULTS.fabric,
            triangles: int = DEFAULTS.studio_triangles, engine: str = ENGINES[0],
            revision: int | None = None) -> str | None:
        """Start a new session on a built-in garment, body and fabric, each named as in
        ``/api/options`` (replaces the current session, which is kept: see :meth:`_archive`,
        whose answer this returns). ``revision``: the one the asking tab saw (see
        :meth:`check_revision`)."""
        for what, value, known in (("garment", garment, GARMENTS), ("size", size, SIZE_NAMES),
                                   ("body", body, list_bodies()), ("fabric", fabric, FABRICS),
                                   ("engine", engine, ENGINES)):
            if not isinstance(value, str) or value not in known:
                raise ValueError(f"{what}: expected one of {', '.join(known)}")
        if isinstance(triangles, bool) or not isinstance(triangles, int) \
                or not 100 <= triangles <= 60000:
            raise ValueError("triangles: expected a whole number in 100..60000")
        self._refuse_while_draping()
        self.check_revision(revision)
        session = api.design_session(garment, body, fabric, size=size, triangles=triangles)
        with self.lock:
            self._refuse_while_draping()
            self.check_revision(revision)
            archived = self._archive()
            self.session = session
            self.info = {"garment": garment, "size": size, "body": body, "fabric": fabric,
                         "engine": engine, "source": f"built-in {garment} {size}"}
            self._save()
            return archived

    def upload(self, kind: str, filename: str, data: bytes, revision: int | None = None
               ) -> dict:
        """Start a new session on an uploaded pattern, body or fabric (``kind``), keeping the
        rest of the current one. The file is read from the session folder under a name of
        the studio's choosing (``uploads/<kind><ending>``, replaced only once the new session
        is); only the ending of the client's ``filename`` is used, to pick the reader, and
        its last part names it in messages. The answer's ``archived``: where the replaced
        session was kept (:meth:`start_from`)."""
        shown = filename.replace("\\", "/").rsplit("/", 1)[-1][:100] or kind
        suffix = Path(shown).suffix.lower()
        self.check_revision(revision)
        if kind not in UPLOAD_SUFFIXES:
            raise ValueError(f"kind: expected one of {', '.join(UPLOAD_SUFFIXES)}")
        if suffix not in UPLOAD_SUFFIXES[kind]:
            raise ValueError(f"upload: expected a {' or '.join(UPLOAD_SUFFIXES[kind])} file")
        self._refuse_while_draping()  # before the file is read: start_from would refuse it
        uploads = self.folder / "uploads"
        uploads.mkdir(exist_ok=True)
        # each upload is read in a folder of its own: two at once never share a file
        part = Path(tempfile.mkdtemp(prefix=".incoming-", dir=uploads))
        target = part / f"{kind}{suffix}"
        try:
            try:
                target.write_bytes(data)
                read, assumed = _read_upload(kind, target, Path(shown).stem)
            except Exception as exc:
                # the readers (trimesh, NumPy's zip) raise many kinds for a bad file, and
                # every one means the upload cannot be used; the message names the client's
                # file, not the server's folder
                raise InputError(designer_message(exc).replace(str(target), shown)) from None
            if kind == "pattern":
                try:
                    archived = self.start_from(pattern=read, upload=target,
                                               labels={"garment": read.name,
                                                       "source": f"uploaded {shown}"},
                                               revision=revision)
                except PatternError as exc:  # meshing it: a gather beyond 2:1
                    if exc.file is not None:
                        raise
                    raise exc.located(shown) from None
                return {"panels": len(read.panels), "archived": archived,
                        **({"assumed": assumed} if assumed else {})}
            archived = self.start_from(**{kind: read}, upload=target, labels={kind: read.name},
                                       revision=revision)
            return {"name": read.name, "archived": archived,
                    **({"assumed": assumed} if assumed else {})}
        finally:
            shutil.rmtree(part, ignore_errors=True)

    def start_from(self, *, labels: dict, pattern=None, body=None, fabric=None,
                   upload: Path | None = None, revision: int | None = None) -> str | None:
        """Start a new session on ``pattern``, ``body`` or ``fabric`` (uploaded), keeping the
        rest of the current session (its pattern, body, fabric, mesh size, threshold);
        ``labels`` update what the page shows of the session (``info``). ``upload``: the
        file it was read from, kept as ``uploads/<its name>`` once the session is replaced.
        The replaced session is kept (:meth:`_archive`, whose answer this returns)."""
        self._refuse_while_draping()
        with self.lock:
            old = self.ensure()
        session = api.design_session(old.pattern if pattern is None else pattern,
                                     old.body if body is None else body,
                                     old.fabric if fabric is None else fabric,
                                     triangles=old.triangles, threshold=old.threshold)
        with self.lock:
            self._refuse_while_draping()
            self.check_revision(revision)
            archived = self._archive()
            if upload is not None:
                os.replace(upload, self.folder / "uploads" / upload.name)
            self.session = session
            self.info = {**self.info, **labels}
            self._save()
            return archived

    def _refuse_while_draping(self) -> None:
        if self.job.running:
            raise Refused(_DRAPING)

    def _archive(self) -> str | None:
        """Move the saved session about to be replaced (``session/`` and ``studio.json``)
        into ``archive/<date>_<time>/``, a session folder of its own (``patternfit studio
        --session`` continues it), and return that folder relative to the studio's; None
        when there is no session yet. Called under the lock, once the replacing request
        passed its checks: saving the new session into ``session/`` would delete every state
        of the old history (``DesignSession.save`` removes the states it does not name)."""
        if self.session is None:
            return None
        self._write()  # the last edits, which the background saver may not have written yet
        stamp = time.strftime("%Y-%m-%d_%H-%M-%S")
        archive = self.folder / "archive"
        archive.mkdir(exist_ok=True)
        for n in itertools.count(1):  # two replacements within a second
            kept = archive / (stamp if n == 1 else f"{stamp}-{n}")
            try:
                kept.mkdir()
                break
            except FileExistsError:
                continue
        os.replace(self.folder / "session", kept / "session")
        os.replace(self.folder / "studio.json", kept / "studio.json")
        return kept.relative_to(self.folder).as_posix()

    # -- edits ---------------------------------------------------------------------------
    def apply(self, op: str, args: dict, revision: int | None = None) -> dict:
        """Apply an editing tool (lengths [m]); returns the mesh update's report in words."""
        with self.lock:
            self._refuse_while_draping()
            self.check_revision(revision)
            s = self.ensure()
            report = s.apply(op, label=describe_edit(op, args),
                             cache=self._coords.get(s.state.key), **args)
            self._save(later=True)
            return {"remeshed": report is None or bool(report.remeshed),
                    "min_angle": None if report is None else _finite(report.min_angle)}

    def undo(self, revision: int | None = None) -> None:
        with self.lock:
            self._refuse_while_draping()
            self.check_revision(revision)
            self.ensure().undo()
            self._save(later=True)

    def redo(self, revision: int | None = None) -> None:
        with self.lock:
            self._refuse_while_draping()
            self.check_revision(revision)
            self.ensure().redo()
            self._save(later=True)

    def drag(self, op: str, args: dict) -> tuple[np.ndarray, list[str]]:
        """Live preview of a drag: the mesh's flat vertices (n, 2) [m] for the edited pattern,
        through the cached coordinates of the current mesh (nothing is recorded)."""
        if op not in DRAG_OPS:
            raise ValueError(f"op: the drag preview takes {', '.join(DRAG_OPS)}")
        with self.lock:
            s = self.ensure()
            st = s.state
            cache = self.coordinates(st)
        new = getattr(tools, op)(st.pattern, **args)
        # a preview never re-meshes (the page maps the vertices onto the mesh it has): a
        # panel that would need it (a dart dragged far) shows its stretched mesh, same
        # vertex count; the drop re-meshes it
        mesh, report = update_mesh(st.pattern, new, st.mesh, cache=cache, min_angle=0.0,
                                   remesh=False, return_report=True)
        if mesh.n_vertices != st.mesh.n_vertices:  # pragma: no cover - update_mesh's promise
            raise RuntimeError("the drag preview changed the mesh's vertex count")
        return mesh.vertices, list(report.moved)

    def drag_basis(self, op: str, args: dict, *, step: float = 0.005) -> np.ndarray:
        """How the mesh's flat vertices move per metre of drag offset, (2, n, 2): the change
        for an offset ``(step, 0)`` and ``(0, step)`` [m], divided by ``step``. The page moves
        the mesh by ``basis[0] * dx + basis[1] * dy`` between two exact previews (exact for
        straight edges, where the update is linear in the offset)."""
        base = self.ensure().mesh.vertices
        out = [(self.drag(op, {**args, "offset": d})[0] - base) / step
               for d in ((step, 0.0), (0.0, step))]
        return np.stack(out)

    # -- drape ---------------------------------------------------------------------------
    def start_drape(self, *, kind: str = "drape", revision: int | None = None) -> None:
        """Drape the current state (``kind="drape"``) or run the automatic fit correction
        (``"correct"``: drape, edit, re-drape rounds) in a background thread (progress in
        :attr:`job`)."""
        if kind not in ("drape", "correct"):
            raise ValueError(f"kind: 'drape' or 'correct', got {kind!r}")
        with self.lock:
            self._refuse_while_draping()
            self.check_revision(revision)
            self.ensure()
            self._drapes.start(DrapeJob(kind=kind), self._run_drape, busy=_DRAPING)

    @property
    def job(self) -> DrapeJob:
        """The drape (or correction) running, or the last one run."""
        return self._drapes.job

    def stop_drape(self) -> None:
        self._drapes.stop()

    def wait(self, timeout: float | None = None) -> None:
        """Wait for the background drape (tests, shutdown)."""
        self._drapes.wait(timeout)

    def _run_drape(self, job: DrapeJob) -> None:
        t0 = time.perf_counter()
        tracker = job.tracker

        def progress(it, energy, step, elapsed, residual=float("nan")):
            if job.stop:
                raise DrapeStopped
            tracker.update(int(it))
            job.iteration = tracker.iterations  # counted over the runs: never goes back
            job.energy, job.step, job.residual = float(energy), float(step), float(residual)
            job.elapsed = time.perf_counter() - t0
            share = (len(job.rounds) + tracker.fraction) / job.drapes
            job.fraction = max(job.fraction, min(0.99, share))

        progress.phase = tracker.enter  # the runner names each phase as it starts
        session = state = None
        try:
            with self.lock:
                session = self.session
                state = session.state
            tracker.begin(session)
            if job.kind == "correct":
                self._run_correction(job, session, progress)
            else:
                session.redrape(progress=progress)
                with self.lock:
                    if self.session is session and session.state is state:
                        self.stopped.discard(state.key)
                        self._save()
        except DrapeStopped:
            # nothing of the stopped drape is recorded: the state keeps its ϖ (unknown when
            # it had none) and is marked stopped; the session keeps its last drape
            job.stopped = True
            with self.lock:
                if self.session is session:
                    tracker.abandon(session)
                    self.stopped.add(session.state.key)
                    self._publish()
        except Exception as exc:  # shown in the page; the server keeps serving
            job.error = designer_message(exc)
        finally:
            if job.error is None and not job.stopped:
                job.fraction = 1.0
            job.finished = time.time()

    def _run_correction(self, job: DrapeJob, session, progress) -> None:
        """The automatic correction; each round's ϖ and edits go to ``job.rounds`` and the
        session is saved after each round, so the page can follow and a reload keeps it.
        Stopped, it reports no outcome (``result.stopped``), never "reached"."""
        settings = api.CorrectionSettings(threshold=session.threshold)
        job.drapes = settings.max_iterations + 2  # its rounds, then the fresh drape

        def round_done(it):
            job.rounds.append({"iteration": it.index, "fitting_ratio": it.fitting_ratio,
                               "edits": len(it.edits), "seconds": it.seconds,
                               "failed": failure(it.checks)})
            job.fraction = max(job.fraction, min(0.99, len(job.rounds) / job.drapes))
            with self.lock:
                if self.session is session:
                    self._save()
            if job.stop:
                raise DrapeStopped
            job.tracker.begin(session)  # the next round's drape

        try:
            result = api.correct(session, settings=settings, progress=round_done,
                                 drape_progress=progress)
            fresh = None
            if result.edited:
                # as the CLI: the loop's drapes go on from its first, a garment made from
                # the pattern is put on afresh, and may sit elsewhere or fail
                job.tracker.begin(session)
                fresh = api.fresh_drape(result.pattern, session,
                                        verdict_rules=settings.rules, progress=progress)
        except DrapeStopped:
            job.result = {"reached": False, "stopped": True, "fitting_ratio": None,
                          "failed": None, "fresh_drape": None}
            raise
        job.result = {"reached": result.reached and (fresh or {}).get("passed") is not False,
                      "fitting_ratio": result.fitting_ratio, "failed": result.failed,
                      "verdict": result.verdict,
                      "fresh_drape": fresh, "stopped": False}
        with self.lock:
            if self.session is session:
                self._save()


def _drape_id(positions: np.ndarray) -> str:
    """A fingerprint of a drape's positions (n, 3): a sample of rows and the size."""
    sample = np.ascontiguousarray(positions[::max(1, len(positions) // 257)])
    return f"{len(positions)}-{zlib.crc32(sample.tobytes()):08x}"


def _read_upload(kind: str, path: Path, stem: str) -> tuple[object, list[str]]:
    """The pattern, body or fabric in the uploaded file ``path``, named after ``stem`` (the
    client's file name) where the file gives no name of its own, and what was assumed for
    values the file does not carry (an ARCSim fabric's friction and thickness) or guessed
    or noticed in reading it (a body's unit, its turn to face +Z; a pattern reader's
    warnings, ``meta["warnings"]``)."""
    if kind == "pattern":
        # what the reader noticed (a seam of unequal sides sewn in as ease, a CAD quirk),
        # as the CLI prints it: the page said only "Opened"
        pattern = api.read_pattern(path)
        return pattern, list(pattern.meta.get("warnings") or [])
    if kind == "fabric":
        fabric, assumed = api.read_fabric_with_notes(path)
        return (replace(fabric, name=stem) if fabric.name == path.stem else fabric), assumed
    body = api.read_body(path)
    body.name = stem
    body.meta = {**body.meta, "source": f"uploaded {stem}{path.suffix}"}
    # what the CLI says of a body file (a unit guessed, a turn to face +Z) the page says too
    return body, [sentence for _, sentence in body_notes(body)]
