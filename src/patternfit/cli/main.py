"""Entry point of the ``patternfit`` command: imports every command module onto ``app``."""

from __future__ import annotations

from . import commands  # noqa: F401  (registers mesh, fit, patterns, demo)
from . import convert  # noqa: F401
from . import bodies  # noqa: F401
from . import edit  # noqa: F401
from . import drape  # noqa: F401
from . import studio  # noqa: F401
from . import loop  # noqa: F401
from . import fabric  # noqa: F401
from . import seams  # noqa: F401
from .app import app

__all__ = ["app"]

if __name__ == "__main__":
    app()
