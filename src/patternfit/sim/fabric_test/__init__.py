"""A virtual fabric-testing kit: the three bench tests a fabric is measured with, run on the
static solver (``GarmentSolver``) and compared with what the fabric's constants predict.

- :func:`strip_test`: a strip hanging from its clamped top edge stretches under its own weight
  by ``rho g L^2 / (2 k)``.
- :func:`cantilever_test`: Peirce's cantilever (ASTM D1388): the overhang at which the tip has
  bent down 41.5 deg is twice the bending length ``c = (B / (rho g))^(1/3)``; run at several
  mesh sizes (with bending friction, 2HB, against the exact strip under the same law).
- :func:`cusick_test`: the drape test (BS 5058 / ISO 9073-9): a circular specimen clamped on a
  smaller disc, its drape coefficient and its number of nodes (folds), from several slightly
  perturbed flat starts.

Units: metres, kilograms, seconds, newtons; ``y`` is up. Every function returns a plain result
dataclass whose ``to_dict()`` is JSON-ready (no NaN: a value that could not be measured is
None). See docs/fabrics.md, "Testing a fabric".

One module per test (``strip``, ``cantilever``, ``cusick``) over the shared ``common``;
this package gives their public names.
"""

from .cantilever import (CANTILEVER_TRIANGLES, ELASTICA_ANGLES, PEIRCE_ANGLE, CantileverMesh,
                         CantileverResult, CantileverRun, cantilever_test, elastica_ratio,
                         elastica_tip_angle, expected_reading, friction_tip_angle,
                         peirce_length, write_cantilever_picture)
from .common import AT_REST, Progress, SolveInfo, kit_settings, residual_of, settings_from_pairs
from .cusick import (CUSICK_DISC, CUSICK_DISC_OUTLINE, CUSICK_MESH_TOLERANCE, CUSICK_SPECIMEN,
                     CusickResult, CusickRun, count_nodes, cusick_test, cusick_triangles,
                     shadow_area, write_cusick_picture)
from .strip import StripResult, strip_test

__all__ = ["AT_REST", "CANTILEVER_TRIANGLES", "CUSICK_DISC", "CUSICK_DISC_OUTLINE",
           "CUSICK_MESH_TOLERANCE", "CUSICK_SPECIMEN", "ELASTICA_ANGLES", "PEIRCE_ANGLE",
           "CantileverMesh", "CantileverResult", "CantileverRun", "CusickResult", "CusickRun",
           "Progress", "SolveInfo", "StripResult", "cantilever_test", "count_nodes",
           "cusick_test", "cusick_triangles", "elastica_ratio", "elastica_tip_angle",
           "expected_reading", "friction_tip_angle", "kit_settings", "peirce_length",
           "residual_of", "settings_from_pairs", "shadow_area", "strip_test",
           "write_cantilever_picture", "write_cusick_picture"]
