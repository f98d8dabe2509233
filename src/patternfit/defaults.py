"""The defaults every front end (CLI, studio, demo, batch) starts from, in one place."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Defaults:
    """Default choices of a drape and a design session.

    Attributes
    ----------
    body : str
        Built-in body name.
    garment : str
        Built-in garment name.
    size : str
        Size of a built-in garment (S, M, L, XL).
    fabric : str
        Fabric preset name.
    triangles : int
        Target triangle count of a garment mesh for a drape [-] (laptop-sized).
    studio_triangles : int
        Target triangle count of a studio session [-]: fewer than a drape's, so that a drag
        previews at the pointer's pace and a re-drape takes about a second.
    mesh_triangles : int
        Target triangle count of ``patternfit mesh`` (a mesh for export, not a drape) [-].
    threshold : float
        ϖ at which a design counts as fitting (METHOD.md section 1) [-].
    tight, loose : float
        Area change beyond which a triangle is tight / loose [-].
    clearance : float
        Gap between body and panels at placement [m].
    max_iterations : int
        Iteration limit of one drape [-].
    time_limit : float
        Time limit of one drape [s].
    correction_rounds : int
        Rounds of the automatic correction [-].
    table2_goal, table2_rounds : str, int
        Goal and rounds of ``patternfit reproduce table2``: "fits" in at most 5, since the
        issue judges the corrected coat by "fits", and at full size the goal "tight" stops
        the coat at "tight" after 3 rounds (docs/fit-correction.md).
    seam_score : float
        Lowest score [0, 1] of a seam suggested for an unsewn pattern
        (:func:`patternfit.pattern.seam_suggest.suggest_seams`).
    """

    body: str = "female_average"
    garment: str = "skirt"
    size: str = "M"
    fabric: str = "cotton_shirting"
    triangles: int = 3000
    studio_triangles: int = 1500
    mesh_triangles: int = 20000
    threshold: float = 0.90
    tight: float = 0.02
    loose: float = 0.02
    clearance: float = 0.03
    max_iterations: int = 5000
    time_limit: float = 300.0
    correction_rounds: int = 3
    table2_goal: str = "fits"
    table2_rounds: int = 5
    seam_score: float = 0.4


DEFAULTS = Defaults()
