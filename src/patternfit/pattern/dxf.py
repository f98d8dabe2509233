"""DXF-AAMA (ASTM D6673) pattern exchange: import and export, on ``ezdxf``.

A DXF-AAMA file is DXF R12 with one block per pattern piece; inside a block, layers carry the
meaning (ASTM D6673 numbering): 1 piece boundary (cut line) and piece text, 2 turn points, 3
curve points, 4 notches, 5 grade reference, 6 mirror line, 7 grain line, 8 internal lines,
9 stripe and 10 plaid reference, 11 internal cut-outs, 13 drill holes, 14 sew lines, 15
annotation text (80-86 special notch shapes). Piece text reads ``Piece Name: front``,
``Size: M``, ``Quantity: 1``; the style text in the entities section carries ``Units:
METRIC`` (millimetres) or ``Units: ENGLISH`` (inches).

Export writes the outline on layer 1 as a polyline (curves sampled finely enough that the
polyline stays within 0.02 mm of the curve), turn points at every edge end (layer 2), curve
points between them (layer 3), a notch at the middle of every seam side (layer 4), the grain
line (layer 7) and inner loops as internal cut-outs (layer 11), through ezdxf's Gerber writer
(``ezdxf.addons.gerber_D6673``) so that Gerber's strict parser accepts the file. DXF-AAMA has no
seams, edge names or 3D placement: they go to a side file ``<name>.seams.json``.

Import drops repeated points (``tol.dxf_repeat``), splits each closed outline at its turn
points (or, without any, at corners) and turns each run of points back into a line, a circular
arc or a cubic Bézier when the fit stays within 0.05 mm of the points and 0.5 mm of the
polyline everywhere, else into a chain of shorter curves (``dxf_curves``). Units come from the
``Units:`` text, ``$INSUNITS`` or ``$MEASUREMENT``; implausible piece sizes are warned about. A closed sew line (layer 14) is preferred to the
cut line as the outline, since sewing happens there. Seams come from the side file; without
one, seams are suggested (``meta["suggested_seams"]``) from edge pairs of equal length with
matching notches. Everything inside is metres.
"""

from __future__ import annotations

import io
import json
import re
from dataclasses import replace
from itertools import islice
from pathlib import Path
from typing import Any

import numpy as np
from ezdxf import path as dxfpath
from ezdxf.addons import gerber_D6673
from ezdxf.document import Drawing
from ezdxf.filemanagement import dxf_stream_info
from ezdxf.lldxf.tagger import binary_tags_loader
from ezdxf.lldxf.validator import is_dxf_stream
from scipy.spatial import cKDTree

from ..constants import UNITS, limits, tol
from ..files import atomic_write_text, read_bytes_capped, read_json_file
from .dxf_curves import dedupe, loop_from_points
from .edges import Edge
from .errors import PatternError
from .formats import check_imported
from .io import json_field, json_point, json_vec3, seams_from_json, shown
from .model import Loop, Panel, Pattern, Placement, Seam, SeamSide
from .validate import check_pattern

__all__ = ["LAYERS", "load_dxf", "notch_marks", "save_dxf", "sidecar_path", "suggest_seams"]

#: ASTM D6673 layer numbers by meaning.
LAYERS = {"boundary": 1, "turn_points": 2, "curve_points": 3, "notches": 4,
          "grade_reference": 5, "mirror": 6, "grain": 7, "internal": 8, "stripe": 9,
          "plaid": 10, "cutout": 11, "drill_holes": 13, "sew": 14, "annotation": 15}

SIDE_FORMAT = "patternfit-dxf-sidecar"
#: how many edges next in length :func:`suggest_seams` compares each edge with [-]
SEAM_WINDOW = 64
_PIECE_LAYERS = (LAYERS["boundary"], LAYERS["sew"])
_BINARY_DXF = b"AutoCAD Binary DXF\r\n\x1a\x00"
_NOTCH = 0.006  # notch slit length [m]
_UNIT = {"METRIC": 0.001, "ENGLISH": 0.0254}
_INSUNITS = {1: 0.0254, 2: 0.3048, 4: 0.001, 5: 0.01, 6: 1.0}
#: sizes across (largest side of the bounding box) a garment piece plausibly has; outside
#: them the file's units are probably misread and the reader warns [m]
PLAUSIBLE = (0.01, 3.0)


def sidecar_path(path) -> Path:
    """The side file that goes with a DXF file: ``x.dxf`` -> ``x.seams.json``."""
    path = Path(path)
    return path.with_name(path.stem + ".seams.json")


# -- export ------------------------------------------------------------------------------------
def _sample(edge: Edge) -> np.ndarray:
    """Points along an edge, the polyline within ``tol.dxf_sample`` of the curve: (k, 2) [m]."""
    if edge.kind == "line":
        return np.array(edge.points)
    n = 8
    while True:
        f = np.linspace(0.0, 1.0, 2 * n + 1)
        p = edge.point_at(f)
        chord_mid = 0.5 * (p[0:-1:2] + p[2::2])
        if np.max(np.linalg.norm(p[1::2] - chord_mid, axis=1)) < tol.dxf_sample or n >= 1024:
            return p[::2]
        n *= 2


def _block_name(name: str, used: set[str]) -> str:
    base = re.sub(r"[^A-Za-z0-9_\-]", "_", name) or "piece"
    out, k = base, 1
    while out.upper() in used:
        k += 1
        out = f"{base}_{k}"
    used.add(out.upper())
    return out


def _loop_points(loop: Loop) -> tuple[np.ndarray, list[int]]:
    """Closed polyline of a loop (first point not repeated) and where each edge starts."""
    pts, starts = [], []
    for e in loop.edges:
        starts.append(sum(len(p) for p in pts))
        pts.append(_sample(e)[:-1])
    return np.concatenate(pts), starts


def notch_marks(pattern: Pattern, *, length: float = 0.006) -> list[tuple[str, str, np.ndarray,
                                                                           np.ndarray]]:
    """Slit notches at the middle of every seam side, pointing into the fabric.

    Returns ``(panel, seam, point, inner_end)`` per notch, points (2,) [m] in the panel frame;
    the two sides of a seam get one notch each, at matching places.
    """
    out = []
    for seam in pattern.seams:
        for side in (seam.a, seam.b):
            panel = pattern.panel(side.panel)
            edge = panel.edge(side.edge)
            f = 0.5 * (side.start + side.end)
            p, q = edge.point_at([max(f - 1e-4, 0.0), min(f + 1e-4, 1.0)])
            t = q - p
            inward = np.array([-t[1], t[0]]) / max(np.linalg.norm(t), 1e-300)
            loop = next(lp for lp in panel.loops if any(e.name == side.edge for e in lp.edges))
            # the left of a counter-clockwise loop is its inside; fabric lies outside inner loops
            if (loop.signed_area() < 0) != (loop is not panel.outline):
                inward = -inward
            at = edge.point_at([f])[0]
            out.append((panel.name, seam.name, at, at + length * inward))
    return out


def _dxf_document(pattern: Pattern):
    doc = Drawing.new("R12")  # not ezdxf.new(): R12 has no $INSUNITS, the text says the units
    msp = doc.modelspace()
    mm = 1000.0
    used: set[str] = set()
    x = 0.0
    notches = notch_marks(pattern, length=_NOTCH)
    size = str(pattern.meta.get("size", "")) if isinstance(pattern.meta, dict) else ""
    for panel in pattern.panels:
        block = doc.blocks.new(_block_name(panel.name, used))
        loops = [(panel.outline, LAYERS["boundary"])] + \
                [(lp, LAYERS["cutout"]) for lp in panel.inner]
        for loop, layer in loops:
            pts, starts = _loop_points(loop)
            block.add_polyline2d((pts * mm).tolist(), close=True,
                                 dxfattribs={"layer": str(layer)})
            turns = set(starts)
            for i, p in enumerate(pts * mm):
                kind = "turn_points" if i in turns else "curve_points"
                block.add_point((float(p[0]), float(p[1])),
                                dxfattribs={"layer": str(LAYERS[kind])})
        for pname, _, a, b in notches:
            if pname == panel.name:
                block.add_line(tuple(a * mm), tuple(b * mm),
                               dxfattribs={"layer": str(LAYERS["notches"])})
        poly = panel.outline.polygon(16)
        lo, hi = poly.min(axis=0), poly.max(axis=0)
        centre = 0.5 * (lo + hi)
        g = np.asarray(panel.grainline)
        half = 0.3 * float(np.abs(hi - lo) @ np.abs(g))
        block.add_line(tuple((centre - half * g) * mm), tuple((centre + half * g) * mm),
                       dxfattribs={"layer": str(LAYERS["grain"])})
        height = max(3.0, min(12.0, 0.03 * float(np.min(hi - lo)) * mm))
        texts = [f"Piece Name: {panel.name}", f"Size: {size}", "Quantity: 1"]
        for k, text in enumerate(texts):
            at = (centre + np.array([0.02, -0.02]) + np.array([0.0, -0.02]) * k) * mm
            block.add_text(text, dxfattribs={"layer": str(LAYERS["boundary"]),
                                             "height": height, "insert": tuple(at)})
        msp.add_blockref(block.name, ((x - lo[0]) * mm, -lo[1] * mm))
        x += float(hi[0] - lo[0]) + 0.05
    for k, text in enumerate([f"Style Name: {pattern.name}", f"Sample Size: {size}",
                              "Units: METRIC", "Author: patternfit"]):
        msp.add_text(text, dxfattribs={"layer": str(LAYERS["boundary"]), "height": 5.0,
                                       "insert": (0.0, -40.0 - 8.0 * k)})
    return doc


def _sidecar(pattern: Pattern) -> dict:
    panels = {}
    for p in pattern.panels:
        pl = p.placement
        placement: dict[str, Any] = {"part": pl.part, "side": pl.side}
        if pl.translation is not None:
            placement["translation"] = list(pl.translation)
        if pl.rotation is not None:
            placement["rotation"] = list(pl.rotation)
        panels[p.name] = {"edges": [e.name for e in p.outline.edges],
                          "inner": [{"name": lp.name, "edges": [e.name for e in lp.edges]}
                                    for lp in p.inner],
                          "grainline": list(p.grainline), "placement": placement}
    seams = [{"name": s.name, "reverse": s.reverse,
              "a": {"panel": s.a.panel, "edge": s.a.edge, "range": [s.a.start, s.a.end]},
              "b": {"panel": s.b.panel, "edge": s.b.edge, "range": [s.b.start, s.b.end]}}
             for s in pattern.seams]
    return {"format": SIDE_FORMAT, "version": 1, "units": "m", "name": pattern.name,
            "panels": panels, "seams": seams}


def save_dxf(pattern: Pattern, path, *, sidecar: bool = True) -> Path:
    """Write ``pattern`` as DXF-AAMA (R12, millimetres) atomically; with ``sidecar`` also
    write ``<name>.seams.json`` with seams, edge names and placement. Returns the DXF path.

    Seams whose sides differ in length are allowed (:func:`formats.check_imported`)."""
    check_imported(pattern)  # seams of unequal length may come from elsewhere and go back
    stream = io.StringIO()
    gerber_D6673.export_stream(_dxf_document(pattern), stream)
    text = stream.getvalue().encode("ascii", errors="replace").decode("ascii")
    atomic_write_text(path, text)
    if sidecar:
        atomic_write_text(sidecar_path(path), json.dumps(_sidecar(pattern), indent=1) + "\n")
    return Path(path)


# -- import ------------------------------------------------------------------------------------
def _layer(entity) -> int | None:
    name = str(entity.dxf.get("layer", "")).strip()
    return int(name) if name.isdigit() else None


def _why(exc: Exception) -> str:
    """An exception from ezdxf as message text, its kind named once."""
    text, kind = str(exc), type(exc).__name__
    return text if text.startswith(kind) else f"{kind}: {text}"


def _entity_name(entity) -> str:
    return f"{entity.dxftype()} entity (handle {entity.dxf.get('handle', '?')})"


def _within_extent(pts: np.ndarray, entity, where: dict) -> np.ndarray:
    """``pts`` (k, 2) [m], refused when a point is not finite or lies beyond
    ``limits.extent``: checked on a curve's control points, before it is sampled."""
    if len(pts) and not np.isfinite(pts).all():
        raise PatternError(f"{_entity_name(entity)} has a coordinate that is NaN or infinite",
                           **where)
    far = float(np.max(np.abs(pts))) if len(pts) else 0.0
    if far > limits.extent:
        raise PatternError(f"{_entity_name(entity)} reaches {far:.3g} m from the origin, "
                           f"beyond the limit of {limits.extent:g} m", **where)
    return pts


def _entity_points(entity, scale: float, budget: int, where: dict
                   ) -> tuple[np.ndarray, bool] | None:
    """Points [m] of a curve entity and whether it is closed; None for other entities.

    At most ``budget`` points: more (a curve of very many segments) is refused, as is
    geometry beyond ``limits.extent``, before sampling. Repeated points are dropped.
    """
    kind = entity.dxftype()
    if kind == "LINE":
        pts = np.array([tuple(entity.dxf.start)[:2], tuple(entity.dxf.end)[:2]]) * scale
        return _within_extent(pts, entity, where), False
    if kind not in ("POLYLINE", "LWPOLYLINE", "ARC", "CIRCLE", "SPLINE", "ELLIPSE"):
        return None
    try:
        pth = dxfpath.make_path(entity)
    except (TypeError, ValueError):
        return None
    control = np.array([(v.x, v.y) for v in pth.control_vertices()]).reshape(-1, 2)
    _within_extent(control * scale, entity, where)
    if any(cmd.type != dxfpath.Command.LINE_TO for cmd in pth.commands()):
        flat = islice(pth.flattening(tol.dxf_sample / scale / 4), budget + 1)
        pts = np.array([(v.x, v.y) for v in flat]).reshape(-1, 2) * scale
    else:
        pts = control * scale
    if len(pts) > budget:
        raise PatternError(f"{_entity_name(entity)}: the piece's curves make more than "
                           f"{limits.segments_per_panel} points (the segment limit)", **where)
    # CAD tools repeat every turn point (Gerber) and round them (inch files): a segment
    # shorter than tol.dxf_repeat has no direction to fit
    pts = dedupe(pts, closed=False)
    if len(pts) < 2:
        return None
    ends_meet = np.linalg.norm(pts[0] - pts[-1]) < tol.dxf_repeat
    closed = bool(getattr(entity, "is_closed", False)) or kind == "CIRCLE" or ends_meet
    if closed:
        pts = dedupe(pts, closed=True)
    return pts, closed


def _clusters(points: np.ndarray) -> np.ndarray:
    """A cluster number for each point (n, 2) [m]: points within ``tol.dxf_repeat`` of each other
    (and some up to three times that) share one. Linear time, however many coincide."""
    cells = np.floor(points / tol.dxf_repeat).astype(np.int64)
    keys, index = np.unique(cells, axis=0, return_inverse=True)
    index = index.reshape(-1)
    parent = list(range(len(keys)))

    def root(k):
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    where = {tuple(k): n for n, k in enumerate(keys.tolist())}
    for n, (x, y) in enumerate(keys.tolist()):
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                m = where.get((x + dx, y + dy))
                if m is not None:
                    parent[root(m)] = root(n)
    return np.array([root(k) for k in index], dtype=np.int64)


def _chain(pieces: list[tuple[np.ndarray, bool]]) -> list[np.ndarray]:
    """Closed loops from closed entities and from open ones joined end to end.

    Open pieces are taken in file order; each grows at its end by the first free piece
    (in file order) that starts or ends there, until it closes or nothing fits.
    """
    loops = [p for p, closed in pieces if closed and len(p) >= 3]
    open_ = [p for p, closed in pieces if not closed]
    if not open_:
        return loops
    node = _clusters(np.array([[p[0], p[-1]] for p in open_]).reshape(-1, 2))
    at: dict[int, list[int]] = {}  # cluster -> piece ends there (2k: start, 2k + 1: end)
    for end, c in enumerate(node.tolist()):
        at.setdefault(c, []).append(end)
    head = dict.fromkeys(at, 0)
    free = [True] * len(open_)

    def first_free(c: int) -> int | None:
        ends, h = at[c], head[c]
        while h < len(ends) and not free[ends[h] // 2]:
            h += 1
        head[c] = h
        return ends[h] if h < len(ends) else None

    for k, piece in enumerate(open_):
        if not free[k]:
            continue
        free[k] = False
        parts, start, tip, count = [piece], node[2 * k], node[2 * k + 1], len(piece)
        while True:
            if start == tip and count > 3:
                loops.append(np.concatenate(parts)[:-1])
                break
            end = first_free(int(tip))
            if end is None:
                break
            q = open_[end // 2]
            free[end // 2] = False
            parts.append(q[1:] if end % 2 == 0 else q[::-1][1:])
            tip = node[end + 1] if end % 2 == 0 else node[end - 1]
            count += len(q) - 1
    return loops


def _closed_loops(pieces) -> list[np.ndarray]:
    """:func:`_chain`'s loops without repeated points (where pieces join, and the closing
    point), those with fewer than three points left out."""
    loops = [dedupe(q, closed=True) for q in _chain(pieces)]
    return [q for q in loops if len(q) >= 3]


def _area(p: np.ndarray) -> float:
    q = np.roll(p, -1, axis=0)
    return 0.5 * float(np.sum(p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]))


def _texts(entities) -> list[str]:
    out = []
    for e in entities:
        if e.dxftype() in ("TEXT", "ATTRIB", "MTEXT", "ATTDEF"):
            raw = e.dxf.get("text", "") if e.dxftype() != "MTEXT" else e.text
            out.append(str(raw or "").strip())
    return out


def _field(texts: list[str], key: str) -> str | None:
    for t in texts:
        if t.lower().startswith(key.lower() + ":"):
            return t.split(":", 1)[1].strip()
    return None


def _read_piece(block, scale: float, prefer_sew: bool, foreign: bool = True):
    """A piece block's outline, inner loops, grain line, notches and name, or None.

    Every entity is read inside this function's error boundary: whatever ezdxf raises on a
    damaged entity becomes a :class:`PatternError` naming the block and the entity.
    """
    where = {"panel": block.name}
    if len(block) > limits.segments_per_panel:
        raise PatternError(f"the block has {len(block)} entities, more than the limit of "
                           f"{limits.segments_per_panel} (the segment limit)", **where)
    by_layer: dict[int, list] = {}
    points: dict[int, list] = {}
    budget = limits.segments_per_panel
    for e in block:
        try:
            layer = _layer(e)
            if e.dxftype() == "POINT":
                at = np.array(tuple(e.dxf.location)[:2]).reshape(1, 2) * scale
                points.setdefault(layer, []).append(_within_extent(at, e, where)[0])
                continue
            got = _entity_points(e, scale, budget, where)
        except PatternError:
            raise
        except Exception as exc:  # ezdxf raises many kinds on a damaged entity
            raise PatternError(f"{_entity_name(e)} cannot be read: {_why(exc)}",
                               **where) from exc
        if got is not None:
            by_layer.setdefault(layer, []).append(got)
            budget -= len(got[0])
    cut = _closed_loops(by_layer.get(LAYERS["boundary"], []))
    sew = _closed_loops(by_layer.get(LAYERS["sew"], []))
    loops = sew if (prefer_sew and sew) else cut
    if not loops:
        return None
    loops.sort(key=lambda q: -abs(_area(q)))
    turns = np.array(points.get(LAYERS["turn_points"], []) or np.zeros((0, 2))).reshape(-1, 2)
    outline = loop_from_points(loops[0], turns, "outline", "e", foreign=foreign)
    cutouts = _closed_loops(by_layer.get(LAYERS["cutout"], []))
    inner = tuple(loop_from_points(q, turns, f"inner{k}", f"i{k}_e", foreign=foreign)
                  for k, q in enumerate(cutouts))
    grain = (0.0, 1.0)
    for p, _ in by_layer.get(LAYERS["grain"], []):
        d = p[-1] - p[0]
        if np.linalg.norm(d) > 0:
            grain = (float(d[0]), float(d[1]))
            break
    notches = [p[0] for p, _ in by_layer.get(LAYERS["notches"], [])]
    notches += points.get(LAYERS["notches"], [])
    texts = _texts(block)
    return outline, inner, grain, notches, _field(texts, "Piece Name")


def _notch_fractions(panel: Panel, notches: list[np.ndarray]) -> dict[str, list[float]]:
    """Arc-length fractions of the notches on each outline edge they lie on (within
    ``tol.notch_reach``), read off 401 samples of every edge."""
    out: dict[str, list[float]] = {}
    if not notches:
        return out
    f = np.linspace(0, 1, 401)
    edges = panel.outline.edges
    dist, idx = cKDTree(np.concatenate([e.point_at(f) for e in edges])).query(
        np.asarray(notches).reshape(-1, 2))
    for d, k in zip(dist, idx):
        frac = float(f[k % len(f)])
        if d < tol.notch_reach and 0.0 < frac < 1.0:
            out.setdefault(edges[k // len(f)].name, []).append(frac)
    return out


def suggest_seams(pattern: Pattern, notches: dict[str, dict[str, list[float]]] | None = None,
                  ) -> list[Seam]:
    """Seams offered for a pattern without any: pairs of outline edges of equal length
    (``tol.seam_length`` or ``tol.seam_length_rel``) on different panels, notched alike.

    notches : {panel: {edge: [arc-length fractions]}}. Pairs whose notches match (mirrored,
    as on two pieces sewn right side to right side, within ``tol.notch_match``) are offered;
    when the pattern has notches at all, unnotched pairs are not. Each edge is used once;
    ``reverse`` is always True. Each edge is compared with the ``SEAM_WINDOW`` edges next to
    it in length, which keeps the work linear in the number of edges.
    """
    notches = notches or {}
    notched = any(f for per_panel in notches.values() for f in per_panel.values())
    edges = [(p.name, e) for p in pattern.panels for e in p.outline.edges]
    lengths = [e.length for _, e in edges]
    order = sorted(range(len(edges)), key=lengths.__getitem__)
    cands = []
    for pos, i in enumerate(order):
        for j in order[pos + 1:pos + 1 + SEAM_WINDOW]:
            la, lb = lengths[i], lengths[j]
            if abs(la - lb) > max(tol.seam_length, tol.seam_length_rel * 0.5 * (la + lb)):
                break  # sorted by length: every later edge differs more
            (pa, ea), (pb, eb) = edges[min(i, j)], edges[max(i, j)]
            if pa == pb:
                continue
            na = sorted(notches.get(pa, {}).get(ea.name, []))
            nb = sorted(1.0 - f for f in notches.get(pb, {}).get(eb.name, []))
            if len(na) != len(nb) or (notched and not na) or \
                    (na and not np.allclose(na, nb, atol=tol.notch_match)):
                continue
            cands.append((abs(la - lb), pa, ea.name, pb, eb.name))
    cands.sort()
    used: set[tuple[str, str]] = set()
    seams = []
    for _, pa, a, pb, b in cands:
        if (pa, a) in used or (pb, b) in used:
            continue
        used |= {(pa, a), (pb, b)}
        seams.append(Seam(f"s{len(seams)}", SeamSide(pa, a), SeamSide(pb, b), reverse=True))
    return seams


def _renamed(loop: Loop, name: str, names, where: dict) -> Loop:
    """``loop`` called ``name``, its edges renamed by the side file's list ``names`` (None:
    keep them)."""
    if names is None:
        return replace(loop, name=name)
    if len(names) != len(loop.edges):
        raise PatternError(f"side file names {len(names)} edges for loop '{loop.name}' "
                           f"but the DXF piece has {len(loop.edges)}",
                           edge=loop.edges[0].name, **where)
    for k, n in enumerate(names):
        if not isinstance(n, str) or not n:
            raise PatternError(f"side file: edge name #{k} of loop '{loop.name}' must be a "
                               f"non-empty string, got {shown(n)}", **where)
    return Loop(name, tuple(replace(e, name=n) for n, e in zip(names, loop.edges)))


def _with_sidecar(pattern: Pattern, side: Any) -> Pattern:
    """``pattern`` with the side file's edge names, placement, grain line and seams."""
    if not isinstance(side, dict):
        raise PatternError("side file must be a JSON object")
    if side.get("format") != SIDE_FORMAT:
        raise PatternError(f"not a patternfit DXF side file (format "
                           f"{shown(side.get('format'))})")
    info = json_field(side, "panels", dict, "side file", {})
    panels = []
    for p in pattern.panels:
        where = {"panel": p.name}
        d = json_field(info, p.name, dict, "side file 'panels'", {}, **where)
        inner = json_field(d, "inner", list, "side file panel", [], **where)
        loops = [_renamed(p.outline, p.outline.name,
                          json_field(d, "edges", list, "side file panel", None, **where), where)]
        for k, loop in enumerate(p.inner):
            lp = inner[k] if k < len(inner) else {}
            what = f"side file inner loop #{k}"
            loops.append(_renamed(loop, json_field(lp, "name", str, what, loop.name, **where),
                                  json_field(lp, "edges", list, what, None, **where), where))
        pl = json_field(d, "placement", dict, "side file panel", {}, **where)
        placement = Placement(
            part=json_field(pl, "part", str, "placement", p.placement.part, **where),
            side=json_field(pl, "side", str, "placement", p.placement.side, **where),
            translation=json_vec3(pl.get("translation"), 1.0, "placement translation", **where),
            rotation=json_vec3(pl.get("rotation"), 1.0, "placement rotation", **where))
        grain = json_point(d.get("grainline", p.grainline), 1.0, "grainline", **where)
        panels.append(Panel(p.name, loops[0], tuple(loops[1:]), grain, placement))
    outline_edges = {p.name: [e.name for e in p.outline.edges] for p in panels}
    seams = seams_from_json(json_field(side, "seams", list, "side file", []), prefix="s",
                            outline_edges=outline_edges)
    return Pattern(json_field(side, "name", str, "side file", pattern.name), tuple(panels),
                   seams, dict(pattern.meta))


def _document(data: bytes):
    """The ezdxf document in a DXF file's bytes (ASCII in its own code page, or binary)."""
    if data.startswith(_BINARY_DXF):
        return Drawing.load(binary_tags_loader(data, errors="surrogateescape"))
    text = data.decode("utf-8", errors="ignore")  # the header's code page is plain ASCII
    if not is_dxf_stream(io.StringIO(text)):
        raise PatternError("not a DXF file (it does not start with a DXF section)")
    encoding = dxf_stream_info(io.StringIO(text)).encoding
    return Drawing.read(io.StringIO(data.decode(encoding, errors="surrogateescape"),
                                    newline=None))


def _read_dxf(path: Path, units: str | None, prefer_sew: bool):
    """The pattern (no seams) and notch fractions of a DXF file; errors without the file."""
    data = read_bytes_capped(path, limit=limits.dxf_bytes, error=PatternError)
    doc = _document(data)
    # ezdxf makes up a header (metres) for a file without one: only what the file says counts
    said = {v for v in ("$INSUNITS", "$MEASUREMENT") if v.encode() in data}
    msp_texts = _texts(doc.modelspace())
    blocks = [b for b in doc.blocks if not b.name.startswith("*")]
    scale, unit_says = _file_scale(doc, said, msp_texts, blocks) if units is None else \
        (UNITS[units], f"units={units!r}")
    # our own files keep an edge between every two turn points (exact round trip)
    foreign = (_field(msp_texts, "Author") or "") != "patternfit"
    # count the blocks that can be pieces before fitting any
    drawn = sum(any(_layer(e) in _PIECE_LAYERS for e in b) for b in blocks)
    if drawn > limits.panels:
        raise PatternError(f"the DXF has {drawn} blocks with a boundary, more than the limit "
                           f"of {limits.panels} panels")
    panels, notch_map, names = [], {}, set()
    for block in blocks:
        try:
            piece = _read_piece(block, scale, prefer_sew, foreign)
        except PatternError:
            raise
        except Exception as exc:  # a fit that fails on damaged geometry, of whatever kind
            raise PatternError(f"piece cannot be read: {_why(exc)}", panel=block.name) from exc
        if piece is None:
            continue
        outline, inner, grain, notches, pname = piece
        name = pname or block.name
        while name in names:
            name += "_2"
        names.add(name)
        panel = Panel(name, outline, inner, grain)
        panels.append(panel)
        notch_map[name] = _notch_fractions(panel, notches)
    if not panels:
        raise PatternError("the DXF has no pattern pieces (no block with a closed boundary "
                           "on layer 1)")
    style = _field(msp_texts, "Style Name") or path.stem
    meta: dict[str, Any] = {"source_format": "dxf-aama"}
    size = _field(msp_texts, "Sample Size")
    if size:
        meta["size"] = size
    warnings = _size_warnings(panels, scale, unit_says)
    if warnings:
        meta["warnings"] = warnings
    pattern = Pattern(style, tuple(panels), (), meta)
    check_pattern(pattern)
    return pattern, notch_map


def _file_scale(doc, said: set[str], msp_texts: list[str], blocks) -> tuple[float, str]:
    """Metres per file unit, and what said so: the AAMA ``Units:`` text (in the entities,
    else in a piece block), else ``$INSUNITS`` (when the header has it and it is a length),
    else ``$MEASUREMENT`` (0 inches, 1 millimetres), else millimetres."""
    word = _field(msp_texts, "Units")
    if word is None:
        for block in blocks:
            word = _field(_texts(block), "Units")
            if word is not None:
                break
    if word is not None and word.strip().upper() in _UNIT:
        word = word.strip().upper()
        return _UNIT[word], f"the text 'Units: {word}'"
    if "$INSUNITS" in said and doc.header.get("$INSUNITS") in _INSUNITS:
        code = doc.header.get("$INSUNITS")
        return _INSUNITS[code], f"$INSUNITS = {code}"
    if "$MEASUREMENT" in said and doc.header.get("$MEASUREMENT") in (0, 1):
        code = doc.header.get("$MEASUREMENT")
        return (0.0254, 0.001)[code], f"$MEASUREMENT = {code}"
    return 0.001, "no unit in the file (millimetres assumed)"


_UNIT_NAMES = {0.001: "mm", 0.01: "cm", 0.0254: "in", 0.3048: "ft", 1.0: "m"}


def _size_warnings(panels, scale: float, unit_says: str) -> list[str]:
    """A warning for every piece whose size is implausible for a garment piece in the unit
    read (``PLAUSIBLE``), naming the units that would make it plausible."""
    out = []
    lo, hi = PLAUSIBLE
    for panel in panels:
        poly = panel.outline.polygon(8)
        size = float(np.max(poly.max(axis=0) - poly.min(axis=0)))
        if lo <= size <= hi:
            continue
        fits = [u for u, m in UNITS.items() if lo <= size / scale * m <= hi]
        unit = _UNIT_NAMES.get(scale, f"{scale:g} m")
        out.append(f"panel '{panel.name}' is {size:.3g} m across, read in {unit} ({unit_says}):"
                   f" implausible for a garment piece (expected {lo:g} to {hi:g} m); "
                   + (f"as {' or '.join(fits)} it would be {size / scale * UNITS[fits[0]]:.3g}"
                      f" m (load_dxf(..., units={fits[0]!r}))" if fits else
                      "check the file's units"))
    return out


def load_dxf(path, *, sidecar=None, units: str | None = None, prefer_sew: bool = True
             ) -> Pattern:
    """Read a DXF-AAMA file into a :class:`Pattern` [m].

    sidecar : side file with seams, edge names and placement; by default ``<name>.seams.json``
        beside the DXF when it exists. Without one, ``meta["suggested_seams"]`` lists seams
        offered by :func:`suggest_seams` and the pattern has none.
    units : ``"mm"``, ``"cm"``, ``"in"`` or ``"m"`` to override the file's (``Units:`` style
        text, else ``$INSUNITS``, else millimetres).

    Every problem with the file is a :class:`PatternError` naming the file (the DXF or the
    side file) and where known the piece, the entity or the side file's key: a file that is
    not DXF, damaged or larger than ``limits.dxf_bytes``; geometry beyond ``limits.extent``
    (refused before any curve is sampled), more entities or points in a piece than
    ``limits.segments_per_panel``, more pieces than ``limits.panels``; no pieces; whatever
    :func:`~patternfit.pattern.check_pattern` refuses.
    """
    if units is not None and units not in UNITS:
        raise ValueError(f"units: expected one of {sorted(UNITS)}, got {units!r}")
    path = Path(path)
    try:
        pattern, notch_map = _read_dxf(path, units, prefer_sew)
    except PatternError as exc:
        raise exc.located(path) from None
    except Exception as exc:  # ezdxf raises many kinds on a damaged file
        raise PatternError(f"cannot read DXF: {_why(exc)}", file=path) from exc
    side_path = Path(sidecar) if sidecar is not None else sidecar_path(path)
    if sidecar is not None or side_path.exists():
        side = read_json_file(side_path, error=PatternError)
        try:
            out = _with_sidecar(pattern, side)
            warnings = check_imported(out)
        except PatternError as exc:
            raise exc.located(side_path) from None
        warnings = list(pattern.meta.get("warnings", [])) + list(warnings)
        if warnings:
            out.meta["warnings"] = warnings
        return out
    pattern.meta["notches"] = notch_map
    pattern.meta["suggested_seams"] = [
        {"name": s.name, "reverse": s.reverse,
         "a": {"panel": s.a.panel, "edge": s.a.edge}, "b": {"panel": s.b.panel, "edge": s.b.edge}}
        for s in suggest_seams(pattern, notch_map)]
    return pattern
