"""Shared parts of the virtual fabric-testing kit (``patternfit.sim.fabric_test``): test
meshes, the solver settings a test is read with (:data:`AT_REST`), how a solve ended
(:class:`SolveInfo`), JSON-ready values and picture files.

Units: metres, kilograms, seconds, newtons; ``y`` is up.
"""

from __future__ import annotations

import io
import math
from collections.abc import Callable
from dataclasses import dataclass, fields, is_dataclass
from pathlib import Path

import numpy as np
import triangle as tr

from ...arguments import number
from ...files import atomic_write_bytes
from ...geometry import counter_clockwise
from ..result import DrapeResult
from ..settings import SolverSettings

Progress = Callable[[str], None]


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


#: solver settings the kit's tests fix (their readings are held to formulas in g)
_EARTH = frozenset({"gravity"})


def kit_settings(**changes) -> SolverSettings:
    """The solver settings the kit uses by default (:data:`AT_REST` over the solver's
    defaults) with ``changes`` (SolverSettings fields, e.g. ``compression=0.05``) applied.
    Raises ValueError naming an unknown field."""
    known = {f.name for f in fields(SolverSettings)} - _EARTH
    for key, value in changes.items():
        if key in _EARTH:
            raise ValueError(f"settings: {key!r} is not a setting of the kit: its tests are "
                             "made on Earth, and their expectations (the strip's ρgL²/2k, "
                             "the bending length (B/(ρg))^(1/3)) take g = 9.80665 m/s²")
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

    def describe(self) -> str:
        """How the solve ended, in words: stop reason, iterations and residual."""
        text = f"{self.stop_reason} after {self.iterations} iterations"
        r = self.residual if isinstance(self.residual, dict) else {}
        if r.get("residual_rms") is not None and r.get("residual_p99") is not None:
            text += (f", residual rms {r['residual_rms']:.3g}, p99 {r['residual_p99']:.3g} "
                     "weights")
        return text

    def to_dict(self) -> dict:
        return _plain({"iterations": self.iterations, "seconds": self.seconds,
                       "converged": self.converged, "equilibrium": self.equilibrium,
                       "stop_reason": self.stop_reason, "residual": self.residual,
                       "balanced": self.balanced, "at_rest": self.at_rest})


def _say(progress: Progress | None, text: str) -> None:
    if progress is not None:
        progress(text)


def _solve(solver, x0) -> DrapeResult:
    """``solver.solve(x0)`` (x0 (n, 3) [m]), raising KeyboardInterrupt when Ctrl-C stopped
    it: the solver turns the interrupt into an "interrupted" result, and a test read on it
    went on with its other solves and wrote complete-looking results (even passed)."""
    res = solver.solve(x0)
    if res.interrupted:
        raise KeyboardInterrupt
    return res


def _save(fig, path) -> Path:
    buf = io.BytesIO()
    fig.savefig(buf, format=Path(path).suffix.lstrip(".").lower() or "png", dpi=130)
    return atomic_write_bytes(path, buf.getvalue())

