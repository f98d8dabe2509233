"""Signed distance field of a static body on a regular grid, with trilinear lookup.

Distances are in metres, negative inside the body. The grid is ``values[i, j, k]`` at the
point ``origin + spacing * (i, j, k)``.
"""

from __future__ import annotations

import numpy as np


class DistanceField:
    """A signed distance grid with trilinear interpolation and its gradient.

    Parameters
    ----------
    origin : (3,) float
        Position of grid node (0, 0, 0) [m].
    spacing : float
        Grid step [m].
    values : (nx, ny, nz) float
        Signed distance at the nodes [m], negative inside.
    """

    def __init__(self, origin, spacing: float, values):
        self.origin = np.asanyarray(origin, dtype=np.float64).reshape(3)
        self.spacing = float(spacing)
        self.values = np.ascontiguousarray(values, dtype=np.float32)
        if self.values.ndim != 3 or min(self.values.shape) < 2:
            raise ValueError(f"values: expected a 3-D grid at least 2 nodes wide, "
                             f"got shape {self.values.shape}")
        if not self.spacing > 0:
            raise ValueError(f"spacing: must be positive, got {spacing}")

    @property
    def shape(self) -> tuple[int, int, int]:
        return self.values.shape

    def query(self, points) -> tuple[np.ndarray, np.ndarray]:
        """Distance and gradient at ``points``.

        Parameters
        ----------
        points : (n, 3) float
            Query positions [m]; points outside the grid are clamped to its border.

        Returns
        -------
        distance : (n,) float
            Signed distance [m], negative inside.
        gradient : (n, 3) float
            Gradient of the interpolated distance (approximately the outward unit normal).
        """
        p = np.asanyarray(points, dtype=np.float64).reshape(-1, 3)
        g = (p - self.origin) / self.spacing
        hi = np.array(self.values.shape) - 1
        g = np.clip(g, 0.0, hi - 1e-9)
        i0 = np.minimum(np.floor(g).astype(np.int64), hi - 1)
        f = g - i0
        v = self.values
        x, y, z = i0[:, 0], i0[:, 1], i0[:, 2]
        c = np.empty((len(p), 2, 2, 2))
        for a in (0, 1):
            for b in (0, 1):
                for e in (0, 1):
                    c[:, a, b, e] = v[x + a, y + b, z + e]
        fx, fy, fz = f[:, 0], f[:, 1], f[:, 2]
        cx = c[:, 0] * (1 - fx)[:, None, None] + c[:, 1] * fx[:, None, None]
        cxy = cx[:, 0] * (1 - fy)[:, None] + cx[:, 1] * fy[:, None]
        d = cxy[:, 0] * (1 - fz) + cxy[:, 1] * fz
        dx = c[:, 1] - c[:, 0]
        gx = ((dx[:, 0, 0] * (1 - fz) + dx[:, 0, 1] * fz) * (1 - fy)
              + (dx[:, 1, 0] * (1 - fz) + dx[:, 1, 1] * fz) * fy)
        dy = cx[:, 1] - cx[:, 0]
        gy = dy[:, 0] * (1 - fz) + dy[:, 1] * fz
        gz = cxy[:, 1] - cxy[:, 0]
        grad = np.stack([gx, gy, gz], axis=1) / self.spacing
        return d, grad
