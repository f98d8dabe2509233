"""Edits for a region the verdict calls too tight (or, taking in, too loose) where the
corner moves across the grain cannot reach it: each connected part of the region on a
panel lacks the length its stretch says, and the panel's outline edges along it that
face the panel's cross-grain are moved outward by that length (the pattern maker's "let
out the side seam at the bust", "widen the sleeve at the overarm"); a region off every
such seam (across the shoulders) is let out at the first seam ahead (the shoulder
points); a too-loose girth's side edges move inward by its excess ease. The edits are
corner moves, so they go through the correction's machinery (sewn corners shared,
mirror symmetry kept, ``close_seams``, ``check_pattern``) and are recorded as
``move_point`` edits. Lengths in metres.
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
#: a region with no seam of its own on a side is let out at the first seam ahead along
#: its stretch within this many times its width along it (the shoulders: their width
#: across the back reaches the shoulder points)
REACH = 1.2
#: ... and it faces the stretch direction: |outward normal · direction| at least this
MIN_FACING = 0.5
#: weight of the pull to zero of a corner away from the region (its mesh vertex not within
#: :data:`RING` of it), against :data:`RIDGE` for one at it: a let-out at the armpit of the
#: 3K Table 2 coat with every corner free moved the hem corners out 2.5–5 cm a round (the
#: armpit, asked out by the side seam and in by the sleeve's underarm, stayed) and grew the
#: hip ease to +84 cm; weights 0.1 and 0.3 left the biceps tight and the hip let out
PIN = 1.0


def _gradients(mesh: GarmentMesh, positions, triangles) -> np.ndarray:
    """Deformation gradients (k, 3, 2) [-] of ``triangles`` (k,) of ``mesh`` from the flat
    pattern to ``positions`` (n, 3) [m]."""
    v, t = mesh.vertices, mesh.triangles[triangles]
    x = np.asanyarray(positions, dtype=np.float64)
    dm = np.stack([v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]], axis=2)
    ds = np.stack([x[t[:, 1]] - x[t[:, 0]], x[t[:, 2]] - x[t[:, 0]]], axis=2)
    return ds @ np.linalg.inv(dm)


def region_strain(mesh: GarmentMesh, positions, triangles) -> tuple[np.ndarray, float]:
    """The area-weighted mean Green strain of ``triangles`` (k,) of ``mesh`` at
    ``positions`` (n, 3) [m]: its principal direction (2,) in the flat pattern and the
    stretch along it [-] (1.1 = 10 % longer than flat)."""
    f = _gradients(mesh, positions, triangles)
    area = mesh.triangle_areas()[triangles]
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


def _seam_ahead(mesh: GarmentMesh, loop, eligible, centre, direction,
                reach: float) -> int | None:
    """Position in ``loop`` (a panel's outline vertices, in order) of the first of the
    ``eligible`` (bool, per loop vertex: those on edges facing the direction) that a ray
    from ``centre`` (2,) along ``direction`` (2,) meets within ``reach`` [m], or None. A
    region in the middle of a panel (across the shoulders) is let out at the seam its
    stretch pulls on (the shoulder point), not through the cloth."""
    rel = mesh.vertices[loop] - centre
    along = rel @ direction
    across = np.abs(rel @ np.array([-direction[1], direction[0]]))
    step = float(np.median(np.linalg.norm(np.diff(mesh.vertices[loop], axis=0), axis=1)))
    ahead = np.flatnonzero(eligible & (along > 0) & (across <= step) & (along <= reach))
    return int(ahead[np.argmin(along[ahead])]) if len(ahead) else None


def edge_moves(pattern, mesh: GarmentMesh, panel: int, triangles, direction,
               amount: float) -> dict:
    """Corner offsets ``{(panel, edge): (2,) [m]}`` that let out the outline of panel
    ``panel`` (its index) where it borders ``triangles`` (k,) by ``amount`` [m] in all
    across ``direction`` (2,): the points of edges facing the direction (|outward normal
    · direction| ≥ :data:`MIN_FACING`) by half of it on each side, along their own edge's
    outward normal, as a seam is let out (all of it where only one side has such points;
    a negative ``amount`` takes in); a region with none moves the first edges ahead along
    the direction (:func:`_seam_ahead`).

    The corner moves are fitted to these displacements by least squares (a corner move
    carries its two edges' points along linearly in their arc-length fraction), corners
    away from the region held by :data:`PIN`: an edge the region lies along is
    translated, one it touches at an end tapers; a corner between two let-out edges (a
    kimono sleeve's underarm and the side seam at the armpit) moves by about the mean of
    their asks: the armpit goes down, the underarm deepened (across the grain only, the
    two asks cancelled there and the 3K Table 2 coat's biceps stayed tight, 12–14 %). (Asked to keep the rest of a let-out edge in place, so
    that the seam tapered, the 3K Table 2 coat's re-drape crossed itself: 102 pairs
    against 2.)"""
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
    cos = np.array([_outward_normal(mesh, mesh.edge_vertices(pname, n)[0]) @ d
                    for n in names])[k_edge]
    facing, side = np.abs(cos) >= MIN_FACING, np.sign(cos)
    chosen = {s: np.flatnonzero(near[loop] & facing & (side == s)) for s in (1.0, -1.0)}
    chosen = {s: v for s, v in chosen.items() if len(v) >= MIN_EDGE_VERTICES}
    ahead = not chosen
    if ahead:  # a region off every seam facing its stretch (across the shoulders)
        for s in (1.0, -1.0):
            hit = _seam_ahead(mesh, loop, facing & (side == s), centre, s * d, reach)
            if hit is not None:
                chosen[s] = np.array([hit])
    if not chosen:
        return {}
    idx = np.concatenate(list(chosen.values()))
    # each point moves along its own edge's outward normal, as a seam is let out
    normal = np.array([_outward_normal(mesh, mesh.edge_vertices(pname, n)[0])
                       for n in names])[k_edge[idx]]
    want = normal * (amount / len(chosen))
    A = np.zeros((len(idx), len(names)))
    A[np.arange(len(idx)), k_edge[idx]] += 1.0 - t[idx]
    A[np.arange(len(idx)), (k_edge[idx] + 1) % len(names)] += t[idx]
    used = np.flatnonzero(A.any(axis=0))
    A = A[:, used]
    corner_vertex = np.array([mesh.edge_vertices(pname, names[c])[0][0] for c in used])
    # (a seam ahead lies away from the region: its corners are free)
    ridge = np.where(near[corner_vertex] | ahead, RIDGE, PIN)
    u = np.linalg.solve(A.T @ A + np.diag(ridge), A.T @ want)
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
    ``target`` [-] — its width along that direction times (stretch − 1 − target) /
    (1 + target) — across the panel's grain, as a pattern maker adds width, by
    :func:`edge_moves` (the asks of several parts added): let out along a kimono sleeve's
    oblique stretch, its shoulder point moved up or down and the 3K Table 2 coat's
    re-drape crossed itself (45–119 pairs; across the grain, none); the stretch
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
        g = mesh.grain[pi]
        across = np.array([-g[1], g[0]])
        for key, d in edge_moves(pattern, mesh, pi, part, across, amount).items():
            moves[key] = moves.get(key, 0.0) + d
    return moves


def _stretch(mesh: GarmentMesh, positions, triangles) -> np.ndarray:
    """max(warp, weft) stretch (k,) [-] of ``triangles`` (k,) at ``positions`` (n, 3) [m]
    (1.1 = 10 % longer than flat along one yarn)."""
    f = _gradients(mesh, positions, triangles)
    g = mesh.grain[mesh.triangle_panel[triangles]]
    c = np.stack([-g[:, 1], g[:, 0]], axis=1)
    return np.maximum(np.linalg.norm(np.einsum("mij,mj->mi", f, g), axis=1),
                      np.linalg.norm(np.einsum("mij,mj->mi", f, c), axis=1))


def opening_moves(pattern, mesh: GarmentMesh, positions, triangles, target: float, *,
                  least: float = 0.0) -> dict:
    """Corner offsets ``{(panel, edge): (2,) [m]}`` that widen a free edge running across
    the grain — one no seam sews, a neckline — where the cloth next to it is stretched
    beyond ``target`` [-]: the pattern maker's "widen the neckline" when the neck opening
    is too small and the cloth around it is pulled (the 3K Table 2 coat's yoke, stretched
    10–24 % at the front and back neck after its shoulders and sleeves were let out).

    The patches of ``triangles`` (k,) stretched beyond ``target`` (max of warp and weft)
    that reach the edge (:data:`RING` rings of triangles from it) lack ``Σ a_t (s_t − 1 −
    target) / (1 + target) / H`` of width (a_t their flat areas, s_t their stretch, H their
    extent along the grain: the lack over the band's height); the edge's two end corners
    move apart across the grain by half of it each."""
    sewn = {(side.panel, side.edge) for s in pattern.seams for side in (s.a, s.b)}
    tris = np.asanyarray(triangles)
    out: dict = {}
    for pi in np.unique(mesh.triangle_panel[tris]):
        pname = mesh.panel_names[int(pi)]
        mine = tris[mesh.triangle_panel[tris] == pi]
        hot = mine[_stretch(mesh, positions, mine) > 1.0 + target]
        if len(hot) < MIN_PART:
            continue
        g = mesh.grain[pi]
        c = np.array([-g[1], g[0]])
        edges = pattern.panel(pname).outline.edges
        for k, edge in enumerate(edges):
            if (pname, edge.name) in sewn:
                continue
            ids, _ = mesh.edge_vertices(pname, edge.name)
            if abs(float(_outward_normal(mesh, ids) @ g)) < MIN_FACING:
                continue  # runs along the grain: not an opening across it
            ring = np.zeros(mesh.n_vertices, dtype=bool)
            ring[ids] = True
            for _ in range(RING):
                ring[mesh.triangles[ring[mesh.triangles].any(axis=1)]] = True
            near = [p for p in _parts(mesh, hot) if ring[mesh.triangles[p]].any(axis=1).any()]
            if not near:
                continue
            at = np.concatenate(near)
            excess = np.maximum(_stretch(mesh, positions, at), 1.0 + least) - 1.0 - target
            height = float(np.ptp(mesh.vertices[np.unique(mesh.triangles[at])] @ g))
            lack = float(mesh.triangle_areas()[at] @ excess) / (1.0 + target) / max(
                height, 1e-3)
            start, end = np.asarray(edge.start), np.asarray(edge.end)
            side = np.sign((start - end) @ c)
            out[(pname, edge.name)] = 0.5 * lack * side * c
            out[(pname, edges[(k + 1) % len(edges)].name)] = -0.5 * lack * side * c
    return out
