"""Outline edges of a panel: straight lines, quadratic and cubic Béziers, circular arcs.

All coordinates are in metres, in the panel's own flat 2D frame (x to the right, y up).
An edge is immutable; its geometry is evaluated by curve parameter or by arc-length fraction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

KINDS = {"line": 2, "quadratic": 3, "cubic": 4, "arc": 2}

# Samples of the curve parameter used to tabulate arc length of curved edges.
_TABLE = 1025


def _as_points(points) -> tuple[tuple[float, float], ...]:
    arr = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    return tuple((float(x), float(y)) for x, y in arr)


@dataclass(frozen=True, eq=True)
class Edge:
    """One edge of a panel outline or inner loop.

    Parameters
    ----------
    name : str
        Unique within its panel ("side_r", "hem", ...); seams refer to edges by name.
    kind : str
        ``"line"``, ``"quadratic"``, ``"cubic"`` or ``"arc"``.
    points : (k, 2) float
        Start point, Bézier control points (if any), end point [m]. An arc has only its two
        end points; its shape is given by ``radius``, ``large_arc`` and ``sweep``.
    radius : float
        Arc radius [m] (arcs only).
    large_arc, sweep : bool
        SVG's arc flags: take the larger of the two possible arcs; run counter-clockwise
        (increasing angle, y up) from start to end.
    """

    name: str
    kind: str
    points: tuple
    radius: float | None = None
    large_arc: bool = False
    sweep: bool = True

    def __post_init__(self):
        object.__setattr__(self, "points", _as_points(self.points))
        if self.kind not in KINDS:
            raise ValueError(f"edge '{self.name}': unknown edge type '{self.kind}' "
                             f"(expected one of {sorted(KINDS)})")
        if len(self.points) != KINDS[self.kind]:
            raise ValueError(f"edge '{self.name}': a {self.kind} edge needs "
                             f"{KINDS[self.kind]} points, got {len(self.points)}")
        if self.kind == "arc":
            if self.radius is None:
                raise ValueError(f"edge '{self.name}': an arc needs a radius")
            object.__setattr__(self, "radius", float(self.radius))

    # -- construction helpers -------------------------------------------------------------
    @classmethod
    def line(cls, name, start, end) -> "Edge":
        """A straight edge from ``start`` to ``end`` [m]."""
        return cls(name, "line", (start, end))

    @classmethod
    def quadratic(cls, name, start, control, end) -> "Edge":
        """A quadratic Bézier edge [m]."""
        return cls(name, "quadratic", (start, control, end))

    @classmethod
    def cubic(cls, name, start, c1, c2, end) -> "Edge":
        """A cubic Bézier edge [m]."""
        return cls(name, "cubic", (start, c1, c2, end))

    @classmethod
    def arc(cls, name, start, end, radius, *, large_arc=False, sweep=True) -> "Edge":
        """A circular arc of ``radius`` [m] from ``start`` to ``end`` (SVG flags)."""
        return cls(name, "arc", (start, end), radius=radius, large_arc=large_arc, sweep=sweep)

    # -- basic geometry -------------------------------------------------------------------
    @property
    def start(self) -> np.ndarray:
        """(2,) float: first point [m]."""
        return np.array(self.points[0])

    @property
    def end(self) -> np.ndarray:
        """(2,) float: last point [m]."""
        return np.array(self.points[-1])

    def is_finite(self) -> bool:
        """True when every coordinate (and the radius) is a finite number."""
        vals = [c for p in self.points for c in p]
        if self.radius is not None:
            vals.append(self.radius)
        return bool(np.all(np.isfinite(vals)))

    def with_points(self, points) -> "Edge":
        """The same edge with new points (same kind and flags)."""
        return replace(self, points=_as_points(points))

    def transformed(self, matrix, offset=(0.0, 0.0)) -> "Edge":
        """Edge under ``x -> matrix @ x + offset``; arcs accept only similarity transforms."""
        m = np.asarray(matrix, dtype=np.float64)
        pts = np.asarray(self.points) @ m.T + np.asarray(offset, dtype=np.float64)
        if self.kind != "arc":
            return self.with_points(pts)
        det = float(np.linalg.det(m))
        scale = math.sqrt(abs(det))
        if not np.allclose(m.T @ m, scale**2 * np.eye(2), atol=1e-9 * max(scale**2, 1)):
            raise ValueError(f"edge '{self.name}': an arc can only be moved by a similarity "
                             "transform (rotation, uniform scale, mirror)")
        return replace(self, points=_as_points(pts), radius=self.radius * scale,
                       sweep=self.sweep if det > 0 else not self.sweep)

    def reversed(self) -> "Edge":
        """The same curve traversed from end to start."""
        if self.kind == "arc":
            return replace(self, points=self.points[::-1], sweep=not self.sweep)
        return replace(self, points=self.points[::-1])

    # -- arcs ------------------------------------------------------------------------------
    @cached_property
    def _arc(self):
        """Centre (2,), start angle, signed sweep angle of an arc [rad]."""
        p0, p1 = self.start, self.end
        chord = np.linalg.norm(p1 - p0)
        r = max(abs(self.radius), chord / 2)  # SVG: too small a radius is scaled up
        mid = (p0 + p1) / 2
        h = math.sqrt(max(r * r - (chord / 2) ** 2, 0.0))
        perp = np.array([-(p1 - p0)[1], (p1 - p0)[0]]) / max(chord, 1e-300)
        # centre on the left of the chord for a counter-clockwise minor arc
        sign = 1.0 if self.large_arc != self.sweep else -1.0
        centre = mid + sign * h * perp
        a0 = math.atan2(*(p0 - centre)[::-1])
        a1 = math.atan2(*(p1 - centre)[::-1])
        delta = a1 - a0
        if self.sweep and delta <= 0:
            delta += 2 * math.pi
        elif not self.sweep and delta >= 0:
            delta -= 2 * math.pi
        return centre, r, a0, delta

    # -- evaluation ------------------------------------------------------------------------
    def evaluate(self, t) -> np.ndarray:
        """Points at curve parameters ``t`` in [0, 1]: (len(t), 2) float [m]."""
        t = np.atleast_1d(np.asarray(t, dtype=np.float64))[:, None]
        P = np.asarray(self.points)
        if self.kind == "line":
            return (1 - t) * P[0] + t * P[1]
        if self.kind == "quadratic":
            return (1 - t) ** 2 * P[0] + 2 * (1 - t) * t * P[1] + t**2 * P[2]
        if self.kind == "cubic":
            u = 1 - t
            return u**3 * P[0] + 3 * u * u * t * P[1] + 3 * u * t * t * P[2] + t**3 * P[3]
        centre, r, a0, delta = self._arc
        ang = a0 + delta * t[:, 0]
        return centre + r * np.stack([np.cos(ang), np.sin(ang)], axis=1)

    @cached_property
    def _table(self):
        """Curve parameters and cumulative arc length [m] on a dense grid."""
        if self.kind in ("line", "arc"):
            return None
        t = np.linspace(0.0, 1.0, _TABLE)
        p = self.evaluate(t)
        s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])
        return t, s

    @property
    def length(self) -> float:
        """Arc length [m]."""
        if self.kind == "line":
            return float(np.linalg.norm(self.end - self.start))
        if self.kind == "arc":
            _, r, _, delta = self._arc
            return float(r * abs(delta))
        return float(self._table[1][-1])

    def parameter_at(self, fraction) -> np.ndarray:
        """Curve parameters at arc-length fractions in [0, 1]: (len(fraction),) float."""
        f = np.clip(np.atleast_1d(np.asarray(fraction, dtype=np.float64)), 0.0, 1.0)
        if self._table is None:
            return f
        t, s = self._table
        return np.interp(f * s[-1], s, t)

    def point_at(self, fraction) -> np.ndarray:
        """Points at arc-length fractions in [0, 1]: (len(fraction), 2) float [m]."""
        return self.evaluate(self.parameter_at(fraction))

    def polyline(self, n: int | None = None) -> np.ndarray:
        """The edge as ``n + 1`` points evenly spaced in arc length: (n + 1, 2) float [m].

        ``n`` defaults to 1 for lines and 32 for curves.
        """
        if n is None:
            n = 1 if self.kind == "line" else 32
        return self.point_at(np.linspace(0.0, 1.0, n + 1))

    def sub_length(self, start: float, end: float) -> float:
        """Arc length of the part between fractions ``start`` and ``end`` [m]."""
        return self.length * (end - start)
