"""The solver's sparse Cholesky factors and the Newton step (SI units: m, N).

- L-BFGS's initial inverse Hessian: a factor of the constant quadratic part (membrane at
  rest, seam springs) plus a contact-stiffness diagonal and a mass regulariser
  (METHOD.md 5.1), refactored only when that matrix changed enough;
- Newton's step: conjugate gradients on the PSD-projected Hessian of every term
  (:func:`patternfit.sim.total_energy.hessian`), preconditioned by the factor of a trimmed
  recent Hessian (METHOD.md 5.2), in 3 x 3 vertex blocks (:mod:`.block_cholesky`: its
  ordering made once per mesh topology).

:class:`Factors` keeps them between iterations and solves (a re-drape reuses them).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from cholespy import CholeskySolverD, MatrixType

from . import kernels
from .block_cholesky import BlockCholesky, TrimSlots
from .model import ClothModel
from .settings import SolverSettings
from .state import ContactState
from .threads import both
from .total_energy import (ContactLookups, HessianPattern, fits_pattern, hessian_parts,
                           hessian_pattern)


@dataclass(eq=False)
class Factors:
    """The factors and what they were made from.

    Attributes
    ----------
    base : (n, n) sparse or None
        The L-BFGS preconditioner's matrix without its contact diagonal [N/m].
    lbfgs : CholeskySolverD or None
        Factor of ``matrix`` + diag(``diag``) (pinned rows identity).
    matrix, diag
        The ``base`` and contact diagonal (n,) [N/m] last factored.
    pattern : HessianPattern or None
        The Hessian's sparsity (kept while the mesh topology is).
    newton : BlockCholesky or None
        Factor of a trimmed recent Hessian (:func:`newton_preconditioner`), ordered for
        ``pattern``'s vertex graph.
    trim : TrimSlots or None
        Where ``pattern``'s entries go in ``newton`` when trimmed (made at its first
        factorisation, forgotten with it).
    cg_last : int
        Conjugate-gradient iterations of the last Newton step.
    count : int
        Factorisations made so far.
    """

    base: sp.csr_matrix | None = None
    lbfgs: CholeskySolverD | None = None
    matrix: sp.csr_matrix | None = None
    diag: np.ndarray | None = None
    pattern: HessianPattern | None = None
    newton: BlockCholesky | None = None
    trim: TrimSlots | None = None
    cg_last: int = 0
    count: int = 0

    def follow(self, model: ClothModel) -> None:
        """Forget the Hessian's sparsity and the Newton factor when ``model``'s triangles
        (in solved vertices) are not those they were made for (after a weld)."""
        if self.pattern is not None and not np.array_equal(self.pattern.tris, model.terms.tris):
            self.pattern = None
            self.newton = self.trim = None

    def pattern_of(self, model: ClothModel, *, bending: bool = False) -> HessianPattern:
        """The Hessian's sparsity of ``model``, made when missing or stale; ``bending``: the
        preconditioner keeps the bending's pairs (:func:`hessian_pattern`)."""
        if not fits_pattern(self.pattern, model, bending=bending):
            self.pattern = hessian_pattern(model, bending=bending)
            self.newton = self.trim = None
        return self.pattern


def set_base(factors: Factors, model: ClothModel, springs, *, settings: SolverSettings):
    """The L-BFGS preconditioner's matrix: the membrane at rest, the seam ``springs`` (n, n)
    [N/m] (``outer_updates.set_springs``) and the mass regulariser m / precond_dt^2."""
    factors.base = (model.terms.membrane_pd + springs
                    + sp.diags(model.mass / settings.precond_dt ** 2)).tocsr()


def ensure_factor(factors: Factors, model: ClothModel, diag, *, settings: SolverSettings):
    """Factor ``factors.base`` + diag(``diag``) ((n,) [N/m]) unless the last factor is close
    enough: the same sparsity, a relative change of the base below ``refactor_change`` and
    the diagonal changed on at most ``refactor_share`` of the vertices."""
    s = settings
    base = factors.base
    old = factors.matrix
    same_base = base is old or (old is not None and base.shape == old.shape
                                and base.nnz == old.nnz
                                and np.array_equal(base.indptr, old.indptr)
                                and np.array_equal(base.indices, old.indices)
                                and np.linalg.norm(base.data - old.data)
                                <= s.refactor_change * np.linalg.norm(old.data))
    if same_base and factors.diag is not None:
        changed = np.count_nonzero(diag != factors.diag)
        if changed <= s.refactor_share * len(diag):
            return
    M = base + sp.diags(diag)
    free = model.free.astype(float)
    M = (sp.diags(free) @ M @ sp.diags(free) + sp.diags(1.0 - free)).tocoo()
    factors.lbfgs = CholeskySolverD(model.n, M.row.astype(np.int32), M.col.astype(np.int32),
                                    M.data.astype(np.float64), MatrixType.COO)
    factors.matrix = base
    factors.diag = diag
    factors.count += 1


def precondition(factors: Factors, q) -> np.ndarray:
    """The L-BFGS factor's solve of the flat vector ``q`` (3n,) [N]: (3n,) [m]."""
    b = np.ascontiguousarray(q.reshape(-1, 3))
    out = np.zeros_like(b)
    factors.lbfgs.solve(b, out)
    return out.ravel()


def newton_preconditioner(H, pattern: HessianPattern):
    """Lower triangle, as CSR (row starts (3n + 1,), columns, values [N/m]), of the matrix
    factored to precondition Newton's CG: ``H`` (3n x 3n CSR) on the entries
    between vertices that share a triangle (and, with the pattern's ``bending``, across an
    edge); every other entry (bending across an edge, self-collision pairs) is dropped and
    its absolute value added to its row's diagonal,
    which keeps the matrix above ``H`` (positive definite). The factor's fill then is the
    membrane's (15K skirt, then with cholespy: 1.18 -> 0.23 s a factorisation, 13 -> 6 ms a
    solve, as many CG iterations), and its vertex graph is ``pattern``'s, fixed while the
    topology is (:class:`BlockCholesky` orders it once)."""
    return kernels.trim_to_near(H.indptr, H.indices, H.data, pattern.near_indptr,
                                pattern.near_indices)


def newton_direction(factors: Factors, model: ClothModel, state: ContactState, x, grad, *,
                     settings: SolverSettings,
                     lookups: ContactLookups | None = None) -> np.ndarray:
    """Inexact Newton step (3n,) [m] at solved positions ``x`` (n, 3) [m] with gradient
    ``grad`` (n, 3) [N]: conjugate gradients on H d = -grad, preconditioned by the Cholesky
    factor of this or an earlier Hessian (refactored when CG was slow). ``lookups``: the
    energy's contact lookup cache (``total_energy.hessian_parts``, whose pairs CG multiplies
    apart and a refactorisation adds)."""
    s = settings
    pattern = factors.pattern_of(model, bending=s.newton_bending_preconditioner)
    H, extra = hessian_parts(model, state, x, settings=s, pattern=pattern, lookups=lookups)
    if factors.newton is None:
        factors.newton = BlockCholesky(pattern.near_indptr, pattern.near_indices)
        factors.trim = None
    if not factors.newton.factored or factors.cg_last > s.newton_refactor:
        if model.free.all():  # H's entries are the pattern's, in its order
            if factors.trim is None:
                factors.trim = factors.newton.trim_slots(pattern.indptr, pattern.indices,
                                                         pattern.near_indptr,
                                                         pattern.near_indices)
            factors.newton.factor_trimmed(factors.trim, H.data, extra)
        else:  # pinned vertices: H is the pattern's matrix with their rows made identity
            whole = H if extra is None else (H + extra).tocsr()
            factors.newton.factor(*newton_preconditioner(whole, pattern))
        factors.count += 1
    b = -grad.ravel()
    b[np.repeat(~model.free, 3)] = 0.0
    prec = factors.newton.solve
    # H's rows in two halves of equal entries, one per thread (the same sums either way)
    rows = (0, int(np.searchsorted(H.indptr, H.indptr[-1] // 2)), H.shape[0])
    out = np.empty_like(b)

    def product(p):
        both(*(lambda k=k: kernels.csr_rows_product(H.indptr, H.indices, H.data, p, out,
                                                    rows[k], rows[k + 1]) for k in (0, 1)),
             threads=factors.newton.threads)
        return out if extra is None else out + extra @ p

    # (the dot products by kernels.dot: BLAS's threads only wait on a busy machine)
    dot = kernels.dot
    xk = np.zeros_like(b)
    r = b.copy()
    z = prec(r)
    p = z.copy()
    rz = dot(r, z)
    tol2 = s.newton_cg_tol ** 2 * dot(b, b)
    its = 0
    for its in range(1, s.newton_cg_max + 1):
        hp = product(p)
        php = dot(p, hp)
        if not php > 0.0:
            break
        a = rz / php
        kernels.axpy(a, p, xk)
        kernels.axpy(-a, hp, r)
        if dot(r, r) <= tol2:
            break
        z = prec(r)
        rz_new = dot(r, z)
        p = z + (rz_new / rz) * p
        rz = rz_new
    factors.cg_last = its
    if not xk.any():
        return prec(b)
    return xk
