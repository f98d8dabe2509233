"""Mittens: each hand as the cloth meets it, the convex hull of the hand.

A sleeve that reaches the hand closes round it while its seams are sewn; a thumb held out
from the hand (1.5-2 cm across, narrower than a triangle of a 2-3K garment) then passes
between the sleeve's contact points and stays through it (the 3K shirt M on male_average:
6 cloth edges through the body when its seams welded). No sleeve goes between the fingers,
so the cloth meets the hull of each hand (and of the last 6 cm of the forearm) instead:
the body it cannot enter only grows, and a drape outside the mittens is outside the hands.
A cuff narrower than the mitten (a spread thumb makes it 30-34 cm round, where a hand
with the thumb laid in is about 21 cm) stops at the wrist, and the sleeve gathers above it.
"""

from __future__ import annotations

import numpy as np
import trimesh

#: a hand reaches no farther than this from its wrist landmark [m]: a part of the mesh
#: past the wrist that does (the arm ends at the wrist, or the hand is fused with the
#: thigh) is no hand, and gets no mitten
HAND_REACH = 0.3
#: the mitten begins this far up the forearm from the wrist [m]. Begun at the wrist, the
#: hull flared out from it at once, and a cuff that could not pass the thumb was pressed
#: into the crease between the two until its contact stiffened without bound (the 2K
#: GarmentCode hoodie on male_average: 23 edges through the wrist, 29 crossings, residual
#: 1.7e7); from 6 cm up the cuff meets a ramp, and rests on it
FOREARM = 0.06
#: the hand is the part of the mesh past the wrist that begins within this of the wrist
#: landmark [m] (a wrist is 5-6 cm across)
WRIST_REACH = 0.06


def mittens(vertices, faces, landmarks) -> list[trimesh.Trimesh]:
    """The convex hull of each hand of a body, as closed meshes.

    Parameters
    ----------
    vertices : (n, 3) float
        The body's vertices [m].
    faces : (m, 3) int
        Its triangles.
    landmarks : dict of str to array
        At least ``arm_axis_left`` and ``arm_axis_right`` (2, 3) [m] (shoulder to wrist),
        as :func:`patternfit.body.measure.measure` gives them.

    Returns
    -------
    list of trimesh.Trimesh
        One hull per hand found: the faces wholly past the plane across the arm's axis
        :data:`FOREARM` up from the wrist, connected to the wrist, all within
        :data:`HAND_REACH` of it. A side without one (an arm that ends at the wrist) has
        none.
    """
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    out = []
    for side in ("left", "right"):
        shoulder, wrist = landmarks[f"arm_axis_{side}"]
        axis = wrist - shoulder
        beyond = (v - wrist) @ axis > -FOREARM * np.linalg.norm(axis)
        past = f[beyond[f].all(axis=1)]
        if not len(past):
            continue
        label = trimesh.graph.connected_component_labels(
            trimesh.geometry.faces_to_edges(past), node_count=len(v))
        used = np.unique(past)
        near = np.linalg.norm(v[used] - wrist, axis=1)
        if near.min() > WRIST_REACH:
            continue
        hand = v[label == label[used[np.argmin(near)]]]
        if np.linalg.norm(hand - wrist, axis=1).max() > HAND_REACH or len(hand) < 4 \
                or np.linalg.svd(hand - hand.mean(axis=0), compute_uv=False)[-1] < 1e-3:
            continue  # no hand there, or a flat piece of one: no volume to hull
        out.append(trimesh.convex.convex_hull(hand))
    return out
