"""The garment's 3D state as GLB and OBJ with per-vertex fit colours (trimesh)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import trimesh

from ..arguments import array
from ..files import atomic_write_bytes


def colored_mesh(positions, triangles, vertex_rgb) -> trimesh.Trimesh:
    """A trimesh of the garment with vertex colours.

    Parameters
    ----------
    positions : (n, 3) float
        Vertex positions [m].
    triangles : (m, 3) int
    vertex_rgb : (n, 3) float
        Colours in [0, 1].

    Raises ``ValueError`` for non-finite positions or colours, or triangles indexing beyond
    the positions.
    """
    # a mesh file would carry these on silently as "nan" text or as broken faces
    x = array(positions, "positions", shape=(None, 3), finite=True)
    t = np.asanyarray(triangles)
    if t.ndim != 2 or t.shape[1] != 3 or (t.size and (t.min() < 0 or t.max() >= len(x))):
        raise ValueError("triangles: expected (m, 3) indices of the positions")
    rgb = array(vertex_rgb, "vertex_rgb", shape=(len(x), 3), finite=True)
    rgba = np.concatenate([np.clip(rgb * 255, 0, 255), np.full((len(x), 1), 255)],
                          axis=1).astype(np.uint8)
    return trimesh.Trimesh(vertices=x, faces=t, vertex_colors=rgba, process=False)


def export_garment(positions, triangles, vertex_rgb, path, *, status: dict | None = None
                   ) -> Path:
    """Write the coloured garment to ``path``; the format follows the ending (.glb, .obj, .ply).

    ``status`` (JSON values: whether the drape passed its checks, its verdict, ϖ, why it
    failed) goes with the garment: the GLB mesh's ``extras`` under ``patternfit``, the
    OBJ's first comment line. A file parted from its report still says whether it is a fit."""
    path = Path(path)
    kind = path.suffix.lower().lstrip(".")
    if kind not in ("glb", "obj", "ply"):
        raise ValueError(f"path: expected a .glb, .obj or .ply file, got {path.name}")
    mesh = colored_mesh(positions, triangles, vertex_rgb)
    options: dict = {}
    if status is not None:
        mesh.metadata["patternfit"] = status
        if kind == "obj":
            options["header"] = "patternfit " + json.dumps(status, ensure_ascii=False)
    if kind == "obj":
        options["include_color"] = True
    data = mesh.export(file_type=kind, **options)
    atomic_write_bytes(path, data if isinstance(data, bytes) else data.encode("utf-8"))
    return path
