"""Finite-difference checks of the energy terms, the Newton Hessian and the residual force
(patternfit.sim.kernels, patternfit.sim.solver)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from patternfit.constants import GRAVITY
from patternfit.sim import kernels
from patternfit.sim.energies import build_terms, spring_matrix
from patternfit.sim.settings import SolverSettings
from patternfit.sim.solver import GarmentSolver
from patternfit.sim.total_energy import energy

from scenes import fd_gradient, grain_at, rect_mesh, sphere_field

FABRIC = dict(k_warp=900.0, k_weft=600.0, k_shear=40.0)


def _sheet(seed=0, scale=3e-3):
    v, t = rect_mesh(0.06, 0.04, 2e-4)
    grain = grain_at(30, len(t))
    terms = build_terms(v, t, grain, np.arange(len(v)), len(v), bend_warp=1e-5,
                        bend_weft=2e-5, **FABRIC)
    rng = np.random.default_rng(seed)
    x = np.c_[v, np.zeros(len(v))] + rng.normal(scale=scale, size=(len(v), 3))
    return v, t, terms, x


@pytest.mark.parametrize("compression, gathered", [(1.0, False), (0.05, False), (1.0, True)])
def test_membrane_gradient_matches_finite_differences(compression, gathered):
    _, _, T, x = _sheet()
    # gathered: every triangle may shrink by up to 0-30 % at no cost, as in a gathered seam's
    # band (the sheet's yarn strains run from -23 % to +44 %: some within their slack, some
    # beyond it)
    slack = (np.random.default_rng(5).uniform(0.0, 0.3, (len(T.tris), 2)) if gathered
             else np.zeros((len(T.tris), 2)))

    def energy(y):
        return kernels.membrane(y, T.tris, T.cu, T.cv, T.area, FABRIC["k_warp"],
                                FABRIC["k_weft"], FABRIC["k_shear"], compression, slack,
                                np.zeros_like(y))

    grad = np.zeros_like(x)
    kernels.membrane(x, T.tris, T.cu, T.cv, T.area, FABRIC["k_warp"], FABRIC["k_weft"],
                     FABRIC["k_shear"], compression, slack, grad)
    np.testing.assert_allclose(grad, fd_gradient(energy, x), atol=1e-6 * np.abs(grad).max())


def test_a_gathered_yarn_is_free_in_its_slack_and_smooth_at_its_corners():
    # one triangle, the warp along x, squeezed and stretched along x only: the yarn's
    # tension is 0 from 0 down to -slack, full stiffness beyond, and the Hessian (C2 energy)
    # is the tension's derivative everywhere, in the rounded corners too
    v = np.array([[0.0, 0.0], [0.01, 0.0], [0.0, 0.01]])
    t = np.array([[0, 1, 2]])
    T = build_terms(v, t, grain_at(0, 1), np.arange(3), 3, bend_warp=1e-5, bend_weft=1e-5,
                    **FABRIC)
    slack = np.array([[0.3, 0.0]])  # the warp's slack; the weft (along y, unstrained) none
    dof = (3 * T.tris[:, :, None] + np.arange(3)).reshape(-1, 9)
    slots = (dof[:, :, None] * 9 + dof[:, None, :]).ravel()
    along = np.zeros((3, 3))
    along[:, 0] = v[:, 0]  # d x / d e: stretching along x by e

    def tension_and_stiffness(e):
        x = np.c_[v, np.zeros(3)] + e * along
        g = np.zeros_like(x)
        kernels.membrane(x, T.tris, T.cu, T.cv, T.area, FABRIC["k_warp"], FABRIC["k_weft"],
                         0.0, 1.0, slack, g)
        out = np.zeros(81)
        kernels.membrane_hessian(x, T.tris, T.cu, T.cv, T.area, FABRIC["k_warp"],
                                 FABRIC["k_weft"], 0.0, 1.0, slack, slots, out)
        d = along.ravel()
        return float(g.ravel() @ d), float(d @ out.reshape(9, 9) @ d)

    h = kernels.energy_terms.SLACK_ROUND
    for e in (-0.2, -0.1, -0.001):
        assert tension_and_stiffness(e) == (0.0, 0.0)
    assert tension_and_stiffness(-0.4)[0] < 0.0 < tension_and_stiffness(0.1)[0]
    # no jump of the stiffness where the yarn leaves its slack either way
    full = tension_and_stiffness(0.1)[1]
    assert tension_and_stiffness(1e-6)[1] < 1e-3 * full
    assert tension_and_stiffness(-0.3 - 1e-6)[1] < 1e-3 * full
    step = 1e-7
    for e in (0.5 * h, 2 * h, 0.05, -0.3 - 0.5 * h, -0.3 - 2 * h, -0.4):
        slope = (tension_and_stiffness(e + step)[0]
                 - tension_and_stiffness(e - step)[0]) / (2 * step)
        assert tension_and_stiffness(e)[1] == pytest.approx(slope, rel=1e-4)


def test_membrane_hessian_is_exact_in_pure_stretch_and_psd_everywhere():
    v, _, T, _ = _sheet()
    # stretched 2 % along x and 1 % along y, the grain turned: every yarn stretched, shear
    # small; the Hessian is the derivative of the gradient there
    x = np.c_[1.02 * v[:, 0], 1.01 * v[:, 1], np.zeros(len(v))]
    n = len(v)

    def grad_at(y):
        g = np.zeros_like(y)
        kernels.membrane(y, T.tris, T.cu, T.cv, T.area, FABRIC["k_warp"], FABRIC["k_weft"],
                         0.0, 1.0, np.zeros((len(T.tris), 2)), g)
        return g.ravel()

    def hessian(y, k_shear=0.0, compression=1.0):
        # each block entry's slot: its place in the dense 3n x 3n matrix, flattened
        dof = (3 * T.tris[:, :, None] + np.arange(3)).reshape(-1, 9)
        slots = (dof[:, :, None] * 3 * n + dof[:, None, :]).ravel()
        out = np.zeros(9 * n * n)
        kernels.membrane_hessian(y, T.tris, T.cu, T.cv, T.area, FABRIC["k_warp"],
                                 FABRIC["k_weft"], k_shear, compression, np.zeros((len(T.tris), 2)),
                                 slots, out)
        return out.reshape(3 * n, 3 * n)

    H = hessian(x)
    h = 1e-7
    rng = np.random.default_rng(3)
    for _ in range(5):
        d = rng.normal(size=x.shape)
        fd = (grad_at(x + h * d) - grad_at(x - h * d)) / (2 * h)
        np.testing.assert_allclose(H @ d.ravel(), fd, atol=1e-5 * np.abs(fd).max())
    # a crumpled state: the projected Hessian stays positive semi-definite
    _, _, _, y = _sheet(seed=2, scale=5e-3)
    for comp in (1.0, 0.05):
        assert np.linalg.eigvalsh(hessian(y, FABRIC["k_shear"], comp)).min() > -1e-8


def test_contact_friction_seam_and_repulsion_gradients():
    rng = np.random.default_rng(4)
    field = sphere_field(0.1, half=0.2, h=0.01)
    x = rng.normal(size=(30, 3))
    x = 0.1015 * x / np.linalg.norm(x, axis=1, keepdims=True)  # in the 3 mm layer
    k = np.full(len(x), 2e3)
    seen, room = np.full((len(x), 3), np.inf), np.zeros(len(x))

    def contact(y, g):
        seen[:] = np.inf
        room[:] = 0.0
        # an onset of 2 mm: the 1.5 mm deep vertices lie on its ramp
        return kernels.contact(y, field.values, field.origin, field.spacing, 0.003, k, 2e-3,
                               seen, room, g)

    idx = np.arange(0, 30, 2)
    anchor = x[idx] + rng.normal(scale=1e-3, size=(len(idx), 3))
    nrm = x[idx] / np.linalg.norm(x[idx], axis=1, keepdims=True)
    limit = np.full(len(idx), 0.01)

    def friction(y, g):
        return kernels.friction(y, idx, anchor, nrm, limit, 1e-3, g)

    a, b = np.arange(0, 10), np.arange(10, 20)

    # both regimes of the bounded seam pull: limit / k = 1 cm; the gaps straddle it
    x[b[:5]] = x[a[:5]] + rng.normal(scale=2e-3, size=(5, 3))
    gaps = np.linalg.norm(x[a] - x[b], axis=1)
    assert (gaps < 0.01).any() and (gaps > 0.01).any()

    def seams(y, g):
        return kernels.seam_springs(y, a, b, 50.0, np.full(10, 0.5), g)

    # and both of friction's: sticking (|u| < slip) and sliding
    u = x[idx] - anchor
    u -= np.einsum("ij,ij->i", u, nrm)[:, None] * nrm
    assert (np.linalg.norm(u, axis=1) < 1e-3).any() and (np.linalg.norm(u, axis=1) > 1e-3).any()

    for term in (contact, friction, seams):
        grad = np.zeros_like(x)
        term(x, grad)
        fd = fd_gradient(lambda y: term(y, np.zeros_like(y)), x)
        np.testing.assert_allclose(grad, fd, atol=1e-6 * max(np.abs(grad).max(), 1e-9))
    # vertex-triangle repulsion
    tris = np.array([[0, 1, 2]])
    y = np.array([[0.0, 0.0, 0.0], [0.02, 0.0, 0.0], [0.0, 0.02, 0.0], [0.005, 0.005, 0.002]])
    pairs = np.array([[3, 0]])
    bary = np.array([[0.5, 0.25, 0.25]])
    normal = np.array([[0.0, 0.0, 1.0]])
    ks = np.full(4, 80.0)

    def rep(z, g):
        return kernels.self_repulsion(z, tris, pairs, bary, normal, 0.004, ks, g)

    grad = np.zeros_like(y)
    assert rep(y, grad) > 0
    np.testing.assert_allclose(grad, fd_gradient(lambda z: rep(z, np.zeros_like(z)), y),
                               atol=1e-7)


def test_bending_and_weld_springs_are_quadratic_forms_with_the_right_gradient():
    """The bending matrix Q and the welded seams' spring matrix enter the energy as
    ``sum_c x_c^T Q x_c / 2`` with gradient ``Q x``: finite differences agree, and bending
    costs nothing on a rigid motion of the flat sheet but something on a fold."""
    v, _, T, x = _sheet(seed=6)
    n = len(v)
    pairs = np.c_[np.arange(0, 5), np.arange(5, 10)]
    for Q in (T.bending, spring_matrix(pairs, 40.0, n)):
        Q = Q.tocsr()

        def energy(y, Q=Q):
            return 0.5 * float(np.einsum("ij,ij->", y, Q @ y))

        np.testing.assert_allclose(Q @ x, fd_gradient(energy, x),
                                   atol=1e-6 * np.abs(Q @ x).max())
    flat = np.c_[v, np.zeros(n)]
    c, s = np.cos(0.7), np.sin(0.7)
    rigid = flat @ np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]).T + [0.1, -0.2, 0.3]
    fold = flat.copy()
    fold[:, 2] = 0.3 * np.maximum(v[:, 0] - 0.03, 0.0)
    bend = T.bending.tocsr()
    scale = np.abs(bend).sum()
    for y in (flat, rigid):
        assert np.abs(bend @ y).max() < 1e-9 * scale
    assert 0.5 * float(np.einsum("ij,ij->", fold, bend @ fold)) > 1e-9


@settings(max_examples=40, deadline=None)
@given(n=st.integers(1, 40), density=st.floats(0.0, 0.5), seed=st.integers(0, 2**31 - 1))
def test_the_quadratic_kernel_is_the_quadratic_form_with_forces(n, density, seed):
    """``kernels.quadratic`` on any sparse Q (unsorted rows, explicit zeros, empty rows)
    gives the energy ``x^T Q x / 2 - f . x`` and adds the gradient ``Q x - f``."""
    rng = np.random.default_rng(seed)
    Q = sp.random(n, n, density=density, random_state=rng, format="csr")
    Q = (Q + Q.T).tocsr()
    Q.data[rng.uniform(size=len(Q.data)) < 0.1] = 0.0
    perm = rng.permutation(len(Q.indices))  # a row's entries in any order
    for i in range(n):
        lo, hi = Q.indptr[i], Q.indptr[i + 1]
        order = lo + np.argsort(perm[lo:hi])
        Q.indices[lo:hi], Q.data[lo:hi] = Q.indices[order], Q.data[order]
    x = rng.normal(size=(n, 3))
    f = rng.normal(size=(n, 3))
    grad = rng.normal(size=(n, 3))
    start = grad.copy()
    e = kernels.quadratic(Q.indptr, Q.indices, Q.data, x, f, grad)
    qx = Q @ x
    want = 0.5 * float(np.sum(x * qx)) - float(np.sum(f * x))
    assert e == pytest.approx(want, rel=1e-12, abs=1e-12 * (1.0 + np.abs(x * qx).sum()))
    np.testing.assert_allclose(grad, start + qx - f, rtol=1e-12, atol=1e-12)


def test_the_energy_takes_any_sparse_quadratic_and_refuses_one_of_another_size():
    """The kernel reads Q as CSR, unchecked: another sparse format gives the same energy,
    and a state whose Q is not the model's size is refused."""
    v, t = rect_mesh(0.1, 0.1, 2e-4)
    solver = GarmentSolver(v, t, grain_at(0, len(t)), "cotton_shirting",
                           settings=SolverSettings(max_iterations=0, self_collision=False))
    x = np.c_[v[:, 0], 0.01 * np.sin(40 * v[:, 0]), v[:, 1]]
    solver.solve(x)
    state = solver.state
    e, g = energy(solver.model, state, x, settings=solver.settings)
    state.quadratic = state.quadratic.tocsc()
    e2, g2 = energy(solver.model, state, x, settings=solver.settings)
    assert e2 == e and np.array_equal(g2, g)
    state.quadratic = sp.identity(len(v) - 1, format="csr")
    with pytest.raises(ValueError, match="state.quadratic"):
        energy(solver.model, state, x, settings=solver.settings)


def test_residual_of_an_unsupported_flat_sheet_is_its_weight():
    """Nothing holds it: every free vertex's total force is its weight, rms = p99 = 1."""
    v, t = rect_mesh(0.2, 0.1, 2e-4)
    solver = GarmentSolver(v, t, grain_at(0, len(t)), "cotton_shirting",
                           settings=SolverSettings(max_iterations=0, self_collision=False))
    res = solver.solve(np.c_[v[:, 0], np.zeros(len(v)), v[:, 1]])
    assert res.checks.residual_rms == pytest.approx(1.0, rel=1e-6)
    assert res.checks.residual_p99 == pytest.approx(1.0, rel=1e-6)
    assert not res.checks.equilibrium and "residual_rms" in res.checks.to_dict()


def test_weight_ratios_are_numpys_over_the_free_vertices_of_mass():
    rng = np.random.default_rng(11)
    grad = rng.normal(size=(50, 3))
    mass = rng.uniform(1e-5, 1e-3, size=50)
    mass[[3, 17]] = 0.0
    free = rng.uniform(size=50) > 0.2
    out = np.full(50, np.nan)
    k = kernels.weight_ratios2(grad, mass, free, GRAVITY, out)
    keep = free & (mass > 0)
    want = (grad[keep] ** 2).sum(axis=1) / (mass[keep] * GRAVITY) ** 2
    assert k == keep.sum() and np.array_equal(out[:k], want)


def test_residual_is_the_finite_difference_force_of_the_total_energy():
    """A crumpled sheet pinned on one edge, lying on a sphere: the reported residual is the
    rms of |dE/dx_i| / (m_i g) with dE/dx taken by finite differences of the energy."""
    v, t = rect_mesh(0.1, 0.1, 4e-4)
    v -= 0.05
    pinned = np.flatnonzero(v[:, 0] < -0.05 + 1e-9)
    body = sphere_field(0.1, half=0.2)
    rng = np.random.default_rng(5)
    x0 = np.c_[v[:, 0], np.full(len(v), 0.102), v[:, 1]] + rng.normal(scale=1e-3,
                                                                     size=(len(v), 3))
    solver = GarmentSolver(v, t, grain_at(20, len(t)), "cotton_shirting", body=body,
                           pinned=pinned, settings=SolverSettings(max_iterations=0))
    res = solver.solve(x0)
    fd = fd_gradient(lambda y: energy(solver.model, solver.state, y,
                                       settings=solver.settings)[0], x0, h=1e-8)
    free = np.ones(len(v), bool)
    free[pinned] = False
    r = np.linalg.norm(fd[free], axis=1) / (solver.model.mass[free] * GRAVITY)
    assert res.checks.residual_rms == pytest.approx(np.sqrt(np.mean(r ** 2)), rel=1e-4)
    assert res.checks.residual_p99 == pytest.approx(np.percentile(r, 99), rel=1e-3)
