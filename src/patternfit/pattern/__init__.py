"""Pattern model and I/O: panels (closed outlines of edges, inner loops, grainline) and seams.

Units are metres inside the library; files state their own units.
"""

from .edges import Edge
from .errors import PatternError
from .io import load_pattern, pattern_from_dict, pattern_to_dict, save_pattern
from .model import InnerLine, Loop, Notch, Panel, Pattern, Placement, Seam, SeamSide
from .validate import check_pattern

__all__ = [
    "Edge", "InnerLine", "Loop", "Notch", "Panel", "Pattern", "PatternError", "Placement", "Seam", "SeamSide",
    "check_pattern", "load_pattern", "pattern_from_dict", "pattern_to_dict", "save_pattern",
]
