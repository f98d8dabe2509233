"""Prior functions m_i(v) of maximum entropy coordinates (paper Sec. 5.1.2, METHOD.md 4).

Every prior is returned as its logarithm (up to an additive constant per point), so that
products of many small edge terms neither underflow nor lose precision.
"""

from __future__ import annotations

import numpy as np

PRIORS = ("uniform", "gaussian", "edge", "bisector", "bisector_literal")


def edge_terms(nodes: np.ndarray, nxt: np.ndarray, points: np.ndarray):
    """Per edge j = (p_j, p_next(j)) seen from each point: rho_j and the bisector t_j.

    rho_j = |v - p_j| + |v - p_j+1| - |p_j - p_j+1| (Hormann–Sukumar) and t_j the length of
    the bisector of the angle at v in triangle (v, p_j, p_j+1) (paper eq. 15), both in the
    cancellation-free forms of METHOD.md section 4. Both vanish on edge j.

    Returns
    -------
    rho, t : (q, n) float
    """
    sx = nodes[:, 0] - points[:, 0:1]
    sy = nodes[:, 1] - points[:, 1:2]
    a = np.hypot(sx, sy)
    b = a[:, nxt]
    d = sx * sx[:, nxt] + sy * sy[:, nxt]
    cross = sx * sy[:, nxt] - sy * sx[:, nxt]
    ab = a * b
    with np.errstate(divide="ignore", invalid="ignore"):
        # ab + d = (ab)(1 + cos) cancels when the angle nears pi: use (2A)^2 / (ab - d)
        abd = np.where(d >= 0, ab + d, cross * cross / (ab - d))
    e = nodes[nxt] - nodes
    c = np.hypot(e[:, 0], e[:, 1])
    rho = 2.0 * abd / (a + b + c)
    t = np.sqrt(2.0 * ab * abd) / (a + b)
    return rho, t


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
    rho, t = edge_terms(nodes, nxt, points)
    if prior == "bisector_literal":
        with np.errstate(divide="ignore"):
            return np.log(t)
    term = rho if prior == "edge" else t
    prv = np.empty_like(nxt)
    prv[nxt] = np.arange(len(nxt))
    with np.errstate(divide="ignore"):
        lg = np.log(term)
    return lg.sum(axis=1, keepdims=True) - lg - lg[:, prv]
