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
#: ... and the most of it an edge contact point takes (``total_energy.edge_stiffness``)
EDGE_CONTACT_SCALE = 16.0
#: ... and a contact point inside a triangle
FACE_CONTACT_SCALE = 1.0
#: the fields of a saved drape's state (:meth:`ContactState.saved_arrays`)
SAVED = ("contact_scale", "anchor_of", "friction_idx", "friction_anchor", "friction_normal",
         "friction_limit", "pairs", "bary", "pair_normal", "near_edges", "edge_pairs",
         "edge_st", "edge_normal", "pairs_x")


class SavedStateError(ValueError):
    """A saved contact state (:meth:`ContactState.from_saved`) that does not fit the model;
    ``array`` names the array at fault."""

    def __init__(self, array: str, reason: str):
        super().__init__(f"{array}: {reason}")
        self.array = array
        self.reason = reason


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
    bary : (p, 3) float
        Barycentric weights of the triangle's corners at the closest point.
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
    at_rest : bool
        Whether the last solve ended at a force balance (force rule): a solve from exactly
        ``x`` keeps its self pairs too (a search made afresh there loses those the Newton
        phase held).
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
    bary: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
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
    at_rest: bool = False

    @property
    def held(self) -> np.ndarray | None:
        """``x`` when the last solve ended with friction on, else None."""
        return self.x if self.friction_on else None

    def copy(self) -> "ContactState":
        """A deep copy (arrays and matrix copied)."""
        return replace(self, **{f.name: _copied(getattr(self, f.name)) for f in fields(self)})

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The whole state as named arrays (e.g. for ``np.savez``); :meth:`from_arrays` reads
        them back unchecked. A None field is left out; the sparse matrix is stored as its CSR
        parts. (A saved drape keeps the checked part of :meth:`saved_arrays`.)"""
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
                values[f.name] = (value.item() if f.name in ("seam_k", "friction_on",
                                                             "at_rest") else value)
            else:
                values[f.name] = None
        values["friction_on"] = bool(values["friction_on"])
        values["at_rest"] = bool(values["at_rest"])
        values["seam_k"] = float(values["seam_k"])
        return cls(**values)

    def saved_arrays(self) -> dict[str, np.ndarray]:
        """What a saved drape keeps of this state besides its positions (``SAVED``: each
        contact's stiffening, the friction anchors and terms, the self pairs), as named
        arrays for ``np.savez``; :meth:`from_saved` reads them back. A restart from the positions
        alone cannot recompute them: the 1.5K coat on male_heavy, restarted from its saved
        rest without them, moved 4.4 mm over 105 iterations."""
        out = {name: np.array(getattr(self, name)) for name in SAVED
               if getattr(self, name) is not None}
        out["at_rest"] = np.asarray(self.at_rest)
        return out

    @classmethod
    def from_saved(cls, arrays, *, n: int, n_triangles: int, x) -> "ContactState":
        """The state of :meth:`saved_arrays` (a mapping of name -> array, e.g. a checked read
        of its ``.npz``) for a model of ``n`` solved vertices and ``n_triangles``
        triangles, ended at the simulated positions ``x`` (n3, 3) [m] with friction on: a
        solve from exactly ``x`` continues it. Raises :class:`SavedStateError` naming the
        array when one is missing or does not fit that model (shape, kind, range, NaN)."""
        def get(name, shape, kind="f"):
            if name not in arrays:
                raise SavedStateError(name, "missing")
            a = np.asarray(arrays[name])
            if a.dtype.kind not in ("fiu" if kind == "f" else "iu"):
                want = "numbers" if kind == "f" else "integers"
                raise SavedStateError(name, f"expected {want}, got {a.dtype}")
            if a.ndim != len(shape) or any(w is not None and w != g
                                           for w, g in zip(shape, a.shape)):
                want = "(" + ", ".join("k" if w is None else str(w) for w in shape) + ")"
                raise SavedStateError(name, f"expected shape {want}, got {a.shape}")
            return np.ascontiguousarray(a, dtype=np.float64 if kind == "f" else np.int64)

        def flag(name):  # a true/false written by saved_arrays; absent: False
            a = np.asarray(arrays.get(name, False))
            if a.dtype.kind != "b" or a.size != 1:
                raise SavedStateError(name, f"expected one true or false, got {a.dtype} "
                                            f"{a.shape}")
            return bool(a.item())

        def finite(name, a):
            if not np.isfinite(a).all():
                raise SavedStateError(name, "holds NaN or infinite values")
            return a

        def within(name, a, stop, what="indices"):
            if len(a) and (a.min() < 0 or a.max() >= stop):
                raise SavedStateError(name, f"{what} outside 0 ... {stop - 1}")
            return a

        scale = finite("contact_scale", get("contact_scale", (n,)))
        if len(scale) and (scale.min() < 1.0 or scale.max() > MAX_CONTACT_SCALE):
            raise SavedStateError("contact_scale", f"outside 1 ... {MAX_CONTACT_SCALE:g}")
        anchor_of = get("anchor_of", (n, 3))
        if np.isinf(anchor_of).any() or (np.isnan(anchor_of).any(axis=1)
                                         != np.isnan(anchor_of).all(axis=1)).any():
            raise SavedStateError("anchor_of", "rows must be finite or all NaN (no anchor)")
        friction_idx = within("friction_idx", get("friction_idx", (None,), "i"), n)
        k = len(friction_idx)
        friction_limit = finite("friction_limit", get("friction_limit", (k,)))
        if len(friction_limit) and friction_limit.min() < 0.0:
            raise SavedStateError("friction_limit", "negative")
        pairs = get("pairs", (None, 2), "i")
        within("pairs", pairs[:, 0], n, "vertex indices")
        within("pairs", pairs[:, 1], n_triangles, "triangle indices")
        p = len(pairs)
        near_edges = within("near_edges", get("near_edges", (None, 2), "i"), n)
        edge_pairs = within("edge_pairs", get("edge_pairs", (None, 2), "i"), len(near_edges))
        q = len(edge_pairs)
        return cls(contact_scale=scale, anchor_of=anchor_of, friction_idx=friction_idx,
                   friction_anchor=finite("friction_anchor", get("friction_anchor", (k, 3))),
                   friction_normal=finite("friction_normal", get("friction_normal", (k, 3))),
                   friction_limit=friction_limit, pairs=pairs,
                   bary=finite("bary", get("bary", (p, 3))),
                   pair_normal=finite("pair_normal", get("pair_normal", (p, 3))),
                   near_edges=near_edges, edge_pairs=edge_pairs,
                   edge_st=finite("edge_st", get("edge_st", (q, 2))),
                   edge_normal=finite("edge_normal", get("edge_normal", (q, 3))),
                   pairs_x=finite("pairs_x", get("pairs_x", (n, 3)))
                   if "pairs_x" in arrays else None,
                   x=np.array(x, dtype=np.float64), friction_on=True,
                   at_rest=flag("at_rest"))


def _copied(value):
    if value is None or isinstance(value, (bool, float, int)):
        return value
    return value.copy()
