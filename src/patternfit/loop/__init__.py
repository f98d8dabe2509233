"""The design loop (METHOD.md section 1): a session holding body, fabric, pattern, mesh,
drape and fit, with edits, undo/redo and atomic save/load; where to modify (regions) and
the automatic fit correction."""

from .correct import CorrectionSettings, correct
from .regions import Region, find_regions
from .session import EDIT_OPS, DesignSession, State

__all__ = ["CorrectionSettings", "DesignSession", "EDIT_OPS", "Region", "State", "correct",
           "find_regions"]
