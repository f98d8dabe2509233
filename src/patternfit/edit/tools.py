"""Pattern editing tools (paper Sec. 6.4): pure functions from a pattern to a new pattern.

Boundary tools move a corner, an edge or a curve control point, lengthen or shorten a panel,
or grade it; the internal tool inserts, moves and resizes darts. Arguments are checked
before any geometry is computed (finite, offsets within twice ``limits.extent``, scales
within ``limits.edit_scale`` and its inverse), and every result is checked: a panel beyond
``limits.extent``, turned inside out, collapsed or crossing itself is refused, and so is a
seam whose two sides differ in length unless ``partner=True``, which makes the matching
edit on the partner edge (its far corner slides along the edge until the lengths agree, or
for a seam with ``ease`` until they are in the ratio they had before the edit).
Refusals are :class:`PatternError` naming the panel and the argument. Offsets and lengths
in metres, in the panel's flat frame.
"""

from __future__ import annotations

import functools
from dataclasses import replace

import numpy as np

from ..arguments import array, instance
from ..constants import limits, tol
from ..pattern import Edge, Loop, Panel, Pattern, PatternError
from ..pattern.validate import check_panel, check_seams


#: the largest move an edit may ask for, per coordinate [m]: any two points of a pattern
#: within ``limits.extent`` of the origin are at most this far apart
REACH = 2.0 * limits.extent


def pattern_edit(edit):
    """Mark ``edit`` as a public edit: its first argument must be a :class:`Pattern` (a
    ``ValueError`` naming ``pattern``, not an AttributeError from inside the edit)."""
    @functools.wraps(edit)
    def checked(pattern, *args, **kwargs):
        instance(pattern, Pattern, "pattern", "a Pattern")
        return edit(pattern, *args, **kwargs)
    return checked


def _arg(x, name: str, panel: str | None, *, lo: float = -REACH, hi: float = REACH,
         vector: bool = False, unit: str = "m"):
    """Check one edit argument (:func:`patternfit.arguments.array`): ``x`` as a float, or
    (``vector``) as a (2,) float array, each value finite and within [``lo``, ``hi``]
    [``unit``]; anything else (a scale of 1e300, an offset of 1e30, NaN) is refused with a
    :class:`PatternError` naming ``panel`` and the argument ``name`` before any geometry is
    computed with it."""
    try:
        v = array(x, name, shape=(2,) if vector else (), low=lo, high=hi, unit=unit,
                  what="a 2-vector 'x,y'" if vector else "a number")
    except ValueError as err:
        raise PatternError(str(err), panel=panel) from None
    return v if vector else float(v)


def _panel(pattern: Pattern, name: str) -> Panel:
    """The panel called ``name``; a :class:`PatternError` listing the panels otherwise."""
    for p in pattern.panels:
        if p.name == name:
            return p
    raise PatternError(f"no such panel (panels: {', '.join(p.name for p in pattern.panels)})",
                       panel=name)


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


def move_corner(panel: Panel, edge: str, offset) -> Panel:
    """``panel`` with the corner where edge ``edge`` starts (and its predecessor ends) moved
    by ``offset`` (2,) [m]; the adjacent Bézier controls follow. Unchecked: the building
    block of :func:`move_point` and of the automatic correction, whose callers check the
    result (``check_pattern``)."""
    d = np.asarray(offset, dtype=np.float64)
    li, k = panel.locate(edge)
    edges = list(panel.loops[li].edges)
    edges[k] = _move_end(edges[k], 0, d)
    edges[k - 1] = _move_end(edges[k - 1], -1, d)
    return _with_loop(panel, li, replace(panel.loops[li], edges=tuple(edges)))


def _edge_corner(panel: Panel, edge: str, at_start: bool) -> tuple[str, str]:
    """(panel, name of the edge that starts there): the start or the end corner of
    ``edge``."""
    li, k = panel.locate(edge)
    edges = panel.loops[li].edges
    return panel.name, edge if at_start else edges[(k + 1) % len(edges)].name


def _corner_edges(pattern: Pattern, corner: tuple[str, str]) -> set:
    """The two edges (panel, edge) that meet at ``corner``."""
    p = pattern.panel(corner[0])
    li, k = p.locate(corner[1])
    return {(p.name, corner[1]), (p.name, p.loops[li].edges[k - 1].name)}


def _sewn_ends(pattern: Pattern, seam) -> list[tuple[tuple[str, str], tuple[str, str]]]:
    """The corners that ``seam`` sews together, as pairs of (panel, edge starting there):
    with ``reverse`` the start of side ``a`` meets the end of side ``b`` (and the end of
    ``a`` the start of ``b``), without it start meets start. Only a side covering its whole
    edge has its corners at the seam's ends."""
    a, b = seam.a, seam.b
    if (a.start, a.end, b.start, b.end) != (0.0, 1.0, 0.0, 1.0):
        return []
    pa, pb = pattern.panel(a.panel), pattern.panel(b.panel)
    return [(_edge_corner(pa, a.edge, True), _edge_corner(pb, b.edge, not seam.reverse)),
            (_edge_corner(pa, a.edge, False), _edge_corner(pb, b.edge, seam.reverse))]


def _match_partners(old: Pattern, new: Pattern, edited: set) -> Pattern:
    """Make the partner edges of the seams whose edited side changed length match again.

    For each such seam the partner's corner that is sewn to the edited side's moved end (the
    end that moved most; ``Seam.reverse`` says which end of the partner that is) is free to
    move, and so is every corner sewn to that one in turn (the four panels meeting at a
    crotch point), unless it is a corner of an edited edge. The free corners move together (:func:`_solve_corners`) until every seam
    touching them has equal sides: a corner on one seam slides along its edge, a corner
    shared by two seams (the underarm point between side and underarm seams) is fixed by
    both.
    """
    links: dict = {}
    for s in new.seams:
        for c1, c2 in _sewn_ends(new, s):
            links.setdefault(c1, set()).add(c2)
            links.setdefault(c2, set()).add(c1)
    free: list[tuple[str, str]] = []
    for s in new.seams:
        for mine, other in ((s.a, s.b), (s.b, s.a)):
            if (mine.panel, mine.edge) not in edited or (other.panel, other.edge) in edited:
                continue
            if abs(_misfit(new, s, _ratio(s, new, old))) <= tol.merge:
                continue
            if (mine.start, mine.end, other.start, other.end) != (0.0, 1.0, 0.0, 1.0):
                raise PatternError(f"seam '{s.name}' covers part of an edge: edit its partner "
                                   "by hand", panel=other.panel, edge=other.edge)
            e_old = old.panel(mine.panel).edge(mine.edge)
            e_new = new.panel(mine.panel).edge(mine.edge)
            d_start = np.linalg.norm(e_new.start - e_old.start)
            d_end = np.linalg.norm(e_new.end - e_old.end)
            # sewn with reverse: the start of one side meets the end of the other
            at_start = (d_start > d_end) != s.reverse
            ends = [_edge_corner(new.panel(other.panel), other.edge, at_start),
                    _edge_corner(new.panel(other.panel), other.edge, not at_start)]
            # a corner of the edit itself stays where the edit put it: then the other end
            open_ends = [c for c in ends if not _corner_edges(new, c) & edited]
            if abs(d_start - d_end) <= tol.merge and open_ends:
                # both ends moved alike (a grade about the panel's centre): which one moved
                # "most" is a rounding accident that differs between mirror-image seams and
                # made the result lopsided; both are free and share the change
                seeds = open_ends
            else:
                seeds = open_ends[:1] or ends[:1]
            todo = list(seeds)
            while todo:
                c = todo.pop()
                if c in free or (c not in seeds and _corner_edges(new, c) & edited):
                    continue
                free.append(c)
                todo.extend(links.get(c, ()))
    return _solve_corners(new, free, old) if free else new


def _solve_corners(pattern: Pattern, free: list, before: Pattern, *,
                   iterations: int = 20) -> Pattern:
    """``pattern`` with the corners ``free`` ((panel, edge starting there)) moved by the
    smallest steps that make every seam touching them have sides of equal length (of the
    ratio they had in ``before``, for a seam with ease), each step halved until it reduces
    the differences (:func:`_equal_sides`)."""
    touched = set().union(*(_corner_edges(pattern, c) for c in free))
    seams = [s for s in pattern.seams
             if (s.a.panel, s.a.edge) in touched or (s.b.panel, s.b.edge) in touched]
    return _equal_sides(pattern, free, seams, [_ratio(s, pattern, before) for s in seams],
                        iterations=iterations, h=1e-7, halvings=8)


def _ratio(seam, pattern: Pattern, before: Pattern | None) -> float:
    """The length ratio (side ``b`` / side ``a``) an edit keeps on ``seam`` of
    ``pattern``: 1 without ease; with ease, the ratio the seam had in ``before`` (the
    pattern before the edit) within its ease, else the full ease ``1 + ease``, the longer
    side being the one that is longer now."""
    if not seam.ease:
        return 1.0
    top = 1.0 + seam.ease
    was = next((s for s in (before.seams if before is not None else ())
                if s.name == seam.name), None)
    if was is not None:
        return float(np.clip(before.seam_side_length(was.b) / before.seam_side_length(was.a),
                             1.0 / top, top))
    longer_b = pattern.seam_side_length(seam.b) >= pattern.seam_side_length(seam.a)
    return top if longer_b else 1.0 / top


def _misfit(pattern: Pattern, seam, ratio: float) -> float:
    """How much longer side ``b`` of ``seam`` is than ``ratio`` times side ``a`` [m]."""
    return pattern.seam_side_length(seam.b) - ratio * pattern.seam_side_length(seam.a)


def _equal_sides(pattern: Pattern, corners: list, seams, ratios, *, iterations: int,
                 h: float, halvings: int) -> Pattern:
    """``pattern`` with the ``corners`` ((panel, edge starting there)) moved so that every
    one of ``seams`` has side ``b`` ``ratios`` (one per seam) times as long as side ``a``:
    Gauss–Newton with minimum-norm steps on the length misfits [m], the Jacobian by finite
    differences of step ``h`` [m], each step halved up to ``halvings`` times until it
    reduces the misfits."""
    def moved(x):
        out = pattern
        for (pname, ename), d in zip(corners, x.reshape(-1, 2)):
            if d.any():
                out = out.with_panel(move_corner(out.panel(pname), ename, d))
        return out

    def residual(x):
        pat = moved(x)
        return np.array([_misfit(pat, s, q) for s, q in zip(seams, ratios)])

    x = np.zeros(2 * len(corners))
    r = residual(x)
    for _ in range(iterations):
        if np.abs(r).max(initial=0.0) <= 0.1 * tol.merge:
            break
        J = np.empty((len(r), len(x)))
        for j in range(len(x)):
            e = np.zeros_like(x)
            e[j] = h
            J[:, j] = (residual(x + e) - r) / h
        step = np.linalg.lstsq(J, r, rcond=None)[0]
        r_try = residual(x - step)
        for _ in range(halvings):
            if np.linalg.norm(r_try) < np.linalg.norm(r):
                break
            step = 0.5 * step
            r_try = residual(x - step)
        x, r = x - step, r_try
    return moved(x)


def _said(name: str, value, unit: str = "m") -> str:
    """``name=value unit`` for a message, a 2-vector as ``(x, y)``."""
    v = np.atleast_1d(np.asarray(value, dtype=np.float64))
    text = f"{v[0]:g}" if v.size == 1 else "(" + ", ".join(f"{c:g}" for c in v) + ")"
    return f"{name}={text}{' ' + unit if unit else ''}"


def _check_result(old: Pattern, new: Pattern) -> None:
    """Refuse a result that is no garment. For each panel the edit changed, in the order
    that names the cause rather than a symptom: a coordinate (of the outline or a curve's
    control point) that is not finite or lies beyond ``limits.extent``; what ``check_panel`` refuses (a loop crossing itself, a
    degenerate edge); a loop turned inside out (its signed area changes sign) or collapsed
    to less than ``1 / limits.edit_scale**2`` of its area (more than the strongest grading
    shrinks it). Then the seams of the whole pattern (``check_seams``). The panels the edit
    left alone are not checked again."""
    before = {p.name: p for p in old.panels}
    for p in new.panels:
        was = before[p.name]
        if was is p:
            continue
        for lp in p.loops:
            # Bézier controls as well as the curve: a reader refuses either beyond the extent
            pts = np.concatenate([lp.polygon(), *(np.asarray(e.points) for e in lp.edges)])
            if not np.isfinite(pts).all():
                raise PatternError(f"loop '{lp.name}' has a NaN or infinite coordinate",
                                   panel=p.name)
            reach = float(np.abs(pts).max())
            if reach > limits.extent:
                raise PatternError(f"loop '{lp.name}' reaches {reach:.3g} m from the origin, "
                                   f"beyond the limit of {limits.extent:g} m", panel=p.name)
        check_panel(p)
        loops = {lp.name: lp for lp in was.loops}
        for lp in p.loops:
            if lp.name not in loops:
                continue
            a0, a1 = loops[lp.name].signed_area(), lp.signed_area()
            if a0 * a1 < 0:
                raise PatternError(f"loop '{lp.name}' is turned inside out (its signed area "
                                   f"goes from {a0:.4g} to {a1:.4g} m²)", panel=p.name)
            # the slack lets the strongest allowed grading through despite rounding
            if abs(a1) * limits.edit_scale ** 2 < abs(a0) * (1.0 - 1e-9):
                raise PatternError(f"loop '{lp.name}' collapses (area {abs(a0):.4g} → "
                                   f"{abs(a1):.3g} m²)", panel=p.name)
    check_seams(new)


def _marks_mapped(panel: Panel, f) -> Panel:
    """``panel`` with what is drawn on it (cut line, internal lines, drill holes) mapped by
    ``f`` ((k, 2) -> (k, 2) points [m]), the map its outline went through."""
    def pts(points):
        return f(np.asarray(points, dtype=np.float64).reshape(-1, 2))
    return replace(panel, cut_line=pts(panel.cut_line), drill_holes=pts(panel.drill_holes),
                   lines=tuple(replace(ln, points=pts(ln.points)) for ln in panel.lines))


def _without_stale_cut_lines(old: Pattern, new: Pattern) -> Pattern:
    """``new`` without the cut line of each panel whose outline (the sew line) an edit
    moved while leaving its cut line where it was (a local edit: the seam allowance between
    them would be wrong), each named in ``meta["warnings"]``. A grade or a lengthening
    maps the cut line with the outline and keeps it; internal lines and drill holes stay
    where they are drawn."""
    before = {p.name: p for p in old.panels}
    dropped = []
    for p in new.panels:
        was = before.get(p.name)
        if was is None or p.outline is was.outline or not p.cut_line \
                or p.cut_line != was.cut_line:
            continue
        new = new.with_panel(replace(p, cut_line=()))
        dropped.append(f"panel '{p.name}': its cut line was dropped, the edit moved its sew "
                       "line (outline) but not the cut line; add the seam allowance again")
    if not dropped:
        return new
    return replace(new, meta={**new.meta,
                              "warnings": [*new.meta.get("warnings", ()), *dropped]})


def _finish(old: Pattern, new: Pattern, edited: set, partner: bool, cause: str) -> Pattern:
    """Check the result of the edit ``cause`` (its arguments, for the message); with
    ``partner``, first make the matching partner edits. A panel's cut line left behind by
    the edit is dropped (:func:`_without_stale_cut_lines`)."""
    if partner:
        new = _match_partners(old, new, set(edited))
    new = _without_stale_cut_lines(old, new)
    try:
        _check_result(old, new)
    except PatternError as err:
        hint = ("" if partner or "different length" not in err.reason else
                " (edit the partner edge to match: partner=True, --partner on the "
                "command line)")
        raise PatternError(f"edit refused ({cause}): {err.reason}{hint}", panel=err.panel,
                           edge=err.edge) from None
    return new


@pattern_edit
def close_seams(pattern: Pattern, *, like: Pattern | None = None,
                iterations: int = 12) -> Pattern:
    """Make every seam's two sides equally long by the smallest moves (least squares) of
    the corners at the ends of each seam's side ``b``: Gauss–Newton with minimum-norm
    steps on the length misfits [m], Jacobian by finite differences.

    A seam with ``ease`` keeps its gather instead: its sides get the length ratio they have
    in ``like`` (the pattern before the moves, within the ease), or without ``like`` the
    full stated ratio ``1 + ease`` (the longer side the one that is longer now). With
    ``like``, a panel whose outline moved keeps no cut line of ``like``'s
    (:func:`_without_stale_cut_lines`)."""
    corners = []
    for s in pattern.seams:
        p = pattern.panel(s.b.panel)
        li, k = p.locate(s.b.edge)
        edges = p.loops[li].edges
        for key in ((s.b.panel, s.b.edge), (s.b.panel, edges[(k + 1) % len(edges)].name)):
            if key not in corners:
                corners.append(key)
    ratios = [_ratio(s, pattern, like) for s in pattern.seams]
    out = _equal_sides(pattern, corners, pattern.seams, ratios, iterations=iterations,
                       h=1e-5, halvings=0)
    return out if like is None else _without_stale_cut_lines(like, out)


def _panel_edges(panel: Panel) -> set:
    return {(panel.name, e.name) for lp in panel.loops for e in lp.edges}


@pattern_edit
def move_point(pattern: Pattern, panel: str, corner: str, offset, *,
               partner: bool = False) -> Pattern:
    """Move the corner where edge ``corner`` starts by ``offset`` (2,) [m]."""
    d = _arg(offset, "offset", panel, vector=True)
    p = move_corner(_panel(pattern, panel), corner, d)
    li, k = p.locate(corner)
    prev = p.loops[li].edges[k - 1].name
    return _finish(pattern, pattern.with_panel(p), {(panel, corner), (panel, prev)}, partner,
                   _said("offset", d))


@pattern_edit
def move_edge(pattern: Pattern, panel: str, edge: str, offset, *,
              partner: bool = False) -> Pattern:
    """Translate edge ``edge`` by ``offset`` (2,) [m]; its neighbours' ends follow."""
    d = _arg(offset, "offset", panel, vector=True)
    p = _panel(pattern, panel)
    li, k = p.locate(edge)
    edges = p.loops[li].edges
    p = _with_loop(p, li, replace(p.loops[li], edges=tuple(
        e.with_points(np.array(e.points) + d) if e.name == edge else e for e in edges)))
    p = _move_corner_neighbour(p, li, k, d)
    names = {(panel, edges[k - 1].name), (panel, edge), (panel, edges[(k + 1) % len(edges)].name)}
    return _finish(pattern, pattern.with_panel(p), names, partner, _said("offset", d))


def _move_corner_neighbour(p: Panel, li: int, k: int, d) -> Panel:
    edges = list(p.loops[li].edges)
    edges[k - 1] = _move_end(edges[k - 1], -1, d)
    n = (k + 1) % len(edges)
    edges[n] = _move_end(edges[n], 0, d)
    return _with_loop(p, li, replace(p.loops[li], edges=tuple(edges)))


@pattern_edit
def edit_curve(pattern: Pattern, panel: str, edge: str, offset, *, control: int = 1,
               partner: bool = False) -> Pattern:
    """Move Bézier control point ``control`` of ``edge`` by ``offset`` (2,) [m]; a straight
    edge becomes a quadratic Bézier whose control starts at the midpoint."""
    d = _arg(offset, "offset", panel, vector=True)
    p = _panel(pattern, panel)
    li, k = p.locate(edge)
    e = p.loops[li].edges[k]
    if e.kind == "line":
        e = Edge.quadratic(e.name, e.start, 0.5 * (e.start + e.end), e.end)
    if e.kind == "arc":
        raise PatternError("an arc has no control points", panel=panel, edge=edge)
    if not 1 <= control <= len(e.points) - 2:
        raise PatternError(f"control: a {e.kind} edge has control points "
                           f"1..{len(e.points) - 2}, got {control!r}", panel=panel, edge=edge)
    pts = np.array(e.points)
    pts[control] += d
    return _finish(pattern, pattern.with_panel(p.with_edge(e.with_points(pts))),
                   {(panel, edge)}, partner, _said("offset", d))


@pattern_edit
def lengthen(pattern: Pattern, panel: str, a, b, amount: float, *,
             partner: bool = False) -> Pattern:
    """Lengthen (``amount`` > 0) or shorten the panel between points ``a`` and ``b`` (2,) [m].

    The panel is cut across the segment a–b at its midpoint; every outline point beyond the
    cut (on ``b``'s side) moves by ``amount`` along a→b, so edges crossing the cut stretch;
    so do the points of the panel's cut line, internal lines and drill holes beyond it.
    """
    a = _arg(a, "a", panel, lo=-limits.extent, hi=limits.extent, vector=True)
    b = _arg(b, "b", panel, lo=-limits.extent, hi=limits.extent, vector=True)
    amount = _arg(amount, "amount", panel)
    if np.linalg.norm(b - a) <= tol.merge:
        raise PatternError("a, b: the two points coincide", panel=panel)
    u = (b - a) / np.linalg.norm(b - a)
    mid = 0.5 * (a + b)
    p = _panel(pattern, panel)
    changed = set()

    def moved(pts: np.ndarray) -> np.ndarray:
        pts = np.array(pts)
        pts[(pts - mid) @ u > 0] += amount * u
        return pts

    def shift(e: Edge) -> Edge:
        pts = moved(e.points)
        if np.array_equal(pts, e.points):
            return e
        changed.add((panel, e.name))
        return e.with_points(pts)

    p = replace(p, outline=replace(p.outline, edges=tuple(shift(e) for e in p.outline.edges)),
                inner=tuple(replace(lp, edges=tuple(shift(e) for e in lp.edges))
                            for lp in p.inner))
    p = _marks_mapped(p, moved)
    return _finish(pattern, pattern.with_panel(p), changed, partner, _said("amount", amount))


@pattern_edit
def grade(pattern: Pattern, panel: str | None, sx: float, sy: float, *, about=None,
          partner: bool = False) -> Pattern:
    """Scale one panel (or all, ``panel=None``) by ``sx``, ``sy`` about ``about`` (2,) [m]
    (default: each panel's outline centroid). Each factor lies within ``limits.edit_scale``
    and its inverse; arcs allow only ``sx == sy``. The panel's cut line, internal lines and
    drill holes are scaled with it."""
    sx, sy = (_arg(s, n, panel, lo=1.0 / limits.edit_scale, hi=limits.edit_scale, unit="")
              for s, n in ((sx, "sx"), (sy, "sy")))
    if about is not None:
        about = _arg(about, "about", panel, lo=-limits.extent, hi=limits.extent, vector=True)
    m = np.diag([sx, sy])
    names = [panel] if panel is not None else [p.name for p in pattern.panels]
    new, changed = pattern, set()
    for name in names:
        p = _panel(new, name)
        c = p.outline.polygon().mean(axis=0) if about is None else about
        try:
            p = replace(p, outline=_transform(p.outline, m, c),
                        inner=tuple(_transform(lp, m, c) for lp in p.inner))
            p = _marks_mapped(p, lambda q: q @ m.T + (c - m @ c))
        except ValueError as err:
            raise PatternError(f"grading refused: {err}", panel=name) from None
        new = new.with_panel(p)
        changed |= _panel_edges(p)
    return _finish(pattern, new, changed, partner,
                   f"{_said('sx', sx, '')}, {_said('sy', sy, '')}")


def _transform(loop: Loop, m: np.ndarray, c: np.ndarray) -> Loop:
    return replace(loop, edges=tuple(e.transformed(m, c - m @ c) for e in loop.edges))
