"""Panel meshing: constrained quality Delaunay triangulation of every panel, seams matched."""

from ..geometry import signed_areas
from .garment import GarmentMesh
from .quality import min_angle, triangle_angles
from .triangulate import inside_point, mesh_pattern

__all__ = ["GarmentMesh", "inside_point", "mesh_pattern", "min_angle", "signed_areas",
           "triangle_angles"]
