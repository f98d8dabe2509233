"""Triangle quality measures for flat meshes."""

from __future__ import annotations

import numpy as np


def triangle_angles(vertices, triangles) -> np.ndarray:
    """Interior angles of every triangle.

    Parameters
    ----------
    vertices : (n, 2) or (n, 3) float
        Positions [m].
    triangles : (m, 3) int
        Vertex indices.

    Returns
    -------
    (m, 3) float
        The angle at each corner [degrees].
    """
    v = np.asanyarray(vertices, dtype=np.float64)
    t = np.asanyarray(triangles)
    p = v[t]
    out = np.empty(t.shape)
    for k in range(3):
        a = p[:, (k + 1) % 3] - p[:, k]
        b = p[:, (k + 2) % 3] - p[:, k]
        cos = np.einsum("ij,ij->i", a, b) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
        out[:, k] = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
    return out


def min_angle(vertices, triangles) -> float:
    """Smallest interior angle over all triangles [degrees]."""
    return float(triangle_angles(vertices, triangles).min())
