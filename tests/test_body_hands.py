"""Mittens: the hands as the cloth meets them (body/hands.py), joined into the field."""

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings, strategies as st

from patternfit.body import DistanceField, load_body
from patternfit.body.hands import HAND_REACH, mittens
from patternfit.body.sdf import signed_distance


@pytest.fixture(scope="module")
def body():
    return load_body("male_average")


def _hand(body, side):
    """Vertices of the body past its wrist on one side, near the wrist."""
    shoulder, wrist = body.landmarks[f"arm_axis_{side}"]
    axis = (wrist - shoulder) / np.linalg.norm(wrist - shoulder)
    v = body.vertices
    return v[((v - wrist) @ axis > 0.0) & (np.linalg.norm(v - wrist, axis=1) < 0.25)]


def test_each_hand_lies_in_its_mitten_and_nothing_else_does(body):
    hulls = body.mittens()
    assert len(hulls) == 2 and all(m.is_volume for m in hulls)
    for side, hull in zip(("left", "right"), hulls):
        hand = _hand(body, side)
        # the whole hand is in it, thumb and fingertips included
        assert (signed_distance(hand, hull.vertices, hull.faces) < 1e-9).all()
        wrist = body.landmarks[f"wrist_{side}"]
        assert np.linalg.norm(hull.vertices - wrist, axis=1).max() < HAND_REACH
        # the other hand, the torso and the thigh beside it are not
        torso = [body.landmarks["hip"], body.landmarks["waist"]]
        assert (signed_distance(torso, hull.vertices, hull.faces) > 0.05).all()
    assert np.linalg.norm(hulls[0].centroid - hulls[1].centroid) > 0.5


def test_the_gap_between_thumb_and_fingers_is_inside_the_field(body):
    # the middle of the mitten is between the thumb and the palm or in the hand: inside
    # the field either way, while the body's own mesh leaves the gap outside
    plain = DistanceField.from_mesh(body.vertices, body.faces, spacing=0.005, cache=False)
    field = body.distance_field()
    for side, hull in zip(("left", "right"), body.mittens()):
        lo, hi = hull.bounds
        pts = np.random.default_rng(1).uniform(lo, hi, (2000, 3))
        pts = pts[signed_distance(pts, hull.vertices, hull.faces) < 0.0]
        d_plain, d = plain.query(pts)[0], field.query(pts)[0]
        assert (d < 0.002).all()  # inside, up to the trilinear grid's rounding
        assert (d_plain > 0.005).mean() > 0.2  # much of it is not the hand itself
    # away from the hands the field is the body's
    far = body.landmarks["bust"] + [[0.0, 0.0, z] for z in (0.05, 0.1, 0.2)]
    np.testing.assert_allclose(field.query(far)[0], plain.query(far)[0], atol=1e-6)


def test_a_body_without_hands_gets_no_mittens(body):
    # an arm that ends at the wrist: its landmark has nothing past it
    lm = dict(body.landmarks)
    for side in ("left", "right"):
        shoulder, wrist = lm[f"arm_axis_{side}"]
        far = wrist + 2.0 * (wrist - shoulder)
        lm[f"arm_axis_{side}"] = np.array([shoulder, far])
        lm[f"wrist_{side}"] = far
    assert mittens(body.vertices, body.faces, lm) == []


@settings(max_examples=15, deadline=None)
@given(st.floats(-0.3, 0.3), st.floats(-0.3, 0.3), st.floats(0.05, 0.2))
def test_a_field_joined_with_a_solid_is_the_nearer_of_the_two(dx, dz, size):
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.4)
    box = trimesh.creation.box(extents=[size] * 3)
    box.apply_translation([dx, 0.35, dz])
    spacing = 0.02
    field = DistanceField.from_mesh(sphere.vertices, sphere.faces, spacing=spacing,
                                    solids=[(box.vertices, box.faces)], cache=False)
    rng = np.random.default_rng(0)
    p = rng.uniform(-0.45, 0.45, (500, 3))
    exact = np.minimum(signed_distance(p, sphere.vertices, sphere.faces),
                       signed_distance(p, box.vertices, box.faces))
    near = np.abs(exact) < 0.02  # within the exact band
    err = np.abs(field.query(p)[0] - exact)
    # trilinear: exact on flat parts, up to about a cell's diagonal at the box's corners
    assert np.median(err[near]) < 0.1 * spacing and err[near].max() < spacing
    assert np.all(err[~near] < 2 * spacing)
