"""Checks that a pattern can be meshed and sewn; each failure names panel and edge."""

from __future__ import annotations

import numpy as np

from ..constants import tol
from .errors import PatternError
from .model import Loop, Panel, Pattern

# Polyline samples per curved edge for the intersection tests.
_SAMPLES = 24


def _segments_cross(p: np.ndarray, q: np.ndarray, r: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Proper crossings of segments p-q against r-s, broadcast: bool array."""
    def orient(a, b, c):
        return ((b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1])
                - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0]))
    d1, d2 = orient(r, s, p), orient(r, s, q)
    d3, d4 = orient(p, q, r), orient(p, q, s)
    eps = tol.merge**2
    return (((d1 > eps) & (d2 < -eps)) | ((d1 < -eps) & (d2 > eps))) & \
           (((d3 > eps) & (d4 < -eps)) | ((d3 < -eps) & (d4 > eps)))


def _loop_segments(loop: Loop):
    """Segments (a, b) of a loop's polyline and the edge name of each."""
    pts, names = [], []
    for e in loop.edges:
        poly = e.polyline(None if e.kind == "line" else _SAMPLES)
        pts.append(poly[:-1])
        names += [e.name] * (len(poly) - 1)
    a = np.concatenate(pts)
    return a, np.roll(a, -1, axis=0), names


def _check_loop(panel: Panel, loop: Loop) -> None:
    if not loop.edges:
        raise PatternError(f"loop '{loop.name}' has no edges", panel=panel.name)
    for e in loop.edges:
        if not e.is_finite():
            raise PatternError("coordinate is NaN or infinite", panel=panel.name, edge=e.name)
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
    a, b, names = _loop_segments(loop)
    k = len(a)
    i, j = np.triu_indices(k, 2)
    keep = ~((i == 0) & (j == k - 1))  # first and last segments share a point
    i, j = i[keep], j[keep]
    hit = _segments_cross(a[i], b[i], a[j], b[j])
    if hit.any():
        n = int(np.argmax(hit))
        raise PatternError(f"self-intersecting outline: loop '{loop.name}' crosses itself "
                           f"(edge '{names[i[n]]}' crosses edge '{names[j[n]]}')",
                           panel=panel.name, edge=names[i[n]])
    if abs(loop.signed_area()) < tol.area:
        raise PatternError(f"loop '{loop.name}' encloses no area", panel=panel.name)


def _point_in_polygon(pts: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Even-odd test of points (q, 2) against a closed polygon (k, 2): bool (q,)."""
    x, y = pts[:, 0:1], pts[:, 1:2]
    x0, y0 = poly[:, 0], poly[:, 1]
    x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
    cond = (y0 > y) != (y1 > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xc = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
    return (np.sum(cond & (x < xc), axis=1) % 2) == 1


def check_panel(panel: Panel) -> None:
    """Raise :class:`PatternError` if ``panel`` cannot be meshed.

    Checked: finite coordinates, closed loops, no degenerate edges, no self-intersection,
    unique edge names, inner loops strictly inside the outline and apart from each other.
    """
    names = [e.name for lp in panel.loops for e in lp.edges]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise PatternError(f"edge name used twice: {sorted(dup)}", panel=panel.name,
                           edge=sorted(dup)[0])
    if not all(np.isfinite(panel.grainline)) or np.linalg.norm(panel.grainline) == 0:
        raise PatternError("grainline is not a finite non-zero direction", panel=panel.name)
    for loop in panel.loops:
        _check_loop(panel, loop)
    if not panel.inner:
        return
    outer = panel.outline.polygon(_SAMPLES)
    segs = [_loop_segments(lp) for lp in panel.loops]
    for n, inner in enumerate(panel.inner, start=1):
        poly = inner.polygon(_SAMPLES)
        if not _point_in_polygon(poly, outer).all():
            raise PatternError(f"inner loop '{inner.name}' is not inside the outline",
                               panel=panel.name, edge=inner.edges[0].name)
        for m in range(n):
            a1, b1, _ = segs[n]
            a2, b2, names2 = segs[m]
            hit = _segments_cross(a1[:, None], b1[:, None], a2[None], b2[None])
            if hit.any():
                raise PatternError(f"inner loop '{inner.name}' crosses loop "
                                   f"'{panel.loops[m].name}'", panel=panel.name,
                                   edge=names2[int(np.argwhere(hit)[0, 1])])


def check_seams(pattern: Pattern, *, unequal: str = "error") -> list[str]:
    """Raise :class:`PatternError` for a seam naming a missing panel or edge, a bad range,
    overlapping seams on one edge, or two sides whose lengths differ beyond tolerance
    (``tol.seam_length`` or ``tol.seam_length_rel`` of their mean, whichever is larger).

    With ``unequal="warn"`` (patterns from other tools, which gather or ease seams) sides of
    different length are allowed and returned as warnings instead.
    """
    if unequal not in ("error", "warn"):
        raise ValueError(f"unequal: expected 'error' or 'warn', got {unequal!r}")
    warnings: list[str] = []
    names = [s.name for s in pattern.seams]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise PatternError(f"seam name used twice: {sorted(dup)}")
    used: dict[tuple[str, str], list[tuple[float, float, str]]] = {}
    for seam in pattern.seams:
        lengths = []
        for side in (seam.a, seam.b):
            try:
                panel = pattern.panel(side.panel)
            except KeyError:
                raise PatternError(f"seam '{seam.name}' names missing panel '{side.panel}'",
                                   panel=side.panel) from None
            if side.edge not in panel.edges():
                raise PatternError(f"seam '{seam.name}' names missing edge '{side.edge}'",
                                   panel=side.panel, edge=side.edge)
            if not (0.0 <= side.start < side.end <= 1.0):
                raise PatternError(f"seam '{seam.name}' has an invalid range "
                                   f"[{side.start}, {side.end}] (need 0 <= start < end <= 1)",
                                   panel=side.panel, edge=side.edge)
            for s0, s1, other in used.get((side.panel, side.edge), []):
                if side.start < s1 - 1e-9 and s0 < side.end - 1e-9:
                    raise PatternError(f"seams '{other}' and '{seam.name}' overlap on the "
                                       "same edge", panel=side.panel, edge=side.edge)
            used.setdefault((side.panel, side.edge), []).append(
                (side.start, side.end, seam.name))
            lengths.append(pattern.seam_side_length(side))
        la, lb = lengths
        allowed = max(tol.seam_length, tol.seam_length_rel * 0.5 * (la + lb))
        if abs(la - lb) > allowed:
            err = PatternError(
                f"seam '{seam.name}' joins sides of different length: "
                f"{la * 100:.2f} cm ({seam.a.panel}/{seam.a.edge}) vs {lb * 100:.2f} cm "
                f"({seam.b.panel}/{seam.b.edge}); tolerance {allowed * 1000:.1f} mm",
                panel=seam.a.panel, edge=seam.a.edge)
            if unequal == "error":
                raise err
            warnings.append(err.reason)
    return warnings


def check_pattern(pattern: Pattern) -> None:
    """Raise :class:`PatternError` if the pattern cannot be meshed and sewn."""
    if not pattern.panels:
        raise PatternError(f"pattern '{pattern.name}' has no panels")
    names = [p.name for p in pattern.panels]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise PatternError(f"panel name used twice: {sorted(dup)}", panel=sorted(dup)[0])
    for panel in pattern.panels:
        check_panel(panel)
    check_seams(pattern)
