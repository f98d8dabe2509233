"""Tolerances and physical constants in one place (SI units: metres, seconds, kilograms)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Tolerances:
    """Geometric tolerances, all in metres unless stated."""

    #: two points closer than this are the same point (outline closure, seam ends) [m]
    merge: float = 1e-6
    #: an edge shorter than this is degenerate [m]
    edge_length: float = 1e-5
    #: the two sides of a seam may differ in length by at most this much [m] ...
    seam_length: float = 2e-3
    #: ... or by this fraction of their mean length, whichever is larger [-]
    seam_length_rel: float = 0.005
    #: triangles whose area is below this are degenerate [m^2]
    area: float = 1e-12


tol = Tolerances()

#: standard gravity [m/s^2]
GRAVITY = 9.80665

#: length of one file unit in metres
UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254}
