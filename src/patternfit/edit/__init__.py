"""Pattern editing tools and the smooth mesh update that follows them (paper Sec. 5, 6.4).

Tools are pure functions ``Pattern -> Pattern`` that refuse invalid results with
``PatternError``; :func:`move_corner` (one panel's corner, unchecked) and
:func:`close_seams` (equal seam sides by the smallest corner moves) are their building
blocks; :func:`add_seam`, :func:`remove_seam` and :func:`set_seam_ease` edit the seams;
:func:`update_mesh` carries a panel mesh over to the edited pattern.
"""

from .darts import insert_dart, move_dart, resize_dart
from .seams import add_seam, remove_seam, seam_side, set_seam_ease
from .tools import close_seams, edit_curve, grade, lengthen, move_corner, move_edge, move_point
from .update import CoordinateCache, UpdateReport, panel_coordinates, update_mesh

__all__ = ["CoordinateCache", "UpdateReport", "add_seam", "close_seams", "edit_curve", "grade",
           "insert_dart", "lengthen", "move_corner", "move_dart", "move_edge", "move_point",
           "panel_coordinates", "remove_seam", "resize_dart", "seam_side", "set_seam_ease",
           "update_mesh"]
