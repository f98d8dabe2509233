"""Where a garment's limbs end on the body: a sleeve's end against the wrist, a trouser
leg's against the ankle, read on the drape.

A pattern maker judges length as well as width: a let-out of the chest that turns a
kimono sleeve up, so that it ends mid-forearm where it reached the wrist, is no fix. A
limb's cloth is the garment's triangles with a vertex in that limb's body regions
(:mod:`patternfit.fit.body_regions`: ``bicep_*``/``forearm_*`` for a sleeve,
``thigh_*``/``lower_leg_*`` for a trouser leg, or a coat's hem over it), sampled densely;
along the limb's axis (the body's ``arm_axis_*``: shoulder point to wrist; ``leg_axis_*``:
top of the thigh to 3 cm above the floor) it is cut in slices :data:`SLICE` long, and the
limb is covered where the slice's cloth goes around the axis (no angular gap over
:data:`MAX_GAP_DEG`). The limb's end is where the covered slices, followed down from the
first, stop: a sleeve come off the forearm and hanging from it as a flap (the 3K Table 2
coat's let-out sleeve, its underarm corner 10 cm beyond the wrist along the arm) ends
where the tube ends, not at the flap's corner. Its length is read as how far that end
stops short of the axis' end. Lengths in metres inside; the report is in cm.
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
#: the slices along the limb's axis the cover is judged in [m]
SLICE = 0.02
#: a slice is covered when its cloth leaves no gap around the axis wider than this [deg]
#: (a flap hanging from one side of the arm covers at most half of it)
MAX_GAP_DEG = 120.0
#: barycentric points each triangle is sampled at (its corners, edge midpoints, centroid
#: and the points between): a 3K coat's triangles are 4–5 cm across, wider than a slice
_SAMPLES = np.array([(i, j, 4 - i - j) for i in range(5) for j in range(5 - i)]) / 4.0


def _largest_gap(angles) -> float:
    """The widest empty arc [rad] between ``angles`` (k,) [rad] around a circle."""
    a = np.sort(np.mod(angles, 2 * np.pi))
    return float(np.max(np.diff(np.concatenate([a, [a[0] + 2 * np.pi]]))))


def covered_reach(points, a, b) -> float | None:
    """How far [m] along the axis a→b (3,) the cloth sampled at ``points`` (k, 3) [m]
    goes all around it (:data:`SLICE`, :data:`MAX_GAP_DEG`): from the first covered slice,
    the farthest point of the last one before an uncovered slice; None when no slice is covered."""
    d = (b - a) / np.linalg.norm(b - a)
    n1 = np.cross(d, [1.0, 0.0, 0.0] if abs(d[0]) < 0.9 else [0.0, 1.0, 0.0])
    n1 /= np.linalg.norm(n1)
    n2 = np.cross(d, n1)
    r = np.asanyarray(points, dtype=np.float64) - a
    t = r @ d
    angle = np.arctan2(r @ n2, r @ n1)
    k = np.floor(t / SLICE).astype(int)
    end = None
    for s in range(int(k.min()), int(k.max()) + 1):
        here = k == s
        if here.sum() > 2 and _largest_gap(angle[here]) <= np.radians(MAX_GAP_DEG):
            end = float(t[here].max())
        elif end is not None:
            break
    return end


def limb_ends(positions, triangles, vertex_region, body) -> dict[str, float]:
    """How far each limb's cloth stops short of the limb's end [m], per limb of
    :data:`LIMBS` the garment covers: ``positions`` (n, 3) [m] the drape, ``triangles``
    (m, 3) int, ``vertex_region`` (n,) int its vertices' body regions (indices into
    :data:`~patternfit.fit.body_regions.REGIONS`), ``body`` with the axis landmarks.
    Positive: the sleeve ends that far above the wrist (along the arm); negative: beyond
    it."""
    x = np.asanyarray(positions, dtype=np.float64)
    tri = np.asanyarray(triangles)
    region = np.asanyarray(vertex_region)
    out = {}
    for limb, (axis, names) in LIMBS.items():
        on = np.isin(region, [REGIONS.index(n) for n in names])
        if on.sum() < MIN_VERTICES or axis not in body.landmarks:
            continue
        a, b = (np.asanyarray(v, dtype=np.float64) for v in body.landmarks[axis])
        mine = tri[on[tri].any(axis=1)]
        reach = covered_reach(np.einsum("sk,mkd->msd", _SAMPLES, x[mine]).reshape(-1, 3),
                              a, b)
        if reach is not None:
            out[limb] = float(np.linalg.norm(b - a)) - reach
    return out


def risen(before: dict, after: dict, tolerance: float) -> dict[str, float]:
    """The limbs whose end rose (stops shorter of the limb's end) by more than
    ``tolerance`` [m] from ``before`` to ``after`` (both as :func:`limb_ends` gives them):
    limb → how far it rose [m]."""
    return {k: after[k] - before[k] for k in before
            if k in after and after[k] - before[k] > tolerance}


__all__ = ["LIMBS", "limb_ends", "risen"]
