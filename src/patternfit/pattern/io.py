"""Reading and writing patterns in patternfit's versioned JSON format.

The schema is written in ``docs/pattern-format.md``. Files state their units (``m``, ``cm``,
``mm`` or ``in``); inside the library everything is metres. Writing is atomic: the new file
is written beside the target and renamed over it, so a crash never leaves half a file.
"""

from __future__ import annotations

import difflib
import json
import math
import reprlib
from dataclasses import replace
from pathlib import Path
from typing import Any

from ..constants import UNITS
from ..files import atomic_write_text, read_json_file
from .edges import KINDS, Edge
from .errors import PatternError
from .model import InnerLine, Loop, Notch, Panel, Pattern, Placement, Seam, SeamSide
from .validate import check_pattern, check_size

FORMAT = "patternfit-pattern"
VERSION = 1


_MISSING = object()
# how messages name the JSON types wanted
_JSON_NAMES = {bool: "true or false", str: "a string", list: "a list", dict: "an object",
               int: "an integer", float: "a number"}


def shown(value, width: int = 60) -> str:
    """``repr(value)`` cut to about ``width`` characters, for a message (a file may hold a
    list of a million numbers where one was expected)."""
    short = reprlib.Repr()
    short.maxlevel, short.maxlist, short.maxdict = 2, 4, 4
    short.maxstring = short.maxother = width
    return short.repr(value)


def json_number(value, what: str, **where) -> float:
    """``value`` as a float; :class:`PatternError` (at ``where``: panel, edge) unless it is a
    finite JSON number (booleans are not numbers)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise PatternError(f"{what} must be a number, got {shown(value)}", **where)
    if not math.isfinite(value):
        raise PatternError(f"{what} is NaN or infinite", **where)
    return float(value)


def json_point(value, scale: float, what: str, **where) -> tuple[float, float]:
    """``[x, y]`` times ``scale`` (file unit length [m]) as a pair of floats."""
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise PatternError(f"{what} must be a pair [x, y], got {shown(value)}", **where)
    return (json_number(value[0], what, **where) * scale,
            json_number(value[1], what, **where) * scale)


def json_vec3(value, scale: float, what: str, **where) -> tuple[float, float, float] | None:
    """``[x, y, z]`` times ``scale`` as three floats; ``None`` stays ``None``."""
    if value is None:
        return None
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise PatternError(f"{what} must be [x, y, z], got {shown(value)}", **where)
    return tuple(json_number(c, what, **where) * scale for c in value)


def json_placement(pl, scale: float, *, part: str = "torso", side: str = "front",
                   **where) -> Placement:
    """The placement object ``pl`` of a panel (``part``, ``side``: its defaults; an explicit
    ``translation`` in file units times ``scale``, a ``rotation`` in degrees), refused with
    a :class:`PatternError` at ``where`` when a value is unknown or absurd."""
    known_keys(pl, PLACEMENT_KEYS, "placement", **where)
    part = json_field(pl, "part", str, "placement", part, **where)
    side = json_field(pl, "side", str, "placement", side, **where)
    translation = json_vec3(pl.get("translation"), scale, "placement translation", **where)
    rotation = json_vec3(pl.get("rotation"), 1.0, "placement rotation", **where)
    try:
        return Placement(part, side, translation, rotation)
    except ValueError as e:
        raise PatternError(str(e), **where) from None


def known_keys(obj, keys, what: str, **where) -> None:
    """Refuse a key of the JSON object ``obj`` that is not one of ``keys``, naming it and
    the nearest known one: a misspelt key was skipped for its default without a word
    (``"reversed": false`` read as reverse true, ``"grain_line"`` left the grain at [0, 1])."""
    if not isinstance(obj, dict):
        return
    for key in obj:
        if key not in keys:
            near = difflib.get_close_matches(str(key), list(keys), n=1)
            hint = f"; did you mean '{near[0]}'?" if near else ""
            raise PatternError(f"{what}: unknown key {shown(key, 40)} (known: "
                               f"{', '.join(keys)}){hint}", **where)


#: the keys of each object of the format (docs/pattern-format.md)
PATTERN_KEYS = ("format", "version", "units", "name", "meta", "panels", "seams")
PANEL_KEYS = ("name", "outline", "inner", "grainline", "placement", "lines", "drill_holes",
              "cut_line", "notches")
LOOP_KEYS = ("name", "edges")
EDGE_KEYS = ("name", "type", "points", "radius", "large_arc", "sweep")
PLACEMENT_KEYS = ("part", "side", "translation", "rotation")
LINE_KEYS = ("name", "points")
NOTCH_KEYS = ("edge", "t", "kind")
SEAM_KEYS = ("name", "a", "b", "reverse", "ease")
SEAM_SIDE_KEYS = ("panel", "edge", "range")


def json_field(obj, key: str, kind, what: str, default=_MISSING, **where):
    """``obj[key]``, which must be of type ``kind`` (``bool`` must be a real boolean, ``str``
    a real string); ``default`` when the key is missing, an error when there is none."""
    if not isinstance(obj, dict):
        raise PatternError(f"{what} must be an object", **where)
    if key not in obj:
        if default is _MISSING:
            raise PatternError(f"{what} is missing '{key}'", **where)
        return default
    value = obj[key]
    kinds = kind if isinstance(kind, tuple) else (kind,)
    if not isinstance(value, kinds) or (isinstance(value, bool) and bool not in kinds):
        names = " or ".join(_JSON_NAMES.get(k, k.__name__) for k in kinds)
        raise PatternError(f"{what}: '{key}' must be {names}, got {shown(value)}", **where)
    return value


def _edge_from_dict(d: Any, scale: float, panel: str, index: int) -> Edge:
    where = {"panel": panel}
    if not isinstance(d, dict):
        raise PatternError(f"edge #{index} must be an object", **where)
    name = d.get("name", f"e{index}")
    if not isinstance(name, str) or not name:
        raise PatternError(f"edge #{index} has no valid name", **where)
    where["edge"] = name
    known_keys(d, EDGE_KEYS, f"edge #{index}", **where)
    kind = json_field(d, "type", str, f"edge #{index}", **where)
    if kind not in KINDS:
        raise PatternError(f"unknown edge type '{kind}' (expected one of {sorted(KINDS)})",
                           **where)
    pts = json_field(d, "points", list, f"edge #{index}", **where)
    if len(pts) != KINDS[kind]:
        raise PatternError(f"a {kind} edge needs {KINDS[kind]} points, got {len(pts)}", **where)
    points = [json_point(p, scale, "point", **where) for p in pts]
    if kind != "arc":
        return Edge(name, kind, points)
    radius = json_number(json_field(d, "radius", (int, float), "arc", **where), "radius",
                         **where)
    if radius <= 0:
        raise PatternError("arc radius must be positive", **where)
    return Edge(name, "arc", points, radius=radius * scale,
                large_arc=json_field(d, "large_arc", bool, "arc", False, **where),
                sweep=json_field(d, "sweep", bool, "arc", True, **where))


def _loop_from_dict(d: Any, scale: float, panel: str, default_name: str) -> Loop:
    if not isinstance(d, dict):
        raise PatternError(f"loop '{default_name}' must be an object", panel=panel)
    name = json_field(d, "name", str, f"loop '{default_name}'", default_name, panel=panel)
    known_keys(d, LOOP_KEYS, f"loop '{name}'", panel=panel)
    edges = json_field(d, "edges", list, f"loop '{name}'", panel=panel)
    return Loop(name, tuple(_edge_from_dict(e, scale, panel, i) for i, e in enumerate(edges)))


def _panel_from_dict(d: Any, scale: float, index: int) -> Panel:
    if not isinstance(d, dict):
        raise PatternError(f"panel #{index} must be an object")
    name = json_field(d, "name", str, f"panel #{index}")
    known_keys(d, PANEL_KEYS, "panel", panel=name)
    outline = _loop_from_dict(json_field(d, "outline", dict, "panel", panel=name), scale, name,
                              "outline")
    inner = tuple(_loop_from_dict(lp, scale, name, f"inner{i}")
                  for i, lp in enumerate(json_field(d, "inner", list, "panel", [], panel=name)))
    grain = json_point(d.get("grainline", [0.0, 1.0]), 1.0, "grainline", panel=name)
    pl = json_field(d, "placement", dict, "panel", {}, panel=name)
    placement = json_placement(pl, scale, panel=name)
    lines = []
    for i, ln in enumerate(json_field(d, "lines", list, "panel", [], panel=name)):
        what = f"line #{i}"
        known_keys(ln, LINE_KEYS, what, panel=name)
        pts = json_field(ln, "points", list, what, panel=name)
        if len(pts) < 2:
            raise PatternError(f"{what} needs at least 2 points, got {len(pts)}", panel=name)
        lines.append(InnerLine(json_field(ln, "name", str, what, f"line{i}", panel=name),
                               [json_point(q, scale, f"{what} point", panel=name)
                                for q in pts]))
    drills = [json_point(q, scale, "drill hole", panel=name)
              for q in json_field(d, "drill_holes", list, "panel", [], panel=name)]
    cut = [json_point(q, scale, "cut line point", panel=name)
           for q in json_field(d, "cut_line", list, "panel", [], panel=name)]
    if 0 < len(cut) < 3:
        raise PatternError(f"the cut line needs at least 3 points, got {len(cut)}", panel=name)
    panel = Panel(name, outline, inner, grain, placement, lines=tuple(lines),
                  drill_holes=tuple(drills), cut_line=tuple(cut))
    return replace(panel, notches=notches_from_json(
        json_field(d, "notches", list, "panel", [], panel=name), panel))


def notches_from_json(raw: list, panel: Panel) -> tuple[Notch, ...]:
    """The notches of ``panel`` from their JSON list ``[{"edge", "t", "kind"}]``; a
    :class:`PatternError` naming the panel for an edge it does not have or ``t`` outside
    [0, 1]."""
    names = set(panel.edges())
    out = []
    for i, n in enumerate(raw):
        what = f"notch #{i}"
        known_keys(n, NOTCH_KEYS, what, panel=panel.name)
        edge = json_field(n, "edge", str, what, panel=panel.name)
        if edge not in names:
            raise PatternError(f"{what} is on edge '{edge}', which the panel does not have",
                               panel=panel.name, edge=edge)
        t = json_number(json_field(n, "t", (int, float), what, panel=panel.name, edge=edge),
                        f"{what}: t", panel=panel.name, edge=edge)
        if not 0.0 <= t <= 1.0:
            raise PatternError(f"{what}: t = {t:g} is outside [0, 1] (a fraction of the "
                               "edge's arc length)", panel=panel.name, edge=edge)
        kind = json_field(n, "kind", str, what, "slit", panel=panel.name, edge=edge)
        out.append(Notch(edge, t, kind))
    return tuple(out)


def check_notches(pattern: Pattern) -> None:
    """A :class:`PatternError` naming the panel for a notch on an edge the panel does not
    have or at ``t`` outside [0, 1] (an edit may have renamed or removed its edge)."""
    for panel in pattern.panels:
        notches_from_json(notches_to_json(panel), panel)


def notches_to_json(panel: Panel) -> list[dict]:
    """The JSON list of the panel's notches."""
    return [{"edge": n.edge, "t": float(n.t), "kind": n.kind} for n in panel.notches]


def _side_from_dict(d: Any, seam: str, outline_edges) -> SeamSide:
    if not isinstance(d, dict):
        raise PatternError(f"seam '{seam}': each side must be an object")
    panel = json_field(d, "panel", str, f"seam '{seam}' side")
    known_keys(d, SEAM_SIDE_KEYS, f"seam '{seam}' side", panel=panel)
    edge = d.get("edge")
    if outline_edges is not None and isinstance(edge, int) and not isinstance(edge, bool):
        if panel not in outline_edges:
            raise PatternError(f"seam '{seam}' names missing panel '{panel}'")
        if not 0 <= edge < len(outline_edges[panel]):
            raise PatternError(f"seam '{seam}': edge index {edge} out of range (the outline "
                               f"has {len(outline_edges[panel])} edges)", panel=panel,
                               edge=str(edge))
        edge = outline_edges[panel][edge]
    if not isinstance(edge, str):
        raise PatternError(f"seam '{seam}' side: 'edge' must be an edge name, got {shown(edge)}",
                           panel=panel)
    rng = d.get("range", [0.0, 1.0])
    if not isinstance(rng, list) or len(rng) != 2:
        raise PatternError(f"seam '{seam}': range must be [start, end]", panel=panel, edge=edge)
    start = json_number(rng[0], "range", panel=panel, edge=edge)
    end = json_number(rng[1], "range", panel=panel, edge=edge)
    return SeamSide(panel, edge, start, end)


def seams_from_json(raw: list, *, prefix: str = "seam", outline_edges=None) -> tuple[Seam, ...]:
    """Seams from their JSON list (the pattern file's ``seams``, also the DXF side file's).

    Unnamed seams are called ``{prefix}{i}``. With ``outline_edges`` ({panel: [outline edge
    names]}) a side's ``edge`` may also be an index into its panel's outline.
    """
    seams = []
    for i, s in enumerate(raw):
        if not isinstance(s, dict):
            raise PatternError(f"seam #{i} must be an object")
        name = json_field(s, "name", str, f"seam #{i}", f"{prefix}{i}")
        known_keys(s, SEAM_KEYS, f"seam '{name}'")
        side_a = _side_from_dict(s.get("a"), name, outline_edges)
        where = {"panel": side_a.panel, "edge": side_a.edge}
        ease = json_number(json_field(s, "ease", (int, float), f"seam '{name}'", 0.0,
                                      **where), f"seam '{name}': ease", **where)
        seams.append(Seam(name, side_a, _side_from_dict(s.get("b"), name, outline_edges),
                          json_field(s, "reverse", bool, f"seam '{name}'", True), ease))
    return tuple(seams)


def _edge_count(panels: list) -> int:
    """Edges in the raw panels, counted before any is built (malformed parts count 0)."""
    def edges(loop):
        e = loop.get("edges") if isinstance(loop, dict) else None
        return len(e) if isinstance(e, list) else 0
    total = 0
    for p in panels:
        if isinstance(p, dict):
            inner = p.get("inner")
            total += edges(p.get("outline")) + sum(
                edges(lp) for lp in (inner if isinstance(inner, list) else []))
    return total


def pattern_from_dict(data: Any) -> Pattern:
    """Build and validate a :class:`Pattern` [m] from the parsed JSON document.

    Raises :class:`PatternError` naming the panel and edge at fault; sizes beyond
    :data:`~patternfit.constants.limits` are refused before anything is built.
    """
    if not isinstance(data, dict):
        raise PatternError("the document must be a JSON object")
    if data.get("format") != FORMAT:
        raise PatternError(f"not a patternfit pattern (format is {shown(data.get('format'))}, "
                           f"expected '{FORMAT}')")
    version = data.get("version")
    if isinstance(version, bool) or version != VERSION:
        raise PatternError(f"unsupported format version {shown(version)} (this build reads "
                           f"version {VERSION})")
    known_keys(data, PATTERN_KEYS, "pattern")
    units = json_field(data, "units", str, "pattern", "m")
    if units not in UNITS:
        raise PatternError(f"unknown units {shown(units)} (expected one of {sorted(UNITS)})")
    scale = UNITS[units]
    name = json_field(data, "name", str, "pattern", "pattern")
    meta = json_field(data, "meta", dict, "pattern", {})
    panels_raw = json_field(data, "panels", list, "pattern")
    seams_raw = json_field(data, "seams", list, "pattern", [])
    check_size(len(panels_raw), _edge_count(panels_raw))
    panels = tuple(_panel_from_dict(p, scale, i) for i, p in enumerate(panels_raw))
    pattern = Pattern(name, panels, seams_from_json(seams_raw), dict(meta))
    check_pattern(pattern)
    return pattern


def _edge_to_dict(e: Edge, scale: float) -> dict:
    d: dict[str, Any] = {"name": e.name, "type": e.kind,
                         "points": [[x / scale, y / scale] for x, y in e.points]}
    if e.kind == "arc":
        d.update(radius=e.radius / scale, large_arc=e.large_arc, sweep=e.sweep)
    return d


def _marks_to_dict(p: Panel, scale: float) -> dict:
    """The panel's notches, internal lines, drill holes and cut line, those it has."""
    def pts(points):
        return [[x / scale, y / scale] for x, y in points]
    out: dict[str, Any] = {}
    if p.notches:
        out["notches"] = notches_to_json(p)
    if p.lines:
        out["lines"] = [{"name": ln.name, "points": pts(ln.points)} for ln in p.lines]
    if p.drill_holes:
        out["drill_holes"] = pts(p.drill_holes)
    if p.cut_line:
        out["cut_line"] = pts(p.cut_line)
    return out


def _loop_to_dict(loop: Loop, scale: float) -> dict:
    return {"name": loop.name, "edges": [_edge_to_dict(e, scale) for e in loop.edges]}


def pattern_to_dict(pattern: Pattern, *, units: str = "m") -> dict:
    """The JSON document of ``pattern`` with lengths written in ``units``."""
    if units not in UNITS:
        raise ValueError(f"units: expected one of {sorted(UNITS)}, got {units!r}")
    s = UNITS[units]
    panels = []
    for p in pattern.panels:
        pl = p.placement
        placement: dict[str, Any] = {"part": pl.part, "side": pl.side}
        if pl.translation is not None:
            placement["translation"] = [c / s for c in pl.translation]
        if pl.rotation is not None:
            placement["rotation"] = list(pl.rotation)
        panels.append({"name": p.name, "grainline": list(p.grainline), "placement": placement,
                       "outline": _loop_to_dict(p.outline, s),
                       "inner": [_loop_to_dict(lp, s) for lp in p.inner],
                       **_marks_to_dict(p, s)})
    return {"format": FORMAT, "version": VERSION, "units": units, "name": pattern.name,
            "meta": pattern.meta, "panels": panels, "seams": seams_to_json(pattern.seams)}


def seams_to_json(seams) -> list[dict]:
    """The JSON list of seams (the pattern file's ``seams``, also the DXF side file's)."""
    return [{"name": sm.name, "reverse": sm.reverse,
             "a": {"panel": sm.a.panel, "edge": sm.a.edge, "range": [sm.a.start, sm.a.end]},
             "b": {"panel": sm.b.panel, "edge": sm.b.edge, "range": [sm.b.start, sm.b.end]},
             **({"ease": float(sm.ease)} if sm.ease else {})}
            for sm in seams]


def load_pattern(path) -> Pattern:
    """Read and validate a pattern JSON file; every error is a :class:`PatternError` naming
    the file and, where it applies, the line and column or the panel and edge."""
    path = Path(path)
    return pattern_from_document(read_json_file(path, error=PatternError), path)


def pattern_from_document(data: Any, path) -> Pattern:
    """:func:`pattern_from_dict` of the document ``data`` read from the file ``path``, its
    errors naming that file (for a caller that needs the document too: its ``units``)."""
    try:
        return pattern_from_dict(data)
    except PatternError as exc:
        raise exc.located(path) from None


def save_pattern(pattern: Pattern, path, *, units: str = "m") -> Path:
    """Validate ``pattern`` (its notches too: a file is written only if it reads back) and
    write it atomically to ``path`` in ``units``."""
    check_pattern(pattern)
    check_notches(pattern)
    atomic_write_text(path, json.dumps(pattern_to_dict(pattern, units=units), indent=1) + "\n")
    return Path(path)
