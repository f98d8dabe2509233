"""Checks of a solved state: vertices and edges inside the body, seam gaps, crossed triangle pairs,
the force balance (:class:`DrapeChecks`), and the share of compressed cloth (SI units: m;
reports in mm)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..arguments import array
from ..constants import limits, tol
from ..geometry import inner_grid, longest_edges
from . import kernels
from .model import ClothModel
from .settings import SolverSettings


@dataclass(frozen=True)
class DrapeChecks:
    """Checks of a solved state (every result carries them)."""

    #: vertices deeper in the body than ``constants.tol.penetration``, and the deepest
    #: vertex's depth [mm]
    inside_vertices: int
    max_depth_mm: float
    #: cloth edges passing through the body deeper than ``constants.tol.penetration``
    #: between their vertices (GarmentCode's body intersections; :func:`edges_in_body`)
    edges_in_body: int
    #: cloth triangles the body passes through inside, their edges clear of it (a thumb
    #: through the middle of a large triangle; :func:`faces_in_body`)
    faces_in_body: int
    #: smallest vertex distance to the body [mm] (None without a body)
    min_clearance_mm: float | None
    #: largest distance between the two sides of a seam pair [mm]
    seam_gap_max_mm: float
    #: triangle pairs (sharing no vertex) that cross each other
    self_intersections: int
    #: whether the garment is at rest: the stop criterion was met and, where the residual
    #: is known, residual_rms and residual_p99 are within ``tol.rest_rms`` and
    #: ``tol.rest_p99`` (0.01 and 0.1) and within SolverSettings' own when they are stricter
    equilibrium: bool
    #: residual force |F_i| / (m_i g) over the free vertices: rms and 99th percentile [-]
    #: (None where unknown, e.g. a state checked without the solver's energy)
    residual_rms: float | None = None
    residual_p99: float | None = None

    @property
    def passed(self) -> bool:
        """Vertices, edges and faces inside the body and crossed triangle pairs within
        ``constants.limits`` (none), seams closed (below ``limits.seam_gap_mm``), equilibrium
        reached."""
        return (self.inside_vertices <= limits.body_penetrations
                and self.edges_in_body <= limits.body_penetrations
                and self.faces_in_body <= limits.body_penetrations
                and self.seam_gap_max_mm < limits.seam_gap_mm
                and self.self_intersections <= limits.self_intersections and self.equilibrium)

    def to_dict(self) -> dict:
        return {"inside_vertices": self.inside_vertices, "max_depth_mm": self.max_depth_mm,
                "edges_in_body": self.edges_in_body, "faces_in_body": self.faces_in_body,
                "min_clearance_mm": self.min_clearance_mm,
                "seam_gap_max_mm": self.seam_gap_max_mm,
                "self_intersections": self.self_intersections, "equilibrium": self.equilibrium,
                "residual_rms": self.residual_rms, "residual_p99": self.residual_p99}


def compressed_share(model: ClothModel, x, strain: float = 0.01) -> float:
    """Share of the membrane's rest area [-] whose warp or weft is compressed by more than
    ``strain`` at simulated positions ``x`` (n3, 3) [m] (cloth that shrinks in plane instead
    of folding), beyond the slack of a gathered seam's band (``ClothModel.gather_slack``)."""
    x = model.reduce(array(x, "x", shape=(None, 3), contiguous=True))
    t = model.terms
    p = x[t.tris]  # (m, 3, 3)
    lu = np.linalg.norm(np.einsum("mj,mjc->mc", t.cu, p), axis=1)
    lv = np.linalg.norm(np.einsum("mj,mjc->mc", t.cv, p), axis=1)
    least = 1.0 - model.gather_slack - strain
    short = (lu < least[:, 0]) | (lv < least[:, 1])
    return float(t.area[short].sum() / t.area.sum())


def depth_mm(model: ClothModel, x) -> float:
    """Deepest point of simulated positions ``x`` (n3, 3) [m] in the body [mm], 0 when
    none is inside or there is no body."""
    d = _body_distance(model, array(x, "x", shape=(None, 3), contiguous=True))
    return 0.0 if d is None else _deepest_mm(d)


def _body_distance(model: ClothModel, x: np.ndarray) -> np.ndarray | None:
    """Signed distance (n3,) [m] of positions ``x`` to ``model``'s body, None without one."""
    body = model.body
    if body is None:
        return None
    return kernels.sdf_query(body.values, body.origin, body.spacing, x)[0]


def _deepest_mm(d: np.ndarray) -> float:
    """Deepest of signed distances ``d`` [m] inside the body [mm], 0 when none is inside."""
    return float(max(0.0, -d.min()) * 1e3)


def crossings(model: ClothModel, x) -> int:
    """Triangle pairs (sharing no vertex once welded) that cross each other at simulated
    positions ``x`` (n3, 3) [m]."""
    x = array(x, "x", shape=(None, 3), contiguous=True)
    # welded pairs are one vertex here, so triangles meeting across a seam are neighbours
    return int(kernels.intersecting_pairs(model.reduce(x), model.terms.tris,
                                          model.terms.edge_length))


def edges_in_body(model: ClothModel, x, *, step: float = 2e-3) -> int:
    """Edges of ``model`` whose points lie deeper in the body than ``tol.penetration`` at
    simulated positions ``x`` (n3, 3) [m], looked up every ``step`` [m] or closer along each
    edge (the field is trilinear on a 5 mm grid); 0 without a body.

    This is the measure GarmentCode rejects a drape by (cloth edges through the body
    surface): with contact felt at the vertices alone it missed a body that passes
    between them (the 3K coat on male_average: 156 edges, no vertex inside)."""
    return through_body(model, x, step=step)[0]


def faces_in_body(model: ClothModel, x, *, step: float = 2e-3) -> int:
    """Triangles of ``model`` with a point inside them deeper in the body than
    ``tol.penetration`` at simulated positions ``x`` (n3, 3) [m] while none of their edges
    is (:func:`edges_in_body`), looked up on a grid ``step`` [m] apart or closer; 0 without
    a body.

    A body feature narrower than a triangle (a thumb under a sleeve of 1.5-2K triangles,
    1 cm across) can pass through its middle with its corners and edges clear: the 2K
    GarmentCode shirt on male_thin passed every other check with a thumb 7.6 mm through
    its sleeve."""
    return through_body(model, x, step=step)[1]


def through_body(model: ClothModel, x, *, step: float = 2e-3,
                 depth: float = tol.penetration) -> tuple[int, int]:
    """(:func:`edges_in_body`, :func:`faces_in_body`) of simulated positions ``x`` (n3, 3)
    [m] in one pass: the faces' test needs the edges' anyway. ``depth`` [m]: how deep in the
    body a point of an edge or face must lie to count (the checks' ``tol.penetration``)."""
    body = model.body
    if body is None or not len(model.edges):
        return 0, 0
    x = model.reduce(array(x, "x", shape=(None, 3), contiguous=True))
    d_end, _ = kernels.sdf_query(body.values, body.origin, body.spacing, x)
    deep = _deep_edges(model, x, d_end, step, depth)
    return int(deep.sum()), _pierced_faces(model, x, d_end, deep, step, depth)


def _deep_edges(model: ClothModel, x, d_end, step: float, depth: float) -> np.ndarray:
    """Whether each of ``model.edges`` (e,) has a point deeper in the body than ``depth``
    [m], at solved positions ``x`` (n, 3) [m] whose body distances are ``d_end`` (n,) [m]."""
    body = model.body
    e = model.edges
    out = np.zeros(len(e), dtype=bool)
    length = np.linalg.norm(x[e[:, 1]] - x[e[:, 0]], axis=1)
    # the distance changes by at most SDF_SLOPE per metre: an edge whose ends are both
    # farther than that over half its length cannot reach the body
    near = np.flatnonzero(np.minimum(d_end[e[:, 0]], d_end[e[:, 1]])
                          < kernels.SDF_SLOPE * 0.5 * length)
    if not len(near):
        return out
    count = np.maximum(np.ceil(length[near] / step).astype(np.int64), 1)
    owner = np.repeat(near, count)
    t = (np.arange(len(owner)) - np.repeat(np.cumsum(count) - count, count)) \
        / np.repeat(count, count)
    p = x[e[owner, 0]] * (1.0 - t)[:, None] + x[e[owner, 1]] * t[:, None]
    d, _ = kernels.sdf_query(body.values, body.origin, body.spacing, np.ascontiguousarray(p))
    out[np.unique(owner[d < -depth])] = True
    return out


def _pierced_faces(model: ClothModel, x, d_end, deep_edge, step: float, depth: float) -> int:
    """Triangles with a point inside them deeper in the body than ``depth`` [m] and none of
    their edges in ``deep_edge`` (e,) (:func:`_deep_edges`), at solved positions ``x``
    (n, 3) [m] whose body distances are ``d_end`` (n,) [m]."""
    body = model.body
    tris = model.terms.tris
    p = x[tris]  # (m, 3, 3)
    longest = longest_edges(p)
    # the distance changes by at most SDF_SLOPE per metre: no point of a triangle is
    # farther than its longest edge from a corner
    near = np.flatnonzero(d_end[tris].min(axis=1) < kernels.SDF_SLOPE * longest)
    pierced = 0
    levels = np.maximum(np.ceil(longest[near] / step).astype(np.int64), 3)
    for n in np.unique(levels):
        group = near[levels == n]
        side = np.stack([tris[group], np.roll(tris[group], 1, axis=1)], axis=2)
        clear = ~deep_edge[model.edge_index(side)].any(axis=1)
        group = group[clear]
        if not len(group):
            continue
        q = np.einsum("qj,gjc->gqc", inner_grid(n)[:, [2, 0, 1]], p[group])  # grid inside
        d, _ = kernels.sdf_query(body.values, body.origin, body.spacing,
                                 np.ascontiguousarray(q.reshape(-1, 3)))
        pierced += int((d.reshape(len(group), -1) < -depth).any(axis=1).sum())
    return pierced


def seam_gap_mm(pairs, x) -> float:
    """The widest gap between the two vertices of a seam pair [mm]: ``pairs`` (k, 2) int,
    ``x`` (n, 3) float positions [m]; 0 without pairs."""
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    return (float(np.linalg.norm(x[pairs[:, 0]] - x[pairs[:, 1]], axis=1).max() * 1e3)
            if len(pairs) else 0.0)


def inside_reason(inside: int, deepest_mm: float) -> str | None:
    """The vertices inside the body in words when more than ``limits.body_penetrations``."""
    if inside <= limits.body_penetrations:
        return None
    return (f"{inside} vertices inside the body (deepest {deepest_mm:.1f} mm; limit "
            f"{limits.body_penetrations})")


def seam_gap_reason(gap_mm: float) -> str | None:
    """The seams' widest gap [mm] in words when it is not below ``limits.seam_gap_mm``."""
    return None if gap_mm < limits.seam_gap_mm else f"seams open by up to {gap_mm:.1f} mm"


def crossing_reasons(edges_in_body: int, faces_in_body: int,
                     self_intersections: int) -> list[str]:
    """Cloth edges and triangles through the body and crossed triangle pairs in words, each
    where above its limit (``limits.body_penetrations``, ``limits.self_intersections``)."""
    out = []
    if edges_in_body > limits.body_penetrations:
        out.append(f"{edges_in_body} cloth edges through the body between their "
                   f"vertices (limit {limits.body_penetrations})")
    if faces_in_body > limits.body_penetrations:
        out.append(f"{faces_in_body} cloth triangles with the body through them, "
                   f"their edges clear (limit {limits.body_penetrations})")
    if self_intersections > limits.self_intersections:
        out.append(f"{self_intersections} crossed triangle pairs (limit "
                   f"{limits.self_intersections})")
    return out


def drape_checks(model: ClothModel, x, *, settings: SolverSettings, converged: bool = False,
                 residual=None) -> DrapeChecks:
    """Checks of simulated positions ``x`` (n3, 3) [m]; see :class:`DrapeChecks`.
    ``residual``: (rms, p99) of the residual force at ``x`` when known; then ``equilibrium``
    also needs them within the ``settings``' thresholds (force rule)."""
    x = array(x, "x", shape=(None, 3), contiguous=True)
    d = _body_distance(model, x)
    if d is not None:
        inside = int((d < -tol.penetration).sum())
        depth = _deepest_mm(d)
        clearance = float(d.min() * 1e3)
    else:
        inside, depth, clearance = 0, 0.0, None
    through, pierced = through_body(model, x)
    gap = seam_gap_mm(model.seam_pairs, x)
    crossing = crossings(model, x)
    rms = p99 = None
    at_rest = bool(converged)
    if residual is not None:
        rms, p99 = float(residual[0]), float(residual[1])
        at_rest = at_rest and rms <= min(settings.residual_rms, tol.rest_rms) \
            and p99 <= min(settings.residual_p99, tol.rest_p99)
    return DrapeChecks(inside_vertices=inside, max_depth_mm=depth, edges_in_body=through,
                       faces_in_body=pierced,
                       min_clearance_mm=clearance,
                       seam_gap_max_mm=gap, self_intersections=crossing,
                       equilibrium=at_rest, residual_rms=rms, residual_p99=p99)
