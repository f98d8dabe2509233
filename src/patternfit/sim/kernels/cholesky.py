"""Numba kernels of a sparse Cholesky factorisation in 3 x 3 vertex blocks (SI units: N/m).

The Newton step's preconditioner (``sim.block_cholesky``) factors a 3n x 3n matrix whose
nonzeros come in 3 x 3 blocks, one per pair of neighbouring vertices, and whose sparsity is
the mesh's for as long as the topology is. So the ordering and the factor's pattern are made
once (:func:`block_symbolic`) and each factorisation is numeric only
(:func:`block_scatter`, or :func:`block_trim_scatter` through the slots
:func:`block_trim_slots` made once per Hessian pattern, then :func:`block_factor_columns`):
left-looking, a block column at a time, the 3 x 3 block products written out. Against
cholespy (which orders the matrix again at every call and factors it scalar, simplicial) the
22K coat's 33K-unknown matrix factors in 0.04 s instead of 0.2 s and solves in 2.5 ms instead
of 5 ms (``docs/simulation.md``).

L is kept as a block CSC: ``colptr`` (n + 1,), ``rowidx`` (nnzb,) with each column's
diagonal block first and the rows ascending, and ``values`` (9 nnzb,), block p at
``values[9 p : 9 p + 9]`` row-major. A diagonal block holds the *inverse* of its 3 x 3 lower
factor (the solves multiply by it).

The factorisation and the solves work on given sets of columns, so that two subtrees of the
elimination tree (whose columns never touch each other) can be done at once
(``sim.block_cholesky``): each set keeps its own list heads (factor) or adds what it owes
the columns above both into its own buffer (forward solve). Serial loops in a fixed order:
two factorisations of the same matrix are bit-identical, however many threads ran them.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .sparse_assembly import is_near


@njit(cache=True)
def block_symbolic(n, indptr, indices):
    """The block pattern of L for the symmetric vertex graph ``indptr`` (n + 1,),
    ``indices`` (sorted rows, already in elimination order): ``(colptr (n + 1,), rowidx
    (nnzb,))``, each column's diagonal first and its rows ascending (elimination tree by
    Liu's algorithm, each row's pattern by its row subtree)."""
    parent = -np.ones(n, np.int64)
    ancestor = -np.ones(n, np.int64)
    for j in range(n):
        for p in range(indptr[j], indptr[j + 1]):
            i = indices[p]
            while i != -1 and i < j:
                up = ancestor[i]
                ancestor[i] = j
                if up == -1:
                    parent[i] = j
                i = up
    mark = -np.ones(n, np.int64)
    count = np.ones(n, np.int64)
    for j in range(n):
        mark[j] = j
        for p in range(indptr[j], indptr[j + 1]):
            i = indices[p]
            while i < j and mark[i] != j:
                count[i] += 1
                mark[i] = j
                i = parent[i]
    colptr = np.zeros(n + 1, np.int64)
    for j in range(n):
        colptr[j + 1] = colptr[j] + count[j]
    rowidx = np.empty(colptr[n], np.int64)
    fill = colptr[:-1].copy()
    for j in range(n):
        rowidx[fill[j]] = j
        fill[j] += 1
    mark[:] = -1
    for j in range(n):
        mark[j] = j
        for p in range(indptr[j], indptr[j + 1]):
            i = indices[p]
            while i < j and mark[i] != j:
                rowidx[fill[i]] = j
                fill[i] += 1
                mark[i] = j
                i = parent[i]
    return colptr, rowidx


@njit(cache=True, nogil=True)
def _slot(colptr, rowidx, row, col):
    """Position of block (``row``, ``col``), row >= col, in L's pattern, or -1."""
    lo = colptr[col]
    hi = colptr[col + 1] - 1
    while lo < hi:
        mid = (lo + hi) // 2
        if rowidx[mid] < row:
            lo = mid + 1
        else:
            hi = mid
    return lo if rowidx[lo] == row else -1


@njit(cache=True, nogil=True)
def _entry_slots(colptr, rowidx, iperm, r, c):
    """Position in L's ``values`` of the scalar entry (``r``, ``c``) of a matrix permuted
    by ``iperm`` (its block's lower triangle), and of its mirror when it lies off the
    diagonal of a diagonal block (else -1); (-1, -1) when L has no block for it."""
    bi = iperm[r // 3]
    bj = iperm[c // 3]
    a = r % 3
    b = c % 3
    if bi < bj:
        bi, bj, a, b = bj, bi, b, a
    q = _slot(colptr, rowidx, bi, bj)
    if q < 0:
        return -1, -1
    return 9 * q + 3 * a + b, (9 * q + 3 * b + a if bi == bj and a != b else -1)


@njit(cache=True, nogil=True)
def block_scatter(colptr, rowidx, iperm, indptr, indices, data, values, r0, r1):
    """Add the scalar rows ``r0``:``r1`` of the lower-triangle CSR matrix (``indptr``
    (3n + 1,), ``indices``, ``data``) into L's blocks ``values`` (permuted by ``iperm``; a
    diagonal block's strictly lower entries mirrored). Rows of different vertices write
    different blocks. Returns the first row whose entry has no slot, or -1."""
    for r in range(r0, r1):
        for p in range(indptr[r], indptr[r + 1]):
            at, mirror = _entry_slots(colptr, rowidx, iperm, r, indices[p])
            if at < 0:
                return r
            values[at] += data[p]
            if mirror >= 0:
                values[mirror] += data[p]
    return -1


@njit(cache=True, nogil=True)
def block_factor_columns(cols, colptr, rowidx, values, head, link, nextpos, pos):
    """Factor the block columns ``cols`` (ascending) in place in ``values`` (9 nnzb,), the
    matrix already scattered there, in the pattern ``colptr``, ``rowidx`` of
    :func:`block_symbolic`: left-looking, each column updated by the earlier columns
    linked from ``head`` (n,) through ``link`` (n,) (the next block each is at:
    ``nextpos`` (n,)); ``pos`` (n,) is scratch. Every column whose updates reach a column of
    ``cols`` must be done or in ``cols``. Returns -1, or the block column whose pivot is not
    positive (the matrix is not positive definite there)."""
    for jj in range(cols.shape[0]):
        j = cols[jj]
        c0 = colptr[j]
        c1 = colptr[j + 1]
        for p in range(c0, c1):
            pos[rowidx[p]] = p
        # L[:, j] -= L[:, k] L[j, k]^T for every earlier column k with a block in row j
        k = head[j]
        while k != -1:
            k_next = link[k]
            pk = nextpos[k]
            b = 9 * pk
            j00, j01, j02 = values[b], values[b + 1], values[b + 2]
            j10, j11, j12 = values[b + 3], values[b + 4], values[b + 5]
            j20, j21, j22 = values[b + 6], values[b + 7], values[b + 8]
            for p in range(pk, colptr[k + 1]):
                q = 9 * p
                t = 9 * pos[rowidx[p]]
                for a in range(3):
                    l0, l1, l2 = values[q + 3 * a], values[q + 3 * a + 1], values[q + 3 * a + 2]
                    values[t + 3 * a] -= l0 * j00 + l1 * j01 + l2 * j02
                    values[t + 3 * a + 1] -= l0 * j10 + l1 * j11 + l2 * j12
                    values[t + 3 * a + 2] -= l0 * j20 + l1 * j21 + l2 * j22
            nextpos[k] = pk + 1
            if pk + 1 < colptr[k + 1]:
                r = rowidx[pk + 1]
                link[k] = head[r]
                head[r] = k
            k = k_next
        b = 9 * c0
        a00, a10, a11 = values[b], values[b + 3], values[b + 4]
        a20, a21, a22 = values[b + 6], values[b + 7], values[b + 8]
        if not a00 > 0.0:
            return j
        l00 = np.sqrt(a00)
        l10 = a10 / l00
        l20 = a20 / l00
        s = a11 - l10 * l10
        if not s > 0.0:
            return j
        l11 = np.sqrt(s)
        l21 = (a21 - l20 * l10) / l11
        s = a22 - l20 * l20 - l21 * l21
        if not s > 0.0:
            return j
        l22 = np.sqrt(s)
        m00 = 1.0 / l00
        m11 = 1.0 / l11
        m22 = 1.0 / l22
        m10 = -l10 * m00 * m11
        m21 = -l21 * m11 * m22
        m20 = -(l20 * m00 + l21 * m10) * m22
        values[b], values[b + 1], values[b + 2] = m00, 0.0, 0.0
        values[b + 3], values[b + 4], values[b + 5] = m10, m11, 0.0
        values[b + 6], values[b + 7], values[b + 8] = m20, m21, m22
        # L[i, j] = A[i, j] L[j, j]^-T
        for p in range(c0 + 1, c1):
            q = 9 * p
            for a in range(3):
                x0, x1, x2 = values[q + 3 * a], values[q + 3 * a + 1], values[q + 3 * a + 2]
                values[q + 3 * a] = x0 * m00
                values[q + 3 * a + 1] = x0 * m10 + x1 * m11
                values[q + 3 * a + 2] = x0 * m20 + x1 * m21 + x2 * m22
        if c0 + 1 < c1:
            r = rowidx[c0 + 1]
            link[j] = head[r]
            head[r] = j
            nextpos[j] = c0 + 1
    return -1


@njit(cache=True, nogil=True)
def block_join_lists(cols, head, other, link):
    """Append, for each column of ``cols``, the update list ``other`` starts to the one
    ``head`` starts (both linked through ``link``): the lists two subtrees' factorisations
    left for the columns above them, joined in a fixed order."""
    for i in range(cols.shape[0]):
        r = cols[i]
        if other[r] == -1:
            continue
        if head[r] == -1:
            head[r] = other[r]
            continue
        k = head[r]
        while link[k] != -1:
            k = link[k]
        link[k] = other[r]


@njit(cache=True, nogil=True)
def block_forward(cols, colptr, rowidx, values, y, owner, me, spill):
    """Forward solve L z = y over the block columns ``cols`` (ascending), in place in ``y``
    (3n,) (in elimination order): an update of a row ``owner`` (n,) gives to another part
    than ``me`` is subtracted in ``spill`` (3n,) instead, to be added to ``y`` once the
    parts are done."""
    for jj in range(cols.shape[0]):
        j = cols[jj]
        q = 9 * colptr[j]
        y0, y1, y2 = y[3 * j], y[3 * j + 1], y[3 * j + 2]
        z0 = values[q] * y0
        z1 = values[q + 3] * y0 + values[q + 4] * y1
        z2 = values[q + 6] * y0 + values[q + 7] * y1 + values[q + 8] * y2
        y[3 * j], y[3 * j + 1], y[3 * j + 2] = z0, z1, z2
        for p in range(colptr[j] + 1, colptr[j + 1]):
            q = 9 * p
            row = rowidx[p]
            t = y if owner[row] == me else spill
            r = 3 * row
            t[r] -= values[q] * z0 + values[q + 1] * z1 + values[q + 2] * z2
            t[r + 1] -= values[q + 3] * z0 + values[q + 4] * z1 + values[q + 5] * z2
            t[r + 2] -= values[q + 6] * z0 + values[q + 7] * z1 + values[q + 8] * z2


@njit(cache=True, nogil=True)
def block_backward(cols, back_colptr, back_rowidx, back_values, y):
    """Backward solve L^T x = z over the block columns ``cols`` (ascending; done from the
    last), in place in ``y`` (3n,): the rows below each column must be solved already. L
    is read from its copy with the columns stored last first (``back_colptr`` (n + 1,),
    ``back_rowidx``, ``back_values``: column j at n - 1 - j), so that the solve reads memory
    forwards (read backwards it took 3-4 times as long)."""
    n = back_colptr.shape[0] - 1
    for jj in range(cols.shape[0] - 1, -1, -1):
        j = cols[jj]
        c = n - 1 - j
        s0, s1, s2 = y[3 * j], y[3 * j + 1], y[3 * j + 2]
        for p in range(back_colptr[c] + 1, back_colptr[c + 1]):
            q = 9 * p
            r = 3 * back_rowidx[p]
            x0, x1, x2 = y[r], y[r + 1], y[r + 2]
            s0 -= back_values[q] * x0 + back_values[q + 3] * x1 + back_values[q + 6] * x2
            s1 -= back_values[q + 1] * x0 + back_values[q + 4] * x1 + back_values[q + 7] * x2
            s2 -= back_values[q + 2] * x0 + back_values[q + 5] * x1 + back_values[q + 8] * x2
        q = 9 * back_colptr[c]
        y[3 * j] = back_values[q] * s0 + back_values[q + 3] * s1 + back_values[q + 6] * s2
        y[3 * j + 1] = back_values[q + 4] * s1 + back_values[q + 7] * s2
        y[3 * j + 2] = back_values[q + 8] * s2


@njit(cache=True, nogil=True)
def block_gather(b, perm, y):
    """``y`` (3n,) = ``b`` (3n,) in elimination order: vertex ``perm[i]``'s three values at
    block i."""
    for i in range(perm.shape[0]):
        v = perm[i]
        y[3 * i] = b[3 * v]
        y[3 * i + 1] = b[3 * v + 1]
        y[3 * i + 2] = b[3 * v + 2]


@njit(cache=True, nogil=True)
def block_spread(y, perm, out):
    """The inverse of :func:`block_gather`: ``out`` (3n,) in vertex order from ``y``."""
    for i in range(perm.shape[0]):
        v = perm[i]
        out[3 * v] = y[3 * i]
        out[3 * v + 1] = y[3 * i + 1]
        out[3 * v + 2] = y[3 * i + 2]


@njit(cache=True)
def block_trim_slots(colptr, rowidx, iperm, indptr, indices, near_indptr, near_indices):
    """Where each entry of a 3n x 3n scalar CSR pattern (``indptr``, ``indices``) goes when
    the matrix is trimmed to the vertex pattern ``near_indptr``, ``near_indices`` (rows
    sorted) and scattered into L's blocks (as :func:`block_scatter` does with the lower
    triangle ``kernels.trim_to_near`` makes): ``slot`` (nnz,), the position in ``values``
    of a kept entry (between near vertices, on or below the diagonal), -1 for an entry above
    the diagonal (left out), -2 for one between vertices that are not near (its absolute
    value goes to its row's diagonal); ``mirror`` (nnz,), the second position of a diagonal
    block's off-diagonal entry, else -1; ``diagonal`` (3n,), the position of each row's
    diagonal entry. Returns (slot, mirror, diagonal, bad): ``bad`` is the first row with a
    kept entry that has no block in L, or -1."""
    n3 = indptr.shape[0] - 1
    slot = np.empty(indices.shape[0], np.int64)
    mirror = np.full(indices.shape[0], -1, np.int64)
    diagonal = np.empty(n3, np.int64)
    for r in range(n3):
        diagonal[r] = _entry_slots(colptr, rowidx, iperm, r, r)[0]
        if diagonal[r] < 0:
            return slot, mirror, diagonal, r
        for p in range(indptr[r], indptr[r + 1]):
            c = indices[p]
            if not is_near(near_indices, near_indptr[r // 3], near_indptr[r // 3 + 1], c // 3):
                slot[p] = -2
            elif c > r:
                slot[p] = -1
            else:
                slot[p], mirror[p] = _entry_slots(colptr, rowidx, iperm, r, c)
                if slot[p] < 0:
                    return slot, mirror, diagonal, r
    return slot, mirror, diagonal, -1


@njit(cache=True, nogil=True)
def block_trim_scatter(indptr, indices, data, slot, mirror, diagonal, e_indptr, e_indices,
                       e_data, near_indptr, near_indices, values, r0, r1):
    """Rows ``r0``:``r1`` of H + E trimmed and scattered into L's blocks ``values`` (zeros
    where they write): H a matrix on the pattern whose :func:`block_trim_slots` are ``slot``,
    ``mirror``, ``diagonal``, E (``e_indptr``, ``e_indices`` sorted per row, ``e_data``) a
    few more entries. The same values, bit for bit, as ``kernels.trim_to_near`` of SciPy's
    H + E (rows sorted) and :func:`block_scatter` of its result: a row's entries between
    vertices that are not near are summed as absolute values in column order, H's and E's
    added first where both have one, and the sum goes onto the diagonal. An entry of E
    between near vertices where H has none has no slot: returns its row, else -1."""
    for r in range(r0, r1):
        extra = 0.0
        p = indptr[r]
        p_end = indptr[r + 1]
        q = e_indptr[r]
        q_end = e_indptr[r + 1]
        while p < p_end or q < q_end:
            if q >= q_end or (p < p_end and indices[p] < e_indices[q]):
                if slot[p] == -2:
                    extra += abs(data[p])
                p += 1
            elif p >= p_end or e_indices[q] < indices[p]:
                if is_near(near_indices, near_indptr[r // 3], near_indptr[r // 3 + 1],
                           e_indices[q] // 3):
                    return r
                extra += abs(e_data[q])
                q += 1
            else:
                if slot[p] == -2:
                    extra += abs(data[p] + e_data[q])
                p += 1
                q += 1
        p = indptr[r]
        q = e_indptr[r]
        while p < p_end:
            v = data[p]
            while q < q_end and e_indices[q] < indices[p]:
                q += 1
            if q < q_end and e_indices[q] == indices[p]:
                v = v + e_data[q]
            if slot[p] >= 0 and v != 0.0:
                values[slot[p]] += v
                if mirror[p] >= 0:
                    values[mirror[p]] += v
            p += 1
        # each slot written once above, so this is trim_to_near's diagonal + extra
        values[diagonal[r]] += extra
    return -1
