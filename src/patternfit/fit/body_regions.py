"""The body's regions a garment covers, named as a pattern maker names them, so that every
garment vertex and triangle belongs to the girth it is judged at.

A point on an arm (beyond the shoulder point along the arm axis, nearer that axis than
the torso's, and, below the armpit, outside the torso's width at its height) is on the
upper arm (``bicep_*``, the first half from shoulder to wrist) or
the forearm; any other point belongs to the torso or a leg by its height between the
body's landmark heights: above the armpit ``shoulders``; down to halfway between bust and
waist ``bust``; down to halfway between waist and hip ``waist``; down to the crotch
``hip``; below it the nearer leg's ``thigh_*`` down to the knee, then ``lower_leg_*``.
Lengths in metres.
"""

from __future__ import annotations

import numpy as np

from ..body.hands import FOREARM, HAND_REACH
from ..body.measure import cross_section

REGIONS = ("shoulders", "bust", "waist", "hip", "thigh_left", "thigh_right",
           "lower_leg_left", "lower_leg_right", "bicep_left", "bicep_right",
           "forearm_left", "forearm_right")
#: the knee's height as a share of the crotch height (knee height 0.285 and crotch height
#: 0.47 of stature in the Drillis & Contini proportions) [-]
KNEE_SHARE = 0.6
#: the upper arm is this share of the way from the shoulder point to the wrist [-]
UPPER_ARM = 0.5
#: below the armpit, the torso's half-width is read from body sections this far apart [m]
SECTION_STEP = 0.03
#: ... and a point within this of it belongs to the torso (the cloth lies on it) [m]
TORSO_MARGIN = 0.02
#: a point within this of an arm's axis continued over its hand lies over the hand [m]
#: (a hand with its thumb out reaches 9-10 cm from the axis; the torso's side 25 cm)
HAND_ZONE = 0.15


def torso_half_width(body, heights) -> np.ndarray:
    """Half the width (along x) of the body's torso section [m] at each of ``heights``
    (k,) [m] above the feet: the largest section loop's farthest point from the torso
    axis; 0 where the body has no section."""
    y0 = body.floor
    cx = float(body.landmarks["torso_axis"][0][0])
    out = np.zeros(len(heights))
    for i, h in enumerate(heights):
        loops = cross_section(body.vertices, body.faces, y0 + float(h))
        if loops:
            out[i] = float(np.abs(loops[0].points[:, 0] - cx).max())
    return out


def _segment(points, a, b) -> tuple[np.ndarray, np.ndarray]:
    """Parameter t along a→b (unclamped) and distance [m] of ``points`` (k, 3) to the
    segment a–b."""
    d = b - a
    t = (points - a) @ d / float(d @ d)
    nearest = a + np.clip(t, 0.0, 1.0)[:, None] * d
    return t, np.linalg.norm(points - nearest, axis=1)


def body_regions(points, body) -> np.ndarray:
    """The region of each point (k, 3) [m] on or around ``body``: (k,) int, an index into
    :data:`REGIONS`."""
    p = np.asanyarray(points, dtype=np.float64).reshape(-1, 3)
    m, lm = body.measurements, body.landmarks
    y0 = body.floor
    h = p[:, 1] - y0
    out = np.full(len(p), REGIONS.index("hip"))
    out[h > 0.5 * (m["waist_height"] + m["hip_height"])] = REGIONS.index("waist")
    out[h > 0.5 * (m["bust_height"] + m["waist_height"])] = REGIONS.index("bust")
    out[h > m["armpit_height"]] = REGIONS.index("shoulders")
    legs = h < m["crotch_height"]
    if legs.any():
        dist = [np.linalg.norm(p[legs][:, [0, 2]] - lm[f"leg_axis_{s}"][0][[0, 2]], axis=1)
                for s in ("left", "right")]
        side = np.where(dist[0] <= dist[1], "left", "right")
        low = h[legs] < KNEE_SHARE * m["crotch_height"]
        names = np.where(low, np.char.add("lower_leg_", side), np.char.add("thigh_", side))
        out[legs] = [REGIONS.index(str(n)) for n in names]
    ta, tb = lm["torso_axis"]
    _, torso = _segment(p, np.asanyarray(ta, float), np.asanyarray(tb, float))
    levels = np.arange(m["crotch_height"], m["armpit_height"] + SECTION_STEP, SECTION_STEP)
    half = np.interp(h, levels, torso_half_width(body, levels))
    on_torso = (h < m["armpit_height"]) & (
        np.abs(p[:, 0] - float(ta[0])) < half + TORSO_MARGIN)
    for s in ("left", "right"):
        a, b = (np.asanyarray(v, dtype=np.float64) for v in lm[f"arm_axis_{s}"])
        t, d = _segment(p, a, b)
        arm = (t > 0.0) & (d < torso) & ~on_torso
        out[arm & (t < UPPER_ARM)] = REGIONS.index(f"bicep_{s}")
        out[arm & (t >= UPPER_ARM)] = REGIONS.index(f"forearm_{s}")
    return out


def on_hands(points, body) -> np.ndarray:
    """Whether each point (k, 3) [m] lies over one of ``body``'s hands as the cloth meets
    them (its mitten, :mod:`patternfit.body.hands`): along the arm's axis past where the
    mitten begins, :data:`~patternfit.body.hands.FOREARM` up the forearm from the wrist, and
    within :data:`HAND_ZONE` of the axis continued
    :data:`~patternfit.body.hands.HAND_REACH` beyond the wrist: (k,) bool.

    Cloth there rests on the hull of the hand, a sleeve longer than the arm whose cuff, as
    narrow as a hand, stops on it: a matter of the sleeve's length (``lengths_cm``), not
    of its width (the shirt M on male_average at 3K: 14 kPa past the wrist, 2.5 kPa on the
    mitten's ramp, under 0.5 kPa along the rest of the forearm, read "too tight")."""
    p = np.asanyarray(points, dtype=np.float64).reshape(-1, 3)
    out = np.zeros(len(p), dtype=bool)
    for s in ("left", "right"):
        shoulder, wrist = (np.asanyarray(v, dtype=np.float64)
                           for v in body.landmarks[f"arm_axis_{s}"])
        axis = (wrist - shoulder) / np.linalg.norm(wrist - shoulder)
        t, d = _segment(p, wrist - FOREARM * axis, wrist + HAND_REACH * axis)
        out |= (t >= 0.0) & (t <= 1.0) & (d < HAND_ZONE)
    return out
