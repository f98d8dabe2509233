"""GarmentCode / GarmentCodeData JSON sewing patterns: import and export.

The file is ``{"pattern": {"panels": {name: panel}, "stitches": [...]}, "parameters": ...,
"properties": {...}}``. Conventions, as GarmentCode's own code reads them
(``pygarment/pattern/core.py``, ``utils.py``, ``garmentcode/edge.py``, ``meshgen/boxmeshgen.py``):

- ``properties.units_in_meter``: file units per metre (100: centimetres). Missing means 100.
- A panel has 2D ``vertices``, ``edges`` (``endpoints`` [i, j], optional ``curvature`` and
  ``label``), a 3D ``translation`` (file units) and an XYZ Euler ``rotation`` in degrees. A panel
  point (x, y) goes to ``R @ (x, y, 0) + translation`` with ``R = Rz @ Ry @ Rx`` (Maya's
  intrinsic xyz order), for a body standing at the origin with y up.
- Curvature with ``properties.curvature_coords == "relative"`` (the default): a control point
  [t, n] is ``start + t * d + n * perp(d)`` with ``d = end - start`` and ``perp(d) = (-d_y,
  d_x)``: positive n lies to the left of the edge. ``"absolute"`` gives control points in panel
  coordinates. Forms: ``{"type": "quadratic", "params": [[t, n]]}``, ``{"type": "cubic",
  "params": [[t1, n1], [t2, n2]]}``, ``{"type": "circle", "params": [radius, large_arc,
  sweep]}`` (radius in file units, SVG flags in a y-up frame: sweep runs counter-clockwise,
  the same convention as :class:`~patternfit.pattern.edges.Edge`), and the old bare ``[t, n]``
  list for a quadratic curve.
- A stitch ``[{"panel": A, "edge": i}, {"panel": B, "edge": j}]`` sews the end of edge i to
  the start of edge j (our ``Seam.reverse=True``); a third entry ``"right_wrong"`` sews start
  to start (``reverse=False``).

Inside patternfit everything is metres. What has no place in the model (panel and edge labels,
parameters, properties) is kept in ``pattern.meta["garmentcode"]`` so that export writes it
back. Export adds keys GarmentCode ignores, ``patternfit_placement`` per panel (body part,
side, grain line, and whether the 3D placement is explicit) and ``patternfit_seam_names`` at
the top (with ``patternfit_seam_ease`` and ``patternfit_anchor``, a stated ``meta.anchor``,
where the pattern has them), so that our own patterns come back unchanged.
A file without it gets part ``"torso"`` and its side from the sign of the translation's z
(front: z >= 0), with the file's explicit 3D placement. The reader judges neither: placement
reads each panel's body part from its name, seams and shape
(:func:`patternfit.pattern.roles.panel_roles`) and uses the file's 3D placement only for a
garment hung from the waist whose placement is around the body
(:func:`patternfit.sim.panel_frames.implausible_placements`; older templates put the panels
at the feet or 25 m below), re-placing the garment otherwise (with a warning naming the
panels when they are not around the body; a top's flat panels sewn across the shoulders
failed, :func:`patternfit.sim.placement.place_on_body`).
"""

from __future__ import annotations

import json
import math
import re
from collections import Counter
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from ..arguments import number
from ..constants import UNITS, limits
from ..files import atomic_write_text, read_json_file
from ..geometry import euler_xyz_matrix
from ..text import CONTROL
from .edges import Edge
from .errors import PatternError
from .model import Loop, Panel, Pattern, Placement, Seam, SeamSide
from .orientation import twisted_warning
from .plausible import size_warnings
from .formats import check_imported
from .io import json_field, json_number, shown
from .validate import anchor_value, check_size, measured_ease, seam_slack

__all__ = ["euler_xyz_matrix", "garmentcode_from_dict", "garmentcode_to_dict", "is_garmentcode",
           "load_garmentcode", "panel_points_3d", "save_garmentcode"]

#: the file units a metre may hold (a file unit of 1 km to 1 µm): beyond, no pattern tool's
UNITS_IN_METER = (1e-3, 1e6)
_RIGHT_WRONG = "right_wrong"
# an extra panel key (ignored by GarmentCode) keeping our body part and side for a round trip
_HINT = "patternfit_placement"
_SEAM_NAMES = "patternfit_seam_names"  # likewise at the top level, one per stitch
_SEAM_EASE = "patternfit_seam_ease"  # and each seam's stated ease, where one has any
_ANCHOR = "patternfit_anchor"  # and meta.anchor, where the pattern states one
_AUTO_NAME = re.compile(r"e\d+(_\d+)?$")


def panel_points_3d(placement: Placement, points) -> np.ndarray:
    """Panel-frame points placed in 3D by an explicit placement: ``placement.transform``
    (:meth:`~patternfit.pattern.model.Placement.transform`)."""
    return placement.transform(points)


def is_garmentcode(data: Any) -> bool:
    """True when a parsed JSON document looks like a GarmentCode pattern specification."""
    return (isinstance(data, dict) and isinstance(data.get("pattern"), dict)
            and isinstance(data["pattern"].get("panels"), dict))


# -- import ------------------------------------------------------------------------------------
def _pair(value, what: str, **where) -> np.ndarray:
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise PatternError(f"{what} must be a pair [a, b], got {shown(value)}", **where)
    return np.array([json_number(v, what, **where) for v in value])


def _edge_names(edges: list) -> list[str]:
    """Edge names from GarmentCode labels: the label where it is unique in the panel, else
    ``label_i``, else ``e{i}``."""
    labels = [e.get("label") if isinstance(e, dict) else None for e in edges]
    labels = [lb if isinstance(lb, str) and lb.strip() else None for lb in labels]
    count = Counter(labels)
    names = []
    for i, lb in enumerate(labels):
        if lb is None:
            names.append(f"e{i}")
        elif count[lb] == 1 and not _AUTO_NAME.match(lb):
            names.append(lb)
        else:
            names.append(f"{lb}_{i}")
    seen: set[str] = set()
    for i, n in enumerate(names):  # a label may collide with a generated name
        while n in seen:
            n = f"{n}_{i}"
        names[i] = n
        seen.add(n)
    return names


def _control(start, end, point, relative: bool) -> np.ndarray:
    if not relative:
        return point
    d = end - start
    return start + point[0] * d + point[1] * np.array([-d[1], d[0]])


def _edge_from_gc(e: Any, verts: np.ndarray, scale: float, relative: bool, name: str,
                  index: int, where: dict) -> Edge:
    if not isinstance(e, dict):
        raise PatternError(f"edge #{index} must be an object", **where)
    json_field(e, "label", (str, type(None)), f"edge #{index}", None, **where)
    ends = e.get("endpoints")
    if (not isinstance(ends, (list, tuple)) or len(ends) != 2
            or not all(isinstance(k, int) and not isinstance(k, bool) for k in ends)):
        raise PatternError(f"edge #{index}: 'endpoints' must be two vertex indices, "
                           f"got {shown(ends)}", **where)
    for k in ends:
        if not 0 <= k < len(verts):
            raise PatternError(f"edge #{index}: vertex index {k} out of range "
                               f"(panel has {len(verts)} vertices)", **where)
    start, end = verts[ends[0]], verts[ends[1]]
    curv = e.get("curvature")
    if curv is None:
        return Edge.line(name, start * scale, end * scale)
    if isinstance(curv, list):  # old files: a bare control point of a quadratic curve
        ctrl = _control(start, end, _pair(curv, "curvature", **where), relative)
        return Edge.quadratic(name, start * scale, ctrl * scale, end * scale)
    if not isinstance(curv, dict):
        raise PatternError(f"edge #{index}: curvature must be an object or [t, n]", **where)
    kind, params = curv.get("type"), curv.get("params")
    if kind in ("quadratic", "cubic"):
        need = 1 if kind == "quadratic" else 2
        if (isinstance(params, list) and len(params) == 2 and need == 1
                and not isinstance(params[0], list)):
            params = [params]  # a single pair written flat
        if not isinstance(params, list) or len(params) != need:
            raise PatternError(f"edge #{index}: a {kind} curve needs {need} control point(s), "
                               f"got {shown(params)}", **where)
        ctrl = [_control(start, end, _pair(p, "control point", **where), relative) * scale
                for p in params]
        return Edge(name, kind, [start * scale, *ctrl, end * scale])
    if kind == "circle":
        if not isinstance(params, list) or len(params) != 3:
            raise PatternError(f"edge #{index}: a circle needs [radius, large_arc, sweep], "
                               f"got {shown(params)}", **where)
        radius = json_number(params[0], "circle radius", **where)
        if radius <= 0:
            raise PatternError(f"edge #{index}: circle radius must be positive", **where)
        flags = [bool(json_number(f, "circle flag", **where)) for f in params[1:]]
        return Edge.arc(name, start * scale, end * scale, radius * scale,
                        large_arc=flags[0], sweep=flags[1])
    raise PatternError(f"edge #{index}: unknown curvature type {shown(kind)} "
                       "(expected 'quadratic', 'cubic' or 'circle')", **where)


def _vec3(panel: dict, key: str, where: dict) -> tuple[float, float, float]:
    v = panel.get(key, [0.0, 0.0, 0.0])
    if not isinstance(v, (list, tuple)) or len(v) != 3:
        raise PatternError(f"'{key}' must be [x, y, z], got {shown(v)}", **where)
    return tuple(json_number(c, key, **where) for c in v)


def _panel_from_gc(name: str, p: Any, scale: float, relative: bool):
    where = {"panel": name}
    if not isinstance(p, dict):
        raise PatternError("panel must be an object", **where)
    json_field(p, "label", (str, type(None)), "panel", None, **where)
    raw = p.get("vertices")
    if not isinstance(raw, list) or len(raw) < 2:
        raise PatternError("panel needs a list of at least two 'vertices'", **where)
    verts = np.array([_pair(v, "vertex", **where) for v in raw])
    far = np.flatnonzero(np.abs(verts).max(axis=1) > limits.extent / scale)
    if len(far):  # refused before any length is taken of it
        raise PatternError(f"vertex #{far[0]} {shown(raw[far[0]])} lies "
                           f"{np.abs(verts[far[0]]).max() * scale:.3g} m from the origin, beyond "
                           f"the limit of {limits.extent:g} m", **where)
    edges_raw = p.get("edges")
    if not isinstance(edges_raw, list) or not edges_raw:
        raise PatternError("panel needs a non-empty list of 'edges'", **where)
    names = _edge_names(edges_raw)
    edges = [_edge_from_gc(e, verts, scale, relative, n, i, {**where, "edge": n})
             for i, (e, n) in enumerate(zip(edges_raw, names))]
    t = _vec3(p, "translation", where)
    r = _vec3(p, "rotation", where)
    hint = json_field(p, _HINT, dict, "panel", {}, **where)
    part = json_field(hint, "part", str, _HINT, "torso", **where)
    side = json_field(hint, "side", str, _HINT, "back" if t[2] < 0 else "front", **where)
    explicit = json_field(hint, "explicit", bool, _HINT, True, **where)
    try:
        if not explicit and not any(t) and not any(r):
            placement = Placement(part=part, side=side)  # ours, without a 3D placement
        else:
            placement = Placement(part=part, side=side,
                                  translation=tuple(c * scale for c in t), rotation=r)
    except ValueError as e:
        raise PatternError(str(e), **where) from None
    grain = hint.get("grainline", [0.0, 1.0])
    panel = Panel(name, Loop("outline", tuple(edges)),
                  grainline=tuple(_pair(grain, "grainline", **where)), placement=placement)
    labels = [e.get("label") if isinstance(e.get("label"), str) else None for e in edges_raw]
    return panel, names, labels


def _edge_count(panels: dict) -> int:
    """Edges or vertices of the raw panels, whichever are more (a closed outline has as many
    of each), counted before any panel is built."""
    def size(p, key):
        v = p.get(key) if isinstance(p, dict) else None
        return len(v) if isinstance(v, list) else 0
    return max(sum(size(p, "edges") for p in panels.values()),
               sum(size(p, "vertices") for p in panels.values()))


def _place(edge) -> str:
    """An edge reference from a stitch as the error's place."""
    return edge if isinstance(edge, str) else shown(edge)


def _stitch_side(side: Any, i: int, k: int, names: dict[str, list[str]]) -> SeamSide:
    if not isinstance(side, dict):
        raise PatternError(f"stitch #{i}: side {k} must be {{'panel': ..., 'edge': ...}}")
    panel, edge = json_field(side, "panel", str, f"stitch #{i} side {k}"), side.get("edge")
    if panel not in names:
        raise PatternError(f"stitch #{i} names missing panel {panel!r}")
    if isinstance(edge, bool) or not isinstance(edge, int) or not 0 <= edge < len(names[panel]):
        raise PatternError(f"stitch #{i}: edge index {shown(edge)} out of range (panel has "
                           f"{len(names[panel])} edges)", panel=panel, edge=_place(edge))
    return SeamSide(panel, names[panel][edge])


def _with_ease(pattern: Pattern, given) -> tuple[Pattern, list[str]]:
    """``pattern`` with every seam's ``ease``: the one our export wrote (``given``, one per
    stitch) or else the one its sides' lengths need (GarmentCode gathers and eases seams by
    sewing edges of different length), and a note for each seam so gathered."""
    if given is not None and not (
            isinstance(given, list) and len(given) == len(pattern.seams)
            and all(isinstance(x, (int, float)) and not isinstance(x, bool)
                    and 0 <= x <= limits.seam_ease for x in given)):
        # ours, written by the export: a damaged one was dropped without a word and every
        # ease measured afresh
        raise PatternError(f"'{_SEAM_EASE}': expected one number in [0, "
                           f"{limits.seam_ease:g}] per stitch ({len(pattern.seams)}), got "
                           f"{shown(given)}")
    seams, notes = [], []
    for i, seam in enumerate(pattern.seams):
        la, lb = pattern.seam_side_length(seam.a), pattern.seam_side_length(seam.b)
        ease = float(given[i]) if given is not None else measured_ease(la, lb)
        # a gather past the limit is capped there and said by check_imported as beyond it
        # (meshing refuses it): "sewn in as ease 1" beside that read as if it had been
        capped = bool(ease) and min(la, lb) > 0 \
            and max(la, lb) / min(la, lb) - 1.0 > limits.seam_ease
        if ease and abs(la - lb) > seam_slack(la, lb) and not capped:
            notes.append(f"seam '{seam.name}' joins sides of different length: "
                         f"{la * 100:.2f} cm ({seam.a.panel}/{seam.a.edge}) vs "
                         f"{lb * 100:.2f} cm ({seam.b.panel}/{seam.b.edge}); sewn in as "
                         f"ease {ease:g}")
        seams.append(replace(seam, ease=ease))
    return replace(pattern, seams=tuple(seams)), notes


def garmentcode_from_dict(data: Any, *, name: str = "pattern") -> Pattern:
    """Build a :class:`Pattern` [m] from a parsed GarmentCode specification.

    Stitches whose two edges differ in length beyond tolerance (gathers, cap ease) get the
    seam ``ease`` their lengths need (longer / shorter - 1; the one our export wrote under
    ``patternfit_seam_ease`` when there is one) and a note in ``meta["warnings"]``; a
    difference beyond ``limits.seam_ease`` is kept with that ease and a warning
    (:func:`~patternfit.pattern.formats.check_imported`), and meshing refuses it. Raises
    :class:`PatternError` naming panel and edge.
    """
    if not is_garmentcode(data):
        raise PatternError("not a GarmentCode pattern (expected {'pattern': {'panels': {...}}})")
    props = data.get("properties") or {}
    if not isinstance(props, dict):
        raise PatternError("'properties' must be an object")
    units = props.get("units_in_meter", 100)
    if (isinstance(units, bool) or not isinstance(units, (int, float))
            or not math.isfinite(units) or units <= 0):
        raise PatternError(f"bad units: 'units_in_meter' must be a positive number, "
                           f"got {shown(units)}")
    if not UNITS_IN_METER[0] <= units <= UNITS_IN_METER[1]:
        raise PatternError(f"bad units: 'units_in_meter' {units:g} makes a file unit "
                           f"{1.0 / units:.3g} m, no length a pattern is drawn in (1 km to "
                           f"1 µm: 'units_in_meter' {UNITS_IN_METER[0]:g} to "
                           f"{UNITS_IN_METER[1]:g}; 100 is centimetres)")
    coords = props.get("curvature_coords", "relative")
    if coords not in ("relative", "absolute"):
        raise PatternError(f"bad 'curvature_coords' {shown(coords)} (expected 'relative' or "
                           "'absolute')")
    scale = 1.0 / float(units)
    spec = data["pattern"]
    if not spec["panels"]:
        raise PatternError("the pattern has no panels")
    check_size(len(spec["panels"]), _edge_count(spec["panels"]))
    order = spec.get("panel_order")
    if order is not None and not (isinstance(order, list)
                                  and all(isinstance(n, str) for n in order)):
        raise PatternError(f"'panel_order' must be a list of panel names, got {shown(order)}")
    panels, names, labels = [], {}, {}
    for pname, p in spec["panels"].items():
        panel, names[pname], labels[pname] = _panel_from_gc(str(pname), p, scale,
                                                            coords == "relative")
        panels.append(panel)
    stitches = spec.get("stitches", [])
    if not isinstance(stitches, list):
        raise PatternError("'stitches' must be a list")
    seams, tags = [], {}
    seam_names = data.get(_SEAM_NAMES)
    if seam_names is None:
        seam_names = [f"stitch{i}" for i in range(len(stitches))]
    elif not (isinstance(seam_names, list) and len(seam_names) == len(stitches)
              and all(isinstance(n, str) and n for n in seam_names)
              and len(set(seam_names)) == len(seam_names)):
        raise PatternError(f"'{_SEAM_NAMES}': expected one distinct non-empty name per stitch "
                           f"({len(stitches)}), got {shown(seam_names)}")
    unknown_tags = []
    for i, s in enumerate(stitches):
        if not isinstance(s, (list, tuple)) or len(s) < 2:
            raise PatternError(f"stitch #{i} must be a list of two sides")
        a, b = _stitch_side(s[0], i, 0, names), _stitch_side(s[1], i, 1, names)
        extra = list(s[2:])
        if not all(isinstance(x, str) for x in extra):
            raise PatternError(f"stitch #{i}: entries after the two sides must be strings "
                               f"(tags such as '{_RIGHT_WRONG}'), got {shown(extra)}")
        seam_name = seam_names[i]
        unknown_tags += [f"'{t}' (stitch #{i})" for t in extra if t != _RIGHT_WRONG]
        seams.append(Seam(seam_name, a, b, reverse=_RIGHT_WRONG not in extra))
        if extra:
            tags[seam_name] = extra
    pattern, notes = _with_ease(Pattern(name, tuple(panels), tuple(seams)),
                                data.get(_SEAM_EASE))
    if unknown_tags:
        # a misspelt 'right_wrong' sews the seam right side to right side
        notes.append(f"stitch tags not known, read as no tag: {', '.join(unknown_tags[:5])}"
                     + (f" and {len(unknown_tags) - 5} more" if len(unknown_tags) > 5 else "")
                     + f" (the one read is '{_RIGHT_WRONG}'; its stitch is sewn right side "
                     "to right side without it)")
    said = (f"'units_in_meter': {units:g}" if "units_in_meter" in props
            else "no 'units_in_meter', so centimetres")
    warnings = notes + check_imported(pattern) + size_warnings(
        panels, scale, said, hint=lambda unit: (
            f"set \"units_in_meter\": {1.0 / UNITS[unit]:g} in the file's 'properties'"))
    twisted = twisted_warning(pattern, fix="check the stitches' 'right_wrong' tags")
    if twisted:
        warnings.append(twisted)
    keep = {k: data[k] for k in ("parameters", "parameter_order") if k in data}
    meta: dict[str, Any] = {"source_format": "garmentcode", "garmentcode": {
        **keep, "properties": props,
        "panel_labels": {k: p["label"] for k, p in spec["panels"].items()
                         if isinstance(p, dict) and isinstance(p.get("label"), str)},
        "edge_labels": {k: dict(zip(names[k], labels[k])) for k in names},
        "stitch_tags": tags}}
    if "panel_order" in spec:
        meta["garmentcode"]["panel_order"] = spec["panel_order"]
    if warnings:
        meta["warnings"] = warnings
    if _ANCHOR in data:
        meta["anchor"] = anchor_value(data[_ANCHOR], f"'{_ANCHOR}'")
    pattern.meta.update(meta)
    return pattern


def load_garmentcode(path) -> Pattern:
    """Read a GarmentCode JSON file; errors name the file, panel and edge. Lengths in metres.

    The pattern is named after the file (``x_specification.json`` gives ``x``).
    """
    path = Path(path)
    data = read_json_file(path, error=PatternError)
    name = CONTROL.sub("", path.stem.removesuffix("_specification")) or "pattern"
    try:
        return garmentcode_from_dict(data, name=name)
    except PatternError as exc:
        raise exc.located(path) from None


# -- export ------------------------------------------------------------------------------------
def _split(edge: Edge, f0: float, f1: float) -> Edge:
    """The part of ``edge`` between arc-length fractions ``f0`` and ``f1``."""
    if f0 <= 0.0 and f1 >= 1.0:
        return edge
    t0, t1 = (float(x) for x in edge.parameter_at([f0, f1]))
    if edge.kind == "arc":
        _, _, _, delta = edge._arc
        p = edge.evaluate([t0, t1])
        return Edge.arc(edge.name, p[0], p[1], edge.radius,
                        large_arc=abs(delta) * (t1 - t0) > math.pi, sweep=edge.sweep)
    pts = np.asarray(edge.points)

    def cut(points, t, keep_right):  # de Casteljau: left or right part at parameter t
        rows, left, right = points, [points[0]], [points[-1]]
        while len(rows) > 1:
            rows = (1 - t) * rows[:-1] + t * rows[1:]
            left.append(rows[0])
            right.append(rows[-1])
        return np.array(right[::-1]) if keep_right else np.array(left)

    right = cut(pts, t0, True)
    part = cut(right, (t1 - t0) / (1.0 - t0), False) if t1 < 1.0 else right
    return edge.with_points(part)


def _relative(start, end, point) -> list[float]:
    d = end - start
    v = np.asarray(point) - start
    n2 = float(d @ d)
    return [float(v @ d) / n2, float(d[0] * v[1] - d[1] * v[0]) / n2]


def _curvature(e: Edge, scale: float):
    if e.kind == "line":
        return None
    if e.kind == "arc":
        return {"type": "circle", "params": [e.radius / scale, int(e.large_arc), int(e.sweep)]}
    p = np.asarray(e.points)
    return {"type": e.kind, "params": [_relative(p[0], p[-1], c) for c in p[1:-1]]}


def garmentcode_to_dict(pattern: Pattern, *, units_in_meter: float = 100.0) -> dict:
    """The GarmentCode specification of ``pattern``, lengths in ``1 / units_in_meter`` metres.

    Edges are split where a seam covers only part of them (GarmentCode stitches join whole
    edges). Raises :class:`PatternError` for a panel with inner loops, which GarmentCode cannot
    express, and ``ValueError`` for a ``units_in_meter`` outside :data:`UNITS_IN_METER`.
    """
    number(units_in_meter, "units_in_meter", low=UNITS_IN_METER[0], high=UNITS_IN_METER[1])
    scale = 1.0 / units_in_meter
    gc = pattern.meta.get("garmentcode", {}) if isinstance(pattern.meta, dict) else {}
    breaks: dict[tuple[str, str], set[float]] = {}
    for seam in pattern.seams:
        for side in (seam.a, seam.b):
            breaks.setdefault((side.panel, side.edge), set()).update((side.start, side.end))
    panels, index = {}, {}
    for p in pattern.panels:
        if p.inner:
            raise PatternError("GarmentCode panels have no inner loops (darts, cut-outs); "
                               f"loop '{p.inner[0].name}' cannot be written", panel=p.name,
                               edge=p.inner[0].edges[0].name)
        labels = gc.get("edge_labels", {}).get(p.name, {})
        verts, edges = [], []
        for e in p.outline.edges:
            cuts = sorted({0.0, 1.0} | {f for f in breaks.get((p.name, e.name), ())
                                        if 0.0 < f < 1.0})
            for f0, f1 in zip(cuts[:-1], cuts[1:]):
                index[(p.name, e.name, f0)] = len(edges)
                part = _split(e, f0, f1)
                d: dict[str, Any] = {"endpoints": [len(edges), len(edges) + 1]}
                curv = _curvature(part, scale)
                if curv is not None:
                    d["curvature"] = curv
                label = labels.get(e.name, None if _AUTO_NAME.match(e.name) else e.name)
                if label:
                    d["label"] = label
                verts.append([float(c) / scale for c in part.points[0]])
                edges.append(d)
        edges[-1]["endpoints"][1] = 0
        pl = p.placement
        entry = {"translation": [c / scale for c in (pl.translation or (0.0, 0.0, 0.0))],
                 "rotation": list(pl.rotation or (0.0, 0.0, 0.0)),
                 "vertices": verts, "edges": edges}
        if p.name in gc.get("panel_labels", {}):
            entry["label"] = gc["panel_labels"][p.name]
        entry[_HINT] = {"part": pl.part, "side": pl.side, "grainline": list(p.grainline),
                        "explicit": pl.explicit}
        panels[p.name] = entry
    tags = gc.get("stitch_tags", {})
    stitches = []
    for seam in pattern.seams:
        s: list[Any] = [{"panel": side.panel, "edge": index[(side.panel, side.edge, side.start)]}
                        for side in (seam.a, seam.b)]
        extra = [t for t in tags.get(seam.name, []) if t != _RIGHT_WRONG]
        if not seam.reverse:
            extra.insert(0, _RIGHT_WRONG)
        stitches.append(s + extra)
    props = {**gc.get("properties", {}), "curvature_coords": "relative",
             "normalize_panel_translation": False, "normalized_edge_loops": True,
             "units_in_meter": units_in_meter}
    spec: dict[str, Any] = {"panels": panels, "stitches": stitches}
    if gc.get("panel_order") and set(gc["panel_order"]) == set(panels):
        spec["panel_order"] = gc["panel_order"]
    doc = {"pattern": spec, "parameters": gc.get("parameters", {}),
           "parameter_order": gc.get("parameter_order", []), "properties": props,
           _SEAM_NAMES: [seam.name for seam in pattern.seams]}
    if any(seam.ease for seam in pattern.seams):
        doc[_SEAM_EASE] = [float(seam.ease) for seam in pattern.seams]
    if "anchor" in pattern.meta:
        # stated, it may be what the panels deny (dropped, a skirt stated as hung from the
        # neck drapes another way read back)
        doc[_ANCHOR] = pattern.meta["anchor"]
    return doc


def save_garmentcode(pattern: Pattern, path, *, units_in_meter: float = 100.0) -> Path:
    """Write ``pattern`` atomically as a GarmentCode JSON file (default centimetres)."""
    doc = garmentcode_to_dict(pattern, units_in_meter=units_in_meter)
    atomic_write_text(path, json.dumps(doc, indent=2) + "\n")
    return Path(path)
