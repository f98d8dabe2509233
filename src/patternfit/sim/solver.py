"""Quasi-static garment solver: the static equilibrium of a sewn garment on a body.

Minimises the total potential energy over the 3D vertex positions (METHOD.md section 5):
membrane + bending + gravity + body contact + lagged friction + lagged self-repulsion +
seam springs. L-BFGS, whose initial Hessian is a prefactored sparse Cholesky (cholespy) of
the constant quadratic part plus a contact-stiffness diagonal (METHOD.md 5.1), makes the
large motions; Newton steps on the PSD-projected Hessian of every term, solved by conjugate
gradients preconditioned by a Cholesky factor of a recent Hessian, finish at a force balance
(METHOD.md 5.2). Units: metres, kilograms, seconds, newtons, joules. See
``docs/simulation.md``.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from cholespy import CholeskySolverD, MatrixType

from ..arguments import array
from ..constants import GRAVITY, limits, tol
from ..geometry import unique_edges
from . import kernels
from .energies import MeshTerms, build_terms, spring_matrix
from .crossings import wrong_sides
from .fabrics import Fabric, get_fabric


#: the contact stiffness of a vertex found inside the body grows x4 per update up to this
_MAX_CONTACT_SCALE = 4.0 ** 6


@dataclass(frozen=True)
class SolverSettings:
    """Knobs of the solver; defaults are the measured design of METHOD.md 5.1.

    Stopping: converged when, for ``patience`` consecutive iterations, the largest vertex
    step is below ``step_tol`` [m] and the energy drop of the iteration is below
    ``energy_tol`` times the larger of the total drop so far and the work of lifting the
    garment (gravity and external forces) by 0.1 m, and no vertex has moved more than
    ``drift_tol`` [m] over the last ``window`` iterations, or since the start when fewer
    (so that a pause of the solver in a slow slide or fold is not taken for rest, while a
    warm start from an equilibrium still stops at once); or stopped at ``max_iterations`` /
    ``time_limit`` [s] (not converged).
    """

    max_iterations: int = 5000
    time_limit: float = 300.0
    #: stopping rule: "force" stops at a force balance (``residual_rms`` and
    #: ``residual_p99`` below): L-BFGS steps until the kinematic rule below holds, then
    #: Newton steps until the forces balance; "kinematic" is the earlier rule on steps,
    #: energy drop and drift (``step_tol`` ... ``drift_tol``) with L-BFGS alone, kept for
    #: stages whose end is only a start (the gravity-free relaxation, the coarse drape) and
    #: to compare with: its states are not at rest by the force measure (docs/simulation.md)
    stop: str = "force"
    #: equilibrium: the residual |F_i| / (m_i g) over the free vertices (F_i the total force
    #: -dE/dx_i of the energy minimised, m_i the lumped mass, g = 9.80665 m/s^2) has an rms
    #: at most this [-] ...
    residual_rms: float = 0.01
    #: ... and a 99th percentile at most this [-]
    residual_p99: float = 0.1
    #: Newton: the Hessian gets the regulariser m / newton_dt^2 [s] (rigid motions of a
    #: garment without support or friction are otherwise singular)
    newton_dt: float = 1.0
    #: Newton: conjugate gradients stop at this residual, relative to the gradient [-] ...
    newton_cg_tol: float = 0.05
    #: ... or after this many iterations; when more than ``newton_refactor`` were needed
    #: the preconditioner is refactored from the current Hessian (a factorisation costs
    #: some 40 solves: small-garment suite 14.2 -> 11.5 s CPU against 40, 12.5 at 8)
    newton_cg_max: int = 100
    newton_refactor: int = 15
    #: Newton: iterations between outer updates (``refresh`` for L-BFGS)
    newton_refresh: int = 4
    #: Newton: a full step is extended (x2 while the energy falls) only when its energy drop
    #: exceeds this many times the quadratic model's prediction [-]
    newton_extend: float = 1.25
    step_tol: float = 5e-5
    energy_tol: float = 1e-5
    patience: int = 5
    window: int = 50
    drift_tol: float = 1e-3
    history: int = 10
    #: largest vertex displacement of one iteration [m]
    max_step: float = 5e-3
    #: least distance kept from the body [m] when larger than the fabric's thickness: the
    #: trilinear distance field departs from the true surface by up to about half a grid
    #: step, so a margin of that size keeps the cloth off the real body mesh (cloth-cloth
    #: distances keep the thickness)
    contact_margin: float = 0.0
    #: contact pressure per metre of penetration into the thickness layer [N/m^3]
    contact_stiffness: float = 1e7
    #: depth into the layer over which the contact stiffness grows from 0 to its value [m]
    #: (``kernels.contact_law``: a stiffness that jumps at the layer's edge made Newton's
    #: steps chatter on vertices lying there)
    contact_onset: float = 1e-4
    #: share of the contact stiffness put on the preconditioner's diagonal [-]
    contact_precond: float = 0.3
    #: vertices closer than thickness + this get the contact diagonal [m]
    contact_band: float = 5e-3
    #: pseudo time step of the mass regulariser m / dt^2 in the preconditioner [s]
    precond_dt: float = 0.1
    #: refactor when the contact diagonal changed on more than this share of vertices ...
    refactor_share: float = 0.02
    #: ... or the rest of the matrix by more than this relative (Frobenius) change; below it
    #: the old factor stays a good initial Hessian (e.g. after a small pattern edit)
    refactor_change: float = 0.02
    #: iterations between outer updates (friction anchors, self pairs, sewing ramp)
    refresh: int = 25
    #: friction is switched on this many iterations after the seams are welded
    friction_delay: int = 100
    #: tangential slip at which friction reaches the Coulomb limit [m]
    friction_slip: float = 1e-3
    self_collision: bool = True
    #: self-collision pairs are sought within this share of the mean edge length [-]
    self_detect: float = 1.0
    #: cloth-cloth distance kept, as a share of the mean edge length (at least the thickness)
    self_gap: float = 0.1
    #: once the seams are welded, every pair search also looks for crossed triangles and
    #: turns the repulsion of each crossing's vertex to the side it came from
    #: (``crossings.wrong_sides``): the lagged pairs otherwise hold a crossing made
    #: while sewing (the sewing solve has no self-collision) for good (2K trousers: 10
    #: crossed pairs at their crotch at rest without it, none with it)
    untangle: bool = True
    #: stretch stiffness kept in compression, as a share [-]: 1 (full stiffness) makes
    #: cloth fold rather than shrink (bending carries the buckling; docs/simulation.md)
    compression: float = 1.0
    seam_stiffness: float = 1e3
    seam_growth: float = 4.0
    seam_stiffness_max: float = 1e7
    #: a seam pair pulls at most with the contact force of its vertices at this depth into
    #: the thickness layer [m] (0: unbounded springs), so that contact wins over sewing;
    #: once the springs are at their stiffest, the bound grows by ``seam_growth`` at each
    #: outer update where the widest gap did not shrink by 5 %, so that a seam held open by a
    #: pinch (arm against torso) still closes
    seam_pull: float = 1e-3
    #: the preconditioner sees a seam spring as the pull over this gap at most [m]
    seam_precond_gap: float = 1e-2
    #: seam pairs are welded once every gap is below this [m]
    weld_gap: float = 5e-4
    #: return right after the weld (stop_reason "welded"), e.g. to sew without gravity and
    #: drape in a second solve
    stop_at_weld: bool = False
    gravity: tuple = (0.0, -GRAVITY, 0.0)


@dataclass(frozen=True)
class DrapeChecks:
    """Checks of a solved state (every result carries them)."""

    #: vertices deeper in the body than ``constants.tol.penetration``, and the deepest
    #: vertex's depth [mm]
    inside_vertices: int
    max_depth_mm: float
    #: smallest vertex distance to the body [mm] (None without a body)
    min_clearance_mm: float | None
    #: largest distance between the two sides of a seam pair [mm]
    seam_gap_max_mm: float
    #: triangle pairs (sharing no vertex) that cross each other
    self_intersections: int
    #: whether the garment is at rest: the stop criterion was met and, where the residual
    #: is known, residual_rms <= SolverSettings.residual_rms and residual_p99 <=
    #: SolverSettings.residual_p99
    equilibrium: bool
    #: residual force |F_i| / (m_i g) over the free vertices: rms and 99th percentile [-]
    #: (None where unknown, e.g. a state checked without the solver's energy)
    residual_rms: float | None = None
    residual_p99: float | None = None

    @property
    def passed(self) -> bool:
        """Vertices inside the body and crossed triangle pairs within
        ``constants.limits`` (none), seams closed (< 0.5 mm), equilibrium reached."""
        return (self.inside_vertices <= limits.body_penetrations
                and self.seam_gap_max_mm < 0.5
                and self.self_intersections <= limits.self_intersections and self.equilibrium)

    def to_dict(self) -> dict:
        return {"inside_vertices": self.inside_vertices, "max_depth_mm": self.max_depth_mm,
                "min_clearance_mm": self.min_clearance_mm,
                "seam_gap_max_mm": self.seam_gap_max_mm,
                "self_intersections": self.self_intersections, "equilibrium": self.equilibrium,
                "residual_rms": self.residual_rms, "residual_p99": self.residual_p99}


@dataclass(frozen=True, eq=False)
class DrapeResult:
    """Outcome of :meth:`GarmentSolver.solve`.

    Attributes
    ----------
    x : (n3, 3) float
        Simulated vertex positions [m] (welded pairs coincide).
    vertex_map : (n,) int
        Flat vertex -> simulated vertex after welding (both sides of a welded pair map to
        the same index).
    welded : bool
        Whether the seam springs were closed and welded during this or an earlier solve.
    iterations : int
    seconds : float
    converged : bool
    interrupted : bool
        Stopped by KeyboardInterrupt; ``x`` is the last accepted state.
    stop_reason : str
        "converged", "iterations", "time", "interrupted", "stalled" or "welded" (with
        ``SolverSettings.stop_at_weld``).
    energy : float
        Total energy at ``x`` [J].
    checks : DrapeChecks
    factorizations : int
        Cholesky factorisations done by this solver object so far.
    """

    x: np.ndarray
    vertex_map: np.ndarray
    welded: bool
    iterations: int
    seconds: float
    converged: bool
    interrupted: bool
    stop_reason: str
    energy: float
    checks: DrapeChecks
    factorizations: int = 0


class _LBFGS:
    """Two-loop recursion with a given initial inverse Hessian (vectors flattened), the
    pairs kept in a ring of ``size`` rows."""

    def __init__(self, size: int):
        self.size = size
        self.count = 0
        self.head = 0
        self.S = self.Y = None
        self.rho = np.zeros(size)

    def reset(self):
        self.count = 0

    def push(self, s, y):
        sy = kernels.dot(s, y)
        if not sy > 1e-12 * np.sqrt(kernels.dot(s, s) * kernels.dot(y, y)):
            return
        if self.S is None or self.S.shape[1] != len(s):
            self.S = np.empty((self.size, len(s)))
            self.Y = np.empty((self.size, len(s)))
            self.count = self.head = 0
        self.S[self.head] = s
        self.Y[self.head] = y
        self.rho[self.head] = 1.0 / sy
        self.head = (self.head + 1) % self.size
        self.count = min(self.count + 1, self.size)

    def direction(self, g, h0):
        q = g.copy()
        if not self.count:
            return -h0(q)
        alphas = np.empty(self.count)
        kernels.lbfgs_back(self.S, self.Y, self.rho, self.count, self.head, q, alphas)
        r = h0(q)
        kernels.lbfgs_forward(self.S, self.Y, self.rho, self.count, self.head, r, alphas)
        return -r


def _drift(x, it, marks, window) -> float:
    """Largest vertex displacement [m] since the newest mark at least ``window`` iterations
    old, or since the oldest mark (the start) when none is that old yet."""
    old = [m for i, m in marks if it - i >= window] or [marks[0][1]]
    return float(np.sqrt(((x - old[-1]) ** 2).sum(axis=1).max()))


class GarmentSolver:
    """Static equilibrium of a garment from its flat pattern mesh.

    Parameters
    ----------
    rest : (n, 2) float
        Flat rest positions of the pattern mesh [m], each panel in its own frame.
    triangles : (m, 3) int
        Flat triangles (counter-clockwise).
    grain : (m, 2) float
        Warp direction of each triangle in its panel frame (need not be unit).
    fabric : Fabric or str
        The fabric (or a preset name / JSON path for :func:`get_fabric`).
    vertex_map : (n,) int, optional
        Simulated 3D vertex of each flat vertex (welded seam pairs share one). Default: the
        identity. ``n3 = vertex_map.max() + 1``.
    seam_pairs : (k, 2) int, optional
        Simulated-vertex pairs to sew: zero-length springs that stiffen by ``seam_growth``
        every ``refresh`` iterations until every gap is under ``weld_gap``; then the pairs
        are welded (one vertex each) and friction is switched on ``friction_delay``
        iterations later.
    body : DistanceField, optional
        Signed distance field of the body [m]; contact keeps vertices ``fabric.thickness``
        (or ``settings.contact_margin`` when larger)         away from it.
    pinned : (p,) int, optional
        Simulated vertices held at their start position.
    settings : SolverSettings, optional
    """

    def __init__(self, rest, triangles, grain, fabric, *, vertex_map=None, seam_pairs=None,
                 body=None, pinned=None, settings: SolverSettings | None = None):
        self.fabric: Fabric = get_fabric(fabric)
        self.settings = settings or SolverSettings()
        self.rest = array(rest, "rest", shape=(None, 2), contiguous=True)
        self.triangles = array(triangles, "triangles", shape=(None, 3), dtype=np.int64,
                               contiguous=True)
        self.grain = array(grain, "grain", shape=(None, 2), contiguous=True)
        n, m = len(self.rest), len(self.triangles)
        if len(self.grain) != m:
            raise ValueError(f"grain: expected {m} rows (one per triangle), got {len(self.grain)}")
        if m == 0 or self.triangles.min() < 0 or self.triangles.max() >= n:
            raise ValueError(f"triangles: indices must lie in [0, {n})")
        if vertex_map is None:
            vertex_map = np.arange(n)
        vmap = array(vertex_map, "vertex_map", shape=(None,), dtype=np.int64,
                     contiguous=True)
        if len(vmap) != n or vmap.min() < 0:
            raise ValueError(f"vertex_map: expected {n} non-negative indices")
        self.vertex_map = vmap
        self.n3 = int(vmap.max()) + 1
        self.seam_pairs = (np.zeros((0, 2), np.int64) if seam_pairs is None
                           else array(seam_pairs, "seam_pairs", shape=(None, 2), dtype=np.int64,
                                      contiguous=True))
        if len(self.seam_pairs) and (self.seam_pairs.min() < 0
                                     or self.seam_pairs.max() >= self.n3):
            raise ValueError(f"seam_pairs: indices must lie in [0, {self.n3})")
        self.body = body
        self.pinned = (np.zeros(0, np.int64) if pinned is None
                       else array(pinned, "pinned", shape=(None,), dtype=np.int64,
                                  contiguous=True))
        # simulated vertex -> solved ("reduced") vertex; welding merges entries
        self._group = np.arange(self.n3)
        self._welded = len(self.seam_pairs) == 0
        self._factor = None
        self._factor_matrix = None
        self._factor_diag = None
        self.factorizations = 0
        self._held = None
        self._hpattern = None
        self._nfactor = None
        self._cg_last = 0
        self._newton_on = False
        self._build()

    # ------------------------------------------------------------------------ set-up
    def _build(self):
        """(Re)compute the rest-shape terms for the current grouping."""
        f = self.fabric
        self._n = int(self._group.max()) + 1
        self.terms: MeshTerms = build_terms(
            self.rest, self.triangles, self.grain, self._group[self.vertex_map], self._n,
            bend_warp=f.bending_warp, bend_weft=f.bending_weft, k_warp=f.stretch_warp,
            k_weft=f.stretch_weft, k_shear=f.shear)
        self._mass = f.density * self.terms.vertex_area
        self._pinned = np.unique(self._group[self.pinned])
        self._root = (np.arange(self._n) if self._welded or not len(self.seam_pairs)
                      else self._seam_roots())
        self._free = np.ones(self._n, bool)
        self._free[self._pinned] = False
        self._edges = np.ascontiguousarray(unique_edges(self.terms.tris))
        if self._hpattern is not None and not np.array_equal(self._hpattern[0],
                                                             self.terms.tris):
            self._hpattern = None
            self._nfactor = None

    def set_rest(self, rest) -> None:
        """New rest shapes (same topology), e.g. after a pattern edit; then ``solve`` from
        the previous state. The factorisation is kept while the matrix is unchanged."""
        rest = array(rest, "rest", shape=(None, 2), contiguous=True)
        if rest.shape != self.rest.shape:
            raise ValueError(f"rest: expected shape {self.rest.shape}, got {rest.shape}")
        self.rest = rest
        self._build()

    def _seam_roots(self):
        """(n,) int: the solved vertex each solved vertex will be welded into."""
        parent = np.arange(self._n)

        def find(i):
            while parent[i] != i:
                parent[i] = parent[parent[i]]
                i = parent[i]
            return i

        for a, b in self._group[self.seam_pairs]:
            ra, rb = find(a), find(b)
            if ra != rb:
                parent[max(ra, rb)] = min(ra, rb)
        return np.array([find(i) for i in range(self._n)], dtype=np.int64)

    def _weld(self):
        """Merge every seam pair into one solved vertex."""
        _, new = np.unique(self._seam_roots(), return_inverse=True)
        self._group = new[self._group]
        self._welded = True
        self._build()

    def weld(self) -> None:
        """Join every seam pair into one vertex now, before a solve whose start state has
        its seams closed already (e.g. a coarser drape carried over to this mesh)."""
        if not self._welded:
            self._weld()

    def _reduce(self, x_full):
        """Mean position of each group of simulated vertices."""
        out = np.zeros((self._n, 3))
        np.add.at(out, self._group, x_full)
        return out / np.bincount(self._group, minlength=self._n)[:, None]

    # ------------------------------------------------------------------------ energy
    def _distance(self, x):
        """Distances (n,) [m] and gradients (n, 3) of the body's field as contact sees it
        (the field's C1 reading, ``body.sdf.smooth_sdf_query``) at ``x`` (n, 3) [m]."""
        return kernels.smooth_sdf_query(self.body.values, self.body.origin, self.body.spacing, x)

    def _contact_k(self):
        return self.settings.contact_stiffness * self.terms.vertex_area * self._contact_scale

    def _energy(self, x, want_grad=True):
        t = self.terms
        grad = np.zeros_like(x)
        e = kernels.membrane(x, t.tris, t.cu, t.cv, t.area, self.fabric.stretch_warp,
                             self.fabric.stretch_weft, self.fabric.shear,
                             self.settings.compression, grad)
        qx = self._Q @ x
        e += 0.5 * float(np.einsum("ij,ij->", x, qx)) - float(np.einsum("ij,ij->", self._f, x))
        grad += qx - self._f
        if self.body is not None:
            e += kernels.contact(x, self.body.values, self.body.origin, self.body.spacing,
                                 self._reach, self._kc, self.settings.contact_onset, self._seen,
                                 self._room, grad)
        if len(self._fr_idx):
            e += kernels.friction(x, self._fr_idx, self._fr_anchor, self._fr_normal,
                                  self._fr_limit, self.settings.friction_slip, grad)
        if self._seam_limit is not None:
            a, b = self._seam_ab
            e += kernels.seam_springs(x, a, b, self._seam_k, self._seam_limit, grad)
        if len(self._pairs):
            e += kernels.self_repulsion(x, t.tris, self._pairs, self._bary, self._pnormal,
                                        self._self_gap, self._kc, grad)
        if len(self._epairs):
            e += kernels.edge_repulsion(x, self._near_edges, self._epairs, self._est,
                                        self._enormal, self._self_gap, self._kc, grad)
        grad[~self._free] = 0.0
        return e, grad

    # ------------------------------------------------------------------------ Newton
    def _hessian_pattern(self):
        """The fixed sparsity of the 3n x 3n Hessian (membrane, bending and every vertex's
        3x3 block) and each term's slots in it; made once per mesh topology."""
        if self._hpattern is not None and len(self._hpattern[4]) == 3 * self.terms.bending.nnz:
            return self._hpattern
        n3 = 3 * self._n
        tris = self.terms.tris
        dof = (3 * tris[:, :, None] + np.arange(3)).reshape(-1, 9)  # (m, 9)
        r_mem = np.repeat(dof, 9, axis=1).ravel()
        c_mem = np.tile(dof, (1, 9)).ravel()
        Q = self.terms.bending.tocoo()
        r_b = (3 * Q.row[:, None] + np.arange(3)).ravel()
        c_b = (3 * Q.col[:, None] + np.arange(3)).ravel()
        vd = 3 * np.arange(self._n)[:, None] + np.arange(3)
        r_d = np.repeat(vd, 3, axis=1).ravel()
        c_d = np.tile(vd, (1, 3)).ravel()
        keys = np.concatenate([r_mem * n3 + c_mem, r_b * n3 + c_b, r_d * n3 + c_d])
        uniq, slot = np.unique(keys, return_inverse=True)
        rows, cols = uniq // n3, uniq % n3
        indptr = np.searchsorted(rows, np.arange(n3 + 1)).astype(np.int32)
        indices = cols.astype(np.int32)
        k1, k2 = len(r_mem), len(r_mem) + len(r_b)
        # vertex pairs that share a triangle (and each vertex with itself): the pattern the
        # Newton preconditioner keeps (see _newton_preconditioner)
        near = np.unique(np.concatenate([(tris[:, :, None] * self._n + tris[:, None, :]).ravel(),
                                         np.arange(self._n) * (self._n + 1)]))
        self._hpattern = (tris.copy(), indptr, indices, slot[:k1], slot[k1:k2], slot[k2:],
                          rows, cols, near)
        return self._hpattern

    def _hessian(self, x):
        """PSD-projected Hessian (3n x 3n CSR) of the energy at ``x`` with the current lagged
        terms, plus the regulariser m / newton_dt^2; pinned rows and columns are identity."""
        s = self.settings
        t = self.terms
        f = self.fabric
        _, indptr, indices, s_mem, s_b, s_d, rows, cols, _ = self._hessian_pattern()
        mem = np.empty((len(t.tris), 81))
        kernels.membrane_hessian(x, t.tris, t.cu, t.cv, t.area, f.stretch_warp,
                                 f.stretch_weft, f.shear, s.compression, mem)
        Q = t.bending.tocoo()
        blocks = np.zeros((self._n, 3, 3))
        blocks += (self._mass / s.newton_dt ** 2)[:, None, None] * np.eye(3)
        if self.body is not None:
            d, g = self._distance(x)
            on = np.flatnonzero(d < self._reach)
            _, k_on = kernels.contact_forces(self._reach - d[on], self._kc[on], s.contact_onset)
            blocks[on] += k_on[:, None, None] * g[on, :, None] * g[on, None, :]
        if len(self._fr_idx):
            idx, nrm = self._fr_idx, self._fr_normal
            P = np.eye(3)[None] - nrm[:, :, None] * nrm[:, None, :]
            u = np.einsum("kij,kj->ki", P, x[idx] - self._fr_anchor)
            m = np.linalg.norm(u, axis=1)
            ratio, k = kernels.friction_stiffness(m, self._fr_limit, s.friction_slip)
            uh = u / np.maximum(m, 1e-300)[:, None]
            uu = uh[:, :, None] * uh[:, None, :]
            np.add.at(blocks, idx, ratio[:, None, None] * (P - uu) + k[:, None, None] * uu)
        data = (np.bincount(s_mem, weights=mem.ravel(), minlength=len(indices))
                + np.bincount(s_b, weights=np.repeat(Q.data, 3), minlength=len(indices))
                + np.bincount(s_d, weights=blocks.ravel(), minlength=len(indices)))
        n3 = 3 * self._n
        H = sp.csr_matrix((data, indices, indptr), shape=(n3, n3))
        extra = self._pair_hessian(x)
        if extra is not None:
            H = H + extra
        if not self._free.all():
            fd = np.repeat(self._free, 3).astype(float)
            H = (sp.diags(fd) @ H @ sp.diags(fd) + sp.diags(1.0 - fd)).tocsr()
        return H

    def _pair_hessian(self, x):
        """Gauss-Newton Hessian of the self-repulsion pairs (k w w^T n n^T), or None."""
        parts = []
        gap = self._self_gap
        if len(self._pairs):
            v, tri = self._pairs[:, 0], self._pairs[:, 1]
            ids = np.c_[v, self.terms.tris[tri]]
            w = np.c_[np.ones(len(v)), -self._bary]
            d = np.einsum("pc,pc->p", self._pnormal, np.einsum("pj,pjc->pc", w, x[ids]))
            on = gap - d > 0
            if on.any():
                parts.append((ids[on], w[on], self._pnormal[on], self._kc[v[on]]))
        if len(self._epairs):
            e, f = self._epairs[:, 0], self._epairs[:, 1]
            ids = np.c_[self._near_edges[e], self._near_edges[f]]
            st = self._est
            w = np.c_[1.0 - st[:, 0], st[:, 0], st[:, 1] - 1.0, -st[:, 1]]
            d = np.einsum("pc,pc->p", self._enormal, np.einsum("pj,pjc->pc", w, x[ids]))
            on = gap - d > 0
            if on.any():
                parts.append((ids[on], w[on], self._enormal[on], self._kc[ids[on]].mean(axis=1)))
        if not parts:
            return None
        rows, cols, vals = [], [], []
        for ids, w, nrm, k in parts:
            dof = (3 * ids[:, :, None] + np.arange(3)).reshape(len(ids), -1)
            wn = (w[:, :, None] * nrm[:, None, :]).reshape(len(ids), -1)
            rows.append(np.repeat(dof, dof.shape[1], axis=1).ravel())
            cols.append(np.tile(dof, (1, dof.shape[1])).ravel())
            vals.append((k[:, None, None] * wn[:, :, None] * wn[:, None, :]).ravel())
        n3 = 3 * self._n
        return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows),
                                                     np.concatenate(cols))), shape=(n3, n3))

    def _newton_preconditioner(self, H):
        """COO (rows, cols, data) of the matrix factored to precondition Newton's CG: ``H``
        (3n x 3n) on the entries between vertices that share a triangle; every other entry
        (bending across an edge, self-collision pairs) is dropped and its absolute value added
        to its row's diagonal, which keeps the matrix above ``H`` (positive definite). The
        factor's fill then is the membrane's: 15K skirt 1.18 -> 0.23 s a factorisation, 13 ->
        6 ms a solve, as many CG iterations."""
        near = self._hessian_pattern()[8]
        C = H.tocoo()
        key = (C.row // 3).astype(np.int64) * self._n + C.col // 3
        at = np.minimum(np.searchsorted(near, key), len(near) - 1)
        keep = near[at] == key
        extra = np.bincount(C.row[~keep], weights=np.abs(C.data[~keep]), minlength=H.shape[0])
        M = (sp.csr_matrix((C.data[keep], (C.row[keep], C.col[keep])), shape=H.shape)
             + sp.diags(extra)).tocoo()
        return M.row.astype(np.int32), M.col.astype(np.int32), M.data

    def _newton_direction(self, x, grad):
        """Inexact Newton step: conjugate gradients on H d = -grad, preconditioned by the
        Cholesky factor of this or an earlier Hessian (refactored when CG was slow)."""
        s = self.settings
        H = self._hessian(x)
        if self._nfactor is None or self._cg_last > s.newton_refactor:
            rows, cols, data = self._newton_preconditioner(H)
            self._nfactor = CholeskySolverD(H.shape[0], rows, cols, data, MatrixType.COO)
            self.factorizations += 1
        b = -grad.ravel()
        b[np.repeat(~self._free, 3)] = 0.0

        def prec(r):
            out = np.zeros((len(r), 1))
            self._nfactor.solve(r.reshape(-1, 1), out)
            return out.ravel()

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
            hp = H @ p
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
        self._cg_last = its
        if not xk.any():
            return prec(b)
        return xk

    # ------------------------------------------------------------------------ outer updates
    def _set_springs(self, stiffness, pull=1.0):
        s = self.settings
        Q = self.terms.bending
        # the preconditioner leaves bending out: next to the membrane it is small, and its
        # wider stencil doubled the factor's fill (22K coat: 3.1 -> 1.4 ms a solve, and as
        # many iterations or fewer on the three garments)
        Qpre = sp.csr_matrix(Q.shape)
        self._seam_limit = None
        if not self._welded and len(self.seam_pairs):
            pairs = self._group[self.seam_pairs]
            if s.seam_pull > 0:
                # bounded pull (kernels.seam_springs): the preconditioner gets the secant
                # stiffness of a pull over seam_precond_gap at most
                kc = s.contact_stiffness * self.terms.vertex_area
                self._seam_ab = (np.ascontiguousarray(pairs[:, 0]),
                                 np.ascontiguousarray(pairs[:, 1]))
                self._seam_limit = pull * s.seam_pull * np.minimum(kc[pairs[:, 0]], kc[pairs[:, 1]])
                self._seam_k = float(stiffness)
                k_pre = min(stiffness, float(np.median(self._seam_limit)) / s.seam_precond_gap)
                Qpre = Qpre + spring_matrix(pairs, k_pre, self._n)
            else:
                Qpre = spring_matrix(pairs, stiffness, self._n)
                Q = Q + Qpre
        self._Q = Q.tocsr()
        self._Qpre = Qpre.tocsr()
        self._base = (self.terms.membrane_pd + self._Qpre
                      + sp.diags(self._mass / s.precond_dt ** 2)).tocsr()

    def _refresh(self, x, friction_on, hold=False):
        """Contact stiffness, friction anchors, self-collision pairs, preconditioner.
        ``hold``: new contacts are anchored so that friction balances the tangential force
        on them (up to the Coulomb limit) instead of where they are (see ``_anchors``)."""
        s = self.settings
        n = self._n
        diag = np.zeros(n)
        self._fr_idx = np.zeros(0, np.int64)
        if self.body is not None:
            d, g = self._distance(x)
            # a vertex found inside the body (or deeper than half the contact margin, where
            # the true surface may lie) gets a stiffer contact (x4, up to 4^6)
            inside = d < self._floor
            self._contact_scale[inside] = np.minimum(self._contact_scale[inside] * 4.0,
                                                     _MAX_CONTACT_SCALE)
            self._kc = self._contact_k()
            near = d < self._reach + s.contact_band
            diag[near] = s.contact_precond * self._kc[near]
        else:
            self._kc = self._contact_k()
        if self.settings.self_collision and (self._x_pairs is None
                                             or self._moved_since_pairs(x)):
            self._find_pairs(x)
        if self.body is not None and friction_on and self.fabric.friction > 0:
            pen = self._reach - d
            idx = np.flatnonzero((pen > 0) & self._free)
            nrm = g[idx] / np.maximum(np.linalg.norm(g[idx], axis=1, keepdims=True), 1e-12)
            self._fr_normal = np.ascontiguousarray(nrm)
            self._fr_limit = self.fabric.friction * kernels.contact_forces(
                pen[idx], self._kc[idx], s.contact_onset)[0]
            # the gradient of every other term (friction is off here): what friction holds
            held = self._energy(x)[1][idx] if hold else None
            self._fr_anchor = self._anchors(x, idx, nrm, held)
            self._fr_idx = idx
        if not self._newton_on:
            self._ensure_factor(diag)

    def _anchors(self, x, idx, normal, grad=None):
        """Friction anchors of the contact vertices ``idx``.

        A vertex that sticks (tangential offset from its anchor below the slip distance)
        keeps its anchor, so static friction holds instead of creeping one slip distance per
        update; one that slides is re-anchored a slip distance behind, at the Coulomb limit;
        a new contact is anchored where it is, or, given ``grad`` (k, 3) [N] (the gradient of
        the other terms at those vertices), where friction balances its tangential part up to
        the Coulomb limit (a start taken from a saved rest: static friction held it there, and
        anchored in place it would first have to slip to carry that force; the 1.5K skirt
        restarted from its rest moved 5.4 mm).
        """
        slip = self.settings.friction_slip
        held = self._anchor_of[idx]
        new = x[idx].copy()
        if grad is not None:
            # friction cancels the tangential gradient g_t at the offset -g_t / |g_t| times
            # the offset where its force is |g_t| (kernels.friction_offset: at most slip)
            gt = grad - np.einsum("ij,ij->i", grad, normal)[:, None] * normal
            g = np.linalg.norm(gt, axis=1)
            m = kernels.friction_offset(g, self._fr_limit, slip)
            new += (m / np.maximum(g, 1e-300))[:, None] * gt
        has = ~np.isnan(held[:, 0])
        u = x[idx] - held
        u -= np.einsum("ij,ij->i", u, normal)[:, None] * normal
        m = np.linalg.norm(u, axis=1)
        stick = has & (m <= slip)
        new[stick] = held[stick]
        slide = has & (m > slip)
        new[slide] = x[idx][slide] - slip * u[slide] / m[slide, None]
        self._anchor_of[:] = np.nan
        self._anchor_of[idx] = new
        return np.ascontiguousarray(new)

    def _find_pairs(self, x):
        """Vertex-triangle and edge-edge pairs within the detection radius (lagged
        self-collision)."""
        if not self.settings.self_collision:
            return
        held = (self._pairs, self._bary, self._pnormal) if self._newton_on \
            and len(self._pairs) else None
        # grid cells of the search radius for the vertices (a 20K mesh: 9.6 ms, 11.9 at
        # twice that), twice the radius for the edges' boxes
        self._pairs, self._bary, self._pnormal = kernels.near_pairs(
            x, self.terms.tris, self._detect, self._detect, self._root)
        if held is not None:
            self._hold_pairs(x, *held)
        # edges cross each other only where two sheets are near: search the edges of the
        # vertex-triangle pairs' vertices and triangles (a tenth of the 20K trousers' edges)
        near = np.zeros(self._n, bool)
        near[self._pairs[:, 0]] = True
        near[self.terms.tris[self._pairs[:, 1]]] = True
        self._near_edges = np.ascontiguousarray(self._edges[near[self._edges].any(axis=1)])
        self._epairs, self._est, self._enormal = kernels.near_edge_pairs(
            x, self._near_edges, self._detect, 2 * self._detect, self._root)
        self._x_pairs = x.copy()
        if self._welded and self.settings.untangle:
            self._untangle(x)

    def _hold_pairs(self, x, pairs, bary, normal):
        """Keep the vertex-triangle pairs of the last search (``pairs``, ``bary``,
        ``normal``) whose vertex the new search paired with nothing while it is still within
        the detection radius on its side of the pair's normal (Newton phase). A vertex
        pressed between a fold and the body had its pair found at one search and lost at the
        next (its projection just off the triangle): its repulsion came and went, a residual
        of 29,000 x its weight at each return (22K coat, hem re-drape: 8 returns, each
        settled in 5-10 Newton steps)."""
        ids = np.c_[pairs[:, 0], self.terms.tris[pairs[:, 1]]]
        w = np.c_[np.ones(len(pairs)), -bary]
        d = np.einsum("pc,pc->p", normal, np.einsum("pj,pjc->pc", w, x[ids]))
        paired = np.zeros(self._n, bool)
        paired[self._pairs[:, 0]] = True
        # (not one whose vertex has passed to the other side: untangling turns those)
        keep = ~paired[pairs[:, 0]] & (d > 0.0) & (d < self._detect)
        if keep.any():
            self._pairs = np.ascontiguousarray(np.r_[self._pairs, pairs[keep]])
            self._bary = np.ascontiguousarray(np.r_[self._bary, bary[keep]])
            self._pnormal = np.ascontiguousarray(np.r_[self._pnormal, normal[keep]])

    def _untangle(self, x):
        """Turn the self-collision pairs towards undoing the crossings at ``x``: each vertex
        that passed through a triangle (``crossings.wrong_sides``) gets a pair with that
        triangle whose normal points back to the side it came from (replacing the pair the
        search made, which would hold it where it is), and the edge pairs around a crossing,
        which would hold it too, are dropped until it is undone."""
        tris = self.terms.tris
        crossed = kernels.crossed_pairs(x, tris, self.terms.edge_length, self._root)
        if not len(crossed):
            return
        vt, bary, normal = wrong_sides(x, tris, crossed)
        _, first = np.unique(vt[:, 0] * len(tris) + vt[:, 1], return_index=True)
        vt, bary, normal = vt[first], bary[first], normal[first]
        keep = ~np.isin(self._pairs[:, 0] * len(tris) + self._pairs[:, 1],
                        vt[:, 0] * len(tris) + vt[:, 1])
        self._pairs = np.ascontiguousarray(np.r_[self._pairs[keep], vt])
        self._bary = np.ascontiguousarray(np.r_[self._bary[keep], bary])
        self._pnormal = np.ascontiguousarray(np.r_[self._pnormal[keep], normal])
        near = np.zeros(self._n, bool)
        near[tris[crossed].ravel()] = True
        ok = ~near[self._near_edges[self._epairs].reshape(len(self._epairs), 4)].any(axis=1)
        self._epairs = np.ascontiguousarray(self._epairs[ok])
        self._est = np.ascontiguousarray(self._est[ok])
        self._enormal = np.ascontiguousarray(self._enormal[ok])

    @property
    def _reach(self):
        """Distance kept from the body [m]."""
        return max(self.fabric.thickness, self.settings.contact_margin)

    @property
    def _floor(self):
        """Distance to the body below which the contact is stiffened [m]."""
        return 0.5 * self.settings.contact_margin

    @property
    def _detect(self):
        # pairs are sought this far apart; they are searched again before any vertex could
        # have closed the margin beyond the thickness (see solve)
        return max(2.0 * self._self_gap, self.settings.self_detect * self.terms.edge_length)

    @property
    def _self_gap(self):
        # the fabric thickness, but at least a share of the edge length: with vertex-triangle
        # pairs only, edges of coarse meshes could otherwise slip through each other
        return max(self.fabric.thickness, self.settings.self_gap * self.terms.edge_length)

    def _ensure_factor(self, diag):
        s = self.settings
        base = self._base
        old = self._factor_matrix
        same_base = base is old or (old is not None and base.shape == old.shape
                                    and base.nnz == old.nnz
                                    and np.array_equal(base.indptr, old.indptr)
                                    and np.array_equal(base.indices, old.indices)
                                    and np.linalg.norm(base.data - old.data)
                                    <= s.refactor_change * np.linalg.norm(old.data))
        if same_base and self._factor_diag is not None:
            changed = np.count_nonzero(diag != self._factor_diag)
            if changed <= s.refactor_share * len(diag):
                return
        M = base + sp.diags(diag)
        free = self._free.astype(float)
        M = (sp.diags(free) @ M @ sp.diags(free) + sp.diags(1.0 - free)).tocoo()
        self._factor = CholeskySolverD(self._n, M.row.astype(np.int32), M.col.astype(np.int32),
                                       M.data.astype(np.float64), MatrixType.COO)
        self._factor_matrix = base
        self._factor_diag = diag
        self.factorizations += 1

    def _moved_since_pairs(self, x):
        """Whether two vertices may have closed half the detection margin since the search."""
        margin = self._detect - self._self_gap
        return kernels.max_relative_move(x, self._x_pairs) > 0.25 * margin

    def _precondition(self, q):
        b = np.ascontiguousarray(q.reshape(-1, 3))
        out = np.zeros_like(b)
        self._factor.solve(b, out)
        return out.ravel()

    # ------------------------------------------------------------------------ solve
    def solve(self, x0, *, forces=None, resume: bool = False,
              progress: Callable[[int, float, float, float], None] | None = None) -> DrapeResult:
        """Minimise the energy from the start positions ``x0``.

        Parameters
        ----------
        x0 : (n3, 3) float
            Start positions of the simulated vertices [m] (a previous result's ``x`` for a
            warm start after :meth:`set_rest`).
        forces : (n3, 3) float, optional
            Constant external forces on the simulated vertices [N].
        resume : bool
            ``x0`` is the end of the last solve moved a little (by an edit): its contact
            stiffness is kept, the friction anchors move with their vertices and friction
            holds from the first iteration. (A start equal to the last solve's end is
            resumed anyway.)
        progress : callable, optional
            Called after every iteration as ``progress(iteration, energy [J], step [m],
            elapsed [s])``. Raising KeyboardInterrupt in it stops the solve cleanly.

        Returns
        -------
        DrapeResult
        """
        t_start = time.perf_counter()
        s = self.settings
        x_full = array(x0, "x0", shape=(None, 3), contiguous=True)
        if len(x_full) != self.n3:
            raise ValueError(f"x0: expected {self.n3} rows, got {len(x_full)}")
        f_ext = np.zeros((self.n3, 3)) if forces is None else \
            array(forces, "forces", shape=(None, 3), contiguous=True)
        if len(f_ext) != self.n3:
            raise ValueError(f"forces: expected {self.n3} rows, got {len(f_ext)}")
        sewing = not self._welded
        k_seam = s.seam_stiffness
        pull = 1.0
        last_gap = np.inf
        # a solve that follows one which ended with friction on (a warm start) keeps its
        # friction anchors and contact stiffness, and friction acts from the first iteration
        same = self._held is not None and np.array_equal(x_full, self._held)
        warm = not sewing and self._held is not None and (same or resume)
        force_rule = s.stop == "force"
        delay = s.friction_delay
        friction_from = None if sewing else (0 if warm else delay)
        # L-BFGS steps (cheap, the large motions) until the kinematic rule holds, then (force
        # rule) Newton steps, whose Hessian sees the stiff contact and membrane, to the
        # force balance
        self._newton_on = False

        def setup(x_red, keep):
            self._f = self._mass[:, None] * np.asarray(s.gravity)[None, :]
            np.add.at(self._f, self._group, f_ext)
            self._f[~self._free] = 0.0
            self._fr_idx = np.zeros(0, np.int64)
            if not keep:
                self._contact_scale = np.ones(self._n)
                self._anchor_of = np.full((self._n, 3), np.nan)
            self._pairs = np.zeros((0, 2), np.int64)
            self._epairs = np.zeros((0, 2), np.int64)
            self._x_pairs = None
            # contact lookups start afresh (the reach may differ from the last solve's)
            self._seen = np.full((self._n, 3), np.inf)
            self._room = np.zeros(self._n)
            self._set_springs(k_seam)
            return x_red

        x = setup(self._reduce(x_full), keep=warm)
        if warm and not same:
            # the anchors move with their vertices: friction keeps the force it held
            self._anchor_of += x - self._reduce(self._held)
        # a cold start with friction on at once (from a saved or coarser rest) is held by
        # static friction where it stands
        self._refresh(x, friction_on=friction_from == 0, hold=friction_from == 0 and not warm)
        energy, grad = self._energy(x)
        lbfgs = _LBFGS(s.history)
        # the work of lifting the garment by 10 cm: the energy scale of a warm start, whose
        # own total drop is tiny
        e_scale = 0.1 * float(np.linalg.norm(self._f.sum(axis=0)))
        it = 0
        last_refresh = 0
        calm = 0
        total_drop = 0.0
        marks = [(0, x.copy())]  # (iteration, positions): the start, then every half window
        converged = interrupted = False
        reason = "iterations"
        try:
            while True:
                if it >= s.max_iterations:
                    reason = "iterations"
                    break
                if time.perf_counter() - t_start > s.time_limit:
                    reason = "time"
                    break
                every = s.newton_refresh if self._newton_on else s.refresh
                if it - last_refresh >= every or (sewing and calm >= s.patience):
                    last_refresh = it
                    if sewing:
                        gap = self._seam_gap(x)
                        if gap < s.weld_gap:
                            x_full = x[self._group]
                            self._weld()
                            x = setup(self._reduce(x_full), keep=False)
                            marks = [(it, x.copy())]
                            sewing = False
                            friction_from = it + delay
                            lbfgs.reset()
                            if s.stop_at_weld:
                                energy, grad = self._energy(x)
                                reason = "welded"
                                break
                        else:
                            if k_seam >= s.seam_stiffness_max and gap > 0.95 * last_gap:
                                pull *= s.seam_growth
                            last_gap = gap
                            k_seam = min(k_seam * s.seam_growth, s.seam_stiffness_max)
                            self._set_springs(k_seam, pull)
                    self._refresh(x, friction_on=friction_from is not None and it >= friction_from)
                    energy, grad = self._energy(x)
                    calm = 0
                if force_rule and not sewing and self._at_rest(grad):
                    if self._can_stiffen(x):
                        last_refresh = it - every  # stiffen the contact and go on
                        continue
                    converged, reason = True, "converged"
                    break
                g = grad.ravel()
                newton_now = self._newton_on
                if newton_now:
                    d = self._newton_direction(x, grad)
                else:
                    d = lbfgs.direction(g, self._precondition)
                gd = kernels.dot(g, d)
                if not gd < 0.0 and not newton_now:
                    lbfgs.reset()
                    d = -self._precondition(g)
                    gd = kernels.dot(g, d)
                if not gd < 0.0:
                    if self._to_newton(sewing):
                        continue
                    converged, reason = self._stalled(sewing, grad)
                    break
                # a capped step cannot tunnel through the body, nor follow the unbounded
                # descent of a garment that would fall past it
                longest = kernels.max_row_norm(d.reshape(-1, 3))
                alpha = min(1.0, s.max_step / max(longest, 1e-300))
                accepted = False
                # near rest the energy's rounding (its gravity part is large) hides the drop
                noise = 1e-13 * (abs(energy) + e_scale) if force_rule else 0.0
                for tries in range(30):
                    x_new = x + alpha * d.reshape(-1, 3)
                    e_new, g_new = self._energy(x_new)
                    if e_new <= energy + 1e-4 * alpha * gd + noise:
                        accepted = True
                        break
                    alpha *= 0.5
                if accepted and newton_now and tries == 0 \
                        and energy - e_new > -0.5 * s.newton_extend * gd:
                    # a full Newton step taken whole that lowered the energy by more than the
                    # model's -g.d / 2 (the drop a CG step predicts): the projected Hessian is
                    # stiffer than the energy there (cloth that buckles or slides), so try twice
                    # as far while that lowers the energy further; where the model holds (near
                    # rest) the full step stands, as an extended one threw the stiff directions
                    # off again (15K skirt: rms 0.02 -> 0.4 after a 4x step)
                    while 2.0 * alpha * longest <= s.max_step:
                        x_try = x + 2.0 * alpha * d.reshape(-1, 3)
                        e_try, g_try = self._energy(x_try)
                        if not e_try < e_new:
                            break
                        alpha *= 2.0
                        x_new, e_new, g_new = x_try, e_try, g_try
                if not accepted:
                    if lbfgs.count and not newton_now:
                        lbfgs.reset()
                        continue
                    if self._to_newton(sewing):
                        continue
                    converged, reason = self._stalled(sewing, grad)
                    break
                step_vec = x_new - x
                if not newton_now:
                    lbfgs.push(step_vec.ravel(), (g_new - grad).ravel())
                drop = energy - e_new
                total_drop += max(drop, 0.0)
                step = kernels.max_row_norm(step_vec)
                x, energy, grad = x_new, e_new, g_new
                it += 1
                if s.self_collision and self._moved_since_pairs(x):
                    self._find_pairs(x)
                    energy, grad = self._energy(x)
                if progress is not None:
                    progress(it, energy, step, time.perf_counter() - t_start)
                if it % max(s.window // 2, 1) == 0:
                    marks = marks[-2:] + [(it, x.copy())]
                small = step < s.step_tol and drop <= s.energy_tol * max(total_drop, e_scale)
                calm = calm + 1 if small else 0
                if not newton_now and calm >= s.patience and not sewing \
                        and _drift(x, it, marks, s.window) <= s.drift_tol:
                    if self._can_stiffen(x):
                        last_refresh = it - s.refresh  # stiffen the contact and go on
                        continue
                    if self._to_newton(sewing):
                        last_refresh = it - s.newton_refresh  # refresh for Newton's Hessian
                        continue
                    converged, reason = True, "converged"
                    break
        except KeyboardInterrupt:
            interrupted, reason = True, "interrupted"
        x_out = x[self._group]
        # remember the end state when friction was on: a solve from exactly here is warm
        self._held = (x_out.copy() if friction_from is not None and it >= friction_from
                      and not interrupted else None)
        seconds = time.perf_counter() - t_start
        return DrapeResult(
            x=x_out, vertex_map=self._group[self.vertex_map], welded=self._welded,
            iterations=it, seconds=seconds, converged=converged, interrupted=interrupted,
            stop_reason=reason, energy=float(energy),
            checks=self.checks(x_out, converged=converged, residual=self._residual(grad)),
            factorizations=self.factorizations)

    # ------------------------------------------------------------------------ checks
    def _seam_gap(self, x_red):
        if not len(self.seam_pairs):
            return 0.0
        a, b = self._group[self.seam_pairs[:, 0]], self._group[self.seam_pairs[:, 1]]
        return float(np.linalg.norm(x_red[a] - x_red[b], axis=1).max())

    def _residual(self, grad):
        """(rms, 99th percentile) of |F_i| / (m_i g) over the free solved vertices, F = -grad
        of the energy minimised (lagged terms at their current anchors and pairs)."""
        free = self._free & (self._mass > 0)
        if not free.any():
            return 0.0, 0.0
        r = np.sqrt((grad[free] ** 2).sum(axis=1)) / (self._mass[free] * GRAVITY)
        return float(np.sqrt(np.mean(r * r))), float(np.percentile(r, 99))

    def _at_rest(self, grad) -> bool:
        """Whether the force balance of ``SolverSettings.residual_rms`` / ``residual_p99``
        holds (the p99 is computed only when the rms passes)."""
        s = self.settings
        free = self._free & (self._mass > 0)
        if not free.any():
            return True
        r2 = (grad[free] ** 2).sum(axis=1) / (self._mass[free] * GRAVITY) ** 2
        if float(np.mean(r2)) > s.residual_rms ** 2:
            return False
        return float(np.sqrt(np.percentile(r2, 99))) <= s.residual_p99

    def _to_newton(self, sewing) -> bool:
        """Switch from L-BFGS to Newton steps (force rule, seams welded, not yet switched);
        whether it switched."""
        if sewing or self._newton_on or self.settings.stop != "force":
            return False
        self._newton_on = True
        return True

    def _stalled(self, sewing, grad):
        """(converged, reason) when no descent step is found: at rest by the force rule, or
        (kinematic rule) whenever not sewing."""
        if sewing:
            return False, "stalled"
        if self.settings.stop == "force" and not self._at_rest(grad):
            return False, "stalled"
        return True, "converged"

    def _can_stiffen(self, x_red):
        """Whether a vertex is inside the body (or deeper than half the contact margin) with
        its contact stiffness not yet at the cap."""
        if self.body is None:
            return False
        d, _ = self._distance(x_red)
        return bool(((d < self._floor) & (self._contact_scale < _MAX_CONTACT_SCALE)).any())

    def compressed_share(self, x, strain: float = 0.01) -> float:
        """Share of the membrane's rest area [-] whose warp or weft is compressed by more
        than ``strain`` at simulated positions ``x`` (n3, 3) [m] (cloth that shrinks in
        plane instead of folding)."""
        x = self._reduce(array(x, "x", shape=(None, 3), contiguous=True))
        t = self.terms
        p = x[t.tris]  # (m, 3, 3)
        lu = np.linalg.norm(np.einsum("mj,mjc->mc", t.cu, p), axis=1)
        lv = np.linalg.norm(np.einsum("mj,mjc->mc", t.cv, p), axis=1)
        short = (lu < 1.0 - strain) | (lv < 1.0 - strain)
        return float(t.area[short].sum() / t.area.sum())

    def crossings(self, x) -> int:
        """Triangle pairs (sharing no vertex once welded) that cross each other at simulated
        positions ``x`` (n3, 3) [m]."""
        x = array(x, "x", shape=(None, 3), contiguous=True)
        # welded pairs are one vertex here, so triangles meeting across a seam are neighbours
        return int(kernels.intersecting_pairs(self._reduce(x), self.terms.tris,
                                              self.terms.edge_length))

    def checks(self, x, *, converged: bool = False, residual=None) -> DrapeChecks:
        """Checks of simulated positions ``x`` (n3, 3) [m]; see :class:`DrapeChecks`.
        ``residual``: (rms, p99) of the residual force at ``x`` when known; then
        ``equilibrium`` also needs them within the settings' thresholds."""
        x = array(x, "x", shape=(None, 3), contiguous=True)
        if self.body is not None:
            d, _ = kernels.sdf_query(self.body.values, self.body.origin, self.body.spacing, x)
            inside = int((d < -tol.penetration).sum())
            depth = float(max(0.0, -d.min()) * 1e3)
            clearance = float(d.min() * 1e3)
        else:
            inside, depth, clearance = 0, 0.0, None
        gap = (float(np.linalg.norm(x[self.seam_pairs[:, 0]] - x[self.seam_pairs[:, 1]],
                                    axis=1).max() * 1e3) if len(self.seam_pairs) else 0.0)
        crossing = self.crossings(x)
        rms = p99 = None
        at_rest = bool(converged)
        if residual is not None:
            rms, p99 = float(residual[0]), float(residual[1])
            if self.settings.stop == "force":
                at_rest = at_rest and rms <= self.settings.residual_rms \
                    and p99 <= self.settings.residual_p99
        return DrapeChecks(inside_vertices=inside, max_depth_mm=depth, min_clearance_mm=clearance,
                           seam_gap_max_mm=gap, self_intersections=crossing,
                           equilibrium=at_rest, residual_rms=rms, residual_p99=p99)
