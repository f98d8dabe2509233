"""Reading and writing patterns in patternfit's versioned JSON format.

The schema is written in ``docs/pattern-format.md``. Files state their units (``m``, ``cm``,
``mm`` or ``in``); inside the library everything is metres. Writing is atomic: the new file
is written beside the target and renamed over it, so a crash never leaves half a file.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

from ..constants import UNITS
from ..files import atomic_write_text
from .edges import KINDS, Edge
from .errors import PatternError
from .model import Loop, Panel, Pattern, Placement, Seam, SeamSide
from .validate import check_pattern

FORMAT = "patternfit-pattern"
VERSION = 1


def _num(value, what: str, **where) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise PatternError(f"{what} must be a number, got {value!r}", **where)
    if not math.isfinite(value):
        raise PatternError(f"{what} is NaN or infinite", **where)
    return float(value)


def _point(value, scale: float, what: str, **where) -> tuple[float, float]:
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise PatternError(f"{what} must be a pair [x, y], got {value!r}", **where)
    return (_num(value[0], what, **where) * scale, _num(value[1], what, **where) * scale)


def _require(obj, key: str, kind, what: str, **where):
    if not isinstance(obj, dict) or key not in obj:
        raise PatternError(f"{what} is missing '{key}'", **where)
    if not isinstance(obj[key], kind):
        raise PatternError(f"{what}: '{key}' has the wrong type ({type(obj[key]).__name__})",
                           **where)
    return obj[key]


def _edge_from_dict(d: Any, scale: float, panel: str, index: int) -> Edge:
    where = {"panel": panel}
    if not isinstance(d, dict):
        raise PatternError(f"edge #{index} must be an object", **where)
    name = d.get("name", f"e{index}")
    if not isinstance(name, str) or not name:
        raise PatternError(f"edge #{index} has no valid name", **where)
    where["edge"] = name
    kind = _require(d, "type", str, f"edge #{index}", **where)
    if kind not in KINDS:
        raise PatternError(f"unknown edge type '{kind}' (expected one of {sorted(KINDS)})",
                           **where)
    pts = _require(d, "points", list, f"edge #{index}", **where)
    if len(pts) != KINDS[kind]:
        raise PatternError(f"a {kind} edge needs {KINDS[kind]} points, got {len(pts)}", **where)
    points = [_point(p, scale, "point", **where) for p in pts]
    if kind != "arc":
        return Edge(name, kind, points)
    radius = _num(_require(d, "radius", (int, float), "arc", **where), "radius", **where)
    if radius <= 0:
        raise PatternError("arc radius must be positive", **where)
    return Edge(name, "arc", points, radius=radius * scale,
                large_arc=bool(d.get("large_arc", False)), sweep=bool(d.get("sweep", True)))


def _loop_from_dict(d: Any, scale: float, panel: str, default_name: str) -> Loop:
    if not isinstance(d, dict):
        raise PatternError(f"loop '{default_name}' must be an object", panel=panel)
    name = d.get("name", default_name)
    edges = _require(d, "edges", list, f"loop '{name}'", panel=panel)
    return Loop(name, tuple(_edge_from_dict(e, scale, panel, i) for i, e in enumerate(edges)))


def _panel_from_dict(d: Any, scale: float, index: int) -> Panel:
    if not isinstance(d, dict):
        raise PatternError(f"panel #{index} must be an object")
    name = _require(d, "name", str, f"panel #{index}")
    outline = _loop_from_dict(_require(d, "outline", dict, "panel", panel=name), scale, name,
                              "outline")
    inner_raw = d.get("inner", [])
    if not isinstance(inner_raw, list):
        raise PatternError("'inner' must be a list of loops", panel=name)
    inner = tuple(_loop_from_dict(lp, scale, name, f"inner{i}")
                  for i, lp in enumerate(inner_raw))
    grain = _point(d.get("grainline", [0.0, 1.0]), 1.0, "grainline", panel=name)
    pl = d.get("placement") or {}
    if not isinstance(pl, dict):
        raise PatternError("'placement' must be an object", panel=name)
    def vec3(key, s):
        v = pl.get(key)
        if v is None:
            return None
        if not isinstance(v, list) or len(v) != 3:
            raise PatternError(f"placement '{key}' must be [x, y, z]", panel=name)
        return tuple(_num(c, f"placement {key}", panel=name) * s for c in v)
    placement = Placement(part=str(pl.get("part", "torso")), side=str(pl.get("side", "front")),
                          translation=vec3("translation", scale), rotation=vec3("rotation", 1.0))
    return Panel(name, outline, inner, grain, placement)


def _side_from_dict(d: Any, seam: str) -> SeamSide:
    if not isinstance(d, dict):
        raise PatternError(f"seam '{seam}': each side must be an object")
    panel = _require(d, "panel", str, f"seam '{seam}' side")
    edge = _require(d, "edge", str, f"seam '{seam}' side", panel=panel)
    rng = d.get("range", [0.0, 1.0])
    if not isinstance(rng, list) or len(rng) != 2:
        raise PatternError(f"seam '{seam}': range must be [start, end]", panel=panel, edge=edge)
    start = _num(rng[0], "range", panel=panel, edge=edge)
    end = _num(rng[1], "range", panel=panel, edge=edge)
    return SeamSide(panel, edge, start, end)


def pattern_from_dict(data: Any) -> Pattern:
    """Build and validate a :class:`Pattern` from the parsed JSON document.

    Raises :class:`PatternError` naming the panel and edge at fault.
    """
    if not isinstance(data, dict):
        raise PatternError("the document must be a JSON object")
    if data.get("format") != FORMAT:
        raise PatternError(f"not a patternfit pattern (format is {data.get('format')!r}, "
                           f"expected '{FORMAT}')")
    version = data.get("version")
    if version != VERSION:
        raise PatternError(f"unsupported format version {version!r} (this build reads "
                           f"version {VERSION})")
    units = data.get("units", "m")
    if units not in UNITS:
        raise PatternError(f"unknown units {units!r} (expected one of {sorted(UNITS)})")
    scale = UNITS[units]
    panels_raw = _require(data, "panels", list, "pattern")
    panels = tuple(_panel_from_dict(p, scale, i) for i, p in enumerate(panels_raw))
    seams = []
    for i, s in enumerate(data.get("seams", [])):
        if not isinstance(s, dict):
            raise PatternError(f"seam #{i} must be an object")
        name = s.get("name", f"seam{i}")
        seams.append(Seam(name, _side_from_dict(s.get("a"), name), _side_from_dict(s.get("b"), name),
                          bool(s.get("reverse", True))))
    meta = data.get("meta", {})
    pattern = Pattern(str(data.get("name", "pattern")), panels, tuple(seams),
                      meta if isinstance(meta, dict) else {})
    check_pattern(pattern)
    return pattern


def _edge_to_dict(e: Edge, scale: float) -> dict:
    d: dict[str, Any] = {"name": e.name, "type": e.kind,
                         "points": [[x / scale, y / scale] for x, y in e.points]}
    if e.kind == "arc":
        d.update(radius=e.radius / scale, large_arc=e.large_arc, sweep=e.sweep)
    return d


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
                       "inner": [_loop_to_dict(lp, s) for lp in p.inner]})
    seams = [{"name": sm.name, "reverse": sm.reverse,
              "a": {"panel": sm.a.panel, "edge": sm.a.edge, "range": [sm.a.start, sm.a.end]},
              "b": {"panel": sm.b.panel, "edge": sm.b.edge, "range": [sm.b.start, sm.b.end]}}
             for sm in pattern.seams]
    return {"format": FORMAT, "version": VERSION, "units": units, "name": pattern.name,
            "meta": pattern.meta, "panels": panels, "seams": seams}


def read_json(path) -> Any:
    """The parsed JSON document in ``path``; :class:`PatternError` naming the file when it
    cannot be read or parsed."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise PatternError(f"cannot read file: {exc.strerror}", file=path) from None
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise PatternError(f"not valid JSON (line {exc.lineno}, column {exc.colno}: {exc.msg})",
                           file=path) from None


def load_pattern(path) -> Pattern:
    """Read and validate a pattern JSON file; errors name the file, panel and edge."""
    path = Path(path)
    data = read_json(path)
    try:
        return pattern_from_dict(data)
    except PatternError as exc:
        raise exc.located(path) from None


def save_pattern(pattern: Pattern, path, *, units: str = "m") -> Path:
    """Validate ``pattern`` and write it atomically to ``path`` in ``units``."""
    check_pattern(pattern)
    atomic_write_text(path, json.dumps(pattern_to_dict(pattern, units=units), indent=1) + "\n")
    return Path(path)
