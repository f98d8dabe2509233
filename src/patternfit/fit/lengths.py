"""Where a garment's limbs end on the body: a sleeve's end against the wrist, a trouser
leg's against the ankle, read on the drape.

A pattern maker judges length as well as width: a let-out of the chest that turns a
kimono sleeve up, so that it ends mid-forearm where it reached the wrist, is no fix. Each
limb's end is the farthest garment vertex of that limb's body regions
(:mod:`patternfit.fit.body_regions`: ``bicep_*``/``forearm_*`` for a sleeve,
``thigh_*``/``lower_leg_*`` for a trouser leg) along the limb's axis (the body's
``arm_axis_*``: shoulder point to wrist; ``leg_axis_*``: top of the thigh to 3 cm above the
floor); its length is read as how far that end stops short of the axis' end, along the
axis. Lengths in metres inside; the report is in cm.
"""

from __future__ import annotations

import numpy as np

from .body_regions import REGIONS

#: limb → (the body's axis landmark, the body regions its cloth lies in)
LIMBS = {
    "sleeve_left": ("arm_axis_left", ("bicep_left", "forearm_left")),
    "sleeve_right": ("arm_axis_right", ("bicep_right", "forearm_right")),
    "leg_left": ("leg_axis_left", ("thigh_left", "lower_leg_left")),
    "leg_right": ("leg_axis_right", ("thigh_right", "lower_leg_right")),
}
#: a limb with fewer garment vertices than this on it is not covered (a few vertices of
#: a bodice's side read as on the upper arm)
MIN_VERTICES = 8


def limb_ends(positions, vertex_region, body) -> dict[str, float]:
    """How far each limb's cloth stops short of the limb's end [m], per limb of
    :data:`LIMBS` the garment covers: ``positions`` (n, 3) [m] the drape, ``vertex_region``
    (n,) int its vertices' body regions (indices into
    :data:`~patternfit.fit.body_regions.REGIONS`), ``body`` with the axis landmarks.
    Positive: the sleeve ends that far above the wrist (along the arm); negative: beyond
    it."""
    x = np.asanyarray(positions, dtype=np.float64)
    region = np.asanyarray(vertex_region)
    out = {}
    for limb, (axis, names) in LIMBS.items():
        on = np.isin(region, [REGIONS.index(n) for n in names])
        if on.sum() < MIN_VERTICES or axis not in body.landmarks:
            continue
        a, b = (np.asanyarray(v, dtype=np.float64) for v in body.landmarks[axis])
        length = float(np.linalg.norm(b - a))
        reach = float(((x[on] - a) @ (b - a)).max()) / length
        out[limb] = length - reach
    return out


def risen(before: dict, after: dict, tolerance: float) -> dict[str, float]:
    """The limbs whose end rose (stops shorter of the limb's end) by more than
    ``tolerance`` [m] from ``before`` to ``after`` (both as :func:`limb_ends` gives them):
    limb → how far it rose [m]."""
    return {k: after[k] - before[k] for k in before
            if k in after and after[k] - before[k] > tolerance}


__all__ = ["LIMBS", "limb_ends", "risen"]
