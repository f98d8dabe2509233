"""Whether a pattern read from another tool's file has a garment's size: a unit misread
(millimetres taken for centimetres, CLO's ``UNITS: METRIC`` over centimetres) makes every
piece ten times too large or small, which nothing else in the file betrays. Lengths in m."""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from ..constants import UNITS
from .errors import PatternError

#: sizes across (largest side of the bounding box) a garment piece plausibly has; outside
#: them the file's units are probably misread and the reader warns [m]
PLAUSIBLE = (0.01, 3.0)
#: a piece larger across than this is no garment piece at all [m] (twice the plausible
#: largest): draping is refused (a DXF read in inches over millimetres, 16 m pieces, was
#: draped for more than 400 s before it failed)
ABSURD = 2 * PLAUSIBLE[1]
#: the least size across the largest piece of a garment plausibly has [m]: below it the whole
#: pattern is probably read in too small a unit (CLO writes ``UNITS: METRIC`` over centimetres)
PLAUSIBLE_LARGEST = 0.1

#: the units as a message names them ("read in in" read as a typo)
_UNIT_NAMES = {0.001: "millimetres", 0.01: "centimetres", 0.0254: "inches", 0.3048: "feet",
               1.0: "metres"}


def across(panel) -> float:
    """A panel's size across [m]: the largest side of its outline's bounding box."""
    poly = panel.outline.polygon(8)
    return float(np.max(poly.max(axis=0) - poly.min(axis=0)))


def size_warnings(panels, scale: float, unit_says: str, *,
                  hint: Callable[[str], str]) -> list[str]:
    """A warning for every panel whose size is implausible for a garment piece in the unit
    read (``scale`` metres per file unit, ``unit_says`` what said so), naming the units that
    would make it plausible; and one when every panel is plausible but even the largest is
    smaller than :data:`PLAUSIBLE_LARGEST`. ``hint(unit)`` says how to read the file in the
    likeliest of them (a reader's option, a file's field)."""
    out = []
    lo, hi = PLAUSIBLE
    unit = _UNIT_NAMES.get(scale, f"{scale:g} m")
    sizes = []
    for panel in panels:
        size = across(panel)
        sizes.append(size)
        if lo <= size <= hi:
            continue
        fits = [u for u, m in UNITS.items() if lo <= size / scale * m <= hi]
        out.append(f"panel '{panel.name}' is {size:.3g} m across, read in {unit} ({unit_says}):"
                   f" implausible for a garment piece (expected {lo:g} to {hi:g} m); "
                   + _as_other_units(size / scale, fits, hint))
    largest = max(sizes, default=PLAUSIBLE_LARGEST)
    if not out and largest < PLAUSIBLE_LARGEST:
        fits = [u for u, m in UNITS.items()
                if PLAUSIBLE_LARGEST <= largest / scale * m <= hi]
        out.append(f"the largest piece is {largest * 100:.3g} cm across, read in {unit} "
                   f"({unit_says}): small for a garment (at least {PLAUSIBLE_LARGEST * 100:g}"
                   " cm expected); " + _as_other_units(largest / scale, fits, hint))
    return out


def is_size_warning(text) -> bool:
    """Whether ``text`` is one of :func:`size_warnings`' (which depend on the units a file
    was read in: a pattern written again in other units keeps them, stale)."""
    return isinstance(text, str) and ", read in " in text and (
        (text.startswith("panel '") and "implausible for a garment piece" in text)
        or (text.startswith("the largest piece is ") and "small for a garment" in text))


def check_drapeable_size(pattern, *, source=None) -> None:
    """Refuse (:class:`~patternfit.pattern.errors.PatternError` naming ``source`` and the
    panel) a pattern with a piece larger across than :data:`ABSURD`: its units were
    misread, and no drape of it is a garment's."""
    for panel in pattern.panels:
        size = across(panel)
        if size > ABSURD:
            raise PatternError(f"{size:.3g} m across: no garment piece is larger than "
                               f"{ABSURD:g} m (were the file's units misread? the reader's "
                               "warning names the units that fit); not draped",
                               file=source, panel=panel.name)


def _as_other_units(drawn: float, fits: list[str], hint: Callable[[str], str]) -> str:
    """What a piece ``drawn`` file units across would measure in each unit of ``fits``,
    and how to read the file so; or to check the units when none fits."""
    if not fits:
        return "check the file's units"
    sizes = ", ".join(f"as {u} {drawn * UNITS[u]:.3g} m" for u in fits)
    # the reading nearest a typical piece (half a metre) is the one to try first
    best = min(fits, key=lambda u: abs(math.log(drawn * UNITS[u] / 0.5)))
    return f"{sizes} ({hint(best)})"
