"""One task of a batch, as a worker runs it: drape, evaluate, make the row and the
thumbnail. Never raises for a drape that goes wrong: an exception becomes a failed row."""

from __future__ import annotations

import hashlib
import io
import os
import re
import socket
import time
import traceback
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np

from ..api import GIRTHS, SolverSettings, drape_and_evaluate
from ..fit.pictures import FAILED_GREY
from ..errors import ctrl_c
from .rows import Task, failed_row

#: the thumbnails' folder inside a batch folder
THUMBS = "thumbs"
#: the key of a row that carries its thumbnail (PNG bytes) from the worker to the driver,
#: which writes it (a worker on another machine has no access to the batch folder)
PNG = "thumbnail_png"


@dataclass(frozen=True)
class TaskOptions:
    """What every task of a batch shares.

    triangles : int
        Target triangle count of the garment mesh [-].
    time_limit : float
        The solver's time limit per drape [s]; the batch cancels a task that runs far
        beyond it (:func:`patternfit.batch.cluster.hard_limit`).
    thumbnails : bool
        Whether to draw a thumbnail per drape.
    """

    triangles: int
    time_limit: float
    thumbnails: bool = True


class Inputs(NamedTuple):
    """What the tasks drape, read once on the driver: body name -> Body, (pattern, size) ->
    Pattern, fabric -> Fabric (a name or file instead of an object is read by the task)."""

    bodies: dict
    patterns: dict
    fabrics: dict

    def of(self, task: Task) -> tuple:
        """(body, pattern, fabric) of ``task``."""
        return (self.bodies[task.body], self.patterns.get((task.pattern, task.size),
                                                          task.pattern),
                self.fabrics.get(task.fabric, task.fabric))


def worker_id() -> str:
    """The host and process that ran a task (``host:pid``)."""
    return f"{socket.gethostname()}:{os.getpid()}"


def thumbnail_name(task: Task) -> str:
    """A file name for the task's thumbnail: readable, and unique per 4-tuple."""
    slug = "_".join(re.sub(r"[^A-Za-z0-9.-]+", "-", Path(p).stem if i == 0 else p)
                    for i, p in enumerate(task))
    return f"{slug}-{hashlib.sha1(repr(tuple(task)).encode()).hexdigest()[:8]}.png"


def failed_checks(checks: dict, fitting_ratio: float) -> list[str]:
    """Names of the checks a drape failed: ``inside`` (vertices, edges or triangles in the
    body), ``seams``
    (open >= 0.5 mm), ``crossings``, ``equilibrium``, ``on_body``, ``fitting_ratio`` (not
    finite)."""
    out = []
    if checks.get("inside_vertices") or checks.get("edges_in_body") \
            or checks.get("faces_in_body"):
        out.append("inside")
    if not checks.get("seam_gap_max_mm", 0.0) < 0.5:
        out.append("seams")
    if checks.get("self_intersections"):
        out.append("crossings")
    if checks.get("equilibrium") is False:
        out.append("equilibrium")
    if checks.get("on_body") is False:
        out.append("on_body")
    if not np.isfinite(fitting_ratio):
        out.append("fitting_ratio")
    return out


def outcome_row(task: Task, outcome, *, seconds: float, worker: str) -> dict:
    """The row of a drape's :class:`~patternfit.api.FitOutcome`: status ``ok`` when the
    drape passed its checks, ``failed`` (with the failed checks and reasons) otherwise."""
    checks = outcome.checks
    report = outcome.measures.report() if outcome.measures is not None else {}
    ease = report.get("ease_cm", {})
    pressure = report.get("pressure_kpa") or {}
    ratio = outcome.fitting_ratio
    failed = failed_checks(checks, ratio)
    passed = outcome.passed and not failed
    reasons = list(checks.get("reasons") or [])
    return {**task._asdict(), "status": "ok" if passed else "failed",
            "fitting_ratio": ratio if np.isfinite(ratio) else None,
            "fitting_ratio_symmetric": float(outcome.fit.fitting_ratio_symmetric),
            "verdict": outcome.verdict, "verdict_regions": _verdict_regions(outcome),
            **{f"ease_{g}_cm": ease.get(g) for g in GIRTHS},
            "pressure_p95_kpa": pressure.get("p95"), "pressure_p99_kpa": pressure.get("p99"),
            "checks_passed": passed, "failed_checks": " ".join(failed),
            "reasons": "; ".join(reasons), "residual_rms": checks.get("residual_rms"),
            "residual_p99": checks.get("residual_p99"), "seconds": seconds, "worker": worker}


def _verdict_regions(outcome) -> str:
    """The regions whose own verdict is the drape's (``"waist hip"``): where it is what it
    is said to be."""
    if outcome.judgement is None:
        return ""
    regions = outcome.judgement.report().get("region_verdicts") or {}
    return " ".join(k for k, v in regions.items() if v.get("verdict") == outcome.verdict)


def run_task(task: Task, body, options: TaskOptions, pattern=None, fabric=None) -> dict:
    """Drape ``task`` on ``body`` (a :class:`~patternfit.api.Body`, its distance field
    already on it, or a name) in ``pattern`` and ``fabric`` (objects read on the driver;
    the task's own names or files when None) and return its row, with the thumbnail's PNG
    bytes under :data:`PNG`. An exception becomes a failed row naming it; a
    KeyboardInterrupt stops."""
    t0 = time.perf_counter()
    worker = worker_id()
    try:
        outcome = drape_and_evaluate(task.pattern if pattern is None else pattern, body,
                                     task.fabric if fabric is None else fabric,
                                     size=task.size, triangles=options.triangles,
                                     settings=SolverSettings(time_limit=options.time_limit))
        if outcome.interrupted:
            # Ctrl-C inside the solve, which stops with its last state: that state is no
            # result of the task, so no row (--resume drapes it again), and the batch stops
            raise KeyboardInterrupt
        row = outcome_row(task, outcome, seconds=time.perf_counter() - t0, worker=worker)
        if options.thumbnails:
            row["thumbnail"] = f"{THUMBS}/{thumbnail_name(task)}"
            row[PNG] = thumbnail_png(outcome)
    except Exception as exc:  # a failed drape is a failed row, never a failed batch
        if ctrl_c(exc):
            # Ctrl-C in a compiled kernel outside the solve's own catch (the distance field
            # of the first contact lookup) was a failed row for good: --resume skipped it
            raise KeyboardInterrupt from exc
        where = traceback.extract_tb(exc.__traceback__)[-1]
        first = (str(exc).strip().splitlines() or [""])[0]
        reason = (f"{type(exc).__name__}: {first} (at {Path(where.filename).name}:"
                  f"{where.lineno})")
        row = failed_row(task, reason, seconds=time.perf_counter() - t0, worker=worker)
    return row


def _shaded(rgba, tri):
    """Colours (k, 4) of triangles (k, 3, 3) lit from the viewer (+Z), either side."""
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    lit = np.abs(n[:, 2]) / np.maximum(np.linalg.norm(n, axis=1), 1e-12)
    out = np.array(rgba, dtype=np.float64)
    out[:, :3] *= (0.55 + 0.45 * lit)[:, None]
    out[:, 3] = 1.0
    return out


def thumbnail_png(outcome, *, pixels: int = 180) -> bytes:
    """A small front view of the drape: the body in grey, the garment coloured by its area
    change (red stretched, yellow unchanged, blue compressed, ±10%; a drape that failed its
    checks in the darker grey of every failed picture, no fit colour), drawn back to front,
    lit from the front, framed on the garment: PNG bytes, ``pixels`` high."""
    # matplotlib without pyplot: no global state, safe in any worker
    from matplotlib import colormaps
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.collections import PolyCollection
    from matplotlib.figure import Figure

    faces, colours = [], []
    body = outcome.body
    if body is not None:
        tri = body.vertices[body.faces]
        faces.append(tri)
        colours.append(_shaded(np.full((len(tri), 4), 0.8), tri))
    garment = outcome.positions[outcome.mesh.triangles]
    change = np.nan_to_num(outcome.fit.area_change, nan=0.0)
    faces.append(garment)
    if outcome.passed:
        rgba = colormaps["RdYlBu_r"](np.clip(0.5 + 5.0 * change, 0.0, 1.0))
    else:
        rgba = np.tile(np.r_[FAILED_GREY, 1.0], (len(garment), 1))
    colours.append(_shaded(rgba, garment))
    tris = np.concatenate(faces)
    order = np.argsort(tris[:, :, 2].mean(axis=1))  # painter's: far (-z) first
    fig = Figure(figsize=(pixels / 150, pixels / 100), dpi=100)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.add_collection(PolyCollection(tris[order][:, :, :2], edgecolors="none",
                                     facecolors=np.concatenate(colours)[order],
                                     antialiased=False))
    lo, hi = garment[:, :, :2].reshape(-1, 2).min(0), garment[:, :, :2].reshape(-1, 2).max(0)
    ax.set_xlim(lo[0] - 0.08, hi[0] + 0.08)
    ax.set_ylim(lo[1] - 0.08, hi[1] + 0.08)
    ax.set_aspect("equal")
    ax.axis("off")
    buf = io.BytesIO()
    FigureCanvasAgg(fig).print_png(buf)
    return buf.getvalue()
