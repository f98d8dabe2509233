"""The solver's parts (patternfit.sim.model, .state, .total_energy, .solver.solve): the cloth
model is frozen, the energy is a pure function of model, state and positions, and a solve's
state round-trips through a file and continues the drape as the solver that kept it does."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.sparse as sp

from patternfit.sim import kernels
from patternfit.sim.model import ClothModel
from patternfit.sim.preconditioners import Factors, newton_preconditioner
from patternfit.sim.settings import SolverSettings
from patternfit.sim.solver import GarmentSolver, solve
from patternfit.sim.state import ContactState
from patternfit.sim.total_energy import (ContactLookups, edge_points, energy, hessian,
                                         hessian_parts, hessian_pattern, pair_hessian)

from scenes import grain_at, rect_mesh, sphere_field


def _same(a, b) -> bool:
    if a is None or b is None:
        return a is None and b is None
    if sp.issparse(a):
        return sp.issparse(b) and a.shape == b.shape and (a != b).nnz == 0
    return np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)


def _snapshot(state: ContactState) -> dict:
    return {f.name: (v.copy() if hasattr(v, "copy") else v)
            for f in dataclasses.fields(state) for v in [getattr(state, f.name)]}


def _unchanged(state: ContactState, snap: dict) -> list[str]:
    return [k for k, v in snap.items() if not _same(getattr(state, k), v)]


@pytest.fixture(scope="module")
def rested():
    """A 0.4 m square of shirting rested on a 0.1 m sphere (contact, friction and
    self-collision pairs in its folds), one solve of a GarmentSolver."""
    body = sphere_field(0.1, half=0.25)
    v, t = rect_mesh(0.4, 0.4, 4e-4)
    v -= 0.2
    x0 = np.c_[v[:, 0], np.full(len(v), 0.11), v[:, 1]]
    solver = GarmentSolver(v, t, grain_at(15, len(t)), "cotton_shirting", body=body)
    result = solver.solve(x0)
    return solver, result


@pytest.fixture(scope="module")
def sewing():
    """Two strips 4 cm apart, sewn along their long edges, stopped before the seams close:
    the bounded seam springs are in the state."""
    import triangle

    xs = np.linspace(0.0, 0.2, 21)  # the same 21 vertices on both long edges
    pts = np.r_[np.c_[xs, np.zeros(21)], np.c_[xs[::-1], np.full(21, 0.05)]]
    seg = np.c_[np.arange(42), (np.arange(42) + 1) % 42]
    out = triangle.triangulate({"vertices": pts, "segments": seg}, "pq30a2e-4YQ")
    v1, t1 = out["vertices"].astype(float), out["triangles"].astype(np.int64)
    n1 = len(v1)
    v, t = np.r_[v1, v1], np.r_[t1, t1 + n1]
    x0 = np.c_[v[:, 0], np.zeros(len(v)), v[:, 1]]
    x0[n1:, 2] += 0.09
    a = np.flatnonzero(v1[:, 1] > 0.05 - 1e-9)
    b = np.flatnonzero(v1[:, 1] < 1e-9)
    a, b = a[np.argsort(v1[a, 0])], b[np.argsort(v1[b, 0])] + n1
    solver = GarmentSolver(v, t, grain_at(0, len(t)), "cotton_shirting",
                           seam_pairs=np.c_[a, b],
                           settings=SolverSettings(gravity=(0.0, 0.0, 0.0), max_iterations=3))
    result = solver.solve(x0)
    return solver, result


def test_the_scenes_fill_every_lagged_term(rested, sewing):
    solver, result = rested
    st = solver.state
    assert result.converged and st.friction_on
    assert len(st.friction_idx) > 0 and len(st.pairs) > 0
    assert (st.contact_k > 0).all()
    sewn, res = sewing
    assert not res.welded and sewn.state.seam_limit is not None and len(sewn.state.seam_a)


@pytest.mark.parametrize("scene", ["rested", "sewing"])
def test_energy_is_pure(scene, request):
    """The same model, state and positions give the same energy and gradient, bit for bit,
    with or without a lookup cache; nothing of the state, the model or x is written."""
    solver, result = request.getfixturevalue(scene)
    model, state, s = solver.model, solver.state, solver.settings
    rng = np.random.default_rng(3)
    x = model.reduce(result.x) + rng.normal(scale=2e-4, size=(model.n, 3))
    x_copy = x.copy()
    snap = _snapshot(state)
    rest, mass = model.rest.copy(), model.mass.copy()
    e1, g1 = energy(model, state, x, settings=s)
    lookups = ContactLookups.for_model(model, s)
    e2, g2 = energy(model, state, x, settings=s, lookups=lookups)
    e3, g3 = energy(model, state, x, settings=s, lookups=lookups)  # the cache now warm
    assert e1 == e2 == e3 and np.isfinite(e1)
    assert np.array_equal(g1, g2) and np.array_equal(g1, g3)
    assert g1 is not g2
    assert not _unchanged(state, snap)
    assert np.array_equal(x, x_copy)
    assert np.array_equal(model.rest, rest) and np.array_equal(model.mass, mass)
    H1 = hessian(model, state, x, settings=s, pattern=hessian_pattern(model))
    H2 = hessian(model, state, x, settings=s, pattern=hessian_pattern(model))
    assert (H1 != H2).nnz == 0 and H1.shape == (3 * model.n, 3 * model.n)
    # the warm lookups spare distance lookups (on the body), not one entry of the Hessian
    pts = edge_points(model, s).matrix @ x
    looked = len(lookups.unspared(x)) + len(kernels.unspared(pts, lookups.edge_seen,
                                                             lookups.edge_room))
    assert model.body is None or 0 < looked < model.n + len(pts)
    H3 = hessian(model, state, x, settings=s, pattern=hessian_pattern(model), lookups=lookups)
    assert np.array_equal(H1.indptr, H3.indptr) and np.array_equal(H1.indices, H3.indices)
    assert np.array_equal(H1.data, H3.data)
    assert not _unchanged(state, snap)


def test_newton_preconditioner_is_the_trimmed_hessian(rested):
    """The Newton preconditioner's matrix (``kernels.trim_to_near``) is, bit for bit, the
    Hessian kept on the vertex pairs that share a triangle with every other entry's
    absolute value on its row's diagonal, as SciPy sums it, lower triangle. The
    self-collision pairs in the scene's folds, their normals turned, all push: their entries
    are added and dropped."""
    solver, result = rested
    model, s = solver.model, solver.settings
    state = dataclasses.replace(solver.state.copy(), pair_normal=-solver.state.pair_normal,
                                edge_normal=-solver.state.edge_normal)
    pattern = hessian_pattern(model)
    x = model.reduce(result.x)
    assert pair_hessian(model, state, x, settings=s).nnz > 0
    H = hessian(model, state, x, settings=s, pattern=pattern)
    tris = model.terms.tris
    near = sp.csr_matrix((np.ones(9 * len(tris)), (np.repeat(tris, 3, axis=1).ravel(),
                                                   np.tile(tris, (1, 3)).ravel())))
    C = H.tocoo()
    keep = np.asarray(near[C.row // 3, C.col // 3]).ravel() > 0
    extra = np.bincount(C.row[~keep], weights=np.abs(C.data[~keep]), minlength=H.shape[0])
    want = sp.tril(sp.csr_matrix((C.data[keep], (C.row[keep], C.col[keep])), shape=H.shape)
                   + sp.diags(extra)).tocsr()
    indptr, indices, data = newton_preconditioner(H, pattern)
    assert np.array_equal(indptr, want.indptr) and np.array_equal(indices, want.indices)
    assert np.array_equal(data, want.data)
    # the Newton step keeps the pairs apart from the fixed pattern: the same sum
    within, apart = hessian_parts(model, state, x, settings=s, pattern=pattern)
    assert within.nnz == len(pattern.indices) and apart.nnz == pair_hessian(
        model, state, x, settings=s).nnz
    np.testing.assert_allclose((within + apart).toarray(), H.toarray(), rtol=1e-12,
                               atol=1e-9 * abs(H).max())


def test_energy_sees_the_state_it_is_given(rested):
    """Friction is in the state, not hidden in the solver: without its anchors the energy
    and gradient differ."""
    solver, result = rested
    model, s = solver.model, solver.settings
    x = model.reduce(result.x) + 1e-3
    loose = dataclasses.replace(solver.state.copy(), friction_idx=np.zeros(0, np.int64))
    e_held, g_held = energy(model, solver.state, x, settings=s)
    e_free, g_free = energy(model, loose, x, settings=s)
    assert e_held > e_free
    assert not np.array_equal(g_held, g_free)


@pytest.mark.parametrize("scene", ["rested", "sewing"])
def test_state_round_trips_through_a_file(scene, request, tmp_path):
    solver, result = request.getfixturevalue(scene)
    state = solver.state
    np.savez(tmp_path / "state.npz", **state.to_arrays())
    with np.load(tmp_path / "state.npz") as f:
        back = ContactState.from_arrays(f)
    snap = _snapshot(state)
    assert not _unchanged(back, snap)
    assert isinstance(back.friction_on, bool) and isinstance(back.seam_k, float)
    x = solver.model.reduce(result.x)
    e1, g1 = energy(solver.model, state, x, settings=solver.settings)
    e2, g2 = energy(solver.model, back, x, settings=solver.settings)
    assert e1 == e2 and np.array_equal(g1, g2)


def test_a_solve_from_a_saved_state_continues_like_the_kept_solver(rested, tmp_path):
    """The rested square solved again from its end: by the solver that kept its state, and
    by ``solve`` from that state read back from a file; both warm (friction held), both the
    same. ``solve`` does not write the state it is given."""
    solver, result = rested
    np.savez(tmp_path / "state.npz", **solver.state.to_arrays())
    with np.load(tmp_path / "state.npz") as f:
        saved = ContactState.from_arrays(f)
    snap = _snapshot(saved)
    model = solver.model
    out = solve(model, saved, result.x, settings=solver.settings, factors=Factors())
    assert not _unchanged(saved, snap)
    kept = solver.solve(result.x)
    assert out.result.iterations == kept.iterations < 5
    assert np.array_equal(out.result.x, kept.x)
    assert out.model is model and out.state is not saved and out.state.friction_on
    # without the state, the same start is a cold one: friction starts from nothing
    cold = solve(model, ContactState(), result.x, settings=solver.settings, factors=Factors())
    assert not np.array_equal(cold.result.x, kept.x)


def test_model_is_frozen_and_edits_make_new_models(sewing):
    solver, _ = sewing
    model = solver.model
    with pytest.raises(dataclasses.FrozenInstanceError):
        model.rest = model.rest * 2
    rest = model.rest.copy()
    wider = model.with_rest(model.rest * 1.1)
    assert wider is not model and np.array_equal(model.rest, rest)
    assert wider.terms.area.sum() == pytest.approx(1.21 * model.terms.area.sum())
    assert np.array_equal(wider.terms.tris, model.terms.tris)
    with pytest.raises(ValueError, match="rest"):
        model.with_rest(model.rest[:-1])
    welded = model.welded_model()
    assert welded.welded and not model.welded
    pairs = model.seam_pairs
    assert welded.n == model.n - len(pairs)
    assert np.array_equal(welded.group[pairs[:, 0]], welded.group[pairs[:, 1]])
    assert welded.mass.sum() == pytest.approx(model.mass.sum())


def test_model_refuses_bad_input():
    v, t = rect_mesh(0.1, 0.1, 1e-3)
    with pytest.raises(ValueError, match="grain"):
        ClothModel.build(v, t, np.ones((3, 2)), "denim")
    with pytest.raises(ValueError, match="seam_pairs"):
        ClothModel.build(v, t, grain_at(0, len(t)), "denim", seam_pairs=[[0, len(v)]])
    with pytest.raises(ValueError, match="vertex_map"):
        ClothModel.build(v, t, grain_at(0, len(t)), "denim", vertex_map=np.arange(len(v) - 1))


def test_a_solve_that_welds_hands_back_the_welded_model(sewing):
    """``solve`` sews the strips to the weld: the model it hands back is welded (both sides of
    every pair one vertex), the one it was given is not, nor is the given state written."""
    solver, _ = sewing
    model, state = solver.model, ContactState()
    x0 = np.zeros((model.n3, 3))
    x0[:, [0, 2]] = model.rest
    x0[model.n3 // 2:, 2] += 0.09
    out = solve(model, state, x0, settings=dataclasses.replace(solver.settings,
                                                               max_iterations=2000),
                factors=Factors())
    assert out.result.welded and out.model.welded and not model.welded
    assert out.model.n == model.n - len(model.seam_pairs)
    assert out.result.checks.seam_gap_max_mm < 0.5
    assert state.x is None and len(state.forces) == 0
    assert out.state.x is not None and len(out.state.forces) == out.model.n
