"""The Newton preconditioner's sparse Cholesky in 3 x 3 vertex blocks
(``patternfit.sim.block_cholesky``): solves against SciPy's on random meshes, refactoring on
the same graph, clear refusals, and its split in two halves for two threads."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import Delaunay

from patternfit.sim.block_cholesky import BlockCholesky, subtree_split


def _mesh(rng, n):
    """Triangles (m, 3) of a Delaunay triangulation of ``n`` random points, plus the vertex
    graph (CSR of the pairs that share a triangle, diagonal included)."""
    tri = Delaunay(rng.random((n, 2))).simplices
    pairs = (tri[:, :, None] * n + tri[:, None, :]).ravel()
    keys = np.unique(np.concatenate([pairs, np.arange(n) * (n + 1)]))
    graph = sp.csr_matrix((np.ones(len(keys)), (keys // n, keys % n)), shape=(n, n))
    return tri, graph


def _matrix(rng, tri, n, shift=1.0):
    """A random SPD 3n x 3n matrix with nonzeros in the blocks of triangle-sharing
    vertices: a sum of random PSD 9 x 9 per-triangle blocks plus ``shift`` I."""
    dof = (3 * tri[:, :, None] + np.arange(3)).reshape(-1, 9)
    B = rng.standard_normal((len(tri), 9, 9))
    K = np.einsum("tij,tkj->tik", B, B)
    rows = np.repeat(dof, 9, axis=1).ravel()
    cols = np.tile(dof, (1, 9)).ravel()
    A = sp.csr_matrix((K.ravel(), (rows, cols)), shape=(3 * n, 3 * n))
    return (A + shift * sp.eye(3 * n)).tocsr()


def _lower(A):
    low = sp.tril(A).tocsr()
    low.sort_indices()
    return low.indptr, low.indices, low.data


@settings(max_examples=25, deadline=None)
@given(n=st.integers(4, 300), seed=st.integers(0, 2 ** 31 - 1))
def test_solves_match_scipy_on_random_meshes(n, seed):
    rng = np.random.default_rng(seed)
    tri, graph = _mesh(rng, n)
    A = _matrix(rng, tri, n)
    chol = BlockCholesky(graph.indptr, graph.indices)
    assert sorted(chol.perm) == list(range(n))
    chol.factor(*_lower(A))
    b = rng.standard_normal(3 * n)
    x = chol.solve(b)
    expected = spla.spsolve(A.tocsc(), b)
    # the solves read the factor in single precision
    assert np.linalg.norm(x - expected) <= 1e-4 * np.linalg.norm(expected)


def test_refactoring_on_the_same_graph_gives_the_new_matrix_and_repeats_bit_for_bit():
    rng = np.random.default_rng(3)
    n = 400
    tri, graph = _mesh(rng, n)
    chol = BlockCholesky(graph.indptr, graph.indices)
    b = rng.standard_normal(3 * n)
    for shift in (1.0, 50.0):
        A = _matrix(rng, tri, n, shift)
        chol.factor(*_lower(A))
        x = chol.solve(b)
        assert np.linalg.norm(A @ x - b) <= 1e-4 * np.linalg.norm(b)
        again = chol.solve(b)
        chol.factor(*_lower(A))
        assert np.array_equal(chol.solve(b), again)
    # a fill-reducing order: far fewer blocks than the dense lower triangle
    assert chol.blocks < 0.2 * n * (n + 1) / 2


def test_a_matrix_with_a_negative_pivot_is_refused_naming_the_vertex():
    rng = np.random.default_rng(5)
    n = 30
    tri, graph = _mesh(rng, n)
    A = _matrix(rng, tri, n).tolil()
    A[3 * 7 + 1, 3 * 7 + 1] = -1.0
    chol = BlockCholesky(graph.indptr, graph.indices)
    with pytest.raises(np.linalg.LinAlgError, match="not positive definite at vertex 7$"):
        chol.factor(*_lower(A.tocsr()))
    assert not chol.factored
    with pytest.raises(RuntimeError, match="factor"):
        chol.solve(np.ones(3 * n))


def test_entries_outside_the_graph_and_a_wrong_size_are_refused():
    rng = np.random.default_rng(8)
    n = 40
    tri, graph = _mesh(rng, n)
    A = _matrix(rng, tri, n).tolil()
    far = [v for v in range(n) if graph[0, v] == 0][0]
    A[3 * far + 2, 0] = 0.5
    A[0, 3 * far + 2] = 0.5
    chol = BlockCholesky(graph.indptr, graph.indices)
    with pytest.raises(ValueError, match="not neighbours"):
        chol.factor(*_lower(A.tocsr()))
    small = _matrix(rng, np.array([[0, 1, 2]]), 3)
    with pytest.raises(ValueError, match="indptr"):
        chol.factor(*_lower(small))


def test_isolated_vertices_with_identity_rows_factor():
    """Pinned vertices reach the factor as identity rows with no neighbour."""
    n = 5
    graph = sp.eye(n, format="csr")
    chol = BlockCholesky(graph.indptr, graph.indices)
    chol.factor(*_lower(sp.eye(3 * n, format="csr") * 2.0))
    assert np.allclose(chol.solve(np.arange(3.0 * n)), np.arange(3.0 * n) / 2.0)


@settings(max_examples=25, deadline=None)
@given(n=st.integers(2, 400), seed=st.integers(0, 2 ** 31 - 1))
def test_the_split_gives_each_set_whole_subtrees_below_the_columns_above(n, seed):
    rng = np.random.default_rng(seed)
    _, graph = _mesh(rng, max(n, 4))
    chol = BlockCholesky(graph.indptr, graph.indices)
    parts, top, owner = subtree_split(chol.colptr, chol.rowidx)
    count = np.diff(chol.colptr)
    assert sorted(np.concatenate([*parts, top]).tolist()) == list(range(chol.n))
    for k, cols in enumerate((*parts, top)):
        assert np.all(owner[cols] == k) and np.all(np.diff(cols) > 0)
    for j in range(chol.n):
        if count[j] > 1:  # its parent: the first row below the diagonal
            up = chol.rowidx[chol.colptr[j] + 1]
            # a set's column hangs below a column of its own set or above both; above stays
            assert owner[up] in ((owner[j], 2) if owner[j] < 2 else (2,))


@pytest.mark.parametrize("n", [60, 900])
def test_two_threads_give_the_factor_and_solves_of_one_bit_for_bit(n):
    rng = np.random.default_rng(11)
    tri, graph = _mesh(rng, n)
    A = _matrix(rng, tri, n)
    b = rng.standard_normal(3 * n)
    out = []
    for threads in (1, 2):
        chol = BlockCholesky(graph.indptr, graph.indices)
        chol.threads = threads  # (below PARALLEL_VERTICES it would run on one)
        chol.factor(*_lower(A))
        out.append((chol.values.copy(), chol.solve(b)))
    assert np.array_equal(out[0][0], out[1][0]) and np.array_equal(out[0][1], out[1][1])
    assert np.linalg.norm(A @ out[1][1] - b) <= 1e-4 * np.linalg.norm(b)
    parts, top, _ = subtree_split(chol.colptr, chol.rowidx)
    assert min(len(parts[0]), len(parts[1])) > 0.2 * n  # both threads have work


def test_a_bad_pivot_in_either_half_is_refused_on_two_threads():
    rng = np.random.default_rng(5)
    n = 300
    tri, graph = _mesh(rng, n)
    chol = BlockCholesky(graph.indptr, graph.indices)
    chol.threads = 2
    parts, _, _ = subtree_split(chol.colptr, chol.rowidx)
    for cols in parts:
        vertex = int(chol.perm[cols[0]])
        A = _matrix(rng, tri, n).tolil()
        A[3 * vertex, 3 * vertex] = -1e6
        with pytest.raises(np.linalg.LinAlgError, match=f"at vertex {vertex}$"):
            chol.factor(*_lower(A.tocsr()))
        assert not chol.factored


def _trim_case(rng, n, *, cancel=True):
    """A mesh's vertex graph, a 3n x 3n matrix H on a fixed pattern wider than the graph
    (its pairs two edges apart too, as the bending's), sorted rows with some explicit zeros,
    and a small symmetric E: some entries on H's pattern (one cancelling H's exactly), some
    between vertices H leaves out."""
    tri, graph = _mesh(rng, n)
    A = _matrix(rng, tri, n, shift=0.0)
    far = ((graph @ graph) > 0).astype(float) - (graph > 0).astype(float)
    far = sp.triu(far, k=1).tocoo()
    far_dof = sp.kron(sp.csr_matrix((rng.uniform(-0.3, 0.3, far.nnz), (far.row, far.col)),
                                    shape=(n, n)), np.ones((3, 3))).tocsr()
    H = (A + far_dof + far_dof.T).tocsr()
    H.sum_duplicates()
    H.sort_indices()
    H.data[rng.uniform(size=H.nnz) < 0.05] = 0.0
    # diagonally dominant (so positive definite) whatever was zeroed, the zeros kept
    H.setdiag(H.diagonal() + 2.0 * abs(H).sum(axis=1).A1.max() + 1.0)
    on = rng.choice(H.nnz, size=min(40, H.nnz), replace=False)
    rows = np.repeat(np.arange(3 * n), np.diff(H.indptr))
    er, ec = list(rows[on]), list(H.indices[on])
    ev = list(rng.uniform(-0.05, 0.05, len(on)))
    if cancel:
        k = int(np.flatnonzero(rows != H.indices)[0])
        er.append(rows[k]), ec.append(H.indices[k]), ev.append(-H.data[k])
    for _ in range(10):  # pairs H leaves out (never near: H holds every near pair)
        i, j = rng.integers(0, 3 * n, 2)
        if H[i, j] == 0 and not graph[i // 3, j // 3]:
            er.append(i), ec.append(j), ev.append(rng.uniform(-0.05, 0.05))
    E = sp.coo_matrix((ev, (er, ec)), shape=(3 * n, 3 * n))
    return graph, H, (E + E.T).tocsr()


@settings(max_examples=25, deadline=None)
@given(n=st.integers(4, 200), seed=st.integers(0, 2 ** 31 - 1))
def test_the_trimmed_factor_is_the_factor_of_the_trimmed_sum_bit_for_bit(n, seed):
    """``factor_trimmed`` (H on its fixed pattern, E apart) writes the same factor as
    ``factor`` of ``kernels.trim_to_near`` of SciPy's H + E, and of H alone."""
    from patternfit.sim import kernels

    rng = np.random.default_rng(seed)
    graph, H, E = _trim_case(rng, n)
    near_ptr, near_idx = graph.indptr, graph.indices
    for extra in (E, None):
        whole = H if extra is None else (H + extra).tocsr()
        old = BlockCholesky(near_ptr, near_idx)
        old.factor(*kernels.trim_to_near(whole.indptr, whole.indices, whole.data, near_ptr,
                                         near_idx))
        new = BlockCholesky(near_ptr, near_idx)
        new.factor_trimmed(new.trim_slots(H.indptr, H.indices, near_ptr, near_idx), H.data,
                           extra)
        assert np.array_equal(old.values, new.values)
        b = rng.standard_normal(3 * n)
        assert np.array_equal(old.solve(b), new.solve(b))


def test_the_trimmed_factor_refuses_what_it_cannot_place():
    rng = np.random.default_rng(3)
    n = 30
    graph, H, E = _trim_case(rng, n, cancel=False)
    chol = BlockCholesky(graph.indptr, graph.indices)
    slots = chol.trim_slots(H.indptr, H.indices, graph.indptr, graph.indices)
    with pytest.raises(ValueError, match="data"):
        chol.factor_trimmed(slots, H.data[:-1])
    with pytest.raises(ValueError, match="extra"):
        chol.factor_trimmed(slots, H.data, sp.identity(3 * n - 3, format="csr"))
    # an extra entry between near vertices where H's pattern has none
    diag = sp.identity(3 * n, format="csr") * 10.0
    only = chol.trim_slots(diag.indptr, diag.indices, graph.indptr, graph.indices)
    i, j = 3 * graph.indices[graph.indptr[0]:graph.indptr[1]].max(), 0
    near = sp.csr_matrix(([0.1, 0.1], ([i, j], [j, i])), shape=(3 * n, 3 * n))
    with pytest.raises(ValueError, match="extra matrix"):
        chol.factor_trimmed(only, diag.data, near)
    assert not chol.factored
    # a kept entry outside the factor's graph (a factor of the diagonal alone)
    lone = BlockCholesky(np.arange(n + 1), np.arange(n))
    with pytest.raises(ValueError, match="row"):
        lone.trim_slots(H.indptr, H.indices, graph.indptr, graph.indices)
    with pytest.raises(ValueError, match="indptr"):
        chol.trim_slots(H.indptr[:-3], H.indices, graph.indptr, graph.indices)
