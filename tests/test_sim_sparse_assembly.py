"""The Newton solver's sparse assembly kernels (patternfit.sim.kernels.sparse_assembly): the
Hessian's fixed-pattern sum and the trimmed preconditioner matrix."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from patternfit.sim import kernels


def test_scatter_hessian_sums_as_bincount_does():
    rng = np.random.default_rng(5)
    nnz, n = 80, 6
    bend = rng.normal(size=7)
    bend_slots = rng.choice(nnz, size=21, replace=False).astype(np.int32)
    # each term's slots distinct, as in a HessianPattern; the two terms share some
    block_slots = rng.choice(nnz, size=9 * n, replace=False).astype(np.int32)
    blocks = rng.normal(size=(n, 3, 3))
    start = rng.normal(size=nnz)  # what the membrane kernel left there
    out = start.copy()
    kernels.scatter_hessian(bend, bend_slots, blocks, block_slots, out)
    want = ((start + np.bincount(bend_slots, weights=np.repeat(bend, 3), minlength=nnz))
            + np.bincount(block_slots, weights=blocks.ravel(), minlength=nnz))
    assert np.array_equal(out, want)


def test_trim_to_near_keeps_near_pairs_and_moves_the_rest_to_the_diagonal():
    # three vertices: 0 and 1 near each other, 2 near only itself
    near_indptr = np.array([0, 2, 4, 5], np.int32)
    near_indices = np.array([0, 1, 0, 1, 2], np.int32)
    rng = np.random.default_rng(6)
    A = rng.normal(size=(9, 9))
    A = A + A.T
    A[0, 4] = A[4, 0] = 0.0      # a near pair's zero: left out
    A[6:, :6] = A[:6, 6:] = 0.0
    A[7, 7] = 0.0                # vertex 2's y row has no diagonal entry ...
    A[7, 1] = A[1, 7] = -2.5     # ... but one far entry, which becomes its diagonal
    H = sp.csr_matrix(A)
    H.eliminate_zeros()
    indptr, indices, data = kernels.trim_to_near(H.indptr, H.indices, H.data, near_indptr,
                                                 near_indices)
    got = sp.csr_matrix((data, indices, indptr), shape=H.shape).toarray()
    v = np.arange(9) // 3
    near = np.zeros((3, 3), bool)
    near[np.repeat(np.arange(3), np.diff(near_indptr)), near_indices] = True
    keep = near[v[:, None], v[None, :]]
    want = np.tril(np.where(keep, A, 0.0) + np.diag(np.where(keep, 0.0, np.abs(A)).sum(1)))
    np.testing.assert_allclose(got, want, rtol=1e-15, atol=0.0)
    assert got[7, 7] == 2.5 and got[7, 1] == 0.0
    # the lower triangle only, each row's columns sorted and its diagonal last, no zeros
    rows = np.repeat(np.arange(9), np.diff(indptr))
    assert np.all(indices <= rows) and np.array_equal(indices[indptr[1:] - 1], np.arange(9))
    assert np.all(np.diff(indices)[np.diff(rows) == 0] > 0) and np.all(data != 0.0)
    # rows in another order (a pinned Hessian's are not sorted): the same matrix
    order = np.lexsort((-H.indices, np.repeat(np.arange(9), np.diff(H.indptr))))
    out = kernels.trim_to_near(H.indptr, H.indices[order], H.data[order], near_indptr,
                               near_indices)
    assert np.array_equal(sp.csr_matrix(out[::-1], shape=H.shape).toarray(), got)


def test_scatter_points_adds_each_points_rank_one_blocks():
    # two triangles sharing the edge 1-2: vertices 0 and 3 share none
    tris = np.array([[0, 1, 2], [1, 3, 2]])
    n = 4
    dof = (3 * tris[:, :, None] + np.arange(3)).reshape(-1, 9)
    rows, cols = np.repeat(dof, 9, axis=1).ravel(), np.tile(dof, (1, 9)).ravel()
    P = sp.csr_matrix((np.zeros(len(rows)), (rows, cols)), shape=(3 * n, 3 * n))
    P.sum_duplicates()
    P.sort_indices()
    rng = np.random.default_rng(7)
    ids = np.array([[1, 2, 0], [0, 1, 2], [3, 2, 1]])
    w = np.array([[0.3, 0.7, 0.0], [0.2, 0.5, 0.3], [0.1, 0.6, 0.3]])
    v = rng.normal(size=(3, 3))
    v /= np.linalg.norm(v, axis=1)[:, None]
    k = np.array([2.0, 5.0, 7.0])
    start = rng.normal(size=P.nnz)
    out = start.copy()
    assert kernels.scatter_points(P.indptr, P.indices, ids, w, v, k, out) == -1
    want = sp.csr_matrix((start, P.indices, P.indptr), shape=P.shape).toarray()
    for q in range(3):
        wn = np.zeros(3 * n)
        for a in range(3):
            wn[3 * ids[q, a]:3 * ids[q, a] + 3] += w[q, a] * v[q]
        want += k[q] * np.outer(wn, wn)
    got = sp.csr_matrix((out, P.indices, P.indptr), shape=P.shape).toarray()
    np.testing.assert_allclose(got, want, rtol=1e-13, atol=1e-13)
    # a point whose vertices share no triangle is named, not written elsewhere
    assert kernels.scatter_points(P.indptr, P.indices, np.array([[0, 3, 1]]),
                                  np.array([[0.5, 0.5, 0.0]]), v[:1], k[:1], out) == 0


@settings(max_examples=40, deadline=None)
@given(cols=st.integers(1, 4), rows=st.integers(1, 3), seed=st.integers(0, 2 ** 32 - 1),
       count=st.integers(1, 12))
def test_scatter_points_on_a_grid_mesh_is_the_dense_sum(cols, rows, seed, count):
    # a grid of (cols + 1) x (rows + 1) vertices cut into triangles; points inside random
    # triangles and edges, as the contact's face and edge points are
    rng = np.random.default_rng(seed)
    idx = np.arange((cols + 1) * (rows + 1)).reshape(rows + 1, cols + 1)
    quads = np.c_[idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(),
                  idx[1:, :-1].ravel()]
    tris = np.r_[quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]
    n = idx.size
    dof = (3 * tris[:, :, None] + np.arange(3)).reshape(-1, 9)
    P = sp.csr_matrix((np.zeros(dof.size * 9), (np.repeat(dof, 9, axis=1).ravel(),
                                                 np.tile(dof, (1, 9)).ravel())),
                      shape=(3 * n, 3 * n))
    P.sum_duplicates()
    P.sort_indices()
    ids = tris[rng.integers(0, len(tris), count)]
    w = rng.dirichlet(np.ones(3), count)
    w[rng.uniform(size=count) < 0.5, 2] = 0.0  # edge points: a third weight of 0
    v = rng.normal(size=(count, 3))
    k = rng.uniform(1.0, 1e4, count)
    out = np.zeros(P.nnz)
    assert kernels.scatter_points(P.indptr, P.indices, ids, w, v, k, out) == -1
    A = np.zeros((count, 3 * n))
    for q in range(count):
        for a in range(3):
            A[q, 3 * ids[q, a]:3 * ids[q, a] + 3] += w[q, a] * v[q]
    want = A.T @ (k[:, None] * A)
    got = sp.csr_matrix((out, P.indices, P.indptr), shape=P.shape).toarray()
    np.testing.assert_allclose(got, want, rtol=1e-10, atol=1e-10 * np.abs(want).max())
