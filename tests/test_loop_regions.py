"""Where to modify: connected tight/loose regions named after the pattern's edges."""

import dataclasses

import numpy as np
import pytest

from patternfit.fit.metrics import FitEvaluator
from patternfit.loop.regions import find_regions, triangle_adjacency
from patternfit.mesh.triangulate import mesh_pattern
from patternfit.pattern.library import build


@pytest.fixture(scope="module")
def skirt():
    pattern = build("skirt", "M")
    return pattern, mesh_pattern(pattern, triangles=1200)


def _lifted(mesh, stretch_of_vertex):
    """A flat 3D state where each vertex is moved in x by its panel-local stretch field."""
    v = mesh.vertices
    x = np.zeros((mesh.n_vertices, 3))
    x[:, :2] = v
    x[:, 0] = stretch_of_vertex(v)
    return x


def test_adjacency_pairs_share_an_edge(skirt):
    _, mesh = skirt
    a, b = triangle_adjacency(mesh.triangles)
    shared = [len(set(mesh.triangles[i]) & set(mesh.triangles[j])) for i, j in zip(a, b)]
    assert len(a) > mesh.n_triangles and set(shared) == {2}


def test_a_known_tight_band_is_found_as_the_band(skirt):
    pattern, mesh = skirt
    front = mesh.panel_names.index("front")
    v = mesh.vertices
    y0, y1 = 0.25, 0.45  # band across the front panel, heights in its flat frame
    on_front = mesh.vertex_panel == front

    def field(p):
        # x stretched by 1.3 inside the band (ramps of 4 cm), unchanged elsewhere
        w = np.clip((p[:, 1] - y0) / 0.04, 0, 1) * np.clip((y1 - p[:, 1]) / 0.04, 0, 1)
        return np.where(on_front, p[:, 0] * (1.0 + 0.3 * w), p[:, 0])

    x = _lifted(mesh, field)
    fit = FitEvaluator(mesh)(x)
    regions = find_regions(mesh, fit)
    tight = [r for r in regions if r.kind == "tight"]
    assert len(tight) == 1 and not [r for r in regions if r.kind == "loose"]
    band = tight[0]
    assert band.panel == "front"
    cy = v[mesh.triangles[band.triangles]].mean(axis=1)[:, 1]
    assert cy.min() > y0 - 0.02 and cy.max() < y1 + 0.02
    # nearly the whole band, nothing else
    mid = mesh.vertices[mesh.triangles].mean(axis=1)
    truth = (mesh.triangle_panel == front) & (mid[:, 1] > y0 + 0.05) & (mid[:, 1] < y1 - 0.05)
    assert np.isin(np.flatnonzero(truth), band.triangles).mean() > 0.95
    assert 0.2 < band.area_change < 0.3
    assert 1.2 < band.weft < 1.3 and band.warp < band.weft - 0.1  # shear in the ramps
    # tied to a side edge of the front, with a span inside the band's height
    assert band.edge in ("side_l", "side_r", "hip_l", "hip_r") and band.seam == band.edge
    assert 0 <= band.span_cm[0] < band.span_cm[1]
    text = band.describe()
    assert "front" in text and "too small" in text and band.edge in text
    d = band.to_dict()
    assert d["triangles"] == len(band.triangles) and d["description"] == text
    # a region whose span rounds to one place says so ("22–22 cm along it" before)
    point = dataclasses.replace(band, span_cm=(22.2, 21.8))
    assert "at 22 cm along it" in point.describe() and "22–22" not in point.describe()
    # a band is a part of its panel; a region over nearly all of it says so ("near side_l,
    # 6 cm in" was said of a whole panel, the demo's first drape)
    assert 0.1 < band.panel_share < 0.5 and "of the panel" not in text
    whole = dataclasses.replace(band, panel_share=0.97)
    assert whole.describe().startswith(f"front, 97% of the panel, its nearest seam {band.seam}:")


def test_untouched_garment_has_no_region(skirt):
    _, mesh = skirt
    x = _lifted(mesh, lambda p: p[:, 0])
    assert find_regions(mesh, FitEvaluator(mesh)(x)) == []


def test_fit_of_another_mesh_is_refused(skirt):
    pattern, mesh = skirt
    other = mesh_pattern(pattern, triangles=400)
    fit = FitEvaluator(other)(_lifted(other, lambda p: p[:, 0]))
    with pytest.raises(ValueError, match="fit"):
        find_regions(mesh, fit)
