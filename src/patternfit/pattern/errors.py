"""The error raised for a pattern that cannot be used, naming the file and the place at fault."""

from __future__ import annotations

from ..errors import InputError


class PatternError(InputError):
    """A pattern is malformed; the message names the file, panel and edge where known.

    Attributes
    ----------
    file, panel, edge : str or None
        Where the fault is, as far as it is known.
    """

    def __init__(self, message: str, *, file=None, panel=None, edge=None):
        self.panel = panel
        self.edge = edge
        place = ", ".join(([f"panel '{panel}'"] if panel is not None else [])
                          + ([f"edge '{edge}'"] if edge is not None else []))
        super().__init__(message, file=file, place=place or None)

    def located(self, file) -> "PatternError":
        """Return the same error with the file name filled in."""
        return PatternError(self.reason, file=file, panel=self.panel, edge=self.edge)
