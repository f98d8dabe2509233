"""The cloth model of a solve: everything that stays fixed while the solver iterates (SI
units: m, kg, N).

A :class:`ClothModel` holds the flat rest geometry, the fabric, the seams, the pinned
vertices and the body's distance field, and what follows from them: the rest-shape energy
terms (:func:`energies.build_terms`), the lumped masses, which vertices are free. It is
frozen: a pattern edit (:meth:`ClothModel.with_rest`) and the weld of the seams
(:meth:`ClothModel.welded_model`) make a new model. The lagged contact and friction state is
:class:`patternfit.sim.state.ContactState`; the energy of both at positions ``x`` is
:func:`patternfit.sim.total_energy.energy`.

Vertices come in three numberings: the flat pattern mesh's ``n`` vertices, the ``n3``
simulated vertices (``vertex_map``: a seam's two sides sewn by springs are two of them), and
the solved vertices (``group``: once the seams are welded, both sides of a pair are one).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sp

from ..arguments import array
from ..body.sdf import DistanceField
from ..geometry import inner_grid, longest_edges, unique_edges
from .bending_friction import BendingFriction
from .energies import MeshTerms, build_terms
from .fabrics import Fabric, get_fabric
from .gathers import gather_slack
from .settings import SolverSettings


@dataclass(frozen=True, eq=False)
class EdgePoints:
    """Body contact points between the cloth's vertices, inside its edges and (where a
    triangle is wider than the spacing) inside its triangles: point ``k`` lies at
    ``sum_j w[k, j] x[ids[k, j]]``; its contact force is shared by its vertices with the same
    weights. A point inside an edge has a third weight 0 (its third id repeats its first).

    Attributes
    ----------
    ids : (p, 3) int
        The solved vertices of each point's edge or triangle.
    w : (p, 3) float
        Their weights (non-negative, summing to 1).
    matrix : (p, n) sparse CSR
        Positions (p, 3) [m] = ``matrix @ x``; forces on the vertices = ``matrix.T @ f``.
    n_edge : int
        Points ``0 ... n_edge - 1`` lie inside edges, the rest inside triangles.
    """

    ids: np.ndarray
    w: np.ndarray
    matrix: sp.csr_matrix
    n_edge: int

    @classmethod
    def of(cls, edges, lengths, spacing: float, n: int, triangles=None,
           longest=None) -> "EdgePoints":
        """Points inside each of ``edges`` (e, 2) (over ``n`` vertices) of rest ``lengths``
        (e,) [m], evenly spaced at most ``spacing`` [m] apart (none for ``spacing`` 0), and
        inside each of ``triangles`` (m, 3) whose ``longest`` (m,) rest edge [m] is more than
        twice ``spacing``: the inner nodes of its barycentric grid of ``ceil(longest /
        spacing)`` steps a side (a body feature narrower than a triangle, a bust under a
        tight coarse dress, otherwise passes between the edges' points)."""
        edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
        count = (np.zeros(len(edges), np.int64) if spacing <= 0 else
                 np.maximum(np.ceil(np.asarray(lengths) / spacing).astype(np.int64) - 1, 0))
        owner = np.repeat(np.arange(len(edges)), count)
        # j / (count + 1) of the way along, j = 1 ... count
        j = np.arange(len(owner)) - np.repeat(np.cumsum(count) - count, count) + 1
        t = j / (count[owner] + 1.0)
        ids = edges[owner][:, [0, 1, 0]]
        w = np.c_[1.0 - t, t, np.zeros_like(t)]
        n_edge = len(ids)
        if triangles is not None and spacing > 0:
            face_ids, face_w = _face_points(np.asarray(triangles, dtype=np.int64),
                                            np.asarray(longest, dtype=np.float64), spacing)
            ids, w = np.r_[ids, face_ids], np.r_[w, face_w]
        rows = np.repeat(np.arange(len(ids)), 3)
        matrix = sp.csr_matrix((w.ravel(), (rows, ids.ravel())), shape=(len(ids), n))
        return cls(ids, w, matrix, n_edge)


def _face_points(triangles, longest, spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertex ids (q, 3) and barycentric weights (q, 3) of the inner nodes of each
    triangle's grid of ``k = ceil(longest / spacing)`` steps a side (none where k < 3)."""
    steps = np.ceil(longest / spacing - 1e-9).astype(np.int64)
    owner, w = [np.zeros(0, np.int64)], [np.zeros((0, 3))]
    for k in np.unique(steps[steps >= 3]):
        bary = inner_grid(k)
        tri = np.flatnonzero(steps == k)
        owner.append(np.repeat(tri, len(bary)))
        w.append(np.tile(bary, (len(tri), 1)))
    # in triangle order, as the vertices are numbered
    owner, w = np.concatenate(owner), np.concatenate(w)
    order = np.argsort(owner, kind="stable")
    return triangles[owner[order]], w[order]


@dataclass(frozen=True, eq=False)
class ClothModel:
    """A garment's cloth as the solver sees it; made by :meth:`build`.

    Attributes
    ----------
    rest, triangles, grain, fabric, vertex_map, seam_pairs, body, pinned
        The flat mesh (rest ``(n, 2)`` [m], triangles ``(m, 3)``, grain ``(m, 2)``), the
        fabric, the simulated vertex of each flat vertex ``(n,)``, the seam pairs ``(k, 2)``
        and pinned vertices ``(p,)`` in simulated vertices, the body's distance field [m] or
        None: :class:`patternfit.sim.solver.GarmentSolver`'s parameters, checked by
        :meth:`build`.
    group : (n3,) int
        Solved vertex of each simulated vertex (welding merges entries).
    welded : bool
        Whether the seam pairs are welded (or there are none).

    Derived (from the above):

    terms : MeshTerms
        Rest-shape energy terms over the solved vertices.
    mass : (n_solved,) float
        Lumped vertex masses [kg].
    bend_friction : BendingFriction or None
        The fabric's bending friction (KES 2HB), None when it has none.
    pinned_solved : (q,) int
        Solved vertices that are pinned.
    root : (n_solved,) int
        Solved vertex each solved vertex will be welded into (itself once welded): vertices
        with the same root are never a self-collision pair.
    free : (n_solved,) bool
        Not pinned.
    edges : (e, 2) int
        Unique edges in solved vertices.
    gather_slack : (m, 2) float
        How far each triangle's warp and weft may shrink at no cost [-]: above 0 in the band
        of a seam's longer side, whose gathers are finer than the mesh
        (:func:`patternfit.sim.gathers.gather_slack`).
    """

    #: edge contact points by spacing (:meth:`edge_points`), made on first use
    _edge_points: dict = field(init=False, default_factory=dict, repr=False)

    rest: np.ndarray
    triangles: np.ndarray
    grain: np.ndarray
    fabric: Fabric
    vertex_map: np.ndarray
    seam_pairs: np.ndarray
    body: DistanceField | None
    pinned: np.ndarray
    group: np.ndarray
    welded: bool
    terms: MeshTerms = field(init=False)
    mass: np.ndarray = field(init=False)
    bend_friction: BendingFriction | None = field(init=False)
    pinned_solved: np.ndarray = field(init=False)
    root: np.ndarray = field(init=False)
    free: np.ndarray = field(init=False)
    edges: np.ndarray = field(init=False)
    gather_slack: np.ndarray = field(init=False)

    def __post_init__(self):
        f = self.fabric
        n = self.n
        terms = build_terms(
            self.rest, self.triangles, self.grain, self.group[self.vertex_map], n,
            bend_warp=f.bending_warp, bend_weft=f.bending_weft, k_warp=f.stretch_warp,
            k_weft=f.stretch_weft, k_shear=f.shear)
        pinned = np.unique(self.group[self.pinned])
        free = np.ones(n, bool)
        free[pinned] = False
        object.__setattr__(self, "terms", terms)
        object.__setattr__(self, "mass", f.density * terms.vertex_area)
        object.__setattr__(self, "bend_friction", BendingFriction.of(terms, f))
        object.__setattr__(self, "pinned_solved", pinned)
        object.__setattr__(self, "root", np.arange(n) if self.welded or not len(self.seam_pairs)
                           else self.seam_roots())
        object.__setattr__(self, "free", free)
        object.__setattr__(self, "edges", np.ascontiguousarray(unique_edges(terms.tris)))
        object.__setattr__(self, "gather_slack", gather_slack(
            self.rest, self.triangles, self.grain, self.vertex_map, self.seam_pairs))

    @classmethod
    def build(cls, rest, triangles, grain, fabric, *, vertex_map=None, seam_pairs=None,
              body=None, pinned=None) -> "ClothModel":
        """The model of a flat pattern mesh, its seams not yet welded; the arguments are
        :class:`patternfit.sim.solver.GarmentSolver`'s (checked here)."""
        fabric = get_fabric(fabric)
        rest = array(rest, "rest", shape=(None, 2), contiguous=True)
        triangles = array(triangles, "triangles", shape=(None, 3), dtype=np.int64,
                          contiguous=True)
        grain = array(grain, "grain", shape=(None, 2), contiguous=True)
        n, m = len(rest), len(triangles)
        if len(grain) != m:
            raise ValueError(f"grain: expected {m} rows (one per triangle), got {len(grain)}")
        if m == 0 or triangles.min() < 0 or triangles.max() >= n:
            raise ValueError(f"triangles: indices must lie in [0, {n})")
        if vertex_map is None:
            vertex_map = np.arange(n)
        vmap = array(vertex_map, "vertex_map", shape=(None,), dtype=np.int64,
                     contiguous=True)
        if len(vmap) != n or vmap.min() < 0:
            raise ValueError(f"vertex_map: expected {n} non-negative indices")
        n3 = int(vmap.max()) + 1
        seam_pairs = (np.zeros((0, 2), np.int64) if seam_pairs is None
                      else array(seam_pairs, "seam_pairs", shape=(None, 2), dtype=np.int64,
                                 contiguous=True))
        if len(seam_pairs) and (seam_pairs.min() < 0 or seam_pairs.max() >= n3):
            raise ValueError(f"seam_pairs: indices must lie in [0, {n3})")
        pinned = (np.zeros(0, np.int64) if pinned is None
                  else array(pinned, "pinned", shape=(None,), dtype=np.int64, contiguous=True))
        return cls(rest=rest, triangles=triangles, grain=grain, fabric=fabric,
                   vertex_map=vmap, seam_pairs=seam_pairs, body=body, pinned=pinned,
                   group=np.arange(n3), welded=len(seam_pairs) == 0)

    @property
    def n3(self) -> int:
        """Simulated vertices."""
        return int(self.vertex_map.max()) + 1

    @property
    def n(self) -> int:
        """Solved vertices."""
        return int(self.group.max()) + 1

    def with_rest(self, rest) -> "ClothModel":
        """The model with new rest shapes ``rest`` (n, 2) [m] (same topology), e.g. after a
        pattern edit."""
        rest = array(rest, "rest", shape=(None, 2), contiguous=True)
        if rest.shape != self.rest.shape:
            raise ValueError(f"rest: expected shape {self.rest.shape}, got {rest.shape}")
        return replace(self, rest=rest)

    def seam_roots(self) -> np.ndarray:
        """(n_solved,) int: the solved vertex each solved vertex will be welded into."""
        parent = np.arange(self.n)

        def find(i):
            while parent[i] != i:
                parent[i] = parent[parent[i]]
                i = parent[i]
            return i

        for a, b in self.group[self.seam_pairs]:
            ra, rb = find(a), find(b)
            if ra != rb:
                parent[max(ra, rb)] = min(ra, rb)
        return np.array([find(i) for i in range(self.n)], dtype=np.int64)

    def welded_model(self) -> "ClothModel":
        """The model with every seam pair merged into one solved vertex."""
        _, new = np.unique(self.seam_roots(), return_inverse=True)
        return replace(self, group=new[self.group], welded=True)

    def reduce(self, x_full) -> np.ndarray:
        """Mean position (n_solved, 3) [m] of each group of simulated positions ``x_full``
        (n3, 3) [m]."""
        out = np.zeros((self.n, 3))
        np.add.at(out, self.group, x_full)
        return out / np.bincount(self.group, minlength=self.n)[:, None]

    def seam_gap(self, x_red) -> float:
        """Widest seam gap [m] at solved positions ``x_red`` (n_solved, 3) [m]."""
        if not len(self.seam_pairs):
            return 0.0
        a, b = self.group[self.seam_pairs[:, 0]], self.group[self.seam_pairs[:, 1]]
        return float(np.linalg.norm(x_red[a] - x_red[b], axis=1).max())

    # ------------------------------------------------ distances that depend on the settings
    def edge_points(self, spacing: float) -> "EdgePoints":
        """Contact points inside the edges, evenly spaced at most ``spacing`` [m] apart
        along the edges' rest lengths, and inside the triangles wider than that
        (:class:`EdgePoints`); made once per spacing."""
        if spacing not in self._edge_points:
            self._edge_points[spacing] = EdgePoints.of(
                self.edges, self.rest_lengths(), spacing, self.n, self.terms.tris,
                longest_edges(self.rest[self.triangles]))
        return self._edge_points[spacing]

    def rest_lengths(self) -> np.ndarray:
        """Rest length (e,) [m] of each of :attr:`edges` (the flat pattern's; a seam edge
        sewn from two sides: the longer)."""
        flat = unique_edges(self.triangles)
        length = np.linalg.norm(self.rest[flat[:, 0]] - self.rest[flat[:, 1]], axis=1)
        out = np.zeros(len(self.edges))
        np.maximum.at(out, self.edge_index(self.group[self.vertex_map][flat]), length)
        return out

    def edge_index(self, pairs) -> np.ndarray:
        """Index in :attr:`edges` of each of ``pairs`` (..., 2) of solved vertices, in
        either order (a pair that is no edge: a neighbouring index)."""
        pairs = np.sort(np.asarray(pairs, dtype=np.int64), axis=-1)
        keys = self.edges[:, 0] * self.n + self.edges[:, 1]  # sorted (unique_edges)
        return np.minimum(np.searchsorted(keys, pairs[..., 0] * self.n + pairs[..., 1]),
                          len(keys) - 1)

    def reach(self, settings: SolverSettings) -> float:
        """Distance kept from the body [m]."""
        return max(self.fabric.thickness, settings.contact_margin)

    @staticmethod
    def floor(settings: SolverSettings) -> float:
        """Distance to the body below which the contact is stiffened [m]."""
        return 0.5 * settings.contact_margin

    def self_gap(self, settings: SolverSettings) -> float:
        """Cloth-cloth distance kept [m]."""
        # the fabric thickness, but at least a share of the edge length: with vertex-triangle
        # pairs only, edges of coarse meshes could otherwise slip through each other
        return max(self.fabric.thickness, settings.self_gap * self.terms.edge_length)

    def detect(self, settings: SolverSettings) -> float:
        """Self-collision pairs are sought this far apart [m]."""
        # they are searched again before any vertex could have closed the margin beyond the
        # thickness (see solver.solve)
        return max(2.0 * self.self_gap(settings), settings.self_detect * self.terms.edge_length)
