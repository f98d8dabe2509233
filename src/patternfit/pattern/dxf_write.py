"""Writing DXF-AAMA (R12, millimetres): every panel as a piece block, every other size of a
graded pattern as the file drew it, through ezdxf's Gerber writer
(``ezdxf.addons.gerber_D6673``, which Gerber's strict parser accepts).

A panel's block holds the cut line on layer 1 (its ``cut_line`` when it has one, else the
outline) and then the outline as the sew line on layer 14; curves sampled so that the polyline
stays within ``tol.dxf_sample`` of them; a turn point (layer 2) at every edge end, curve
points (layer 3) between; notches as 6 mm slits into the fabric (layer 4: the panel's own,
else one at the middle of every seam side); internal lines (layer 8), drill holes (layer 13),
inner loops as cut-outs (layer 11), the grain line (layer 7) and the piece text (``Piece
Name``, ``Size``, ``Quantity``). A left/right pair (``meta["pairs"]``) whose right panel is
still the left one turned over is written once with ``Quantity: 2``.
"""

from __future__ import annotations

import io
import re

import numpy as np
from ezdxf.addons import gerber_D6673
from ezdxf.document import Drawing
from matplotlib.path import Path as MplPath

from ..constants import tol
from .dxf_format import LAYERS, RawPiece
from .dxf_grades import graded_pieces
from .dxf_notches import notch_marks, notch_slits
from .dxf_pieces import mirrored
from .edges import Edge
from .model import Loop, Panel, Pattern

__all__ = ["dxf_text", "piece_of"]

_MM = 1000.0
_NOTCH = 0.006  # notch slit length [m]


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


def _loop_points(loop: Loop) -> tuple[np.ndarray, np.ndarray]:
    """Closed polyline of a loop (first point not repeated) and its edges' start points."""
    pts = [_sample(e)[:-1] for e in loop.edges]
    return np.concatenate(pts), np.array([e.start for e in loop.edges])


def _cut_line_holds(panel: Panel) -> bool:
    """Whether the panel's cut line still surrounds its outline (an edit of the outline may
    have moved it past the cut line; such a cut line is not written)."""
    if not panel.cut_line:
        return False
    ring = MplPath(np.asarray(panel.cut_line))
    return bool(ring.contains_points(panel.outline.polygon(16), radius=-tol.dxf_fit).all()
                or ring.contains_points(panel.outline.polygon(16), radius=tol.dxf_fit).all())


def piece_of(panel: Panel, size: str | None, notches: list[np.ndarray], *, name: str | None = None,
             quantity: int = 1) -> RawPiece:
    """The DXF piece of a panel [m]: cut line and sew line, turn points, ``notches`` ((2, 2)
    slits), internal lines, drill holes, cut-outs, grain line and text."""
    outline, turns = _loop_points(panel.outline)
    inner = [_loop_points(lp) for lp in panel.inner]
    with_cut = _cut_line_holds(panel)
    return RawPiece(
        name or panel.name, name or panel.name, size, quantity,
        cut=[np.asarray(panel.cut_line)] if with_cut else [outline],
        sew=[outline] if with_cut else [],
        cutouts=[p for p, _ in inner],
        turns=np.vstack([turns] + [t for _, t in inner]), notches=notches,
        lines=[np.asarray(ln.points) for ln in panel.lines],
        drills=np.asarray(panel.drill_holes).reshape(-1, 2), grain=panel.grainline)


def _block_name(name: str, used: set[str]) -> str:
    base = re.sub(r"[^A-Za-z0-9_\-]", "_", name) or "piece"
    out, k = base, 1
    while out.upper() in used:
        k += 1
        out = f"{base}_{k}"
    used.add(out.upper())
    return out


def _add_piece(doc, piece: RawPiece, used: set[str], graded: bool):
    """A block drawing ``piece`` (lengths in mm), named with its size in a ``graded`` file;
    returns it and the piece's bounding box."""
    name = piece.name or piece.block
    block = doc.blocks.new(_block_name(f"{name}_{piece.size}" if graded and piece.size
                                       else name, used))

    def at(p):
        return tuple(float(c) for c in np.asarray(p) * _MM)

    def layer(key):
        return {"layer": str(LAYERS[key])}

    turns = np.asarray(piece.turns).reshape(-1, 2)
    for key, loops in (("boundary", piece.cut), ("sew", piece.sew), ("cutout", piece.cutouts)):
        for loop in loops:
            block.add_polyline2d((np.asarray(loop) * _MM).tolist(), close=True,
                                 dxfattribs=layer(key))
            for p in np.asarray(loop):
                turn = len(turns) and np.min(np.linalg.norm(turns - p, axis=1)) < tol.dxf_repeat
                if not turn:
                    block.add_point(at(p), dxfattribs=layer("curve_points"))
    for p in turns:
        block.add_point(at(p), dxfattribs=layer("turn_points"))
    for a, b in (np.asarray(n).reshape(2, 2) for n in piece.notches):
        if np.linalg.norm(b - a) < tol.dxf_repeat:
            block.add_point(at(a), dxfattribs=layer("notches"))
        else:
            block.add_line(at(a), at(b), dxfattribs=layer("notches"))
    for line in piece.lines:
        block.add_polyline2d((np.asarray(line) * _MM).tolist(), dxfattribs=layer("internal"))
    for p in np.asarray(piece.drills).reshape(-1, 2):
        block.add_point(at(p), dxfattribs=layer("drill_holes"))
    for a, b in piece.folds:
        block.add_line(at(a), at(b), dxfattribs=layer("mirror"))
    ring = np.asarray(piece.cut[0] if piece.cut else piece.sew[0])
    lo, hi = ring.min(axis=0), ring.max(axis=0)
    centre = 0.5 * (lo + hi)
    if piece.grain is not None:
        g = np.asarray(piece.grain, dtype=np.float64)
        g = g / max(float(np.linalg.norm(g)), 1e-300)
        half = 0.3 * float(np.abs(hi - lo) @ np.abs(g))
        block.add_line(at(centre - half * g), at(centre + half * g), dxfattribs=layer("grain"))
    height = max(3.0, min(12.0, 0.03 * float(np.min(hi - lo)) * _MM))
    texts = [f"Piece Name: {name}", f"Size: {piece.size or ''}", f"Quantity: {piece.quantity}"]
    for k, text in enumerate(texts):
        block.add_text(text, dxfattribs={**layer("boundary"), "height": height,
                                         "insert": at(centre + (0.02, -0.02 - 0.02 * k))})
    return block, lo, hi


def _pairs(pattern: Pattern) -> dict[str, str]:
    """Right panel -> base name, for every pair in ``meta["pairs"]`` whose right panel is still
    its left one turned over (an edit to one side makes them two pieces)."""
    pairs = pattern.meta.get("pairs") if isinstance(pattern.meta, dict) else None
    out: dict[str, str] = {}
    names = {p.name for p in pattern.panels}
    for base, members in (pairs or {}).items():
        if not (isinstance(members, list) and len(members) == 2 and set(members) <= names):
            continue
        left, right = pattern.panel(members[0]), pattern.panel(members[1])
        turned = mirrored(left, right.name)
        if (turned.outline == right.outline and turned.inner == right.inner
                and turned.notches == right.notches and turned.lines == right.lines
                and turned.drill_holes == right.drill_holes):
            out[right.name] = base
            out[left.name] = base
    return out


def _document(pattern: Pattern) -> Drawing:
    doc = Drawing.new("R12")  # not ezdxf.new(): R12 has no $INSUNITS, the text says the units
    msp = doc.modelspace()
    meta = pattern.meta if isinstance(pattern.meta, dict) else {}
    size = str(meta["size"]) if meta.get("size") is not None else None
    seam_marks = notch_marks(pattern, length=_NOTCH)
    pairs = _pairs(pattern)
    pieces, done = [], set()
    for panel in pattern.panels:
        base = pairs.get(panel.name)
        if base in done:
            continue
        notches = notch_slits(panel, length=_NOTCH) if panel.notches else \
            [np.array([a, b]) for pname, _, a, b in seam_marks if pname == panel.name]
        if base is not None:
            done.add(base)
            pieces.append(piece_of(panel, size, notches, name=base, quantity=2))
        else:
            pieces.append(piece_of(panel, size, notches))
    others = graded_pieces(meta)
    rows = [pieces] + list(others.values())
    used: set[str] = set()
    y = 0.0
    for row in rows:
        x, tallest = 0.0, 0.0
        for piece in row:
            block, lo, hi = _add_piece(doc, piece, used, bool(others))
            msp.add_blockref(block.name, ((x - lo[0]) * _MM, (y - lo[1]) * _MM))
            x += float(hi[0] - lo[0]) + 0.05
            tallest = max(tallest, float(hi[1] - lo[1]))
        y -= tallest + 0.1
    sample = meta.get("sample_size", size)
    style = [f"Style Name: {pattern.name}", f"Sample Size: {sample or ''}", "Units: METRIC",
             "Author: patternfit"]
    for k, text in enumerate(style):
        msp.add_text(text, dxfattribs={"layer": str(LAYERS["boundary"]), "height": 5.0,
                                       "insert": (0.0, 40.0 + 8.0 * k)})
    return doc


def dxf_text(pattern: Pattern) -> str:
    """The DXF-AAMA file of ``pattern`` as ASCII text (see the module doc)."""
    stream = io.StringIO()
    gerber_D6673.export_stream(_document(pattern), stream)
    return stream.getvalue().encode("ascii", errors="replace").decode("ascii")
