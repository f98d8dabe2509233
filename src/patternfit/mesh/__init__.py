"""Panel meshing: constrained quality Delaunay triangulation of every panel, seams matched."""

from .garment import GarmentMesh

__all__ = ["GarmentMesh"]
