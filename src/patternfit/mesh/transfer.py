"""Carry per-vertex values from one garment mesh to another of the same pattern.

Two meshes of one pattern (another resolution, or a re-meshed panel) share the panels' flat
frames, so a value on one (a 3D drape state, a colour) reaches the other through the flat
triangle that holds each vertex: barycentric interpolation, panel by panel. Vertices on an
outline take the value along their pattern edge instead, interpolated in arc length between
the source's vertices on that edge: the two sides of a seam are sampled alike, so a seam
closed in the source stays closed (the linear extension of a triangle beyond a curved
outline's chord opened the 20K trousers' crotch seams by up to 5 mm).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..arguments import array
from .garment import GarmentMesh

#: candidate triangles tried per point (nearest centroids)
_CANDIDATES = 12


def _barycentric(p, a, b, c):
    """Barycentric coordinates (..., 3) of points ``p`` in triangles ``abc`` (all (..., 2))."""
    v0, v1, v2 = b - a, c - a, p - a
    d00 = (v0 * v0).sum(-1)
    d01 = (v0 * v1).sum(-1)
    d11 = (v1 * v1).sum(-1)
    d20 = (v2 * v0).sum(-1)
    d21 = (v2 * v1).sum(-1)
    den = d00 * d11 - d01 * d01
    v = (d11 * d20 - d01 * d21) / den
    w = (d00 * d21 - d01 * d20) / den
    return np.stack([1.0 - v - w, v, w], axis=-1)


def locate(mesh: GarmentMesh, panel: int, points) -> tuple[np.ndarray, np.ndarray]:
    """Triangle of ``panel`` holding each flat point, and the point's barycentric coordinates.

    Parameters
    ----------
    mesh : GarmentMesh
    panel : int
        Panel index in ``mesh``.
    points : (k, 2) float
        Flat points in that panel's frame [m].

    Returns
    -------
    triangles : (k,) int
        Triangle index in ``mesh`` (the best-fitting one for a point outside every triangle).
    bary : (k, 3) float
        Barycentric coordinates; they sum to 1 and are all >= 0 inside the panel's mesh,
        slightly negative (a linear extension) outside it.
    """
    points = array(points, "points", shape=(None, 2))
    tris = np.flatnonzero(mesh.triangle_panel == panel)
    if not len(tris):
        raise ValueError(f"panel: mesh has no triangles in panel {panel}")
    corners = mesh.vertices[mesh.triangles[tris]]
    tree = cKDTree(corners.mean(axis=1))
    k = min(_CANDIDATES, len(tris))
    _, cand = tree.query(points, k=k)
    cand = cand.reshape(len(points), k)
    c = corners[cand]
    bary = _barycentric(points[:, None, :], c[..., 0, :], c[..., 1, :], c[..., 2, :])
    best = np.argmax(bary.min(axis=2), axis=1)
    rows = np.arange(len(points))
    return tris[cand[rows, best]], bary[rows, best]


def transfer(source: GarmentMesh, values, target: GarmentMesh) -> np.ndarray:
    """Values per vertex of ``source`` interpolated at every vertex of ``target``.

    Parameters
    ----------
    source : GarmentMesh
    values : (n_source, d) float
        A value per source vertex, e.g. 3D positions [m].
    target : GarmentMesh
        A mesh of the same pattern (panels matched by name).

    Returns
    -------
    (n_target, d) float
    """
    values = array(values, "values", shape=(source.n_vertices, None))
    names = {name: i for i, name in enumerate(source.panel_names)}
    out = np.empty((target.n_vertices, values.shape[1]))
    for p, name in enumerate(target.panel_names):
        if name not in names:
            raise ValueError(f"target: panel {name!r} is not in the source mesh")
        idx = np.flatnonzero(target.vertex_panel == p)
        tri, bary = locate(source, names[name], target.vertices[idx])
        out[idx] = np.einsum("kj,kjd->kd", bary, values[source.triangles[tri]])
    edges = _edge_profiles(source, values)
    for e, name in enumerate(target.edge_names):
        if name not in edges:
            continue
        params, along = edges[name]
        on = np.flatnonzero(target.boundary_edge == e)
        at = target.boundary_param[on]
        out[target.boundary_vertices[on]] = np.stack(
            [np.interp(at, params, along[:, c]) for c in range(values.shape[1])], axis=1)
    return out


def _edge_profiles(mesh: GarmentMesh, values) -> dict:
    """(panel, edge) -> (arc-length fractions (k,) from 0 to 1, values (k, d)) along each
    pattern edge of ``mesh``, its end corner (the next edge's first vertex) included."""
    out = {}
    loops = mesh.boundary_loop
    for e, name in enumerate(mesh.edge_names):
        on = np.flatnonzero(mesh.boundary_edge == e)
        if not len(on):
            continue
        loop = np.flatnonzero(loops == loops[on[0]])
        last = on[np.argmax(mesh.boundary_param[on])]
        end = loop[(np.searchsorted(loop, last) + 1) % len(loop)]
        order = on[np.argsort(mesh.boundary_param[on])]
        params = np.r_[mesh.boundary_param[order], 1.0]
        out[name] = (params, values[mesh.boundary_vertices[np.r_[order, end]]])
    return out


def follow_edit(old_flat, new_flat, triangles, positions) -> np.ndarray:
    """3D positions moved with an edit of the flat mesh (same topology).

    Each vertex's flat displacement is mapped to 3D by the mean deformation gradient
    (flat -> 3D, (3, 2)) of its triangles, weighted by their flat areas: a hem lowered 3 cm
    in the pattern hangs 3 cm lower along the draped cloth, instead of starting compressed
    where it was.

    Parameters
    ----------
    old_flat, new_flat : (n, 2) float
        Flat vertex positions before and after the edit [m].
    triangles : (m, 3) int
    positions : (n, 3) float
        3D positions of the flat vertices before the edit [m].

    Returns
    -------
    (n, 3) float
        The moved positions [m].
    """
    old = np.asanyarray(old_flat, dtype=np.float64)
    new = np.asanyarray(new_flat, dtype=np.float64)
    tris = np.asanyarray(triangles, dtype=np.int64)
    x = np.asanyarray(positions, dtype=np.float64)
    n = len(old)
    if old.shape != (n, 2) or new.shape != (n, 2):
        raise ValueError(f"old_flat, new_flat: expected two ({n}, 2) arrays, got {old.shape} "
                         f"and {new.shape}")
    array(x, "positions", shape=(n, 3))
    if tris.ndim != 2 or tris.shape[1] != 3 or (len(tris) and (tris.min() < 0 or tris.max() >= n)):
        raise ValueError(f"triangles: expected (m, 3) indices in [0, {n})")
    flat = np.stack([old[tris[:, 1]] - old[tris[:, 0]], old[tris[:, 2]] - old[tris[:, 0]]], 2)
    space = np.stack([x[tris[:, 1]] - x[tris[:, 0]], x[tris[:, 2]] - x[tris[:, 0]]], 2)
    det = flat[:, 0, 0] * flat[:, 1, 1] - flat[:, 0, 1] * flat[:, 1, 0]
    ok = np.abs(det) > 0.0
    inv = np.zeros_like(flat)
    inv[ok, 0, 0], inv[ok, 1, 1] = flat[ok, 1, 1] / det[ok], flat[ok, 0, 0] / det[ok]
    inv[ok, 0, 1], inv[ok, 1, 0] = -flat[ok, 0, 1] / det[ok], -flat[ok, 1, 0] / det[ok]
    area = 0.5 * np.abs(det)
    grad = (space @ inv) * area[:, None, None]
    mean = np.zeros((n, 3, 2))
    weight = np.zeros(n)
    for k in range(3):
        np.add.at(mean, tris[:, k], grad)
        np.add.at(weight, tris[:, k], area)
    used = weight > 0
    mean[used] /= weight[used, None, None]
    return x + np.einsum("nij,nj->ni", mean, new - old)
