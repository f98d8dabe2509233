"""Panel meshing: constrained quality Delaunay triangulation of every panel, seams matched."""

from .garment import GarmentMesh
from .triangulate import mesh_pattern

__all__ = ["GarmentMesh", "mesh_pattern"]
