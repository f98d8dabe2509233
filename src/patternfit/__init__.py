"""patternfit: virtual try-on for fit evaluation and pattern modification.

The design loop, one sub-package per stage: ``pattern`` (model and I/O) -> ``mesh`` ->
``sim`` (placement, drape) -> ``fit`` -> ``edit`` / ``coords`` -> ``mesh``; ``body`` holds the
bodies, ``loop`` the design session, :mod:`patternfit.api` the calls a user scripts with
(re-exported here), ``cli`` and ``studio`` the user interfaces. Units: metres, seconds,
kilograms. See docs/architecture.md.

    import patternfit as pf
    outcome = pf.drape_and_evaluate("skirt", "female_average", "cotton", triangles=1500)
"""

__version__ = "0.1.0"

__all__ = ["BodyMeshError", "Correction", "CorrectionSettings", "DEFAULTS", "Defaults",
           "DesignSession", "FabricError", "FitOutcome", "InputError", "PatternError",
           "__version__", "correct", "correct_design", "design_session", "drafted_too_small",
           "drape_and_evaluate", "evaluate_saved", "fabric_catalogue", "list_bodies",
           "list_fabrics", "list_garments", "mesh_garment", "place_and_evaluate",
           "placed_fitting_ratio", "read_body", "read_fabric", "read_pattern", "save_any_pattern",
           "save_garment"]


def __getattr__(name: str):
    # the API loads the solver and its compiled kernels (0.7 s): only when a name is used,
    # so that `patternfit --help` and the stages imported alone stay quick
    if name in __all__:
        from . import api

        return getattr(api, name)
    raise AttributeError(f"module 'patternfit' has no attribute {name!r}")


def __dir__():
    return sorted(__all__)
