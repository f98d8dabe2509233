"""Fit evaluation (METHOD.md section 3, paper Sec. 4): per-triangle area change and the fitting ratio.

Triangle ``t`` of the flat pattern is triangle ``t`` of the 3D garment, so every measure here is
per triangle: S2 its flat area, S3 its 3D area [m^2], γ = S2 − S3 (eq. 1), ϖ = ΣS2 / ΣS3 (eq. 2).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..arguments import array, number
from ..geometry import triangle_areas
from ..mesh.garment import GarmentMesh

#: fit classes, stored per triangle as these integers
LOOSE, FIT, TIGHT = -1, 0, 1
CLASS_NAMES = {LOOSE: "loose", FIT: "fit", TIGHT: "tight"}


@dataclass(frozen=True, eq=False)
class FitResult:
    """The fit of one 3D state of a garment mesh.

    Attributes
    ----------
    area_2d, area_3d : (m,) float
        Flat and 3D triangle areas S2, S3 [m^2].
    gamma : (m,) float
        Shape variable γ = S2 − S3 [m^2] (eq. 1): < 0 stretched (tight), > 0 compressed (loose).
    area_change : (m,) float
        Relative area change S3 / S2 − 1 [-]; the colour maps show this.
    warp, weft : (m,) float
        Stretch ratio along the panel's grainline and across it [-] (1 = unstretched).
    principal : (m, 2) float
        Principal stretches (largest first) [-].
    fit_class : (m,) int
        ``TIGHT`` (1), ``FIT`` (0) or ``LOOSE`` (-1) per triangle.
    fitting_ratio : float
        ϖ = ΣS2 / ΣS3 (eq. 2), a fraction (1.0 = 100 %).
    fitting_ratio_symmetric : float
        Σ min(S2, S3) / Σ max(S2, S3): punishes stretch and compression alike.
    panel_ratio : (p,) float
        ϖ of each panel.
    thresholds : tuple of float
        (tight, loose): area change above ``tight`` is tight, below ``-loose`` loose.
    """

    area_2d: np.ndarray
    area_3d: np.ndarray
    gamma: np.ndarray
    area_change: np.ndarray
    warp: np.ndarray
    weft: np.ndarray
    principal: np.ndarray
    fit_class: np.ndarray
    fitting_ratio: float
    fitting_ratio_symmetric: float
    panel_ratio: np.ndarray
    thresholds: tuple[float, float]

    def class_fractions(self) -> dict[str, float]:
        """Fraction of the flat fabric area in each fit class."""
        total = float(self.area_2d.sum())
        return {name: float(self.area_2d[self.fit_class == c].sum() / total)
                for c, name in CLASS_NAMES.items()}


def fit_bands(tight, loose) -> tuple[float, float]:
    """The area-change bands ``tight`` and ``loose`` [-] as floats >= 0; a ``ValueError``
    naming the one that is not a number (a bool, a string, NaN) or is negative."""
    return number(tight, "tight", low=0.0), number(loose, "loose", low=0.0)


class FitEvaluator:
    """Evaluates the fit of any 3D state of one garment mesh; the flat side is computed once.

    Parameters
    ----------
    mesh : GarmentMesh
        The flat garment.
    tight : float
        Relative area growth above which a triangle is tight [-] (default 0.02 = 2 %).
    loose : float
        Relative area loss above which a triangle is loose [-] (default 0.02).
    """

    def __init__(self, mesh: GarmentMesh, *, tight: float = 0.02, loose: float = 0.02):
        self.mesh = mesh
        self.thresholds = fit_bands(tight, loose)
        v, t = mesh.vertices, mesh.triangles
        self.tri = np.ascontiguousarray(t)
        self.area_2d = triangle_areas(v, t)
        if np.any(self.area_2d <= 0):
            raise ValueError("mesh: has degenerate triangles (zero flat area)")
        # Rest edge matrix Dm = [e1 e2] (2x2) per triangle; F = Ds Dm^-1.
        dm = np.stack([v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]], axis=2)
        self.dm_inv = np.linalg.inv(dm)
        g = mesh.grain[mesh.triangle_panel]
        self.grain = g
        self.cross = np.stack([-g[:, 1], g[:, 0]], axis=1)
        self.panel_of = mesh.triangle_panel
        self.n_panels = len(mesh.panel_names)
        self.panel_area_2d = np.bincount(self.panel_of, self.area_2d, minlength=self.n_panels)

    def metrics(self, positions) -> tuple[np.ndarray, float]:
        """The fast path: 3D areas (m,) [m^2] and ϖ, for a state (n, 3) [m]."""
        x = np.asanyarray(positions, dtype=np.float64)
        a3 = triangle_areas(x, self.tri)
        # a state collapsed to a point or a line (a failed drape) has no 3D area: ϖ is then
        # infinite, which the report's checks refuse, not a warning on the console
        with np.errstate(divide="ignore", invalid="ignore"):
            return a3, float(self.area_2d.sum() / a3.sum())

    def __call__(self, positions) -> FitResult:
        """Evaluate the fit of the 3D state ``positions`` (n, 3) [m]."""
        x = array(positions, "positions", shape=(self.mesh.n_vertices, 3), finite=True)
        t = self.tri
        a2 = self.area_2d
        a3, ratio = self.metrics(x)
        ds = np.stack([x[t[:, 1]] - x[t[:, 0]], x[t[:, 2]] - x[t[:, 0]]], axis=2)
        F = ds @ self.dm_inv  # (m, 3, 2)
        warp = np.linalg.norm(np.einsum("mij,mj->mi", F, self.grain), axis=1)
        weft = np.linalg.norm(np.einsum("mij,mj->mi", F, self.cross), axis=1)
        # singular values of F from the 2x2 matrix C = F^T F
        C = np.einsum("mki,mkj->mij", F, F)
        tr = C[:, 0, 0] + C[:, 1, 1]
        det = C[:, 0, 0] * C[:, 1, 1] - C[:, 0, 1] * C[:, 1, 0]
        disc = np.sqrt(np.maximum(0.25 * tr * tr - det, 0.0))
        principal = np.sqrt(np.maximum(np.stack([0.5 * tr + disc, 0.5 * tr - disc], 1), 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            change = a3 / a2 - 1.0
            panel_ratio = self.panel_area_2d / np.bincount(self.panel_of, a3,
                                                           minlength=self.n_panels)
        tight, loose = self.thresholds
        cls = np.where(change > tight, TIGHT, np.where(change < -loose, LOOSE, FIT))
        return FitResult(
            area_2d=a2, area_3d=a3, gamma=a2 - a3, area_change=change, warp=warp, weft=weft,
            principal=principal, fit_class=cls.astype(np.int8), fitting_ratio=ratio,
            fitting_ratio_symmetric=float(np.minimum(a2, a3).sum() / np.maximum(a2, a3).sum()),
            panel_ratio=panel_ratio, thresholds=self.thresholds)


def evaluate_fit(mesh: GarmentMesh, positions, *, tight: float = 0.02,
                 loose: float = 0.02) -> FitResult:
    """Fit of the 3D state ``positions`` (n, 3) [m] of ``mesh``; see :class:`FitEvaluator`."""
    return FitEvaluator(mesh, tight=tight, loose=loose)(positions)
