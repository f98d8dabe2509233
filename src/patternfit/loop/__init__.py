"""The design loop (METHOD.md section 1): a session holding body, fabric, pattern, mesh,
drape and fit, with edits, undo/redo and atomic save/load."""

from .session import EDIT_OPS, DesignSession, State

__all__ = ["DesignSession", "EDIT_OPS", "State"]
