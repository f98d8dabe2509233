"""Left/right symmetry of the correction's edits: a pattern maker edits both sides of a
symmetric body alike, from the mean of the two sides, even where one drape came to rest a
little askew (a drape is never exactly symmetric: one side's region then covers other
parts of the outline, or reads too tight where its mirror image does not).

A mirror maps a panel onto itself (a front symmetric about its centre line) or onto its
left/right partner (the two legs, two sleeves, a jacket's two fronts: the same
``placement.side``, parts the same but for left/right); front and back are not mirrors of
each other, however alike they are cut. Points of panel ``a`` map to panel ``b`` by
``reflect @ p + shift`` (reflected across ``a``'s grainline), corners by name. Lengths in
metres, in the panels' flat frames.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ..mesh.garment import GarmentMesh
from ..pattern.model import Panel, Pattern

#: corners closer than this to their mirror image's place are mirrored [m]
CORNER_TOLERANCE = 1e-3
#: a triangle's mirror image is the triangle whose centroid is nearest to the mirrored
#: centroid, if within this many of the panel's median mesh edge lengths
TRIANGLE_REACH = 1.0
#: orbits of a corner under the mirrors larger than this are not averaged (the mirrors of
#: panels with different grainlines compose into rotations that need not close)
MAX_ORBIT = 16


@dataclass(frozen=True)
class Mirror:
    """Panel ``a`` mirrored onto panel ``b`` (possibly itself): ``corners`` ((edge of a,
    edge of b), ...) whose start corners map onto each other, and the map of flat points
    p (2,) [m] of ``a`` to ``b``: ``reflect @ p + shift`` (``reflect`` (2, 2), ``shift``
    (2,) [m])."""

    a: str
    b: str
    corners: tuple
    reflect: np.ndarray
    shift: np.ndarray


def other_side(name: str) -> str | None:
    """The name on the body's other side (``bicep_left`` → ``bicep_right``, ``sleeve_right``
    → ``sleeve_left``), or None for a name with no side."""
    for mine, other in (("_left", "_right"), ("_right", "_left")):
        if name.endswith(mine):
            return name[: -len(mine)] + other
    return None


def _partners(pa: Panel, pb: Panel) -> bool:
    """Whether ``pb`` may be ``pa``'s left/right mirror: the same panel, or one facing the
    same side whose body part is the same or its left/right counterpart."""
    if pa.name == pb.name:
        return True
    qa, qb = pa.placement, pb.placement
    swap = qb.part.replace("left", "#").replace("right", "left").replace("#", "right")
    return qa.side == qb.side and qa.part in (qb.part, swap)


def mirror(pa: Panel, pb: Panel, grain) -> Mirror | None:
    """The mirror of ``pa`` onto ``pb`` across ``pa``'s grainline ``grain`` (2,) (after
    aligning the outlines' bounding-box centres), or None if their outlines do not map
    corner to corner."""
    c = np.array([-grain[1], grain[0]], dtype=np.float64)
    ea, eb = pa.outline.edges, pb.outline.edges
    if len(ea) != len(eb):
        return None
    qa = np.array([e.start for e in ea])
    qb = np.array([e.start for e in eb])
    ma, mb = pa.outline.polygon(), pb.outline.polygon()
    reflect = np.eye(2) - 2.0 * np.outer(c, c)
    shift = 0.5 * (mb.min(axis=0) + mb.max(axis=0)) - reflect @ (
        0.5 * (ma.min(axis=0) + ma.max(axis=0)))
    dist = np.linalg.norm((qa @ reflect.T + shift)[:, None, :] - qb[None, :, :], axis=2)
    match = np.argmin(dist, axis=1)
    if not np.all(dist[np.arange(len(qa)), match] < CORNER_TOLERANCE):
        return None
    return Mirror(pa.name, pb.name, tuple((ea[k].name, eb[m].name) for k, m in
                                          enumerate(match)), reflect, shift)


def mirrors(pattern: Pattern, mesh: GarmentMesh) -> list[Mirror]:
    """Every mirror of the pattern's panels (each pair once, a panel onto itself
    included), with the grainlines of ``mesh``."""
    names = list(mesh.panel_names)
    out = []
    for i, a in enumerate(names):
        for b in names[i:]:
            pa, pb = pattern.panel(a), pattern.panel(b)
            m = mirror(pa, pb, mesh.grain[i]) if _partners(pa, pb) else None
            if m is not None:
                out.append(m)
    return out


def symmetric_moves(pattern: Pattern, mesh: GarmentMesh, moves: dict) -> dict:
    """``moves`` ``{(panel, corner edge): (2,) [m]}`` made mirror-symmetric: every corner
    moves by the mean of the moves of its mirror images (each mapped back by its
    reflection; a mirror image not in ``moves`` counts as not moving), and the corners so
    given a move are added."""
    links: dict = {}
    for m in mirrors(pattern, mesh):
        for ea, eb in m.corners:
            links.setdefault((m.a, ea), []).append(((m.b, eb), m.reflect))
            links.setdefault((m.b, eb), []).append(((m.a, ea), m.reflect))
    out = dict(moves)
    done: set = set()
    for key in moves:
        if key in done:
            continue
        # the orbit: (corner, map from the key's frame to the corner's) for every chain of
        # mirrors from the key; a corner on a panel's axis is reached under both maps
        orbit = [(key, np.eye(2))]
        seen = {(key, (1.0, 0.0, 0.0, 1.0))}
        frontier = list(orbit)
        while frontier and len(orbit) <= MAX_ORBIT:
            node, to = frontier.pop()
            for other, reflect in links.get(node, ()):
                t = reflect @ to
                tag = (other, tuple(np.round(t.ravel(), 9)))
                if tag not in seen:
                    seen.add(tag)
                    orbit.append((other, t))
                    frontier.append((other, t))
        done.update(node for node, _ in orbit)
        if len(orbit) > MAX_ORBIT:
            continue
        mean = np.mean([t.T @ np.asarray(moves.get(node, np.zeros(2)), dtype=np.float64)
                        for node, t in orbit], axis=0)
        for node, t in orbit:
            out[node] = t @ mean
    return out


def mirrored_triangles(pattern: Pattern, mesh: GarmentMesh, triangles) -> np.ndarray:
    """``triangles`` (k,) int of ``mesh`` with their mirror images under every mirror
    (:func:`mirrors`) added: (k',) int, sorted, unique."""
    tris = np.unique(np.asanyarray(triangles, dtype=np.int64))
    centroid = mesh.vertices[mesh.triangles].mean(axis=1)
    index = {n: i for i, n in enumerate(mesh.panel_names)}
    found = [tris]
    for m in mirrors(pattern, mesh):
        for src, dst, forward in ((m.a, m.b, True), (m.b, m.a, False)):
            mine = tris[mesh.triangle_panel[tris] == index[src]]
            if not len(mine):
                continue
            p = centroid[mine]
            q = p @ m.reflect.T + m.shift if forward else (p - m.shift) @ m.reflect.T
            target = mesh.panel_triangles(index[dst])
            t = mesh.triangles[target]
            step = float(np.median(np.linalg.norm(
                mesh.vertices[t[:, 1]] - mesh.vertices[t[:, 0]], axis=1)))
            dist, k = cKDTree(centroid[target]).query(q)
            found.append(target[k[dist <= TRIANGLE_REACH * step]])
    return np.unique(np.concatenate(found))
