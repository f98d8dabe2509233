"""The internal tool: darts as inner loops whose legs are sewn together (paper Sec. 6.4).

A diamond dart is a closed loop top → left → bottom → right; its upper legs form seam
``<name>_upper`` and its lower legs ``<name>_lower``. A triangle dart is apex → left → right
with its two legs forming seam ``<name>``. Lengths in metres, in the panel's flat frame.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..constants import limits, tol
from ..pattern import Edge, Loop, Pattern, PatternError, Seam, SeamSide
from .tools import _arg, _finish, _panel, _said, pattern_edit

SHAPES = ("diamond", "triangle")


def _dart_points(centre, axis, length, width, shape):
    u = axis / np.linalg.norm(axis)
    n = np.array([-u[1], u[0]])
    if shape == "diamond":
        return [centre + 0.5 * length * u, centre - 0.5 * width * n,
                centre - 0.5 * length * u, centre + 0.5 * width * n]
    base = centre - 0.5 * length * u
    return [centre + 0.5 * length * u, base - 0.5 * width * n, base + 0.5 * width * n]


def _dart_loop(name, pts):
    k = len(pts)
    return Loop(name, tuple(Edge.line(f"{name}_{i}", pts[i], pts[(i + 1) % k])
                            for i in range(k)))


def _dart_seams(panel, name, shape):
    side = lambda i: SeamSide(panel, f"{name}_{i}")  # noqa: E731
    if shape == "diamond":
        return (Seam(f"{name}_upper", side(0), side(3)), Seam(f"{name}_lower", side(1), side(2)))
    return (Seam(name, side(0), side(2)),)


@pattern_edit
def insert_dart(pattern: Pattern, panel: str, name: str, centre, *, length: float,
                width: float, axis=(0.0, 1.0), shape: str = "diamond") -> Pattern:
    """Insert a dart of ``length`` x ``width`` [m] centred at ``centre`` (2,), its long axis
    along ``axis`` (2,). Its legs become seams, so sewing closes it."""
    if shape not in SHAPES:
        raise PatternError(f"shape: expected one of {SHAPES}, got {shape!r}", panel=panel)
    length, width = _size(length, "length", panel), _size(width, "width", panel)
    centre = _arg(centre, "centre", panel, lo=-limits.extent, hi=limits.extent, vector=True)
    axis = _arg(axis, "axis", panel, lo=-np.inf, hi=np.inf, vector=True)
    if not np.linalg.norm(axis) > 0:
        raise PatternError("axis: expected a direction, got (0, 0)", panel=panel)
    p = _panel(pattern, panel)
    if any(lp.name == name for lp in p.loops):
        raise PatternError(f"a loop called '{name}' exists already", panel=panel)
    pts = _dart_points(centre, axis, length, width, shape)
    new = pattern.with_panel(replace(p, inner=(*p.inner, _dart_loop(name, pts))))
    new = replace(new, seams=(*new.seams, *_dart_seams(panel, name, shape)))
    return _finish(pattern, new, set(), False,
                   f"{_said('length', length)}, {_said('width', width)}")


def _size(x, name: str, panel: str) -> float:
    """A dart's length or width [m]: at least an edge long, at most the pattern's reach."""
    return _arg(x, name, panel, lo=tol.edge_length)


def _dart(pattern, panel, name):
    p = _panel(pattern, panel)
    for li, lp in enumerate(p.inner, start=1):
        if lp.name == name:
            pts = [np.array(e.start) for e in lp.edges]
            if len(pts) not in (3, 4):
                break
            return p, li, pts
    raise PatternError(f"no dart '{name}'", panel=panel)


@pattern_edit
def move_dart(pattern: Pattern, panel: str, name: str, offset) -> Pattern:
    """Translate dart ``name`` by ``offset`` (2,) [m]; topology (and the mesh's) unchanged."""
    d = _arg(offset, "offset", panel, vector=True)
    p, li, pts = _dart(pattern, panel, name)
    loop = _dart_loop(name, [q + d for q in pts])
    inner = list(p.inner)
    inner[li - 1] = loop
    return _finish(pattern, pattern.with_panel(replace(p, inner=tuple(inner))), set(), False,
                   _said("offset", d))


@pattern_edit
def resize_dart(pattern: Pattern, panel: str, name: str, *, length: float | None = None,
                width: float | None = None) -> Pattern:
    """Widen/narrow or lengthen/shorten dart ``name`` about its centre [m]."""
    p, li, pts = _dart(pattern, panel, name)
    shape = "diamond" if len(pts) == 4 else "triangle"
    if shape == "diamond":
        top, left, bottom, right = pts
        centre, axis = 0.5 * (top + bottom), top - bottom
        w0 = np.linalg.norm(right - left)
    else:
        apex, left, right = pts
        base = 0.5 * (left + right)
        centre, axis = 0.5 * (apex + base), apex - base
        w0 = np.linalg.norm(right - left)
    length = np.linalg.norm(axis) if length is None else _size(length, "length", panel)
    width = w0 if width is None else _size(width, "width", panel)
    inner = list(p.inner)
    inner[li - 1] = _dart_loop(name, _dart_points(centre, axis, length, width, shape))
    return _finish(pattern, pattern.with_panel(replace(p, inner=tuple(inner))), set(), False,
                   f"{_said('length', length)}, {_said('width', width)}")
