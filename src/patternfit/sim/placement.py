"""Isometric placement: every panel rolled onto a vertical cylinder around the body part it
dresses (METHOD.md section 3: placement keeps areas, so ϖ = 1 before sewing).

World frame: metres, y up, the body facing +z, its left at +x.
"""

from __future__ import annotations

import math

import numpy as np

from ..mesh.garment import GarmentMesh
from ..pattern.model import Pattern

#: default axis position (x, z) [m] and radius [m] of the cylinder for each body part
PART_AXES = {
    "torso": ((0.0, 0.0), 0.17),
    "leg_left": ((0.10, 0.0), 0.09),
    "leg_right": ((-0.10, 0.0), 0.09),
    "arm_left": ((0.30, 0.0), 0.06),
    "arm_right": ((-0.30, 0.0), 0.06),
}


def roll_panel(uv, *, radius: float, side: str = "front", axis=(0.0, 0.0),
               height: float = 0.0) -> np.ndarray:
    """Roll flat points onto a vertical cylinder, isometrically (arc length = u).

    Parameters
    ----------
    uv : (k, 2) float
        Flat positions [m]; ``u = 0`` lands on the cylinder's front (or back) meridian.
    radius : float
        Cylinder radius [m].
    side : str
        ``"front"`` faces +z (the panel's +u goes to +x), ``"back"`` faces −z (its +u goes
        to −x, as seen from behind).
    axis : (2,) float
        Cylinder axis position (x, z) [m].
    height : float
        Added to the flat v coordinate to give y [m].

    Returns
    -------
    (k, 3) float
        Positions [m].
    """
    p = np.asanyarray(uv, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 2:
        raise ValueError(f"uv: expected shape (k, 2), got {p.shape}")
    if not radius > 0:
        raise ValueError(f"radius: must be positive, got {radius}")
    if side not in ("front", "back"):
        raise ValueError(f"side: expected 'front' or 'back', got {side!r}")
    s = 1.0 if side == "front" else -1.0
    ang = p[:, 0] / radius
    x = axis[0] + s * radius * np.sin(ang)
    z = axis[1] + s * radius * np.cos(ang)
    return np.stack([x, p[:, 1] + height, z], axis=1)


def place_on_cylinders(pattern: Pattern, mesh: GarmentMesh, *,
                       clearance: float = 0.03) -> np.ndarray:
    """Place every panel of ``mesh`` on a cylinder around its body part (``Panel.placement``).

    A panel is centred on the front or back meridian of its part's cylinder; the cylinder
    grows when a panel would wrap more than half way round. ``clearance`` [m] is added to
    the part's radius. Returns positions (n, 3) [m], one per flat vertex.
    """
    x = np.zeros((mesh.n_vertices, 3))
    for pi, panel in enumerate(pattern.panels):
        ids = mesh.panel_vertices(pi)
        uv = mesh.vertices[ids].copy()
        uv[:, 0] -= 0.5 * (uv[:, 0].min() + uv[:, 0].max())
        axis, r = PART_AXES.get(panel.placement.part, PART_AXES["torso"])
        width = np.ptp(uv[:, 0])
        r = max(r + clearance, width / (0.95 * math.pi))
        x[ids] = roll_panel(uv, radius=r, side=panel.placement.side, axis=axis)
    return x
