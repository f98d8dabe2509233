"""Apparel-science fit measures of a draped garment: body–garment gap, ease at the girths,
contact pressure.

ϖ (:mod:`patternfit.fit.metrics`) says whether the cloth is stretched; a pattern maker also
reads *ease* (garment girth minus body girth, cm) and *clothing pressure* (kPa; about 1.3 kPa
is comfortable, 2.0 kPa the most for daily wear, after Kawabata). Everything here is a pure
function of the garment mesh, its positions ``(n, 3)`` [m] (Y up), the body, the fabric and
the solver's contact distance; the pressure is read from the force balance at rest
(:mod:`patternfit.fit.pressure`), not from the solver's contact penalty. Inside metres and
newtons; the results are in mm, cm and kPa as named.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from scipy.spatial import ConvexHull, QhullError, cKDTree

from ..body.measure import Loop, cross_section
from ..body.sdf import DistanceField
from ..geometry import triangle_areas, unique_edges
from .body_regions import REGIONS, body_regions, on_hands
from .lengths import limb_ends
from .pressure import force_balance_pressure, grain_coefficients

#: the girths measured, with the body's level of each (see :func:`girth_levels`)
GIRTHS = ("bust", "waist", "hip", "thigh_left", "thigh_right", "bicep_left", "bicep_right")
#: the thigh is measured this far below the crotch [m]
THIGH_BELOW_CROTCH = 0.04
#: the bicep is measured this share of the way from the shoulder point to the wrist [-]
BICEP_AT = 0.3
#: a girth counts as covered when no angular gap of the garment's section around the body
#: section's centre exceeds this [deg]
MAX_GAP_DEG = 30.0
#: garment section points further than this from the body section are not part of it [m]
SECTION_REACH = 0.25
#: a garment point this much nearer another body loop still belongs to the girth's [m]
SHARED_REACH = 0.03
#: a chain of the garment's section (one per panel and tube) takes part in a girth when it
#: spans at least this angle around the body section's centre [deg]: a tape measure goes
#: around the torso's chains, not around a sleeve hanging beside the waist (the 3K Table 2
#: coat's let-out sleeves, 30 cm out, read as +58 cm of waist ease; they span 4–8°, a
#: panel's chain around the torso 160–190°)
MIN_CHAIN_SPAN_DEG = 45.0
#: a waist that the garment does not go all around because its top rests below the body's
#: waist level (a skirt or trousers wider than the waist slide down until the body is as
#: wide: the skirt M, waist 78 cm, 6 cm down on female_average's 68.5 cm waist, read "fits"
#: with no waist ease; the trousers M, 90 cm, 3.5 cm down, too) is measured at the highest
#: level below it, :data:`WAIST_STEP` apart and down to this far [m], where the garment goes
#: all around: the ease where its waist rests. Not against the waist's girth: that counts
#: the body's own widening as slack (the demo's corrected skirt, 3 cm of ease in its 66.6
#: cm waist, resting 3 cm low, read +9.7 cm). Farther down the on-body check (``sim.onbody``,
#: 10 cm) calls the garment slid off
WAIST_BELOW = 0.10
WAIST_STEP = 0.01
#: ... and no farther than this below the garment's highest cloth there [m]: a top may
#: slope from front to back (the trousers M on female_average at 1K: cloth from 2 cm below
#: the waist, all around from 7 cm), while a waistband whose top the gathers below pull
#: into scallops goes all around nowhere, and lower down the plane cuts the gathered
#: skirt instead (its 78 cm band read 37 cm of waist ease on female_heavy)
WAIST_BAND = 0.05
#: a vertex this much farther from the body than the solver's contact distance still rests
#: on it (the penalty lets it sit a little inside; the distance field is interpolated) [m]
CONTACT_SLACK = 0.001


@dataclass(eq=False)
class Section:
    """One girth's cross-section of body and garment, in the section plane's 2D frame [m].

    ``body`` (k, 2) and ``garment`` (g, 2): the section points; ``body_hull`` and
    ``garment_hull``: the closed convex hull polygons (h, 2); ``body_cm``, ``garment_cm``:
    their perimeters [cm]; ``ease_cm`` = garment − body [cm]; ``origin`` (3,), ``normal``
    (3,): the plane [m]; ``covered``: whether the garment goes all around the body there;
    ``below_cm``: how far below the body's level the section was cut [cm] (0, or a waist
    the garment's top rests under, :data:`WAIST_BELOW`).
    """

    name: str
    origin: np.ndarray
    normal: np.ndarray
    body: np.ndarray
    garment: np.ndarray
    body_hull: np.ndarray
    garment_hull: np.ndarray
    body_cm: float
    garment_cm: float
    ease_cm: float | None
    covered: bool
    below_cm: float = 0.0


@dataclass(eq=False)
class FitMeasures:
    """The measures of one drape.

    gap_mm : (n,) float
        Signed distance of every garment vertex to the body surface [mm], negative inside.
    pressure_kpa : (n,) float
        Clothing pressure per vertex [kPa] (:mod:`patternfit.fit.pressure`), 0 off the body.
    contact : (n,) bool
        Vertices within the contact distance (the contact area).
    vertex_area : (n,) float
        3D area around each vertex [m²].
    sections : dict of str to Section
        The girths measured (covered or not).
    vertex_region, triangle_region : (n,) and (m,) int
        The body region of each vertex / triangle centroid, an index into
        :data:`~patternfit.fit.body_regions.REGIONS`.
    limb_ends : dict of str to float
        How far each covered limb's cloth stops short of the wrist or ankle [m]
        (:func:`~patternfit.fit.lengths.limb_ends`).
    vertex_on_hand, triangle_on_hand : (n,) and (m,) bool
        The vertices / triangle centroids over a hand
        (:func:`~patternfit.fit.body_regions.on_hands`), left out of the verdict's pressure
        and stretch: a sleeve resting on the hand is too long, not too tight.
    """

    gap_mm: np.ndarray
    pressure_kpa: np.ndarray
    contact: np.ndarray
    vertex_area: np.ndarray
    sections: dict = field(default_factory=dict)
    vertex_region: np.ndarray | None = None
    triangle_region: np.ndarray | None = None
    regions: tuple = REGIONS
    limb_ends: dict = field(default_factory=dict)
    vertex_on_hand: np.ndarray | None = None
    triangle_on_hand: np.ndarray | None = None

    def report(self) -> dict:
        """``gap_mm`` (p5, p50, p95, area-weighted over the garment), ``ease_cm`` (girth name
        → cm, only the girths the garment covers all around) and ``pressure_kpa`` (p50, p95,
        p99, max over the contact area, ``contact_vertices``, ``contact_area_m2``) and
        ``lengths_cm`` (limb → cm its cloth stops short of the wrist or ankle, negative
        beyond it), and ``ease_below_cm`` (girth → how far below the body's level the
        garment's girth was cut, for a waist its top rests under: ``Section.below_cm``);
        a value that cannot be measured is None, never NaN."""
        return {"gap_mm": gap_summary(self.gap_mm, self.vertex_area),
                "ease_cm": {k: s.ease_cm for k, s in self.sections.items() if s.covered},
                "ease_below_cm": {k: s.below_cm for k, s in self.sections.items()
                                  if s.below_cm},
                "pressure_kpa": pressure_summary(self.pressure_kpa, self.contact,
                                                 self.vertex_area),
                "lengths_cm": {k: round(100.0 * v, 2) for k, v in self.limb_ends.items()}}


# --------------------------------------------------------------------------- per vertex
def vertex_areas(triangles, positions) -> np.ndarray:
    """A third of the 3D area of every triangle around each vertex: (n,) [m²]."""
    t = np.asanyarray(triangles, dtype=np.int64)
    x = np.asanyarray(positions, dtype=np.float64)
    a = 0.5 * np.linalg.norm(np.cross(x[t[:, 1]] - x[t[:, 0]], x[t[:, 2]] - x[t[:, 0]]), axis=1)
    return np.bincount(t.ravel(), weights=np.repeat(a / 3.0, 3), minlength=len(x))


def gap(positions, body_field: DistanceField) -> np.ndarray:
    """Signed distance of each garment vertex to the body surface [mm], (n,), negative
    inside; from the body's distance field (``positions`` (n, 3) [m]). A vertex resting on
    the body reads the distance the solver keeps (the fabric thickness or the contact
    margin, 3 mm for :func:`patternfit.sim.drape.drape`)."""
    d, _ = body_field.query(positions)
    return 1000.0 * d


def _weighted_percentiles(values, weights, qs) -> list[float]:
    v = np.asanyarray(values, dtype=np.float64)
    w = np.asanyarray(weights, dtype=np.float64)
    ok = np.isfinite(v) & (w > 0)
    v, w = v[ok], w[ok]
    if len(v) == 0:
        return [None] * len(qs)
    order = np.argsort(v)
    v, w = v[order], w[order]
    c = (np.cumsum(w) - 0.5 * w) / w.sum()
    return [float(np.interp(q / 100.0, c, v)) for q in qs]


def gap_summary(gap_mm, areas) -> dict:
    """``p5``, ``p50``, ``p95`` of the gap [mm], weighted by vertex area (None if none)."""
    p5, p50, p95 = _weighted_percentiles(gap_mm, areas, (5, 50, 95))
    return {"p5": p5, "p50": p50, "p95": p95}


def pressure_summary(pressure_kpa, contact, areas) -> dict:
    """``p50``, ``p95``, ``p99``, ``max`` of the pressure [kPa] over the contact vertices,
    weighted by vertex area (None without contact), with ``contact_vertices`` and
    ``contact_area_m2``."""
    c = np.asanyarray(contact, dtype=bool)
    p = np.asanyarray(pressure_kpa, dtype=np.float64)[c]
    a = np.asanyarray(areas, dtype=np.float64)[c]
    p50, p95, p99 = _weighted_percentiles(p, a, (50, 95, 99))
    return {"p50": p50, "p95": p95, "p99": p99,
            "max": float(p.max()) if len(p) and np.isfinite(p).all() else None,
            "contact_vertices": int(c.sum()), "contact_area_m2": float(a.sum())}


# --------------------------------------------------------------------------- girths
def _frame(normal) -> np.ndarray:
    """Rotation (3, 3) taking ``normal`` to +Y (rows: the plane's u, normal, w axes); the
    identity for a horizontal plane, so that its 2D frame is (x, z)."""
    n = np.asanyarray(normal, dtype=np.float64)
    n = n / np.linalg.norm(n)
    ref = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 0.0, 1.0])
    u = ref - n * (ref @ n)
    u /= np.linalg.norm(u)
    w = np.cross(u, n)
    return np.array([u, n, w])


def plane_section(vertices, triangles, origin, normal) -> list[Loop]:
    """The curves where the plane through ``origin`` (3,) [m] with ``normal`` (3,) cuts the
    triangle mesh (vertices (n, 3) [m], triangles (m, 3)); closed loops for a closed mesh,
    open chains (one per panel) for a garment. Points are in the rotated frame of
    :func:`_frame` (its x, z columns are the plane's 2D coordinates), largest first."""
    r = _frame(normal)
    v = (np.asanyarray(vertices, dtype=np.float64) - origin) @ r.T
    return cross_section(v, triangles, 0.0)


def _hull(points2) -> tuple[np.ndarray, float]:
    """Closed convex hull polygon (h + 1, 2) and its perimeter [m] of points (k, 2)."""
    if len(points2) < 3:
        return np.zeros((0, 2)), 0.0
    try:
        h = ConvexHull(points2)
    except QhullError:
        return np.zeros((0, 2)), 0.0
    poly = points2[h.vertices]
    return np.vstack([poly, poly[:1]]), float(h.area)


def girth_levels(body) -> dict[str, tuple[np.ndarray, np.ndarray, str]]:
    """Where each girth of :data:`GIRTHS` is measured on ``body``: name → (origin (3,) [m],
    plane normal (3,), which body loops: ``"torso"`` the largest, ``"all_big"`` every large
    loop (the hip: both legs' tops), ``"nearest"`` the loop nearest the origin).

    Bust, waist, hip: horizontal at the body's landmark heights (``bust_height`` ...).
    Thigh: horizontal, :data:`THIGH_BELOW_CROTCH` below the crotch, one leg each. Bicep:
    perpendicular to the arm axis, :data:`BICEP_AT` of the way from shoulder to wrist."""
    m, lm = body.measurements, body.landmarks
    y0 = body.floor
    up = np.array([0.0, 1.0, 0.0])
    out = {}
    c = lm["torso_axis"][0]
    for name, kind in (("bust", "torso"), ("waist", "torso"), ("hip", "all_big")):
        out[name] = (np.array([c[0], y0 + m[f"{name}_height"], c[2]]), up, kind)
    for side in ("left", "right"):
        leg = lm[f"leg_axis_{side}"]
        y = y0 + m["crotch_height"] - THIGH_BELOW_CROTCH
        out[f"thigh_{side}"] = (np.array([leg[0][0], y, leg[0][2]]), up, "nearest")
        s, w = lm[f"arm_axis_{side}"]
        out[f"bicep_{side}"] = (s + BICEP_AT * (w - s), w - s, "nearest")
    return out


def _body_loops(loops: list[Loop], kind: str, centre2) -> list[Loop]:
    if not loops:
        return []
    if kind == "torso":
        return loops[:1]
    if kind == "all_big":
        return [lp for lp in loops if lp.area >= 0.3 * loops[0].area]
    big = [lp for lp in loops if lp.area >= 0.03 * loops[0].area] or loops
    return [min(big, key=lambda lp: np.linalg.norm(lp.centroid[[0, 2]] - centre2))]


def _belongs(points, body_points, mine) -> np.ndarray:
    """Which garment section ``points`` (k, 2) belong to the chosen body loops (``mine``
    marks their points among ``body_points``): within :data:`SECTION_REACH` of them and no
    more than :data:`SHARED_REACH` farther from them than from another loop (a sleeve's
    underarm lies between the arm and the torso)."""
    dist = np.linalg.norm(points[:, None, :] - body_points[None, :, :], axis=2)
    to_mine = np.where(mine[None, :], dist, np.inf).min(axis=1)
    return (to_mine < SECTION_REACH) & (to_mine <= dist.min(axis=1) + SHARED_REACH)


def _around(chains: list[Loop], centre) -> list[Loop]:
    """The garment section's ``chains`` that go around the body: the angles of each one's
    points around ``centre`` (2,) [m] spanning at least :data:`MIN_CHAIN_SPAN_DEG` (all of
    the chains when none does)."""
    def span(lp: Loop) -> float:
        rel = lp.points[:, [0, 2]] - centre
        a = np.sort(np.degrees(np.arctan2(rel[:, 1], rel[:, 0])))
        return 360.0 - float(np.diff(np.append(a, a[0] + 360.0)).max())

    kept = [lp for lp in chains if len(lp.points) > 1 and span(lp) >= MIN_CHAIN_SPAN_DEG]
    return kept or chains


def _on_chains(segments, chains: list[Loop], kept: list[Loop]) -> np.ndarray:
    """Which ``segments`` (k, 2, 2) [m] of the section belong to the ``kept`` ones of its
    ``chains``: the chain point nearest each segment's midpoint is one of theirs."""
    pts = np.concatenate([lp.points[:, [0, 2]] for lp in chains])
    mine = np.concatenate([np.full(len(lp.points), any(lp is k for k in kept))
                           for lp in chains])
    _, nearest = cKDTree(pts).query(np.asanyarray(segments).mean(axis=1))
    return mine[nearest]


def section_segments(vertices, triangles, origin, normal) -> np.ndarray:
    """The segments (k, 2, 2) where the plane through ``origin`` (3,) [m] with ``normal``
    cuts the triangles, in the plane's 2D frame (:func:`_frame`; x and z columns)."""
    v = (np.asanyarray(vertices, dtype=np.float64) - origin) @ _frame(normal).T
    t = np.asanyarray(triangles, dtype=np.int64)
    s = v[:, 1].copy()
    s[s == 0.0] = 1e-12  # no vertex exactly on the plane: a crossing edge is cut once
    above = s[t] > 0
    cut = above.sum(axis=1) % 3 != 0
    out = []
    for tri in t[cut]:
        pts = []
        for i, j in ((0, 1), (1, 2), (2, 0)):
            a, b = tri[i], tri[j]
            if (s[a] > 0) != (s[b] > 0):
                w = s[a] / (s[a] - s[b])
                pts.append((v[a] + w * (v[b] - v[a]))[[0, 2]])
        out.append(pts[:2])
    return np.array(out, dtype=np.float64).reshape(-1, 2, 2)


def largest_gap_deg(segments, centre) -> float:
    """The largest angle [deg] around ``centre`` (2,) that no segment (k, 2, 2) covers, each
    segment covering the short way between its ends' angles: a sparse mesh's section has
    few points, but no gap where its segments join them."""
    bins = np.zeros(720, dtype=bool)  # half-degree bins
    for p, q in np.asanyarray(segments, dtype=np.float64):
        a0, a1 = (float(np.degrees(np.arctan2(r[1] - centre[1], r[0] - centre[0])))
                  for r in (p, q))
        span = (a1 - a0 + 180.0) % 360.0 - 180.0
        steps = np.arange(0.0, abs(span) + 0.5, 0.5) * (1.0 if span >= 0 else -1.0)
        bins[((a0 + steps) % 360.0 * 2).astype(int) % 720] = True
    if bins.all():
        return 0.0
    if not bins.any():
        return 360.0
    run = np.diff(np.flatnonzero(np.concatenate([bins, bins])))
    return float((run.max() - 1) * 0.5)


def girth_section(name, triangles, positions, body_vertices, body_faces, origin,
                  normal, kind) -> Section | None:
    """The body's and the garment's section for one girth (see :func:`ease`); None where
    the body has no section there."""
    centre2 = np.zeros(2)  # the origin, in the plane's own frame
    body_loops = plane_section(body_vertices, body_faces, origin, normal)
    chosen = _body_loops(body_loops, kind, centre2)
    if not chosen:
        return None
    bp = np.concatenate([lp.points[:, [0, 2]] for lp in chosen])
    bhull, bper = _hull(bp)
    if bper <= 0:
        return None
    chains = plane_section(positions, triangles, origin, normal)
    g_loops = _around(chains, bp.mean(axis=0))
    gp = (np.concatenate([lp.points[:, [0, 2]] for lp in g_loops]) if g_loops
          else np.zeros((0, 2)))
    if len(gp):
        # a garment point belongs to this girth when the body point nearest it is one of
        # the chosen loops' (a sleeve's section goes to the arm, not to the bust)
        allb = np.concatenate([lp.points[:, [0, 2]] for lp in body_loops])
        mine = np.concatenate([np.full(len(lp.points), any(lp is c for c in chosen))
                               for lp in body_loops])
        gp = gp[_belongs(gp, allb, mine)]
    ghull, gper = _hull(gp)
    covered = False
    if gper > 0:
        # the same choice for the segments, by their midpoints
        seg = section_segments(positions, triangles, origin, normal)
        seg = seg[_belongs(seg.mean(axis=1), allb, mine) & _on_chains(seg, chains, g_loops)]
        covered = largest_gap_deg(seg, bp.mean(axis=0)) <= MAX_GAP_DEG
    ease_cm = 100.0 * (gper - bper) if covered else None
    return Section(name, np.asanyarray(origin, dtype=np.float64), np.asanyarray(normal, float),
                   bp, gp, bhull, ghull, 100.0 * bper, 100.0 * gper, ease_cm, covered)


def ease(triangles, positions, body) -> dict[str, Section]:
    """The girths of :data:`GIRTHS` at the body's levels (:func:`girth_levels`) as
    :class:`Section` s; ``ease_cm`` of each = garment girth − body girth [cm], None where the
    garment does not go all around the body there.

    A girth is a tape measure's: the perimeter of the convex hull of the section, since the
    tape (and the cloth) bridges the body's hollows (between the breasts, the small of the
    back); the body's girth is taken the same way from the body mesh in the same plane (for
    bust, waist and hip that is the definition of the stored measurements). The garment's
    section is where the plane cuts its triangles (``positions`` (n, 3) [m]); its points
    that lie nearer another part of the body (a sleeve's, at bust height) are left out. A
    garment covers a girth when its section leaves no angular gap over
    :data:`MAX_GAP_DEG` around the body section's centre (a skirt covers no single thigh,
    an open jacket no bust). A waist the garment's top rests under is measured where the
    garment goes all around below it, body and garment alike (:data:`WAIST_BELOW`,
    ``Section.below_cm``)."""
    out = {}
    for name, (origin, normal, kind) in girth_levels(body).items():
        s = girth_section(name, triangles, positions, body.vertices, body.faces,
                          origin, normal, kind)
        if s is not None and name == "waist" and not s.covered:
            s = _waist_below(s, triangles, positions, body, origin, normal, kind)
        if s is not None:
            out[name] = s
    return out


def _waist_below(waist: Section, triangles, positions, body, origin, normal, kind) -> Section:
    """The ``waist`` section (not covered) taken instead at the highest level below it,
    within :data:`WAIST_BELOW` and :data:`WAIST_BAND` [m], where the garment goes all
    around: garment and body girths there; ``waist`` itself when there is none."""
    top = None
    for k in range(1, int(round(WAIST_BELOW / WAIST_STEP)) + 1):
        level = np.asanyarray(origin, dtype=np.float64) - k * WAIST_STEP * np.asarray(normal)
        s = girth_section(waist.name, triangles, positions, body.vertices, body.faces,
                          level, normal, kind)
        if s is None:
            continue
        if s.covered:
            return replace(s, below_cm=100.0 * k * WAIST_STEP)
        top = k if top is None and len(s.garment) else top
        if top is not None and (k - top) * WAIST_STEP >= WAIST_BAND:
            break  # past the garment's waistband: a gathered skirt's folds are no waist
    return waist


def resting(x, triangles, d, field: DistanceField, limit: float) -> np.ndarray:
    """Vertices (n,) bool resting on the body at ``x`` (n, 3) [m]: nearer its surface than
    ``limit`` [m] (their distances ``d`` (n,) [m]), or with the half of an edge next to them
    that near (looked up at a sixth, a third and half of the way along; the solver's contact
    acts inside the edges too, and a vertex whose edges rest on the body carries their load:
    a 1K skirt's waist is a polygon that touches the body along its sides, its corners some
    mm off)."""
    out = d < limit
    e = unique_edges(triangles)
    if not len(e):
        return out
    for a, b in ((0, 1), (1, 0)):
        near = np.zeros(len(e), bool)
        for frac in (1.0 / 6.0, 1.0 / 3.0, 0.5):
            near |= field.query(x[e[:, a]] * (1.0 - frac) + x[e[:, b]] * frac)[0] < limit
        out[e[near, a]] = True
    return out


def fit_measures(mesh, positions, body, fabric, body_field: DistanceField | None = None, *,
                 reach: float) -> FitMeasures:
    """Gap, pressure, ease and body regions of a garment ``mesh`` (a
    :class:`~patternfit.mesh.garment.GarmentMesh`) at ``positions`` (n, 3) [m] on ``body``
    (a :class:`~patternfit.body.model.Body`) in ``fabric``; ``body_field`` the distance
    field the drape used (the body's default one when None), ``reach`` [m] the solver's
    contact distance: vertices nearer the body than ``reach + CONTACT_SLACK`` rest on it.
    The pressure is the force balance of :mod:`patternfit.fit.pressure`."""
    f = body_field if body_field is not None else body.distance_field()
    x = np.asanyarray(positions, dtype=np.float64)
    t = mesh.triangles
    a = vertex_areas(t, x)
    d, grad = f.query(x)
    normals = grad / np.maximum(np.linalg.norm(grad, axis=1), 1e-12)[:, None]
    contact = resting(x, t, d, f, reach + CONTACT_SLACK)
    cu, cv = grain_coefficients(mesh.vertices, t, mesh.grain[mesh.triangle_panel])
    p = force_balance_pressure(x, t, cu, cv, triangle_areas(mesh.vertices, t), fabric,
                               normals, a, contact)
    vertex_region = body_regions(x, body)
    centroids = x[t].mean(axis=1)
    return FitMeasures(1000.0 * d, p, contact, a, ease(t, x, body), vertex_region,
                       body_regions(centroids, body),
                       limb_ends=limb_ends(x, t, vertex_region, body),
                       vertex_on_hand=on_hands(x, body),
                       triangle_on_hand=on_hands(centroids, body))
