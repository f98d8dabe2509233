"""Pattern editing tools (paper Sec. 6.4): pure functions from a pattern to a new pattern.

Boundary tools move a corner, an edge or a curve control point, lengthen or shorten a panel,
or grade it; the internal tool inserts, moves and resizes darts. Every result is checked
(``check_pattern``): an edit that makes a loop cross itself is refused, and one that leaves a
seam's two sides of different length is refused unless ``partner=True``, which makes the
matching edit on the partner edge (its far corner slides along the edge until the lengths
agree). Offsets and lengths in metres, in the panel's flat frame.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..constants import tol
from ..pattern import Edge, Loop, Panel, Pattern, PatternError
from ..pattern.validate import check_pattern


def _vec(x, name: str) -> np.ndarray:
    v = np.asanyarray(x, dtype=np.float64)
    if v.shape != (2,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name}: expected a finite 2-vector [m], got {x!r}")
    return v


def _locate(panel: Panel, edge: str) -> tuple[int, int]:
    """(loop number, position in the loop) of edge ``edge``."""
    for li, loop in enumerate(panel.loops):
        for k, e in enumerate(loop.edges):
            if e.name == edge:
                return li, k
    raise PatternError(f"no edge '{edge}'", panel=panel.name, edge=edge)


def _with_loop(panel: Panel, li: int, loop: Loop) -> Panel:
    if li == 0:
        return replace(panel, outline=loop)
    inner = list(panel.inner)
    inner[li - 1] = loop
    return replace(panel, inner=tuple(inner))


def _move_end(edge: Edge, end: int, d: np.ndarray) -> Edge:
    """Move the first (``end=0``) or last (``end=-1``) point; the adjacent Bézier control
    follows so the curve keeps its shape near the other end."""
    p = np.array(edge.points)
    p[end] += d
    if edge.kind == "cubic":
        p[1 if end == 0 else -2] += d
    elif edge.kind == "quadratic":
        p[1] += 0.5 * d
    return edge.with_points(p)


def _move_corner(panel: Panel, edge: str, d: np.ndarray) -> Panel:
    """Move the corner where ``edge`` starts (and where its predecessor ends)."""
    li, k = _locate(panel, edge)
    edges = list(panel.loops[li].edges)
    edges[k] = _move_end(edges[k], 0, d)
    edges[k - 1] = _move_end(edges[k - 1], -1, d)
    return _with_loop(panel, li, replace(panel.loops[li], edges=tuple(edges)))


def _seams_on(pattern: Pattern, panel: str, edge: str):
    """(seam, this side, other side) for every seam on one edge."""
    for s in pattern.seams:
        for mine, other in ((s.a, s.b), (s.b, s.a)):
            if mine.panel == panel and mine.edge == edge:
                yield s, mine, other


def _match_partners(old: Pattern, new: Pattern, edited: set) -> Pattern:
    """Lengthen/shorten partner edges of seams whose edited side changed length.

    The partner's corner that is sewn to the edited side's moved end slides along the
    partner edge's end tangent until the lengths agree (a few secant steps).
    """
    for s in new.seams:
        for mine, other in ((s.a, s.b), (s.b, s.a)):
            if (mine.panel, mine.edge) not in edited or (other.panel, other.edge) in edited:
                continue
            want = new.seam_side_length(mine)
            if abs(want - new.seam_side_length(other)) <= tol.merge:
                continue
            if (mine.start, mine.end, other.start, other.end) != (0.0, 1.0, 0.0, 1.0):
                raise PatternError(f"seam '{s.name}' covers part of an edge: edit its partner "
                                   "by hand", panel=other.panel, edge=other.edge)
            e_old = old.panel(mine.panel).edge(mine.edge)
            e_new = new.panel(mine.panel).edge(mine.edge)
            start_moved = np.linalg.norm(e_new.start - e_old.start) > \
                np.linalg.norm(e_new.end - e_old.end)
            # sewn with reverse: start of one side meets end of the other
            free_start = start_moved != s.reverse
            new = _slide_end(new, other.panel, other.edge, want, at_start=free_start)
            edited.add((other.panel, other.edge))
    return new


def _slide_end(pattern: Pattern, panel: str, edge: str, length: float, *, at_start: bool):
    p = pattern.panel(panel)
    e = p.edge(edge)
    for _ in range(6):
        cur = e.length
        if abs(cur - length) <= 0.1 * tol.merge:
            break
        f = np.array([0.0, 1e-3]) if at_start else np.array([1.0, 1.0 - 1e-3])
        a, b = e.point_at(f)
        tangent = (a - b) / np.linalg.norm(a - b)  # pointing out of the edge
        li, k = _locate(p, edge)
        corner = edge if at_start else p.loops[li].edges[(k + 1) % len(p.loops[li].edges)].name
        p = _move_corner(p, corner, (length - cur) * tangent)
        e = p.edge(edge)
    return pattern.with_panel(p)


def _finish(old: Pattern, new: Pattern, edited: set, partner: bool) -> Pattern:
    """Check the result; with ``partner``, first make the matching partner edits."""
    if partner:
        new = _match_partners(old, new, set(edited))
    try:
        check_pattern(new)
    except PatternError as err:
        hint = ("" if partner or "different length" not in err.reason else
                " (edit the partner edge to match: partner=True, --partner on the "
                "command line)")
        raise PatternError(f"edit refused: {err.reason}{hint}", panel=err.panel,
                           edge=err.edge) from None
    return new


def _panel_edges(panel: Panel) -> set:
    return {(panel.name, e.name) for lp in panel.loops for e in lp.edges}


def move_point(pattern: Pattern, panel: str, corner: str, offset, *,
               partner: bool = False) -> Pattern:
    """Move the corner where edge ``corner`` starts by ``offset`` (2,) [m]."""
    p = _move_corner(pattern.panel(panel), corner, _vec(offset, "offset"))
    li, k = _locate(p, corner)
    prev = p.loops[li].edges[k - 1].name
    return _finish(pattern, pattern.with_panel(p), {(panel, corner), (panel, prev)}, partner)


def move_edge(pattern: Pattern, panel: str, edge: str, offset, *,
              partner: bool = False) -> Pattern:
    """Translate edge ``edge`` by ``offset`` (2,) [m]; its neighbours' ends follow."""
    d = _vec(offset, "offset")
    p = pattern.panel(panel)
    li, k = _locate(p, edge)
    edges = p.loops[li].edges
    p = _with_loop(p, li, replace(p.loops[li], edges=tuple(
        e.with_points(np.array(e.points) + d) if e.name == edge else e for e in edges)))
    p = _move_corner_neighbour(p, li, k, d)
    names = {(panel, edges[k - 1].name), (panel, edge), (panel, edges[(k + 1) % len(edges)].name)}
    return _finish(pattern, pattern.with_panel(p), names, partner)


def _move_corner_neighbour(p: Panel, li: int, k: int, d) -> Panel:
    edges = list(p.loops[li].edges)
    edges[k - 1] = _move_end(edges[k - 1], -1, d)
    n = (k + 1) % len(edges)
    edges[n] = _move_end(edges[n], 0, d)
    return _with_loop(p, li, replace(p.loops[li], edges=tuple(edges)))


def edit_curve(pattern: Pattern, panel: str, edge: str, offset, *, control: int = 1,
               partner: bool = False) -> Pattern:
    """Move Bézier control point ``control`` of ``edge`` by ``offset`` (2,) [m]; a straight
    edge becomes a quadratic Bézier whose control starts at the midpoint."""
    d = _vec(offset, "offset")
    p = pattern.panel(panel)
    e = p.edge(edge)
    if e.kind == "line":
        e = Edge.quadratic(e.name, e.start, 0.5 * (e.start + e.end), e.end)
    if e.kind == "arc":
        raise PatternError("an arc has no control points", panel=panel, edge=edge)
    if not 1 <= control <= len(e.points) - 2:
        raise ValueError(f"control: a {e.kind} edge has control points 1..{len(e.points) - 2}")
    pts = np.array(e.points)
    pts[control] += d
    return _finish(pattern, pattern.with_panel(p.with_edge(e.with_points(pts))),
                   {(panel, edge)}, partner)


def lengthen(pattern: Pattern, panel: str, a, b, amount: float, *,
             partner: bool = False) -> Pattern:
    """Lengthen (``amount`` > 0) or shorten the panel between points ``a`` and ``b`` (2,) [m].

    The panel is cut across the segment a–b at its midpoint; every outline point beyond the
    cut (on ``b``'s side) moves by ``amount`` along a→b, so edges crossing the cut stretch.
    """
    a, b = _vec(a, "a"), _vec(b, "b")
    if np.linalg.norm(b - a) <= tol.merge:
        raise ValueError("a, b: the two points coincide")
    if not np.isfinite(amount):
        raise ValueError("amount: must be finite [m]")
    u = (b - a) / np.linalg.norm(b - a)
    mid = 0.5 * (a + b)
    p = pattern.panel(panel)
    changed = set()

    def shift(e: Edge) -> Edge:
        pts = np.array(e.points)
        beyond = (pts - mid) @ u > 0
        if not beyond.any():
            return e
        changed.add((panel, e.name))
        pts[beyond] += amount * u
        return e.with_points(pts)

    p = replace(p, outline=replace(p.outline, edges=tuple(shift(e) for e in p.outline.edges)),
                inner=tuple(replace(lp, edges=tuple(shift(e) for e in lp.edges))
                            for lp in p.inner))
    return _finish(pattern, pattern.with_panel(p), changed, partner)


def grade(pattern: Pattern, panel: str | None, sx: float, sy: float, *, about=None,
          partner: bool = False) -> Pattern:
    """Scale one panel (or all, ``panel=None``) by ``sx``, ``sy`` about ``about`` (2,) [m]
    (default: each panel's outline centroid). Arcs allow only ``sx == sy``."""
    if not (np.isfinite(sx) and np.isfinite(sy) and sx > 0 and sy > 0):
        raise ValueError(f"sx, sy: must be positive, got {sx}, {sy}")
    m = np.diag([sx, sy])
    names = [panel] if panel is not None else [p.name for p in pattern.panels]
    new, changed = pattern, set()
    for name in names:
        p = new.panel(name)
        c = p.outline.polygon().mean(axis=0) if about is None else _vec(about, "about")
        try:
            p = replace(p, outline=_transform(p.outline, m, c),
                        inner=tuple(_transform(lp, m, c) for lp in p.inner))
        except ValueError as err:
            raise PatternError(f"grading refused: {err}", panel=name) from None
        new = new.with_panel(p)
        changed |= _panel_edges(p)
    return _finish(pattern, new, changed, partner)


def _transform(loop: Loop, m: np.ndarray, c: np.ndarray) -> Loop:
    return replace(loop, edges=tuple(e.transformed(m, c - m @ c) for e in loop.edges))
