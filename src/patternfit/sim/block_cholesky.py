"""Sparse Cholesky factor in 3 x 3 vertex blocks, its ordering made once per mesh topology
(SI units: N/m for the matrix, the solve's units are its right-hand side's over N/m).

The Newton step's preconditioner (``preconditioners.newton_direction``) is refactored every
few steps with new values on the same vertex graph (the pairs of vertices that share a
triangle). :class:`BlockCholesky` orders that graph once by METIS nested dissection
(``pymetis``) and finds the factor's block pattern; :meth:`BlockCholesky.factor` is then
numeric only and :meth:`BlockCholesky.solve` works on blocks (``kernels.cholesky``).
Both split the elimination tree in two sets of subtrees of about equal work and the columns
above them (:func:`subtree_split`): the two sets run at once on a machine with two cores
(:mod:`patternfit.sim.threads`), and one after the other, with the same arithmetic, on one.
The backward solve reads a copy of the factor stored last column first, so that it reads
memory forwards (22K coat: a factorisation 79 -> 70 ms, a solve 3.3 -> 1.9 ms on two
threads, docs/simulation.md "Two threads").
:meth:`BlockCholesky.factor_trimmed` takes the Newton Hessian on its fixed pattern and trims
it while it scatters (22K coat: a refactorisation 60 -> 42 ms, the same factor bit for bit).
The solves read the factor rounded to single precision: they are bound by memory traffic,
which that halves (22K coat: 3.3 -> 2.0 ms a solve), and a preconditioner needs no more (the
solve is exact for a matrix within a relative 1e-7 of the one factored, still symmetric
positive definite, and the arithmetic stays double).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from .kernels import (block_backward, block_factor_columns, block_forward, block_gather,
                      block_join_lists, block_scatter, block_spread, block_symbolic,
                      block_trim_scatter, block_trim_slots)
from .threads import both, threads_for


class TrimSlots(NamedTuple):
    """A scalar CSR pattern (``indptr``, ``indices``), the vertex pattern it is trimmed to
    (``near_indptr``, ``near_indices``) and where each entry goes in a :class:`BlockCholesky`
    (``kernels.block_trim_slots``: ``slot``, ``mirror``, ``diagonal``)."""

    indptr: np.ndarray
    indices: np.ndarray
    near_indptr: np.ndarray
    near_indices: np.ndarray
    slot: np.ndarray
    mirror: np.ndarray
    diagonal: np.ndarray


class BlockCholesky:
    """L L^T of 3n x 3n SPD matrices whose nonzeros lie in the 3 x 3 blocks of the vertex
    pairs of one graph.

    Parameters
    ----------
    graph_indptr : (n + 1,) int
        Row starts of the symmetric n x n vertex pattern (the diagonal may be in it).
    graph_indices : int
        Its column indices.

    Attributes
    ----------
    n : int
        Vertices (the matrices are 3n x 3n).
    perm : (n,) int
        The elimination order: the vertex at each position.
    blocks : int
        Blocks in L's pattern (its fill; 9 values each).
    factored : bool
        Whether :meth:`factor` has given a factor that :meth:`solve` may use.
    threads : int
        Threads the factorisations and solves use (1 or 2).
    """

    def __init__(self, graph_indptr, graph_indices):
        indptr = np.asarray(graph_indptr, dtype=np.int64)
        indices = np.asarray(graph_indices, dtype=np.int64)
        n = len(indptr) - 1
        graph = sp.csr_matrix((np.ones(len(indices)), indices, indptr), shape=(n, n))
        graph = (graph + graph.T).tocsr()
        graph.setdiag(0)
        graph.eliminate_zeros()
        graph.sort_indices()
        self.n = n
        self.perm = _nested_dissection(graph)
        self.iperm = np.empty(n, np.int64)
        self.iperm[self.perm] = np.arange(n)
        ordered = graph[self.perm][:, self.perm].tocsr()
        ordered.sort_indices()
        self.colptr, self.rowidx = block_symbolic(n, ordered.indptr.astype(np.int64),
                                                  ordered.indices.astype(np.int64))
        self.blocks = len(self.rowidx)
        self.values = np.zeros(9 * self.blocks)
        self._solve_rows = self.rowidx.astype(np.int32)
        self._solve_values = np.zeros(9 * self.blocks, np.float32)
        # the backward solve's copy, columns last first (kernels.block_backward)
        count = np.diff(self.colptr)[::-1]
        self._back_colptr = np.concatenate([[0], np.cumsum(count)]).astype(np.int64)
        # block q of the copy is block q + (the column's start in L - its start in the copy)
        self._back_order = np.arange(self.blocks, dtype=np.int64) + np.repeat(
            self.colptr[:-1][::-1] - self._back_colptr[:-1], count)
        self._back_rows = self._solve_rows[self._back_order]
        self._back_values = np.zeros((self.blocks, 9), np.float32)
        self._parts, self._top, self._owner = subtree_split(self.colptr, self.rowidx)
        self._top3 = (3 * self._top[:, None] + np.arange(3)).ravel()
        # what each half's forward solve owes the columns above both: only those rows used
        self._spill = (np.zeros(3 * n), np.zeros(3 * n))
        self.threads = threads_for(n)
        self.factored = False

    def factor(self, indptr, indices, data) -> None:
        """Factor the matrix given by its lower triangle as scalar CSR: ``indptr`` (3n + 1,),
        ``indices``, ``data`` [N/m] (dofs x0 y0 z0 x1 ..., every entry between vertices of
        the graph). Raises ``ValueError`` for an entry outside the graph and
        ``np.linalg.LinAlgError`` naming the vertex where the matrix is not positive
        definite; either way no factor is left to solve with."""
        self.factored = False
        if len(indptr) != 3 * self.n + 1:
            raise ValueError(f"indptr: {len(indptr) - 1} rows, the graph has {self.n} "
                             f"vertices ({3 * self.n} rows)")
        indptr = np.asarray(indptr, dtype=np.int64)
        indices = np.asarray(indices, dtype=np.int64)
        data = np.asarray(data, dtype=np.float64)
        colptr, rowidx, v = self.colptr, self.rowidx, self.values
        self._numeric(indptr, lambda r0, r1: block_scatter(colptr, rowidx, self.iperm, indptr,
                                                           indices, data, v, r0, r1),
                      "an entry between vertices that are not neighbours in the factor's graph")

    def trim_slots(self, indptr, indices, near_indptr, near_indices) -> TrimSlots:
        """Where each entry of a 3n x 3n scalar CSR pattern (``indptr`` (3n + 1,),
        ``indices``) goes in this factor when the matrix is trimmed to the vertex pattern
        ``near_indptr``, ``near_indices`` (rows sorted) as ``kernels.trim_to_near`` trims it
        (:meth:`factor_trimmed`); made once per pattern. Raises ``ValueError`` for a kept
        entry outside the factor's graph."""
        if len(indptr) != 3 * self.n + 1:
            raise ValueError(f"indptr: {len(indptr) - 1} rows, the graph has {self.n} "
                             f"vertices ({3 * self.n} rows)")
        slot, mirror, diagonal, bad = block_trim_slots(
            self.colptr, self.rowidx, self.iperm, np.asarray(indptr, dtype=np.int64),
            np.asarray(indices, dtype=np.int64), np.asarray(near_indptr, dtype=np.int64),
            np.asarray(near_indices, dtype=np.int64))
        if bad >= 0:
            raise ValueError(f"row {bad}: an entry between near vertices that are not "
                             f"neighbours in the factor's graph")
        return TrimSlots(indptr, indices, np.asarray(near_indptr, dtype=np.int64),
                         np.asarray(near_indices, dtype=np.int64), slot, mirror, diagonal)

    def factor_trimmed(self, slots: TrimSlots, data, extra=None) -> None:
        """Factor H + E trimmed (``kernels.trim_to_near``: the entries between vertices that
        are not near dropped, their absolute values added to their rows' diagonals), H given
        by its ``data`` [N/m] on the pattern of ``slots`` (:meth:`trim_slots`), E (``extra``,
        3n x 3n sparse [N/m], or None) a few more entries (the self-repulsion pairs). The same
        factor, bit for bit, as :meth:`factor` of the trimmed SciPy sum, without making it:
        the 22K coat's sum, trim and scatter took some 15 ms of a 60 ms refactorisation. Raises
        as :meth:`factor` does, ``ValueError`` also for an entry of E between near vertices
        where H has none."""
        data = np.asarray(data, dtype=np.float64)
        if data.shape != slots.slot.shape:
            raise ValueError(f"data: {data.shape[0]} values, the pattern has "
                             f"{slots.slot.shape[0]} entries")
        if extra is None:
            e_ptr, e_idx, e_val = np.zeros(3 * self.n + 1, np.int64), np.zeros(0, np.int64), \
                np.zeros(0)
        else:
            extra = sp.csr_matrix(extra)
            if extra.shape != (3 * self.n, 3 * self.n):
                raise ValueError(f"extra: {extra.shape[0]} x {extra.shape[1]}, not "
                                 f"{3 * self.n} x {3 * self.n}")
            extra.sum_duplicates()  # rows sorted, as the kernel merges them with H's
            e_ptr, e_idx, e_val = extra.indptr, extra.indices, extra.data
        v = self.values
        self._numeric(slots.indptr, lambda r0, r1: block_trim_scatter(
            slots.indptr, slots.indices, data, slots.slot, slots.mirror, slots.diagonal, e_ptr,
            e_idx, e_val, slots.near_indptr, slots.near_indices, v, r0, r1),
            "an entry of the extra matrix between near vertices where the pattern has none")

    def _numeric(self, indptr, scatter, what: str) -> None:
        """Zero the factor's values, ``scatter(r0, r1)`` the matrix's rows into them (two
        halves at once; each returns the first bad row or -1, named with ``what``), then
        factor."""
        self.factored = False
        self.values[:] = 0.0
        # rows split at a vertex: the two halves then write different blocks
        mid = 3 * int(np.searchsorted(indptr, indptr[-1] // 2) // 3)
        bad = both(lambda: scatter(0, mid), lambda: scatter(mid, 3 * self.n),
                   threads=self.threads)
        for row in bad:
            if row >= 0:
                raise ValueError(f"row {row}: {what}")
        v, colptr, rowidx = self.values, self.colptr, self.rowidx
        n = self.n
        heads = (-np.ones(n, np.int64), -np.ones(n, np.int64))
        link = -np.ones(n, np.int64)
        nextpos = colptr[:-1].copy()
        pos = (np.empty(n, np.int64), np.empty(n, np.int64))
        failed = list(both(*(lambda k=k: block_factor_columns(
            self._parts[k], colptr, rowidx, v, heads[k], link, nextpos, pos[k])
            for k in (0, 1)), threads=self.threads))
        if max(failed) < 0:
            block_join_lists(self._top, heads[0], heads[1], link)
            failed.append(block_factor_columns(self._top, colptr, rowidx, v, heads[0], link,
                                               nextpos, pos[0]))
        for where in failed:
            if where >= 0:
                raise np.linalg.LinAlgError(f"the matrix is not positive definite at vertex "
                                            f"{self.perm[where]}")
        self._solve_values[:] = self.values
        self._back_values[:] = self._solve_values.reshape(-1, 9)[self._back_order]
        self.factored = True

    def solve(self, b) -> np.ndarray:
        """x (3n,) with L L^T x = ``b`` (3n,), L the factor rounded to single precision."""
        if not self.factored:
            raise RuntimeError("no factor: factor() first")
        n, colptr, rows, values = self.n, self.colptr, self._solve_rows, self._solve_values
        y = np.empty(3 * n)
        block_gather(np.ascontiguousarray(b, dtype=np.float64), self.perm, y)
        spill, top3 = self._spill, self._top3
        for part in spill:
            part[top3] = 0.0
        both(*(lambda k=k: block_forward(self._parts[k], colptr, rows, values, y, self._owner,
                                         k, spill[k]) for k in (0, 1)), threads=self.threads)
        y[top3] += spill[0][top3]
        y[top3] += spill[1][top3]
        block_forward(self._top, colptr, rows, values, y, self._owner, 2, spill[0])
        back = (self._back_colptr, self._back_rows, self._back_values.reshape(-1))
        block_backward(self._top, *back, y)
        both(*(lambda k=k: block_backward(self._parts[k], *back, y) for k in (0, 1)),
             threads=self.threads)
        out = np.empty(3 * n)
        block_spread(y, self.perm, out)
        return out


def subtree_split(colptr, rowidx) -> tuple[tuple[np.ndarray, np.ndarray], np.ndarray,
                                           np.ndarray]:
    """Split the block columns of a factor (``colptr``, ``rowidx`` of
    ``kernels.block_symbolic``) into two sets of whole subtrees of its elimination tree and
    the columns above them, so that the two sets can be factored and solved at once: the
    heaviest subtree is split into its root (above) and its children's subtrees while that
    shortens the longer set plus the part above, the subtrees dealt to the lighter set
    largest first. A column's work is its blocks squared (a factorisation's). Returns
    ``((set 0, set 1), above, owner)``: the columns of each (ascending) and ``owner`` (n,),
    0, 1 or 2 (above) per column."""
    n = len(colptr) - 1
    count = np.diff(colptr)
    parent = np.full(n, -1, dtype=np.int64)
    has = count > 1
    parent[has] = rowidx[colptr[:-1][has] + 1]
    work = count.astype(np.float64) ** 2
    subtree = work.copy()
    children: list[list[int]] = [[] for _ in range(n)]
    for j in range(n):  # a parent comes after its children
        if parent[j] >= 0:
            subtree[parent[j]] += subtree[j]
            children[parent[j]].append(j)
    candidates = [j for j in range(n) if parent[j] < 0]
    above: list[int] = []
    best = None
    for _ in range(n):
        candidates.sort(key=lambda j: (-subtree[j], j))
        load, dealt = [0.0, 0.0], ([], [])
        for j in candidates:
            k = 0 if load[0] <= load[1] else 1
            load[k] += subtree[j]
            dealt[k].append(j)
        top = float(work[above].sum())
        if best is None or top + max(load) < best[0]:
            best = (top + max(load), dealt, list(above))
        if not candidates or not children[candidates[0]] or top > best[0]:
            break
        above.append(candidates[0])
        candidates = candidates[1:] + children[candidates[0]]
    _, dealt, above = best
    owner = np.full(n, -1, dtype=np.int64)
    for k in (0, 1):
        owner[dealt[k]] = k
    owner[above] = 2
    for j in range(n - 1, -1, -1):
        if owner[j] < 0:
            owner[j] = owner[parent[j]]
    return ((np.flatnonzero(owner == 0), np.flatnonzero(owner == 1)),
            np.flatnonzero(owner == 2), owner)


def _nested_dissection(graph: sp.csr_matrix) -> np.ndarray:
    """METIS's fill-reducing order (n,) of the symmetric ``graph`` (no diagonal): the vertex
    at each position. METIS seeds its own generator, so the order repeats run to run."""
    import pymetis  # (100 ms to import: only a solve that factors pays it)

    n = graph.shape[0]
    if n < 2 or graph.nnz == 0:
        return np.arange(n, dtype=np.int64)
    perm, _ = pymetis.nested_dissection(
        adjacency=pymetis.CSRAdjacency(graph.indptr.astype(np.int64),
                                       graph.indices.astype(np.int64)))
    return np.asarray(perm, dtype=np.int64)
