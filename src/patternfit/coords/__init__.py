"""Generalized barycentric coordinates for the mesh update (paper Sec. 5, METHOD.md 4).

``mean_value_coordinates`` (enhanced MVC over nested loops) and ``max_entropy_coordinates``
(MEC with uniform, Gaussian, Hormann–Sukumar edge and angle-bisector priors). Both return a
``(q, n)`` weight matrix, columns in the caller's node order.
"""

from .mec import MECInfo, max_entropy_coordinates
from .mvc import mean_value_coordinates

__all__ = ["MECInfo", "max_entropy_coordinates", "mean_value_coordinates"]
