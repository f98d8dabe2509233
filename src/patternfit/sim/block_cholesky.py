"""Sparse Cholesky factor in 3 x 3 vertex blocks, its ordering made once per mesh topology
(SI units: N/m for the matrix, the solve's units are its right-hand side's over N/m).

The Newton step's preconditioner (``preconditioners.newton_direction``) is refactored every
few steps with new values on the same vertex graph (the pairs of vertices that share a
triangle). :class:`BlockCholesky` orders that graph once by METIS nested dissection
(``pymetis``) and finds the factor's block pattern; :meth:`BlockCholesky.factor` is then
numeric only and :meth:`BlockCholesky.solve` works on blocks (``kernels.cholesky``).
The solves read the factor rounded to single precision: they are bound by memory traffic,
which that halves (22K coat: 3.3 -> 2.0 ms a solve), and a preconditioner needs no more (the
solve is exact for a matrix within a relative 1e-7 of the one factored, still symmetric
positive definite, and the arithmetic stays double).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .kernels import block_factor, block_solve, block_symbolic


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
        status, where = block_factor(self.colptr, self.rowidx, self.iperm,
                                     np.asarray(indptr, dtype=np.int64),
                                     np.asarray(indices, dtype=np.int64),
                                     np.asarray(data, dtype=np.float64), self.values)
        if status == 1:
            raise ValueError(f"row {where}: an entry between vertices that are not "
                             f"neighbours in the factor's graph")
        if status == 2:
            raise np.linalg.LinAlgError(f"the matrix is not positive definite at vertex "
                                        f"{self.perm[where]}")
        self._solve_values[:] = self.values
        self.factored = True

    def solve(self, b) -> np.ndarray:
        """x (3n,) with L L^T x = ``b`` (3n,), L the factor rounded to single precision."""
        if not self.factored:
            raise RuntimeError("no factor: factor() first")
        out = np.empty(3 * self.n)
        block_solve(self.colptr, self._solve_rows, self._solve_values, self.perm,
                    np.ascontiguousarray(b, dtype=np.float64), out)
        return out


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
