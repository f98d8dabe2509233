"""The DXF-AAMA (ASTM D6673) format: its layers, units and text fields, and each piece block
read into a :class:`RawPiece`, the file's points by meaning, in metres, nothing fitted yet.

A DXF-AAMA file is DXF R12 with one block per piece and size; inside a block, layers carry
the meaning (ASTM D6673 numbering, :data:`LAYERS`). Piece text reads ``Piece Name: front``,
``Size: M``, ``Quantity: 2`` (the ASTM variant's layers 84, 85 and 87, boundary, internal and
sew lines, are read as 1, 8 and 14 in a block that has nothing on those: Gerber's ASTM export
draws every line twice, on both layers, and CLO's layer 84 is the curves' control polygon); the
style text in the entities section carries ``Units:
METRIC`` (millimetres) or ``Units: ENGLISH`` (inches) and ``Sample Size:`` (the base size).
"""

from __future__ import annotations

import io
from dataclasses import dataclass, field as dc_field

import numpy as np
from ezdxf.document import Drawing
from ezdxf.filemanagement import dxf_stream_info
from ezdxf.lldxf.tagger import binary_tags_loader
from ezdxf.lldxf.validator import is_dxf_stream

from ..constants import limits
from .dxf_entities import (LINE_KINDS, closed_loops, entity_name, entity_points, layer_of, why,
                           within_extent)
from ..geometry import polygon_area
from ..text import CONTROL
from .errors import PatternError

__all__ = ["ASTM_LAYERS", "LAYERS", "PIECE_LAYERS", "RawPiece", "curve_tolerance", "field",
           "file_scale", "read_document", "read_piece", "texts"]

#: ASTM D6673 layer numbers by meaning.
LAYERS = {"boundary": 1, "turn_points": 2, "curve_points": 3, "notches": 4,
          "grade_reference": 5, "mirror": 6, "grain": 7, "internal": 8, "stripe": 9,
          "plaid": 10, "cutout": 11, "drill_holes": 13, "sew": 14, "annotation": 15}
#: the ASTM D6673 variant's layers for the boundary, internal and sew lines, read as AAMA's
#: only in a block without any entity on that AAMA layer (Gerber's ASTM export draws each line
#: on both, more densely sampled on the ASTM one; CLO draws its curves' control polygon on 84)
ASTM_LAYERS = {84: LAYERS["boundary"], 85: LAYERS["internal"], 87: LAYERS["sew"]}
#: layers whose closed loop makes a block a piece
PIECE_LAYERS = (LAYERS["boundary"], LAYERS["sew"], 84, 87)
_BINARY_DXF = b"AutoCAD Binary DXF\r\n\x1a\x00"
_UNIT = {"METRIC": 0.001, "ENGLISH": 0.0254}
_INSUNITS = {1: 0.0254, 2: 0.3048, 4: 0.001, 5: 0.01, 6: 1.0}


def texts(entities) -> list[str]:
    """The texts of ``entities`` (TEXT, ATTRIB, MTEXT, ATTDEF), control characters dropped."""
    out = []
    for e in entities:
        if e.dxftype() in ("TEXT", "ATTRIB", "MTEXT", "ATTDEF"):
            raw = e.dxf.get("text", "") if e.dxftype() != "MTEXT" else e.text
            out.append(CONTROL.sub("", str(raw or "")).strip())
    return out


def field(texts: list[str], key: str) -> str | None:
    for t in texts:
        if t.lower().startswith(key.lower() + ":"):
            return t.split(":", 1)[1].strip()
    return None


def read_document(data: bytes):
    """The ezdxf document in a DXF file's bytes (ASCII in its own code page, or binary)."""
    if data.startswith(_BINARY_DXF):
        return Drawing.load(binary_tags_loader(data, errors="surrogateescape"))
    # a Windows export ends its lines in CR LF, and a UTF-8 one may open with a byte order
    # mark: both were refused as "not a DXF file" (ezdxf's test reads "0\r" as no "0")
    data = data.removeprefix(b"\xef\xbb\xbf").replace(b"\r\n", b"\n")
    text = data.decode("utf-8", errors="ignore")  # the header's code page is plain ASCII
    if not is_dxf_stream(io.StringIO(text)):
        raise PatternError("not a DXF file (it does not start with a DXF section)")
    encoding = dxf_stream_info(io.StringIO(text)).encoding
    return Drawing.read(io.StringIO(data.decode(encoding, errors="surrogateescape"),
                                    newline=None))


def file_scale(doc, said: set[str], msp_texts: list[str], blocks) -> tuple[float, str]:
    """Metres per file unit, and what said so: the AAMA ``Units:`` text (in the entities,
    else in a piece block), else ``$INSUNITS`` (when the header has it and it is a length),
    else ``$MEASUREMENT`` (0 inches, 1 millimetres), else millimetres."""
    word = field(msp_texts, "Units")
    if word is None:
        for block in blocks:
            word = field(texts(block), "Units")
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


def curve_tolerance(msp_texts: list[str], scale: float) -> float | None:
    """How far [m] the file says its polylines stray from the curves they sample: AccuMark's
    ``Curve Tolerance: .152`` (ASTM) or ``TOLERANCE: .006`` (AAMA), in the file's units
    (``scale`` metres each); None where it states none or no positive number."""
    for key in ("Curve Tolerance", "Tolerance"):
        text = field(msp_texts, key)
        if text is None:
            continue
        try:
            value = float(text) * scale
        except ValueError:
            return None
        return value if np.isfinite(value) and value > 0 else None
    return None


def _points(a) -> list:
    # to the nanometre: every size of a graded style is kept in the pattern's JSON
    return np.round(np.asarray(a, dtype=np.float64).reshape(-1, 2), 9).tolist()


def _array(a) -> np.ndarray:
    return np.asarray(a, dtype=np.float64).reshape(-1, 2)


@dataclass
class RawPiece:
    """One piece block as the file draws it, every point (k, 2) [m] in the block's frame.

    cut, sew, cutouts : closed loops (last point not repeated) on layers 1, 14 and 11, the
        largest first. turns : turn points (layer 2). notches : one (2, 2) array per notch,
        its two ends (the same point twice for a POINT). lines : internal lines (layer 8),
        open polylines (a closed one ends where it starts). drills : drill holes (layer 13).
        folds : mirror lines (layer 6), (2, 2) each. grain : the grain line's axis, up the drawing.
        name, size, quantity : the block's ``Piece Name:``, ``Size:``, ``Quantity:`` text
        (quantity None where the block has none: AccuMark states it in the sample size's
        block only, :func:`dxf_grades.share_quantities` gives it to the other sizes).
        ours : the block says ``Source: patternfit`` (drawn by our writer from a panel: its
        edges end at its turn points and are not merged on reading).
    """

    block: str
    name: str | None = None
    size: str | None = None
    quantity: int | None = 1
    cut: list = dc_field(default_factory=list)
    sew: list = dc_field(default_factory=list)
    cutouts: list = dc_field(default_factory=list)
    turns: np.ndarray = dc_field(default_factory=lambda: np.zeros((0, 2)))
    notches: list = dc_field(default_factory=list)
    lines: list = dc_field(default_factory=list)
    drills: np.ndarray = dc_field(default_factory=lambda: np.zeros((0, 2)))
    folds: list = dc_field(default_factory=list)
    grain: tuple[float, float] | None = None
    ours: bool = False

    def to_json(self) -> dict:
        """The piece as JSON-able lists [m] (how a graded pattern keeps its other sizes)."""
        return {"block": self.block, "name": self.name, "size": self.size,
                "quantity": self.quantity, "cut": [_points(q) for q in self.cut],
                "sew": [_points(q) for q in self.sew],
                "cutouts": [_points(q) for q in self.cutouts], "turns": _points(self.turns),
                "notches": [_points(q) for q in self.notches],
                "lines": [_points(q) for q in self.lines], "drills": _points(self.drills),
                "folds": [_points(q) for q in self.folds],
                "grain": list(self.grain) if self.grain is not None else None,
                "ours": self.ours}

    @classmethod
    def from_json(cls, d: dict) -> "RawPiece":
        """The piece :meth:`to_json` wrote; a :class:`PatternError` when it is malformed."""
        try:
            grain = d.get("grain")
            piece = cls(str(d["block"]), d.get("name"), d.get("size"), int(d.get("quantity", 1)),
                       [_array(q) for q in d.get("cut", [])],
                       [_array(q) for q in d.get("sew", [])],
                       [_array(q) for q in d.get("cutouts", [])], _array(d.get("turns", [])),
                       [_array(q) for q in d.get("notches", [])],
                       [_array(q) for q in d.get("lines", [])], _array(d.get("drills", [])),
                       [_array(q) for q in d.get("folds", [])],
                       None if grain is None else (float(grain[0]), float(grain[1])),
                       d.get("ours") is True)
        except (KeyError, TypeError, ValueError, AttributeError) as exc:
            raise PatternError(f"a graded size's piece is malformed ({why(exc)})") from None
        loops = piece.cut + piece.sew
        if not loops or any(len(q) < 3 for q in loops + piece.cutouts):
            raise PatternError(f"a graded size's piece '{piece.block}' has no closed line of "
                               "3 points or more")
        return piece


def _quantity(text: str | None, where: dict) -> int | None:
    """The piece count of a ``Quantity:`` text: ``2``, or ``1,1`` (Optitex: one left and one
    right, a mirrored pair like 2), ``1,0`` (AccuMark), ``0`` (AccuMark: a piece the marker
    does not cut, still a piece of the style); None without a text."""
    if text is None or not text.strip():
        return None
    try:
        q = sum(int(float(part)) for part in text.strip().split(","))
    except (ValueError, OverflowError):  # "inf" is a float but no count
        raise PatternError(f"'Quantity: {text}' is not a number", **where) from None
    if not 0 <= q <= 64:
        raise PatternError(f"'Quantity: {text}' is not a piece count (0 to 64)", **where)
    return q


def read_piece(block, scale: float) -> RawPiece | None:
    """A piece block's points by layer, or None when it has no closed cut or sew line.

    Every entity is read inside this function's error boundary: whatever ezdxf raises on a
    damaged entity becomes a :class:`PatternError` naming the block and the entity. More
    entities or points than ``limits.segments_per_panel`` are refused.
    """
    where = {"panel": block.name}
    if len(block) > limits.segments_per_panel:
        raise PatternError(f"the block has {len(block)} entities, more than the limit of "
                           f"{limits.segments_per_panel} (the segment limit)", **where)
    by_layer: dict[int, list] = {}
    points: dict[int, list] = {}
    budget = limits.segments_per_panel
    # the layers a line is drawn on (piece text sits on layer 1 in either variant)
    drawn = {layer_of(e) for e in block if e.dxftype() in LINE_KINDS}
    astm = {k: v for k, v in ASTM_LAYERS.items() if v not in drawn}
    for e in block:
        try:
            layer = layer_of(e)
            if layer in ASTM_LAYERS:
                if layer not in astm:
                    continue
                layer = astm[layer]
            if e.dxftype() == "POINT":
                at = np.array(tuple(e.dxf.location)[:2]).reshape(1, 2) * scale
                points.setdefault(layer, []).append(within_extent(at, e, where)[0])
                continue
            got = entity_points(e, scale, budget, where)
        except PatternError:
            raise
        except Exception as exc:  # ezdxf raises many kinds on a damaged entity
            raise PatternError(f"{entity_name(e)} cannot be read: {why(exc)}",
                               **where) from exc
        if got is not None:
            by_layer.setdefault(layer, []).append(got)
            budget -= len(got[0])
    folds = [p[[0, -1]] for p, _ in by_layer.get(LAYERS["mirror"], [])]
    # a half piece's lines may end on its mirror line (Gerber: the sew line of a half)
    cut = closed_loops(by_layer.get(LAYERS["boundary"], []), folds)
    sew = closed_loops(by_layer.get(LAYERS["sew"], []), folds)
    if not (cut or sew):
        return None
    words = texts(block)
    piece = RawPiece(block.name, field(words, "Piece Name"), field(words, "Size") or None,
                     _quantity(field(words, "Quantity"), where),
                     ours=field(words, "Source") == "patternfit")
    piece.cut = sorted(cut, key=lambda q: -abs(polygon_area(q)))
    piece.sew = sorted(sew, key=lambda q: -abs(polygon_area(q)))
    piece.cutouts = closed_loops(by_layer.get(LAYERS["cutout"], []))
    piece.turns = _array(points.get(LAYERS["turn_points"], []))
    piece.notches = [p[[0, -1]] for p, _ in by_layer.get(LAYERS["notches"], [])]
    piece.notches += [np.array([q, q]) for q in points.get(LAYERS["notches"], [])]
    piece.lines = [np.vstack([p, p[:1]]) if closed else p
                   for p, closed in by_layer.get(LAYERS["internal"], [])]
    # a drill hole is a POINT, or a small circle whose centre is the hole
    drills = list(points.get(LAYERS["drill_holes"], []))
    drills += [p.mean(axis=0) for p, closed in by_layer.get(LAYERS["drill_holes"], []) if closed]
    piece.drills = _array(drills)
    piece.folds = folds
    for p, _ in by_layer.get(LAYERS["grain"], []):
        d = p[-1] - p[0]
        if np.linalg.norm(d) > 0:
            # a grain LINE is an axis, not an arrow: which end a CAD tool writes first is
            # its own choice, and a skirt whose line ran hem to waist was hung upside down.
            # Pieces are drawn as worn, so the warp is taken up the drawing
            if d[1] < 0:
                d = 0.0 - d
            piece.grain = (float(d[0]), float(d[1]))
            break
    return piece


#: a grain line closer than this to the drawing's horizontal [degrees] says nothing of
#: which of the piece's ends is up (AccuMark draws many pieces on their side)
SIDEWAYS_GRAIN = 20.0


def sideways(grain) -> bool:
    """Whether grain axis ``grain`` (2,) lies within :data:`SIDEWAYS_GRAIN` of horizontal."""
    return grain is not None and \
        abs(grain[1]) < np.tan(np.radians(SIDEWAYS_GRAIN)) * abs(grain[0])
