"""The far-from-body check on a full circle skirt: its hem may stand out from the body as far
as the cloth between it and the waist is long (:func:`patternfit.sim.onbody.anchor_reach`);
the same skirt moved off the body, or a piece of it flown off, still fails."""

import json
import math

import numpy as np
import pytest

from patternfit.body.builtin import load_body
from patternfit.mesh import mesh_pattern
from patternfit.pattern.formats import load_any_pattern
from patternfit.sim.onbody import ON_BODY, anchor_line, anchor_reach, on_body_checks

BODY = "female_thin"
LENGTH = 0.60  # the skirt's length from waist to hem [m]


def _quarter(name: str, r: float, big: float, z: float) -> dict:
    """A quarter of a circle skirt as GarmentCode writes a panel (cm, y up, waist on top,
    the centre of the circle above it): a waist arc of radius ``r``, a hem arc of radius
    ``big``, two straight side edges at 45 degrees."""
    c = math.sqrt(0.5)
    cx, cy = 0.0, 0.0
    waist_l, waist_r = (cx - r * c, cy - r * c), (cx + r * c, cy - r * c)
    hem_l, hem_r = (cx - big * c, cy - big * c), (cx + big * c, cy - big * c)
    return {"vertices": [list(waist_l), list(hem_l), list(hem_r), list(waist_r)],
            "edges": [{"endpoints": [0, 1]},
                      {"endpoints": [1, 2],
                       "curvature": {"type": "circle", "params": [big, 0, 1]}},
                      {"endpoints": [2, 3]},
                      {"endpoints": [3, 0],
                       "curvature": {"type": "circle", "params": [r, 0, 0]}}],
            "translation": [0.0, 100.0, z], "rotation": [0.0, 0.0, 0.0]}


@pytest.fixture(scope="module")
def circle(tmp_path_factory):
    """A four-gore full circle skirt written as a GarmentCode specification, read and
    meshed (about 1,200 triangles), with the body: (pattern, mesh, body, waist radius,
    hem radius) in metres."""
    body = load_body(BODY)
    r = body.measurements["waist"] * 1.04 / (2 * math.pi)
    big = r + LENGTH
    # round the body in the order the cone below lays them (from the front through the
    # body's left, +x, to the back)
    names = ["skirt_front_l", "skirt_back_l", "skirt_back_r", "skirt_front_r"]
    panels = {n: _quarter(n, r * 100, big * 100, 15.0 if "front" in n else -15.0)
              for n in names}
    stitches = [[{"panel": names[i], "edge": 2}, {"panel": names[(i + 1) % 4], "edge": 0}]
                for i in range(4)]
    path = tmp_path_factory.mktemp("gc") / "circle_skirt_specification.json"
    path.write_text(json.dumps({"pattern": {"panels": panels, "stitches": stitches},
                                "properties": {"curvature_coords": "relative",
                                               "units_in_meter": 100}}))
    pattern = load_any_pattern(path)
    return pattern, mesh_pattern(pattern, triangles=1200), body, r, big


def _cone(mesh, body, r, slope_deg):
    """The skirt's 3D state as a cone round the waist: each panel's flat point at radius
    rho [m] from its circle's centre lies ``rho - r`` down the cone's side, the side at
    ``slope_deg`` from the vertical; panel k covers the quarter centred 90 k + 45 degrees
    round from the front (+z) towards the body's left (+x): front left, back left, back
    right, front right, each gore on the side its name says."""
    waist = np.asarray(body.landmarks["waist"], dtype=float)
    centre = np.array([waist[0], body.measurements["waist_height"], waist[2]])
    # the body's waist as a circle of the same girth (the skirt's waist is 4 % wider)
    r_body = body.measurements["waist"] / (2 * math.pi)
    x = np.zeros((mesh.n_vertices, 3))
    a = math.radians(slope_deg)
    for k in range(len(mesh.panel_names)):
        ids = mesh.panel_vertices(k)
        v = mesh.vertices[ids]
        v = v - [0.5 * (v[:, 0].min() + v[:, 0].max()), 0.0]  # the circle's centre on x = 0
        top = v[:, 1].max() + r * math.sqrt(0.5)  # the centre's height in the flat frame
        rho = np.hypot(v[:, 0], v[:, 1] - top)
        phi = math.radians(90 * k + 45) + np.arctan2(v[:, 0], top - v[:, 1])
        s = rho - r
        radial = r_body + s * math.sin(a)
        x[ids] = centre + np.stack([radial * np.sin(phi), -s * math.cos(a),
                                    radial * np.cos(phi)], axis=1)
    return x


def test_the_reach_is_the_cloth_length_from_the_waist(circle):
    pattern, mesh, body, r, big = circle
    reach = anchor_reach(pattern, mesh)
    line = anchor_line(pattern, mesh)
    assert len(line) >= 4 and np.all(reach[line] == 0.0)
    assert np.isfinite(reach).all()
    # never shorter than the straight line from the anchor line within a gore, and longer
    # only by the mesh edges' zigzag (under 10 %)
    straight = np.zeros(mesh.n_vertices)
    for k in range(len(mesh.panel_names)):
        ids = mesh.panel_vertices(k)
        tops = np.intersect1d(ids, line)
        gap = mesh.vertices[ids][:, None] - mesh.vertices[tops][None]
        straight[ids] = np.linalg.norm(gap, axis=2).min(axis=1)
    assert np.all(reach >= straight - 1e-9)
    assert np.all(reach <= 1.1 * straight + 0.02)
    assert reach.max() > LENGTH  # the hem: the skirt's length and more, from the corners


def test_a_circle_skirt_standing_out_is_on_the_body(circle):
    pattern, mesh, body, r, big = circle
    x = _cone(mesh, body, r, 60.0)  # twirled: the hem 52 cm out from the waist
    c = on_body_checks(pattern, mesh, body, x)
    assert c.farthest_mm > ON_BODY.far * 1e3, c.farthest_mm  # the old 30 cm limit refused it
    assert c.passed, c.reasons
    assert c.far_vertices == 0 and abs(c.anchor_offset_mm) < 20


@pytest.mark.parametrize("case", ["moved 60 cm aside", "a gore flown off", "flung out"])
def test_a_circle_skirt_off_the_body_fails(circle, case):
    pattern, mesh, body, r, big = circle
    x = _cone(mesh, body, r, 60.0)
    if case == "moved 60 cm aside":  # at the waist's height, beside the body
        x = x + [0.6, 0.0, 0.0]
    elif case == "a gore flown off":
        ids = mesh.panel_vertices(0)
        x[ids] += [0.0, 0.0, 1.2]
    else:  # the hem farther out than the cloth reaches: stretched beyond the skirt
        x = _cone(mesh, body, r, 90.0)
        x[:, [0, 2]] = (x[:, [0, 2]] - x[:, [0, 2]].mean(axis=0)) * 2.0 + x[:, [0, 2]].mean(axis=0)
    c = on_body_checks(pattern, mesh, body, x)
    assert not c.passed and c.far_vertices > 0, (case, c.reasons)
    assert any("far from the body" in t for t in c.reasons), c.reasons
