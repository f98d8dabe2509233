"""The state a solve passes on: the lagged contact, friction, self-collision and seam terms
(SI units: m, N, kg).

The energy the solver minimises (:func:`patternfit.sim.total_energy.energy`) reads the
cloth model, this state and the positions. The outer updates of a solve
(:mod:`patternfit.sim.outer_updates`: every ``SolverSettings.refresh`` iterations) write it:
contact stiffness, friction anchors, self-collision pairs, seam springs. A solve takes a
state in and hands one out (:func:`patternfit.sim.solver.solve`); the next solve from its
end positions is then warm (friction anchors and contact stiffness kept). Arrays are over
the solved vertices (``ClothModel.n``) of the model the state was made with.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace

import numpy as np
import scipy.sparse as sp

#: the contact stiffness of a vertex found inside the body grows x4 per update up to this
MAX_CONTACT_SCALE = 4.0 ** 6


def _ints(*shape):
    return np.zeros(shape, np.int64)


@dataclass(eq=False)
class ContactState:
    """Lagged terms of the energy and the end of the last solve.

    Attributes
    ----------
    forces : (n, 3) float
        Constant forces on the solved vertices [N]: gravity and external forces, zero on
        pinned vertices.
    contact_scale : (n,) float
        Multiplier of each vertex's contact stiffness (x4 per update while it is found inside
        the body, up to ``MAX_CONTACT_SCALE``).
    contact_k : (n,) float
        Contact stiffness per vertex [N/m] (pressure stiffness x vertex area x scale).
    anchor_of : (n, 3) float
        Friction anchor of each vertex [m] (NaN where none).
    friction_idx : (k,) int
        Vertices under friction (in contact at the last update).
    friction_anchor, friction_normal : (k, 3) float
        Their anchors [m] and the body's unit normals there.
    friction_limit : (k,) float
        Their Coulomb limits mu x normal force [N].
    pairs : (p, 2) int
        Self-collision vertex-triangle pairs (vertex, triangle).
    bary : (p, 2) float
        Barycentric weights of the triangle's 2nd and 3rd corner at the closest point.
    pair_normal : (p, 3) float
        Unit normal each pair is kept apart along.
    near_edges : (e, 2) int
        Edges near some vertex-triangle pair (those searched for edge-edge pairs).
    edge_pairs : (q, 2) int
        Edge-edge pairs, rows of ``near_edges``.
    edge_st : (q, 2) float
        Closest-point parameters on both edges.
    edge_normal : (q, 3) float
        Unit normal each edge pair is kept apart along.
    pairs_x : (n, 3) float or None
        Positions [m] at the last pair search.
    quadratic : (n, n) sparse
        The quadratic energy's matrix per coordinate [N/m]: bending, plus linear seam springs
        (``SolverSettings.seam_pull`` 0).
    seam_a, seam_b : (s,) int
        Solved vertices of the bounded seam springs.
    seam_k : float
        Their stiffness [N/m].
    seam_limit : (s,) float or None
        Their largest pull [N]; None: no bounded seam springs.
    x : (n3, 3) float or None
        Simulated positions [m] where the last solve ended (None before any).
    friction_on : bool
        Whether the last solve ended with friction on (and was not interrupted): a solve
        from exactly ``x`` (or from ``x`` moved a little, ``resume``) is warm.
    """

    forces: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    contact_scale: np.ndarray = field(default_factory=lambda: np.zeros(0))
    contact_k: np.ndarray = field(default_factory=lambda: np.zeros(0))
    anchor_of: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    friction_idx: np.ndarray = field(default_factory=lambda: _ints(0))
    friction_anchor: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    friction_normal: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    friction_limit: np.ndarray = field(default_factory=lambda: np.zeros(0))
    pairs: np.ndarray = field(default_factory=lambda: _ints(0, 2))
    bary: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    pair_normal: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    near_edges: np.ndarray = field(default_factory=lambda: _ints(0, 2))
    edge_pairs: np.ndarray = field(default_factory=lambda: _ints(0, 2))
    edge_st: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    edge_normal: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    pairs_x: np.ndarray | None = None
    quadratic: sp.csr_matrix = field(default_factory=lambda: sp.csr_matrix((0, 0)))
    seam_a: np.ndarray = field(default_factory=lambda: _ints(0))
    seam_b: np.ndarray = field(default_factory=lambda: _ints(0))
    seam_k: float = 0.0
    seam_limit: np.ndarray | None = None
    x: np.ndarray | None = None
    friction_on: bool = False

    @property
    def held(self) -> np.ndarray | None:
        """``x`` when the last solve ended with friction on, else None."""
        return self.x if self.friction_on else None

    def copy(self) -> "ContactState":
        """A deep copy (arrays and matrix copied)."""
        return replace(self, **{f.name: _copied(getattr(self, f.name)) for f in fields(self)})

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The state as named arrays (e.g. for ``np.savez``); :meth:`from_arrays` reads them
        back. A None field is left out; the sparse matrix is stored as its CSR parts."""
        out = {}
        for f in fields(self):
            value = getattr(self, f.name)
            if value is None:
                continue
            if sp.issparse(value):
                m = value.tocsr()
                out.update({f"{f.name}.data": m.data, f"{f.name}.indices": m.indices,
                            f"{f.name}.indptr": m.indptr,
                            f"{f.name}.shape": np.array(m.shape, np.int64)})
            else:
                out[f.name] = np.asarray(value)
        return out

    @classmethod
    def from_arrays(cls, arrays) -> "ContactState":
        """The state written by :meth:`to_arrays` (a mapping of name -> array, e.g. an
        ``np.load`` of its ``np.savez``)."""
        values = {}
        for f in fields(cls):
            if f.name == "quadratic":
                shape = tuple(int(v) for v in arrays["quadratic.shape"])
                values[f.name] = sp.csr_matrix(
                    (np.array(arrays["quadratic.data"]), np.array(arrays["quadratic.indices"]),
                     np.array(arrays["quadratic.indptr"])), shape=shape)
            elif f.name in arrays:
                value = np.array(arrays[f.name])
                values[f.name] = (value.item() if f.name in ("seam_k", "friction_on")
                                  else value)
            else:
                values[f.name] = None
        values["friction_on"] = bool(values["friction_on"])
        values["seam_k"] = float(values["seam_k"])
        return cls(**values)


def _copied(value):
    if value is None or isinstance(value, (bool, float, int)):
        return value
    return value.copy()
