"""Maximum entropy coordinates (paper Sec. 5.1, eqs. 6–15) by the 2-D dual and damped Newton.

a_i(v) = m_i(v) exp(-lambda . (p_i - v)) / Z, with lambda minimising the convex dual
F(lambda) = log sum_i m_i exp(-lambda . (p_i - v)); the gradient of F vanishes exactly when
sum_i a_i (p_i - v) = 0 (linear precision).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..constants import tol
from .polygon import as_loops, as_points, boundary_weights, diameter, oriented
from .priors import PRIORS, log_prior

#: Newton stops at |sum a_i (p_i - v)| below this fraction of the outline's diameter
RESIDUAL = 1e-12
MAX_ITERATIONS = 100
_ARMIJO = 1e-4
# Trust radius on the multipliers (dimensionless: offsets are scaled by the diameter). Where
# the weights collapse onto collinear nodes the Hessian is nearly singular and a full Newton
# step would leap to a flat region of the dual.
_MAX_STEP = 4.0
_DAMP = 1e-12


@dataclass(frozen=True)
class MECInfo:
    """Convergence of the Newton solve, per query point.

    iterations : (q,) int  Newton steps taken (0 for points on the boundary).
    residual : (q,) float  final |sum a_i (p_i - v)| / diameter.
    converged : (q,) bool  residual below ``RESIDUAL``.
    """

    iterations: np.ndarray
    residual: np.ndarray
    converged: np.ndarray

    @property
    def max_iterations(self) -> int:
        return int(self.iterations.max(initial=0))

    @property
    def mean_iterations(self) -> float:
        return float(self.iterations.mean()) if len(self.iterations) else 0.0


def _softmax(logm, dx, dy, lam):
    """Weights and dual value F at multipliers ``lam`` (q, 2)."""
    z = logm - (lam[:, 0:1] * dx + lam[:, 1:2] * dy)
    zmax = z.max(axis=1, keepdims=True)
    e = np.exp(z - zmax)
    s = e.sum(axis=1, keepdims=True)
    return e / s, np.log(s[:, 0]) + zmax[:, 0]


def solve_dual(logm: np.ndarray, dx: np.ndarray, dy: np.ndarray):
    """Damped Newton on the dual for every row; ``dx, dy`` (q, n) are (p_i - v)/diameter.

    Returns the weights (q, n), iterations (q,) and residuals (q,).
    """
    q = len(logm)
    lam = np.zeros((q, 2))
    a, F = _softmax(logm, dx, dy, lam)
    iters = np.zeros(q, dtype=np.int64)
    res = np.full(q, np.inf)
    radius = np.full(q, _MAX_STEP)
    active = np.arange(q)
    for _ in range(MAX_ITERATIONS + 1):
        aa, ddx, ddy = a[active], dx[active], dy[active]
        mx, my = (aa * ddx).sum(axis=1), (aa * ddy).sum(axis=1)
        res[active] = np.hypot(mx, my)
        keep = res[active] >= RESIDUAL
        active = active[keep]
        if not len(active) or _ == MAX_ITERATIONS:
            break
        aa, ddx, ddy, mx, my = aa[keep], ddx[keep], ddy[keep], mx[keep], my[keep]
        hxx = (aa * ddx * ddx).sum(axis=1) - mx * mx + _DAMP
        hxy = (aa * ddx * ddy).sum(axis=1) - mx * my
        hyy = (aa * ddy * ddy).sum(axis=1) - my * my + _DAMP
        det = hxx * hyy - hxy * hxy
        step = np.stack([hyy * mx - hxy * my, hxx * my - hxy * mx], axis=1) / det[:, None]
        norm = np.hypot(step[:, 0], step[:, 1])
        capped = norm > radius[active]
        step[capped] *= (radius[active][capped] / norm[capped])[:, None]
        slope = -(step[:, 0] * mx + step[:, 1] * my)  # directional derivative of F, < 0
        s = np.ones(len(active))
        todo = np.arange(len(active))
        for _ls in range(40):
            rows = active[todo]
            trial = lam[rows] + s[todo, None] * step[todo]
            an, Fn = _softmax(logm[rows], dx[rows], dy[rows], trial)
            # near the solution F changes below its rounding error: allow for it
            slack = 8 * np.finfo(float).eps * (1.0 + np.abs(F[rows]))
            ok = Fn <= F[rows] + _ARMIJO * s[todo] * slope[todo] + slack
            lam[rows[ok]] = trial[ok]
            a[rows[ok]] = an[ok]
            F[rows[ok]] = Fn[ok]
            todo = todo[~ok]
            if not len(todo):
                break
            s[todo] *= 0.5
        # trust radius: grow while capped steps succeed outright, shrink to what was taken
        full = s == 1.0
        radius[active] = np.where(full & capped, 4.0 * radius[active],
                                  np.where(full, radius[active],
                                           np.maximum(s * np.minimum(norm, radius[active]),
                                                      _MAX_STEP)))
        iters[active] += 1
    return a, iters, res


def max_entropy_coordinates(outline, points, *, prior="bisector", beta=None,
                            return_info=False):
    """Maximum entropy coordinates of ``points`` with respect to a closed outline.

    Parameters
    ----------
    outline : (n, 2) float
        Outline nodes in either orientation [m].
    points : (q, 2) float
        Query points [m], inside the outline (they must lie in its convex hull for the
        coordinates to exist).
    prior : {"uniform", "gaussian", "edge", "bisector", "bisector_literal"}
        ``"bisector"``: the paper's angle-bisector prior in Hormann's product form
        (default; Lagrange and edge-linear on the boundary); ``"bisector_literal"``: eq. 15d
        as printed, t_i / sum t_j (lacks those properties, kept for comparison); ``"edge"``:
        Hormann–Sukumar; ``"gaussian"``: exp(-beta |v - p_i|^2); ``"uniform"``.
    beta : float, optional
        Gaussian prior width [1/m^2]; default 4 / diameter^2.
    return_info : bool
        Also return a :class:`MECInfo` with iteration counts and residuals.

    Returns
    -------
    (q, n) float
        Non-negative weights summing to 1 that reproduce each point; columns follow the
        caller's node order. Points within ``tol.merge`` of the outline take the exact edge
        interpolation. With ``return_info``, ``(weights, info)``.

    Raises
    ------
    ValueError
        For bad arguments, or points where Newton does not converge (outside the hull).
    """
    if prior not in PRIORS:
        raise ValueError(f"prior: expected one of {PRIORS}, got {prior!r}")
    (poly,) = as_loops([outline], "outline")
    pts = as_points(points, "points")
    nodes, nxt, order = oriented([poly])
    diam = diameter(nodes)
    if beta is None:
        beta = 4.0 / diam**2
    elif not (np.isfinite(beta) and beta > 0):
        raise ValueError(f"beta: expected a positive number [1/m^2], got {beta!r}")
    on, wb = boundary_weights(nodes, nxt, pts, eps=tol.merge)
    w = np.empty((len(pts), len(nodes)))
    w[on] = wb
    iters = np.zeros(len(pts), dtype=np.int64)
    res = np.zeros(len(pts))
    free = np.flatnonzero(~on)
    if len(free):
        pf = pts[free]
        logm = log_prior(prior, nodes, nxt, pf, beta)
        dx = (nodes[:, 0] - pf[:, 0:1]) / diam
        dy = (nodes[:, 1] - pf[:, 1:2]) / diam
        w[free], iters[free], res[free] = solve_dual(logm, dx, dy)
    converged = res < RESIDUAL
    if not converged.all():
        bad = np.flatnonzero(~converged)
        raise ValueError(f"points: maximum entropy coordinates did not converge at {len(bad)} "
                         f"point(s), first {pts[bad[0]].tolist()} (outside the outline's "
                         "convex hull?)")
    out = np.empty_like(w)
    out[:, order] = w
    if return_info:
        return out, MECInfo(iters, res, converged)
    return out
