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
from scipy.spatial import cKDTree

from ..mesh.garment import GarmentMesh

#: an outline edge borders a region when at least this many of its mesh vertices lie
#: within :data:`NEAR` mesh edge lengths of the region's vertices (flat): a coarse mesh has
#: two or three vertices on an edge's part at a girth, and the two sides of a symmetric
#: panel must be found alike
MIN_EDGE_VERTICES = 2
NEAR = 1.5
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


def _taper(params) -> tuple[float, float]:
    """Weights (start, end) of an edge's two corner moves whose linear blend along the
    edge moves the points at arc-length fractions ``params`` (k,) by 1 on average with the
    smallest corner moves: a region near one end moves mostly that corner, one along the
    whole edge translates it."""
    s = np.asanyarray(params, dtype=np.float64)
    m = np.array([np.mean(1.0 - s), np.mean(s)])
    return tuple(m / float(m @ m))


def edge_moves(pattern, mesh: GarmentMesh, panel: int, triangles, direction,
               amount: float) -> dict:
    """Corner offsets ``{(panel, edge): (2,) [m]}`` that move the outline edges of panel
    ``panel`` (its index) bordering ``triangles`` (k,) and facing ``direction`` (2,) by
    ``amount`` [m] in all along it, outward (half on each side when both sides have such
    edges; a negative ``amount`` takes in), where they border the region: the seam is let
    out there, tapering to nothing towards a corner far from it (:func:`_taper`), as a
    pattern maker lets out a side seam at the bust only. A corner of two such edges of a
    side moves by the mean of what each asks."""
    pname = mesh.panel_names[panel]
    t = mesh.triangles[np.asanyarray(triangles)]
    region = cKDTree(mesh.vertices[np.unique(t)])
    step = float(np.median(np.linalg.norm(mesh.vertices[t[:, 1]] - mesh.vertices[t[:, 0]],
                                          axis=1)))
    near = np.zeros(mesh.n_vertices, dtype=bool)
    ids_all = mesh.panel_vertices(panel)
    near[ids_all] = region.query(mesh.vertices[ids_all])[0] <= NEAR * step
    edges = pattern.panel(pname).outline.edges
    sides: dict = {1.0: [], -1.0: []}
    for k, e in enumerate(edges):
        ids, params = mesh.edge_vertices(pname, e.name)
        if near[ids].sum() < MIN_EDGE_VERTICES:
            continue
        facing = float(_outward_normal(mesh, ids) @ direction)
        if abs(facing) >= MIN_FACING:
            sides[float(np.sign(facing))].append((k, params[near[ids]]))
    used = [s for s in sides if sides[s]]
    asked: dict = {}
    for s in used:
        offset = s * (amount / len(used)) * np.asarray(direction, dtype=np.float64)
        for k, params in sides[s]:
            for corner, w in zip((edges[k].name, edges[(k + 1) % len(edges)].name),
                                 _taper(params)):
                asked.setdefault((pname, corner), []).append(w * offset)
    return {key: np.mean(d, axis=0) for key, d in asked.items()}


def let_out_moves(pattern, mesh: GarmentMesh, positions, triangles, target: float, *,
                  least: float = 0.0) -> dict:
    """Corner offsets that give each panel's part of ``triangles`` (k,) the length it
    lacks along its own principal stretch (:func:`region_strain`, per panel: mirrored
    panels have mirrored frames) for a stretch of ``target`` [-]: its width across that
    direction times (stretch − 1 − target) / (1 + target), by :func:`edge_moves`; the
    stretch taken at least ``least`` [-] (the region's high percentile: a woven pressing
    too hard is stretched only at its edge, and its mean says nothing)."""
    tris = np.asanyarray(triangles)
    moves: dict = {}
    for pi in np.unique(mesh.triangle_panel[tris]):
        mine = tris[mesh.triangle_panel[tris] == pi]
        direction, stretch = region_strain(mesh, positions, mine)
        stretch = max(stretch, 1.0 + least)
        if stretch - 1.0 <= target:
            continue
        ids = np.unique(mesh.triangles[mine])
        width = float(np.ptp(mesh.vertices[ids] @ direction))
        amount = width * (stretch - 1.0 - target) / (1.0 + target)
        moves.update(edge_moves(pattern, mesh, int(pi), mine, direction, amount))
    return moves
