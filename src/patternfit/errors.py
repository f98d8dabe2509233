"""The one error family for inputs that cannot be used.

Every reader (pattern JSON, GarmentCode, DXF and its side file, body meshes, fabric JSON,
saved garment folders, session folders) raises a subclass of :class:`InputError`; its message
names the file and the place in it. Front ends catch :class:`InputError` once and print the
message without a traceback.
"""

from __future__ import annotations


class InputError(ValueError):
    """An input that cannot be used.

    Attributes
    ----------
    file : str or None
        The file (or folder) at fault, where known.
    place : str or None
        Where in it (a key, a line, a panel and edge), where known.
    reason : str
        What is wrong, without the place.
    """

    def __init__(self, message: str, *, file=None, place: str | None = None):
        self.file = None if file is None else str(file)
        self.place = place
        self.reason = message
        super().__init__(": ".join(s for s in (self.file, place, message) if s))

    def located(self, file) -> "InputError":
        """The same error with the file name filled in (the class is kept)."""
        err = InputError.__new__(type(self))
        err.__dict__.update(self.__dict__)
        InputError.__init__(err, self.reason, file=file, place=self.place)
        return err


class GarmentFileError(InputError):
    """A saved garment folder (``pattern.json``, ``mesh.npz``, ``positions.npy``) that cannot
    be used."""


class FabricError(InputError):
    """An invalid fabric; the message names the file (if any) and the field."""


class SessionError(InputError):
    """A design-session folder that cannot be used."""


def ctrl_c(exc: BaseException) -> bool:
    """Whether ``exc`` is Ctrl-C: a KeyboardInterrupt, or the SystemError ("returned a
    result with an exception set") a compiled numba function raises when the interrupt
    arrives while it runs, the KeyboardInterrupt as its cause, or as the cause of the
    SystemError that is its cause (one kernel dispatched from another: an outside test's
    batch recorded such a Ctrl-C as a failed row)."""
    seen = 0
    while isinstance(exc, SystemError) and seen < 8:
        exc, seen = exc.__cause__ or exc.__context__, seen + 1
    return isinstance(exc, KeyboardInterrupt)
