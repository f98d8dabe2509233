"""Torso panels of one side sewn to each other along seams that run up the body (a gored
skirt's gores, GarmentCode's left and right bodice halves), assembled flat before
:mod:`patternfit.sim.placement` rolls them round the body.

Centred each on its side's meridian, as a lone panel is, such panels start one on another
and the sewing phase pulls them through each other. So a side's panels make a *row*: laid
side by side in seam order and centred on the side (:class:`Row`), or, when their seams fan
out (flared gores), a *fan*: each panel turned and moved onto its neighbour's seam, the row
then a sector of a ring that :func:`~patternfit.sim.placement.place_on_body` rolls onto a
cone (:class:`Fan`).

Flat frame: the panels' upright frames (:func:`~patternfit.sim.panel_frames.upright_frames`),
metres, ``u`` across, ``v`` up.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..mesh.garment import GarmentMesh
from ..pattern.model import Pattern

#: panels of one side sewn along a vertical seam start this far [m] either side of it (not
#: touching: the solver counts touching cloth as crossed)
HALF_GAP = 0.005

#: a seam runs up the body when it runs across less than this share of its height on both
#: panels; seams steeper than :data:`STRAIGHT` lay a row out by shifts (a cone for gores
#: flared that little would be narrower than the hips: the shifted row clears them)
STEEP = 1.0
STRAIGHT = 0.3

#: a row whose panels, put seam to seam, fan out by more than this [rad] in all is a fan
FAN_ANGLE = math.radians(20.0)


@dataclass(frozen=True)
class Row:
    """A panel's place in a row laid out by shifts: ``shift`` [m] along ``u`` and the row's
    ``reach`` [m] either side of the side's middle."""

    shift: float
    reach: float


@dataclass(frozen=True)
class Fan:
    """A side's flared panels put seam to seam: a sector of a ring.

    ``panels`` maps each panel to the angle [rad] it is turned by (counter-clockwise, as
    many turns as the fan takes: a very full skirt's fan spreads over more than half a turn)
    and the ring's centre, the apex, in the panel's own flat frame ``(2,)`` [m]. A point of
    the fan lies at a distance ``r`` [m] from the apex and at an angle from straight down
    (positive towards +u); the fan spans ``spread`` [rad] of angle about ``middle``, and runs
    from ``r_top`` (its top edge, the waist) to ``r_bottom`` [m] (its hem); its top lies at
    ``top`` [m] in the panels' own flat frames (the height the placement hangs it from)."""

    panels: dict[int, tuple[float, np.ndarray]]
    middle: float
    spread: float
    r_top: float
    r_bottom: float
    top: float

    def polar(self, panel: int, uv) -> tuple[np.ndarray, np.ndarray]:
        """Distance from the apex [m] and angle from the fan's middle [rad] of a panel's
        flat points ``uv`` (k, 2) [m]: each (k,)."""
        r, angle = _polar(*self.panels[panel], uv)
        return r, angle - self.middle


def _polar(turn: float, apex: np.ndarray, uv) -> tuple[np.ndarray, np.ndarray]:
    """Distance [m] from ``apex`` (2,) and angle [rad] from straight down, plus ``turn``,
    of flat points ``uv`` (k, 2) [m] (:class:`Fan`)."""
    d = np.asarray(uv, dtype=np.float64) - apex
    return np.hypot(d[:, 0], d[:, 1]), np.arctan2(d[:, 0], -d[:, 1]) + turn


def side_rows(pattern: Pattern, mesh: GarmentMesh, flat: np.ndarray,
              roles) -> dict[int, Row | Fan]:
    """{panel index: its :class:`Row` or :class:`Fan`} for torso panels sewn along seams
    that run up the body to others of the same kind and side. ``flat`` (n, 2) [m]: the
    mesh's vertices in the panels' upright frames; ``roles``: ``panel_roles(pattern)``.

    A row fans out when one of its seams is at least as slanted as :data:`STRAIGHT` and its
    panels, put seam to seam, spread by :data:`FAN_ANGLE` or more about the point above
    them where the lines of their sewn sides meet. Otherwise the panels sewn along
    seams steeper than :data:`STRAIGHT` are laid out by shifts, in seam order, each clear
    of its neighbour at their widest, centred on its middle seam (a left and a right half's
    centre line on the side's middle, however wide each is) or its middle panel. A ring of
    one side's panels is a row too, the seam that closes it starting open across the row."""
    links, sides = _links(pattern, mesh, flat, roles)
    out: dict[int, Row | Fan] = {}
    tried: set[int] = set()
    for first in sorted(links):
        if first in tried:
            continue
        fan, row = _fan(first, links, sides, flat, mesh)
        tried |= row
        if fan is not None:
            out.update(dict.fromkeys(row, fan))
    straight = {i: [link for link in ls if link[2] and link[0] not in out]
                for i, ls in links.items() if i not in out}
    straight = {i: ls for i, ls in straight.items() if ls}
    for first in sorted(straight):
        if first not in out:
            out.update(_shifted(first, straight, flat, mesh))
    return out


def _links(pattern, mesh, flat, roles):
    """``(links, sides)``: ``links`` {panel: [(neighbour, vertex pairs (k, 2) own side
    first, whether the seam is steeper than STRAIGHT)]} over the seams between torso panels
    of one kind and side that run up the body; ``sides`` {panel: [vertex indices (k,) of
    each of its sewn sides that runs up the body]} (a fan's lines)."""
    index = {p.name: i for i, p in enumerate(pattern.panels)}
    links: dict[int, list[tuple[int, np.ndarray, bool]]] = {}
    sides: dict[int, list[np.ndarray]] = {}
    for k, s in enumerate(pattern.seams):
        if s.a.panel == s.b.panel:  # a dart
            continue
        pairs = mesh.seam_pairs[mesh.seam_index == k]
        a, b = index[s.a.panel], index[s.b.panel]
        slants = (_slant(flat[pairs[:, 0]]), _slant(flat[pairs[:, 1]]))
        for panel, ids, slant in ((a, pairs[:, 0], slants[0]), (b, pairs[:, 1], slants[1])):
            if slant < STEEP:
                sides.setdefault(panel, []).append(ids)
        ra, rb = roles[s.a.panel], roles[s.b.panel]
        if ra.part != "torso" or rb.part != "torso" or (ra.kind, ra.side) != (rb.kind, rb.side) \
                or ra.side not in ("front", "back") or max(slants) >= STEEP:
            continue  # a yoke's or a band's seam, or one to another kind of panel
        links.setdefault(a, []).append((b, pairs, max(slants) < STRAIGHT))
        links.setdefault(b, []).append((a, pairs[:, ::-1], max(slants) < STRAIGHT))
    return links, sides


def _slant(uv: np.ndarray) -> float:
    return float(np.ptp(uv[:, 0]) / max(np.ptp(uv[:, 1]), 1e-9))


def _shifted(first: int, links, flat, mesh) -> dict[int, Row]:
    """The row of ``first`` laid out by shifts along u (:func:`side_rows`)."""
    u = {}
    shift, queue = {first: 0.0}, [first]
    while queue:
        i = queue.pop(0)
        u.setdefault(i, flat[mesh.panel_vertices(i), 0])
        for j, pairs, _ in links[i]:
            if j in shift:
                continue
            u[j] = flat[mesh.panel_vertices(j), 0]
            # next to its neighbour on the seam's side, clear of it at their widest (a
            # flared gore's slanted seams, put together, crossed below the middle)
            if flat[pairs[:, 0], 0].mean() > u[i].mean():
                shift[j] = u[i].max() + shift[i] + 2.0 * HALF_GAP - u[j].min()
            else:
                shift[j] = u[i].min() + shift[i] - 2.0 * HALF_GAP - u[j].max()
            queue.append(j)
    row = sorted(shift, key=lambda i: float(u[i].min()) + shift[i])
    left, right = row[(len(row) - 1) // 2], row[len(row) // 2]  # the same when odd
    mid = 0.5 * (float(u[left].max()) + shift[left] + float(u[right].min()) + shift[right])
    reach = max(float(np.abs(u[i] + d - mid).max()) for i, d in shift.items())
    return {i: Row(d - mid, reach) for i, d in shift.items()}


def _fan(first: int, links, sides, flat, mesh) -> tuple[Fan | None, set[int]]:
    """The row of ``first`` put seam to seam, each panel turned and moved onto the seam of
    the neighbour it was reached from and then moved clear of it by 2 HALF_GAP: the
    :class:`Fan` (None unless it fans out, :func:`side_rows`; its apex is where the lines
    of its panels' sewn sides meet) and the row's panels."""
    moves = {first: (0.0, np.eye(2), np.zeros(2))}
    queue, slanted = [first], False
    while queue:
        i = queue.pop(0)
        angle_i, turn_i, shift_i = moves[i]
        for j, pairs, straight in links[i]:
            slanted |= not straight
            if j in moves:
                continue
            target = flat[pairs[:, 0]] @ turn_i.T + shift_i
            turn, shift = _rigid(flat[pairs[:, 1]], target)
            # clear of the neighbour, across the seam's line
            along = _direction(target)
            across = np.array([-along[1], along[0]])
            away = flat[mesh.panel_vertices(j)].mean(axis=0) @ turn.T + shift \
                - flat[mesh.panel_vertices(i)].mean(axis=0) @ turn_i.T - shift_i
            shift = shift + 2.0 * HALF_GAP * math.copysign(1.0, away @ across) * across
            relative = math.atan2(turn[1, 0], turn[0, 0]) - math.atan2(turn_i[1, 0], turn_i[0, 0])
            moves[j] = (angle_i + math.remainder(relative, 2.0 * math.pi), turn, shift)
            queue.append(j)
    lines = [(p.mean(axis=0), _direction(p)) for i, (_, turn, shift) in moves.items()
             for p in (flat[ids] @ turn.T + shift for ids in sides.get(i, ()))]
    apex = _meeting_point(lines) if slanted else None
    if apex is None:
        return None, set(moves)
    # the apex in each panel's own frame, which must lie above the panel (flared downwards)
    panels = {i: (angle, (apex - shift) @ turn) for i, (angle, turn, shift) in moves.items()}
    points = {i: flat[mesh.panel_vertices(i)] for i in moves}
    if any(own[1] <= points[i][:, 1].max() for i, (_, own) in panels.items()):
        return None, set(moves)
    r, theta = (np.concatenate(v) for v in zip(*(_polar(*panels[i], p)
                                                  for i, p in points.items())))
    if np.ptp(theta) < FAN_ANGLE:
        return None, set(moves)
    return Fan(panels, 0.5 * float(theta.min() + theta.max()), float(np.ptp(theta)),
               float(r.min()), float(r.max()),
               max(float(p[:, 1].max()) for p in points.values())), set(moves)


def _rigid(p: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The turn (2, 2) and shift (2,) that take points ``p`` (k, 2) closest to ``q`` (k, 2)
    (least squares, no mirroring; trimesh's ``procrustes`` takes 3D points only)."""
    pc, qc = p - p.mean(axis=0), q - q.mean(axis=0)
    angle = math.atan2(float(np.sum(pc[:, 0] * qc[:, 1] - pc[:, 1] * qc[:, 0])),
                       float(np.sum(pc * qc)))
    c, s = math.cos(angle), math.sin(angle)
    turn = np.array([[c, -s], [s, c]])
    return turn, q.mean(axis=0) - p.mean(axis=0) @ turn.T


def _direction(points: np.ndarray) -> np.ndarray:
    """Unit direction (2,) of the line that fits ``points`` (k, 2) best, pointing up."""
    _, _, vt = np.linalg.svd(points - points.mean(axis=0), full_matrices=False)
    return vt[0] if vt[0, 1] >= 0 else -vt[0]


def _meeting_point(lines) -> np.ndarray | None:
    """The point (2,) nearest, in least squares, to ``lines`` [(point (2,), unit direction
    (2,))]; None when they are (nearly) parallel."""
    a, b = np.zeros((2, 2)), np.zeros(2)
    for p, d in lines:
        off = np.eye(2) - np.outer(d, d)
        a += off
        b += off @ p
    if np.linalg.cond(a) > 1e8:
        return None
    return np.linalg.solve(a, b)
