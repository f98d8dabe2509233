"""The studio's server-side state: one design session, its save folder, the drape running in
the background and the live-drag coordinate cache.

Every change goes through :class:`Studio` under one lock, so two browser tabs on the same
session cannot interleave half-done edits; the session's ``revision`` counts changes and
lets a tab notice that another one wrote in between (last write wins, with a warning).
Body and fabric are chosen by preset name or by an uploaded file, never by a path.
"""

from __future__ import annotations

import math
import os
import shutil
import tempfile
import threading
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from .. import api
from .. import edit as tools
from ..body.builtin import list_bodies
from ..defaults import DEFAULTS
from ..edit import CoordinateCache, update_mesh
from ..errors import InputError, SessionError
from ..files import atomic_write_text, dumps_finite_json, read_json_file
from ..fit.colormap import FitScale
from ..loop.session import holds_session
from ..pattern.library import GARMENTS
from ..pattern.sizes import SIZE_NAMES
from ..sim.fabrics import FABRICS

#: triangle count of a new session's garment mesh unless asked otherwise
#: what an upload may be, with the file endings each kind is read from
UPLOAD_SUFFIXES = {"pattern": (".json", ".dxf"),
                   "body": (".obj", ".ply", ".stl", ".glb", ".off", ".npz"),
                   "fabric": (".json",)}
#: the editing tools the live drag preview accepts (they keep the mesh topology)
DRAG_OPS = ("move_point", "move_edge", "edit_curve", "move_dart")
#: relative stretch at which the warp/weft colours saturate [-]
STRETCH_SCALE = FitScale(limit=0.10, band=0.01)


@dataclass
class DrapeJob:
    """The drape running in the background thread, as the progress endpoint reports it."""

    running: bool = False
    stop: bool = False
    iteration: int = 0
    energy: float = float("nan")
    step: float = float("nan")
    elapsed: float = 0.0
    fraction: float = 0.0
    error: str | None = None
    finished: float | None = None
    kind: str = "drape"
    rounds: list = field(default_factory=list)
    result: dict | None = None
    _step0: float | None = field(default=None, repr=False)

    def as_dict(self) -> dict:
        return {"running": self.running, "iteration": self.iteration,
                "energy": _finite(self.energy), "step": _finite(self.step),
                "elapsed": self.elapsed, "fraction": self.fraction, "error": self.error,
                "stopping": self.stop and self.running, "kind": self.kind,
                "rounds": self.rounds, "result": self.result}


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
        self.job = DrapeJob()
        self._thread: threading.Thread | None = None
        self._drag: tuple | None = None  # (state object, CoordinateCache)
        self.info: dict = {}
        self.session: api.DesignSession | None = None
        #: what ``GET /api/state`` answers, rebuilt after every change so that reading it
        #: never waits for the lock a long change holds
        self.summary: dict | None = None
        if holds_session(self.folder / "session"):
            self.session = api.DesignSession.load(self.folder / "session")
            self.info = self._read_info()
            self._publish()

    # -- session life --------------------------------------------------------------------
    def _read_info(self) -> dict:
        p = self.folder / "studio.json"
        if not p.exists():
            return {}
        info = read_json_file(p, error=SessionError)
        if not isinstance(info, dict):
            raise SessionError("expected a JSON object", file=p)
        return info

    def _save(self) -> None:
        """Write the session (only its new states) and count the change."""
        self.session.save(self.folder / "session")
        atomic_write_text(self.folder / "studio.json", dumps_finite_json(self.info))
        self.revision += 1
        self._publish()

    def _publish(self) -> None:
        s = self.session
        self.summary = {
            "revision": self.revision, "info": dict(self.info), "fabric": s.fabric.name,
            "triangles": s.triangles, "threshold": s.threshold, "position": s.position,
            "history": [{**{k: r[k] for k in ("index", "label", "fitting_ratio", "current")},
                         "failed": _failed(s.history[r["index"]].checks)}
                        for r in s.summary()],
            "fitting_ratio": s.state.fitting_ratio, "draped": s.positions is not None,
            "checks": s.state.checks, "failed": _failed(s.state.checks),
            "can_undo": s.position > 0,
            "can_redo": s.position + 1 < len(s.history)}

    def ensure(self) -> api.DesignSession:
        """The session, starting the default one (built-in skirt) when there is none."""
        with self.lock:
            if self.session is None:
                self.new()
            return self.session

    def new(self, *, garment: str = DEFAULTS.garment, size: str = DEFAULTS.size,
            body: str = DEFAULTS.body, fabric: str = DEFAULTS.fabric,
            triangles: int = DEFAULTS.studio_triangles) -> None:
        """Start a new session on a built-in garment, body and fabric, each named as in
        ``/api/options`` (replaces the current session)."""
        for what, value, known in (("garment", garment, GARMENTS), ("size", size, SIZE_NAMES),
                                   ("body", body, list_bodies()), ("fabric", fabric, FABRICS)):
            if not isinstance(value, str) or value not in known:
                raise ValueError(f"{what}: expected one of {', '.join(known)}")
        if isinstance(triangles, bool) or not isinstance(triangles, int) \
                or not 100 <= triangles <= 60000:
            raise ValueError("triangles: expected a whole number in 100..60000")
        self._refuse_while_draping()
        session = api.design_session(garment, body, fabric, size=size, triangles=triangles)
        with self.lock:
            self._refuse_while_draping()
            self.session = session
            self.info = {"garment": garment, "size": size, "body": body, "fabric": fabric,
                         "source": f"built-in {garment} {size}"}
            self._save()

    def upload(self, kind: str, filename: str, data: bytes) -> dict:
        """Start a new session on an uploaded pattern, body or fabric (``kind``), keeping the
        rest of the current one. The file is read from the session folder under a name of
        the studio's choosing (``uploads/<kind><ending>``); only the ending of the client's
        ``filename`` is used, to pick the reader, and its last part names it in messages."""
        shown = filename.replace("\\", "/").rsplit("/", 1)[-1][:100] or kind
        suffix = Path(shown).suffix.lower()
        if kind not in UPLOAD_SUFFIXES:
            raise ValueError(f"kind: expected one of {', '.join(UPLOAD_SUFFIXES)}")
        if suffix not in UPLOAD_SUFFIXES[kind]:
            raise ValueError(f"upload: expected a {' or '.join(UPLOAD_SUFFIXES[kind])} file")
        uploads = self.folder / "uploads"
        uploads.mkdir(exist_ok=True)
        # each upload is read in a folder of its own: two at once never share a file
        part = Path(tempfile.mkdtemp(prefix=".incoming-", dir=uploads))
        target = part / f"{kind}{suffix}"
        try:
            target.write_bytes(data)
            read = _read_upload(kind, target, Path(shown).stem)
            os.replace(target, uploads / target.name)
        except Exception as exc:
            # the readers (trimesh, NumPy's zip) raise many kinds for a bad file, and every
            # one means the upload cannot be used; the message names the client's file, not
            # the server's folder
            raise InputError(describe_error(exc).replace(str(target), shown)) from None
        finally:
            shutil.rmtree(part, ignore_errors=True)
        if kind == "pattern":
            self.start_from(pattern=read, labels={"garment": read.name,
                                                  "source": f"uploaded {shown}"})
            return {"panels": len(read.panels)}
        self.start_from(**{kind: read}, labels={kind: read.name})
        return {"name": read.name}

    def start_from(self, *, labels: dict, pattern=None, body=None, fabric=None) -> None:
        """Start a new session on ``pattern``, ``body`` or ``fabric`` (uploaded), keeping the
        rest of the current session (its pattern, body, fabric, mesh size, threshold);
        ``labels`` update what the page shows of the session (``info``)."""
        self._refuse_while_draping()
        with self.lock:
            old = self.ensure()
        session = api.design_session(old.pattern if pattern is None else pattern,
                                     old.body if body is None else body,
                                     old.fabric if fabric is None else fabric,
                                     triangles=old.triangles, threshold=old.threshold)
        with self.lock:
            self._refuse_while_draping()
            self.session = session
            self.info = {**self.info, **labels}
            self._save()

    def _refuse_while_draping(self) -> None:
        if self.job.running:
            raise RuntimeError("a drape is running: stop it first")

    # -- edits ---------------------------------------------------------------------------
    def apply(self, op: str, args: dict) -> dict:
        """Apply an editing tool (lengths [m]); returns the mesh update's report in words."""
        with self.lock:
            self._refuse_while_draping()
            report = self.ensure().apply(op, **args)
            self._save()
            return {"remeshed": report is None or bool(report.remeshed),
                    "min_angle": None if report is None else _finite(report.min_angle)}

    def undo(self) -> None:
        with self.lock:
            self._refuse_while_draping()
            self.ensure().undo()
            self._save()

    def redo(self) -> None:
        with self.lock:
            self._refuse_while_draping()
            self.ensure().redo()
            self._save()

    def drag(self, op: str, args: dict) -> tuple[np.ndarray, list[str]]:
        """Live preview of a drag: the mesh's flat vertices (n, 2) [m] for the edited pattern,
        through the cached coordinates of the current mesh (nothing is recorded)."""
        if op not in DRAG_OPS:
            raise ValueError(f"op: the drag preview takes {', '.join(DRAG_OPS)}")
        with self.lock:
            s = self.ensure()
            st = s.state
            if self._drag is None or self._drag[0] is not st:
                self._drag = (st, CoordinateCache(st.mesh))
            cache = self._drag[1]
        new = getattr(tools, op)(st.pattern, **args)
        # a preview never re-meshes: a panel that would need it shows its stretched mesh
        mesh, report = update_mesh(st.pattern, new, st.mesh, cache=cache, min_angle=0.0,
                                   return_report=True)
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
    def start_drape(self, *, kind: str = "drape") -> None:
        """Drape the current state (``kind="drape"``) or run the automatic fit correction
        (``"correct"``: drape, edit, re-drape rounds) in a background thread (progress in
        :attr:`job`)."""
        if kind not in ("drape", "correct"):
            raise ValueError(f"kind: 'drape' or 'correct', got {kind!r}")
        with self.lock:
            self._refuse_while_draping()
            self.ensure()
            self.job = DrapeJob(running=True, kind=kind)
            self._thread = threading.Thread(target=self._run_drape, args=(self.job,),
                                            daemon=True, name="patternfit-drape")
            self._thread.start()

    def stop_drape(self) -> None:
        self.job.stop = True

    def wait(self, timeout: float | None = None) -> None:
        """Wait for the background drape (tests, shutdown)."""
        if self._thread is not None:
            self._thread.join(timeout)

    def _run_drape(self, job: DrapeJob) -> None:
        t0 = time.perf_counter()

        def progress(it, energy, step, elapsed):
            job.iteration, job.energy, job.step = int(it), float(energy), float(step)
            job.elapsed = time.perf_counter() - t0
            if math.isfinite(step) and step > 0:
                # progress: the largest vertex step falling towards the stopping tolerance,
                # on a log scale (the iteration count is not known in advance)
                job._step0 = max(job._step0 or step, step)
                span = math.log(job._step0 / 1e-5)
                done = math.log(job._step0 / max(step, 1e-5)) / span if span > 0 else 1.0
                job.fraction = max(job.fraction, min(0.99, done))
            if job.stop:
                raise KeyboardInterrupt

        try:
            with self.lock:
                session = self.session
                state = session.state
            if job.kind == "correct":
                self._run_correction(job, session, progress)
            else:
                session.redrape(progress=progress)
                with self.lock:
                    if self.session is session and session.state is state:
                        self._save()
        except KeyboardInterrupt:  # stopped between two drapes of the correction
            pass
        except Exception as exc:  # shown in the page; the server keeps serving
            job.error = f"{type(exc).__name__}: {exc}"
        finally:
            job.elapsed = time.perf_counter() - t0
            job.fraction = 1.0 if job.error is None else job.fraction
            job.running = False
            job.finished = time.time()

    def _run_correction(self, job: DrapeJob, session, progress) -> None:
        """The automatic correction; each round's ϖ and edits go to ``job.rounds`` and the
        session is saved after each round, so the page can follow and a reload keeps it."""
        def round_done(it):
            job.rounds.append({"iteration": it.index, "fitting_ratio": it.fitting_ratio,
                               "edits": len(it.edits), "seconds": it.seconds,
                               "failed": _failed(it.checks)})
            job.fraction = 0.0
            job._step0 = None
            with self.lock:
                if self.session is session:
                    self._save()
            if job.stop:
                raise KeyboardInterrupt

        result = api.correct(session, settings=api.CorrectionSettings(
            threshold=session.threshold), progress=round_done, drape_progress=progress)
        job.result = {"reached": result.reached, "fitting_ratio": result.fitting_ratio,
                      "failed": result.failed}
        with self.lock:
            if self.session is session:
                self._save()


def _failed(checks: dict | None) -> str | None:
    """Why a state's drape failed its checks, in words (None: passed or not draped): the
    page shows such a ϖ red, as "failed", never as a fit."""
    if not checks or checks.get("passed") is not False:
        return None
    reasons = [str(r) for r in checks.get("reasons") or [] if r]
    return "; ".join(reasons) if reasons else "the drape's checks failed"


def _read_upload(kind: str, path: Path, stem: str):
    """The pattern, body or fabric in the uploaded file ``path``, named after ``stem`` (the
    client's file name) where the file gives no name of its own."""
    if kind == "pattern":
        return api.read_pattern(path)
    if kind == "fabric":
        fabric = api.read_fabric(path)
        return replace(fabric, name=stem) if fabric.name == path.stem else fabric
    body = api.read_body(path)
    body.name = stem
    body.meta = {**body.meta, "source": f"uploaded {stem}{path.suffix}"}
    return body


def describe_error(exc: Exception) -> str:
    """The message shown in the page for a refused request."""
    if isinstance(exc, KeyError) and exc.args:  # str() of a KeyError is the key's repr
        return str(exc.args[0])
    if isinstance(exc, (ValueError, IndexError, RuntimeError, TypeError)):
        return str(exc) or type(exc).__name__
    return f"{type(exc).__name__}: {exc}"
