"""The garment mesh: every panel's flat triangle mesh in one object (METHOD.md section 2).

Triangle ``t`` of the flat pattern is triangle ``t`` of any 3D state of the garment: a 3D
state is just an ``(n, 3)`` array of positions for the same vertices. Each panel keeps its own
vertices (a seam's two sides are two sets of vertices, paired in ``seam_pairs``).
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..arguments import array
from ..constants import limits
from ..errors import GarmentFileError
from ..files import atomic_write_bytes, read_npz
from ..geometry import triangle_areas


@dataclass(frozen=True, eq=False)
class GarmentMesh:
    """Flat meshes of all panels of a pattern, with boundary and seam bookkeeping.

    Attributes
    ----------
    vertices : (n, 2) float
        Rest positions [m], each panel in its own flat frame.
    triangles : (m, 3) int
        Vertex indices, counter-clockwise in the flat frame.
    triangle_panel : (m,) int
        Panel index of each triangle.
    vertex_panel : (n,) int
        Panel index of each vertex.
    panel_names : tuple of str
        Panel names, in the pattern's order.
    grain : (p, 2) float
        Unit warp direction of each panel in its flat frame.
    edge_names : tuple of (str, str)
        ``(panel, edge)`` of every pattern edge that carries boundary vertices.
    boundary_vertices : (b,) int
        Boundary vertices, loop by loop, in the order of the loop's edges.
    boundary_edge : (b,) int
        Index into ``edge_names`` of the edge each boundary vertex lies on (a corner belongs
        to the edge that starts there).
    boundary_param : (b,) float
        Arc-length fraction in [0, 1) of each boundary vertex along its edge.
    boundary_loop : (b,) int
        Loop number of each boundary vertex (0 = outline of panel 0, numbered through all
        panels' loops in order).
    loop_panel : (L,) int
        Panel index of each loop.
    seam_pairs : (k, 2) int
        Vertex pairs that sewing joins (side a, side b), one row per pair.
    seam_index : (k,) int
        Seam number (in the pattern's ``seams``) of each pair.
    seam_names : tuple of str
        The pattern's seam names.
    """

    vertices: np.ndarray
    triangles: np.ndarray
    triangle_panel: np.ndarray
    vertex_panel: np.ndarray
    panel_names: tuple
    grain: np.ndarray
    edge_names: tuple
    boundary_vertices: np.ndarray
    boundary_edge: np.ndarray
    boundary_param: np.ndarray
    boundary_loop: np.ndarray
    loop_panel: np.ndarray
    seam_pairs: np.ndarray
    seam_index: np.ndarray
    seam_names: tuple

    @property
    def n_vertices(self) -> int:
        return len(self.vertices)

    @property
    def n_triangles(self) -> int:
        return len(self.triangles)

    def triangle_areas(self) -> np.ndarray:
        """(m,) float: flat (rest) area of every triangle [m^2]."""
        return triangle_areas(self.vertices, self.triangles)

    def panel_vertices(self, panel: int) -> np.ndarray:
        """(k,) int: indices of the vertices of panel number ``panel``."""
        return np.flatnonzero(self.vertex_panel == panel)

    def panel_triangles(self, panel: int) -> np.ndarray:
        """(t,) int: indices of the triangles of panel number ``panel``."""
        return np.flatnonzero(self.triangle_panel == panel)

    def loops(self, panel: int) -> list[np.ndarray]:
        """Boundary loops of ``panel`` (outline first) as arrays of vertex indices."""
        ids = np.flatnonzero(self.loop_panel == panel)
        return [self.boundary_vertices[self.boundary_loop == i] for i in ids]

    def boundary_mask(self) -> np.ndarray:
        """(n,) bool: True for vertices on a panel boundary."""
        mask = np.zeros(self.n_vertices, dtype=bool)
        mask[self.boundary_vertices] = True
        return mask

    def edge_vertices(self, panel: str, edge: str) -> np.ndarray:
        """Vertices on one pattern edge, from its start, and their arc-length fractions."""
        k = self.edge_names.index((panel, edge))
        sel = np.flatnonzero(self.boundary_edge == k)
        order = np.argsort(self.boundary_param[sel], kind="stable")
        return self.boundary_vertices[sel[order]], self.boundary_param[sel[order]]

    def with_vertices(self, vertices) -> "GarmentMesh":
        """The same topology with new rest positions ``vertices`` (n, 2) [m]."""
        v = array(vertices, "vertices", shape=self.vertices.shape)
        fields = {k: getattr(self, k) for k in self.__dataclass_fields__}
        fields["vertices"] = v
        return GarmentMesh(**fields)

    # -- files -----------------------------------------------------------------------------
    def to_bytes(self) -> bytes:
        """The mesh as the bytes of a compressed ``.npz`` file (what :meth:`save` writes)."""
        buf = io.BytesIO()
        arrays = {k: getattr(self, k) for k in self.__dataclass_fields__}
        arrays["edge_names"] = np.array(["\x1f".join(e) for e in self.edge_names], dtype=str)
        arrays["panel_names"] = np.array(self.panel_names, dtype=str)
        arrays["seam_names"] = np.array(self.seam_names, dtype=str)
        np.savez_compressed(buf, **arrays)
        return buf.getvalue()

    def save(self, path) -> Path:
        """Write the mesh to a compressed ``.npz`` file (atomically)."""
        return atomic_write_bytes(path, self.to_bytes())

    @classmethod
    def load(cls, path) -> "GarmentMesh":
        """Read a mesh written by :meth:`save`, every array checked.

        Raises :class:`~patternfit.errors.GarmentFileError` naming the file and the array when
        the file is unreadable, damaged or truncated, holds Python objects, or an array is
        missing, of the wrong kind or shape, not finite, beyond ``limits.extent`` [m] (flat
        vertices), or indexes beyond what it refers to (triangle corners, panels, loops,
        edges, seams).
        """
        arrays = read_npz(path, limit=limits.mesh_bytes, error=GarmentFileError)
        sizes: dict[str, int] = {}
        fields = {}
        for key, (kind, size, cols) in _LAYOUT.items():
            def bad(why, key=key):
                return GarmentFileError(why, file=path, place=f"array '{key}'")

            if key not in arrays:
                raise bad("missing (not a garment mesh saved by patternfit)")
            a = arrays[key]
            if a.dtype.kind not in _KINDS[kind]:
                raise bad(f"expected {_KIND_NAMES[kind]}, got {a.dtype}")
            if a.ndim != (2 if cols else 1) or (cols and a.shape[1] != cols):
                raise bad(f"expected shape ({size}{f', {cols}' if cols else ''}), got "
                          f"{a.shape}")
            if len(a) != sizes.setdefault(size, len(a)):
                raise bad(f"{len(a)} rows for {sizes[size]} {size}")
            if kind == "f":
                a = a.astype(np.float64)
                if not np.isfinite(a).all():
                    raise bad("holds NaN or infinite values")
            elif kind == "i":
                a = a.astype(np.int64)
            fields[key] = a
        if sizes["triangles"] > limits.triangles:
            raise GarmentFileError(f"{sizes['triangles']} triangles, more than the limit of "
                                   f"{limits.triangles}", file=path, place="array 'triangles'")
        for key, size in _INDEXES.items():
            a = fields[key]
            if a.size and (a.min() < 0 or a.max() >= sizes[size]):
                raise GarmentFileError(f"index {int(a.min() if a.min() < 0 else a.max())} out "
                                       f"of range: there are {sizes[size]} {size}", file=path,
                                       place=f"array '{key}'")
        param = fields["boundary_param"]
        tri = np.sort(fields["triangles"], axis=1)
        checks = (("triangles", len(np.unique(tri, axis=0)) == len(tri),
                   "a triangle given twice"),
                  ("triangles", (np.diff(tri, axis=1) != 0).all(),
                   "a triangle with a vertex twice"),
                  ("vertices", np.abs(fields["vertices"]).max(initial=0.0) <= limits.extent,
                   f"coordinates beyond {limits.extent} m"),
                  ("boundary_param", ((param >= 0) & (param <= 1)).all(),
                   "fractions outside [0, 1]"),
                  ("grain", np.allclose(np.linalg.norm(fields["grain"], axis=1), 1.0,
                                        atol=1e-6), "not unit directions"))
        for key, ok, why in checks:
            if not ok:
                raise GarmentFileError(why, file=path, place=f"array '{key}'")
        edges = tuple(tuple(str(e).split("\x1f")) for e in fields["edge_names"])
        if any(len(e) != 2 for e in edges):
            raise GarmentFileError("expected 'panel<US>edge' names", file=path,
                                   place="array 'edge_names'")
        fields["edge_names"] = edges
        fields["panel_names"] = tuple(str(s) for s in fields["panel_names"])
        fields["seam_names"] = tuple(str(s) for s in fields["seam_names"])
        return cls(**fields)


#: what :meth:`GarmentMesh.load` expects of each array: kind (f float, i integer, U text),
#: what its rows count (arrays counting the same must agree) and its columns
_LAYOUT = {
    "vertices": ("f", "vertices", 2), "triangles": ("i", "triangles", 3),
    "triangle_panel": ("i", "triangles", None), "vertex_panel": ("i", "vertices", None),
    "panel_names": ("U", "panels", None), "grain": ("f", "panels", 2),
    "edge_names": ("U", "edges", None), "boundary_vertices": ("i", "boundary vertices", None),
    "boundary_edge": ("i", "boundary vertices", None),
    "boundary_param": ("f", "boundary vertices", None),
    "boundary_loop": ("i", "boundary vertices", None), "loop_panel": ("i", "loops", None),
    "seam_pairs": ("i", "seam pairs", 2), "seam_index": ("i", "seam pairs", None),
    "seam_names": ("U", "seams", None),
}
#: integer arrays and what their values index
_INDEXES = {"triangles": "vertices", "triangle_panel": "panels", "vertex_panel": "panels",
            "boundary_vertices": "vertices", "boundary_edge": "edges", "boundary_loop": "loops",
            "loop_panel": "panels", "seam_pairs": "vertices", "seam_index": "seams"}
_KINDS = {"f": "f", "i": "iu", "U": "U"}
_KIND_NAMES = {"f": "floats", "i": "integers", "U": "text"}
