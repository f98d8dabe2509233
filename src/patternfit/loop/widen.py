"""Edits for a region the verdict calls too tight (or, taking in, too loose) where the
corner moves across the grain cannot reach it: the panel's outline edges next to the
region are translated along the region's stretch direction (the pattern maker's "let out
the shoulder line", "widen the sleeve at the overarm seam"), by the length the region's
stretch says it lacks; a too-loose girth's side edges are translated inward by its excess
ease. Each edge translation is the move of its two end corners by the same offset, so it
goes through the correction's machinery (sewn corners shared, mirror symmetry kept,
``close_seams``, ``check_pattern``). Lengths in metres.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..geometry import face_adjacency
from ..mesh.garment import GarmentMesh

#: an outline edge borders a region when at least this many of its mesh vertices are
#: within :data:`RING` rings of triangles of the region's (through the mesh, not across
#: the flat plane: a sleeve's forearm is near the side seam across the notch under the
#: arm, not through the cloth); a coarse mesh has two or three vertices on an edge's part
#: at a girth
MIN_EDGE_VERTICES = 2
RING = 1
#: connected parts of a region with fewer triangles than this are left (specks)
MIN_PART = 4
#: weight of the pull of every corner move to zero in the least-squares fit [-] (the
#: outline points' blend weights are 0..1)
RIDGE = 1e-2
#: weight of the outline points of a let-out edge away from the region, which should stay
#: (against 1 for those at the region, which should move) [-]
STAY = 0.5
#: a region with no seam of its own on a side is let out at the first seam ahead along
#: its stretch within this many times its width along it (the shoulders: their width
#: across the back reaches the shoulder points)
REACH = 1.2
#: ... and it faces the stretch direction: |outward normal · direction| at least this
MIN_FACING = 0.5


def region_strain(mesh: GarmentMesh, positions, triangles) -> tuple[np.ndarray, float]:
    """The area-weighted mean Green strain of ``triangles`` (k,) of ``mesh`` at
    ``positions`` (n, 3) [m]: its principal direction (2,) in the flat pattern and the
    stretch along it [-] (1.1 = 10 % longer than flat)."""
    v, t = mesh.vertices, mesh.triangles[triangles]
    x = np.asanyarray(positions, dtype=np.float64)
    dm = np.stack([v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]], axis=2)
    ds = np.stack([x[t[:, 1]] - x[t[:, 0]], x[t[:, 2]] - x[t[:, 0]]], axis=2)
    f = ds @ np.linalg.inv(dm)
    area = 0.5 * np.abs(np.linalg.det(dm))
    green = 0.5 * (np.einsum("mki,mkj->mij", f, f) - np.eye(2))
    mean = np.einsum("m,mij->ij", area, green) / area.sum()
    w, vec = np.linalg.eigh(mean)
    return vec[:, -1], float(np.sqrt(max(1.0 + 2.0 * w[-1], 0.0)))


def _outward_normal(mesh: GarmentMesh, ids) -> np.ndarray:
    """Mean outward unit normal (2,) of the outline polyline through boundary vertices
    ``ids`` (in loop order), for a counter-clockwise outline."""
    p = mesh.vertices[ids]
    d = p[-1] - p[0]
    n = np.array([d[1], -d[0]])
    return n / max(np.linalg.norm(n), 1e-12)


def _seam_ahead(mesh: GarmentMesh, loop, centre, direction, reach: float) -> int | None:
    """Position in ``loop`` (a panel's outline vertices, in order) where a ray from
    ``centre`` (2,) along ``direction`` (2,) first leaves the panel within ``reach`` [m],
    or None (a sleeve's stretch towards the chest has no seam of its own there). A region in
    the middle of a panel (across the shoulders) is let out at the seam its stretch pulls
    on (the shoulder point), not through the cloth."""
    rel = mesh.vertices[loop] - centre
    along = rel @ direction
    across = np.abs(rel @ np.array([-direction[1], direction[0]]))
    step = float(np.median(np.linalg.norm(np.diff(mesh.vertices[loop], axis=0), axis=1)))
    ahead = np.flatnonzero((along > 0) & (across <= step) & (along <= reach))
    return int(ahead[np.argmin(along[ahead])]) if len(ahead) else None


def edge_moves(pattern, mesh: GarmentMesh, panel: int, triangles, direction,
               amount: float) -> dict:
    """Corner offsets ``{(panel, edge): (2,) [m]}`` that move the outline of panel
    ``panel`` (its index) where it borders ``triangles`` (k,) by ``amount`` [m] in all
    along ``direction`` (2,), outward: the outline points there on the far side of the
    region's centre along the direction by half of it, those on the near side by half of
    it back (all of it where only one side has such points; a negative ``amount`` takes
    in). Only points of edges facing the direction count (|outward normal · direction| ≥
    :data:`MIN_FACING`); a region with none moves the first edges ahead along the
    direction (:func:`_seam_ahead`). The corner moves are fitted to these displacements by least
    squares (a corner move carries its two edges' points along linearly in their
    arc-length fraction), with the rest of those edges asked to stay (weight
    :data:`STAY`), so the seam is let out where the region is and tapers towards a far
    corner, as a pattern maker lets out a side seam at the bust."""
    pname = mesh.panel_names[panel]
    d = np.asarray(direction, dtype=np.float64)
    near = np.zeros(mesh.n_vertices, dtype=bool)
    near[mesh.triangles[np.asanyarray(triangles)]] = True
    for _ in range(RING):
        near[mesh.triangles[near[mesh.triangles].any(axis=1)]] = True
    flat = mesh.vertices[near & (mesh.vertex_panel == panel)]
    centre = flat.mean(axis=0)
    reach = REACH * float(np.ptp(flat @ d))
    names = [e.name for e in pattern.panel(pname).outline.edges]
    loop = mesh.loops(panel)[0]
    where = {int(v): i for i, v in enumerate(mesh.boundary_vertices)}
    rows = np.array([where[int(v)] for v in loop])
    k_edge = np.array([names.index(mesh.edge_names[k][1]) for k in mesh.boundary_edge[rows]])
    t = mesh.boundary_param[rows]
    facing = np.array([abs(_outward_normal(mesh, mesh.edge_vertices(pname, n)[0]) @ d)
                       for n in names])[k_edge] >= MIN_FACING
    side = np.sign((mesh.vertices[loop] - centre) @ d)
    chosen = {s: np.flatnonzero(near[loop] & facing & (side == s)) for s in (1.0, -1.0)}
    chosen = {s: v for s, v in chosen.items() if len(v) >= MIN_EDGE_VERTICES}
    if not chosen:  # a region off every seam facing its stretch (across the shoulders)
        for s in (1.0, -1.0):
            hit = _seam_ahead(mesh, loop, centre, s * d, reach)
            if hit is not None and facing[hit]:
                chosen[s] = np.array([hit])
    if not chosen:
        return {}
    idx = np.concatenate(list(chosen.values()))
    want = np.concatenate([np.outer(np.full(len(v), s * amount / len(chosen)), d)
                           for s, v in chosen.items()])
    # the rest of those edges stays where it is (less firmly): the let-out tapers
    rest = np.setdiff1d(np.flatnonzero(np.isin(k_edge, k_edge[idx])), idx)
    weight = np.concatenate([np.ones(len(idx)), np.full(len(rest), STAY)])
    idx = np.concatenate([idx, rest])
    want = np.vstack([want, np.zeros((len(rest), 2))]) * weight[:, None]
    A = np.zeros((len(idx), len(names)))
    A[np.arange(len(idx)), k_edge[idx]] += (1.0 - t[idx]) * weight
    A[np.arange(len(idx)), (k_edge[idx] + 1) % len(names)] += t[idx] * weight
    used = np.flatnonzero(A.any(axis=0))
    for _ in range(2):
        B = A[:, used]
        # a faint pull to zero keeps a corner with few outline points near it well posed
        u = np.linalg.solve(B.T @ B + RIDGE * np.eye(len(used)), B.T @ want)
        # a corner fitted against the way its points should go (the far end of a let-out
        # edge overshooting to make it taper) stays instead
        keep = np.einsum("ij,ij->i", u, B.T @ want) >= 0.0
        if keep.all():
            break
        used = used[keep]
    return {(pname, names[c]): u[j] for j, c in enumerate(used)}


def _parts(mesh: GarmentMesh, triangles) -> list[np.ndarray]:
    """``triangles`` (k,) split into their edge-connected parts on each panel (a region
    and its mirror image on a symmetric panel, the two sleeves of a kimono front, are two
    parts, each with its own stretch direction)."""
    tris = np.asanyarray(triangles)
    out = []
    for pi in np.unique(mesh.triangle_panel[tris]):
        mine = tris[mesh.triangle_panel[tris] == pi]
        pairs = face_adjacency(mesh.triangles[mine])
        graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])),
                           shape=(len(mine), len(mine)))
        _, label = connected_components(graph, directed=False)
        out.extend(mine[label == k] for k in np.unique(label))
    return out


def let_out_moves(pattern, mesh: GarmentMesh, positions, triangles, target: float, *,
                  least: float = 0.0) -> dict:
    """Corner offsets that give each connected part of ``triangles`` (k,) on a panel
    (:func:`_parts`) the length it lacks along its own principal stretch
    (:func:`region_strain`: mirrored parts have mirrored frames) for a stretch of
    ``target`` [-]: its width across that direction times (stretch − 1 − target) /
    (1 + target), by :func:`edge_moves` (the asks of several parts added); the stretch
    taken at least ``least`` [-] (the region's high percentile: a woven pressing too hard
    is stretched only at its edge, and its mean says nothing)."""
    moves: dict = {}
    for part in _parts(mesh, triangles):
        if len(part) < MIN_PART:
            continue
        direction, stretch = region_strain(mesh, positions, part)
        stretch = max(stretch, 1.0 + least)
        if stretch - 1.0 <= target:
            continue
        ids = np.unique(mesh.triangles[part])
        width = float(np.ptp(mesh.vertices[ids] @ direction))
        amount = width * (stretch - 1.0 - target) / (1.0 + target)
        pi = int(mesh.triangle_panel[part[0]])
        for key, d in edge_moves(pattern, mesh, pi, part, direction, amount).items():
            moves[key] = moves.get(key, 0.0) + d
    return moves
