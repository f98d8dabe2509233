"""The ground-floor geometry module: areas against brute force, rotations onto their target
(also for a = ±b), and the edges and hinges of random triangulated grids against trimesh."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st

from patternfit.geometry import (boundary_edges, counter_clockwise, euler_xyz_matrix,
                                 face_adjacency,
                                 face_cross, hinges, inner_grid, interior_edges,
                                 longest_edges, polygon_area,
                                 rotation_between, signed_areas, triangle_areas, unique_edges)

coord = st.floats(-10.0, 10.0, allow_nan=False, allow_infinity=False)
vec3 = st.tuples(coord, coord, coord).map(np.array).filter(lambda v: np.linalg.norm(v) > 1e-3)


def _brute_area(p) -> float:
    """Heron's formula on the side lengths (a different route from the cross product)."""
    a, b, c = (math.dist(p[i], p[(i + 1) % 3]) for i in range(3))
    s = 0.5 * (a + b + c)
    return math.sqrt(max(s * (s - a) * (s - b) * (s - c), 0.0))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(coord, coord, coord), min_size=3, max_size=12),
       st.integers(0, 2**31 - 1), st.sampled_from([2, 3]))
def test_triangle_areas_match_a_brute_force_formula(points, seed, dim):
    v = np.array(points)[:, :dim]
    rng = np.random.default_rng(seed)
    t = rng.integers(0, len(v), size=(8, 3))
    got = triangle_areas(v, t)
    scale = max(1.0, float(np.abs(v).max())) ** 2
    for k, tri in enumerate(t):
        assert got[k] == pytest.approx(_brute_area(v[tri].tolist()), abs=1e-6 * scale)
    # trimesh computes the same areas along another edge pair: equal up to rounding
    v3 = np.column_stack([v, np.zeros((len(v), 3 - dim))])
    np.testing.assert_allclose(got, trimesh.triangles.area(v3[t]), rtol=1e-9, atol=1e-12 * scale)
    if dim == 2:
        s = signed_areas(v, t)
        np.testing.assert_array_equal(np.abs(s), got)
        np.testing.assert_array_equal(signed_areas(v, t[:, [0, 2, 1]]), -s)
        ccw = counter_clockwise(v, t)
        assert (signed_areas(v, ccw) >= 0).all()
        assert all(set(a) == set(b) for a, b in zip(ccw, t))
        for tri, area in zip(t, s):
            assert polygon_area(v[tri]) == pytest.approx(area, abs=1e-9 * scale)
    else:
        np.testing.assert_allclose(np.linalg.norm(face_cross(v, t), axis=1), 2 * got,
                                   rtol=1e-12, atol=1e-12 * scale)


def test_polygon_area_of_a_square_with_its_orientation():
    square = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]])
    assert polygon_area(square) == 2.0
    assert polygon_area(square[::-1]) == -2.0


def _check_rotation(a, b):
    r = rotation_between(a, b)
    np.testing.assert_allclose(r.T @ r, np.eye(3), atol=1e-12)
    assert np.linalg.det(r) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(r @ (a / np.linalg.norm(a)), b / np.linalg.norm(b), atol=1e-12)
    return r


@settings(max_examples=200, deadline=None)
@given(vec3, vec3)
def test_the_rotation_maps_a_onto_b_and_is_orthonormal(a, b):
    r = _check_rotation(a, b)
    axis = np.cross(a, b)
    if np.linalg.norm(axis) > 1e-6 * np.linalg.norm(a) * np.linalg.norm(b):
        # the smallest rotation: about a x b, which it leaves in place
        np.testing.assert_allclose(r @ axis, axis, atol=1e-9 * np.linalg.norm(axis) + 1e-12)


@settings(max_examples=100, deadline=None)
@given(vec3, st.floats(0.01, 100.0), st.sampled_from([1.0, -1.0]))
def test_the_rotation_of_parallel_and_opposite_directions(a, scale, sign):
    b = sign * scale * a
    r = _check_rotation(a, b)
    if sign > 0:
        np.testing.assert_allclose(r, np.eye(3), atol=1e-12)
    else:  # a half turn: symmetric, trace -1
        np.testing.assert_allclose(r, r.T, atol=1e-12)
        assert np.trace(r) == pytest.approx(-1.0, abs=1e-12)


def test_axis_rotations_are_exact():
    down, up = np.array([0.0, -1.0, 0.0]), np.array([0.0, 1.0, 0.0])
    np.testing.assert_array_equal(rotation_between(up, up), np.eye(3))
    np.testing.assert_array_equal(rotation_between(down, up), np.diag([1.0, -1.0, -1.0]))
    np.testing.assert_array_equal(rotation_between([0.0, 0.0, 1.0], up) @ [0.0, 0.0, 1.0], up)
    with pytest.raises(ValueError, match="a, b"):
        rotation_between([0.0, 0.0, 0.0], up)


def test_euler_angles_compose_as_rz_ry_rx():
    r = euler_xyz_matrix([30, 40, 50])
    np.testing.assert_allclose(r, euler_xyz_matrix([0, 0, 50]) @ euler_xyz_matrix([0, 40, 0])
                               @ euler_xyz_matrix([30, 0, 0]), atol=1e-15)
    np.testing.assert_allclose(r.T @ r, np.eye(3), atol=1e-12)


def _grid(nx: int, ny: int, flips: list[bool], shuffle: int):
    """A triangulated (nx x ny)-cell grid, each cell cut along a chosen diagonal, vertices
    numbered in a shuffled order and triangles in a shuffled order and rotation."""
    rng = np.random.default_rng(shuffle)
    perm = rng.permutation((nx + 1) * (ny + 1))
    vid = perm.reshape(ny + 1, nx + 1)
    tris = []
    for j in range(ny):
        for i in range(nx):
            a, b, c, d = vid[j, i], vid[j, i + 1], vid[j + 1, i + 1], vid[j + 1, i]
            tris += [[a, b, c], [a, c, d]] if flips[j * nx + i] else [[a, b, d], [b, c, d]]
    t = np.array(tris)[rng.permutation(2 * nx * ny)]
    t = np.array([np.roll(row, k) for row, k in zip(t, rng.integers(0, 3, len(t)))])
    xy = np.zeros(((nx + 1) * (ny + 1), 3))
    jj, ii = np.meshgrid(np.arange(ny + 1), np.arange(nx + 1), indexing="ij")
    xy[vid.ravel(), 0], xy[vid.ravel(), 1] = ii.ravel(), jj.ravel()
    return xy, t


@st.composite
def grids(draw):
    nx, ny = draw(st.integers(1, 6)), draw(st.integers(1, 6))
    flips = draw(st.lists(st.booleans(), min_size=nx * ny, max_size=nx * ny))
    return nx, ny, _grid(nx, ny, flips, draw(st.integers(0, 2**31 - 1)))


@settings(max_examples=60, deadline=None)
@given(grids())
def test_edges_and_hinges_of_a_random_triangulated_grid(grid):
    nx, ny, (x, t) = grid
    interior = nx * (ny - 1) + (nx - 1) * ny + nx * ny  # inner grid lines and the diagonals
    total = nx * (ny + 1) + (nx + 1) * ny + nx * ny
    tm = trimesh.Trimesh(x, t, process=False)

    edges = unique_edges(t)
    assert len(edges) == total
    assert (edges[:, 0] < edges[:, 1]).all()
    np.testing.assert_array_equal(edges, np.unique(np.sort(tm.edges_unique, axis=1), axis=0))

    faces, corners = interior_edges(t)
    h = hinges(t)
    assert len(faces) == len(h) == interior
    pairs = {tuple(sorted(p)) for p in face_adjacency(t).tolist()}
    assert pairs == {tuple(sorted(p)) for p in faces.tolist()}
    assert pairs == {tuple(sorted(p)) for p in tm.face_adjacency.tolist()}
    want = {tuple(sorted(p)): set(o) for p, o in zip(tm.face_adjacency.tolist(),
                                                     tm.face_adjacency_unshared.tolist())}
    for (f1, f2), (k1, k2), (a, b, o1, o2) in zip(faces, corners, h):
        # the edge runs a -> b in triangle 1 and b -> a in triangle 2 (consistent winding)
        assert (t[f1, k1], t[f1, (k1 + 1) % 3]) == (a, b)
        assert {t[f2, k2], t[f2, (k2 + 1) % 3]} == {a, b}
        assert o1 == t[f1, (k1 + 2) % 3] and o2 == t[f2, (k2 + 2) % 3]
        assert {o1, o2} == want[tuple(sorted((f1, f2)))] and len({a, b, o1, o2}) == 4
    # ordered by the shared edge
    keys = np.sort(h[:, :2], axis=1)
    assert (np.diff(keys[:, 0] * len(x) + keys[:, 1]) > 0).all()


def test_an_edge_of_three_triangles_is_adjacent_but_no_hinge():
    t = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4], [1, 2, 5]])
    np.testing.assert_array_equal(face_adjacency(t), [[0, 1], [1, 2], [0, 3]])
    faces, _ = interior_edges(t)
    np.testing.assert_array_equal(faces, [[0, 3]])
    np.testing.assert_array_equal(hinges(t), [[1, 2, 0, 5]])


@settings(max_examples=40, deadline=None)
@given(grids())
def test_the_boundary_of_a_grid_is_its_outer_frame(grid):
    nx, ny, (x, t) = grid
    b = boundary_edges(t)
    assert len(b) == 2 * (nx + ny) and (b[:, 0] < b[:, 1]).all()
    on_frame = ((x[b][..., 0] == 0).all(1) | (x[b][..., 0] == nx).all(1)
                | (x[b][..., 1] == 0).all(1) | (x[b][..., 1] == ny).all(1))
    assert on_frame.all()


@given(k=st.integers(0, 12))
def test_the_inner_grid_holds_every_node_strictly_inside_once(k):
    bary = inner_grid(k)
    assert len(bary) == max(k - 1, 0) * max(k - 2, 0) // 2
    assert (bary > 0).all() and np.allclose(bary.sum(axis=1), 1.0)
    assert len({tuple(np.round(b * k).astype(int)) for b in bary}) == len(bary)


def test_longest_edges_of_flat_and_spatial_triangles():
    corners = np.array([[[0, 0], [3, 0], [0, 4]], [[0, 0], [1, 0], [0, 1]]], float)
    np.testing.assert_allclose(longest_edges(corners), [5.0, np.sqrt(2.0)])
    np.testing.assert_allclose(longest_edges(np.dstack([corners, np.zeros((2, 3))])),
                               [5.0, np.sqrt(2.0)])
