"""Bending hysteresis: the frictional couple of a woven fabric (SI units: m, N, J).

KES-F's pure-bending tester measures, besides the slope B of the moment-curvature loop, its
width 2HB at curvature +-0.5 1/cm [N m/m = N]: yarns and fibres slide on each other, so a
fabric bent from flat carries ``M = B kappa + HB`` (HB = 2HB / 2) and, unbent, returns along
``B kappa - HB`` (Grosberg 1966, Text. Res. J. 36(3) 205; Lahey & Heppler 2004, J. Appl.
Mech. 71, "Mechanical modeling of fabrics in bending", who fit the same two-branch law to
KES loops). A drape from a flat start bends every part of the cloth one way, so the friction
does the work ``HB |kappa|`` per area, and the static rest of that loading path is the
minimum of the elastic energy plus that work (the one-step incremental form of a
rate-independent friction). This module adds that work:

    E_f = HB sum_t A_t (sqrt(|K_t|^2 + eps^2) - eps),  |K_t|^2 = x_t^T L_t x_t / (A_t B_geo)

with ``L_t`` the triangle's share of the bending matrix (``MeshTerms.bend_local``: its
``A_t (B_warp K_uu^2 + B_weft K_vv^2 + 2 B_twist K_uv^2)``), ``B_geo = sqrt(B_warp B_weft)``
(so ``|K| = |kappa|`` for an isotropic fabric bent on a cylinder) and ``eps`` a small stick
band, :data:`STICK_BAND` times ``HB / B_geo`` (below it the couple grows linearly from zero
instead of jumping, as the stick phase of Lahey & Heppler's loop does). The energy is convex
in the positions (a norm of a linear map), so its Hessian is positive semi-definite.

Not modelled: unloading (a fold that opens again would feel ``-HB``); the drape and the
cantilever from flat load monotonically.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .energies import MeshTerms
from .fabrics import Fabric

#: stick band of the frictional couple in units of HB / B (the curvature at which the
#: elastic moment equals the frictional one): below ``STICK_BAND HB / B`` the couple rises
#: linearly; a numerical smoothing of |kappa| (measured: docs/fabrics.md)
STICK_BAND = 0.1


def couple(fabric: Fabric) -> tuple[float, float, float] | None:
    """The bending-friction law of ``fabric``: ``(HB, B_geo, eps)``, the couple 2HB / 2 [N],
    sqrt(B_warp B_weft) [N m] and the stick band [1/m]; None when it gives no 2HB."""
    two_hb = float(fabric.bending_hysteresis)
    if two_hb <= 0.0:
        return None
    rigidity = float(np.sqrt(fabric.bending_warp * fabric.bending_weft))
    moment = 0.5 * two_hb
    return moment, rigidity, STICK_BAND * moment / rigidity


@dataclass(frozen=True, eq=False)
class BendingFriction:
    """The frictional bending couple of one mesh and fabric.

    Attributes
    ----------
    local : (m, 6, 6) float
        Each triangle's bending matrix share [N/m] (``MeshTerms.bend_local``).
    ids : (m, 6) int
        Its six vertices.
    area : (m,) float
        Rest areas [m^2].
    moment : float
        The frictional couple HB = 2HB / 2 [N m/m = N].
    rigidity : float
        B_geo = sqrt(B_warp B_weft) [N m].
    eps : float
        Stick band [1/m].
    """

    local: np.ndarray
    ids: np.ndarray
    area: np.ndarray
    moment: float
    rigidity: float
    eps: float

    @classmethod
    def of(cls, terms: MeshTerms, fabric: Fabric) -> BendingFriction | None:
        """The couple of ``fabric`` (its ``bending_hysteresis`` 2HB [N]) on ``terms``; None
        when the fabric has none."""
        law = couple(fabric)
        if law is None:
            return None
        return cls(terms.bend_local, terms.bend_ids, terms.area, *law)

    def _stretch(self, x):
        """(L_t x_t per coordinate (m, 6, 3), s_t = sqrt(|K_t|^2 + eps^2) (m,))."""
        xt = x[self.ids]  # (m, 6, 3)
        lx = np.einsum("tij,tjc->tic", self.local, xt)
        q = np.einsum("tic,tic->t", xt, lx)
        s = np.sqrt(np.maximum(q, 0.0) / (self.area * self.rigidity) + self.eps ** 2)
        return lx, s

    def energy(self, x, grad=None) -> float:
        """Energy [J] at positions ``x`` (n, 3) [m]; adds its gradient [N] to ``grad``
        (n, 3) when given."""
        lx, s = self._stretch(x)
        if grad is not None:
            w = self.moment / (self.rigidity * s)
            g = (w[:, None, None] * lx).reshape(-1, 3)
            np.add.at(grad, self.ids.ravel(), g)
        return float(self.moment * np.sum(self.area * (s - self.eps)))

    def hessian(self, x, n: int) -> sp.csr_matrix:
        """A positive semi-definite bound of its Hessian (3n x 3n, ``n`` vertices, dofs
        ordered x0 y0 z0 x1 ...) [N/m] at ``x`` (n, 3) [m]: the
        weighted bending shares ``HB / (B_geo s_t) L_t`` per coordinate (the exact Hessian
        subtracts a rank-one part per triangle, so this one is at least as stiff)."""
        _, s = self._stretch(x)
        w = self.moment / (self.rigidity * s)
        vals = (w[:, None, None] * self.local).ravel()
        rows = np.repeat(self.ids, 6, axis=1).ravel()
        cols = np.tile(self.ids, (1, 6)).ravel()
        q = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
        return sp.kron(q, sp.eye(3), format="csr")
