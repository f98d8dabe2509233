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
from .symmetry import other_side
from .widen import _outward_normal

#: a free edge is a limb's hem when at least this share of its mesh vertices lie on the
#: limb: a cuff or a trouser hem lies all on it; a skirt's or a coat's hem, across both
#: legs, half on each (such a hem is not a limb's, and its height is not kept)
ON_LIMB = 0.75


def hem_edges(pattern, mesh: GarmentMesh, positions, vertex_region, body,
              limb: str) -> dict[str, str]:
    """The hem of ``limb`` (a key of :data:`~patternfit.fit.lengths.LIMBS`) on each panel
    that has one: panel name → the name of its free outline edge (no seam sews it) whose
    mesh vertices lie mostly on the limb (``vertex_region`` (n,), indices into
    :data:`~patternfit.fit.body_regions.REGIONS`, at the drape ``positions`` (n, 3) [m])
    and reach farthest along its axis (``body``'s landmark)."""
    sewn = {(side.panel, side.edge) for s in pattern.seams for side in (s.a, s.b)}
    x = np.asanyarray(positions, dtype=np.float64)
    axis, names = LIMBS[limb]
    on = np.isin(np.asanyarray(vertex_region), [REGIONS.index(n) for n in names])
    a, b = (np.asanyarray(v, dtype=np.float64) for v in body.landmarks[axis])
    out = {}
    for pname in mesh.panel_names:
        far = -np.inf
        for edge in pattern.panel(pname).outline.edges:
            if (pname, edge.name) in sewn:
                continue
            ids, _ = mesh.edge_vertices(pname, edge.name)
            reach = float(((x[ids] - a) @ (b - a)).mean())
            if on[ids].mean() >= ON_LIMB and reach > far:
                out[pname], far = edge.name, reach
    return out


def hem_moves(pattern, mesh: GarmentMesh, positions, vertex_region, body,
              rises: dict) -> dict:
    """Corner offsets ``{(panel, edge): (2,) [m]}`` that lengthen each limb of ``rises``
    (limb → how far its end rose [m], :func:`~patternfit.fit.lengths.risen`) at its hem
    (:func:`hem_edges`, same arguments): both corners of the hem move out along its
    outward normal by the rise. Both sides alike: a limb is lengthened with its left/right
    partner by the larger rise (the symmetry's mean would halve a move asked on one side
    only)."""
    out: dict = {}
    both: dict = {}
    for limb, rise in rises.items():
        for side in filter(None, (limb, other_side(limb))):
            both[side] = max(both.get(side, 0.0), rise)
    for limb, rise in both.items():
        for pname, ename in hem_edges(pattern, mesh, positions, vertex_region, body,
                                      limb).items():
            edges = [e.name for e in pattern.panel(pname).outline.edges]
            ids, _ = mesh.edge_vertices(pname, ename)
            d = float(rise) * _outward_normal(mesh, ids)
            for key in ((pname, ename),
                        (pname, edges[(edges.index(ename) + 1) % len(edges)])):
                out[key] = out.get(key, 0.0) + d
    return out


__all__ = ["hem_edges", "hem_moves"]
