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

# every name of patternfit.api (tests/test_architecture.py holds the two lists equal)
__all__ = ["__version__", "BodyMeshError", "Correction", "CorrectionSettings", "DEFAULTS",
           "Defaults", "DesignSession", "FABRIC_RANGES", "FABRIC_TESTS", "Fabric",
           "FabricError", "FitOutcome", "GIRTHS", "InputError", "PatternError",
           "SeamSuggestion", "SolverSettings", "StartWarning", "Verdict", "VerdictRules",
           "accept_seams",
           "add_seam", "body_from_measurements", "check_bulk", "check_drapeable", "check_sewn",
           "correct",
           "correct_design", "describe_fabric", "design_session", "drafted_too_small",
           "drape_and_evaluate", "evaluate_drape", "evaluate_saved", "fabric_catalogue",
           "fabric_names", "fresh_drape",
           "fabric_test", "judge_state", "list_bodies", "list_body_sets", "list_engines",
           "list_fabrics", "list_garments", "list_sizes", "mesh_garment", "place_and_evaluate",
           "placed_fitting_ratio", "read_bodies", "read_body", "read_fabric",
           "read_fabric_with_notes", "read_pattern", "remove_seam", "save_any_pattern",
           "save_garment", "seam_table", "set_seam_ease", "suggest_seams", "verdict_rules",
           "with_distance_field", "write_fabric_test_picture", "write_pattern"]


def __getattr__(name: str):
    # the API loads the solver and its compiled kernels (0.7 s): only when a name is used,
    # so that `patternfit --help` and the stages imported alone stay quick
    if name in __all__:
        from . import api

        return getattr(api, name)
    raise AttributeError(f"module 'patternfit' has no attribute {name!r}")


def __dir__():
    return sorted(__all__)
