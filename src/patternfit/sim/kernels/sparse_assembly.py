"""Numba kernels that assemble the Newton solver's sparse matrices (SI units: N/m).

- :func:`scatter_hessian`: the fixed-sparsity part of the Hessian, written straight into
  its CSR data array from the per-term values and their slots
  (``total_energy.HessianPattern``);
- :func:`trim_to_near`: the lower triangle of the matrix factored to precondition Newton's
  conjugate gradients (``preconditioners.newton_preconditioner``), in one pass over the
  Hessian's CSR rows;
- :func:`scatter_points`: the rank-one blocks of the body contact of points inside edges
  and triangles, added straight into that data array;
- :func:`csr_rows_product`: rows of a CSR matrix times a vector (the conjugate gradients'
  products, split between two threads by ``preconditioners.newton_direction``).

Serial loops in a fixed order, the same order as the NumPy / SciPy operations they replace
(``np.bincount``, a CSR sum), so that the matrices are bit-identical to theirs.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def scatter_hessian(bend, bend_slots, blocks, block_slots, out):
    """Add the bending matrix's entries ``bend`` (k,) [N/m] at ``bend_slots`` (3 k,) (entry e
    on the slots 3 e .. 3 e + 2, one per coordinate), then the per-vertex blocks ``blocks``
    (n, 3, 3) [N/m] at ``block_slots`` (9 n,), into the Hessian's CSR data ``out`` (nnz,), in
    that order. Each term's slots are distinct (a ``HessianPattern``'s are), so ``out``
    becomes ``(out + bincount(bend)) + bincount(blocks)`` bit for bit."""
    for k in range(bend_slots.shape[0]):
        out[bend_slots[k]] += bend[k // 3]
    flat = blocks.reshape(-1)
    for k in range(flat.shape[0]):
        out[block_slots[k]] += flat[k]


@njit(cache=True)
def scatter_points(indptr, indices, ids, w, v, k, out):
    """Add ``k w_a w_b v v^T`` [N/m] of every point (``ids`` (p, j) its vertices, ``w`` (p, j)
    their weights, ``v`` (p, 3) a unit direction, ``k`` (p,) [N/m]) to the 3 x 3 blocks of its
    vertex pairs in a Hessian's CSR data ``out``, whose sorted rows (``indptr`` (3n + 1,),
    ``indices``) hold the whole block of each pair (vertices that share a triangle: a point's
    vertices do). Zero weights are skipped. Returns -1, or the first point with a vertex
    pair outside the pattern (then ``out`` is partly written)."""
    for q in range(ids.shape[0]):
        for a in range(ids.shape[1]):
            if w[q, a] == 0.0:
                continue
            for b in range(ids.shape[1]):
                if w[q, b] == 0.0:
                    continue
                s = k[q] * w[q, a] * w[q, b]
                col = 3 * ids[q, b]
                for c in range(3):
                    row = 3 * ids[q, a] + c
                    lo, hi = indptr[row], indptr[row + 1]
                    pos = lo + np.searchsorted(indices[lo:hi], col)
                    if pos + 2 >= hi or indices[pos] != col:
                        return q
                    for c2 in range(3):
                        out[pos + c2] += s * v[q, c] * v[q, c2]
    return -1


@njit(cache=True)
def is_near(near_indices, lo, hi, w):
    """Whether vertex ``w`` is in ``near_indices[lo:hi]`` (sorted): a row of the vertex
    pattern the Newton preconditioner keeps (also ``kernels.cholesky``'s trimmed
    scatter)."""
    for k in range(lo, hi):
        if near_indices[k] >= w:
            return near_indices[k] == w
    return False


@njit(cache=True)
def trim_to_near(indptr, indices, data, near_indptr, near_indices):
    """Lower triangle (CSR ``indptr`` (3n + 1,), ``indices``, ``data`` [N/m]) of a 3n x 3n
    matrix H (CSR ``indptr``, ``indices``, ``data`` without duplicates, each row's entries in
    any order; dofs ordered x0 y0 z0 x1 ...) kept on the entries between vertices that are
    neighbours in the vertex pattern ``near_indptr`` (n + 1,), ``near_indices`` (sorted per
    row), every other entry's absolute value added to its row's diagonal. A row's kept
    entries come in H's order, off-diagonal zeros left out, its diagonal last and always
    there (sorted rows when H's are).

    Row i's dropped entries are summed in H's order from zero, and the sum then added to H's
    diagonal entry (or stands alone where H has none): the values of
    ``csr(H kept) + diags(np.bincount(row, |dropped|))``, bit for bit."""
    n3 = indptr.shape[0] - 1
    out_ptr = np.zeros(n3 + 1, np.int32)
    out_idx = np.empty(indices.shape[0] + n3, np.int32)
    out_val = np.empty(indices.shape[0] + n3)
    nnz = 0
    for i in range(n3):
        lo, hi = near_indptr[i // 3], near_indptr[i // 3 + 1]
        extra = 0.0
        for jj in range(indptr[i], indptr[i + 1]):
            if not is_near(near_indices, lo, hi, indices[jj] // 3):
                extra += abs(data[jj])
        diag = extra
        for jj in range(indptr[i], indptr[i + 1]):
            j = indices[jj]
            if j > i or not is_near(near_indices, lo, hi, j // 3):
                continue
            if j == i:
                diag = data[jj] + extra
            elif data[jj] != 0.0:
                out_idx[nnz] = j
                out_val[nnz] = data[jj]
                nnz += 1
        out_idx[nnz] = i
        out_val[nnz] = diag
        nnz += 1
        out_ptr[i + 1] = nnz
    return out_ptr, out_idx[:nnz], out_val[:nnz]


@njit(cache=True, nogil=True)
def csr_rows_product(indptr, indices, data, x, out, r0, r1):
    """``out[r0:r1]`` = rows ``r0``:``r1`` of the CSR matrix (``indptr``, ``indices``,
    ``data``) times ``x``, each row summed in its stored order (as SciPy's product)."""
    # unsigned positions: numba then drops its check for negative indices, which doubled
    # the time of this loop
    for i in range(r0, r1):
        acc = 0.0
        for p in range(np.uint64(indptr[i]), np.uint64(indptr[i + 1])):
            acc += data[p] * x[np.uint64(indices[p])]
        out[i] = acc
