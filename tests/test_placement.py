"""Placement details: explicit 3D placements of imported patterns are kept."""

from dataclasses import replace

import numpy as np
import pytest

from patternfit.body.builtin import load_body
from patternfit.mesh import mesh_pattern
from patternfit.pattern.garmentcode import panel_points_3d
from patternfit.pattern.library import build
from patternfit.pattern.model import Placement
from patternfit.sim.placement import place_on_body


def test_explicit_placement_is_kept():
    body = load_body("female_thin")
    pattern = build("skirt", "M")
    # the skirt's waist (its top, drafted at the panel's largest y) at the body's waist
    y = body.measurements["waist_height"] - max(
        float(p.outline.polygon(8)[:, 1].max()) for p in pattern.panels)
    placed = []
    for i, panel in enumerate(pattern.panels):
        z = 0.3 if i == 0 else -0.3
        placed.append(replace(panel, placement=Placement(
            panel.placement.part, panel.placement.side, translation=(0.0, y, z),
            rotation=(0.0, 0.0 if i == 0 else 180.0, 0.0))))
    pattern = replace(pattern, panels=tuple(placed))
    mesh = mesh_pattern(pattern, triangles=800)
    x = place_on_body(pattern, mesh, body)
    for i, panel in enumerate(pattern.panels):
        ids = mesh.panel_vertices(i)
        want = panel_points_3d(panel.placement, mesh.vertices[ids])
        shift = x[ids] - want
        assert np.allclose(shift, shift[0]) and shift[0, [0, 2]] == pytest.approx([0, 0])
        assert 0.0 <= shift[0, 1] <= 0.06  # at most the sewing lift, the same for all panels


def test_cloth_longer_than_the_legs_is_placed_on_the_floor():
    """The trousers XL are longer than female_thin's legs: the part of each leg that would
    start below the floor (y = 0) starts on it, and the rest is placed as before."""
    body = load_body("female_thin")
    pattern = build("trousers", "XL")
    mesh = mesh_pattern(pattern, triangles=800)
    x = place_on_body(pattern, mesh, body, clearance=0.03)
    assert x[:, 1].min() == pytest.approx(0.015)
    on_floor = np.isclose(x[:, 1], 0.015)
    assert 0 < on_floor.sum() < 0.3 * len(x)  # the hems, not the legs
    top = body.measurements["waist_height"] + 0.01  # the waistband where placement puts it
    assert x[:, 1].max() == pytest.approx(top, abs=0.03)
