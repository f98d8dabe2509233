"""patternfit: virtual try-on for fit evaluation and pattern modification.

The design loop, one sub-package per stage: ``pattern`` (model and I/O) -> ``mesh`` ->
``sim`` (placement, drape) -> ``fit`` -> ``edit`` / ``coords`` -> ``mesh``; ``body`` holds the
bodies, ``loop`` the design session, ``cli`` and ``studio`` the user interfaces.
Units: metres, seconds, kilograms.
"""

__version__ = "0.1.0"
