"""Panel meshing: constrained quality Delaunay triangulation of every panel, seams matched."""

from .garment import GarmentMesh
from .quality import min_angle, signed_areas, triangle_angles
from .triangulate import mesh_pattern

__all__ = ["GarmentMesh", "mesh_pattern", "min_angle", "signed_areas", "triangle_angles"]
