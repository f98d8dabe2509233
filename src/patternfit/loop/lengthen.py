"""Keeping a limb's length through the correction: a let-out that turned a sleeve (or a
trouser leg) up, so that its end rose along the arm by more than the length tolerance
(:attr:`~patternfit.fit.verdict_rules.VerdictRules.length_tolerance_cm`, measured by
:func:`~patternfit.fit.lengths.limb_ends` against the first drape), is answered by
lengthening that limb at its hem, as a pattern maker adds length at a cuff: the two
corners of each panel's free edge at the limb's end (the edge no seam sews whose drape
lies farthest along the limb, the cuff) move out along that edge's outward normal by
the rise. The moves go through the correction's machinery (sewn corners shared, mirror
symmetry kept, ``close_seams``, ``check_pattern``) as recorded ``move_point`` edits.
Lengths in metres.
"""

from __future__ import annotations

import numpy as np

from ..fit.body_regions import REGIONS
from ..fit.lengths import LIMBS
from ..mesh.garment import GarmentMesh
from .widen import _outward_normal

#: a free edge is at a limb when at least this share of its mesh vertices lie on it [-]
ON_LIMB = 0.5


def hem_moves(pattern, mesh: GarmentMesh, positions, vertex_region, body,
              rises: dict) -> dict:
    """Corner offsets ``{(panel, edge): (2,) [m]}`` that lengthen each limb of ``rises``
    (limb → how far its end rose [m], :func:`~patternfit.fit.lengths.risen`) at its hem:
    on every panel, the free outline edge whose mesh vertices lie mostly on the limb
    (``vertex_region`` (n,), indices into :data:`~patternfit.fit.body_regions.REGIONS`, at
    the drape ``positions`` (n, 3) [m]) and reach farthest along its axis (``body``'s
    landmark) has both its corners moved out along its outward normal by the rise. Both
    sides alike: a limb is lengthened with its left/right partner by the larger rise (the
    symmetry's mean would halve a move asked on one side only)."""
    sewn = {(side.panel, side.edge) for s in pattern.seams for side in (s.a, s.b)}
    x = np.asanyarray(positions, dtype=np.float64)
    region = np.asanyarray(vertex_region)
    out: dict = {}
    both = {}
    for limb, rise in rises.items():
        for side in (limb, _partner(limb)):
            both[side] = max(both.get(side, 0.0), rise)
    for limb, rise in both.items():
        axis, names = LIMBS[limb]
        on = np.isin(region, [REGIONS.index(n) for n in names])
        a, b = (np.asanyarray(v, dtype=np.float64) for v in body.landmarks[axis])
        for pname in mesh.panel_names:
            edges = pattern.panel(pname).outline.edges
            best, far = None, -np.inf
            for k, edge in enumerate(edges):
                if (pname, edge.name) in sewn:
                    continue
                ids, _ = mesh.edge_vertices(pname, edge.name)
                if on[ids].mean() < ON_LIMB:
                    continue
                reach = float(((x[ids] - a) @ (b - a)).mean())
                if reach > far:
                    best, far = k, reach
            if best is None:
                continue
            ids, _ = mesh.edge_vertices(pname, edges[best].name)
            d = float(rise) * _outward_normal(mesh, ids)
            for key in ((pname, edges[best].name),
                        (pname, edges[(best + 1) % len(edges)].name)):
                out[key] = out.get(key, 0.0) + d
    return out


def _partner(limb: str) -> str:
    """The limb on the other side (``sleeve_left`` → ``sleeve_right``)."""
    side, other = ("_left", "_right") if limb.endswith("_left") else ("_right", "_left")
    return limb[: -len(side)] + other


__all__ = ["hem_moves"]
