"""A let-out stops at the style's ease range: the correction's moves must not widen a
girth past the most ease its garment type allows (:func:`~patternfit.fit.verdict_rules.
ease_range`; beyond it the verdict reads loose, then too loose).

A girth's growth under a set of moves is read on the flat pattern: on each panel, the
width across the grain of the outline's stretch that holds the panel's axis, at the
median height along the grain of the girth's body region there, after the moves minus
before, summed over the panels. Corners whose moves alone widen a girth that has no room
left are scaled down together until the girth's growth fits in its room (nothing, once
its ease is at the most). Lengths in metres, ease in cm.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..edit import move_corner
from ..fit.measures import FitMeasures
from ..fit.verdict_rules import ease_range
from ..mesh.garment import GarmentMesh
from ..pattern.model import Pattern

#: region verdicts whose girth is never held back
TIGHT = ("too tight", "tight")
#: a corner whose move alone widens a girth by less than this does not feed it [m]
FEEDS = 1e-3


def width_at(outline, grain, height: float, axis: float) -> float | None:
    """Width [m] across the grain of the stretch of the closed polygon ``outline`` (k, 2)
    [m] at ``height`` along ``grain`` (2,) that holds ``axis`` (its coordinate across the
    grain), or the widest stretch when none holds it; None where the line misses it."""
    g = np.asanyarray(grain, dtype=np.float64)
    c = np.array([-g[1], g[0]])
    p = np.asanyarray(outline, dtype=np.float64)
    q = np.roll(p, -1, axis=0)
    hp, hq = p @ g - height, q @ g - height
    cut = (hp > 0) != (hq > 0)
    if not cut.any():
        return None
    w = hp[cut] / (hp[cut] - hq[cut])
    xs = np.sort(((1 - w)[:, None] * p[cut] + w[:, None] * q[cut]) @ c)
    spans = xs.reshape(-1, 2) if len(xs) % 2 == 0 else np.array([[xs[0], xs[-1]]])
    holds = [b - a for a, b in spans if a <= axis <= b]
    return float(holds[0] if holds else (spans[:, 1] - spans[:, 0]).max())


def girth_levels(mesh: GarmentMesh, measures: FitMeasures, girth: str) -> dict:
    """Panel name → (height along its grain [m], its axis across the grain [m]) of body
    region ``girth`` on that panel: the median flat height of the region's triangles there,
    and the median of the panel's outline across the grain."""
    k = list(measures.regions).index(girth)
    centroid = mesh.vertices[mesh.triangles].mean(axis=1)
    out = {}
    for pi, name in enumerate(mesh.panel_names):
        tris = (measures.triangle_region == k) & (mesh.triangle_panel == pi)
        if not tris.any():
            continue
        g = mesh.grain[pi]
        c = np.array([-g[1], g[0]])
        loop = mesh.vertices[mesh.loops(pi)[0]]
        out[name] = (float(np.median(centroid[tris] @ g)), float(np.median(loop @ c)))
    return out


def growth(before: Pattern, after: Pattern, mesh: GarmentMesh, levels: dict) -> float:
    """How much wider [m] ``after`` is than ``before`` at a girth's ``levels``
    (:func:`girth_levels`), summed over its panels."""
    total = 0.0
    for name, (height, axis) in levels.items():
        g = mesh.grain[mesh.panel_names.index(name)]
        a = width_at(before.panel(name).outline.polygon(), g, height, axis)
        b = width_at(after.panel(name).outline.polygon(), g, height, axis)
        if a is not None and b is not None:
            total += b - a
    return total


def _moved(pattern: Pattern, moves: list) -> Pattern:
    """``pattern`` with the corner ``moves`` made, unchecked (seams not closed: a width is
    all that is read)."""
    for mv in moves:
        pattern = pattern.with_panel(move_corner(pattern.panel(mv.panel), mv.edge,
                                                 np.asarray(mv.offset)))
    return pattern


def cap_moves(pattern: Pattern, mesh: GarmentMesh, measures: FitMeasures, verdict,
              moves: list) -> list:
    """Corner ``moves`` (each with ``panel``, ``edge`` and ``offset`` (2,) [m]) with those
    that widen a girth beyond the most ease of the style of ``verdict`` (a
    :class:`~patternfit.fit.verdict.Verdict` of the drape ``measures`` are of, with the
    body's girths of ``measures``) scaled down: for every girth whose ease was measured
    and whose region the verdict does not call tight or too tight (stretched cloth lacks
    fabric whatever its section's hull says: at the first drape the 3K Table 2 coat's
    sleeves, tight on the arms beside the chest, gave its bust +12 cm while the bust was
    stretched 62 %, and capping there crossed the re-drape), the moves that
    alone widen it by :data:`FEEDS` or more are scaled by room / growth when all the moves
    together widen it by more than its room (most ease − ease, at least 0); a move scaled
    to nothing is left out."""
    body = {k: s.body_cm for k, s in measures.sections.items()}
    scale = np.ones(len(moves))
    for girth, section in measures.sections.items():
        judged = verdict.regions.get(girth)
        if section.ease_cm is None or judged is None or judged.verdict in TIGHT:
            continue
        most = (ease_range(verdict.style, girth, body) or (None, None))[1]
        if most is None:
            continue
        levels = girth_levels(mesh, measures, girth)
        room = max(most - section.ease_cm, 0.0) / 100.0
        grown = growth(pattern, _moved(pattern, moves), mesh, levels)
        if grown <= room:
            continue
        feeds = np.array([growth(pattern, _moved(pattern, [mv]), mesh, levels) >= FEEDS
                          for mv in moves])
        scale[feeds] = np.minimum(scale[feeds], room / grown)
    return [mv if s == 1.0 else replace(mv, offset=(s * mv.offset[0], s * mv.offset[1]))
            for mv, s in zip(moves, scale) if s > 0.0]
