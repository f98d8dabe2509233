"""Checks that a pattern can be meshed and sewn; each failure names panel and edge.

The geometry test works on the loops' polylines (curves sampled, :data:`SAMPLES` segments per
curved edge): no two segments may come within ``tol.merge`` of each other unless they are
neighbours in one loop, and two neighbours may meet only at their shared point. That refuses
proper crossings, a loop touching itself (at a point of another segment, or at a vertex: a
pinch), segments running along each other, and zero-width spikes (an edge doubling back on the
previous one), within a loop and between loops, all of which crash or mislead the mesher.
Candidate pairs come from a uniform grid over the segments, so the work is near-linear in the
number of segments for ordinary outlines, and memory stays linear whatever the input.
Sizes are capped by :data:`~patternfit.constants.limits` before anything large is built.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Sequence

import numpy as np

from ..constants import limits, tol
from ..text import control_at
from .errors import PatternError
from .model import ANCHORS, Loop, Panel, Pattern

#: polyline segments per curved edge for the geometry tests (fewer on curves so short that
#: their segments would be shorter than ``tol.edge_length``)
SAMPLES = 24


# segment pairs tested at a time, and point-edge pairs of the inside test: bounds memory
_CHUNK = 1 << 16
# the grid cell is at least the total segment length over this many times the segment count,
# so that cutting long segments into cell-sized pieces makes at most that many pieces each
_PIECES = 4


def check_size(panels: int, edges: int) -> None:
    """Raise :class:`PatternError` when a pattern would have more ``panels`` or ``edges`` (all
    loops of all panels) than :data:`~patternfit.constants.limits` allows. Readers call it on
    the counts in the file, before building anything."""
    if panels > limits.panels:
        raise PatternError(f"the pattern has {panels} panels, more than the limit of "
                           f"{limits.panels}")
    if edges > limits.edges_per_pattern:
        raise PatternError(f"the pattern has {edges} edges, more than the limit of "
                           f"{limits.edges_per_pattern}")


def _cross(o: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """z of (a - o) x (b - o), broadcast over (..., 2) arrays."""
    return ((a[..., 0] - o[..., 0]) * (b[..., 1] - o[..., 1])
            - (a[..., 1] - o[..., 1]) * (b[..., 0] - o[..., 0]))


def _point_segment_d2(x: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Squared distance from points x to segments a-b, (..., 2) arrays [m^2]."""
    dx, dy = b[..., 0] - a[..., 0], b[..., 1] - a[..., 1]
    ux, uy = x[..., 0] - a[..., 0], x[..., 1] - a[..., 1]
    n2 = dx * dx + dy * dy
    t = np.clip((ux * dx + uy * dy) / np.where(n2 > 0, n2, 1.0), 0.0, 1.0)
    return (t * dx - ux) ** 2 + (t * dy - uy) ** 2


def _crossing(p, q, r, s) -> np.ndarray:
    """Segments p-q and r-s cross at a point inside both: bool, broadcast."""
    return (_cross(r, s, p) * _cross(r, s, q) < 0) & (_cross(p, q, r) * _cross(p, q, s) < 0)


def _segment_d2(p, q, r, s) -> np.ndarray:
    """Squared distance between segments p-q and r-s [m^2], broadcast."""
    ends = np.minimum(np.minimum(_point_segment_d2(p, r, s), _point_segment_d2(q, r, s)),
                      np.minimum(_point_segment_d2(r, p, q), _point_segment_d2(s, p, q)))
    return np.where(_crossing(p, q, r, s), 0.0, ends)


def _near_pairs(a: np.ndarray, b: np.ndarray, reach: float):
    """Chunks (i, j) of indices, i < j, covering every pair of segments a-b (n, 2) [m] that
    come within ``reach`` [m] of each other (and some that do not).

    Segments are cut into pieces no longer than a grid cell; each piece is entered in the
    cells its box, grown by ``reach``, covers, and segments sharing a cell are paired.
    """
    n = len(a)
    length = np.linalg.norm(b - a, axis=1)
    # cells about as large as a typical segment, and never so small that a piece's grown
    # box spans more than three cells a side
    cell = max(float(np.median(length)), float(length.sum()) / (_PIECES * n), 4.0 * reach)
    pieces = np.maximum(np.ceil(length / cell).astype(np.int64), 1)
    seg = np.repeat(np.arange(n), pieces)
    k = np.arange(len(seg)) - np.repeat(np.cumsum(pieces) - pieces, pieces)
    d = (b - a)[seg]
    p0 = a[seg] + (k / pieces[seg])[:, None] * d
    p1 = a[seg] + ((k + 1) / pieces[seg])[:, None] * d
    lo, hi = np.minimum(p0, p1) - reach, np.maximum(p0, p1) + reach
    origin = lo.min(axis=0)
    c0 = np.floor((lo - origin) / cell).astype(np.int64)
    c1 = np.floor((hi - origin) / cell).astype(np.int64)
    rows = int(c1[:, 1].max()) + 1
    cells, owners = [], []
    for dx in range(3):
        for dy in range(3):
            m = (c0[:, 0] + dx <= c1[:, 0]) & (c0[:, 1] + dy <= c1[:, 1])
            cells.append((c0[m, 0] + dx) * rows + c0[m, 1] + dy)
            owners.append(seg[m])
    cells, owners = np.concatenate(cells), np.concatenate(owners)
    order = np.lexsort((owners, cells))
    cells, owners = cells[order], owners[order]
    keep = np.ones(len(cells), dtype=bool)
    keep[1:] = (cells[1:] != cells[:-1]) | (owners[1:] != owners[:-1])
    cells, owners = cells[keep], owners[keep]
    # entry k pairs with k + d while both lie in one cell; sorted by cell, the entries that
    # still do so at d + 1 are among those that did at d
    d, active, batch = 1, np.arange(len(cells) - 1), []
    while len(active):
        active = active[cells[active + d] == cells[active]]
        batch.append((owners[active], owners[active + d]))
        d += 1
        active = active[active + d < len(cells)]
        if not len(active) or sum(len(x) for x, _ in batch) >= _CHUNK:
            x, y = (np.concatenate(v) for v in zip(*batch))
            for s in range(0, len(x), _CHUNK):
                yield (np.minimum(x[s:s + _CHUNK], y[s:s + _CHUNK]),
                       np.maximum(x[s:s + _CHUNK], y[s:s + _CHUNK]))
            batch = []


def _fmt(p) -> str:
    return "[" + ", ".join(f"{float(c):.6g}" for c in p) + "]"


def _contact(p, q, r, s, adjacent: bool, reach: float) -> tuple[str, str, np.ndarray]:
    """How segment p-q meets segment r-s, for the message: a verb, what follows the second
    edge's name, and the place (2,) [m]."""
    if adjacent:
        return "doubles back on", " (a zero-width spike)", q
    if _crossing(p, q, r, s):
        d1, d2 = _cross(r, s, p), _cross(r, s, q)
        return "crosses", "", p + (q - p) * (d1 / (d1 - d2))
    u = q - p
    n = float(np.linalg.norm(u))
    if max(abs(float(_cross(p, q, x))) for x in (r, s)) < reach * n:
        t0, t1 = sorted(float(np.dot(x - p, u)) / n**2 for x in (r, s))
        lo, hi = max(t0, 0.0), min(t1, 1.0)
        if (hi - lo) * n > reach:
            return "runs along", " (they overlap)", p + u * 0.5 * (lo + hi)
    for x in (p, q):
        for y in (r, s):
            if np.sum((x - y) ** 2) < reach * reach:
                return "meets", " at a point (a pinch)", x
    near = [(float(_point_segment_d2(x, r, s)), x) for x in (p, q)] + \
           [(float(_point_segment_d2(x, p, q)), x) for x in (r, s)]
    return "touches", "", min(near, key=lambda t: t[0])[1]


def _contact_error(si: int, sj: int, segments, names, ring_of, loops, panel) -> PatternError:
    """The error for segments ``si`` and ``sj`` that come too close, naming both edges."""
    a, b, nxt = segments
    adjacent = nxt[si] == sj or nxt[sj] == si
    if adjacent and nxt[si] != sj:
        si, sj = sj, si  # si runs into sj, which doubles back on it
    verb, tail, at = _contact(a[si], b[si], a[sj], b[sj], adjacent, tol.merge)
    first, second = (names[sj], names[si]) if adjacent else (names[si], names[sj])
    li, lj = int(ring_of[si]), int(ring_of[sj])
    itself = li == lj and first == second
    what = f"edge '{first}' {verb} " + ("itself" if itself else f"edge '{second}'") \
        + f"{tail} at {_fmt(at)}"
    if li == lj:
        kind = "outline" if li == 0 else "inner loop"
        return PatternError(f"self-intersecting {kind}: in loop '{loops[li]}', {what}",
                            panel=panel, edge=first)
    if li == 0:
        li, lj = lj, li
    where = "is not inside the outline" if lj == 0 else \
        f"is not apart from inner loop '{loops[lj]}'"
    return PatternError(f"inner loop '{loops[li]}' {where}: {what}", panel=panel, edge=first)


def check_polygons(rings: Sequence[np.ndarray], edges: Sequence[Sequence[str]],
                   loops: Sequence[str], *, panel: str | None = None) -> None:
    """Raise :class:`PatternError` unless the closed polylines ``rings`` are simple and apart.

    rings : closed polylines (k_i, 2) float [m], last point not repeated; the first is the
        outline, the others inner loops.
    edges : per ring, the edge name of each segment (segment ``i`` runs from point ``i`` to
        point ``i + 1``), for the message.
    loops : the loop name of each ring.

    Refused: a ring of fewer than three points, a coordinate that is not finite or lies
    beyond ``limits.extent``, a segment shorter than ``tol.merge``, two segments within
    ``tol.merge`` of each other unless they are neighbours in one ring, and two neighbours
    that meet anywhere but at their shared point (a zero-width spike).
    """
    for ring, name, per_ring in zip(rings, loops, edges):
        if len(ring) < 3:
            raise PatternError(f"loop '{name}' has fewer than three points", panel=panel,
                               edge=per_ring[0] if len(per_ring) else None)
    pts = np.concatenate([np.asarray(r, dtype=np.float64).reshape(-1, 2) for r in rings])
    names = [n for per_ring in edges for n in per_ring]
    sizes = np.array([len(r) for r in rings])
    ring_of = np.repeat(np.arange(len(rings)), sizes)
    if not np.isfinite(pts).all():
        k = int(np.flatnonzero(~np.isfinite(pts).all(axis=1))[0])
        raise PatternError("coordinate is NaN or infinite", panel=panel, edge=names[k])
    far = np.abs(pts).max(axis=1)
    if far.max() > limits.extent:
        k = int(np.argmax(far))
        raise PatternError(f"loop '{loops[ring_of[k]]}' reaches {far[k]:.3g} m from the origin, "
                           f"beyond the limit of {limits.extent:g} m", panel=panel,
                           edge=names[k])
    nxt = np.arange(len(pts)) + 1
    ends = np.cumsum(sizes)
    nxt[ends - 1] = ends - sizes
    a, b = pts, pts[nxt]
    reach = tol.merge
    short = np.flatnonzero(np.sum((b - a) ** 2, axis=1) < reach * reach)
    if len(short):
        k = int(short[0])
        raise PatternError(f"loop '{loops[ring_of[k]]}' repeats the point {_fmt(a[k])}",
                           panel=panel, edge=names[k])
    worst = None  # a spike explains more than the contacts around it: report it first
    for i, j in _near_pairs(a, b, reach):
        ij, ji = nxt[i] == j, nxt[j] == i
        # neighbours share a point; they fold onto each other when a far end lies on the other
        fold = (ij & ((_point_segment_d2(b[j], a[i], b[i]) < reach * reach)
                      | (_point_segment_d2(a[i], a[j], b[j]) < reach * reach))) | \
               (ji & ((_point_segment_d2(b[i], a[j], b[j]) < reach * reach)
                      | (_point_segment_d2(a[j], a[i], b[i]) < reach * reach)))
        hit = np.flatnonzero(np.where(ij | ji, fold,
                                      _segment_d2(a[i], b[i], a[j], b[j]) < reach * reach))
        if len(hit):
            m = hit[np.lexsort((j[hit], i[hit], ~fold[hit]))[0]]
            found = (not fold[m], int(i[m]), int(j[m]))
            worst = found if worst is None else min(worst, found)
    if worst is not None:
        raise _contact_error(worst[1], worst[2], (a, b, nxt), names, ring_of, loops, panel)


def _inside(points: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """Even-odd test of points (q, 2) against a closed polyline (k, 2): bool (q,)."""
    x0, y0 = ring[:, 0], ring[:, 1]
    x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
    out = np.zeros(len(points), dtype=bool)
    step = max(1, _CHUNK // len(ring))
    for s in range(0, len(points), step):
        x, y = points[s:s + step, 0:1], points[s:s + step, 1:2]
        cond = (y0 > y) != (y1 > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
        out[s:s + step] = (np.sum(cond & (x < xc), axis=1) % 2) == 1
    return out


def _samples(edge) -> int:
    if edge.kind == "line":
        return 1
    return int(min(SAMPLES, max(1, edge.length // tol.edge_length)))


def _loop_polyline(loop: Loop) -> tuple[np.ndarray, list[str]]:
    """The polyline the geometry tests use for ``loop``: points (k, 2) float [m], last not
    repeated, and the edge name of each segment (k,)."""
    pts, names = [], []
    for e in loop.edges:
        n = _samples(e)
        pts.append(e.polyline(n)[:-1])
        names += [e.name] * n
    return np.concatenate(pts), names


def _check_loop(panel: Panel, loop: Loop) -> None:
    if not loop.edges:
        raise PatternError(f"loop '{loop.name}' has no edges", panel=panel.name)
    for e in loop.edges:
        if not e.is_finite():  # its radius too
            raise PatternError("coordinate is NaN or infinite", panel=panel.name, edge=e.name)
        _within_extent(e.points, panel.name, edge=e.name)
    for e in loop.edges:
        if e.length < tol.edge_length:
            raise PatternError(f"edge is degenerate (length {e.length:.2e} m)",
                               panel=panel.name, edge=e.name)
    for e, nxt in zip(loop.edges, loop.edges[1:] + loop.edges[:1]):
        gap = float(np.linalg.norm(e.end - nxt.start))
        if gap > tol.merge:
            raise PatternError(f"open outline: loop '{loop.name}' ends at {e.end.tolist()} "
                               f"but the next edge '{nxt.name}' starts at "
                               f"{nxt.start.tolist()} ({gap * 1000:.3g} mm apart)",
                               panel=panel.name, edge=e.name)


def _within_extent(points, panel: str, *, what: str = "", edge: str | None = None) -> None:
    """``points`` (k, 2) [m] finite and within ``limits.extent`` of the origin, else a
    :class:`PatternError` naming the panel and the edge, or the mark ``what``."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if not np.isfinite(pts).all():
        raise PatternError(f"{what}coordinate is NaN or infinite", panel=panel, edge=edge)
    far = float(np.abs(pts).max(initial=0.0))
    if far > limits.extent:
        raise PatternError(f"{what}point {far:.3g} m from the origin, beyond the limit of "
                           f"{limits.extent:g} m", panel=panel, edge=edge)


def _check_marks(panel: Panel) -> None:
    """The marks drawn on the panel (internal lines, drill holes, cut line) finite and within
    ``limits.extent``, as its loops: a drill hole 1e7 m out was read and written to a DXF
    that the DXF reader then refused."""
    marks = [(f"line '{ln.name}'", ln.points) for ln in panel.lines]
    marks += [("drill hole", panel.drill_holes), ("cut line", panel.cut_line)]
    for what, points in marks:
        _within_extent(points, panel.name, what=f"{what}: ")


def check_panel(panel: Panel) -> None:
    """Raise :class:`PatternError` if ``panel`` cannot be meshed.

    Checked, in this order: unique edge names; a finite non-zero grainline; a finite
    placement; at most ``limits.segments_per_panel`` polyline
    segments; per loop, coordinates finite and within ``limits.extent``, no degenerate edge,
    closed; the marks' points (lines, drill holes, cut line) finite and within
    ``limits.extent``; then the loops' polylines (:func:`check_polygons`: no crossing,
    touching, overlap or spike, within a loop or between loops); an enclosed area; inner
    loops inside the outline and none inside another.
    """
    count = Counter(e.name for lp in panel.loops for e in lp.edges)
    dup = sorted(n for n, c in count.items() if c > 1)
    if dup:
        raise PatternError(f"edge name used twice: {dup}", panel=panel.name, edge=dup[0])
    if not all(np.isfinite(panel.grainline)) or np.linalg.norm(panel.grainline) == 0:
        raise PatternError("grainline is not a finite non-zero direction", panel=panel.name)
    pl = panel.placement
    for what, vec in (("translation", pl.translation), ("rotation", pl.rotation)):
        if vec is not None and not np.isfinite(vec).all():
            raise PatternError(f"placement {what} is NaN or infinite", panel=panel.name)
    segments = sum(1 if e.kind == "line" else SAMPLES for lp in panel.loops for e in lp.edges)
    if segments > limits.segments_per_panel:
        raise PatternError(f"the panel's loops make {segments} polyline segments, more than "
                           f"the limit of {limits.segments_per_panel}", panel=panel.name)
    for loop in panel.loops:
        _check_loop(panel, loop)
    _check_marks(panel)
    polys = [_loop_polyline(lp) for lp in panel.loops]
    check_polygons([p for p, _ in polys], [n for _, n in polys],
                   [lp.name for lp in panel.loops], panel=panel.name)
    for loop in panel.loops:
        if abs(loop.signed_area()) < tol.area:
            raise PatternError(f"loop '{loop.name}' encloses no area", panel=panel.name)
    if not panel.inner:
        return
    # the loops neither cross nor touch, so one point of each tells where it lies
    first = np.array([p[0] for p, _ in polys[1:]])
    outside = np.flatnonzero(~_inside(first, polys[0][0]))
    if len(outside):
        inner = panel.inner[int(outside[0])]
        raise PatternError(f"inner loop '{inner.name}' is not inside the outline",
                           panel=panel.name, edge=inner.edges[0].name)
    for k, (ring, _) in enumerate(polys[1:]):
        within = _inside(first, ring)
        within[k] = False
        if within.any():
            inner = panel.inner[int(np.argmax(within))]
            raise PatternError(f"inner loop '{inner.name}' lies inside inner loop "
                               f"'{panel.inner[k].name}'", panel=panel.name,
                               edge=inner.edges[0].name)


def seam_slack(la: float, lb: float) -> float:
    """How much two seam sides of lengths ``la`` and ``lb`` [m] may differ beyond their
    ease [m]: ``tol.seam_length`` or ``tol.seam_length_rel`` of their mean, whichever is
    larger."""
    return max(tol.seam_length, tol.seam_length_rel * 0.5 * (la + lb))


def measured_ease(la: float, lb: float) -> float:
    """The ease sides of lengths ``la`` and ``lb`` [m] need (longer / shorter - 1, rounded up
    to 1e-4), 0 when they are equal within :func:`seam_slack`; at most
    ``limits.seam_ease``. What a reader of another tool's seams states for them."""
    if not (math.isfinite(la) and math.isfinite(lb) and min(la, lb) > 0) or \
            abs(la - lb) <= seam_slack(la, lb):
        return 0.0
    return min(math.ceil((max(la, lb) / min(la, lb) - 1.0) * 1e4) / 1e4, limits.seam_ease)


def check_seams(pattern: Pattern, *, unequal: str = "error") -> list[str]:
    """Raise :class:`PatternError` for a seam naming a missing panel or edge, a bad range,
    overlapping seams on one edge, an ``ease`` that is not a number in [0,
    ``limits.seam_ease``], or two sides whose lengths differ beyond the seam's ease plus
    tolerance: the longer side may exceed the shorter by ``ease`` times the shorter plus
    ``tol.seam_length`` or ``tol.seam_length_rel`` of their mean, whichever is larger (a seam
    without ease: equal lengths within that tolerance). A side shorter than the ease allows
    is fine (the gather is at most ``ease``).

    With ``unequal="warn"`` (patterns from other tools, which gather or ease seams) sides
    that differ beyond that are allowed and returned as warnings instead.
    """
    if unequal not in ("error", "warn"):
        raise ValueError(f"unequal: expected 'error' or 'warn', got {unequal!r}")
    count = Counter(s.name for s in pattern.seams)
    dup = sorted(n for n, c in count.items() if c > 1)
    if dup:
        raise PatternError(f"seam name used twice: {dup}")
    panels = {p.name: p for p in pattern.panels}
    edges: dict[str, dict] = {}
    used: dict[tuple[str, str], list[tuple[float, float, str]]] = {}
    lengths = []
    for seam in pattern.seams:
        ease = seam.ease
        if (isinstance(ease, bool) or not isinstance(ease, (int, float))
                or not math.isfinite(ease) or ease < 0):
            raise PatternError(f"seam '{seam.name}': ease must be a number >= 0 (longer side "
                               f"/ shorter side - 1), got {ease!r}",
                               panel=seam.a.panel, edge=seam.a.edge)
        if ease > limits.seam_ease:
            raise PatternError(f"seam '{seam.name}': ease {ease:g} is beyond the limit of "
                               f"{limits.seam_ease:g} (a {1 + limits.seam_ease:g}:1 gather)",
                               panel=seam.a.panel, edge=seam.a.edge)
        for side in (seam.a, seam.b):
            panel = panels.get(side.panel)
            if panel is None:
                # no place: the panel it names is what is missing
                raise PatternError(f"seam '{seam.name}' names missing panel '{side.panel}'")
            if side.panel not in edges:
                edges[side.panel] = panel.edges()
            edge = edges[side.panel].get(side.edge)
            if edge is None:
                raise PatternError(f"seam '{seam.name}' names missing edge '{side.edge}'",
                                   panel=side.panel, edge=side.edge)
            if not (0.0 <= side.start < side.end <= 1.0):
                raise PatternError(f"seam '{seam.name}' has an invalid range "
                                   f"[{side.start}, {side.end}] (need 0 <= start < end <= 1)",
                                   panel=side.panel, edge=side.edge)
            used.setdefault((side.panel, side.edge), []).append(
                (side.start, side.end, seam.name))
            lengths.append(edge.sub_length(side.start, side.end))
    for (pname, ename), ranges in used.items():
        ranges.sort()
        reach, last = ranges[0][1], ranges[0][2]
        for s0, s1, name in ranges[1:]:
            if s0 < reach - tol.seam_range_overlap:
                raise PatternError(f"seams '{last}' and '{name}' overlap on the same edge",
                                   panel=pname, edge=ename)
            if s1 > reach:
                reach, last = s1, name
    warnings: list[str] = []
    for seam, la, lb in zip(pattern.seams, lengths[0::2], lengths[1::2]):
        slack = seam_slack(la, lb)
        allowed = seam.ease * min(la, lb) + slack
        if abs(la - lb) > allowed:
            ratio = max(la, lb) / min(la, lb)
            if not seam.ease:
                said = f"tolerance {slack * 1000:.1f} mm"
            elif seam.ease >= limits.seam_ease:
                # a reader gathers a file's unequal stitch by the ease its lengths need, at
                # most the limit: the file stated none, so "the stated 1" misled (audit 14)
                said = (f"a {ratio:.3g}:1 gather, beyond the limit of "
                        f"{1 + limits.seam_ease:g}:1")
            else:
                said = (f"ease {ratio - 1:.3g}, beyond the stated {seam.ease:g} (a "
                        f"difference of {allowed * 1000:.1f} mm allowed)")
            hint = "" if seam.ease else " (state the seam's ease to gather it)"
            err = PatternError(
                f"seam '{seam.name}' joins sides of different length: "
                f"{la * 100:.2f} cm ({seam.a.panel}/{seam.a.edge}) vs {lb * 100:.2f} cm "
                f"({seam.b.panel}/{seam.b.edge}); {said}{hint}",
                panel=seam.a.panel, edge=seam.a.edge)
            if unequal == "error":
                raise err
            warnings.append(err.reason)
    return warnings


def check_names(pattern: Pattern) -> None:
    """Raise :class:`PatternError` naming the place when a name of ``pattern`` (its own, a
    panel's, a loop's, an edge's, an inner line's, a seam's) holds a control character
    (:mod:`patternfit.text`: it would act on a terminal, and the mesh file joins edge names
    with one)."""
    def refuse(what: str, name: str, **where) -> None:
        at = control_at(name)
        if at is not None:
            raise PatternError(f"{what} name {name!r:.80} holds a control character "
                               f"({name[at]!r}, at {at})", **where)

    refuse("pattern", pattern.name)
    for panel in pattern.panels:
        refuse("panel", panel.name)
        for loop in panel.loops:
            refuse("loop", loop.name, panel=panel.name)
            for e in loop.edges:
                refuse("edge", e.name, panel=panel.name)
        for line in panel.lines:
            refuse("inner line", line.name, panel=panel.name)
    for seam in pattern.seams:
        refuse("seam", seam.name)


def check_anchor(pattern: Pattern) -> None:
    """Raise :class:`PatternError` when ``meta["anchor"]`` is given and is not one of
    :data:`~patternfit.pattern.model.ANCHORS`: a strapless top given ``"bust"`` was read as
    hung from the waist without a word, draped round the belly and passed."""
    meta = pattern.meta if isinstance(pattern.meta, dict) else {}
    if "anchor" in meta:
        anchor_value(meta["anchor"], "meta 'anchor'")


def anchor_value(value, where: str) -> str:
    """``value`` when it is one of :data:`~patternfit.pattern.model.ANCHORS`, else a
    :class:`PatternError` naming ``where`` it was given (``meta 'anchor'``, a DXF side file's
    or a GarmentCode file's key): a file's stated anchor is checked where it is read."""
    if value not in ANCHORS:
        raise PatternError(f"{where} {value!r:.40}: expected "
                           f"{' or '.join(repr(a) for a in ANCHORS)} (where the garment hangs "
                           "from; a garment held up elsewhere, such as a strapless top held "
                           "at the bust, is not supported), or leave it out to have it read "
                           "from the panels")
    return value


def check_pattern(pattern: Pattern) -> None:
    """Raise :class:`PatternError` if the pattern cannot be meshed and sewn: sizes within
    :data:`~patternfit.constants.limits` (:func:`check_size`), names without control
    characters (:func:`check_names`), a known anchor (:func:`check_anchor`), unique panel
    names, every panel (:func:`check_panel`), the seams (:func:`check_seams`)."""
    if not pattern.panels:
        raise PatternError(f"pattern '{pattern.name}' has no panels")
    check_anchor(pattern)
    check_size(len(pattern.panels), sum(len(lp.edges) for p in pattern.panels
                                        for lp in p.loops))
    check_names(pattern)
    count = Counter(p.name for p in pattern.panels)
    dup = sorted(n for n, c in count.items() if c > 1)
    if dup:
        raise PatternError(f"panel name used twice: {dup}", panel=dup[0])
    for panel in pattern.panels:
        check_panel(panel)
    check_seams(pattern)
