"""DXF-AAMA (ASTM D6673) pattern exchange: :func:`load_dxf`, :func:`save_dxf` and the seam
side file.

The format (layers, units, piece text) and each block read into points by meaning are in
:mod:`.dxf_format` (entities in :mod:`.dxf_entities`); a piece made into panels (unfolded at
its mirror line, the outline fitted on the sew line, cut line, notches, internal lines, drill
holes, left/right pairs) in :mod:`.dxf_pieces` with the curve fitting in :mod:`.dxf_curves`
and the notches in :mod:`.dxf_notches`; graded files (one block per piece and size) in
:mod:`.dxf_grades`, a sample-size file graded by its ``.rul`` rule table in
:mod:`.dxf_rules`; the writer in :mod:`.dxf_write`.

DXF-AAMA has no seams, edge names or 3D placement: :func:`save_dxf` writes them, with every
panel's notches (kinds included) and each seam's ease, to a side file ``<name>.seams.json``
that CAD tools never open. Without a side file the pattern has no seams: they are suggested
by :mod:`.seam_suggest` (``patternfit seams FILE --suggest --accept``).
Everything inside is metres.
"""

from __future__ import annotations

import json
from collections import Counter
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from ..constants import UNITS, limits, tol
from ..files import atomic_write_text, read_bytes_capped, read_json_file
from ..text import CONTROL
from .dxf_entities import LINE_KINDS, layer_of, why
from .dxf_format import (LAYERS, PIECE_LAYERS, SIDEWAYS_GRAIN, curve_tolerance, field,
                         file_scale, read_document, read_piece, sideways, texts)
from .dxf_grades import graded_meta, pick_size, pieces_in_size, share_quantities, sizes_of
from .dxf_notches import notch_marks
from .dxf_pieces import copy_names, panels_from_piece
from .dxf_rules import RuleTable, graded_by_rules, read_rules, rule_points, rules_path
from .dxf_write import dxf_text
from .errors import PatternError
from .formats import check_imported
from .io import (check_notches, json_field, json_placement, json_point, known_keys,
                 notches_from_json, notches_to_json, seams_from_json, seams_to_json, shown)
from .model import Loop, Pattern
from .plausible import PLAUSIBLE, size_warnings
from .validate import anchor_value, check_pattern

__all__ = ["LAYERS", "PLAUSIBLE", "load_dxf", "notch_marks", "save_dxf", "sidecar_path"]

SIDE_FORMAT = "patternfit-dxf-sidecar"
SIDE_VERSION = 1
#: the keys of the side file and of each of its panels (an unknown one is refused: a
#: misspelt key was skipped for its default without a word)
SIDE_KEYS = ("format", "version", "units", "name", "size", "anchor", "panels", "seams")
SIDE_PANEL_KEYS = ("edges", "inner", "grainline", "placement", "notches")


def sidecar_path(path) -> Path:
    """The side file that goes with a DXF file: ``x.dxf`` -> ``x.seams.json``."""
    path = Path(path)
    return path.with_name(path.stem + ".seams.json")


# -- export ------------------------------------------------------------------------------------
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
                          "grainline": list(p.grainline), "placement": placement,
                          "notches": notches_to_json(p)}
    meta = pattern.meta if isinstance(pattern.meta, dict) else {}
    size = meta.get("size")
    # a stated anchor may be what the panels deny: dropped, a skirt stated as hung from the
    # neck drapes another way read back
    return {"format": SIDE_FORMAT, "version": SIDE_VERSION, "units": "m", "name": pattern.name,
            **({"size": str(size)} if size is not None else {}),
            **({"anchor": meta["anchor"]} if "anchor" in meta else {}),
            "panels": panels, "seams": seams_to_json(pattern.seams)}


def save_dxf(pattern: Pattern, path, *, sidecar: bool = True) -> Path:
    """Write ``pattern`` as DXF-AAMA (R12, millimetres; :mod:`.dxf_write`) atomically, with
    every size of a graded pattern; with ``sidecar`` also write ``<name>.seams.json`` with
    seams (and their ease), edge names, notches and placement. Returns the DXF path.

    Seams whose sides differ in length are allowed (:func:`formats.check_imported`)."""
    check_imported(pattern)  # seams of unequal length may come from elsewhere and go back
    check_notches(pattern)
    try:
        text = dxf_text(pattern)
    except PatternError as exc:  # the grade kept in meta is damaged
        raise exc.located(path) from None
    side = sidecar_path(path)
    if sidecar and side.exists() and not _ours(side):
        raise PatternError("is not a side file patternfit wrote, and the DXF's would replace "
                           "it: move it, or write the DXF under another name", file=side)
    atomic_write_text(path, text)
    if sidecar:
        atomic_write_text(side, json.dumps(_sidecar(pattern), indent=1) + "\n")
    return Path(path)


def _ours(side: Path) -> bool:
    """Whether ``side`` is a side file our writer wrote (a user's own file of that name is
    never replaced)."""
    try:
        data = read_json_file(side, error=PatternError)
    except PatternError:
        return False
    return isinstance(data, dict) and data.get("format") == SIDE_FORMAT


# -- import ------------------------------------------------------------------------------------
def _read_dxf(path: Path, units: str | None, prefer_sew: bool, size: str | None,
              rules: RuleTable | None = None) -> Pattern:
    """The pattern (no seams) of a DXF file in ``size`` (graded by ``rules`` when the file
    draws one size only); errors without the file."""
    data = read_bytes_capped(path, limit=limits.dxf_bytes, error=PatternError)
    doc = read_document(data)
    # ezdxf makes up a header (metres) for a file without one: only what the file says counts
    said = {v for v in ("$INSUNITS", "$MEASUREMENT") if v.encode() in data}
    msp = doc.modelspace()
    msp_texts = texts(msp)
    blocks = [b for b in doc.blocks if not b.name.startswith("*")]
    blocks, stray = _inserted_only(doc, blocks)
    scale, unit_says = file_scale(doc, said, msp_texts, blocks) if units is None else \
        (UNITS[units], f"units={units!r}")
    # fitted curves stay as close to the file's polylines as the file says its polylines stay
    # to its curves (AccuMark: 0.152 mm), never farther than tol.dxf_span
    stated = curve_tolerance(msp_texts, scale)
    span = tol.dxf_span if stated is None else min(tol.dxf_span, max(stated, tol.dxf_fit))
    # pieces we drew from panels keep an edge between every two turn points (exact round
    # trip); files written before blocks said so are ours throughout
    author_ours = (field(msp_texts, "Author") or "") == "patternfit"
    # count the blocks that can be pieces, per size, before reading or fitting any
    drawn = Counter(field(texts(b), "Size") or None for b in blocks
                    if any(layer_of(e) in PIECE_LAYERS for e in b))
    every = drawn.pop(None, 0)  # blocks without a size are in every size
    size_most, most = max(drawn.items(), key=lambda kv: kv[1], default=(None, 0))
    if every + most > limits.panels:
        where = f" in size {size_most}" if size_most is not None else ""
        raise PatternError(f"the DXF has {every + most} blocks with a boundary{where}, more "
                           f"than the limit of {limits.panels} panels")
    pieces, marks, unread = [], {}, []
    for block in blocks:
        try:
            piece = read_piece(block, scale)
            if piece is not None and rules is not None:
                marks[block.name] = rule_points(block, scale)
        except PatternError:
            raise
        except Exception as exc:  # damaged geometry, of whatever kind
            raise PatternError(f"piece cannot be read: {why(exc)}", panel=block.name) from exc
        if piece is not None:
            pieces.append(piece)
        elif any(layer_of(e) in PIECE_LAYERS for e in block):
            unread.append(block)
    loose = sum(1 for e in msp if e.dxftype() in LINE_KINDS and layer_of(e) in PIECE_LAYERS)
    if not pieces:
        raise PatternError("the DXF has no pattern pieces (no block with a closed boundary "
                           "on layer 1)" + (f"; it draws {loose} line(s) on the piece layers "
                           "outside any block, which DXF-AAMA does not read as pieces"
                           if loose else ""))
    share_quantities(pieces)
    marked = any(p.ours for p in pieces)
    sample = field(msp_texts, "Sample Size") or None
    if rules is not None and len(sizes_of(pieces)) <= 1:
        # the sample size drawn, the others made by the rule table
        pieces = graded_by_rules(pieces, marks, rules)
        sample = rules.sample
    chosen = pick_size(sizes_of(pieces), size, sample)
    panels, names, pairs, renamed = [], set(), {}, []
    for piece in pieces_in_size(pieces, chosen):
        name = piece.name or piece.block
        while any(n in names for n in copy_names(name, piece.quantity)):
            name += "_2"
        if name != (piece.name or piece.block):
            renamed.append(f"two pieces are named '{piece.name or piece.block}': the one in "
                           f"block '{piece.block}' is read as '{name}', and the name puts both "
                           "on the same side of the body; rename one, or state its side "
                           "(placement) in the side file")
        try:
            ours = piece.ours or (author_ours and not marked)
            made = panels_from_piece(piece, name, prefer_sew=prefer_sew, foreign=not ours,
                                     span=span)
        except PatternError:
            raise
        except Exception as exc:  # a fit that fails on damaged geometry, of whatever kind
            raise PatternError(f"piece cannot be read: {why(exc)}", panel=piece.block) from exc
        names.update(p.name for p in made)
        if len(made) == 2:
            pairs[name] = [p.name for p in made]
        panels += made
    if len(panels) > limits.panels:
        raise PatternError(f"the DXF's pieces make {len(panels)} panels, more than the limit "
                           f"of {limits.panels}")
    meta: dict[str, Any] = {"source_format": "dxf-aama", **graded_meta(pieces, chosen, sample)}
    if pairs:
        meta["pairs"] = pairs
    table = field(msp_texts, "Grade Rule Table") or (rules.name if rules else None)
    if table:
        meta["grade_rule_table"] = table
    warnings = size_warnings(panels, scale, unit_says, hint=lambda unit: (
        f"patternfit convert FILE OUT.json --from-units {unit}; "
        f"load_dxf(..., units={unit!r})")) + renamed
    # what the file says and the reader could not use, said rather than dropped
    word = field(msp_texts, "Units")
    if units is None and word is not None and not unit_says.startswith("the text"):
        warnings.append(f"the text 'Units: {word}' names no unit the reader knows (METRIC or "
                        f"ENGLISH); read instead by: {unit_says}; give the unit "
                        "(--from-units) if that is wrong")
    if sample is not None and chosen is not None and size is None \
            and sample.strip().upper() != str(chosen).strip().upper():
        warnings.append(f"the sample size '{sample}' the file names is not among its sizes "
                        f"({', '.join(sizes_of(pieces))}): size '{chosen}' was read")
    for ref in msp.query("INSERT"):
        sx, sy = ref.dxf.get("xscale", 1.0), ref.dxf.get("yscale", 1.0)
        if (sx, sy) != (1.0, 1.0):
            warnings.append(f"block '{ref.dxf.name}' is inserted at scale ({sx:g}, {sy:g}): "
                            "read at its own size, as drawn in the block")
    warnings += [f"block '{b.name}' draws on a boundary layer but holds no closed outline "
                 "(a gap, or fewer than 3 points): not read as a piece" for b in unread
                 if (field(texts(b), "Size") or None) in (None, chosen)]
    warnings += [f"block '{b.name}' draws a piece but is not inserted in the drawing (a piece "
                 "deleted in the CAD tool stays in the file until it is purged): not read"
                 for b in stray if (field(texts(b), "Size") or None) in (None, chosen)]
    warnings += [f"piece '{p.name or p.block}' draws {len(p.cut)} closed cut lines (layer 1)"
                 f" and {len(p.sew)} sew lines (layer 14): the largest of each is read, the "
                 "others are not (one piece per block)"
                 for p in pieces_in_size(pieces, chosen) if max(len(p.cut), len(p.sew)) > 1]
    if loose:
        warnings.append(f"the drawing has {loose} line(s) on the piece layers outside any "
                        "block: not read (DXF-AAMA draws each piece in a block of its own)")
    warnings += [f"piece '{p.name or p.block}' says 'Quantity: 0' (the marker cuts none of "
                 "it): read as one panel" for p in pieces_in_size(pieces, chosen)
                 if p.quantity == 0]
    if warnings:
        meta["warnings"] = warnings
    name = field(msp_texts, "Style Name") or CONTROL.sub("", path.stem)
    pattern = Pattern(name, tuple(panels), (), meta)
    check_pattern(pattern)
    return pattern


def _inserted_only(doc, blocks: list) -> tuple[list, list]:
    """``blocks`` without the piece blocks that no INSERT places in the drawing (in model
    space, a paper-space layout or any block, anonymous ones too), and those.

    A drawing that inserts none of its piece blocks keeps them all (a bare block table).
    Block names are compared without case, as DXF compares them."""
    inserted = {ref.dxf.name.upper() for layout in doc.blocks
                for ref in layout.query("INSERT")}
    pieces = [b for b in blocks if any(layer_of(e) in PIECE_LAYERS for e in b)]
    if not any(b.name.upper() in inserted for b in pieces):
        return blocks, []
    stray = [b for b in pieces if b.name.upper() not in inserted]
    return [b for b in blocks if b not in stray], stray


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
    known_keys(side, SIDE_KEYS, "side file")
    version = side.get("version", SIDE_VERSION)
    if isinstance(version, bool) or version != SIDE_VERSION:
        raise PatternError(f"side file: unsupported version {shown(version)} (this build reads "
                           f"version {SIDE_VERSION})")
    info = json_field(side, "panels", dict, "side file", {})
    # a panel the side file describes that the DXF does not hold (a piece lost or renamed)
    missing = [name for name in info if name not in {p.name for p in pattern.panels}]
    if missing:
        raise PatternError(f"side file describes {shown(missing[0], 40)}, which the DXF does not "
                           f"hold (its pieces: {', '.join(p.name for p in pattern.panels)})")
    # its explicit placements' length unit (we write "m"; another was ignored without a
    # word, a translation in cm read as metres)
    unit = json_field(side, "units", str, "side file", "m")
    if unit not in UNITS:
        raise PatternError(f"side file 'units' {shown(unit)}: expected one of "
                           f"{', '.join(UNITS)}")
    panels = []
    for p in pattern.panels:
        where = {"panel": p.name}
        d = json_field(info, p.name, dict, "side file 'panels'", {}, **where)
        known_keys(d, SIDE_PANEL_KEYS, "side file panel", **where)
        inner = json_field(d, "inner", list, "side file panel", [], **where)
        loops = [_renamed(p.outline, p.outline.name,
                          json_field(d, "edges", list, "side file panel", None, **where), where)]
        for k, loop in enumerate(p.inner):
            lp = inner[k] if k < len(inner) else {}
            what = f"side file inner loop #{k}"
            loops.append(_renamed(loop, json_field(lp, "name", str, what, loop.name, **where),
                                  json_field(lp, "edges", list, what, None, **where), where))
        pl = json_field(d, "placement", dict, "side file panel", {}, **where)
        placement = json_placement(pl, UNITS[unit], part=p.placement.part,
                                   side=p.placement.side, **where)
        grain = json_point(d.get("grainline", p.grainline), 1.0, "grainline", **where)
        renames = {e.name: f.name for lp, new in zip(p.loops, loops)
                   for e, f in zip(lp.edges, new.edges)}
        panel = replace(p, outline=loops[0], inner=tuple(loops[1:]), grainline=grain,
                        placement=placement,
                        notches=tuple(replace(n, edge=renames[n.edge]) for n in p.notches))
        if "notches" in d:  # ours: exactly as written, kinds included
            panel = replace(panel, notches=notches_from_json(
                json_field(d, "notches", list, "side file panel", **where), panel))
        panels.append(panel)
    outline_edges = {p.name: [e.name for e in p.outline.edges] for p in panels}
    seams = seams_from_json(json_field(side, "seams", list, "side file", []), prefix="s",
                            outline_edges=outline_edges)
    meta = dict(pattern.meta)
    if "anchor" in side:
        meta["anchor"] = anchor_value(side["anchor"], "side file 'anchor'")
    return Pattern(json_field(side, "name", str, "side file", pattern.name), tuple(panels),
                   seams, meta)


def load_dxf(path, *, sidecar=None, units: str | None = None, prefer_sew: bool = True,
             size: str | None = None, rules=None) -> Pattern:
    """Read a DXF-AAMA file into a :class:`Pattern` [m].

    sidecar : side file with seams, edge names and placement; by default ``<name>.seams.json``
        beside the DXF when it exists. It is applied to the size it was written with only
        (another size is read without it, with a warning). Without one the pattern has
        no seams: :func:`.seam_suggest.suggest_seams` offers them from the notches
        (``Panel.notches``) and edge lengths.
    units : ``"mm"``, ``"cm"``, ``"in"`` or ``"m"`` to override the file's (``Units:`` style
        text, else ``$INSUNITS``, else millimetres).
    prefer_sew : the outline is the sew line (layer 14) where a piece has one, the cut line
        kept as ``Panel.cut_line``; False: the cut line is the outline.
    size : of a graded file (one block per piece and size), the size to read (case
        ignored); by default the ``Sample Size`` (:mod:`.dxf_grades`). A size the file does
        not have is a :class:`PatternError` naming the file and its sizes.
    rules : a grade rule table (``.rul``, :mod:`.dxf_rules`); by default the ``.rul`` file
        beside the DXF when it exists. A DXF drawing one size only is graded by it into the
        table's sizes (its grade points: ``# N`` texts on layers 2, 3 and 4); a DXF that
        draws every size keeps its own geometry.

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
    rules_file = Path(rules) if rules is not None else rules_path(path)
    table = read_rules(rules_file) if rules_file is not None else None
    try:
        pattern = _read_dxf(path, units, prefer_sew, size, table)
    except PatternError as exc:
        raise exc.located(path) from None
    except Exception as exc:  # ezdxf raises many kinds on a damaged file
        raise PatternError(f"cannot read DXF: {why(exc)}", file=path) from exc
    side_path = Path(sidecar) if sidecar is not None else sidecar_path(path)
    side = read_json_file(side_path, error=PatternError) \
        if sidecar is not None or side_path.exists() else None
    drawn_in = side.get("size") if isinstance(side, dict) else None
    if drawn_in is not None and str(drawn_in) != str(pattern.meta.get("size")):
        # the side file names the edges of the size it was written with
        pattern.meta.setdefault("warnings", []).append(
            f"{side_path.name} describes size {drawn_in}, not the size {pattern.meta.get('size')}"
            " read: its seams, edge names and placement are not applied")
        side = None
    out = pattern
    if side is not None:
        try:
            out = _with_sidecar(pattern, side)
            warnings = check_imported(out)
        except PatternError as exc:
            raise exc.located(side_path) from None
        warnings = list(pattern.meta.get("warnings", [])) + list(warnings)
        if warnings:
            out.meta["warnings"] = warnings
    # said once the side file has had its say: its 'grainline' settles which way is up
    sideways_grain = _sideways_grain(out)
    if sideways_grain:
        out.meta["warnings"] = list(out.meta.get("warnings", [])) + sideways_grain
    return out


def _sideways_grain(pattern: Pattern) -> list[str]:
    """A warning for each panel whose grain line lies within :data:`SIDEWAYS_GRAIN` of
    horizontal, which way up it hangs then decided by the order the file writes the line's
    points; not for a band (more than three times as long as wide along its grain: a
    waistband or a cuff is drawn lengthwise, and placement takes its up from its shape)."""
    out = []
    for panel in pattern.panels:
        if not sideways(panel.grainline):
            continue
        g = np.asarray(panel.grainline, dtype=float) / np.hypot(*panel.grainline)
        poly = panel.outline.polygon(4)
        along = np.ptp(poly @ g)
        across = np.ptp(poly @ np.array([-g[1], g[0]]))
        if along > 3.0 * across:
            continue
        out.append(f"panel '{panel.name}' has its grain line within {SIDEWAYS_GRAIN:g}° of "
                   "horizontal: drawn on its side, so which end is up was taken from the "
                   "order the file writes the line's two points; if it drapes upside down, "
                   "give its 'grainline' in the side file (docs/interchange.md)")
    return out
