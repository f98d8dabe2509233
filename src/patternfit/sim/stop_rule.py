"""The solver's stopping rules: the force balance (the residual |F_i| / (m_i g) over the free
vertices) and the kinematic rule's drift (SI units: m, N, kg)."""

from __future__ import annotations

import numpy as np

from ..constants import GRAVITY
from . import kernels
from .model import ClothModel
from .settings import SolverSettings


def drift(x, it, marks, window) -> float:
    """Largest vertex displacement [m] of positions ``x`` (n, 3) [m] at iteration ``it``
    since the newest mark (``marks``: (iteration, positions) pairs, oldest first) at least
    ``window`` iterations old, or since the oldest mark (the start) when none is that old
    yet."""
    old = [m for i, m in marks if it - i >= window] or [marks[0][1]]
    return float(np.sqrt(((x - old[-1]) ** 2).sum(axis=1).max()))


def _ratios2(model: ClothModel, grad) -> np.ndarray:
    """(|F_i| / (m_i g))^2 [-] over the free solved vertices of mass (k,), F = -grad."""
    out = np.empty(len(grad))
    k = kernels.weight_ratios2(np.ascontiguousarray(grad, dtype=np.float64), model.mass,
                               model.free, GRAVITY, out)
    return out[:k]


def residual(model: ClothModel, grad) -> tuple[float, float]:
    """(rms, 99th percentile) of |F_i| / (m_i g) [-] over the free solved vertices, F = -grad
    ((n_solved, 3) [N]) of the energy minimised (lagged terms at their current anchors and
    pairs)."""
    return _rms_p99(_ratios2(model, grad))


def _rms_p99(r2) -> tuple[float, float]:
    """(rms, 99th percentile) of the ratios whose squares are ``r2`` (k,); 0, 0 for none."""
    if not len(r2):
        return 0.0, 0.0
    return float(np.sqrt(np.mean(r2))), float(np.percentile(np.sqrt(r2), 99))


def cone_residual(model: ClothModel, force, push, friction: float, *,
                  leave_out=None) -> tuple[float, float, float]:
    """(rms, 99th percentile, largest) of |R_i| / (m_i g) [-] over the free solved vertices but
    ``leave_out`` ((n_solved,) bool, optional), R_i the part of the force ``force``
    (n_solved, 3) [N] on each that no body contact can balance: where ``push``
    (n_solved, 3) [N] (a contact force, any size) is not zero the body may add any force
    along it and up to ``friction`` [-] times that along the surface, and R_i is the
    distance from -F_i to that cone (Coulomb's); elsewhere R_i = F_i."""
    f = np.asarray(force, dtype=np.float64)
    c = np.asarray(push, dtype=np.float64)
    size = np.linalg.norm(c, axis=1)
    touched = size > 0
    n = c[touched] / size[touched, None]
    need = -f[touched]  # what the body would have to add
    pn = np.einsum("ij,ij->i", need, n)
    pt = np.linalg.norm(need - pn[:, None] * n, axis=1)
    # inside the cone: none left; in its polar cone (the cloth pulled off the surface): all
    # of it; else the distance to the cone's side
    dist = np.where((pn >= 0.0) & (pt <= friction * pn), 0.0,
                    np.where(friction * pt <= -pn, np.hypot(pn, pt),
                             (pt - friction * pn) / np.hypot(1.0, friction)))
    left = f.copy()
    left[touched] = 0.0
    left[touched, 0] = dist
    counted = model.free if leave_out is None else model.free & ~np.asarray(leave_out, bool)
    r2 = np.empty(len(left))
    r2 = r2[:kernels.weight_ratios2(left, model.mass, np.ascontiguousarray(counted), GRAVITY,
                                    r2)]
    return (*_rms_p99(r2), float(np.sqrt(r2.max(initial=0.0))))


def residual_rms(model: ClothModel, grad) -> float:
    """rms of |F_i| / (m_i g) [-] over the free solved vertices (:func:`residual`'s first)."""
    r2 = _ratios2(model, grad)
    return float(np.sqrt(np.mean(r2))) if len(r2) else 0.0


def at_rest(model: ClothModel, grad, settings: SolverSettings) -> bool:
    """Whether the force balance of ``settings.residual_rms`` / ``residual_p99`` holds for the
    gradient ``grad`` (n_solved, 3) [N] (the p99 is computed only when the rms passes)."""
    r2 = _ratios2(model, grad)
    if not len(r2):
        return True
    if float(np.mean(r2)) > settings.residual_rms ** 2:
        return False
    return float(np.sqrt(np.percentile(r2, 99))) <= settings.residual_p99


def stalled(model: ClothModel, sewing: bool, grad, settings: SolverSettings
            ) -> tuple[bool, str]:
    """(converged, reason) when no descent step is found: at rest by the force rule, or
    (kinematic rule) whenever not sewing."""
    if sewing:
        return False, "stalled"
    if settings.stop == "force" and not at_rest(model, grad, settings):
        return False, "stalled"
    return True, "converged"


def fell(model: ClothModel, x) -> bool:
    """Whether every solved vertex at ``x`` (n, 3) [m] lies below the body's distance field
    (y up): nothing can hold the garment any more, and it would fall until the iteration
    limit (a pattern in millimetres read as metres fell 25 m in 5,000 iterations)."""
    return model.body is not None and float(x[:, 1].max()) < float(model.body.origin[1])
