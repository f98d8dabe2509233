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
        where = []
        if self.file:
            where.append(self.file)
        if panel is not None:
            where.append(f"panel '{panel}'")
        if edge is not None:
            where.append(f"edge '{edge}'")
        super().__init__((": ".join([", ".join(where), message])) if where else message)

    def located(self, file) -> "PatternError":
        """Return the same error with the file name filled in."""
        return PatternError(self.reason, file=file, panel=self.panel, edge=self.edge)
