"""Drape of small built-in garments on built-in bodies (static engine)."""

import numpy as np
import pytest

from patternfit.body.builtin import load_body
from patternfit.fit import FitEvaluator
from patternfit.mesh import mesh_pattern
from patternfit.pattern.library import build
from patternfit.sim.drape import drape, redrape
from patternfit.sim.placement import place_on_body


@pytest.fixture(scope="module")
def thin_woman():
    return load_body("thin woman")


@pytest.mark.parametrize("garment,body", [("skirt", "female_thin"), ("dress", "female_average"),
                                          ("trousers", "male_thin"), ("coat", "male_heavy")])
def test_placement_is_isometric_and_outside(garment, body):
    b = load_body(body)
    p = build(garment, "M")
    m = mesh_pattern(p, triangles=1500)
    x = place_on_body(p, m, b)
    assert FitEvaluator(m).metrics(x)[1] == pytest.approx(1.0, abs=3e-3)
    d, _ = b.distance_field(0.01).query(x)
    assert np.mean(d > 0) > 0.99
    # fronts in front of the body's axis, backs behind
    centre = np.asarray(b.landmarks["torso_axis"])[:, 2].mean()
    for i, panel in enumerate(p.panels):
        z = x[m.vertex_panel == i, 2].mean()
        assert (z > centre) == (panel.placement.side == "front"), panel.name


def test_skirt_drapes_to_rest(thin_woman):
    p = build("skirt", "M")
    m = mesh_pattern(p, triangles=1500)
    d = drape(p, m, thin_woman, "cotton")
    c = d.checks
    assert c.inside_vertices == 0 and c.seam_gap_max_mm < 0.5
    assert c.self_intersections == 0 and c.equilibrium, c
    # sewn: both copies of every seam pair at one point
    x = d.positions
    assert np.abs(x[m.seam_pairs[:, 0]] - x[m.seam_pairs[:, 1]]).max() < 5e-4
    # it hangs on the hips: the waist is below the body's waist and above the crotch
    top = x[:, 1].max()
    assert thin_woman.measurements["crotch_height"] < top < \
        thin_woman.measurements["waist_height"] + 0.05
    # warm re-drape of the same rest shape stays put and takes few iterations
    again = redrape(d, m)
    assert again.result.iterations < d.result.iterations
    assert np.abs(again.positions - x).max() < 0.01
