"""Prior functions m_i(v) of maximum entropy coordinates (paper Sec. 5.1.2, METHOD.md 4).

Every prior is returned as its logarithm (up to an additive constant per point), so that
products of many small edge terms neither underflow nor lose precision.
"""

from __future__ import annotations

import numba
import numpy as np

PRIORS = ("uniform", "gaussian", "edge", "bisector", "bisector_literal")


@numba.njit(cache=True, nogil=True)
def log_edge_terms(nodes, nxt, points, bisector):  # pragma: no cover - compiled
    """log of rho_j (Hormann–Sukumar) or of the bisector t_j (paper eq. 15) for every point
    and edge j = (p_j, p_next(j)): (q, n) float; -inf on edge j.

    rho_j = |v - p_j| + |v - p_j+1| - |p_j - p_j+1| and t_j, the length of the bisector of
    the angle at v in triangle (v, p_j, p_j+1), in the cancellation-free forms of METHOD.md
    section 4. One pass per point (NumPy's temporaries cost half the solve time).
    """
    q, n = points.shape[0], nodes.shape[0]
    out = np.empty((q, n))
    for k in range(q):
        px, py = points[k, 0], points[k, 1]
        for i in range(n):
            j = nxt[i]
            sx, sy = nodes[i, 0] - px, nodes[i, 1] - py
            tx, ty = nodes[j, 0] - px, nodes[j, 1] - py
            a = np.sqrt(sx * sx + sy * sy)
            b = np.sqrt(tx * tx + ty * ty)
            d = sx * tx + sy * ty
            ab = a * b
            if d >= 0:
                abd = ab + d
            else:
                # ab + d = ab (1 + cos) cancels as the angle nears pi: use (2A)^2 / (ab - d)
                cross = sx * ty - sy * tx
                abd = cross * cross / (ab - d)
            if abd <= 0.0:
                out[k, i] = -np.inf
            elif bisector:
                out[k, i] = 0.5 * np.log(2.0 * ab * abd) - np.log(a + b)
            else:
                c = np.hypot(nodes[j, 0] - nodes[i, 0], nodes[j, 1] - nodes[i, 1])
                out[k, i] = np.log(2.0 * abd / (a + b + c))
    return out


def log_prior(prior: str, nodes: np.ndarray, nxt: np.ndarray, points: np.ndarray,
              beta: float) -> np.ndarray:
    """log m_i(v) for all points and nodes: (q, n) float (unnormalised).

    ``"edge"`` and ``"bisector"``: m_i = product over edges j not adjacent to node i of
    rho_j or t_j; ``"bisector_literal"``: m_i = t_i / sum t_j (eq. 15d as printed);
    ``"gaussian"``: exp(-beta |v - p_i|^2) (eq. 14); ``"uniform"``: 1/n (eq. 13).
    """
    if prior == "uniform":
        return np.zeros((len(points), len(nodes)))
    if prior == "gaussian":
        dx = nodes[:, 0] - points[:, 0:1]
        dy = nodes[:, 1] - points[:, 1:2]
        return -beta * (dx * dx + dy * dy)
    lg = log_edge_terms(nodes, nxt.astype(np.int64), np.ascontiguousarray(points),
                        prior != "edge")
    if prior == "bisector_literal":
        return lg
    prv = np.empty_like(nxt)
    prv[nxt] = np.arange(len(nxt))
    return lg.sum(axis=1, keepdims=True) - lg - lg[:, prv]
