"""DXF entities as point lists: lines, polylines, arcs, splines flattened to (k, 2) points
[m], repeated points dropped, open pieces chained into closed loops.

Every coordinate is checked (finite, within ``limits.extent``) before a curve is sampled, and
a piece's points are capped (``limits.segments_per_panel``), so a hostile file cannot ask for
unbounded work.
"""

from __future__ import annotations

from itertools import islice

import numpy as np
from ezdxf import path as dxfpath

from ..constants import limits, tol
from .dxf_curves import dedupe
from .errors import PatternError

__all__ = ["LINE_KINDS", "closed_loops", "entity_name", "entity_points", "layer_of", "why",
           "within_extent"]

#: the entities that draw a line (the others are points and text)
LINE_KINDS = ("LINE", "POLYLINE", "LWPOLYLINE", "ARC", "CIRCLE", "SPLINE", "ELLIPSE")


def layer_of(entity) -> int | None:
    name = str(entity.dxf.get("layer", "")).strip()
    return int(name) if name.isdigit() else None


def why(exc: Exception) -> str:
    """An exception from ezdxf as message text, its kind named once."""
    text, kind = str(exc), type(exc).__name__
    return text if text.startswith(kind) else f"{kind}: {text}"


def entity_name(entity) -> str:
    return f"{entity.dxftype()} entity (handle {entity.dxf.get('handle', '?')})"


def within_extent(pts: np.ndarray, entity, where: dict) -> np.ndarray:
    """``pts`` (k, 2) [m], refused when a point is not finite or lies beyond
    ``limits.extent``: checked on a curve's control points, before it is sampled."""
    if len(pts) and not np.isfinite(pts).all():
        raise PatternError(f"{entity_name(entity)} has a coordinate that is NaN or infinite",
                           **where)
    far = float(np.max(np.abs(pts))) if len(pts) else 0.0
    if far > limits.extent:
        raise PatternError(f"{entity_name(entity)} reaches {far:.3g} m from the origin, "
                           f"beyond the limit of {limits.extent:g} m", **where)
    return pts


def entity_points(entity, scale: float, budget: int, where: dict
                   ) -> tuple[np.ndarray, bool] | None:
    """Points [m] of a curve entity and whether it is closed; None for other entities.

    At most ``budget`` points: more (a curve of very many segments) is refused, as is
    geometry beyond ``limits.extent``, before sampling. Repeated points are dropped.
    """
    kind = entity.dxftype()
    if kind == "LINE":
        pts = np.array([tuple(entity.dxf.start)[:2], tuple(entity.dxf.end)[:2]]) * scale
        return within_extent(pts, entity, where), False
    if kind not in LINE_KINDS:
        return None
    try:
        pth = dxfpath.make_path(entity)
    except (TypeError, ValueError):
        return None
    control = np.array([(v.x, v.y) for v in pth.control_vertices()]).reshape(-1, 2)
    within_extent(control * scale, entity, where)
    if any(cmd.type != dxfpath.Command.LINE_TO for cmd in pth.commands()):
        flat = islice(pth.flattening(tol.dxf_sample / scale / 4), budget + 1)
        pts = np.array([(v.x, v.y) for v in flat]).reshape(-1, 2) * scale
    else:
        pts = control * scale
    if len(pts) > budget:
        raise PatternError(f"{entity_name(entity)}: the piece's curves make more than "
                           f"{limits.segments_per_panel} points (the segment limit)", **where)
    # CAD tools repeat every turn point (Gerber) and round them (inch files): a segment
    # shorter than tol.dxf_repeat has no direction to fit
    pts = dedupe(pts, closed=False)
    if len(pts) < 2:
        return None
    ends_meet = np.linalg.norm(pts[0] - pts[-1]) < tol.dxf_repeat
    closed = bool(getattr(entity, "is_closed", False)) or kind == "CIRCLE" or ends_meet
    if closed:
        pts = dedupe(pts, closed=True)
    return pts, closed


def _clusters(points: np.ndarray) -> np.ndarray:
    """A cluster number for each point (n, 2) [m]: points within ``tol.dxf_repeat`` of each other
    (and some up to three times that) share one. Linear time, however many coincide."""
    cells = np.floor(points / tol.dxf_repeat).astype(np.int64)
    keys, index = np.unique(cells, axis=0, return_inverse=True)
    index = index.reshape(-1)
    parent = list(range(len(keys)))

    def root(k):
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    where = {tuple(k): n for n, k in enumerate(keys.tolist())}
    for n, (x, y) in enumerate(keys.tolist()):
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                m = where.get((x + dx, y + dy))
                if m is not None:
                    parent[root(m)] = root(n)
    return np.array([root(k) for k in index], dtype=np.int64)


def _chain(pieces: list[tuple[np.ndarray, bool]]
           ) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Closed loops from closed entities and from open ones joined end to end; and the
    chains that did not close.

    Open pieces are taken in file order; each grows at its end by the first free piece
    (in file order) that starts or ends there, until it closes or nothing fits.
    """
    loops = [p for p, closed in pieces if closed and len(p) >= 3]
    open_ = [p for p, closed in pieces if not closed]
    ends: list[np.ndarray] = []
    if not open_:
        return loops, ends
    node = _clusters(np.array([[p[0], p[-1]] for p in open_]).reshape(-1, 2))
    at: dict[int, list[int]] = {}  # cluster -> piece ends there (2k: start, 2k + 1: end)
    for end, c in enumerate(node.tolist()):
        at.setdefault(c, []).append(end)
    head = dict.fromkeys(at, 0)
    free = [True] * len(open_)

    def first_free(c: int) -> int | None:
        ends, h = at[c], head[c]
        while h < len(ends) and not free[ends[h] // 2]:
            h += 1
        head[c] = h
        return ends[h] if h < len(ends) else None

    for k, piece in enumerate(open_):
        if not free[k]:
            continue
        free[k] = False
        parts, start, tip, count = [piece], node[2 * k], node[2 * k + 1], len(piece)
        while True:
            if start == tip and count > 3:
                loops.append(np.concatenate(parts)[:-1])
                break
            end = first_free(int(tip))
            if end is None:
                ends.append(np.concatenate(parts))
                break
            q = open_[end // 2]
            free[end // 2] = False
            parts.append(q[1:] if end % 2 == 0 else q[::-1][1:])
            tip = node[end + 1] if end % 2 == 0 else node[end - 1]
            count += len(q) - 1
    return loops, ends


def _on_line(p: np.ndarray, line: np.ndarray) -> bool:
    """Whether the point ``p`` (2,) [m] lies on the straight line through ``line`` (2, 2)."""
    d = line[1] - line[0]
    n = float(np.linalg.norm(d))
    if n < tol.dxf_fit:
        return False
    q = p - line[0]
    return abs(float(d[0] * q[1] - d[1] * q[0])) / n < tol.dxf_fit


def closed_loops(pieces, folds=()) -> list[np.ndarray]:
    """:func:`_chain`'s loops without repeated points (where pieces join, and the closing
    point), those with fewer than three points left out. A chain that does not close but
    ends with both ends on one of the mirror lines ``folds`` ((2, 2) each) [m] is closed
    along it: a half piece's line drawn up to its fold."""
    loops, ends = _chain(pieces)
    loops += [q for q in ends if len(q) >= 3
              and any(_on_line(q[0], f) and _on_line(q[-1], f) for f in folds)]
    loops = [dedupe(q, closed=True) for q in loops]
    return [q for q in loops if len(q) >= 3]
