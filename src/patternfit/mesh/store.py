"""A saved garment: a folder holding ``pattern.json``, ``mesh.npz`` and, once placed or
draped, ``positions.npy`` (the 3D state, (n, 3) float [m])."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from ..files import atomic_write_bytes
from ..pattern.errors import PatternError
from ..pattern.io import load_pattern, save_pattern
from ..pattern.model import Pattern
from .garment import GarmentMesh

PATTERN, MESH, POSITIONS = "pattern.json", "mesh.npz", "positions.npy"


def save_garment(folder, pattern: Pattern, mesh: GarmentMesh, positions=None) -> Path:
    """Write the pattern, its mesh and optionally a 3D state (n, 3) [m] into ``folder``."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    save_pattern(pattern, folder / PATTERN)
    mesh.save(folder / MESH)
    if positions is not None:
        x = np.asanyarray(positions, dtype=np.float64)
        if x.shape != (mesh.n_vertices, 3):
            raise ValueError(f"positions: expected shape ({mesh.n_vertices}, 3), got {x.shape}")
        buf = io.BytesIO()
        np.save(buf, x)
        atomic_write_bytes(folder / POSITIONS, buf.getvalue())
    return folder


def load_garment(folder) -> tuple[Pattern, GarmentMesh, np.ndarray | None]:
    """Read a folder written by :func:`save_garment`: (pattern, mesh, positions or None)."""
    folder = Path(folder)
    if not (folder / MESH).is_file():
        raise PatternError(f"no {MESH} here: not a saved garment folder", file=folder)
    pattern = load_pattern(folder / PATTERN)
    mesh = GarmentMesh.load(folder / MESH)
    positions = None
    if (folder / POSITIONS).is_file():
        positions = np.load(folder / POSITIONS, allow_pickle=False)
        if positions.shape != (mesh.n_vertices, 3):
            raise PatternError(f"{POSITIONS} has shape {positions.shape}, the mesh has "
                               f"{mesh.n_vertices} vertices", file=folder / POSITIONS)
    if tuple(p.name for p in pattern.panels) != mesh.panel_names:
        raise PatternError(f"{PATTERN} and {MESH} do not belong together (panels differ)",
                           file=folder)
    return pattern, mesh, positions
