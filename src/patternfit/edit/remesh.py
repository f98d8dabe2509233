"""Re-triangulate single panels of a garment mesh, keeping their boundary vertices.

Used when an edit leaves a panel's triangles too thin: the boundary vertices stay (same
count, same seam pairing), the interior is triangulated anew, the other panels keep their
vertices and indices shift down. Lengths in metres.
"""

from __future__ import annotations

import numpy as np
import triangle as tr

from ..geometry import counter_clockwise, triangle_areas
from ..mesh import GarmentMesh, inside_point

#: quality bound of the re-triangulation [degrees] (the mesher's default)
REMESH_ANGLE = 25.0


def _triangulate(mesh: GarmentMesh, panel: int):
    """New interior points (k, 2) and triangles over [boundary ids, new ids] of one panel."""
    loops = mesh.loops(panel)
    ids = np.concatenate(loops)
    segs, start = [], 0
    for lp in loops:
        idx = start + np.arange(len(lp))
        segs.append(np.stack([idx, np.roll(idx, -1)], axis=1))
        start += len(lp)
    data = {"vertices": mesh.vertices[ids], "segments": np.concatenate(segs)}
    if len(loops) > 1:
        data["holes"] = np.array([inside_point(mesh.vertices[lp]) for lp in loops[1:]])
    area = triangle_areas(mesh.vertices, mesh.triangles[mesh.triangle_panel == panel]).mean()
    out = tr.triangulate(data, f"pq{REMESH_ANGLE:.6f}a{1.5 * area:.12f}YQ")
    v = out["vertices"]
    return ids, v[len(ids):], counter_clockwise(v, out["triangles"].astype(np.int64))


def remesh_panels(mesh: GarmentMesh, panels) -> GarmentMesh:
    """``mesh`` with panels number ``panels`` re-triangulated inside their boundaries.

    Boundary vertices (and so ``boundary_*`` and ``seam_pairs``) keep their meaning; the
    re-meshed panels' interior vertices are replaced by new ones appended at the end.
    """
    verts, tris, tpan = [mesh.vertices], [], []
    vpan = [mesh.vertex_panel]
    drop = np.zeros(mesh.n_vertices, dtype=bool)
    keep_tri = ~np.isin(mesh.triangle_panel, list(panels))
    n = mesh.n_vertices
    for pi in panels:
        ids, new_pts, t = _triangulate(mesh, pi)
        interior = np.zeros(mesh.n_vertices, dtype=bool)
        interior[mesh.panel_vertices(pi)] = True
        interior[ids] = False
        drop |= interior
        local = np.concatenate([ids, n + np.arange(len(new_pts))])
        tris.append(local[t])
        tpan.append(np.full(len(t), pi))
        verts.append(new_pts)
        vpan.append(np.full(len(new_pts), pi))
        n += len(new_pts)
    V = np.concatenate(verts)
    keep = np.concatenate([~drop, np.ones(len(V) - mesh.n_vertices, dtype=bool)])
    remap = np.cumsum(keep) - 1
    T = np.concatenate([mesh.triangles[keep_tri], *tris])
    fields = {k: getattr(mesh, k) for k in mesh.__dataclass_fields__}
    fields.update(vertices=V[keep], triangles=remap[T],
                  triangle_panel=np.concatenate([mesh.triangle_panel[keep_tri], *tpan]),
                  vertex_panel=np.concatenate(vpan)[keep],
                  boundary_vertices=remap[mesh.boundary_vertices],
                  seam_pairs=remap[mesh.seam_pairs])
    return GarmentMesh(**fields)
