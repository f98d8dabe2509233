"""Values carried between two meshes of one pattern through the flat panels."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from patternfit.mesh import mesh_pattern
from patternfit.mesh.transfer import follow_edit, locate, transfer
from patternfit.pattern.library import build


@pytest.fixture(scope="module")
def meshes():
    p = build("trousers", "M")
    return mesh_pattern(p, triangles=300), mesh_pattern(p, triangles=1500)


def test_affine_fields_are_carried_exactly_inside(meshes):
    # linear precision off the outline; on it, along the coarse chords (within their sagitta)
    coarse, fine = meshes
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=(2, 3)), rng.normal(size=3)
    out = transfer(coarse, coarse.vertices @ a + b, fine)
    exact = fine.vertices @ a + b
    inside = ~fine.boundary_mask()
    assert np.allclose(out[inside], exact[inside], atol=1e-9)
    assert np.abs(out - exact).max() < 0.02 * np.abs(a).max()


def test_a_closed_seam_stays_closed(meshes):
    coarse, fine = meshes
    rng = np.random.default_rng(4)
    x = rng.normal(size=(coarse.n_vertices, 3))
    # sewn: every group of joined vertices (corners join several) at one point
    n = coarse.n_vertices
    a, b = coarse.seam_pairs.T
    _, group = connected_components(coo_matrix((np.ones(len(a)), (a, b)), shape=(n, n)))
    mean = np.zeros((group.max() + 1, 3))
    np.add.at(mean, group, x)
    x = (mean / np.bincount(group)[:, None])[group]
    out = transfer(coarse, x, fine)
    assert np.abs(out[fine.seam_pairs[:, 0]] - out[fine.seam_pairs[:, 1]]).max() < 1e-12


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


@settings(max_examples=25, deadline=None)
@given(st.lists(st.floats(-0.3, 0.3), min_size=6, max_size=6), st.integers(0, 2**31 - 1))
def test_an_affine_edit_of_a_rigidly_placed_panel_is_followed_exactly(coef, seed):
    # a flat mesh placed by a rotation (3 x 2, orthonormal columns) and an affine edit of it:
    # every deformation gradient is the rotation, so the edit is carried exactly
    m = mesh_pattern(build("skirt", "M"), triangles=200)
    rng = np.random.default_rng(seed)
    rot = np.linalg.qr(rng.normal(size=(3, 3)))[0][:, :2]
    shift = rng.normal(size=3)
    edit = np.eye(2) + np.array(coef[:4]).reshape(2, 2)
    new = m.vertices @ edit.T + np.array(coef[4:])
    out = follow_edit(m.vertices, new, m.triangles, m.vertices @ rot.T + shift)
    assert np.allclose(out, new @ rot.T + shift, atol=1e-12)


def test_follow_edit_keeps_an_unedited_mesh_and_refuses_bad_shapes(meshes):
    coarse, _ = meshes
    x = np.random.default_rng(5).normal(size=(coarse.n_vertices, 3))
    assert np.array_equal(follow_edit(coarse.vertices, coarse.vertices, coarse.triangles, x), x)
    with pytest.raises(ValueError, match="positions"):
        follow_edit(coarse.vertices, coarse.vertices, coarse.triangles, x[:-1])
    with pytest.raises(ValueError, match="new_flat"):
        follow_edit(coarse.vertices, coarse.vertices[:, :1], coarse.triangles, x)
    with pytest.raises(ValueError, match="triangles"):
        follow_edit(coarse.vertices, coarse.vertices, coarse.triangles + coarse.n_vertices, x)
