"""Edges fitted to a DXF outline's points: lines, arcs, quadratic and cubic Béziers.

A closed polygon read from a DXF file is split at its turn points (or at corners) and every run
of points between two becomes the simplest edge that stays within ``tol.dxf_fit`` of the run's
points *and* within ``tol.dxf_span`` of the run's polyline everywhere along it, measured both
ways (curve samples to the polyline, polyline vertices to the curve); a run no single edge fits
is split in halves. For files from other tools (``foreign``), adjacent edges whose union fits as
well are merged (collinear runs become one line, over-split curves one curve), and an edge much
shorter than its neighbours is merged into one when the union stays within ``tol.dxf_span``
(short edges next to long ones leave the mesher thin triangles). Finally a fitted curve that
crosses or touches its neighbours is split, and at the last kept as the file's polyline.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from scipy.spatial import cKDTree

from ..constants import tol
from .dxf_kernels import farthest_from_densified, refine_cubic
from .edges import Edge
from .errors import PatternError
from .model import Loop
from .validate import check_polygons

__all__ = ["corners", "dedupe", "deviation", "loop_from_points"]

# below this determinant of the arc fit's 2 x 2 system its three points lie on a line [m^2]
_COLLINEAR = 1e-18
# the cubic fit stops when its squared error improves by less than this fraction, or falls
# below the absolute value [m^2]
_FIT_STALL, _FIT_EXACT = 1e-14, 1e-24
#: the deviation of a fit is measured on points this far apart along the curve and the
#: polyline (it overestimates by at most half of it) [m]
_DENSE = tol.dxf_span / 10
#: an edge shorter than this fraction of a neighbour is merged into it where it can be [-]
SHORT_RATIO = 0.25
#: samples per curved edge when checking a fitted loop for crossings [-]
_CROSS_SAMPLES = 64


def dedupe(p: np.ndarray, closed: bool, reach: float | None = None) -> np.ndarray:
    """``p`` (k, 2) [m] without points within ``reach`` (default ``tol.dxf_repeat``) of the
    last one kept; for a ``closed`` polygon also without a last point repeating the first."""
    reach = tol.dxf_repeat if reach is None else reach
    p = np.asarray(p, dtype=np.float64).reshape(-1, 2)
    if len(p) == 0:
        return p
    step = np.linalg.norm(np.diff(p, axis=0), axis=1)
    if np.all(step >= reach):
        keep = np.ones(len(p), dtype=bool)
    else:
        keep = np.zeros(len(p), dtype=bool)
        keep[0], last = True, p[0]
        for i in range(1, len(p)):
            if np.linalg.norm(p[i] - last) >= reach:
                keep[i], last = True, p[i]
    p = p[keep]
    while closed and len(p) > 2 and np.linalg.norm(p[-1] - p[0]) < reach:
        p = p[:-1]
    return p


def deviation(edge: Edge, p: np.ndarray) -> float:
    """Largest distance between ``edge`` and the polyline ``p`` (k, 2) [m], both ways: from
    points along the edge to the polyline and from the polyline's vertices to the edge,
    both measured on points ``_DENSE`` apart (an overestimate by at most half of that)."""
    p = np.ascontiguousarray(p, dtype=np.float64)
    length = max(edge.length, float(np.sum(np.linalg.norm(np.diff(p, axis=0), axis=1))))
    n = int(min(20000, max(16, math.ceil(length / _DENSE))))
    curve = np.ascontiguousarray(edge.point_at(np.linspace(0.0, 1.0, n + 1)))
    return max(farthest_from_densified(curve, p, _DENSE),
               farthest_from_densified(p, curve, _DENSE))


def _line_dev(p: np.ndarray) -> float:
    d = p[-1] - p[0]
    n = np.linalg.norm(d)
    if n == 0:
        return float(np.max(np.linalg.norm(p - p[0], axis=1)))
    return float(np.max(np.abs((p[:, 0] - p[0, 0]) * d[1] - (p[:, 1] - p[0, 1]) * d[0]) / n))


def _fit_arc(name: str, p: np.ndarray) -> tuple[Edge, float] | None:
    """The circular arc through the ends and middle of ``p`` (k, 2) [m] and its largest
    distance to ``p``, or None when the points do not run round one centre."""
    a, b, c = p[0], p[len(p) // 2], p[-1]
    m = np.array([b - a, c - a]) * 2
    det = np.linalg.det(m)
    if abs(det) < _COLLINEAR:
        return None
    centre = np.linalg.solve(m, [b @ b - a @ a, c @ c - a @ a])
    r = float(np.linalg.norm(a - centre))
    dev = float(np.max(np.abs(np.linalg.norm(p - centre, axis=1) - r)))
    ang = np.unwrap(np.arctan2(p[:, 1] - centre[1], p[:, 0] - centre[0]))
    steps = np.diff(ang)
    if not (np.all(steps > 0) or np.all(steps < 0)):
        return None
    span = float(ang[-1] - ang[0])
    return Edge.arc(name, a, c, r, large_arc=abs(span) > math.pi, sweep=span > 0), dev


def _fit_cubic(name: str, p: np.ndarray, iterations: int = 100) -> tuple[Edge, float]:
    """Least-squares cubic Bézier through ``p`` (k, 2) [m] with fixed ends; returns it and
    the largest distance from a point of ``p`` to the curve [m].

    Control points and the points' curve parameters are solved together (Levenberg-Marquardt,
    the parameters eliminated by a Schur complement): fitting the control points alone and
    re-projecting stalls on curves whose speed varies a lot.
    """
    p = np.ascontiguousarray(p, dtype=np.float64)
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])
    t = s / s[-1]
    u = 1 - t
    rhs = p - np.outer(u**3, p[0]) - np.outer(t**3, p[-1])
    inner, *_ = np.linalg.lstsq(np.column_stack([3 * u * u * t, 3 * u * t * t]), rhs,
                                rcond=None)
    c = np.array([p[0], inner[0], inner[1], p[-1]])

    c, t = refine_cubic(c, t, p, 1e-3 * s[-1] ** 2, iterations, _FIT_STALL, _FIT_EXACT)
    edge = Edge.cubic(name, *c)
    return edge, float(np.max(np.linalg.norm(edge.evaluate(t) - p, axis=1)))


def _fit_one(name: str, p: np.ndarray, point_tol: float, span_tol: float) -> Edge | None:
    """The simplest edge (line, quadratic or cubic Bézier, arc) within ``point_tol`` of all of
    ``p`` (k, 2) [m] and within ``span_tol`` of its polyline everywhere, or None. Between an
    arc and a cubic the closer one wins."""
    if len(p) == 2:
        return Edge.line(name, p[0], p[-1])
    if _line_dev(p) < point_tol:
        line = Edge.line(name, p[0], p[-1])
        if deviation(line, p) < span_tol:
            return line
    found = []
    arc = _fit_arc(name, p)
    if arc is not None and arc[1] < point_tol:
        found.append((arc[1], 0, arc[0]))
    if len(p) >= 4:
        cubic, dev = _fit_cubic(name, p)
        if dev < point_tol:
            c = np.asarray(cubic.points)
            q1, q2 = (3 * c[1] - c[0]) / 2, (3 * c[2] - c[3]) / 2  # raised quadratic: q1 == q2
            if np.linalg.norm(q1 - q2) < point_tol:
                cubic = Edge.quadratic(name, c[0], 0.5 * (q1 + q2), c[3])
            found.append((dev, 1, cubic))
    for _, _, edge in sorted(found, key=lambda f: (f[0], f[1])):
        if edge.is_finite() and deviation(edge, p) < span_tol:
            return edge
    return None


Piece = tuple[Edge, np.ndarray]  # an edge and the file's points it was fitted to


def _fit_run(p: np.ndarray, point_tol: float = tol.dxf_fit,
             span_tol: float = tol.dxf_span) -> list[Piece]:
    """Edges through one run of points (k, 2) [m], split where a single curve does not fit."""
    edge = _fit_one("e", p, point_tol, span_tol)
    if edge is not None:
        return [(edge, p)]
    if len(p) <= 3:
        return [(Edge.line("e", a, b), np.array([a, b])) for a, b in zip(p[:-1], p[1:])]
    mid = len(p) // 2
    return _fit_run(p[: mid + 1], point_tol, span_tol) + _fit_run(p[mid:], point_tol, span_tol)


def corners(p: np.ndarray, angle: float = 25.0) -> list[int]:
    """Indices of the closed polygon's vertices that turn by more than ``angle`` degrees."""
    a = p - np.roll(p, 1, axis=0)
    b = np.roll(p, -1, axis=0) - p
    cos = np.einsum("ij,ij->i", a, b) / np.maximum(
        np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1), 1e-300)
    return [int(i) for i in np.flatnonzero(cos < math.cos(math.radians(angle)))]


def _merge_pass(pieces: list[Piece], pick, point_tol: float, span_tol: float, *,
                cyclic: bool = True, lines_only: bool = False) -> list[Piece]:
    """Merge neighbouring pieces (of a closed loop when ``cyclic``, else of an open run)
    while ``pick(pieces, i)`` offers piece ``i``'s neighbours (in order of preference) and
    their union fits one edge (only a line, with ``lines_only``)."""
    i = 0
    while i < len(pieces) and len(pieces) > (2 if cyclic else 1):
        done = False
        k = len(pieces)
        for j in pick(pieces, i):
            if not cyclic and not 0 <= j < k:
                continue
            j %= k
            if j == i:
                continue
            a, b = (j, i) if j == (i - 1) % k else (i, j)
            if lines_only and (pieces[a][0].kind != "line" or pieces[b][0].kind != "line"):
                continue
            run = np.vstack([pieces[a][1], pieces[b][1][1:]])
            edge = _fit_one("e", run, point_tol, span_tol)
            if edge is not None and (not lines_only or edge.kind == "line"):
                pieces[a] = (edge, run)
                del pieces[b]
                if b < a:
                    a -= 1
                i = max(0, a - 1)
                done = True
                break
        if not done:
            i += 1
    return pieces


def _forward(ps: list[Piece], i: int) -> list[int]:
    return [i + 1]


def _tiny(ps: list[Piece], i: int) -> list[int]:
    k, own = len(ps), ps[i][0].length
    near = sorted([(i - 1) % k, (i + 1) % k], key=lambda j: ps[j][0].length)
    return [j for j in near if own < SHORT_RATIO * ps[j][0].length]


def _merged_run(pieces: list[Piece], span: float) -> list[Piece]:
    """Foreign files: pieces of one run between turn points whose union fits as tightly
    merged (a run split in halves more often than needed)."""
    return _merge_pass(list(pieces), _forward, tol.dxf_fit, span, cyclic=False)


def _merged(pieces: list[Piece], span: float) -> list[Piece]:
    """Foreign files: lines across turn points merged where collinear (within
    ``tol.dxf_fit``), then tiny edges merged into a neighbour within ``span`` [m]."""
    pieces = _merge_pass(list(pieces), _forward, tol.dxf_fit, span, lines_only=True)
    return _merge_pass(pieces, _tiny, span, span)


def _ring(pieces: list[Piece]) -> tuple[np.ndarray, list[int]]:
    """The loop as a polyline, curves sampled finely, and the piece of every segment."""
    pts, owner = [], []
    for k, (edge, _) in enumerate(pieces):
        q = edge.point_at(np.linspace(0, 1, 2 if edge.kind == "line" else _CROSS_SAMPLES + 1))
        pts.append(q[:-1])
        owner += [k] * (len(q) - 1)
    return np.concatenate(pts), owner


def _uncrossed(pieces: list[Piece], name: str, span: float) -> list[Piece]:
    """Split (at the last: keep as the file's polyline) every fitted curve that crosses or
    touches its loop; crossings between lines are the file's own, left for the checks."""
    for _ in range(4 * len(pieces) + 16):
        ring, owner = _ring(pieces)
        names = [f"p{k}" for k in owner]
        try:
            check_polygons([ring], [names], [name])
            return pieces
        except PatternError as exc:
            if exc.edge is None or not exc.edge.startswith("p"):
                return pieces
            k = int(exc.edge[1:])
        m = len(pieces)
        bad = next((j for j in (k, (k - 1) % m, (k + 1) % m) if pieces[j][0].kind != "line"),
                   None)
        if bad is None:
            return pieces
        pts = pieces[bad][1]
        if len(pts) > 3:
            mid = len(pts) // 2
            new = _fit_run(pts[: mid + 1], span_tol=span) + _fit_run(pts[mid:], span_tol=span)
        else:
            new = [(Edge.line("e", a, b), np.array([a, b])) for a, b in zip(pts[:-1], pts[1:])]
        pieces[bad:bad + 1] = new
    return pieces


def loop_from_points(p: np.ndarray, turns: np.ndarray, name: str, prefix: str, *,
                     foreign: bool = False, span: float = tol.dxf_span) -> Loop:
    """Split a closed polygon (k, 2) at its turn points (t, 2) and fit every run [m].

    foreign : the file comes from another tool: merge what fits together and tiny edges
        (:func:`_merged`); our own files keep an edge between every two turn points.
    span : how far [m] a fitted edge may stray from the run's polyline (at most
        ``tol.dxf_span``; the file's own curve tolerance where it states one)."""
    p = dedupe(p, closed=True)
    breaks = []
    if len(turns):
        near, _ = cKDTree(turns).query(p, distance_upper_bound=tol.dxf_fit)
        breaks = np.flatnonzero(near < tol.dxf_fit).tolist()
    if not breaks:
        breaks = corners(p) or [0]
    p = np.roll(p, -breaks[0], axis=0)
    breaks = [(b - breaks[0]) % len(p) for b in breaks] + [len(p)]
    closed = np.vstack([p, p[:1]])
    pieces: list[Piece] = []
    for b0, b1 in zip(breaks[:-1], breaks[1:]):
        run = _fit_run(closed[b0:b1 + 1], span_tol=span)
        pieces += _merged_run(run, span) if foreign else run
    if foreign:
        pieces = _merged(pieces, span)
    if len(pieces) == 1:  # a loop needs at least two edges: split the single one in halves
        half = len(p) // 2
        pieces = (_fit_run(closed[: half + 1], span_tol=span)
                  + _fit_run(closed[half:], span_tol=span))
    pieces = _uncrossed(pieces, name, span)
    return Loop(name, tuple(replace(e, name=f"{prefix}{k}") for k, (e, _) in
                            enumerate(pieces)))
