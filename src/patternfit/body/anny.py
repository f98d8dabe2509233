"""Custom bodies from the ``anny`` parametric body model (optional extra ``patternfit[anny]``).

anny (Apache-2.0, NAVER Corp.) is built on MakeHuman's CC0 assets. Its default pose has the
elbows bent with the forearms forward, which no sleeve can be placed on, so the elbows are
straightened here; the shoulders keep anny's A-pose (upper arms about 40° from the torso).
torch is imported only when a body is generated.
"""

from __future__ import annotations

import numpy as np

from ..arguments import number
from ..geometry import rotation_between
from .measure import measure
from .model import Body

#: anny phenotypes and statures [m] of the shipped bodies; anny's gender is 0 = male, 1 = female and its
#: age 2/3 is the "young adult" anchor (25 years)
BUILTIN_PHENOTYPES = {
    "female_thin": dict(gender=1.0, weight=0.15, muscle=0.4, stature=1.65),
    "female_average": dict(gender=1.0, weight=0.5, muscle=0.5, stature=1.65),
    "female_heavy": dict(gender=1.0, weight=0.9, muscle=0.5, stature=1.65),
    "male_thin": dict(gender=0.0, weight=0.15, muscle=0.4, stature=1.78),
    "male_average": dict(gender=0.0, weight=0.5, muscle=0.5, stature=1.78),
    "male_heavy": dict(gender=0.0, weight=0.95, muscle=0.5, stature=1.78),
}

_ADULT_AGE = 2.0 / 3.0

_MISSING = ("the anny body model is not installed: install torch's CPU build with "
            "`pip install torch --index-url https://download.pytorch.org/whl/cpu`, then "
            "the anny extra with `pip install \"patternfit[anny]\"`")


def _model():
    try:  # the optional extra, imported only when a body is generated
        import anny
        import torch
    except ImportError as exc:
        raise ImportError(_MISSING) from exc
    return anny.Anny(topology="anny-noeyes-notongue"), torch


def _posed(model, torch, phenotype: dict):
    """Vertices (n, 3) [m, anny's Z-up frame] and bone heads of the straight-armed pose."""
    labels = model.bone_labels
    out = model(phenotype_kwargs=phenotype)
    heads = out["bone_poses"][0][:, :3, 3].detach().numpy().astype(np.float64)
    pose = torch.eye(4, dtype=model.dtype).repeat(1, len(labels), 1, 1)
    for side in "LR":
        shoulder, elbow, wrist = (heads[labels.index(f"{b}.{side}")]
                                  for b in ("upperarm01", "lowerarm01", "wrist"))
        # local-ref pose parameters rotate about world-aligned axes at the bone's head
        rot = rotation_between(wrist - elbow, elbow - shoulder)
        pose[0, labels.index(f"lowerarm01.{side}"), :3, :3] = torch.tensor(rot)
    out = model(pose_parameters=pose, phenotype_kwargs=phenotype)
    verts = out["vertices"][0].detach().numpy().astype(np.float64)
    heads = out["bone_poses"][0][:, :3, 3].detach().numpy().astype(np.float64)
    return verts, dict(zip(labels, heads))


def _to_patternfit_frame(verts, heads) -> np.ndarray:
    """anny's Z-up frame to Y up, facing +Z, left side +X, feet on y = 0, centred."""
    forward = heads["toe1-1.L"] - heads["foot.L"]
    s = 1.0 if forward[1] > 0 else -1.0
    rot = np.array([[-s, 0, 0], [0, 0, 1], [0, s, 0]], dtype=np.float64)  # det = +1
    v = verts @ rot.T
    root = heads["root"] @ rot.T
    v -= [root[0], v[:, 1].min(), root[2]]
    if (heads["upperarm01.L"] @ rot.T)[0] < root[0]:
        raise RuntimeError("anny's left arm did not end up on +X")
    return v


def anny_body(*, gender: float = 0.5, weight: float = 0.5, muscle: float = 0.5,
              height: float = 0.5, proportions: float = 0.5, age: float = _ADULT_AGE,
              stature: float | None = None, name: str = "custom") -> Body:
    """A body from anny's phenotype parameters, in the straight-armed A-pose.

    Parameters
    ----------
    gender, weight, muscle, height, proportions, age : float
        anny phenotype values in [0, 1] (gender 0 = male, 1 = female).
    stature : float, optional
        Wanted standing height [m]; the phenotype ``height`` is searched to reach it, and a
        small uniform scale makes it exact.
    name : str
        Name of the body.
    """
    values = dict(gender=gender, weight=weight, muscle=muscle, height=height,
                  proportions=proportions, age=age)
    for key, x in values.items():
        number(x, key, low=0.0, high=1.0)
    if stature is not None:
        number(stature, "stature", low=0.5, low_open=True, high=2.6, high_open=True, unit="m",
               rule="expected a height in metres")
    model, torch = _model()
    model.eval()
    with torch.no_grad():
        def build(ph):
            return _to_patternfit_frame(*_posed(model, torch, ph))

        v = build(values)
        if stature is not None:
            lo, hi = 0.0, 1.0
            for _ in range(12):
                values["height"] = 0.5 * (lo + hi)
                v = build(values)
                lo, hi = (values["height"], hi) if np.ptp(v[:, 1]) < stature else (lo, values["height"])
            v *= stature / np.ptp(v[:, 1])
    # Stored as float32: measure what will be stored.
    v = v.astype(np.float32).astype(np.float64)
    faces = model.faces.numpy().astype(np.int64)
    meas, lm = measure(v, faces)
    import anny  # optional extra, imported when a body is generated (see _model)

    meta = dict(source=f"anny {anny.__version__} (NAVER Corp., Apache-2.0) on MakeHuman "
                       "assets (CC0)", phenotype=values, pose="A-pose, straight elbows",
                frame="metres, Y up, facing +Z, left +X, feet on y = 0")
    return Body(v, faces, name=name, measurements=meas, landmarks=lm, meta=meta)


#: bisection steps on anny's weight (0-1) in :func:`anny_body_from_girths`: 2^-7 of the
#: range, under a centimetre of girth
GIRTH_STEPS = 7
#: the relative miss of bust + waist + hip beyond which the body is widened (or narrowed)
GIRTH_MISS = 0.02


def anny_body_from_girths(*, gender: float, stature: float, bust: float, waist: float,
                          hip: float, name: str = "custom") -> Body:
    """An anny body of ``stature`` [m] whose bust (chest) + waist + hip [m] add up to the
    given ones: anny's weight is searched by bisection (muscle and proportions at 0.5);
    where its range ends first (at weight 1 anny's women have a waist of about 0.75 m) the body
    is widened, x and z scaled about its waist axis, which scales every horizontal girth by
    one factor (``meta["widened"]``). One parameter and a scale cannot hit three girths:
    the body's own girths are in its ``measurements`` and differ from the given ones by a
    few centimetres."""
    number(gender, "gender", low=0.0, high=1.0)
    for key, x in dict(bust=bust, waist=waist, hip=hip).items():
        number(x, key, low=0.4, high=2.5, unit="m", rule="expected a girth in metres "
               "within [0.4, 2.5]")
    target = bust + waist + hip

    def girths(b):
        return b.measurements["bust"] + b.measurements["waist"] + b.measurements["hip"]

    lo, hi, body = 0.0, 1.0, None
    for _ in range(GIRTH_STEPS):
        weight = 0.5 * (lo + hi)
        body = anny_body(name=name, gender=gender, weight=weight, muscle=0.5, stature=stature)
        lo, hi = (weight, hi) if girths(body) < target else (lo, weight)
    scale = target / girths(body)
    if abs(scale - 1.0) <= GIRTH_MISS:
        return body
    v = body.vertices.copy()
    axis = body.landmarks["waist"][[0, 2]]
    v[:, [0, 2]] = axis + scale * (v[:, [0, 2]] - axis)
    v = v.astype(np.float32).astype(np.float64)  # stored as float32: measure that
    meas, lm = measure(v, body.faces)
    return Body(v, body.faces, name=name, measurements=meas, landmarks=lm,
                meta={**body.meta, "widened": round(float(scale), 4)})
