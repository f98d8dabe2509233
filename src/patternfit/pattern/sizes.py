"""Body measurements that size the built-in patterns, and the size charts S–XL.

All lengths in metres. The charts follow the usual European sizing (EN 13402 body dimensions)
for women and men; a measured body (``patternfit.body``) gives the same fields.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields


@dataclass(frozen=True)
class Measurements:
    """Body measurements [m] that draft the built-in patterns.

    ``bust`` is the bust (women) or chest (men) girth; ``back_length`` runs from the neck
    base at the back to the waist; ``shoulder`` is the width across both shoulder points;
    ``arm_length`` from the shoulder point to the wrist; ``rise`` from the waist to the crotch.
    """

    bust: float
    waist: float
    hip: float
    height: float
    back_length: float
    shoulder: float
    neck: float
    arm_length: float
    bicep: float
    wrist: float
    inseam: float
    rise: float
    thigh: float

    def __post_init__(self):
        for f in fields(self):
            v = getattr(self, f.name)
            if not (isinstance(v, (int, float)) and 0 < v < 3):
                raise ValueError(f"{f.name}: expected a length in metres in (0, 3), got {v!r}")

    def as_dict(self) -> dict[str, float]:
        return asdict(self)


def _m(*cm) -> Measurements:
    return Measurements(*(c / 100 for c in cm))


#: size charts: bust, waist, hip, height, back length, shoulder, neck, arm, bicep, wrist,
#: inseam, rise, thigh [cm]
SIZES: dict[str, dict[str, Measurements]] = {
    "female": {
        "S": _m(84, 68, 92, 164, 40, 38, 35, 58, 27, 15, 76, 25, 54),
        "M": _m(92, 76, 100, 168, 41, 39, 36, 59, 29, 15.5, 78, 26, 58),
        "L": _m(100, 84, 108, 170, 41.5, 40, 37, 60, 31, 16, 79, 27, 62),
        "XL": _m(108, 94, 116, 172, 42, 41.5, 38.5, 60.5, 34, 17, 80, 28, 66),
    },
    "male": {
        "S": _m(92, 80, 94, 174, 44, 44, 38, 62, 30, 17, 80, 26, 54),
        "M": _m(100, 88, 100, 178, 45, 46, 40, 63, 32, 17.5, 82, 27, 57),
        "L": _m(108, 96, 106, 182, 46, 48, 42, 64, 34, 18, 83, 28, 60),
        "XL": _m(116, 106, 112, 184, 46.5, 50, 44, 65, 37, 18.5, 84, 29, 63),
    },
}

SIZE_NAMES = ("S", "M", "L", "XL")


def size_chart(gender: str, size: str) -> Measurements:
    """Measurements of ``size`` (S, M, L, XL) for ``gender`` ("female" or "male")."""
    if gender not in SIZES:
        raise ValueError(f"gender: expected 'female' or 'male', got {gender!r}")
    if size.upper() not in SIZES[gender]:
        raise ValueError(f"size: expected one of {', '.join(SIZE_NAMES)}, got {size!r}")
    return SIZES[gender][size.upper()]
