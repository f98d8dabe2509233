"""Bodies: built-in human bodies, loading any body mesh, and the body's distance field."""

from .sdf import DistanceField

__all__ = ["DistanceField"]
