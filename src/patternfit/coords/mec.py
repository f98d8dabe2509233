"""Maximum entropy coordinates (paper Sec. 5.1, eqs. 6–15) by the 2-D dual and damped Newton.

a_i(v) = m_i(v) exp(-lambda . (p_i - v)) / Z, with lambda minimising the convex dual
F(lambda) = log sum_i m_i exp(-lambda . (p_i - v)); the gradient of F vanishes exactly when
sum_i a_i (p_i - v) = 0 (linear precision).
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from ..arguments import number
from ..constants import tol
from .polygon import as_loops, as_points, boundary_weights, diameter, oriented
from .priors import PRIORS, log_prior

#: Newton stops at |sum a_i (p_i - v)| below this fraction of the outline's diameter
RESIDUAL = 1e-12
MAX_ITERATIONS = 100
_ARMIJO = 1e-4
# Trust radius on the multipliers (dimensionless: offsets are scaled by the diameter)
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


@numba.njit(cache=True, nogil=True)
def _dual_value(logm, dx, dy, lx, ly, w):  # pragma: no cover - compiled
    """F(lambda) = log sum_i m_i exp(-lambda . d_i); fills ``w`` with the weights."""
    n = logm.shape[0]
    zmax = -np.inf
    for i in range(n):
        w[i] = logm[i] - (lx * dx[i] + ly * dy[i])
        zmax = max(zmax, w[i])
    s = 0.0
    for i in range(n):
        w[i] = np.exp(w[i] - zmax)
        s += w[i]
    for i in range(n):
        w[i] /= s
    return np.log(s) + zmax


@numba.njit(cache=True, nogil=True)
def solve_dual(logm, dx, dy, residual, max_iter):  # pragma: no cover - compiled
    """Damped Newton on the dual, one point (row) at a time.

    ``logm`` (q, n) log prior, ``dx, dy`` (q, n) node offsets p_i - v divided by the
    diameter. Armijo backtracking inside a trust radius on lambda (dimensionless): where the
    weights collapse onto collinear nodes the Hessian is nearly singular and a full Newton
    step would leap to a flat region of the dual. Returns weights (q, n), iterations (q,)
    and residuals |sum a_i d_i| (q,).
    """
    q, n = logm.shape
    out = np.empty((q, n))
    iters = np.zeros(q, dtype=np.int64)
    res = np.empty(q)
    trial = np.empty(n)
    eps = 8.0 * np.finfo(np.float64).eps
    for k in range(q):
        w = out[k]
        lx = ly = 0.0
        radius = _MAX_STEP
        F = _dual_value(logm[k], dx[k], dy[k], lx, ly, w)
        for it in range(max_iter + 1):
            mx = my = hxx = hxy = hyy = 0.0
            for i in range(n):
                ax, ay = w[i] * dx[k, i], w[i] * dy[k, i]
                mx += ax
                my += ay
                hxx += ax * dx[k, i]
                hxy += ax * dy[k, i]
                hyy += ay * dy[k, i]
            res[k] = np.hypot(mx, my)
            if res[k] < residual or it == max_iter:
                break
            hxx += _DAMP - mx * mx
            hxy -= mx * my
            hyy += _DAMP - my * my
            det = hxx * hyy - hxy * hxy
            sx = (hyy * mx - hxy * my) / det
            sy = (hxx * my - hxy * mx) / det
            norm = np.hypot(sx, sy)
            capped = norm > radius
            if capped:
                sx *= radius / norm
                sy *= radius / norm
            slope = -(sx * mx + sy * my)  # directional derivative of F, < 0
            t = 1.0
            for _ls in range(60):
                Fn = _dual_value(logm[k], dx[k], dy[k], lx + t * sx, ly + t * sy, trial)
                # near the solution F changes below its rounding error: allow for it
                if Fn <= F + _ARMIJO * t * slope + eps * (1.0 + abs(F)):
                    break
                t *= 0.5
            lx += t * sx
            ly += t * sy
            F = Fn
            w[:] = trial
            # trust radius: grow while capped steps succeed outright, else shrink to the step
            if t == 1.0:
                if capped:
                    radius *= 4.0
            else:
                radius = max(t * min(norm, radius), _MAX_STEP)
            iters[k] += 1
    return out, iters, res


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
    else:
        number(beta, "beta", low=0.0, low_open=True, rule="expected a positive number [1/m^2]")
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
        w[free], iters[free], res[free] = solve_dual(logm, dx, dy, RESIDUAL, MAX_ITERATIONS)
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
