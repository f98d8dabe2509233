"""Notches between a DXF file and a panel: the file's notch marks (layer 4) placed on the
panel's edges as :class:`~patternfit.pattern.model.Notch` (edge, arc-length fraction), and
back to slits on the edges for writing.

A notch mark is a short LINE from the cut line into the fabric (or a POINT); its end nearest
the panel's loops marks the place. With the sew line as the outline the mark lies on the cut
line, up to the seam allowance away, and is carried across to the sew line (nearest point).
A notch at a turn point is at ``t = 0`` of the edge that starts there.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..constants import tol
from .model import Notch, Panel, Pattern

__all__ = ["notch_marks", "notch_slits", "notches_on"]

#: samples per edge when placing a notch (refined on the nearest segment) [-]
_SAMPLES = 401


def notches_on(panel: Panel, marks: list[np.ndarray], reach: float) -> tuple[Notch, ...]:
    """The notch marks (each (2, 2): its two ends [m]) that lie within ``reach`` [m] of an
    edge of ``panel`` (outline or inner loop), as notches on that edge; marks further away
    are left out. Sorted by edge order and position."""
    if not marks:
        return ()
    edges = [e for loop in panel.loops for e in loop.edges]
    f = np.linspace(0.0, 1.0, _SAMPLES)
    samples = np.concatenate([e.point_at(f) for e in edges])
    tree = cKDTree(samples)
    ends = np.concatenate(marks).reshape(-1, 2)
    dist, idx = tree.query(ends)
    out = {}
    for k in range(len(marks)):
        j = 2 * k + int(dist[2 * k + 1] < dist[2 * k])
        if dist[j] > reach:
            continue
        ei, si = divmod(int(idx[j]), _SAMPLES)
        edge = edges[ei]
        # refine on the two sample segments around the nearest sample
        best, t = np.inf, f[si]
        for a in (si - 1, si):
            if not 0 <= a < _SAMPLES - 1:
                continue
            p, q = samples[ei * _SAMPLES + a], samples[ei * _SAMPLES + a + 1]
            d = q - p
            u = float(np.clip((ends[j] - p) @ d / max(d @ d, 1e-300), 0.0, 1.0))
            gap = float(np.linalg.norm(p + u * d - ends[j]))
            if gap < best:
                best, t = gap, f[a] + u * (f[a + 1] - f[a])
        snap = tol.dxf_fit / max(edge.length, 1e-300)
        if t >= 1.0 - snap:  # at the turn point where the next edge starts
            loop = next(lp for lp in panel.loops if edge in lp.edges)
            k_next = (loop.edges.index(edge) + 1) % len(loop.edges)
            edge, ei, t = loop.edges[k_next], edges.index(loop.edges[k_next]), 0.0
        elif t <= snap:
            t = 0.0
        out[(ei, round(t, 9))] = Notch(edge.name, float(t))
    return tuple(out[k] for k in sorted(out))


def _inward(panel: Panel, edge_name: str, t: float) -> tuple[np.ndarray, np.ndarray]:
    """The point at fraction ``t`` of the edge and the unit normal pointing into the fabric."""
    edge = panel.edge(edge_name)
    p, q = edge.point_at([max(t - 1e-4, 0.0), min(t + 1e-4, 1.0)])
    d = q - p
    inward = np.array([-d[1], d[0]]) / max(float(np.linalg.norm(d)), 1e-300)
    loop = next(lp for lp in panel.loops if any(e.name == edge_name for e in lp.edges))
    # the left of a counter-clockwise loop is its inside; fabric lies outside inner loops
    if (loop.signed_area() < 0) != (loop is not panel.outline):
        inward = -inward
    return edge.point_at([t])[0], inward


def notch_slits(panel: Panel, *, length: float = 0.006) -> list[np.ndarray]:
    """The panel's notches as slits ``length`` [m] long into the fabric: (2, 2) each, the
    point on the edge first."""
    out = []
    for n in panel.notches:
        at, inward = _inward(panel, n.edge, n.t)
        out.append(np.array([at, at + length * inward]))
    return out


def notch_marks(pattern: Pattern, *, length: float = 0.006) -> list[tuple[str, str, np.ndarray,
                                                                           np.ndarray]]:
    """Slit notches at the middle of every seam side, pointing into the fabric.

    Returns ``(panel, seam, point, inner_end)`` per notch, points (2,) [m] in the panel frame;
    the two sides of a seam get one notch each, at matching places.
    """
    out = []
    for seam in pattern.seams:
        for side in (seam.a, seam.b):
            panel = pattern.panel(side.panel)
            at, inward = _inward(panel, side.edge, 0.5 * (side.start + side.end))
            out.append((panel.name, seam.name, at, at + length * inward))
    return out
