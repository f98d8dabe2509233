"""The C1 (quadratic B-spline) reading of the body's distance field that contact uses
(``body.sdf.smooth_sdf_query``; the solver's ``kernels.contact``): exact on linear fields,
close to a sphere's distance, a gradient that is the derivative of the value and continuous
across grid cell faces (the trilinear one jumps there), and a contact energy whose gradient
matches finite differences."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patternfit.body.sdf import sdf_query
from patternfit.sim import kernels

from scenes import sphere_field

ORIGIN = np.zeros(3)
H = 0.01


def _linear_grid(a, b, c, e, n=9):
    i, j, k = np.meshgrid(*[np.arange(n)] * 3, indexing="ij")
    return (a * H * i + b * H * j + c * H * k + e).astype(np.float32)


@settings(max_examples=40, deadline=None)
@given(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1), st.floats(-0.1, 0.1),
       st.lists(st.floats(0.02, 0.06), min_size=3, max_size=3))
def test_linear_field_is_reproduced_with_its_gradient(a, b, c, e, p):
    values = _linear_grid(a, b, c, e)
    d, g = kernels.smooth_sdf_query(values, ORIGIN, H, np.array([p]))
    assert abs(d[0] - (a * p[0] + b * p[1] + c * p[2] + e)) < 1e-6
    np.testing.assert_allclose(g[0], [a, b, c], atol=1e-5)


def _shell(seed, n, lo, hi):
    """``n`` random points [m] at radii in [lo, hi] around the origin."""
    rng = np.random.default_rng(seed)
    u = rng.normal(size=(n, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    return u * rng.uniform(lo, hi, size=(n, 1)), rng


def test_sphere_distance_is_close_and_gradient_is_the_derivative():
    field = sphere_field(0.1, half=0.2, h=0.005)
    x, _ = _shell(1, 200, 0.095, 0.12)
    d, g = kernels.smooth_sdf_query(field.values, field.origin, field.spacing, x)
    # the B-spline smooths by about h^2/8 * (2 / r): 0.06 mm here
    np.testing.assert_allclose(d, np.linalg.norm(x, axis=1) - 0.1, atol=2e-4)
    h = 1e-6
    for c in range(3):
        e = np.zeros(3)
        e[c] = h
        dp, _ = kernels.smooth_sdf_query(field.values, field.origin, field.spacing, x + e)
        dm, _ = kernels.smooth_sdf_query(field.values, field.origin, field.spacing, x - e)
        np.testing.assert_allclose(g[:, c], (dp - dm) / (2 * h), atol=1e-4)


def test_gradient_is_continuous_across_a_cell_face_where_trilinear_jumps():
    field = sphere_field(0.1, half=0.2, h=0.005)
    # a point just off the sphere, moved across the grid plane x = node 4 steps off axis
    face = field.origin[0] + field.spacing * np.round((0.06 - field.origin[0]) / field.spacing)
    y = np.sqrt(0.102 ** 2 - face ** 2)
    eps = 1e-9
    pts = np.array([[face - eps, y, 0.0], [face + eps, y, 0.0]])
    _, g_smooth = kernels.smooth_sdf_query(field.values, field.origin, field.spacing, pts)
    _, g_tri = sdf_query(field.values, field.origin, field.spacing, pts)
    assert np.abs(g_smooth[0] - g_smooth[1]).max() < 1e-5
    assert np.abs(g_tri[0] - g_tri[1]).max() > 1e-3


def test_contact_gradient_matches_finite_differences_and_spares_far_vertices():
    field = sphere_field(0.1, half=0.2, h=0.005)
    x, rng = _shell(2, 50, 0.098, 0.106)
    k = rng.uniform(10.0, 100.0, size=50)
    thickness = 0.003
    onset = 1e-3  # the shell's depths straddle it: both parts of the contact law

    def energy(y):
        return kernels.contact(y, field.values, field.origin, field.spacing, thickness, k,
                               onset, np.full_like(y, np.inf), np.zeros(len(y)),
                               np.zeros_like(y))

    grad = np.zeros_like(x)
    seen, room = np.full_like(x, np.inf), np.zeros(len(x))
    e = kernels.contact(x, field.values, field.origin, field.spacing, thickness, k, onset,
                        seen, room, grad)
    assert e > 0 and (np.abs(grad).sum(axis=1) > 0).any()
    h = 1e-7
    fd = np.zeros_like(x)
    for i in range(len(x)):
        for c in range(3):
            xp, xm = x.copy(), x.copy()
            xp[i, c] += h
            xm[i, c] -= h
            fd[i, c] = (energy(xp) - energy(xm)) / (2 * h)
    np.testing.assert_allclose(grad, fd, atol=1e-6 * np.abs(grad).max())
    # vertices far outside are not looked up again while they stay within their room
    far = room > 0
    assert far.any()
    again = np.zeros_like(x)
    kernels.contact(x, field.values, field.origin, field.spacing, thickness, k, onset, seen,
                    room, again)
    np.testing.assert_allclose(again, grad)


def test_contact_law_is_smooth_at_the_layer_edge_and_at_the_onset():
    """Energy, force and stiffness of the contact are continuous (the stiffness grows from 0
    at the layer's edge to k at the onset), the force is the energy's derivative and the
    stiffness the force's, and the solver's array form agrees."""
    k, onset = 250.0, 1e-4
    pens = np.array([1e-9, 3e-5, onset * (1 - 1e-9), onset * (1 + 1e-9), 4e-4, 2e-3])
    law = np.array([kernels.contact_law(p, k, onset) for p in pens])
    assert law[0, 2] < 1e-3 * k  # no stiffness jump at the edge
    np.testing.assert_allclose(law[2], law[3], rtol=1e-6)  # nor at the onset
    h = 1e-9
    for p, (e, f, s) in zip(pens[1:], law[1:]):
        ep, fp, _ = kernels.contact_law(p + h, k, onset)
        em, fm, _ = kernels.contact_law(p - h, k, onset)
        assert abs((ep - em) / (2 * h) - f) <= 1e-6 * f
        assert abs((fp - fm) / (2 * h) - s) <= 1e-5 * s
    force, stiff = kernels.contact_forces(pens, np.full(len(pens), k), onset)
    np.testing.assert_allclose(force, law[:, 1])
    np.testing.assert_allclose(stiff, law[:, 2])
    # onset 0 is the plain quadratic penalty k pen^2 / 2
    e, f, s = kernels.contact_law(2e-3, k, 0.0)
    assert (e, f, s) == pytest.approx((0.5 * k * 4e-6, k * 2e-3, k))


def test_friction_law_gives_way_smoothly_and_its_inverse_holds():
    """Friction's force grows to the Coulomb limit at the slip distance with a stiffness that
    falls continuously to 0 there; the array forms agree with the kernel, and
    ``friction_offset`` finds the offset at which friction pulls with a given force."""
    limit, slip = 0.02, 1e-3
    ms = np.array([0.0, 2e-4, 0.5 * slip, 7e-4, slip * (1 - 1e-9), slip * (1 + 1e-9), 3e-3])
    law = np.array([kernels.friction_law(m, limit, slip) for m in ms])
    force = law[:, 1] * ms
    assert force[-1] == pytest.approx(limit) and force[4] == pytest.approx(limit)
    assert law[4, 2] == pytest.approx(0.0, abs=1e-6 * law[0, 2]) and law[-1, 2] == 0.0
    h = 1e-10
    for m, (e, ratio, k) in zip(ms[1:], law[1:]):
        ep, rp, _ = kernels.friction_law(m + h, limit, slip)
        em, rm, _ = kernels.friction_law(m - h, limit, slip)
        assert abs((ep - em) / (2 * h) - ratio * m) <= 1e-6 * limit
        assert abs((rp * (m + h) - rm * (m - h)) / (2 * h) - k) <= 1e-5 * law[0, 2]
    ratio, stiff = kernels.friction_stiffness(ms, np.full(len(ms), limit), slip)
    np.testing.assert_allclose(ratio, law[:, 1])
    np.testing.assert_allclose(stiff, law[:, 2], atol=1e-9 * law[0, 2])
    np.testing.assert_allclose(kernels.friction_offset(force[:5], np.full(5, limit), slip),
                               ms[:5], rtol=1e-6, atol=1e-12)
    # a force beyond the limit is held at the slip distance
    assert kernels.friction_offset(np.array([2 * limit]), np.array([limit]), slip)[0] == \
        pytest.approx(slip)
