"""Values carried between two meshes of one pattern through the flat panels."""

import numpy as np
import pytest

from patternfit.mesh import mesh_pattern
from patternfit.mesh.transfer import locate, transfer
from patternfit.pattern.library import build


@pytest.fixture(scope="module")
def meshes():
    p = build("trousers", "M")
    return mesh_pattern(p, triangles=300), mesh_pattern(p, triangles=1500)


def test_affine_fields_are_carried_exactly(meshes):
    # linear precision, also at outline vertices outside the coarse chords (linear extension)
    coarse, fine = meshes
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=(2, 3)), rng.normal(size=3)
    out = transfer(coarse, coarse.vertices @ a + b, fine)
    assert np.allclose(out, fine.vertices @ a + b, atol=1e-9)


def test_points_inside_a_panel_get_convex_weights(meshes):
    coarse, fine = meshes
    inner = np.flatnonzero((fine.vertex_panel == 0) & ~fine.boundary_mask())
    tri, bary = locate(coarse, 0, fine.vertices[inner])
    assert (coarse.triangle_panel[tri] == 0).all()
    assert np.allclose(bary.sum(axis=1), 1.0)
    assert bary.min() > -1e-9


def test_bad_values_are_refused(meshes):
    coarse, fine = meshes
    with pytest.raises(ValueError, match="values"):
        transfer(coarse, np.zeros((3, 3)), fine)
    with pytest.raises(ValueError, match="points"):
        locate(coarse, 0, np.zeros((4, 3)))
