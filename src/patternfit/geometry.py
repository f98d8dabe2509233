"""Ground-floor geometry shared by every stage: areas, mesh edges and hinges, rotations.

Imports only numpy and trimesh. Where trimesh has the function and gives the same numbers
it is used (triangle areas from cross products); where its result would differ (trimesh's
``align_vectors`` is an SVD rotation, not the smallest one; its edge groupings come in hash
order) the function is written here, so that meshes, drapes and ϖ stay bit for bit what they
were. Lengths in metres; triangles are ``(m, 3)`` vertex indices, edge ``k`` of a triangle
running from its corner ``k`` to corner ``k + 1``.
"""

from __future__ import annotations

import math

import numpy as np
import trimesh

__all__ = ["counter_clockwise", "euler_xyz_matrix", "face_adjacency", "face_cross", "hinges",
           "interior_edges", "polygon_area", "rotation_between", "signed_areas",
           "triangle_areas", "unique_edges"]


# -- areas -------------------------------------------------------------------------------------
def polygon_area(points) -> float:
    """Signed area of a closed polygon ``points`` (k, 2) [m^2] (shoelace formula, last point
    not repeated), positive when it runs counter-clockwise."""
    p = np.asanyarray(points, dtype=np.float64)
    q = np.roll(p, -1, axis=0)
    return 0.5 * float(np.sum(p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]))


def signed_areas(vertices, triangles) -> np.ndarray:
    """(m,) float: signed flat areas [m^2] of triangles over 2D ``vertices`` (n, 2),
    negative for clockwise (inverted) ones."""
    v = np.asanyarray(vertices, dtype=np.float64)
    t = np.asanyarray(triangles)
    e1 = v[t[:, 1]] - v[t[:, 0]]
    e2 = v[t[:, 2]] - v[t[:, 0]]
    return 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])


def face_cross(vertices, triangles) -> np.ndarray:
    """(m, 3) float: ``(v1 - v0) x (v2 - v0)`` of every triangle over 3D ``vertices``: the
    face normal scaled by twice the area (not normalised)."""
    v = np.asanyarray(vertices, dtype=np.float64)
    t = np.asanyarray(triangles)
    return np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])


def triangle_areas(vertices, triangles) -> np.ndarray:
    """Unsigned areas of triangles in 2D or 3D.

    Parameters
    ----------
    vertices : (n, 2) or (n, 3) float
        Positions [m].
    triangles : (m, 3) int
        Vertex indices.

    Returns
    -------
    (m,) float
        Areas [m^2].
    """
    v = np.asanyarray(vertices, dtype=np.float64)
    t = np.asanyarray(triangles)
    if v.shape[1] == 2:
        return np.abs(signed_areas(v, t))
    return trimesh.triangles.area(crosses=face_cross(v, t))


def longest_edges(corners) -> np.ndarray:
    """Longest edge (m,) [m] of each triangle of ``corners`` (m, 3, 2) or (m, 3, 3) [m]."""
    c = np.asanyarray(corners, dtype=np.float64)
    return np.linalg.norm(c - np.roll(c, 1, axis=1), axis=2).max(axis=1)


def inner_grid(k: int) -> np.ndarray:
    """Barycentric coordinates (q, 3) of the nodes strictly inside a triangle's grid of ``k``
    steps a side, ``(i, j, k - i - j) / k`` with all three >= 1 (none for k < 3)."""
    i, j = np.meshgrid(np.arange(1, k), np.arange(1, k), indexing="ij")
    inner = (i + j < k).ravel()
    i, j = i.ravel()[inner], j.ravel()[inner]
    return np.c_[i, j, k - i - j] / k


def counter_clockwise(vertices, triangles) -> np.ndarray:
    """``triangles`` (m, 3) over 2D ``vertices`` with every clockwise one turned over (its
    last two corners swapped), so that all run counter-clockwise."""
    t = np.array(triangles)
    cw = signed_areas(vertices, t) < 0
    t[cw] = t[cw][:, [0, 2, 1]]
    return t


# -- mesh topology -----------------------------------------------------------------------------
def _half_edges(triangles):
    """Every triangle edge (``3 t + k`` is edge ``k`` of triangle ``t``) sorted by its
    undirected key, ties in that order: (order, sorted keys, vertex count)."""
    t = np.asanyarray(triangles).astype(np.int64, copy=False).reshape(-1, 3)
    a = t.ravel()
    b = t[:, [1, 2, 0]].ravel()
    n = int(t.max()) + 1 if t.size else 1
    key = np.minimum(a, b) * n + np.maximum(a, b)
    order = np.argsort(key, kind="stable")
    return order, key[order], n


def unique_edges(triangles) -> np.ndarray:
    """(e, 2) int: every edge of the mesh once, as ``(low, high)`` vertex pairs in
    lexicographic order (as ``np.unique(sorted_edges, axis=0)``)."""
    t = np.asanyarray(triangles).astype(np.int64, copy=False).reshape(-1, 3)
    a = t.ravel()
    b = t[:, [1, 2, 0]].ravel()
    n = int(t.max()) + 1 if t.size else 1
    u = np.unique(np.minimum(a, b) * n + np.maximum(a, b))
    return np.stack([u // n, u % n], axis=1)


def boundary_edges(triangles) -> np.ndarray:
    """(b, 2) int: the edges used by exactly one of ``triangles`` (m, 3), as ``(low, high)``
    vertex pairs in lexicographic order: the outline of a set of triangles."""
    _, keys, n = _half_edges(triangles)
    u, count = np.unique(keys, return_counts=True)
    u = u[count == 1]
    return np.stack([u // n, u % n], axis=1)


def face_adjacency(triangles) -> np.ndarray:
    """(k, 2) int: pairs of triangles sharing an edge, ordered by the shared edge; where more
    than two triangles share an edge, each pairs with the next one (in triangle order)."""
    order, keys, _ = _half_edges(triangles)
    same = np.flatnonzero(keys[1:] == keys[:-1])
    return np.stack([order[same] // 3, order[same + 1] // 3], axis=1)


def interior_edges(triangles) -> tuple[np.ndarray, np.ndarray]:
    """The edges shared by exactly two triangles, ordered by their ``(low, high)`` vertices.

    Returns
    -------
    faces : (h, 2) int
        The two triangles of each edge (in triangle order).
    corners : (h, 2) int
        Where the edge lies in each: it is edge ``corners[:, i]`` of triangle ``faces[:, i]``
        (from that corner to the next one).
    """
    order, keys, _ = _half_edges(triangles)
    start = np.flatnonzero(np.r_[True, keys[1:] != keys[:-1]])
    counts = np.diff(np.r_[start, len(keys)])
    two = start[counts == 2]
    h = np.stack([order[two], order[two + 1]], axis=1)
    return h // 3, h % 3


def hinges(triangles) -> np.ndarray:
    """(h, 4) int: the bending hinges of a mesh, one per edge shared by exactly two
    triangles: ``(edge start, edge end, opposite vertex in triangle 1, opposite vertex in
    triangle 2)``, the edge running as it does in triangle 1 (see :func:`interior_edges`)."""
    t = np.asanyarray(triangles).astype(np.int64, copy=False).reshape(-1, 3)
    faces, corners = interior_edges(t)
    t1, k1, t2, k2 = faces[:, 0], corners[:, 0], faces[:, 1], corners[:, 1]
    return np.stack([t[t1, k1], t[t1, (k1 + 1) % 3], t[t1, (k1 + 2) % 3],
                     t[t2, (k2 + 2) % 3]], axis=1)


# -- rotations ---------------------------------------------------------------------------------
def _smallest_rotation(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Rodrigues' rotation about ``a x b`` taking unit ``a`` onto unit ``b``; accurate for
    ``a . b >= 0`` (it divides by ``1 + a . b``)."""
    v, c = np.cross(a, b), float(a @ b)
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + k + k @ k / (1.0 + c)


def rotation_between(a, b) -> np.ndarray:
    """(3, 3) rotation turning direction ``a`` (3,) onto direction ``b`` (3,).

    The smallest rotation (about ``a x b``); for ``a = b`` the identity. When the angle is
    obtuse, ``a`` is first turned half round an axis perpendicular to it (and to ``b``) and
    then onto ``b``, which is the same rotation computed without dividing by ``1 + a . b``;
    for ``a = -b`` that axis is the coordinate axis most nearly perpendicular to ``a``
    (``-y`` onto ``+y`` is the half turn about ``x``). ``ValueError`` for a zero or non-finite
    direction.
    """
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    na, nb = float(np.linalg.norm(a)), float(np.linalg.norm(b))
    if a.shape != (3,) or b.shape != (3,) or not (0 < na < math.inf and 0 < nb < math.inf):
        raise ValueError(f"a, b: expected two non-zero finite 3-vectors, got {a!r}, {b!r}")
    a, b = a / na, b / nb
    if float(a @ b) >= 0:
        return _smallest_rotation(a, b)
    axis = np.cross(a, b)
    if not np.linalg.norm(axis) > 1e-8:
        axis = np.eye(3)[int(np.argmin(np.abs(a)))]
    axis = axis - (axis @ a) * a
    axis /= np.linalg.norm(axis)
    half_turn = 2.0 * np.outer(axis, axis) - np.eye(3)
    return _smallest_rotation(-a, b) @ half_turn


def euler_xyz_matrix(angles) -> np.ndarray:
    """Rotation matrix of XYZ Euler angles in degrees, GarmentCode's (Maya's) convention.

    angles : (3,) float, degrees. Returns (3, 3) float ``Rz @ Ry @ Rx``.
    """
    ax, ay, az = np.deg2rad(np.asarray(angles, dtype=np.float64).reshape(3))
    cx, sx, cy, sy, cz, sz = math.cos(ax), math.sin(ax), math.cos(ay), math.sin(ay), \
        math.cos(az), math.sin(az)
    rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rz @ ry @ rx
