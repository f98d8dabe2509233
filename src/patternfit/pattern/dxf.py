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

Import splits each closed outline at its turn points (or, without any, at corners) and turns
each run of points back into a line, a circular arc or a cubic Bézier when the fit stays within
0.05 mm, else into a chain of shorter curves. A closed sew line (layer 14) is preferred to the
cut line as the outline, since sewing happens there. Seams come from the side file; without
one, seams are suggested (``meta["suggested_seams"]``) from edge pairs of equal length with
matching notches. Everything inside is metres.
"""

from __future__ import annotations

import io
import json
import math
import re
from pathlib import Path
from typing import Any

import numpy as np

from ..constants import tol
from ..files import atomic_write_text
from .edges import Edge
from .errors import PatternError
from .model import Loop, Panel, Pattern, Placement, Seam, SeamSide
from .formats import check_imported
from .validate import check_pattern

__all__ = ["LAYERS", "load_dxf", "notch_marks", "save_dxf", "sidecar_path", "suggest_seams"]

#: ASTM D6673 layer numbers by meaning.
LAYERS = {"boundary": 1, "turn_points": 2, "curve_points": 3, "notches": 4,
          "grade_reference": 5, "mirror": 6, "grain": 7, "internal": 8, "stripe": 9,
          "plaid": 10, "cutout": 11, "drill_holes": 13, "sew": 14, "annotation": 15}

SIDE_FORMAT = "patternfit-dxf-sidecar"
#: how far a re-fitted edge may stray from the file's points [m]
FIT_TOL = 5e-5
#: how far an exported polyline may stray from the curve [m]
SAMPLE_TOL = 2e-5
_NOTCH = 0.006  # notch slit length [m]
_UNIT = {"METRIC": 0.001, "ENGLISH": 0.0254}
_INSUNITS = {1: 0.0254, 2: 0.3048, 4: 0.001, 5: 0.01, 6: 1.0}


def sidecar_path(path) -> Path:
    """The side file that goes with a DXF file: ``x.dxf`` -> ``x.seams.json``."""
    path = Path(path)
    return path.with_name(path.stem + ".seams.json")


# -- export ------------------------------------------------------------------------------------
def _sample(edge: Edge) -> np.ndarray:
    """Points along an edge, the polyline within ``SAMPLE_TOL`` of the curve: (k, 2) [m]."""
    if edge.kind == "line":
        return np.array(edge.points)
    n = 8
    while True:
        f = np.linspace(0.0, 1.0, 2 * n + 1)
        p = edge.point_at(f)
        chord_mid = 0.5 * (p[0:-1:2] + p[2::2])
        if np.max(np.linalg.norm(p[1::2] - chord_mid, axis=1)) < SAMPLE_TOL or n >= 1024:
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
    from ezdxf.document import Drawing

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
    from ezdxf.addons import gerber_D6673

    check_imported(pattern)  # seams of unequal length may come from elsewhere and go back
    stream = io.StringIO()
    gerber_D6673.export_stream(_dxf_document(pattern), stream)
    text = stream.getvalue().encode("ascii", errors="replace").decode("ascii")
    atomic_write_text(path, text)
    if sidecar:
        atomic_write_text(sidecar_path(path), json.dumps(_sidecar(pattern), indent=1) + "\n")
    return Path(path)


# -- fitting -----------------------------------------------------------------------------------
def _line_dev(p: np.ndarray) -> float:
    d = p[-1] - p[0]
    n = np.linalg.norm(d)
    if n == 0:
        return float(np.max(np.linalg.norm(p - p[0], axis=1)))
    return float(np.max(np.abs((p[:, 0] - p[0, 0]) * d[1] - (p[:, 1] - p[0, 1]) * d[0]) / n))


def _fit_arc(name: str, p: np.ndarray) -> tuple[Edge, float] | None:
    """The circular arc through the ends and middle of ``p`` (k, 2) [m] and its largest
    distance to ``p``, or None when the points do not run round one centre."""
    a, b, c = p[0], p[len(p) // 2], p[-1]
    m = np.array([b - a, c - a]) * 2
    det = np.linalg.det(m)
    if abs(det) < 1e-18:
        return None
    centre = np.linalg.solve(m, [b @ b - a @ a, c @ c - a @ a])
    r = float(np.linalg.norm(a - centre))
    dev = float(np.max(np.abs(np.linalg.norm(p - centre, axis=1) - r)))
    ang = np.unwrap(np.arctan2(p[:, 1] - centre[1], p[:, 0] - centre[0]))
    steps = np.diff(ang)
    if not (np.all(steps > 0) or np.all(steps < 0)):
        return None
    span = float(ang[-1] - ang[0])
    return Edge.arc(name, a, c, r, large_arc=abs(span) > math.pi, sweep=span > 0), dev


def _bezier(c: np.ndarray, t: np.ndarray):
    """Points, derivatives and control-point weights of a cubic Bézier c (4, 2) at t (k,)."""
    u = 1 - t
    w = np.column_stack([u**3, 3 * u * u * t, 3 * u * t * t, t**3])
    d = 3 * ((u * u)[:, None] * (c[1] - c[0]) + (2 * u * t)[:, None] * (c[2] - c[1])
             + (t * t)[:, None] * (c[3] - c[2]))
    return w @ c, d, w


def _fit_cubic(name: str, p: np.ndarray, iterations: int = 100) -> tuple[Edge, float]:
    """Least-squares cubic Bézier through ``p`` (k, 2) [m] with fixed ends; returns it and
    the largest distance from a point of ``p`` to the curve [m].

    Control points and the points' curve parameters are solved together (Levenberg-Marquardt,
    the parameters eliminated by a Schur complement): fitting the control points alone and
    re-projecting stalls on curves whose speed varies a lot.
    """
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])
    t = s / s[-1]
    u = 1 - t
    rhs = p - np.outer(u**3, p[0]) - np.outer(t**3, p[-1])
    inner, *_ = np.linalg.lstsq(np.column_stack([3 * u * u * t, 3 * u * t * t]), rhs,
                                rcond=None)
    c = np.array([p[0], inner[0], inner[1], p[-1]])

    def cost(c, t):
        return float(np.sum((_bezier(c, t)[0] - p) ** 2))

    lam, now = 1e-3 * s[-1] ** 2, cost(c, t)
    for _ in range(iterations):
        q, d, w = _bezier(c, t)
        r = (q - p)[1:-1]
        d, w = d[1:-1], w[1:-1, 1:3]
        jc = np.zeros((len(r), 2, 4))  # d residual / d (c1x, c1y, c2x, c2y)
        jc[:, 0, 0] = jc[:, 1, 1] = w[:, 0]
        jc[:, 0, 2] = jc[:, 1, 3] = w[:, 1]
        hcc = np.einsum("kai,kaj->ij", jc, jc) + lam * np.eye(4)
        gc = np.einsum("kai,ka->i", jc, r)
        hct = np.einsum("kai,ka->ki", jc, d)
        ht = np.einsum("ka,ka->k", d, d) + lam
        gt = np.einsum("ka,ka->k", d, r)
        schur = hcc - np.einsum("ki,kj,k->ij", hct, hct, 1 / ht)
        dc = -np.linalg.solve(schur, gc - hct.T @ (gt / ht))
        dt = -(gt + hct @ dc) / ht
        c_new = c.copy()
        c_new[1:3] += dc.reshape(2, 2)
        t_new = t.copy()
        t_new[1:-1] = np.clip(t[1:-1] + dt, 0.0, 1.0)
        new = cost(c_new, t_new)
        if new < now:
            done = now - new < 1e-14 * max(now, 1e-300) or new < 1e-24
            c, t, now, lam = c_new, t_new, new, lam / 3
            if done:
                break
        else:
            lam *= 4
    edge = Edge.cubic(name, *c)
    return edge, float(np.max(np.linalg.norm(edge.evaluate(t) - p, axis=1)))


def _fit_one(name: str, p: np.ndarray) -> Edge | None:
    """The simplest edge (line, quadratic or cubic Bézier, arc) within ``FIT_TOL`` of all of
    ``p`` (k, 2) [m], or None. Between an arc and a cubic the closer one wins."""
    if len(p) == 2 or _line_dev(p) < FIT_TOL:
        return Edge.line(name, p[0], p[-1])
    if len(p) < 4:
        return None
    cubic, dev = _fit_cubic(name, p)
    arc = _fit_arc(name, p)
    if arc is not None and arc[1] < min(dev, FIT_TOL):
        return arc[0]
    if dev >= FIT_TOL:
        return None
    c = np.asarray(cubic.points)
    q1, q2 = (3 * c[1] - c[0]) / 2, (3 * c[2] - c[3]) / 2  # a raised quadratic has q1 == q2
    if np.linalg.norm(q1 - q2) < FIT_TOL:
        return Edge.quadratic(name, c[0], 0.5 * (q1 + q2), c[3])
    return cubic


def _fit_run(p: np.ndarray, names: list[str]) -> list[Edge]:
    """Edges through one run of points (k, 2) [m], split where a single curve does not fit."""
    edge = _fit_one(f"e{len(names)}", p)
    if edge is not None:
        names.append(edge.name)
        return [edge]
    if len(p) <= 3:
        out = []
        for a, b in zip(p[:-1], p[1:]):
            names.append(f"e{len(names)}")
            out.append(Edge.line(names[-1], a, b))
        return out
    mid = len(p) // 2
    return _fit_run(p[: mid + 1], names) + _fit_run(p[mid:], names)


def _corners(p: np.ndarray, angle: float = 25.0) -> list[int]:
    """Indices of the closed polygon's vertices that turn by more than ``angle`` degrees."""
    a = p - np.roll(p, 1, axis=0)
    b = np.roll(p, -1, axis=0) - p
    cos = np.einsum("ij,ij->i", a, b) / np.maximum(
        np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1), 1e-300)
    return [int(i) for i in np.flatnonzero(cos < math.cos(math.radians(angle)))]


def _loop_from_points(p: np.ndarray, turns: np.ndarray, name: str, prefix: str) -> Loop:
    """Split a closed polygon (k, 2) at its turn points and fit every run."""
    d = np.linalg.norm(p[:, None] - turns[None], axis=2) if len(turns) else np.zeros((len(p), 0))
    breaks = sorted(np.flatnonzero(d.min(axis=1) < 5e-5).tolist()) if len(turns) else []
    if not breaks:
        breaks = _corners(p) or [0]
    p = np.roll(p, -breaks[0], axis=0)
    breaks = [(b - breaks[0]) % len(p) for b in breaks] + [len(p)]
    closed = np.vstack([p, p[:1]])
    names: list[str] = []
    edges: list[Edge] = []
    for b0, b1 in zip(breaks[:-1], breaks[1:]):
        edges += _fit_run(closed[b0:b1 + 1], names)
    if len(edges) == 1:  # a loop needs at least two edges: split the single one in halves
        half = len(p) // 2
        names = []
        edges = _fit_run(closed[: half + 1], names) + _fit_run(closed[half:], names)
    renamed = tuple(Edge(f"{prefix}{k}", e.kind, e.points, e.radius, e.large_arc, e.sweep)
                    for k, e in enumerate(edges))
    return Loop(name, renamed)


# -- import ------------------------------------------------------------------------------------
def _layer(entity) -> int | None:
    name = str(entity.dxf.get("layer", "")).strip()
    return int(name) if name.isdigit() else None


def _entity_points(entity, scale: float) -> tuple[np.ndarray, bool] | None:
    """Points [m] of a curve entity and whether it is closed; None for other entities."""
    from ezdxf import path as dxfpath

    kind = entity.dxftype()
    if kind == "LINE":
        return np.array([tuple(entity.dxf.start)[:2], tuple(entity.dxf.end)[:2]]) * scale, False
    if kind not in ("POLYLINE", "LWPOLYLINE", "ARC", "CIRCLE", "SPLINE", "ELLIPSE"):
        return None
    try:
        pth = dxfpath.make_path(entity)
    except (TypeError, ValueError):
        return None
    has_curves = any(cmd.type != dxfpath.Command.LINE_TO for cmd in pth.commands())
    pts = np.array([(v.x, v.y) for v in (pth.flattening(SAMPLE_TOL / scale / 4)
                                         if has_curves else pth.control_vertices())])
    if len(pts) < 2:
        return None
    closed = bool(getattr(entity, "is_closed", False)) or kind == "CIRCLE" or \
        np.linalg.norm(pts[0] - pts[-1]) * scale < 1e-6
    if np.linalg.norm(pts[0] - pts[-1]) * scale < 1e-6 and len(pts) > 2:
        pts = pts[:-1]
    return pts * scale, closed


def _chain(pieces: list[tuple[np.ndarray, bool]]) -> list[np.ndarray]:
    """Closed loops from closed entities and from open ones joined end to end."""
    loops = [p for p, closed in pieces if closed and len(p) >= 3]
    open_ = [p for p, closed in pieces if not closed]
    while open_:
        cur = open_.pop(0)
        grown = True
        while grown:
            grown = False
            if np.linalg.norm(cur[0] - cur[-1]) < 1e-6 and len(cur) > 3:
                loops.append(cur[:-1])
                break
            for i, q in enumerate(open_):
                if np.linalg.norm(cur[-1] - q[0]) < 1e-6:
                    cur = np.vstack([cur, q[1:]])
                elif np.linalg.norm(cur[-1] - q[-1]) < 1e-6:
                    cur = np.vstack([cur, q[::-1][1:]])
                else:
                    continue
                open_.pop(i)
                grown = True
                break
    return loops


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


def _read_piece(block, scale: float, prefer_sew: bool):
    """A piece block's outline, inner loops, grain line, notches and name, or None."""
    by_layer: dict[int, list] = {}
    points: dict[int, list] = {}
    for e in block:
        layer = _layer(e)
        if e.dxftype() == "POINT":
            points.setdefault(layer, []).append(np.array(tuple(e.dxf.location)[:2]) * scale)
            continue
        got = _entity_points(e, scale)
        if got is not None:
            by_layer.setdefault(layer, []).append(got)
    cut = _chain(by_layer.get(LAYERS["boundary"], []))
    sew = _chain(by_layer.get(LAYERS["sew"], []))
    loops = sew if (prefer_sew and sew) else cut
    if not loops:
        return None
    loops.sort(key=lambda q: -abs(_area(q)))
    turns = np.array(points.get(LAYERS["turn_points"], []) or np.zeros((0, 2))).reshape(-1, 2)
    outline = _loop_from_points(loops[0], turns, "outline", "e")
    cutouts = _chain(by_layer.get(LAYERS["cutout"], []))
    inner = tuple(_loop_from_points(q, turns, f"inner{k}", f"i{k}_e")
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
    """Arc-length fractions of the notches on each outline edge they lie on (within 1 mm)."""
    out: dict[str, list[float]] = {}
    for q in notches:
        best = None
        for e in panel.outline.edges:
            f = np.linspace(0, 1, 401)
            d = np.linalg.norm(e.point_at(f) - q, axis=1)
            k = int(np.argmin(d))
            if d[k] < 1e-3 and (best is None or d[k] < best[0]):
                best = (d[k], e.name, float(f[k]))
        if best is not None and 0.0 < best[2] < 1.0:
            out.setdefault(best[1], []).append(best[2])
    return out


def suggest_seams(pattern: Pattern, notches: dict[str, dict[str, list[float]]] | None = None,
                  ) -> list[Seam]:
    """Seams offered for a pattern without any: pairs of outline edges of equal length
    (``tol.seam_length`` or ``tol.seam_length_rel``) on different panels, notched alike.

    notches : {panel: {edge: [arc-length fractions]}}. Pairs whose notches match (mirrored,
    as on two pieces sewn right side to right side) are offered; when the pattern has notches
    at all, unnotched pairs are not. Each edge is used once; ``reverse`` is always True.
    """
    notches = notches or {}
    notched = any(f for per_panel in notches.values() for f in per_panel.values())
    edges = [(p.name, e) for p in pattern.panels for e in p.outline.edges]
    cands = []
    for i, (pa, ea) in enumerate(edges):
        for pb, eb in edges[i + 1:]:
            if pa == pb:
                continue
            la, lb = ea.length, eb.length
            if abs(la - lb) > max(tol.seam_length, tol.seam_length_rel * 0.5 * (la + lb)):
                continue
            na = sorted(notches.get(pa, {}).get(ea.name, []))
            nb = sorted(1.0 - f for f in notches.get(pb, {}).get(eb.name, []))
            if len(na) != len(nb) or not np.allclose(na, nb, atol=0.02) or (notched and not na):
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


def _apply_sidecar(pattern: Pattern, side: Any, file) -> Pattern:
    if not isinstance(side, dict) or side.get("format") != SIDE_FORMAT:
        raise PatternError(f"not a patternfit DXF side file (format {side.get('format')!r})"
                           if isinstance(side, dict) else "side file must be a JSON object",
                           file=file)
    info = side.get("panels", {})
    panels = []
    for p in pattern.panels:
        d = info.get(p.name, {})
        loops = [p.outline, *p.inner]
        wanted = [d.get("edges")] + [lp.get("edges") if isinstance(lp, dict) else None
                                     for lp in d.get("inner", [])]
        new_loops = []
        for k, loop in enumerate(loops):
            names = wanted[k] if k < len(wanted) else None
            if names is None:
                new_loops.append(loop)
                continue
            if len(names) != len(loop.edges):
                raise PatternError(f"side file names {len(names)} edges for loop '{loop.name}' "
                                   f"but the DXF piece has {len(loop.edges)}", file=file,
                                   panel=p.name, edge=loop.edges[0].name)
            lname = loop.name if k == 0 else d["inner"][k - 1].get("name", loop.name)
            new_loops.append(Loop(lname, tuple(
                Edge(str(n), e.kind, e.points, e.radius, e.large_arc, e.sweep)
                for n, e in zip(names, loop.edges))))
        pl = d.get("placement", {})
        placement = Placement(
            part=str(pl.get("part", p.placement.part)), side=str(pl.get("side", p.placement.side)),
            translation=tuple(pl["translation"]) if pl.get("translation") else None,
            rotation=tuple(pl["rotation"]) if pl.get("rotation") else None)
        grain = tuple(d.get("grainline", p.grainline))
        panels.append(Panel(p.name, new_loops[0], tuple(new_loops[1:]), grain, placement))
    out = Pattern(str(side.get("name", pattern.name)), tuple(panels), (), dict(pattern.meta))
    seams = []
    for i, s in enumerate(side.get("seams", [])):
        sides = []
        for key in ("a", "b"):
            d = s.get(key, {}) if isinstance(s, dict) else {}
            pname, edge = d.get("panel"), d.get("edge")
            try:
                panel = out.panel(str(pname))
            except KeyError:
                raise PatternError(f"side file seam #{i} names missing panel {pname!r}",
                                   file=file, panel=str(pname)) from None
            if isinstance(edge, int) and not isinstance(edge, bool):
                if not 0 <= edge < len(panel.outline.edges):
                    raise PatternError(f"side file seam #{i}: edge index {edge} out of range",
                                       file=file, panel=panel.name, edge=str(edge))
                edge = panel.outline.edges[edge].name
            rng = d.get("range", [0.0, 1.0])
            sides.append(SeamSide(panel.name, str(edge), float(rng[0]), float(rng[1])))
        seams.append(Seam(str(s.get("name", f"s{i}")), sides[0], sides[1],
                          bool(s.get("reverse", True))))
    out = Pattern(out.name, out.panels, tuple(seams), out.meta)
    try:
        warnings = check_imported(out)
    except PatternError as exc:
        raise exc.located(file) from None
    if warnings:
        out.meta["warnings"] = warnings
    return out


def load_dxf(path, *, sidecar=None, units: str | None = None, prefer_sew: bool = True
             ) -> Pattern:
    """Read a DXF-AAMA file into a :class:`Pattern` [m].

    sidecar : side file with seams, edge names and placement; by default ``<name>.seams.json``
        beside the DXF when it exists. Without one, ``meta["suggested_seams"]`` lists seams
        offered by :func:`suggest_seams` and the pattern has none.
    units : ``"mm"``, ``"cm"``, ``"in"`` or ``"m"`` to override the file's (``Units:`` style
        text, else ``$INSUNITS``, else millimetres).
    Raises :class:`PatternError` naming the file (and piece) for a file that cannot be read or
    has no pieces.
    """
    import ezdxf

    from ..constants import UNITS

    path = Path(path)
    try:
        doc = ezdxf.readfile(str(path))
    except (OSError, ezdxf.DXFError) as exc:
        raise PatternError(f"cannot read DXF: {exc}", file=path) from None
    msp_texts = _texts(doc.modelspace())
    if units is not None:
        if units not in UNITS:
            raise ValueError(f"units: expected one of {sorted(UNITS)}, got {units!r}")
        scale = UNITS[units]
    else:
        word = (_field(msp_texts, "Units") or "").upper()
        scale = _UNIT.get(word) or _INSUNITS.get(doc.header.get("$INSUNITS", 4), 0.001)
    panels, notch_map, names = [], {}, set()
    for block in doc.blocks:
        if block.name.startswith("*"):
            continue
        try:
            piece = _read_piece(block, scale, prefer_sew)
        except (PatternError, ValueError, np.linalg.LinAlgError) as exc:
            raise PatternError(f"piece cannot be read: {exc}", file=path,
                               panel=block.name) from None
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
                           "on layer 1)", file=path)
    style = _field(msp_texts, "Style Name") or path.stem
    meta: dict[str, Any] = {"source_format": "dxf-aama"}
    size = _field(msp_texts, "Sample Size")
    if size:
        meta["size"] = size
    pattern = Pattern(style, tuple(panels), (), meta)
    try:
        check_pattern(pattern)
    except PatternError as exc:
        raise exc.located(path) from None
    side_path = Path(sidecar) if sidecar is not None else sidecar_path(path)
    if sidecar is not None or side_path.exists():
        try:
            side = json.loads(side_path.read_text(encoding="utf-8"))
        except (OSError, json.JSONDecodeError) as exc:
            raise PatternError(f"cannot read side file: {exc}", file=side_path) from None
        return _apply_sidecar(pattern, side, side_path)
    pattern.meta["notches"] = notch_map
    pattern.meta["suggested_seams"] = [
        {"name": s.name, "reverse": s.reverse,
         "a": {"panel": s.a.panel, "edge": s.a.edge}, "b": {"panel": s.b.panel, "edge": s.b.edge}}
        for s in suggest_seams(pattern, notch_map)]
    return pattern
