"""The error raised for a pattern that cannot be used, naming the file and the place at fault."""

from __future__ import annotations


class PatternError(ValueError):
    """A pattern is malformed; the message names the file, panel and edge where known.

    Attributes
    ----------
    file, panel, edge : str or None
        Where the fault is, as far as it is known.
    """

    def __init__(self, message: str, *, file=None, panel=None, edge=None):
        self.file = None if file is None else str(file)
        self.panel = panel
        self.edge = edge
        self.reason = message
        place = ", ".join(([f"panel '{panel}'"] if panel is not None else [])
                          + ([f"edge '{edge}'"] if edge is not None else []))
        super().__init__(": ".join(s for s in (self.file, place, message) if s))

    def located(self, file) -> "PatternError":
        """Return the same error with the file name filled in."""
        return PatternError(self.reason, file=file, panel=self.panel, edge=self.edge)
