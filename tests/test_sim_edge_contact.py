"""Body contact between the vertices: the edge contact points (``SolverSettings.edge_contact``,
``ClothModel.edge_points``) and the count of edges through the body
(``sim.checks.edges_in_body``)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from patternfit.sim.checks import drape_checks, edges_in_body, faces_in_body
from patternfit.sim.model import EdgePoints
from patternfit.sim.settings import SolverSettings
from patternfit.sim.solver import GarmentSolver
from patternfit.sim.total_energy import edge_stiffness, energy, hessian, hessian_pattern

from scenes import fd_gradient, grain_at, sphere_field

R = 0.05


def _square_on_sphere(depth, spacing):
    """Two triangles (a 6 cm square) lying across the top of a sphere of radius R, the
    square's centre ``depth`` [m] inside it: the corners are 13 mm clear, only the points
    of the diagonal edge near the centre are inside."""
    v = np.array([[-0.03, -0.03], [0.03, -0.03], [0.03, 0.03], [-0.03, 0.03]])
    t = np.array([[0, 1, 2], [0, 2, 3]])
    x = np.c_[v[:, 0], np.full(4, R - depth), v[:, 1]]
    solver = GarmentSolver(v, t, grain_at(0, 2), "cotton_shirting",
                           body=sphere_field(R, half=0.1, h=0.0025),
                           settings=SolverSettings(max_iterations=0, edge_contact=spacing))
    return solver, x


def test_points_are_evenly_spaced_inside_each_edge_and_weighted_by_where_they_lie():
    pts = EdgePoints.of(np.array([[0, 1], [1, 2], [2, 3]]), np.array([0.025, 0.01, 0.031]),
                        0.01, 4)
    # 2.5 cm -> 2 points, 1 cm -> none (its ends are 1 cm apart), 3.1 cm -> 3 points
    # (a third vertex of weight 0: the first again)
    np.testing.assert_array_equal(pts.ids, [[0, 1, 0], [0, 1, 0], [2, 3, 2], [2, 3, 2],
                                            [2, 3, 2]])
    np.testing.assert_allclose(pts.w[:, 1], [1 / 3, 2 / 3, 0.25, 0.5, 0.75])
    np.testing.assert_allclose(pts.w[:, 2], 0.0)
    assert pts.n_edge == 5
    np.testing.assert_allclose(pts.w.sum(axis=1), 1.0)
    x = np.random.default_rng(0).normal(size=(4, 3))
    np.testing.assert_allclose(pts.matrix @ x, pts.w[:, :1] * x[pts.ids[:, 0]]
                               + pts.w[:, 1:2] * x[pts.ids[:, 1]])
    assert not len(EdgePoints.of(np.array([[0, 1]]), np.array([0.05]), 0.0, 2).ids)


def test_a_triangle_wider_than_the_spacing_gets_the_inner_nodes_of_its_grid():
    tris = np.array([[0, 1, 2], [1, 2, 3], [2, 3, 4]])
    pts = EdgePoints.of(np.zeros((0, 2)), np.zeros(0), 0.01, 5, tris,
                        np.array([0.035, 0.02, 0.025]))
    # 3.5 cm -> 4 steps a side, 3 inner nodes; 2 cm -> 2 steps, none; 2.5 cm -> 3, the centroid
    np.testing.assert_array_equal(pts.ids, [[0, 1, 2]] * 3 + [[2, 3, 4]])
    assert pts.n_edge == 0
    np.testing.assert_allclose(np.sort(pts.w[:3], axis=1), [[0.25, 0.25, 0.5]] * 3)
    assert len({tuple(w) for w in pts.w[:3]}) == 3
    np.testing.assert_allclose(pts.w[3], 1 / 3)
    x = np.random.default_rng(1).normal(size=(5, 3))
    np.testing.assert_allclose(pts.matrix @ x, np.einsum("pj,pjc->pc", pts.w, x[pts.ids]))


@settings(max_examples=60, deadline=None)
@given(corners=arrays(np.float64, (3, 2), elements=st.floats(-0.08, 0.08)),
       spacing=st.floats(0.004, 0.03))
def test_every_point_of_a_triangle_lies_within_the_spacing_of_a_contact_point(corners,
                                                                               spacing):
    """What the points are for: no part of a triangle (a body feature under it) is further
    than ``spacing`` from a vertex, an edge point or a face point."""
    a, b, c = corners
    area = 0.5 * abs((b - a)[0] * (c - a)[1] - (b - a)[1] * (c - a)[0])
    assume(area > 1e-6)
    tri = np.array([[0, 1, 2]])
    edges = np.array([[0, 1], [1, 2], [0, 2]])
    lengths = np.linalg.norm(corners[edges[:, 0]] - corners[edges[:, 1]], axis=1)
    pts = EdgePoints.of(edges, lengths, spacing, 3, tri, np.array([lengths.max()]))
    nodes = np.r_[corners, pts.matrix @ corners]
    bary = np.random.default_rng(2).dirichlet(np.ones(3), size=400)
    probe = bary @ corners
    nearest = np.linalg.norm(probe[:, None] - nodes[None], axis=2).min(axis=1)
    assert nearest.max() <= spacing


def test_a_body_into_the_middle_of_a_triangle_pushes_all_three_corners():
    """A 10 cm triangle over a 5 cm ball, its centre 3 mm inside and its corners and
    edges clear: the points inside the triangle push its corners out, with the gradient of
    the energy."""
    side = 0.1
    v = side * np.array([[-0.5, -np.sqrt(3) / 6], [0.5, -np.sqrt(3) / 6], [0.0, np.sqrt(3) / 3]])
    t = np.array([[0, 1, 2]])
    x = np.c_[v[:, 0], np.full(3, R - 0.003), v[:, 1]]
    solver = GarmentSolver(v, t, grain_at(0, 1), "cotton_shirting",
                           body=sphere_field(R, half=0.1, h=0.0025),
                           settings=SolverSettings(max_iterations=0, edge_contact=0.01))
    assert edges_in_body(solver.model, x) == 0 and faces_in_body(solver.model, x) == 1
    solver.solve(x)
    m, st_ = solver.model, solver.state
    e, g = energy(m, st_, x, settings=solver.settings)
    assert (g[:, 1] < 0).all()  # the force, -g, lifts every corner
    assert m.edge_points(0.01).w[:, 2].any()  # points inside the triangle
    fd = fd_gradient(lambda y: energy(m, st_, y, settings=solver.settings)[0], x)
    np.testing.assert_allclose(g, fd, atol=1e-6 * np.abs(g).max())
    # stiffened vertices stiffen their edge points up to 16 times, never their face points
    st_.contact_scale[:] = 64.0
    k = edge_stiffness(m, st_, solver.settings)
    face = m.edge_points(0.01).w[:, 2] > 0
    base = solver.settings.contact_stiffness * m.terms.vertex_area
    np.testing.assert_allclose(k[face], (m.edge_points(0.01).matrix @ base)[face])
    np.testing.assert_allclose(k[~face], 16.0 * (m.edge_points(0.01).matrix @ base)[~face])


def test_an_edge_across_the_body_is_pushed_out_though_its_vertices_are_clear():
    """Vertices alone feel nothing; the edge points push, with the gradient of the energy
    (finite differences) and a Hessian that is its derivative (a sphere's field is not
    planar, so the check is on the normal direction the contact's Gauss-Newton term
    models)."""
    off, x = _square_on_sphere(0.003, 0.0)
    on, _ = _square_on_sphere(0.003, 0.01)
    off.solve(x)  # (max_iterations 0: sets the contact state up at x)
    on.solve(x)
    e_off, g_off = energy(off.model, off.state, x, settings=off.settings)
    e_on, g_on = energy(on.model, on.state, x, settings=on.settings)
    assert e_on > e_off
    push = (g_off - g_on)[:, 1]  # the contact's extra force, upwards on every vertex
    assert (push[[0, 2]] > 0).all()  # the diagonal's ends carry it
    fd = fd_gradient(lambda y: energy(on.model, on.state, y, settings=on.settings)[0], x)
    np.testing.assert_allclose(g_on, fd, atol=1e-6 * np.abs(g_on).max())
    h = 1e-7
    # along the vertical (the field's normal at the top) the Hessian is the gradient's
    # derivative: the contact's part of it
    H_on = hessian(on.model, on.state, x, settings=on.settings,
                   pattern=hessian_pattern(on.model)).toarray()
    H_off = hessian(off.model, off.state, x, settings=off.settings,
                    pattern=hessian_pattern(off.model)).toarray()
    up = np.zeros((4, 3))
    up[:, 1] = 1.0
    dg = (energy(on.model, on.state, x + h * up, settings=on.settings)[1]
          - energy(on.model, on.state, x - h * up, settings=on.settings)[1]
          - energy(off.model, off.state, x + h * up, settings=off.settings)[1]
          + energy(off.model, off.state, x - h * up, settings=off.settings)[1]) / (2 * h)
    np.testing.assert_allclose(((H_on - H_off) @ up.ravel()).reshape(4, 3)[:, 1], dg[:, 1],
                               rtol=0.05)


def test_edges_through_the_body_are_counted_and_fail_the_checks():
    solver, x = _square_on_sphere(0.003, 0.0)
    assert edges_in_body(solver.model, x) == 1  # the diagonal; the sides are clear
    checks = drape_checks(solver.model, x, settings=solver.settings, converged=True)
    assert checks.inside_vertices == 0 and checks.edges_in_body == 1
    assert not checks.passed and checks.to_dict()["edges_in_body"] == 1
    # 0.5 mm deep is within the tolerance a vertex gets too
    solver, x = _square_on_sphere(0.0005, 0.0)
    assert edges_in_body(solver.model, x) == 0


@pytest.mark.parametrize("spacing", [0.0, 0.01])
def test_a_coarse_coat_keeps_the_body_out_between_its_vertices(spacing):
    """The 1.5K coat on male_average: with contact at the vertices alone its edges cut
    into the arms and shoulders (some 200 edges, up to 15 mm), and its checks now say so;
    with the edge points none does."""
    from patternfit import api

    out = api.drape_and_evaluate("coat", "male_average", triangles=1500,
                                 settings=SolverSettings(edge_contact=spacing))
    checks = out.extra["checks"]
    if spacing:
        assert checks["edges_in_body"] == 0 and checks["inside_vertices"] == 0
        assert checks["passed"], checks["reasons"]
    else:
        assert checks["edges_in_body"] > 50 and not checks["passed"]
        assert any("edges through the body" in r for r in checks["reasons"])


def test_a_bump_through_a_large_triangle_is_counted_and_seen_by_the_fine_edges_across_it():
    """A 1 cm ball poking 4 mm through the face of a 6 cm triangle, clear of its corners and
    edges, is through no coarse edge but through that face (``faces_in_body``: the checks
    fail); the fine mesh of the same square, laid on the same plane, has edges through it,
    which is why a coarse drape is checked before it is carried to a fine mesh (the coarse
    tries of ``sim.drape``)."""
    v = np.array([[-0.03, -0.03], [0.03, -0.03], [0.03, 0.03], [-0.03, 0.03]])
    coarse = np.array([[0, 1, 2], [0, 2, 3]])
    g = np.linspace(-0.03, 0.03, 13)
    fv = np.array([[a, b] for b in g for a in g])
    fine = np.array([[r * 13 + c, r * 13 + c + 1, (r + 1) * 13 + c + 1] for r in range(12)
                     for c in range(12)] + [[r * 13 + c, (r + 1) * 13 + c + 1, (r + 1) * 13 + c]
                                             for r in range(12) for c in range(12)])
    field = sphere_field(0.01, half=0.06, h=0.0025)
    centroid = v[[0, 1, 2]].mean(axis=0)  # (0.01, -0.01): inside the first triangle
    for rest, tris, through in ((v, coarse, False), (fv, fine, True)):
        solver = GarmentSolver(rest, tris, grain_at(0, len(tris)), "cotton_shirting",
                               body=field, settings=SolverSettings(max_iterations=0))
        # the sheet in the plane y = 6 mm, the ball's top (1 cm) under the centroid
        x = np.c_[rest[:, 0] - centroid[0], np.full(len(rest), 0.006), rest[:, 1] - centroid[1]]
        assert (edges_in_body(solver.model, x) > 0) == through
        if not through:
            assert faces_in_body(solver.model, x) == 1  # the first triangle, not the second
            checks = drape_checks(solver.model, x, settings=solver.settings, converged=True)
            assert not checks.passed and checks.to_dict()["faces_in_body"] == 1
            x[:, 1] = 0.0105  # lifted clear of the ball
            assert faces_in_body(solver.model, x) == 0


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), n_edge=st.integers(0, 40))
def test_the_fused_point_kernel_equals_the_points_assembled_and_their_forces_shared(seed,
                                                                                   n_edge):
    """``kernels.point_contact`` (positions, stiffness and the forces' sharing done inside
    the loop) against the same contact assembled with the points' matrix: the points'
    positions ``matrix @ x``, ``kernels.contact`` on them, forces back by ``matrix.T``; the
    lookups it keeps spare later calls without changing them."""
    import scipy.sparse as sp

    from patternfit.sim import kernels

    rng = np.random.default_rng(seed)
    n, p = 30, 60
    x = rng.normal(scale=0.03, size=(n, 3)) + [0.0, R, 0.0]
    ids = rng.integers(0, n, size=(p, 3))
    w = rng.dirichlet(np.ones(3), size=p)
    w[:n_edge, 2] = 0.0
    w[:n_edge, :2] /= w[:n_edge, :2].sum(axis=1, keepdims=True)
    base, scale = rng.uniform(1.0, 5.0, n), 4.0 ** rng.integers(0, 7, n)
    body = sphere_field(R, half=0.1, h=0.0025)
    args = (body.values, body.origin, body.spacing, 0.004)
    grad, seen, room = np.zeros((n, 3)), np.full((p, 3), np.inf), np.zeros(p)
    e = kernels.point_contact(x, ids, w, n_edge, base, scale, 16.0, 1.0, *args, 0.001, seen,
                              room, grad)
    # again from the lookups kept, 0.1 mm further: only the points in reach are looked up
    # and the sums are the fresh ones
    y, again = x + 1e-4, np.zeros((n, 3))
    e2 = kernels.point_contact(y, ids, w, n_edge, base, scale, 16.0, 1.0, *args, 0.001, seen,
                               room, again)
    fresh = np.zeros((n, 3))
    e3 = kernels.point_contact(y, ids, w, n_edge, base, scale, 16.0, 1.0, *args, 0.001,
                               np.full((p, 3), np.inf), np.zeros(p), fresh)
    assert e2 == e3 and (again == fresh).all()
    matrix = sp.csr_matrix((w.ravel(), (np.repeat(np.arange(p), 3), ids.ravel())),
                           shape=(p, n))
    cap = np.where(np.arange(p) < n_edge, 16.0, 1.0)
    k = np.einsum("pj,pj->p", w, base[ids] * np.minimum(scale[ids], cap[:, None]))
    fp = np.zeros((p, 3))
    e_ref = kernels.contact(matrix @ x, *args, k, 0.001, np.full((p, 3), np.inf),
                            np.zeros(p), fp)
    assert e_ref > 0  # some points in contact
    np.testing.assert_allclose(e, e_ref, rtol=1e-12)
    np.testing.assert_allclose(grad, matrix.T @ fp, rtol=1e-10, atol=1e-12 * abs(fp).max())
    np.testing.assert_allclose(kernels.point_stiffness(ids, w, n_edge, base, scale, 16.0, 1.0),
                               k, rtol=1e-12)
