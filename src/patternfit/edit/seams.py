"""Seam editing tools: sew two edge spans together, unpick a seam, state a seam's ease.

Pure functions ``Pattern -> Pattern`` like the other tools (:mod:`patternfit.edit.tools`);
refusals are :class:`PatternError` naming the seam, the panel and the edge. A side is a
:class:`SeamSide` or a dict ``{"panel", "edge", "start", "end"}`` (``start``/``end``:
arc-length fractions of the edge, default 0 and 1), as a session records it
(``loop.session.EDIT_OPS``). Lengths in metres.
"""

from __future__ import annotations

from dataclasses import replace

from ..arguments import number
from ..constants import limits, tol
from ..pattern import Pattern, PatternError, Seam, SeamSide
from ..pattern.validate import check_seams, measured_ease, seam_slack
from .tools import pattern_edit

__all__ = ["add_seam", "remove_seam", "seam_side", "set_seam_ease"]


def seam_side(side, name: str = "side") -> SeamSide:
    """``side`` (a :class:`SeamSide` or a dict ``{"panel", "edge", "start", "end"}``) as a
    :class:`SeamSide`; a :class:`PatternError` naming the argument ``name`` otherwise."""
    if isinstance(side, SeamSide):
        side = {"panel": side.panel, "edge": side.edge, "start": side.start, "end": side.end}
    if not isinstance(side, dict):
        raise PatternError(f"{name}: expected a seam side {{'panel', 'edge', 'start', 'end'}}"
                           f", got {type(side).__name__}")
    unknown = sorted(set(side) - {"panel", "edge", "start", "end"})
    if unknown:
        raise PatternError(f"{name}: unknown key(s) {unknown} (a side has panel, edge, "
                           "start, end)")
    panel, edge = side.get("panel"), side.get("edge")
    for key, value in (("panel", panel), ("edge", edge)):
        if not isinstance(value, str) or not value:
            raise PatternError(f"{name}: '{key}' must be a non-empty string, got {value!r}")
    try:
        start = number(side.get("start", 0.0), f"{name}.start", low=0.0, high=1.0)
        end = number(side.get("end", 1.0), f"{name}.end", low=0.0, high=1.0)
    except ValueError as err:
        raise PatternError(str(err), panel=panel, edge=edge) from None
    if not start < end:
        raise PatternError(f"{name}: start {start:g} must lie before end {end:g}",
                           panel=panel, edge=edge)
    return SeamSide(panel, edge, start, end)


def _seam(pattern: Pattern, name: str) -> Seam:
    for s in pattern.seams:
        if s.name == name:
            return s
    raise PatternError(f"no seam '{name}' (seams: "
                       f"{', '.join(s.name for s in pattern.seams) or 'none'})")


def _overlaps(a: SeamSide, b: SeamSide) -> bool:
    return (a.panel, a.edge) == (b.panel, b.edge) and \
        min(a.end, b.end) - max(a.start, b.start) > tol.seam_range_overlap


@pattern_edit
def add_seam(pattern: Pattern, a, b, *, name: str | None = None, ease: float | None = None,
             reverse: bool = True) -> Pattern:
    """``pattern`` with a new seam sewing side ``a`` to side ``b``.

    a, b : SeamSide or dict
        The two spans (``panel``, ``edge``, ``start``/``end`` arc-length fractions).
    name : str, optional
        Unique seam name; default ``"<a panel>.<a edge>+<b panel>.<b edge>"`` (``_2``,
        ``_3``... appended when taken).
    ease : float, optional
        Longer / shorter - 1 the seam may gather [-]; None measures it from the two sides'
        lengths (:func:`~patternfit.pattern.validate.measured_ease`: 0 for sides equal
        within tolerance). Sides whose lengths need more than ``limits.seam_ease`` are
        refused, naming the seam and both lengths.
    reverse : bool
        True (two panels laid right side up): the start of ``a`` is sewn to the end of ``b``.

    Refused: a missing panel or edge, a span already sewn by another seam (or ``a`` and
    ``b`` overlapping each other), a name already used, an ease outside [0,
    ``limits.seam_ease``] or one the sides' lengths exceed.
    """
    a, b = seam_side(a, "a"), seam_side(b, "b")
    if not isinstance(reverse, bool):
        raise PatternError(f"reverse: expected true or false, got {reverse!r}")
    for side in (a, b):
        try:
            pattern.panel(side.panel).edge(side.edge)
        except KeyError as err:
            raise PatternError(str(err.args[0]), panel=side.panel, edge=side.edge) from None
    if name is None:
        base, taken = f"{a.panel}.{a.edge}+{b.panel}.{b.edge}", {s.name for s in pattern.seams}
        name = next(n for n in (base if k == 1 else f"{base}_{k}" for k in range(1, 10 ** 6))
                    if n not in taken)
    if not isinstance(name, str) or not name:
        raise PatternError(f"name: a seam name must be a non-empty string, got {name!r}")
    if any(s.name == name for s in pattern.seams):
        raise PatternError(f"seam '{name}' already exists: choose another name")
    if _overlaps(a, b):
        raise PatternError(f"seam '{name}': its two sides overlap on the same edge",
                           panel=a.panel, edge=a.edge)
    for s in pattern.seams:
        for mine in (a, b):
            if _overlaps(mine, s.a) or _overlaps(mine, s.b):
                raise PatternError(f"seam '{name}': the span [{mine.start:g}, {mine.end:g}] "
                                   f"is already sewn by seam '{s.name}' (remove it first)",
                                   panel=mine.panel, edge=mine.edge)
    la, lb = pattern.seam_side_length(a), pattern.seam_side_length(b)
    if ease is None:
        need = max(la, lb) / min(la, lb) - 1.0
        if abs(la - lb) > limits.seam_ease * min(la, lb) + seam_slack(la, lb):
            raise PatternError(
                f"seam '{name}': sides of {la * 100:.2f} cm ({a.panel}/{a.edge}) and "
                f"{lb * 100:.2f} cm ({b.panel}/{b.edge}) would need an ease of {need:.3g}, "
                f"beyond the limit of {limits.seam_ease:g} (a {1 + limits.seam_ease:g}:1 "
                "gather)", panel=a.panel, edge=a.edge)
        ease = measured_ease(la, lb)
    new = replace(pattern, seams=pattern.seams + (Seam(name, a, b, reverse,
                                                       _ease(ease, name)),))
    _check(new, name)
    return new


def _ease(ease, name: str) -> float:
    try:
        return number(ease, f"seam '{name}': ease", low=0.0, high=limits.seam_ease,
                      unit="(longer / shorter - 1)")
    except ValueError as err:
        raise PatternError(str(err)) from None


def _check(pattern: Pattern, name: str) -> None:
    try:
        check_seams(pattern)
    except PatternError as err:
        raise PatternError(f"seam '{name}' refused: {err.reason}", panel=err.panel,
                           edge=err.edge) from None


@pattern_edit
def remove_seam(pattern: Pattern, name: str) -> Pattern:
    """``pattern`` without the seam called ``name`` (refused, listing the seams, when there
    is none)."""
    gone = _seam(pattern, name)
    return replace(pattern, seams=tuple(s for s in pattern.seams if s is not gone))


@pattern_edit
def set_seam_ease(pattern: Pattern, name: str, ease: float) -> Pattern:
    """``pattern`` with seam ``name``'s ease set to ``ease`` (longer / shorter - 1, in [0,
    ``limits.seam_ease``]); refused when the sides already differ by more than it allows."""
    old = _seam(pattern, name)
    new = replace(pattern, seams=tuple(replace(s, ease=_ease(ease, name)) if s is old else s
                                       for s in pattern.seams))
    _check(new, name)
    return new
