"""Bodies: built-in human bodies, loading any body mesh, and the body's distance field."""

from .builtin import ALIASES, list_bodies, load_body
from .mesh_io import BodyMeshError, load_body_mesh, save_body_mesh
from .measure import LandmarkError, measure
from .model import Body
from .sdf import DistanceField

__all__ = ["ALIASES", "Body", "BodyMeshError", "DistanceField", "LandmarkError", "list_bodies",
           "load_body", "load_body_mesh", "measure", "save_body_mesh"]
