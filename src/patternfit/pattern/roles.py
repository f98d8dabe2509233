"""Which body part each panel dresses, and where the garment hangs from, read from the pattern.

A pattern made elsewhere rarely says where its panels go: DXF pieces carry names, GarmentCode
files a 3D placement that may be wrong, and every reader defaults to ``Placement("torso",
"front")``. :func:`panel_roles` reads each panel's role from what the pattern does say, in
this order of trust:

1. a stated body part other than the default torso (our own files, DXF side files);
2. the panel's name (``sleeve``, ``lfsleeve``, ``pant_f_r``, ``FR``/``BK``/``SL``, ``cuff``,
   ``collar``, ``hood``, ``waistband``/``wb``, ``skirt``...);
3. its seams and shape: a panel sewn to itself along its two long sides is a tube (a sleeve,
   or a leg when longer than :data:`LEG_LENGTH`); a long narrow band (aspect at least
   :data:`BAND_ASPECT`) is a cuff when sewn to a sleeve, a collar when sewn at the top of a
   bodice, else a waistband; a panel sewn at the top outer corner of a bodice (an armhole)
   is a sleeve; two long panels sewn along a curved edge at their top (a crotch) are legs;
   two alike panels sewn to each other along a curve and otherwise only by their lower edges
   into the top of body panels (the necklines) are a hood's halves; a small panel sewn at a
   bodice's top near its centre line is a collar's piece. A body panel is a bodice (hung
   from the neck) when it has shoulders (:func:`_set_shoulder`), an edge at its top named
   for the neck, collar, shoulder or armhole (:func:`_named_neck`), or a neck hole between
   two seams across its top with arm openings below, a box-filling shape or a file
   placement at neck height (:func:`_neck_hole`: a boxy top, a poncho, a kimono tee); else
   a skirt.
   A panel sewn along a straight side edge (its centre line) to its mirror image is one half
   of a panel cut at the centre (GarmentCode's bodices, cut at centre front and back): its
   edges are then placed across the whole panel (:meth:`_Shape.outer`). A panel sewn to itself
   along two long edges is a tube; along short ones, a dart.

Front and back come from the stated side where the panels do not all say "front", the name,
the sign of an explicit placement's z, or the deeper neckline (the front's); then from the
panels sewn on: across a side seam the other way, the other half of a panel, the other leg
of a pair and a tier sewn across its middle the same way, a sleeve's half or a collar's piece
as the body panel it shares its longest seam with. Left and right from the name, an explicit
placement's x, or the side of the panel it is sewn to (a sleeve sewn to the front's +x
armhole is on the body's left: panels are drafted as seen from outside, and one drawn
clockwise, as seen from inside, is mirrored). Lengths in metres, in each panel's flat frame.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

#: a band is at least this many times longer than wide [-]
BAND_ASPECT = 4.0
#: a tube or crotch-sewn panel at least this long [m] is a leg, else a sleeve
LEG_LENGTH = 0.60
#: a tube at least this far round [m] (between its sewn sides) goes round the body, a skirt
#: in one piece sewn up its back; a limb is narrower (a heavy thigh 0.7 m; a one-piece
#: skirt 0.95 m round was read as a leg 0.95 m long and fell off the left leg)
TORSO_TUBE = 0.8
#: a sleeve has less than this share of the area of the panel it is sewn into [-] (a shirt's
#: sleeve 0.6 of its front; a skirt's front and back are alike)
SLEEVE_AREA = 0.8
#: the share of a panel's height [-] that counts as its top (shoulders, armholes, necklines)
TOP_SHARE = 0.30
#: a hood's half is at least this long [m] (a head is 0.23 m high; a collar's piece shorter)
HOOD_SIZE = 0.30
#: the two halves of a hood have the same area within this share [-]
TWIN_AREA = 0.03

#: a centre seam (between a panel's two halves) is at least this share of a half's height,
#: and a shoulder at most this share of its panel's height (a flared skirt's side seams run
#: across its top too, but over most of its height) [-]
HALF_SEAM = 0.4
#: a collar's piece has less than this share of the area of the bodice it is sewn to [-]
COLLAR_AREA = 0.25

#: the beginnings of the words in an outline edge's name (any case, split at ``_``, spaces,
#: digits and camelCase; GarmentCode's edge labels become edge names) that put the edge at a
#: neck or shoulders: ``neck``/``neckline``, ``collar``, ``shoulder``/``shldr``,
#: ``armhole``/``armscye``/``scye`` (a boxy top's shoulders run out to its side and a
#: poncho's are longer than :data:`HALF_SEAM`: both, unnamed, read as skirts and were worn
#: round the waist; outside audit 15)
NECK_WORDS = ("neck", "collar", "shoulder", "shldr", "armhole", "armscye", "scye")
#: a neck hole dips at least this far [m] below the inner ends of the seams either side of it
NECK_DIP = 0.01
#: a neck hole's lowest point lies within this share [-] of its panel's height from its top
#: (a deep V neck 25 cm on a 65 cm panel)
NECK_DEPTH = 0.5
#: a panel hanging straight from its shoulders (a poncho) fills at least this share [-] of its
#: upright bounding box; a circle skirt's sector, whose waist is a notch between two seams
#: across its top as well, at most pi / 4
BOX_FILL = 0.88
#: an imported 3D placement that puts a neck hole at least this high [m] (and below
#: :data:`NECK_PLACED_MAX`) says the garment is worn at the neck (a waist lies near 1 m; a
#: GarmentCode body's neck base at 1.35-1.5 m)
NECK_PLACED = 1.2
NECK_PLACED_MAX = 2.1

#: what a panel is, by kind: the body part it goes on is "torso" unless the kind is
#: sleeve/cuff (an arm) or leg
KINDS = ("bodice", "skirt", "sleeve", "leg", "collar", "hood", "waistband", "cuff")

_KIND_WORDS = (("waistband", "waistband"), ("wb", "waistband"), ("cuff", "cuff"),
               ("collar", "collar"), ("hood", "hood"), ("sleeve", "sleeve"), ("slv", "sleeve"),
               ("pant", "leg"), ("trouser", "leg"), ("leg", "leg"), ("skirt", "skirt"),
               ("torso", "bodice"), ("bodice", "bodice"))
# not "yoke": a shirt's yoke is a bodice, a skirt's or jeans' hip yoke is not, and the seams
# tell them apart (shoulders or none); named a bodice, a yoked skirt hung from the neck and
# failed (outside audit 14)
_SHORT_KIND = {"sl": "sleeve", "cf": "bodice", "cb": "bodice"}


@dataclass(frozen=True)
class PanelRole:
    """A panel's role: ``kind`` (one of :data:`KINDS`), the body ``part`` it dresses
    (``torso``, ``arm_left``, ``arm_right``, ``leg_left``, ``leg_right``), the ``side`` it
    faces (``front``, ``back``, ``outer`` for a one-piece sleeve centred on the top of the
    arm; ``left`` or ``right`` for a hood's halves) and ``why``: the evidence, in words;
    ``side_named``: the side is the one the panel's name says (FRONT, BK...), not one read
    from its placement or inferred from its seams; ``tube``: it is sewn to itself along two
    long edges."""

    kind: str
    part: str
    side: str
    why: str
    side_named: bool = False
    #: sewn to itself along two long edges: a sleeve, a leg, or a skirt in one piece
    tube: bool = False


def _words(name: str) -> list[str]:
    spaced = re.sub(r"([a-z])([A-Z])", r"\1 \2", name)
    return [w for w in re.split(r"[^a-z0-9]+", spaced.lower()) if w]


def _kind_from_name(name: str) -> tuple[str | None, str]:
    """(kind, the letters before the kind word in that word: GarmentCode's ``lf`` of
    ``lfsleeve``)."""
    for w in _words(name):
        if w in _SHORT_KIND:
            return _SHORT_KIND[w], ""
        for word, kind in _KIND_WORDS:
            if word == "wb" and w != "wb":
                continue
            at = w.find(word)
            if at >= 0:
                return kind, w[:at]
    return None, ""


def _side_from_name(name: str, prefix: str) -> str | None:
    words = _words(name)
    if any(w in ("front", "fr", "ft", "f", "frt") for w in words) or "f" in prefix:
        return "front"
    if any(w in ("back", "bk", "b", "bck") for w in words) or "b" in prefix:
        return "back"
    joined = "".join(words)
    if "front" in joined:
        return "front"
    if "back" in joined:
        return "back"
    return None


def _hand_from_name(name: str, prefix: str) -> str | None:
    words = _words(name)
    if any(w in ("left", "l", "lt", "lft") for w in words) or prefix.startswith("l") \
            or any(w.startswith("left") for w in words):
        return "left"
    if any(w in ("right", "r", "rt", "rgt") for w in words) or prefix.startswith("r") \
            or any(w.startswith("right") for w in words):
        return "right"
    return None


def upright_turn(up) -> np.ndarray:
    """(2, 2) rotation turning the unit direction ``up`` (2,) onto +y (points: ``p @ M.T``);
    a rotation keeps every length and the right side up."""
    u = np.asarray(up, dtype=np.float64)
    u = u / np.linalg.norm(u)
    return np.array([[u[1], -u[0]], [u[0], u[1]]])


class _Shape:
    """A panel's outline points (k, 2) [m] and its edges, turned so that its grain line
    (warp along the body's height) is +y."""

    def __init__(self, panel):
        self.panel = panel
        self.turn = upright_turn(panel.grainline)
        self.points = panel.outline.polygon(16) @ self.turn.T
        self.lo, self.hi = self.points.min(axis=0), self.points.max(axis=0)
        self.size = self.hi - self.lo
        self.centre = self.points.mean(axis=0)
        self.edges = panel.edges()
        #: -1 or +1 when the panel is a half whose centre line is its left or right side
        self.half = 0
        #: the other half's name, for a half
        self.twin: str | None = None

    def line(self, edge: str) -> np.ndarray:
        """The edge as a polyline (17, 2) [m], turned."""
        return self.edges[edge].polyline(16) @ self.turn.T

    def mid(self, edge: str) -> np.ndarray:
        return self.edges[edge].point_at([0.5])[0] @ self.turn.T

    def at_top(self, edge: str) -> bool:
        e = self.line(edge)
        return float(e[:, 1].mean()) >= self.hi[1] - TOP_SHARE * self.size[1]

    def reaches_top(self, edge: str) -> bool:
        """Whether ``edge`` reaches the panel's top (an armhole runs down from it)."""
        e = self.line(edge)
        return float(e[:, 1].max()) >= self.hi[1] - TOP_SHARE * self.size[1]

    def outer(self, edge: str, at: float = 0.5) -> float:
        """Where ``edge`` (its point at ``at``) lies across the panel: -1 at its left side,
        +1 at its right. For a half, across the whole panel it is one half of: 0 at the
        centre line, and a half whose centre line is its left side spans 0..1, the other
        -1..0."""
        x = self.side_of(edge, at)
        return 0.5 * (x - self.half) if self.half else x

    def reach(self, edge: str) -> float:
        """How far out across the (whole) panel ``edge`` reaches: 1 at its widest point."""
        half = max(0.5 * self.size[0], 1e-9)
        x = (self.line(edge)[:, 0] - 0.5 * (self.lo[0] + self.hi[0])) / half
        return float(np.max(np.abs(0.5 * (x - self.half) if self.half else x)))

    def drawn(self, edge: str, at: float = 0.5) -> float:
        """:meth:`outer` as seen from the panel's outside: a panel drawn clockwise is drawn
        as seen from inside (GarmentCode's backs, seen from the front), mirrored."""
        return self.outer(edge, at) * (1.0 if self.panel.outline.signed_area() > 0 else -1.0)

    def side_of(self, edge: str, at: float = 0.5) -> float:
        """Where ``edge`` (its point at arc-length fraction ``at``) lies across this panel
        alone: -1 at its left side, +1 at its right."""
        half = max(0.5 * self.size[0], 1e-9)
        x = self.edges[edge].point_at([at])[0] @ self.turn.T
        return float((x[0] - 0.5 * (self.lo[0] + self.hi[0])) / half)

    def across(self, edge: str) -> bool:
        """Whether ``edge`` runs more across the panel than up it (a shoulder, a waist)."""
        d = self.turn @ (self.edges[edge].end - self.edges[edge].start)
        return abs(float(d[0])) > abs(float(d[1]))

    def forked(self) -> bool:
        """Whether the panel is widest in its upper half (a trouser leg at its crotch point;
        skirts and bodices are widest at the hem or the sleeves)."""
        p = self.points
        mid_y = self.lo[1] + 0.5 * self.size[1]
        widest = p[[int(np.argmin(p[:, 0])), int(np.argmax(p[:, 0]))], 1]
        return bool((widest > mid_y).any()) and bool((widest < self.hi[1] - 0.05).all())

    @property
    def whole_width(self) -> float:
        """The width [m] of the whole panel this one is (both halves of a half)."""
        return float(self.size[0]) * (2 if self.half else 1)

    @property
    def whole_area(self) -> float:
        """The area [m^2] of the whole panel this one is (both halves of a half)."""
        return self.panel.area() * (2 if self.half else 1)

    def curved(self, edge: str) -> bool:
        return self.edges[edge].kind != "line"

    @property
    def aspect(self) -> float:
        return float(max(self.size) / max(min(self.size), 1e-9))

    @property
    def length(self) -> float:
        return float(max(self.size))

    def top_dip(self) -> float:
        """How far the middle of the top falls below the top's two highest points [m]
        (a neckline's depth)."""
        p = self.points
        middle = {0: self.centre[0], -1: self.lo[0], 1: self.hi[0]}[self.half]
        mid = np.abs(p[:, 0] - middle) < 0.1 * self.size[0]
        return float(self.hi[1] - p[mid, 1].max()) if mid.any() else 0.0


def _links(pattern) -> dict[str, list[tuple[str, str, str]]]:
    """For each panel, its seams as (own edge, other panel, other edge)."""
    out: dict[str, list[tuple[str, str, str]]] = {p.name: [] for p in pattern.panels}
    for s in pattern.seams:
        out[s.a.panel].append((s.a.edge, s.b.panel, s.b.edge))
        if s.b.panel != s.a.panel or s.b.edge != s.a.edge:
            out[s.b.panel].append((s.b.edge, s.a.panel, s.a.edge))
    return out


def _structural_kinds(pattern, shapes, links, kinds, why) -> None:
    """Fill the kinds the names left open from the seams and shapes."""
    open_ = [p.name for p in pattern.panels if kinds[p.name] is None]
    for n in open_:
        sh = shapes[n]
        seam = _tube_seam(n, shapes, links)
        if seam is None:
            continue
        girth = float(np.linalg.norm(sh.mid(seam[0]) - sh.mid(seam[1])))
        if girth >= TORSO_TUBE:
            kinds[n] = "skirt"
            why[n] = f"sewn to itself along two long edges, {girth:.2f} m apart: a tube round " \
                     "the body"
        else:
            kinds[n] = "leg" if sh.length >= LEG_LENGTH + 0.2 else "sleeve"
            why[n] = "sewn to itself along two long edges (a tube)"
    for n in open_:
        sh = shapes[n]
        if kinds[n] is None and sh.aspect >= BAND_ASPECT:
            others = [(o, oe) for _, o, oe in links[n] if o != n]
            if any(kinds.get(o) == "sleeve" for o, _ in others):
                kinds[n], why[n] = "cuff", "a band sewn to a sleeve"
            elif any(shapes[o].at_top(oe) and abs(shapes[o].outer(oe)) < 0.5
                     and _shoulders(o, shapes, links) for o, oe in others):
                kinds[n], why[n] = "collar", "a band sewn at the top of a bodice"
            else:
                kinds[n], why[n] = "waistband", "a long narrow band"
    for n in open_:  # legs: long forked panels sewn to others along a curve at their top
        sh = shapes[n]
        partners = {o for _, o, _ in links[n] if o != n}
        if kinds[n] is None and sh.size[1] >= LEG_LENGTH and sh.forked() and len(partners) > 1 \
                and any(
                sh.curved(e) and sh.at_top(e) and o != n and shapes[o].size[1] >= LEG_LENGTH
                and shapes[o].curved(oe) and kinds[o] in (None, "leg")
                and _mirror_twins(sh, shapes[o]) and abs(sh.outer(e)) > 0.3
                for e, o, oe in links[n]):
            kinds[n], why[n] = "leg", "long, sewn to its mirror image along a curve (crotch)"
    for n in open_:  # sleeves: sewn by their top into another panel's top outer corner
        sh = shapes[n]
        if kinds[n] is None and any(
                o != n and kinds[o] in (None, "bodice") and shapes[o].reaches_top(oe)
                and abs(shapes[o].outer(oe)) > 0.5 and sh.curved(e)
                and sh.panel.area() < SLEEVE_AREA * shapes[o].whole_area
                for e, o, oe in links[n]
                if _is_armhole(shapes[o], oe) and _cap_of(sh, e)):
            kinds[n], why[n] = "sleeve", "sewn by a curved end into an armhole"
    for n in open_:  # hoods: sewn by their lower edges into necklines, and to a twin
        if kinds[n] is None and _is_hood(n, shapes, links, kinds):
            kinds[n] = "hood"
            why[n] = "sewn by its lower edges into a neckline and to its twin along a curve"
    for n in open_:  # collars: small pieces sewn at a bodice's top near its centre line
        sh = shapes[n]
        # (a yoke is sewn across the whole width of the back, a collar into its neckline)
        if kinds[n] is None and sh.length < HOOD_SIZE and any(
                o != n and kinds[o] in (None, "bodice") and shapes[o].at_top(oe)
                and abs(shapes[o].outer(oe)) < 0.5
                and sh.panel.area() < COLLAR_AREA * shapes[o].whole_area
                and shapes[o].edges[oe].length < 0.5 * shapes[o].whole_width
                and _shoulders(o, shapes, links) for e, o, oe in links[n]):
            kinds[n], why[n] = "collar", "a small piece sewn into a bodice's neckline"
    for n in open_:
        if kinds[n] is None:
            sewn_up = any(o != n and kinds[o] in ("bodice",) for _, o, _ in links[n])
            named = _named_neck(shapes[n])
            hole = None if named else _neck_hole(n, shapes, links)
            if _set_shoulder(n, shapes, links):
                kinds[n], why[n] = "bodice", "sewn at its top to another panel's top (shoulders)"
            elif named or hole:
                kinds[n] = "bodice"
                why[n] = f"an edge at its top named {named!r}" if named else hole
            else:
                kinds[n] = "skirt"
                why[n] = "sewn below a bodice" if sewn_up else "a body panel without shoulders"


def _tube_seam(n: str, shapes, links) -> tuple[str, str] | None:
    """The two edges along which panel ``n`` is sewn to itself into a tube (each at least
    half the panel's length), or None."""
    sh = shapes[n]
    for e, other, oe in links[n]:
        if other == n and min(sh.edges[e].length, sh.edges[oe].length) >= 0.5 * sh.length:
            return e, oe
    return None


def _shoulders(n: str, shapes, links) -> bool:
    """Whether panel ``n`` hangs from shoulders: :func:`_set_shoulder`, an edge named for
    the neck or shoulders (:func:`_named_neck`) or a neck hole between two seams across its
    top (:func:`_neck_hole`)."""
    return _set_shoulder(n, shapes, links) or _named_neck(shapes[n]) is not None \
        or _neck_hole(n, shapes, links) is not None


def _set_shoulder(n: str, shapes, links) -> bool:
    """Whether panel ``n`` has a shoulder: an edge at its top, off its centre line, running
    across it, shorter than :data:`HALF_SEAM` of its height and not out to its widest point
    (an armhole lies beyond; a flared skirt's or tier's side seams run out to it), sewn to the
    top of another panel that is not a band."""
    sh = shapes[n]
    return any(o != n and sh.at_top(e) and shapes[o].at_top(oe) and abs(sh.outer(e)) > 0.2
               and sh.across(e) and sh.edges[e].length <= HALF_SEAM * sh.size[1]
               and sh.reach(e) < 0.95 and shapes[o].aspect < BAND_ASPECT
               for e, o, oe in links[n])


def _named_neck(sh: _Shape) -> str | None:
    """The first outline edge reaching the panel's top whose name has a word beginning with
    one of :data:`NECK_WORDS` (``neck``, ``Shoulder_R``, ``armhole_l``, ``NeckLine``,
    ``arm hole``), or None. A skirt's edges are a waist, hip, side, hem or dart."""
    for edge in sh.panel.outline.edges:
        words = _words(edge.name)
        joined = "".join(words)
        if (any(w.startswith(NECK_WORDS) for w in words) or "armhole" in joined
                or "neckline" in joined) and sh.reaches_top(edge.name):
            return edge.name
    return None


def _between(order: list[str], a: str, b: str) -> tuple[list[str], list[str]]:
    """The outline edges strictly between ``a`` and ``b`` going forwards from ``a``, and
    going backwards from it."""
    i, j = order.index(a), order.index(b)
    k = len(order)
    fwd = [order[(i + s) % k] for s in range(1, (j - i) % k)]
    bwd = [order[(i - s) % k] for s in range(1, (i - j) % k)]
    return fwd, bwd


def _neck_hole(n: str, shapes, links) -> str | None:
    """Why panel ``n`` hangs from a neck hole, or None: two edges at its top, running across
    it on either side of its middle, sewn to the top of one other panel (not a band), with
    between them an unsewn stretch of the outline dipping at least :data:`NECK_DIP` below
    their inner ends and no deeper than :data:`NECK_DEPTH` of the panel (the neck hole);
    and, since a circle skirt's sector has that shape too (its waist between its side
    seams), one of: (a) on each side another seam to that panel lower down with an unsewn
    stretch between (an armhole, a kimono sleeve's cuff: a boxy top, a kimono tee); (b) the
    panel fills :data:`BOX_FILL` of its upright bounding box (hanging straight from the
    shoulders: a poncho); (c) the file's own 3D placement puts the hole at least
    :data:`NECK_PLACED` high (a GarmentCode top placed at the neck)."""
    sh = shapes[n]
    order = [e.name for e in sh.panel.outline.edges]
    sewn = {e for e, _, _ in links[n]}
    for o in sorted({o for _, o, _ in links[n] if o != n}):
        if shapes[o].aspect >= BAND_ASPECT:
            continue
        tops = [e for e, oo, oe in links[n] if oo == o and e in order and sh.at_top(e)
                and shapes[o].at_top(oe) and sh.across(e)]
        for a in [e for e in tops if sh.side_of(e) < -0.2]:
            for b in [e for e in tops if sh.side_of(e) > 0.2]:
                gap = next((g for g in _between(order, a, b)
                            if g and not any(e in sewn for e in g)
                            and all(sh.reaches_top(e) for e in g)), None)
                if gap is None:
                    continue
                ends = np.array([pt for e in gap for pt in (sh.edges[e].start, sh.edges[e].end)])
                inner = []  # the heights of a's and b's ends at the gap
                for side in (a, b):
                    pts = np.array([sh.edges[side].start, sh.edges[side].end])
                    at = pts[int(np.argmin(np.linalg.norm(pts[:, None] - ends[None],
                                                          axis=2).min(axis=1)))]
                    inner.append(float((at @ sh.turn.T)[1]))
                pts = np.vstack([sh.line(e) for e in gap])
                low = float(pts[:, 1].min())
                if low < sh.hi[1] - NECK_DEPTH * sh.size[1]:
                    continue
                # a straight (slash, bateau) neck does not dip: its arm openings alone say
                # it is a top (read as a skirt, it was worn round the waist)
                why = _neck_support(n, o, a, b, gap, shapes, links, order,
                                    arms_only=low > min(inner) - NECK_DIP)
                if why:
                    return why
    return None


def _neck_support(n, o, a, b, gap, shapes, links, order, *, arms_only: bool = False
                  ) -> str | None:
    """(a), (b) or (c) of :func:`_neck_hole`, in words, or None; (a) alone with
    ``arms_only`` (a neck that does not dip :data:`NECK_DIP`)."""
    sh = shapes[n]
    sewn = {e for e, _, _ in links[n]}
    to_o = [e for e, oo, _ in links[n] if oo == o and e in order]
    openings = 0
    for top in (a, b):
        sign = np.sign(sh.side_of(top))
        top_low = float(sh.line(top)[:, 1].min())
        for c in to_o:
            if c in (a, b) or np.sign(sh.side_of(c)) != sign \
                    or float(sh.line(c)[:, 1].max()) > top_low + 1e-6:
                continue
            path = next(g for g in _between(order, top, c) if not set(g) & set(gap))
            if any(e not in sewn for e in path):
                openings += 1
                break
    if openings == 2:
        return "a neck hole between seams across its top, openings for the arms below them"
    if arms_only:
        return None
    if sh.panel.area() >= BOX_FILL * float(sh.size[0] * sh.size[1]):
        return "a neck hole between seams across its top, hanging straight from them"
    place = sh.panel.placement
    if place.explicit:
        pts = np.vstack([sh.edges[e].polyline(16) for e in gap])
        height = float(place.transform(pts)[:, 1].mean())
        if NECK_PLACED <= height <= NECK_PLACED_MAX:
            return f"a neck hole between seams across its top, placed {height:.2f} m high " \
                   "by the file"
    return None


def _mirror_twins(a: _Shape, b: _Shape) -> bool:
    """Whether two panels are mirror images: the same size across and up (within 5 mm),
    area and outline length (within 0.5 %; GarmentCode splits the halves' edges differently
    where other panels join them)."""
    area, length = a.panel.area(), a.panel.outline.length
    return bool(np.all(np.abs(a.size - b.size) < 5e-3)) \
        and abs(area - b.panel.area()) < 0.005 * area \
        and abs(length - b.panel.outline.length) < 0.005 * length


def _mark_halves(pattern, shapes, links) -> None:
    """Set ``half`` on each panel that is one half of a panel cut at its centre line: sewn
    to its mirror twin along one straight edge only, at a side of both (running up them, at
    least :data:`HALF_SEAM` of their height)."""
    for p in pattern.panels:
        n, sh = p.name, shapes[p.name]
        by_other: dict[str, list] = {}
        for e, o, oe in links[n]:
            if o != n:
                by_other.setdefault(o, []).append((e, oe))
        for o, pairs in by_other.items():
            if len(pairs) != 1 or not _mirror_twins(sh, shapes[o]):
                continue
            e, oe = pairs[0]
            sides = [(shapes[k], edge) for k, edge in ((n, e), (o, oe))]
            if all(s.edges[edge].kind == "line" and abs(s.side_of(edge)) > 0.9
                   and not s.across(edge) and s.edges[edge].length >= HALF_SEAM * s.size[1]
                   for s, edge in sides):
                sh.half, sh.twin = (-1 if sh.side_of(e) < 0 else 1), o
                break


def _is_hood(n: str, shapes, links, kinds) -> bool:
    """Whether panel ``n`` is one half of a hood: at least :data:`HOOD_SIZE` long and not
    a band, sewn to a twin (a panel of the same area within :data:`TWIN_AREA`, not yet
    known to be anything else) along a curve (the crown), and otherwise only by edges below
    its top into edges at the top of other panels (the front and back necklines); nothing at
    its top goes into another panel's top (shoulders)."""
    sh = shapes[n]
    if sh.length < HOOD_SIZE or sh.aspect >= BAND_ASPECT:
        return False
    area = sh.panel.area()
    twin = necks = 0
    for e, o, oe in links[n]:
        if o == n:
            return False
        if kinds[o] in (None, "hood") and abs(shapes[o].panel.area() - area) <= TWIN_AREA * area:
            if sh.curved(e) or shapes[o].curved(oe):
                twin += 1
            continue
        if sh.at_top(e) or not shapes[o].at_top(oe) or kinds[o] not in (None, "bodice"):
            return False
        necks += 1
    return twin > 0 and necks > 0


def _mirrored_legs(a: _Shape, b: _Shape, kind: str) -> bool:
    """Whether two sewn leg panels are the left and right of one side (mirror images, sewn
    along the crotch: front to front, back to back): the same area within 1 %; a leg's
    front and back differ (the back's crotch extension is the longer)."""
    return kind == "leg" and abs(a.panel.area() - b.panel.area()) < 0.01 * a.panel.area()


def _is_armhole(shape: _Shape, edge: str) -> bool:
    """An edge at the top outer corner of a panel, curved, and not its highest point."""
    e = shape.line(edge)
    return shape.curved(edge) and float(e[:, 1].min()) < shape.hi[1] - 0.05


def _cap_of(shape: _Shape, edge: str) -> bool:
    """Whether ``edge`` lies at an end of the panel's long axis (a sleeve cap)."""
    e = shape.line(edge)
    axis = int(np.argmax(shape.size))
    span = shape.size[axis]
    m = float(e[:, axis].mean())
    return m >= shape.hi[axis] - 0.35 * span or m <= shape.lo[axis] + 0.35 * span


def panel_roles(pattern) -> dict[str, PanelRole]:
    """Every panel's :class:`PanelRole`, by panel name (see the module's docstring)."""
    shapes = {p.name: _Shape(p) for p in pattern.panels}
    links = _links(pattern)
    _mark_halves(pattern, shapes, links)
    kinds: dict[str, str | None] = {}
    why: dict[str, str] = {}
    prefix: dict[str, str] = {}
    for p in pattern.panels:
        part = p.placement.part
        kind, prefix[p.name] = _kind_from_name(p.name)
        if part.startswith("arm"):
            kinds[p.name] = "cuff" if kind == "cuff" else "sleeve"
            why[p.name] = f"stated part {part}"
        elif part.startswith("leg"):
            kinds[p.name], why[p.name] = "leg", f"stated part {part}"
        else:
            kinds[p.name] = kind
            why[p.name] = f"named {p.name!r}" if kind else ""
    _structural_kinds(pattern, shapes, links, kinds, why)
    sides = _sides(pattern, shapes, links, kinds, prefix)
    out = {}
    for p in pattern.panels:
        kind = kinds[p.name]
        part = p.placement.part
        if kind in ("sleeve", "cuff", "leg") and part == "torso":
            limb = "leg" if kind == "leg" else "arm"
            part = f"{limb}_{_hand(pattern, p, shapes, links, kinds, prefix, sides)}"
        elif kind not in ("sleeve", "cuff", "leg"):
            part = "torso"
        out[p.name] = PanelRole(kind, part, sides[p.name], why[p.name],
                                side_named=sides[p.name] == _side_from_name(p.name,
                                                                            prefix[p.name]),
                                tube=_tube_seam(p.name, shapes, links) is not None)
    return out


def _sides(pattern, shapes, links, kinds, prefix) -> dict[str, str]:
    stated = {p.name: p.placement.side for p in pattern.panels}
    trusted = len({stated[p.name] for p in pattern.panels
                   if kinds[p.name] in ("bodice", "skirt", "leg")}) > 1
    sides = {}
    for p in pattern.panels:
        n = p.name
        by_name = _side_from_name(n, prefix[n])
        t = p.placement.translation
        if kinds[n] == "sleeve" and any(o == n for _, o, _ in links[n]):
            sides[n] = "outer"  # a tube: centred on the top of the arm
        elif kinds[n] == "hood" and not by_name:
            sides[n] = "left"  # a hood's half: its hand, once the necklines' sides are known
        elif by_name:
            sides[n] = by_name
        elif t is not None and abs(t[2]) > 1e-3:
            sides[n] = "back" if t[2] < 0 else "front"
        elif trusted or stated[n] not in ("front", "back"):
            sides[n] = stated[n]
        else:
            sides[n] = None
    # what is left: the deeper neckline is the front (else the first panel listed), and a
    # panel sewn to one of the same kind with a side faces the other way
    while any(v is None for v in sides.values()):
        todo = [p.name for p in pattern.panels if sides[p.name] is None]
        grew = False
        for n in todo:
            # a sleeve in two halves, or a collar's piece, faces as the body panel it shares
            # its longest seam with
            into = max(((shapes[n].edges[e].length, o) for e, o, _ in links[n]
                        if kinds[n] in ("sleeve", "collar") and kinds[o] in ("bodice", "skirt")),
                       default=None)
            known = [(sides[into[1]], True)] if into and sides.get(into[1]) else []
            # one of the same kind faces the other way (across a side seam); the other half
            # of a panel, the other leg of a pair and a tier sewn on across its middle the
            # same way
            known += [(sides[o], _mirrored_legs(shapes[n], shapes[o], kinds[n])
                       or shapes[n].twin == o
                       or (shapes[n].across(e) and abs(shapes[n].outer(e)) < 0.5))
                      for e, o, _ in links[n] if o != n and sides.get(o) in ("front", "back")
                      and kinds[o] == kinds[n]]
            # a panel sewn across (a waist seam) to one of another kind faces the same way
            known += [(sides[o], True) for e, o, oe in links[n]
                      if o != n and sides.get(o) in ("front", "back") and kinds[o] != kinds[n]
                      and shapes[n].across(e) and shapes[o].across(oe)
                      and kinds[o] in ("bodice", "skirt", "leg")]
            if known:
                side, same = known[0]
                sides[n] = side if same else ("back" if side == "front" else "front")
                grew = True
        if not grew:
            bodices = [n for n in todo if kinds[n] == "bodice"]
            first = max(bodices, key=lambda n: shapes[n].top_dip()) if bodices else todo[0]
            sides[first] = "front"
    # a hood's half is on the hand of the neckline it is sewn to, which needs that
    # neckline's side: read before it was known, a half sewn to the back's neckline was
    # taken for the front's and the hood went on backwards, twisted across the chest
    for p in pattern.panels:
        if kinds[p.name] == "hood" and not _side_from_name(p.name, prefix[p.name]):
            sides[p.name] = _hood_hand(pattern, p.name, shapes, kinds, sides)
    return sides


def _hood_hand(pattern, name: str, shapes, kinds, sides) -> str:
    """``"left"`` or ``"right"``: the hand of a hood's half, from where along the necklines
    its seams lie (a half is sewn to half of the front's neckline and half of the back's;
    each neckline edge is centred, so the edge as a whole says nothing), each seam weighted
    by its length."""
    left = 0.0
    for seam in pattern.seams:
        for mine, other in ((seam.a, seam.b), (seam.b, seam.a)):
            if mine.panel != name or other.panel == name \
                    or kinds[other.panel] not in ("bodice", "skirt"):
                continue
            shape = shapes[other.panel]
            front = sides.get(other.panel) != "back"
            x = shape.drawn(other.edge, 0.5 * (other.start + other.end))
            length = shape.edges[other.edge].length * abs(other.end - other.start)
            left += length if (x > 0) == front else -length
    return "left" if left >= 0 else "right"


def _hand(pattern, panel, shapes, links, kinds, prefix, sides) -> str:
    """``"left"`` or ``"right"``: the body side of a sleeve, cuff or leg."""
    by_name = _hand_from_name(panel.name, prefix[panel.name])
    if by_name:
        return by_name
    t = panel.placement.translation
    if t is not None and abs(t[0]) > 1e-3:
        return "left" if t[0] > 0 else "right"
    n = panel.name
    if kinds[n] == "leg":  # the crotch, sewn to the other leg's, is on the leg's inner side
        for e, o, _ in links[n]:
            if o != n and kinds[o] == "leg" and sides.get(o) == sides.get(n):
                front = sides.get(n) != "back"
                return "left" if (shapes[n].drawn(e) < 0) == front else "right"
    for e, o, oe in links[n]:
        if o != n and kinds[o] in ("bodice", "skirt"):
            front = sides.get(o) != "back"
            return "left" if (shapes[o].drawn(oe) > 0) == front else "right"
    return "left"


def garment_anchor(pattern, roles: dict[str, PanelRole] | None = None) -> str:
    """``"neck"`` when the garment hangs from the shoulders (a sleeve, collar or hood, or a
    bodice: two body panels sewn at their tops, the shoulders), else ``"waist"`` (skirts,
    trousers, waistbands)."""
    roles = roles if roles is not None else panel_roles(pattern)
    if any(r.kind in ("sleeve", "collar", "hood", "bodice") for r in roles.values()):
        return "neck"
    return "waist"
