"""Body measurements and landmarks from horizontal cross-sections.

The body stands with Y up, feet on y = 0, facing +Z (its left side towards +X), in a
relaxed A-pose (arms away from the torso, legs slightly apart). Girths are what a tape
measure reads: the perimeter of the convex hull of the cross-section, so the tape bridges
the hollows (between the breasts, between the legs at hip level). All lengths in metres.

Levels are found from the topology of the cross-sections: below the crotch the section has
two large loops (the legs), between the armpits and the shoulders the arms join the torso.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import ConvexHull, QhullError

#: step between cross-sections [fraction of the height]
_STEP = 0.004
#: a loop counts as torso or leg when its hull area is at least this fraction of the largest
_BIG = 0.3
#: smaller loops than this fraction of the largest are ignored (fingers, toes)
_TINY = 0.03

#: the landmarks :func:`measure` finds on every body it accepts: points (3,) and axes (2, 3)
LANDMARKS = ("neck_base", "shoulder_left", "shoulder_right", "wrist_left", "wrist_right",
             "crotch", "bust", "waist", "hip", "torso_axis", "arm_axis_left", "arm_axis_right",
             "leg_axis_left", "leg_axis_right")
#: the measurements :func:`measure` returns [m]
MEASUREMENTS = ("height", "bust", "waist", "hip", "neck", "arm_length", "inseam",
                "shoulder_width", "bust_height", "waist_height", "hip_height", "crotch_height",
                "armpit_height", "neck_base_height")


class LandmarkError(ValueError):
    """A human landmark that cannot be found on a mesh (or is missing from a body).

    Attributes
    ----------
    landmark : str
        What is missing: a name from :data:`LANDMARKS` or :data:`MEASUREMENTS`, or the level
        the search needs (``crotch``, ``armpits``, ...).
    """

    def __init__(self, landmark: str, message: str):
        self.landmark = landmark
        super().__init__(message)


@dataclass(eq=False)
class Loop:
    """One closed curve of a horizontal cross-section.

    points : (k, 3) float, the curve's points [m]; centroid : (3,) float [m];
    girth : float, perimeter of its convex hull [m]; area : float, area of that hull [m²].
    """

    points: np.ndarray
    centroid: np.ndarray
    girth: float
    area: float


def cross_section(vertices, faces, y: float) -> list[Loop]:
    """The closed curves where the plane at height ``y`` [m] cuts the mesh, largest first.

    Parameters
    ----------
    vertices : (n, 3) float
        Mesh vertices [m], Y up.
    faces : (m, 3) int
        Triangles of a closed mesh.
    y : float
        Height of the horizontal plane [m].
    """
    v = np.asanyarray(vertices, dtype=np.float64)
    f = np.asanyarray(faces)
    s = v[:, 1] - y
    s[s == 0.0] = 1e-12  # no vertex exactly on the plane: every crossing edge is cut once
    above = s > 0
    count = above[f].sum(axis=1)
    fc = f[(count == 1) | (count == 2)]
    if len(fc) == 0:
        return []
    e = np.stack([fc[:, [0, 1]], fc[:, [1, 2]], fc[:, [2, 0]]], axis=1)
    cut = above[e[..., 0]] != above[e[..., 1]]
    ek = np.sort(e[cut], axis=1)  # two cut edges per face, in face order
    keys = ek[:, 0].astype(np.int64) * len(v) + ek[:, 1]
    uniq, inv = np.unique(keys, return_inverse=True)
    a, b = uniq // len(v), uniq % len(v)
    t = s[a] / (s[a] - s[b])
    pts = v[a] + t[:, None] * (v[b] - v[a])
    pairs = inv.reshape(-1, 2)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])),
                       shape=(len(uniq), len(uniq)))
    ncomp, labels = connected_components(graph, directed=False)
    loops = []
    for c in range(ncomp):
        p = pts[labels == c]
        if len(p) < 3:
            continue
        try:
            hull = ConvexHull(p[:, [0, 2]])
        except QhullError:
            continue
        loops.append(Loop(p, p.mean(axis=0), float(hull.area), float(hull.volume)))
    loops.sort(key=lambda lp: -lp.area)
    return loops


def girth(loops: list[Loop]) -> float:
    """Tape-measure length around several loops: perimeter of their joint convex hull [m]."""
    p = np.concatenate([lp.points for lp in loops])
    return float(ConvexHull(p[:, [0, 2]]).area)


def _big(loops: list[Loop]) -> list[Loop]:
    return [lp for lp in loops if lp.area >= _BIG * loops[0].area] if loops else []


def measure(vertices, faces) -> tuple[dict[str, float], dict[str, np.ndarray]]:
    """Measurements and landmarks of a standing body.

    Parameters
    ----------
    vertices : (n, 3) float
        Body vertices [m]: Y up, feet on y = 0, facing +Z, arms away from the torso.
    faces : (m, 3) int
        Triangles of the closed body surface.

    Returns
    -------
    measurements : dict of str to float
        ``height``, ``bust``, ``waist``, ``hip``, ``neck`` (girths), ``arm_length``
        (shoulder point to wrist), ``inseam`` (floor to crotch), ``shoulder_width``,
        and the heights ``bust_height``, ``waist_height``, ``hip_height``,
        ``crotch_height``, ``armpit_height``, ``neck_base_height``; all [m]
        (:data:`MEASUREMENTS`).
    landmarks : dict of str to array
        Points (3,) [m]: ``neck_base``, ``shoulder_left``, ``shoulder_right``,
        ``wrist_left``, ``wrist_right``, ``crotch``, ``bust``, ``waist``, ``hip``.
        Axes (2, 3) [m] as (start, end): ``torso_axis`` (hip centre to neck base),
        ``arm_axis_left/right`` (shoulder point to wrist), ``leg_axis_left/right`` (top of
        the thigh to the ankle). Left is +X. (:data:`LANDMARKS`.)

    Raises
    ------
    LandmarkError
        When the mesh is no standing human in an A-pose (a sphere, a box, arms down): it
        names the first landmark that cannot be found.
    """
    v = np.asanyarray(vertices, dtype=np.float64)
    f = np.asanyarray(faces)
    height = float(v[:, 1].max() - v[:, 1].min())
    if not height > 0:
        raise LandmarkError("height", "vertices: the body has no height")
    ys = np.arange(0.02, 0.96, _STEP) * height + v[:, 1].min()
    sections = [cross_section(v, f, y) for y in ys]
    nbig = np.array([len(_big(s)) for s in sections])
    nreal = np.array([sum(lp.area >= _TINY * s[0].area for lp in s) if s else 0
                      for s in sections])
    h = ys / height

    # Crotch: the legs' two large loops join into one.
    legs = np.flatnonzero((nbig >= 2) & (h > 0.3) & (h < 0.6))
    if len(legs) == 0:
        raise LandmarkError("crotch", "cannot find the crotch: no level between 30% and 60% "
                            "of the height has two legs apart (is it a person standing, Y up?)")
    ic = legs.max() + 1
    # Armpit: the highest level where the arms are apart from the torso.
    arms = np.flatnonzero((nreal >= 3) & (h > 0.55) & (h < 0.9))
    if len(arms) == 0:
        raise LandmarkError("armpits", "cannot find the armpits: no level between 55% and 90% "
                            "of the height has both arms apart from the torso (A-pose?)")
    ia = arms.max()

    torso_girth = np.array([_big(s)[0].girth if s else 0.0 for s in sections])
    lower_girth = np.array([girth(_big(s)) if s else 0.0 for s in sections])

    def pick(name, lo, hi, values, fn):
        idx = np.arange(max(lo, 0), min(hi, len(ys)))
        if len(idx) == 0:  # the levels found so far leave no room: the proportions are no human's
            raise LandmarkError(name, f"cannot find the {name}: no level left between the "
                                      "levels found below and above it")
        return int(idx[fn(values[idx])])

    ib = pick("bust", ia - int(0.10 / _STEP), ia - int(0.012 / _STEP), torso_girth, np.argmax)
    iw = pick("waist", ic + int(0.08 / _STEP), ib - int(0.04 / _STEP), torso_girth, np.argmin)
    ih = pick("hip", ic, iw - int(0.03 / _STEP), lower_girth, np.argmax)
    inn = pick("neck", ia + 1, int(0.92 / _STEP), torso_girth, np.argmin)
    neck = torso_girth[inn]
    ibase = next((i for i in range(ia + 1, inn + 1) if torso_girth[i] <= 1.2 * neck), None)
    if ibase is None or not neck > 0:
        raise LandmarkError("neck_base", "cannot find the neck base above the armpits")

    def centre(name, i):
        loops = _big(sections[i])
        if not loops:
            raise LandmarkError(name, f"cannot find the {name}: the mesh has no cross-section "
                                      "at its level")
        return np.mean([lp.centroid for lp in loops], axis=0)

    neck_base = centre("neck_base", ibase)
    torso_at_armpit = _big(sections[ia])[0]

    lm: dict[str, np.ndarray] = {}
    meas: dict[str, float] = {"height": height}
    for side, sign in (("left", 1.0), ("right", -1.0)):
        # Shoulder point: the top of the shoulder above the armpit.
        xs = (torso_at_armpit.points[:, 0] * sign).max() * sign
        near = (np.abs(v[:, 0] - xs) < 0.01) & (np.abs(v[:, 2] - neck_base[2]) < 0.08) \
            & (v[:, 1] > ys[ia])
        if not near.any():
            raise LandmarkError(f"shoulder_{side}", f"cannot find the {side} shoulder point "
                                                    "above the armpit")
        shoulder = v[near][np.argmax(v[near][:, 1])]
        # Arm: the lateral loops below the armpit, down to the fingertips.
        arm = []
        for i in range(ia, -1, -1):
            cand = [lp for lp in sections[i] if sign * lp.centroid[0] > sign * xs
                    and lp not in _big(sections[i])]
            if not cand:
                if arm:
                    break
                continue
            arm.append((i, max(cand, key=lambda lp: lp.area)))
        if len(arm) < 5:
            raise LandmarkError(f"arm_axis_{side}", f"cannot follow the {side} arm down from "
                                                    "the armpit")
        end = arm[-1][0]
        span = [(i, lp) for i, lp in arm
                if end + int(0.06 / _STEP) <= i <= end + int(0.14 / _STEP)]
        wrist = min(span, key=lambda t: t[1].girth)[1].centroid if span else arm[-1][1].centroid
        # Leg: centroids of the leg loop below the crotch.
        leg = [lp.centroid for i in (ic - int(0.03 / _STEP), int(0.03 / _STEP))
               for lp in _big(sections[i]) if sign * lp.centroid[0] > 0]
        if len(leg) != 2:
            raise LandmarkError(f"leg_axis_{side}", f"cannot follow the {side} leg down from "
                                                    "the crotch")
        lm[f"shoulder_{side}"] = shoulder
        lm[f"wrist_{side}"] = wrist
        lm[f"arm_axis_{side}"] = np.array([shoulder, wrist])
        lm[f"leg_axis_{side}"] = np.array(leg)
        meas[f"arm_length_{side}"] = float(np.linalg.norm(wrist - shoulder))
    meas["arm_length"] = 0.5 * (meas.pop("arm_length_left") + meas.pop("arm_length_right"))
    meas["shoulder_width"] = float(np.linalg.norm(lm["shoulder_left"] - lm["shoulder_right"]))
    meas.update(bust=float(torso_girth[ib]), waist=float(torso_girth[iw]),
                hip=float(lower_girth[ih]), neck=float(neck), inseam=float(ys[ic] - v[:, 1].min()))
    for name, i in (("bust", ib), ("waist", iw), ("hip", ih), ("crotch", ic),
                    ("armpit", ia), ("neck_base", ibase)):
        meas[f"{name}_height"] = float(ys[i] - v[:, 1].min())
    lm.update(neck_base=neck_base, bust=centre("bust", ib), waist=centre("waist", iw),
              hip=centre("hip", ih), crotch=centre("crotch", ic))
    lm["torso_axis"] = np.array([lm["hip"], neck_base])
    return meas, lm
