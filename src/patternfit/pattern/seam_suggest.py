"""Seams suggested for a pattern that has none (an imported DXF, a file from another tool).

Every pair of free outline edges on which the seam could lie is scored from the evidence a
pattern maker reads, each a factor in [0, 1] with its reason in words:

- **length**: equal within the seam tolerance; a sleeve's edge up to 4 cm longer than a
  body piece's (cap ease); a small ease (up to 5 %); a gather (up to ``limits.seam_ease``),
  likelier into a band at the top of the gathered piece or a cuff at its bottom; nothing
  beyond.
- **piece names** (FR/FRONT, BK/BACK, SL/SLEEVE, CF/CB, YOKE, COLLAR, CUFF, BAND, and
  ``_L``/``_R`` or LEFT/RIGHT): front to back, a sleeve or collar to a body piece are
  expected; a left piece is sewn to a right one only along its centre edge (the centre
  front or back, reaching the top of the piece), so a left leg is never sewn to the right leg.
- **edge names** when the file has them: the same name on both sides; a hem, waist,
  neckline, cuff or armhole edge is an opening unless the other piece is a band, collar,
  cuff, yoke (or, for an armhole, a sleeve).
- **notches** (``Panel.notches``, as the DXF reader gives them): the same count at
  mirrored positions; an unnotched edge of a notched piece is rarely sewn.
- **grain and symmetry**: pieces laid right side up, seen from outside, meet at a seam as
  they wrap the body: across the grain their outward normals point opposite ways (a front's
  right edge meets a back's left edge), along the grain the same way (both shoulder edges
  face up); two horizontal edges may also stack (a yoke's lower edge on a back's upper
  edge), never a front piece's on a back piece's (a front band on the back band). Two
  edges across their pieces facing the same way along the grain are openings (hem to hem,
  waist to waist); two facing down may be (cuffs). Between a sleeve and another piece the
  grain only says that a body piece takes a sleeve at its side (an armhole), not along an
  edge across its middle (a neckline): a sleeve's grain runs along the arm.
- **orientation**: ``reverse`` is True when both outlines run the same way round.

One global assignment, greedy on the score: each edge is sewn at most once. A piece then
still sewn to no other piece (a sleeve) has its top edge split between two edges meeting at
a corner (a set-in cap between the front and back armholes). Then the
garment must keep its openings (:func:`openings`): a top and a bottom one, the arms' for a
garment hung from the neck, the second leg's for one with left and right pieces; while it
has fewer, the lowest-scored suggestion whose removal opens one is dropped (two cuffs or
two armholes sewn shut). Lengths in metres.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace

import numpy as np

from ..arguments import instance
from ..constants import limits, tol
from ..defaults import DEFAULTS
from .errors import PatternError
from .model import Panel, Pattern, Seam, SeamSide
from .validate import measured_ease, seam_slack

__all__ = ["SeamSuggestion", "check_sewn", "openings", "suggest_seams"]

#: how much longer a sleeve cap may be than its armhole [m] (2-4 cm is usual)
CAP_EASE = 0.04
#: a small ease on any seam [-] (longer / shorter - 1)
SMALL_EASE = 0.05
#: the share of a piece's height within which an edge "reaches the top" [-]
TOP_SHARE = 0.1
#: how many edges next in length each edge is compared with [-]: keeps the work linear in
#: the number of edges (50,000 allowed) while every pair of a garment's few hundred is seen
WINDOW = 64

_KINDS = {
    "front": {"fr", "frt", "frnt", "ft", "front", "cf", "ftorso", "fronts"},
    "back": {"bk", "bck", "back", "cb", "btorso", "backs"},
    "sleeve": {"sl", "slv", "sleeve", "sleeves"},
    "cuff": {"cuff", "cuffs"},
    "collar": {"collar", "coll", "col", "stand"},
    "yoke": {"yoke"},
    "band": {"band", "wb", "waistband", "binding"},
}
_SIDES = {"l": "left", "lt": "left", "left": "left", "r": "right", "rt": "right",
          "right": "right"}
#: pieces an opening edge (hem, waist, neckline...) is sewn to
_ATTACH = {"band", "collar", "cuff", "yoke"}
_OPENINGS = ("hem", "waist", "neck", "cuff", "opening", "armhole", "armscye")
_GENERIC = re.compile(r"(e|edge|seg|segment|line)?\d+")
_TORSO = {"front", "back", None}


@dataclass(frozen=True)
class SeamSuggestion:
    """A seam offered for a pattern: ``seam`` (its ``ease`` measured from the sides'
    lengths, ``reverse`` from the outlines' directions), ``score`` in [0, 1] (the product
    of the evidence factors) and ``reasons``, the evidence in words."""

    seam: Seam
    score: float
    reasons: tuple[str, ...]


@dataclass(frozen=True)
class _Piece:
    kind: str | None
    side: str | None
    orient: float           # +1 counter-clockwise, -1 clockwise
    centre: np.ndarray      # (2,) bounding-box centre in the grain frame [m]
    top: float              # highest point along the grain [m]
    height: float           # extent along the grain [m]
    notched: bool
    facing: str | None      # "front" or "back" by the name, whatever the kind (band_front)


@dataclass(frozen=True)
class _Edge:
    panel: str
    name: str
    index: int
    length: float
    normal: np.ndarray      # (2,) outward unit normal in the grain frame (across, along)
    middle: np.ndarray      # (2,) midpoint in the grain frame [m]
    span: tuple             # (lowest, highest) across the grain [m]
    top: float              # highest end along the grain [m]
    notches: tuple


def _tokens(name: str) -> list[str]:
    spaced = re.sub(r"([a-z])([A-Z])", r"\1 \2", name)
    return [t for t in re.split(r"[^a-z0-9]+", spaced.lower()) if t]


def _kind_and_side(panel: Panel) -> tuple[str | None, str | None]:
    """The piece's kind (front, back, sleeve...) and side (left/right) from its name, or
    from its placement's body part (``leg_left``, ``arm_right``) for the side."""
    tokens = _tokens(panel.name)
    kind = next((k for t in tokens for k, words in _KINDS.items() if t in words), None)
    if kind is None:
        joined = "".join(tokens)
        kind = next((k for k in ("front", "back", "sleeve", "collar", "cuff", "yoke")
                     if k in joined), None)
    side = next((_SIDES[t] for t in tokens if t in _SIDES), None)
    if side is None and panel.placement.part.endswith(("_left", "_right")):
        side = panel.placement.part.rsplit("_", 1)[1]
    if kind is None and panel.placement.part.startswith("arm"):
        kind = "sleeve"
    return kind, side


def _notches(panel: Panel) -> dict[str, list[float]]:
    """{edge: sorted arc-length fractions} of the panel's notches (``Panel.notches``)
    along its edges, those at a turn point (t = 0) left out: they mark a corner, not where
    along the edge the pieces meet."""
    out: dict[str, list[float]] = {}
    for n in panel.notches:
        if tol.notch_match < n.t < 1.0 - tol.notch_match:
            out.setdefault(n.edge, []).append(float(n.t))
    return {k: sorted(v) for k, v in out.items()}


def _features(pattern: Pattern, sewn: set) -> tuple[dict, list[_Edge]]:
    pieces, edges = {}, []
    for panel in pattern.panels:
        g = np.asarray(panel.grainline, dtype=np.float64)
        frame = np.array([[g[1], -g[0]], g])        # rows: across, along the grain
        poly = panel.outline.polygon(16) @ frame.T
        lo, hi = poly.min(axis=0), poly.max(axis=0)
        orient = 1.0 if panel.outline.signed_area() >= 0 else -1.0
        notches = _notches(panel)
        kind, side = _kind_and_side(panel)
        facing = next((k for t in _tokens(panel.name) for k in ("front", "back")
                       if t in _KINDS[k]), None)
        pieces[panel.name] = _Piece(kind, side, orient, 0.5 * (lo + hi), float(hi[1]),
                                    float(hi[1] - lo[1]), any(notches.values()), facing)
        for k, e in enumerate(panel.outline.edges):
            if (panel.name, e.name) in sewn:
                continue
            pts = e.polyline(16) @ frame.T
            chord = pts[-1] - pts[0]
            if np.linalg.norm(chord) < 0.1 * e.length:   # a nearly closed curve
                chord = pts[len(pts) * 3 // 4] - pts[len(pts) // 4]
            n = orient * np.array([chord[1], -chord[0]])
            edges.append(_Edge(panel.name, e.name, k, e.length,
                               n / max(np.linalg.norm(n), 1e-12), pts[len(pts) // 2],
                               (float(pts[:, 0].min()), float(pts[:, 0].max())),
                               float(max(pts[0, 1], pts[-1, 1])),
                               tuple(notches.get(e.name, ()))))
    return pieces, edges


def _length(a: _Edge, b: _Edge, pa: _Piece, pb: _Piece):
    la, lb = a.length, b.length
    diff, ratio = abs(la - lb), max(la, lb) / min(la, lb) - 1.0
    if diff <= seam_slack(la, lb):
        return 1.0, f"lengths equal ({la * 100:.1f} cm, Δ {diff * 1000:.1f} mm)"
    long_kind = (pa if la > lb else pb).kind
    short_kind = (pb if la > lb else pa).kind
    if long_kind == "sleeve" and short_kind in _TORSO and diff <= CAP_EASE + \
            seam_slack(la, lb) and ratio <= 0.15:
        return 0.9, f"a sleeve cap easing {diff * 100:.1f} cm into its armhole"
    if ratio <= SMALL_EASE:
        return 0.6, f"a small ease ({ratio * 100:.1f} %, Δ {diff * 10:.1f} mm)"
    if ratio <= limits.seam_ease:
        gathered = f"gathered {1 + ratio:.2f}:1 ({max(la, lb) * 100:.1f} into " \
                   f"{min(la, lb) * 100:.1f} cm)"
        # a gather is sewn into a band at the top of the gathered piece (a skirt into its
        # waistband) or into a cuff at its bottom (a sleeve's wrist)
        long_e, long_p = (a, pa) if la > lb else (b, pb)
        at_top = long_e.top >= long_p.top - TOP_SHARE * long_p.height
        if (short_kind == "band" and at_top) or (short_kind == "cuff" and not at_top):
            return 0.7, f"{gathered} into a {short_kind}"
        return 0.3, gathered
    return 0.0, ""


def _is_centre(e: _Edge, p: _Piece) -> bool:
    """Whether ``e`` is the centre edge of a left or right piece: it reaches the top of the
    piece and, when the piece is a front or a back, lies on the side facing the body's
    centre (seen from outside: a right front's right, a right back's left)."""
    if e.top < p.top - TOP_SHARE * p.height:
        return False
    if p.kind not in ("front", "back"):
        return True
    inward = 1.0 if (p.kind == "front") == (p.side == "right") else -1.0
    return (e.middle[0] - p.centre[0]) * inward > 0


def _wearer_side(e: _Edge, p: _Piece) -> str | None:
    """The wearer's side an edge of a front or back piece without a side of its own lies
    on, seen from outside: a front's right edge is on the wearer's left, a back's on the
    wearer's right; None near the middle or on other pieces."""
    if p.kind not in ("front", "back") or p.side:
        return None
    off = e.middle[0] - p.centre[0]
    if abs(off) < 0.1 * (e.span[1] - e.span[0] + abs(off)):
        return None
    return "left" if (off > 0) == (p.kind == "front") else "right"


def _pieces(a: _Edge, b: _Edge, pa: _Piece, pb: _Piece):
    for mine, other, pe in ((pa, b, pb), (pb, a, pa)):
        where = _wearer_side(other, pe)
        if mine.side and where and where != mine.side:
            return 0.0, ""   # a left sleeve is not sewn into the right armhole
    if pa.side and pb.side and pa.side != pb.side:
        if pa.kind == pb.kind and pa.kind not in ("sleeve", "cuff") and \
                _is_centre(a, pa) and _is_centre(b, pb):
            return 1.0, "left and right pieces joined at the centre"
        return 0.0, ""
    if a.panel == b.panel:
        if pa.kind == "sleeve":
            return 1.0, "a sleeve sewn into a tube"
        return 0.45, "two edges of one piece"
    kinds = {pa.kind, pb.kind}
    if kinds == {"front", "back"}:
        return 1.0, "front to back"
    if len(kinds) == 2 and kinds & {"sleeve", "collar", "cuff", "yoke", "band"}:
        return 1.0, f"{pb.kind if pa.kind in _TORSO else pa.kind} to " \
                    f"{pa.kind if pa.kind in _TORSO else pb.kind or 'a body piece'}"
    if pa.kind and pa.kind == pb.kind:
        return 0.7, f"two {pa.kind} pieces"
    return 0.8, ""


def _opening(name: str) -> str | None:
    low = name.lower()
    return next((w for w in _OPENINGS if w in low), None)


def _names(a: _Edge, b: _Edge, pa: _Piece, pb: _Piece):
    for e, own, other in ((a, pa, pb), (b, pb, pa)):
        side = next((_SIDES[t] for t in _tokens(e.name) if t in _SIDES), None)
        if side and not own.side and other.side and side != other.side:
            return 0.0, ""   # a left sleeve is not sewn into the right armhole
        word = _opening(e.name)
        if word and other.kind not in _ATTACH and not (word.startswith("arm")
                                                        and other.kind == "sleeve"):
            return 0.35, f"'{e.name}' names an opening"
    generic = _GENERIC.fullmatch(a.name.lower()) or _GENERIC.fullmatch(b.name.lower())
    if not generic and a.name.lower() == b.name.lower():
        return 1.0, f"both edges are called '{a.name}'"
    return 0.8, ""


def _notch_factor(a: _Edge, b: _Edge, pa: _Piece, pb: _Piece, reverse: bool):
    if a.notches and b.notches:
        mirrored = sorted(1.0 - t for t in b.notches) if reverse else list(b.notches)
        if len(a.notches) == len(mirrored) and np.allclose(a.notches, mirrored,
                                                           atol=tol.notch_match):
            return 1.0, f"notches match ({len(a.notches)})"
        return 0.1, "notches differ"
    if a.notches or b.notches:
        return 0.3, "only one side notched"
    if pa.notched and pb.notched:
        return 0.45, "neither side notched on notched pieces"
    return 1.0, ""


def _grain(a: _Edge, b: _Edge, pa: _Piece, pb: _Piece):
    if (pa.kind == "sleeve") != (pb.kind == "sleeve"):
        # a sleeve's grain runs along the arm, not with the body's; but a body piece takes
        # it at the side (an armhole), never along an edge across its middle
        edge, body = (b, pb) if pa.kind == "sleeve" else (a, pa)
        if body.kind in _TORSO and edge.span[0] < body.centre[0] < edge.span[1]:
            return 0.2, "a sleeve sewn across the middle of a body piece (a neckline or hem)"
        return 1.0, ""
    na, nb = a.normal, b.normal
    wrap = -na[0] * nb[0] + na[1] * nb[1]
    flat = abs(na[1]) > 0.7 and abs(nb[1]) > 0.7
    if flat and na[1] * nb[1] > 0 and a.span[0] <= pa.centre[0] <= a.span[1] and \
            b.span[0] <= pb.centre[0] <= b.span[1]:
        return 0.3, "both edges run across their pieces facing the same way (openings)"
    if flat and na[1] < 0 and nb[1] < 0:
        return 0.7, "both edges face down (a hem or a cuff?)"
    # a front piece and a back piece meet around the body, never one above the other (a
    # front band's lower edge on the back band's upper edge)
    facing_apart = pa.facing and pb.facing and pa.facing != pb.facing
    stack = na[0] * nb[0] - na[1] * nb[1] if flat and not facing_apart else -1.0
    cos = max(wrap, stack)
    factor = 0.25 + 0.75 * 0.5 * (1.0 + cos)
    if cos > 0.8:
        return factor, ("one edge stacked on the other" if stack > wrap else
                        "the edges face each other (grain)")
    return factor, "the edges face the wrong ways for the grain" if cos < 0 else ""


def _scored(edges: list, pieces: dict, counts: dict, i: int, j: int, min_score: float):
    """[(score, -|length difference|, i, j, reverse, reasons)] for edges ``i`` and ``j``
    when the pair may be sewn and scores at least ``min_score``, else []."""
    a, b = edges[i], edges[j]
    pa, pb = pieces[a.panel], pieces[b.panel]
    if a.panel == b.panel and abs(a.index - b.index) in (1, counts[a.panel] - 1):
        return []
    reverse = pa.orient == pb.orient
    score, reasons = 1.0, []
    for factor, why in (_length(a, b, pa, pb), _pieces(a, b, pa, pb), _names(a, b, pa, pb),
                        _notch_factor(a, b, pa, pb, reverse), _grain(a, b, pa, pb)):
        score *= factor
        if why:
            reasons.append(why)
        if score < min_score:
            return []
    return [(score, -abs(a.length - b.length), i, j, reverse, tuple(reasons))]


def suggest_seams(pattern: Pattern, *, min_score: float = DEFAULTS.seam_score
                  ) -> list[SeamSuggestion]:
    """Seams offered for the free outline edges of ``pattern`` (edges already sewn on any
    span are left alone), best first.

    Each pair of edges on different pieces (or non-adjacent edges of one piece) whose
    lengths allow a seam is scored (see the module's text; each edge against the
    ``WINDOW`` edges next to it in length); pairs are taken greedily by score, each edge
    once, and those scoring at least ``min_score`` [0, 1] are returned.
    Each seam covers both edges whole, with ``ease`` measured from their lengths
    (:func:`~patternfit.pattern.validate.measured_ease`) and ``reverse`` from the outlines'
    directions.
    """
    sewn = {(side.panel, side.edge) for s in pattern.seams for side in (s.a, s.b)}
    pieces, edges = _features(pattern, sewn)
    counts = {p.name: len(p.outline.edges) for p in pattern.panels}
    lengths = [e.length for e in edges]
    order = sorted(range(len(edges)), key=lengths.__getitem__)
    found = []
    for pos, i in enumerate(order):
        for j in order[pos + 1:pos + 1 + WINDOW]:
            if lengths[j] > (1.0 + limits.seam_ease) * lengths[i] + tol.seam_length:
                break  # sorted by length: every later edge needs more ease than allowed
            found.extend(_scored(edges, pieces, counts, min(i, j), max(i, j), min_score))
    found.sort(key=lambda f: (-f[0], -f[1], f[2], f[3]))
    used: set[int] = set()
    chosen = []
    for item in found:
        if item[2] in used or item[3] in used:
            continue
        used |= {item[2], item[3]}
        chosen.append(item)
    names: set[str] = {s.name for s in pattern.seams}
    out = []
    for score, _, i, j, reverse, reasons in _caps_matched(chosen, edges, pieces, counts,
                                                          min_score):
        a, b = edges[i], edges[j]
        name = a.name if a.name == b.name and a.name not in names else \
            f"{a.panel}.{a.name}+{b.panel}.{b.name}"
        names.add(name)
        seam = Seam(name, SeamSide(a.panel, a.name), SeamSide(b.panel, b.name), reverse,
                    measured_ease(a.length, b.length))
        out.append(SeamSuggestion(seam, round(float(score), 4), reasons))
    out = _two_spans(pattern, pieces, edges, used, out, min_score)
    return _keep_openings(pattern, out)


def _caps_matched(chosen: list, edges: list, pieces: dict, counts: dict,
                  min_score: float) -> list:
    """``chosen`` (tuples of :func:`_scored`) with the two cap halves of a sleeve swapped
    between the front and back armholes they were given where the swap spreads the cap
    ease more evenly: the cap's ease is shared by its halves in proportion, so the longer
    half goes into the longer armhole (pair by pair, one half of a cap can be as long as
    the other armhole and win it: the shirt's back cap half is within 2 mm of its front
    armhole). Only where both swapped pairs still score at least ``min_score``."""
    out = list(chosen)

    def sleeve_side(item):
        a, b = edges[item[2]], edges[item[3]]
        if pieces[a.panel].kind == "sleeve" and pieces[b.panel].kind in ("front", "back"):
            return item[2], item[3]
        if pieces[b.panel].kind == "sleeve" and pieces[a.panel].kind in ("front", "back"):
            return item[3], item[2]
        return None

    def ratio(x, y):
        return edges[x].length / edges[y].length

    for n in range(len(out)):
        for m in range(n + 1, len(out)):
            one, two = sleeve_side(out[n]), sleeve_side(out[m])
            if one is None or two is None or edges[one[0]].panel != edges[two[0]].panel or \
                    edges[one[1]].panel == edges[two[1]].panel:
                continue
            (x1, y1), (x2, y2) = one, two
            if abs(ratio(x1, y2) - ratio(x2, y1)) >= abs(ratio(x1, y1) - ratio(x2, y2)):
                continue
            swapped = [_scored(edges, pieces, counts, min(x, y), max(x, y), min_score)
                       for x, y in ((x1, y2), (x2, y1))]
            if all(swapped):
                out[n], out[m] = swapped[0][0], swapped[1][0]
    return out


def _rise(pattern: Pattern, panel: str, point) -> float:
    """How high ``point`` (2,) [m] lies on piece ``panel`` along its grain, as a share of
    the piece's height [-]."""
    p = pattern.panel(panel)
    g = np.asarray(p.grainline, dtype=np.float64)
    along = p.outline.polygon(8) @ g
    return float((np.asarray(point) @ g - along.min()) / max(float(np.ptp(along)), 1e-12))


def _loose(pattern: Pattern, seams) -> set[str]:
    """The pieces sewn to no other piece by ``seams``."""
    sewn = {side.panel for s in seams if s.a.panel != s.b.panel for side in (s.a, s.b)}
    return {p.name for p in pattern.panels} - sewn


def _two_spans(pattern: Pattern, pieces: dict, edges: list, used: set, found: list,
               min_score: float) -> list[SeamSuggestion]:
    """``found`` with the edges of pieces still sewn to no other piece (a sleeve, sewn only
    into its own tube) each sewn to two edges of other pieces that meet at a corner (a cap
    to the front and back armholes, meeting at the shoulder seam): the edge is split at the
    share of the first one's length, so the ease spreads evenly. The two edges may be free
    or suggested to each other (then that suggestion gives way), must not look like two
    openings (necklines), and the split edge must reach the top of its piece (a cap, not a
    cuff). Only where the three outlines run the same way round. Scored as a pair would
    be, with the two lengths added; of the two corners where the edges meet, the higher one
    on its piece takes the middle of the split edge (a cap's top meets the shoulder)."""
    seams = pattern.seams + tuple(s.seam for s in found)
    loose = _loose(pattern, seams)
    if not loose:
        return found
    at = {(e.panel, e.name): k for k, e in enumerate(edges)}
    paired = {}
    for n, s in enumerate(found):
        i, j = at.get((s.seam.a.panel, s.seam.a.edge)), at.get((s.seam.b.panel, s.seam.b.edge))
        if i is not None and j is not None:
            paired[frozenset((i, j))] = n
    open_ = [k for k in range(len(edges)) if k not in used]
    spare = open_ + [k for pair in paired for k in pair]
    caps = [k for k in open_ if edges[k].panel in loose and edges[k].top >=
            pieces[edges[k].panel].top - TOP_SHARE * pieces[edges[k].panel].height]
    if not caps:   # a cap is the top of its piece (not a cuff)
        return found
    # the pairs of edges on two other pieces that meet at a corner, found once (not once
    # for every cap: a piece of 400 edges took 9 s, of 1,000 edges minutes)
    corners = {}
    halves = []
    for f1 in spare:
        for f2 in spare:
            a, b = edges[f1], edges[f2]
            if a.panel == b.panel or pieces[a.panel].orient != pieces[b.panel].orient:
                continue
            if _grain(a, b, pieces[a.panel], pieces[b.panel])[0] <= 0.3:
                continue   # the two look like openings (the front and back necklines)
            broken = paired.get(frozenset((f1, f2)))
            if (f1 not in open_ or f2 not in open_) and broken is None:
                continue   # one of them is sewn to a third edge
            if broken not in corners:
                corners[broken] = _Corners(pattern, pattern.seams + tuple(
                    s.seam for n, s in enumerate(found) if n != broken))
            c = corners[broken]
            # with reverse the span [0, t] is sewn end to start to the first edge, so
            # the first edge starts where the second one ends
            if c.find(c.corner(SeamSide(a.panel, a.name), 0.0)) == \
                    c.find(c.corner(SeamSide(b.panel, b.name), 1.0)):
                halves.append((f1, f2, broken))
    triples = []
    for i in caps:
        e, pe = edges[i], pieces[edges[i].panel]
        for f1, f2, broken in halves:
            a, b = edges[f1], edges[f2]
            if e.panel in (a.panel, b.panel) or pieces[a.panel].orient != pe.orient:
                continue
            both = _Edge(a.panel, a.name, a.index, a.length + b.length, a.normal,
                         a.middle, a.span, a.top, ())
            score, reasons = 1.0, []
            for factor, why in (_length(e, both, pe, pieces[a.panel]),
                                min(_pieces(e, a, pe, pieces[a.panel]),
                                    _pieces(e, b, pe, pieces[b.panel])),
                                min(_names(e, a, pe, pieces[a.panel]),
                                    _names(e, b, pe, pieces[b.panel]))):
                score *= factor
                reasons += [why] if why else []
            if score >= min_score:
                # a cap's top meets the shoulder: of the two corners where the edges
                # meet, the junction is the higher one on its piece
                triples.append((score, _rise(pattern, a.panel,
                                              pattern.panel(a.panel).edge(a.name).start),
                                i, f1, f2, broken,
                                tuple(reasons) + (
                    f"one edge sewn to two that meet at a corner ({a.panel}.{a.name}, "
                    f"{b.panel}.{b.name})",)))
    triples.sort(key=lambda t: (-t[0], -t[1], t[2], t[3], t[4]))
    taken, dropped, added = set(), set(), []
    for score, _, i, f1, f2, broken, reasons in triples:
        if {i, f1, f2} & taken:
            continue
        taken |= {i, f1, f2}
        if broken is not None:
            dropped.add(broken)
        e, a, b = edges[i], edges[f1], edges[f2]
        t = round(a.length / (a.length + b.length), 6)
        for side, other, span in ((e, a, (0.0, t)), (e, b, (t, 1.0))):
            seam = Seam(f"{side.panel}.{side.name}+{other.panel}.{other.name}",
                        SeamSide(side.panel, side.name, *span),
                        SeamSide(other.panel, other.name), True,
                        measured_ease((span[1] - span[0]) * side.length, other.length))
            added.append(SeamSuggestion(seam, round(float(score), 4), reasons))
    return [s for n, s in enumerate(found) if n not in dropped] + added


class _Corners:
    """The corners of a pattern's outlines, those sewn together by ``seams`` made one:
    a corner is (panel, k), the start of outline edge k; a seam sews the point at each end
    of side ``a`` to the point at the matching end of side ``b`` (``reverse``: start to
    end), and where both points are corners (a side starting at 0 or ending at 1 of its
    edge) they become one."""

    def __init__(self, pattern: Pattern, seams):
        self.index = {(p.name, e.name): (p.name, k, len(p.outline.edges))
                      for p in pattern.panels for k, e in enumerate(p.outline.edges)}
        self.parent: dict = {}
        self.sewn: set = set()
        for seam in seams:
            if (seam.a.panel, seam.a.edge) not in self.index or \
                    (seam.b.panel, seam.b.edge) not in self.index:
                continue   # a seam on an inner loop (a dart) joins no outline corner
            self.sewn |= {(seam.a.panel, seam.a.edge), (seam.b.panel, seam.b.edge)}
            b_ends = (seam.b.end, seam.b.start) if seam.reverse else (seam.b.start, seam.b.end)
            for fa, fb in zip((seam.a.start, seam.a.end), b_ends):
                ca, cb = self.corner(seam.a, fa), self.corner(seam.b, fb)
                if ca is not None and cb is not None:
                    self.union(ca, cb)

    def corner(self, side, fraction: float):
        """The corner at ``fraction`` 0 or 1 of the side's edge, else None."""
        if fraction not in (0.0, 1.0):
            return None
        pname, k, n = self.index[(side.panel, side.edge)]
        return (pname, k if fraction == 0.0 else (k + 1) % n)

    def find(self, x):
        while self.parent.get(x, x) != x:
            x = self.parent[x]
        return x

    def union(self, x, y):
        self.parent[self.find(x)] = self.find(y)


def openings(pattern: Pattern, seams=None) -> int:
    """How many openings (loops of unsewn outline edges) the garment has when ``seams``
    (default: its own) are sewn: the outline edges no seam touches, linked at the corners
    that the seams sew together (:class:`_Corners`), counted as connected runs."""
    corners = _Corners(pattern, pattern.seams if seams is None else seams)
    free = [(corners.corner(SeamSide(p, e), 0.0), corners.corner(SeamSide(p, e), 1.0))
            for (p, e) in corners.index if (p, e) not in corners.sewn]
    for c0, c1 in free:
        corners.union(c0, c1)
    return len({corners.find(c0) for c0, _ in free})


def _needed_openings(pattern: Pattern) -> int:
    """Openings a garment needs: a top and a bottom one; two more for the arms of a garment
    hung from the neck, one more for the second leg of one with left and right pieces.
    ``pattern`` holds the seams suggested: unsewn, a bodice has no shoulder seams and read
    as hung from the waist, and its armholes were sewn shut (a tank top from a DXF)."""
    if pattern.anchor == "neck":
        return 4
    sides = {_kind_and_side(p)[1] for p in pattern.panels}
    return 3 if {"left", "right"} <= sides else 2


def _height(pattern: Pattern, seam: Seam) -> float:
    """How high the seam reaches on its pieces: the higher end of its sides along the
    grain, as a share of the piece's height [-] (the larger of the two)."""
    return max(_rise(pattern, side.panel, end) for side in (seam.a, seam.b)
               for end in (pattern.panel(side.panel).edge(side.edge).start,
                           pattern.panel(side.panel).edge(side.edge).end))


def _keep_openings(pattern: Pattern, found: list[SeamSuggestion]) -> list[SeamSuggestion]:
    """``found`` without the suggestions that would close the garment's openings (two cuffs
    or two armholes sewn to each other): while the sewn garment has fewer openings than it
    needs, the lowest-scored suggestion whose removal opens one more is dropped."""
    need = _needed_openings(replace(pattern, seams=pattern.seams
                                    + tuple(s.seam for s in found)))
    keep = list(found)
    have = openings(pattern, pattern.seams + tuple(s.seam for s in keep))
    while have < need:
        gains = [k for k, s in enumerate(keep)
                 if openings(pattern, pattern.seams + tuple(t.seam for t in keep if t is not s))
                 > have]
        if not gains:
            break
        # among equal scores an opening is left at the top first (armholes, not the side
        # seams below them)
        del keep[min(gains, key=lambda k: (keep[k].score, -_height(pattern, keep[k].seam)))]
        have = openings(pattern, pattern.seams + tuple(s.seam for s in keep))
    return keep


def check_sewn(pattern: Pattern, *, source=None) -> None:
    """Refuse (:class:`PatternError`) a pattern of several pieces that cannot be draped as
    one garment: no seams at all, or a piece sewn to no other piece while others are sewn
    (its own darts do not count). A one-piece garment (a wrap) passes. The message names
    the fix: ``patternfit seams <source> --suggest --accept`` (``source``: the file the
    pattern came from, if any)."""
    instance(pattern, Pattern, "pattern", "a Pattern")
    if len(pattern.panels) < 2:
        return
    fix = f"patternfit seams {source or 'PATTERN'} --suggest --accept"
    sewn = {side.panel for s in pattern.seams if s.a.panel != s.b.panel
            for side in (s.a, s.b)}
    if not sewn:
        raise PatternError(f"pattern '{pattern.name}' has {len(pattern.panels)} pieces and no "
                           f"seams between them, so it would drape as loose pieces; sew it "
                           f"first: {fix} (or add seams with --set)", file=source)
    loose = [p.name for p in pattern.panels if p.name not in sewn]
    if loose:
        raise PatternError(f"piece{'s' if len(loose) > 1 else ''} "
                           f"{', '.join(repr(n) for n in loose)} of pattern '{pattern.name}' "
                           f"{'are' if len(loose) > 1 else 'is'} sewn to no other piece; sew "
                           f"{'them' if len(loose) > 1 else 'it'} first: {fix} (or --set)",
                           file=source, panel=loose[0])
