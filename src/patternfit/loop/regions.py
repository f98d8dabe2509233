"""Where to modify (paper Sec. 8: "pinpoint the location where it needs to be modified").

From the per-triangle fit, the connected regions of each panel that are too tight or too
loose, named in a pattern maker's words: the panel, the boundary edge (and its seam) nearest
to the region, the span along that edge in centimetres, the area, and the mean stretch along
the grainline and across it. Lengths in metres inside, centimetres in the descriptions.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from ..fit.metrics import LOOSE, TIGHT, FitResult
from ..geometry import face_adjacency
from ..mesh.garment import GarmentMesh


#: a region covering at least this share of its panel's flat area is said to cover the
#: panel, not to lie near an edge [-]
WHOLE_PANEL = 0.8


@dataclass(frozen=True)
class Region:
    """One connected tight or loose region of a panel.

    Attributes
    ----------
    panel : str
    kind : str
        ``"tight"`` or ``"loose"``.
    edge : str
        The panel's boundary edge nearest to most of the region.
    seam : str or None
        The seam that edge belongs to (None for a free edge such as a hem).
    span_cm : (float, float)
        Where the region lies along ``edge``, from its start [cm].
    distance_cm : float
        Mean distance of the region from ``edge`` [cm].
    area_cm2 : float
        Flat area of the region [cm^2].
    area_change : float
        Area-weighted mean relative area change S3/S2 − 1 [-] (> 0 stretched).
    warp, weft : float
        Area-weighted mean stretch ratio along the grainline and across it [-].
    triangles : (k,) int
        The region's triangles.
    panel_share : float
        The region's share of its panel's flat area [-].
    """

    panel: str
    kind: str
    edge: str
    seam: str | None
    span_cm: tuple
    distance_cm: float
    area_cm2: float
    area_change: float
    warp: float
    weft: float
    triangles: np.ndarray
    panel_share: float = 0.0

    def describe(self) -> str:
        """The region in words, e.g. "front, near side_l (seam side_l), 4–21 cm along it:
        18% too small (stretched 1.15 across the grain, 1.02 along it), 310 cm²"; one that
        covers :data:`WHOLE_PANEL` of its panel is said to ("front, 97% of the panel, its
        nearest seam side_r: ..."): "near side_r, 6 cm in" was said of a whole panel."""
        where = f"{self.edge} (seam {self.seam})" if self.seam else self.edge
        amount = abs(self.area_change) * 100
        what = "too small" if self.kind == "tight" else "too large"
        a, b = (f"{s:.0f}" for s in self.span_cm)
        span = f"{a}–{b} cm" if a != b else f"at {a} cm"  # not "22–22 cm": one place
        if self.panel_share >= WHOLE_PANEL:
            place = (f"{self.panel}, {self.panel_share * 100:.0f}% of the panel, its nearest "
                     f"{'seam ' + self.seam if self.seam else 'edge ' + self.edge}")
        else:
            place = (f"{self.panel}, near {where}, {span} along it, "
                     f"{self.distance_cm:.0f} cm in")
        return (f"{place}: {amount:.0f}% {what} (stretch "
                f"{self.weft:.2f} across the grain, {self.warp:.2f} along it), "
                f"{self.area_cm2:.0f} cm²")

    def to_dict(self) -> dict:
        """The region for ``report.json`` (its triangles as a count)."""
        d = asdict(self)
        d["triangles"] = int(len(self.triangles))
        d["span_cm"] = [float(s) for s in self.span_cm]
        d["description"] = self.describe()
        return d


def triangle_adjacency(triangles) -> tuple[np.ndarray, np.ndarray]:
    """Pairs of triangles sharing an edge (:func:`patternfit.geometry.face_adjacency`): two
    (k,) int arrays."""
    pairs = face_adjacency(triangles)
    return pairs[:, 0], pairs[:, 1]


def find_regions(mesh: GarmentMesh, fit: FitResult, *, min_area: float = 2e-3,
                 seam_of: dict | None = None) -> list[Region]:
    """Connected tight and loose regions of every panel, largest misfit first.

    Parameters
    ----------
    mesh : GarmentMesh
        The flat garment the fit belongs to.
    fit : FitResult
        Its per-triangle fit (``fit_class``, ``area_change``, ``warp``, ``weft``).
    min_area : float
        Regions smaller than this flat area are left out [m^2] (default 20 cm²).
    seam_of : dict, optional
        ``{(panel, edge): seam name}``; by default taken from the mesh's seam pairs.

    Returns
    -------
    list of Region
        Ordered by misfit (|area change| × area), largest first.
    """
    if len(fit.area_change) != mesh.n_triangles:
        raise ValueError("fit: does not belong to this mesh (triangle counts differ)")
    seam_of = _seam_names(mesh) if seam_of is None else seam_of
    a, b = triangle_adjacency(mesh.triangles)
    cls = fit.fit_class
    keep = (cls[a] == cls[b]) & (cls[a] != 0) & \
        (mesh.triangle_panel[a] == mesh.triangle_panel[b])
    m = mesh.n_triangles
    graph = coo_matrix((np.ones(int(keep.sum())), (a[keep], b[keep])), shape=(m, m))
    _, label = connected_components(graph, directed=False)
    centroid = mesh.vertices[mesh.triangles].mean(axis=1)
    regions = []
    for lab in np.unique(label[cls != 0]):
        tris = np.flatnonzero(label == lab)
        area = fit.area_2d[tris]
        if area.sum() < min_area:
            continue
        regions.append(_describe_region(mesh, fit, tris, centroid[tris], area, seam_of))
    regions.sort(key=lambda r: -abs(r.area_change) * r.area_cm2)
    return regions


def _seam_names(mesh: GarmentMesh) -> dict:
    """``{(panel, edge): seam}`` from the seam pairs: the seam most of an edge's sewn
    vertices belong to (a corner vertex is counted on the edge starting there)."""
    edge_of = np.full(mesh.n_vertices, -1)
    edge_of[mesh.boundary_vertices] = mesh.boundary_edge
    e = edge_of[mesh.seam_pairs.ravel()]
    s = np.repeat(mesh.seam_index, 2)
    ok = e >= 0
    counts = np.zeros((len(mesh.edge_names), len(mesh.seam_names)), dtype=np.int64)
    np.add.at(counts, (e[ok], s[ok]), 1)
    return {mesh.edge_names[k]: mesh.seam_names[int(np.argmax(counts[k]))]
            for k in np.flatnonzero(counts.sum(axis=1) > 1)}


def _describe_region(mesh, fit, tris, centroid, area, seam_of) -> Region:
    panel = int(mesh.triangle_panel[tris[0]])
    on_panel = np.flatnonzero(mesh.vertex_panel[mesh.boundary_vertices] == panel)
    bp = mesh.vertices[mesh.boundary_vertices[on_panel]]
    dist, k = cKDTree(bp).query(centroid)
    nearest = on_panel[k]
    edges = mesh.boundary_edge[nearest]
    weight = np.bincount(edges, area, minlength=len(mesh.edge_names))
    edge = int(np.argmax(weight))
    # span along that edge: the edge's points nearest to the region's triangles
    mine = nearest[edges == edge]
    pname, ename = mesh.edge_names[edge]
    pts = mesh.vertices[mesh.edge_vertices(pname, ename)[0]]
    length = float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())
    s = mesh.boundary_param[mine] * length * 100
    w = area / area.sum()
    return Region(
        panel=mesh.panel_names[panel], kind="tight" if fit.fit_class[tris[0]] == TIGHT
        else "loose" if fit.fit_class[tris[0]] == LOOSE else "fit",
        edge=ename, seam=seam_of.get((pname, ename)),
        span_cm=(float(s.min()), float(s.max())), distance_cm=float(dist @ w * 100),
        area_cm2=float(area.sum() * 1e4), area_change=float(fit.area_change[tris] @ w),
        warp=float(fit.warp[tris] @ w), weft=float(fit.weft[tris] @ w), triangles=tris,
        panel_share=float(area.sum() / fit.area_2d[mesh.triangle_panel == panel].sum()))
