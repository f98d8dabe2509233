"""Numba kernels of the garment solver, by topic (SI units: m, N, J):

- :mod:`.energy_terms`: each energy term's value and gradient (membrane, the quadratic of
  bending and linear seam springs, body contact, friction, seam springs, vertex-triangle
  and edge-edge repulsion), the membrane's Hessian,
  and the contact and friction laws (force and stiffness, also as array functions for the
  Newton Hessian);
- :mod:`.collision`: the grid search for the lagged repulsion pairs and the count of
  crossed triangle pairs;
- :mod:`.optimiser`: the L-BFGS vector loops and the stopping rule's step measures;
- :mod:`.sparse_assembly`: the Newton Hessian's CSR data and its trimmed preconditioner
  matrix;
- :mod:`.cholesky`: the sparse Cholesky factor of that matrix in 3 x 3 vertex blocks
  (``sim.block_cholesky``).

Every kernel is serial numba compiled with ``cache=True`` (a fixed summation order makes two
runs bit-identical); those that :mod:`patternfit.sim.threads` runs two at a time (the
Cholesky's, the Hessian product, the membrane, quadratic and contact terms, the membrane's
Hessian, the vertex-triangle and crossing searches) release the GIL. The solver calls them as
``kernels.NAME``; the names are re-exported here.
"""

from __future__ import annotations

# the solver's distance lookups (compiled in body.sdf, where the distance field lives)
from ...body.sdf import sdf_query, smooth_sdf_query
from .cholesky import (block_backward, block_factor_columns, block_forward, block_gather,
                       block_join_lists, block_scatter, block_spread, block_symbolic,
                       block_trim_scatter, block_trim_slots)
from .collision import crossed_pairs, intersecting_pairs, near_edge_pairs, near_pairs
from .energy_terms import (SDF_SLOPE, contact, contact_forces, contact_law, edge_repulsion,
                           friction, friction_law, friction_offset, friction_stiffness,
                           membrane, membrane_hessian, point_contact, point_stiffness,
                           quadratic, seam_springs, self_repulsion, unspared)
from .optimiser import (axpy, dot, lbfgs_back, lbfgs_forward, max_relative_move, max_row_norm,
                        weight_ratios2)
from .sparse_assembly import csr_rows_product, scatter_hessian, scatter_points, trim_to_near

__all__ = ["axpy", "block_backward", "block_factor_columns", "block_forward", "block_gather",
           "block_join_lists", "block_scatter", "block_spread", "block_symbolic",
           "block_trim_scatter", "block_trim_slots", "contact", "contact_forces", "contact_law",
           "csr_rows_product", "crossed_pairs", "dot", "edge_repulsion", "friction",
           "friction_law", "friction_offset", "friction_stiffness", "intersecting_pairs",
           "lbfgs_back", "lbfgs_forward", "max_relative_move", "max_row_norm", "membrane",
           "membrane_hessian", "near_edge_pairs", "near_pairs", "point_contact", "point_stiffness",
           "quadratic", "scatter_hessian", "scatter_points", "sdf_query", "SDF_SLOPE",
           "seam_springs", "self_repulsion", "smooth_sdf_query", "trim_to_near", "unspared",
           "weight_ratios2"]
