"""Mesh update after a pattern edit (paper Sec. 5, 6.4, 7.1; METHOD.md section 4).

Boundary vertices are re-placed on the edited outline at their stored arc-length fractions
(``mesh.boundary_edge`` / ``boundary_param``); interior vertices follow through generalized
barycentric coordinates computed once per panel: maximum entropy coordinates with the
angle-bisector prior for a panel with one outline, enhanced mean value coordinates over all
loops for a panel with inner loops. Lengths in metres.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field

import numba
import numpy as np

from ..constants import tol
from ..coords import max_entropy_coordinates, mean_value_coordinates
from ..mesh import GarmentMesh
from ..pattern import Pattern, PatternError
from .remesh import remesh_panels

#: a panel whose minimum angle falls below this after an edit is re-meshed [degrees]
MIN_ANGLE = 15.0
#: most intermediate outlines tried before a panel is re-meshed instead
MAX_STEPS = 32


@dataclass(frozen=True)
class PanelCoordinates:
    """Coordinates of one panel's interior vertices over its boundary vertices.

    control : (n,) int    boundary vertices of the panel, loop by loop (the mesh's order).
    rows : (n,) int       where they sit in ``mesh.boundary_vertices``.
    interior : (q,) int   interior vertices.
    triangles : (t, 3) int   the panel's triangles.
    weights : (q, n) float32   coordinates; used on boundary displacements, so single
        precision costs at most ~1e-7 of the displacement and halves the memory traffic.
    method : str   ``"mec"`` or ``"mvc"``.
    """

    control: np.ndarray
    rows: np.ndarray
    interior: np.ndarray
    triangles: np.ndarray
    weights: np.ndarray
    method: str

    def displace(self, delta: np.ndarray) -> np.ndarray:
        """Interior displacements (q, 2) [m] for boundary displacements ``delta`` (n, 2).

        One single-threaded pass over the weights computing both coordinates: measured on
        the shared 2-core machine, BLAS matrix–vector products had a median of 20 ms (thread
        contention) against 0.6 ms for this loop, and (q, n) @ (n, 2) takes a slow path.
        """
        d = delta.astype(np.float32)
        return _apply(self.weights, np.ascontiguousarray(d[:, 0]),
                      np.ascontiguousarray(d[:, 1])).astype(np.float64)


@numba.njit(cache=True, nogil=True, fastmath=True)
def _apply(w, dx, dy):  # pragma: no cover - compiled
    q, n = w.shape
    out = np.empty((q, 2), dtype=np.float32)
    for k in range(q):
        sx = np.float32(0.0)
        sy = np.float32(0.0)
        for i in range(n):
            sx += w[k, i] * dx[i]
            sy += w[k, i] * dy[i]
        out[k, 0] = sx
        out[k, 1] = sy
    return out


@numba.njit(cache=True, nogil=True)
def _quality(v, tris, area_tol):  # pragma: no cover - compiled
    """(inverted triangles, smallest angle [degrees]) in one pass: the smallest angle of a
    triangle is opposite its shortest side. ``mesh.quality.min_angle`` takes ~10 ms for
    20K triangles, most of a dragging frame."""
    bad = 0
    cmax = -1.0
    for k in range(tris.shape[0]):
        a, b, c = tris[k, 0], tris[k, 1], tris[k, 2]
        e1x, e1y = v[b, 0] - v[a, 0], v[b, 1] - v[a, 1]
        e2x, e2y = v[c, 0] - v[a, 0], v[c, 1] - v[a, 1]
        if 0.5 * (e1x * e2y - e1y * e2x) <= area_tol:
            bad += 1
        l0 = (v[c, 0] - v[b, 0]) ** 2 + (v[c, 1] - v[b, 1]) ** 2
        l1 = e2x * e2x + e2y * e2y
        l2 = e1x * e1x + e1y * e1y
        s, o1, o2 = l0, l1, l2
        if l1 < s:
            s, o1, o2 = l1, l0, l2
        if l2 < s:
            s, o1, o2 = l2, l0, l1
        cos = (o1 + o2 - s) / (2.0 * np.sqrt(o1 * o2))
        cmax = max(cmax, cos)
    return bad, np.degrees(np.arccos(min(cmax, 1.0)))


def panel_coordinates(mesh: GarmentMesh, panel: int) -> PanelCoordinates:
    """Compute the coordinates of panel number ``panel`` of ``mesh`` (the slow part)."""
    loops = mesh.loops(panel)
    rows = np.concatenate([np.flatnonzero(mesh.boundary_loop == i)
                           for i in np.flatnonzero(mesh.loop_panel == panel)])
    control = mesh.boundary_vertices[rows]
    mask = np.zeros(mesh.n_vertices, dtype=bool)
    mask[mesh.panel_vertices(panel)] = True
    mask[mesh.boundary_vertices] = False
    interior = np.flatnonzero(mask)
    pts = mesh.vertices[interior]
    if len(loops) == 1:
        w, method = max_entropy_coordinates(mesh.vertices[control], pts, prior="bisector"), "mec"
    else:
        w, method = mean_value_coordinates([mesh.vertices[lp] for lp in loops], pts), "mvc"
    return PanelCoordinates(control, rows, interior, _panel_triangles(mesh, panel), np.ascontiguousarray(w, dtype=np.float32),
                            method)


@dataclass
class CoordinateCache:
    """Per-panel coordinates of one mesh, computed on first use and then reused.

    Valid for ``mesh`` only: keep it while dragging (every frame updates from the same base
    mesh), build a new one for the mesh an edit produced (:meth:`adopt` takes over the
    panels the edit left as they were). Threads may share it: a panel asked for while
    another thread computes it waits for that computation instead of repeating it.
    """

    mesh: GarmentMesh
    panels: dict = field(default_factory=dict)
    _locks: dict = field(default_factory=dict, repr=False)
    _lock: threading.Lock = field(default_factory=threading.Lock, repr=False)

    def get(self, panel: int) -> PanelCoordinates:
        with self._lock:
            lock = self._locks.setdefault(panel, threading.Lock())
        with lock:
            if panel not in self.panels:
                self.panels[panel] = panel_coordinates(self.mesh, panel)
        return self.panels[panel]

    def adopt(self, other: CoordinateCache) -> list[int]:
        """Take ``other``'s coordinates of every panel that is the same in both meshes (same
        topology, same vertex positions of the panel): computed from the same numbers,
        they are the same numbers. An edit moves a few panels; the others keep theirs.
        Returns the panels taken."""
        a, b = self.mesh, other.mesh
        if a is not b and not all(np.array_equal(getattr(a, k), getattr(b, k)) for k in
                                  ("triangles", "triangle_panel", "vertex_panel",
                                   "boundary_vertices", "boundary_loop", "loop_panel")):
            return []
        taken = []
        for panel, coords in list(other.panels.items()):
            if panel in self.panels:
                continue
            ids = a.panel_vertices(panel)
            if a is b or np.array_equal(a.vertices[ids], b.vertices[ids]):
                self.panels[panel] = coords
                taken.append(panel)
        return taken


@dataclass(frozen=True)
class UpdateReport:
    """What an update did.

    moved : tuple of str       panels whose outline changed.
    steps : dict str -> int    intermediate outlines used per moved panel (1 = direct).
    remeshed : tuple of str    panels re-triangulated (quality or flips).
    inverted : int             inverted triangles after the update (0 on success; with
                               ``remesh=False``, those of the panels in ``needs_remesh``).
    min_angle : float          smallest triangle angle of the moved panels [degrees].
    needs_remesh : tuple of str   with ``remesh=False``: the panels that would have been
                               re-triangulated; they kept their topology (flipped or thin
                               triangles included).
    moved_mesh : GarmentMesh or None   when panels were re-meshed: the old mesh with its
                               vertices moved by the edit, before re-meshing (same topology
                               as the old mesh, flat frames of the new pattern), through which
                               values on the old mesh reach the new one
                               (:func:`patternfit.mesh.transfer.transfer`).
    """

    moved: tuple
    steps: dict
    remeshed: tuple
    inverted: int
    min_angle: float
    needs_remesh: tuple = ()
    moved_mesh: GarmentMesh | None = field(default=None, repr=False, compare=False)


def boundary_positions(pattern: Pattern, mesh: GarmentMesh) -> np.ndarray:
    """Positions (b, 2) [m] of ``mesh.boundary_vertices`` on ``pattern``'s edges, at their
    stored arc-length fractions."""
    out = np.empty((len(mesh.boundary_vertices), 2))
    for k, (pname, ename) in enumerate(mesh.edge_names):
        sel = np.flatnonzero(mesh.boundary_edge == k)
        if not len(sel):
            continue
        try:
            edge = pattern.panel(pname).edge(ename)
        except KeyError as err:
            raise PatternError("the mesh has vertices on an edge the edited pattern lacks; "
                               "re-mesh the pattern", panel=pname, edge=ename) from err
        out[sel] = edge.point_at(mesh.boundary_param[sel])
    return out


def _panel_triangles(mesh: GarmentMesh, panel: int) -> np.ndarray:
    return mesh.triangles[mesh.triangle_panel == panel]


def _step_panel(vertices, coords, new_boundary):
    """Vertices (n, 2) with one panel's boundary moved to ``new_boundary`` (b, 2)."""
    v = vertices.copy()
    delta = new_boundary[coords.rows] - v[coords.control]
    v[coords.interior] += coords.displace(delta)
    v[coords.control] += delta
    return v


def _move_panel(mesh, panel, coords, target):
    """Move one panel to the boundary ``target`` (b, 2); returns (vertices, steps, ok)."""
    tris = coords.triangles
    v = _step_panel(mesh.vertices, coords, target)
    if _quality(v, tris, tol.area)[0] == 0:
        return v, 1, True
    start = mesh.vertices[mesh.boundary_vertices]
    steps = 2
    while steps <= MAX_STEPS:
        # Schneider et al. 2013: a chain of nearby outlines, coordinates recomputed on each
        cur = mesh
        ok = True
        for s in range(1, steps + 1):
            t = s / steps
            b = (1 - t) * start + t * target
            cur = cur.with_vertices(_step_panel(cur.vertices, panel_coordinates(cur, panel), b))
            if _quality(cur.vertices, tris, tol.area)[0]:
                ok = False
                break
        if ok:
            return cur.vertices, steps, True
        steps *= 2
    return v, steps // 2, False


def update_mesh(old_pattern: Pattern, new_pattern: Pattern, mesh: GarmentMesh, *,
                cache: CoordinateCache | None = None, min_angle: float = MIN_ANGLE,
                remesh: bool = True, return_report: bool = False):
    """Carry ``mesh`` (of ``old_pattern``) over to the edited ``new_pattern``.

    Parameters
    ----------
    old_pattern, new_pattern : Pattern
        The pattern before and after the edit; same panels, edge names and seams (their
        ease may differ) [m].
    mesh : GarmentMesh
        The mesh of ``old_pattern``.
    cache : CoordinateCache, optional
        Coordinates of ``mesh`` from an earlier call (dragging: pass the same one each frame).
    min_angle : float
        Panels whose smallest angle falls below this [degrees] are re-meshed (their
        boundary vertices kept, so seams still pair); the others keep their vertices.
    remesh : bool
        False: never re-mesh (a live drag preview, whose vertices the page maps onto its
        mesh): a panel that would need it keeps its topology and its directly updated
        vertices, inverted triangles included, and is named in the report's
        ``needs_remesh``; no ``PatternError`` for inverted triangles.
    return_report : bool
        Also return an :class:`UpdateReport`.

    Returns
    -------
    GarmentMesh, or (GarmentMesh, UpdateReport)
        Same topology (unless a panel was re-meshed; never with ``remesh=False``), no
        inverted triangles (unless ``remesh=False``).
    """
    if [p.name for p in old_pattern.panels] != list(mesh.panel_names) or \
            [p.name for p in new_pattern.panels] != list(mesh.panel_names):
        raise PatternError("the mesh's panels differ from the pattern's; re-mesh the pattern")
    edges = {(p.name, e.name) for p in new_pattern.panels for lp in p.loops for e in lp.edges}
    if edges != set(mesh.edge_names):
        extra = sorted(edges ^ set(mesh.edge_names))[0]
        raise PatternError("the edit added or removed edges (a dart?); the mesh cannot follow, "
                           "re-mesh the pattern", panel=extra[0], edge=extra[1])
    sewn = [[(sm.name, sm.a, sm.b, sm.reverse) for sm in p.seams]
            for p in (old_pattern, new_pattern)]
    if sewn[0] != sewn[1]:
        # a seam added or removed pairs other vertices: the seam pairs cannot follow
        raise PatternError("the edit changed the seams; re-mesh the pattern")
    if cache is None:
        cache = CoordinateCache(mesh)
    elif cache.mesh is not mesh:
        raise ValueError("cache: built for another mesh")
    target = boundary_positions(new_pattern, mesh)
    current = mesh.vertices[mesh.boundary_vertices]
    moved_by = np.linalg.norm(target - current, axis=1)
    vertices = mesh.vertices.copy()
    moved, steps, bad, angles = [], {}, [], {}
    for pi, name in enumerate(mesh.panel_names):
        rows = np.flatnonzero(mesh.vertex_panel[mesh.boundary_vertices] == pi)
        if not len(rows) or moved_by[rows].max() <= tol.merge:
            continue
        moved.append(name)
        pc = cache.get(pi)
        v, n, ok = _move_panel(mesh, pi, pc, target)
        sel = mesh.vertex_panel == pi
        vertices[sel] = v[sel]
        steps[name] = n
        angles[pi] = _quality(vertices, pc.triangles, tol.area)[1]
        if not ok or angles[pi] < min_angle:
            bad.append(pi)
    out = mesh.with_vertices(vertices)
    inverted = 0
    if bad and not remesh:
        inverted = sum(_quality(vertices, cache.get(pi).triangles, tol.area)[0] for pi in bad)
        report = UpdateReport(tuple(moved), steps, (), inverted,
                              min(angles.values(), default=float("nan")),
                              tuple(mesh.panel_names[i] for i in bad))
        return (out, report) if return_report else out
    moved_mesh = None
    if bad:
        moved_mesh, out = out, remesh_panels(out, bad)
        for pi in bad:
            flips, angles[pi] = _quality(out.vertices, _panel_triangles(out, pi), tol.area)
            inverted += flips
    if inverted:
        raise PatternError(f"mesh update left {inverted} inverted triangle(s); re-mesh the "
                           "pattern")
    if not return_report:
        return out
    angle = min(angles.values(), default=float("nan"))
    return out, UpdateReport(tuple(moved), steps, tuple(mesh.panel_names[i] for i in bad),
                             inverted, angle, moved_mesh=moved_mesh)
