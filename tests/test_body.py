"""Built-in bodies: shape, orientation, measurements stored beside them."""

import numpy as np
import pytest
import trimesh

from patternfit.body import ALIASES, Body, list_bodies, load_body, measure

NAMES = ["female_thin", "female_average", "female_heavy", "male_thin", "male_average",
         "male_heavy"]


def test_list_has_the_six_bodies():
    assert set(NAMES) <= set(list_bodies())


@pytest.mark.parametrize("alias, name", [("fat man", "male_heavy"), ("Thin Woman", "female_thin"),
                                         ("thin-man", "male_thin"), ("male_average", "male_average")])
def test_aliases(alias, name):
    assert load_body(alias).name == name
    assert ALIASES.get(alias.lower().replace("-", " "), name) == name


def test_unknown_body_names_the_known_ones():
    with pytest.raises(ValueError, match="female_thin"):
        load_body("giant")


@pytest.fixture(scope="module", params=NAMES)
def body(request) -> Body:
    return load_body(request.param)


def test_closed_outward_and_standing(body):
    tm = trimesh.Trimesh(body.vertices, body.faces, process=False)
    assert 10_000 <= len(body.vertices) <= 15_000
    assert body.vertices.dtype == np.float64 and body.faces.shape[1] == 3
    assert tm.is_watertight and tm.is_winding_consistent
    assert tm.volume > 0.03  # outward normals give a positive volume (a person: 0.04-0.12 m³)
    assert abs(body.vertices[:, 1].min()) < 1e-6
    assert 1.5 < body.height < 1.95
    # A-pose: the hands reach well beyond the hips, and the body faces +Z (toes forward).
    assert np.ptp(body.vertices[:, 0]) > 0.9
    feet = body.vertices[body.vertices[:, 1] < 0.03]
    assert feet[:, 2].max() - body.landmarks["leg_axis_left"][1, 2] > 0.1


def test_arms_are_straight(body):
    """The elbow lies near the shoulder-wrist line (anny's bent default puts it ~10 cm off;
    the line starts on top of the shoulder, not at the joint, hence a few cm of slack)."""
    s, w = body.landmarks["arm_axis_left"]
    v = body.vertices
    t = (v - s) @ (w - s) / np.dot(w - s, w - s)
    axis_pt = s + 0.55 * (w - s)
    mid = v[(np.abs(t - 0.55) < 0.02) & (np.linalg.norm(v - axis_pt, axis=1) < 0.08)]
    assert len(mid) > 20
    assert np.linalg.norm(mid.mean(axis=0) - axis_pt) < 0.04


def test_measured_girths_match_stored(body):
    meas, lm = measure(body.vertices, body.faces)
    for key in ("bust", "waist", "hip", "neck", "height", "arm_length", "inseam"):
        assert abs(meas[key] - body.measurements[key]) < 0.02, key
    assert set(lm) == set(body.landmarks)


def test_measurements_are_plausible(body):
    m = body.measurements
    assert m["waist"] < m["hip"] and m["waist"] < m["bust"] + 0.02
    assert 0.6 < m["bust"] < 1.4 and 0.55 < m["waist"] < 1.3 and 0.8 < m["hip"] < 1.4
    assert 0.44 * m["height"] < m["inseam"] < 0.52 * m["height"]
    assert 0.45 < m["arm_length"] < 0.7
    lm = body.landmarks
    assert lm["shoulder_left"][0] > 0 > lm["shoulder_right"][0]
    assert lm["crotch"][1] <= lm["hip"][1] < lm["waist"][1] < lm["bust"][1] < lm["neck_base"][1]
    assert lm["torso_axis"].shape == (2, 3)


def test_heavier_is_wider():
    g = {n: load_body(n).measurements["waist"] for n in NAMES}
    assert g["female_thin"] < g["female_average"] < g["female_heavy"]
    assert g["male_thin"] < g["male_average"] < g["male_heavy"]
