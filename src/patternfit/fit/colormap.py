"""The fit colour map R (METHOD.md section 3): relative area change on a diverging scale.

Dark red = tight (stretched), a neutral green = fits, light blue = loose (compressed). Values
inside the neutral band all take the neutral colour, so an isometric placement is one uniform
colour (paper Fig. 8b).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

NEUTRAL = np.array([0.60, 0.80, 0.55])  # fits
TIGHT_NEAR = np.array([0.99, 0.68, 0.38])  # just tighter than the band
TIGHT_FAR = np.array([0.40, 0.00, 0.12])  # at the range limit and beyond: dark
LOOSE_NEAR = np.array([0.45, 0.68, 0.85])  # just looser than the band
LOOSE_FAR = np.array([0.90, 0.95, 1.00])  # at the range limit and beyond: light


@dataclass(frozen=True)
class FitScale:
    """How area change maps to colour.

    Parameters
    ----------
    limit : float
        Relative area change at which the colours saturate [-] (default 0.15 = ±15 %).
    band : float
        Half-width of the neutral band [-] (default 0.02 = ±2 %, the fit-class threshold).
    """

    limit: float = 0.15
    band: float = 0.02

    def __post_init__(self):
        if not (0 <= self.band < self.limit):
            raise ValueError(f"band/limit: need 0 <= band < limit, got {self.band}, {self.limit}")

    def colors(self, change) -> np.ndarray:
        """RGB colours in [0, 1] for relative area changes: (k,) -> (k, 3) float."""
        c = np.asanyarray(change, dtype=np.float64)
        s = np.clip((np.abs(c) - self.band) / (self.limit - self.band), 0.0, 1.0)[:, None]
        tight = TIGHT_NEAR + s * (TIGHT_FAR - TIGHT_NEAR)
        loose = LOOSE_NEAR + s * (LOOSE_FAR - LOOSE_NEAR)
        out = np.where((c > self.band)[:, None], tight,
                       np.where((c < -self.band)[:, None], loose, NEUTRAL))
        return np.where(np.isfinite(c)[:, None], out, 0.5)

    def legend(self, steps: int = 7) -> list[tuple[float, np.ndarray, str]]:
        """Legend rows ``(value, rgb, label)`` from loosest to tightest."""
        rows = []
        far = np.linspace(-self.limit, -self.band, steps // 2, endpoint=False)
        near = np.linspace(self.band, self.limit, steps // 2 + 1)[1:]
        for v in far:
            rows.append((float(v), self.colors([v - 1e-12])[0], f"{v * 100:+.0f}% loose"))
        rows.append((0.0, NEUTRAL, f"fits (±{self.band * 100:.0f}%)"))
        for v in near:
            rows.append((float(v), self.colors([v])[0], f"{v * 100:+.0f}% tight"))
        return rows

    def describe(self) -> str:
        """One line for the legend's caption."""
        return (f"area change S3/S2 − 1: dark red = tight (≥ +{self.limit * 100:.0f}%), "
                f"green = fits (±{self.band * 100:.0f}%), light blue = loose "
                f"(≤ −{self.limit * 100:.0f}%)")


def vertex_values(triangles, values, n_vertices: int, weights=None) -> np.ndarray:
    """Per-vertex average of per-triangle values, weighted by ``weights`` (e.g. areas).

    Parameters
    ----------
    triangles : (m, 3) int
    values : (m,) float
    n_vertices : int
    weights : (m,) float, optional

    Returns
    -------
    (n_vertices,) float
        Vertices in no triangle get 0.
    """
    t = np.asanyarray(triangles)
    v = np.asanyarray(values, dtype=np.float64)
    w = np.ones(len(t)) if weights is None else np.asanyarray(weights, dtype=np.float64)
    num = np.bincount(t.ravel(), np.repeat(v * w, 3), minlength=n_vertices)
    den = np.bincount(t.ravel(), np.repeat(w, 3), minlength=n_vertices)
    return np.divide(num, den, out=np.zeros(n_vertices), where=den > 0)
