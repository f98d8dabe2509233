"""On the body, or failed: checks that a draped garment rests on the body where its pattern
says it hangs from.

The solver's checks (:class:`~patternfit.sim.checks.DrapeChecks`: vertices inside the body,
seam gaps, crossings, equilibrium) hold as well for a garment that fell 25 m, lies on the
floor or slid from the shoulders to the hips; these do not. :func:`on_body_checks` is a
pure function of the pattern, its mesh, the body and the 3D state; every drape carries its
result (:attr:`patternfit.sim.drape.Drape.onbody`) and the report's ``checks`` hold it
(``docs/simulation.md``, "On the body, or failed"). Units: metres inside, mm in the checks.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from ..constants import tol
from ..geometry import triangle_areas, unique_edges
from ..mesh.garment import GarmentMesh
from ..pattern.model import Pattern
from ..pattern.roles import garment_anchor, panel_roles
from .checks import crossing_reasons, inside_reason, seam_gap_mm, seam_gap_reason
from .panel_frames import ANCHOR_HEIGHT, upright_frames

#: a body panel whose top lies this far [m] below the garment's top does not hold the
#: anchor (the trousers' back rises 3 cm above the front; a dress's skirt starts 40 cm down)
ANCHOR_PANELS = 0.05



@dataclass(frozen=True)
class OnBodySettings:
    """Thresholds of the on-body checks, all lengths in metres.

    below_feet : float
        A vertex lower than ``-below_feet`` is below the feet (the floor is y = 0; the
        solver's floor, ``Body.contact_field``, holds cloth above it near the body, so a
        vertex below fell past the floor's end).
    far : float
        A vertex farther than this from the body surface (the body's distance field), and
        farther than the cloth that ties it to the anchor line is long
        (:func:`anchor_reach`), is off the body (measured on the built-in garments on the
        six built-in bodies: at most 0.23 m, the flared skirt's hem on the thin man; a
        tiered circle skirt's hem, hanging from the neck, stands 0.49 m out).
    anchor_tolerance : float
        The garment's anchor line may end this far above or below the body's anchor
        height (measured on the six built-in bodies: the skirt rests up to 6.8 cm below
        the waist landmark, where its eased waist meets the body; dress and coat within
        2 cm of the neck base; trousers on women 7–10 cm low, hems through the floor,
        before the solver had a floor).
    top_band : float
        The anchor line: the outline vertices of each panel not on an arm within this
        distance of the panel's top in the flat pattern (the top that placement puts at
        the anchor height) [m].
    min_area_ratio : float
        A state whose 3D area is below this share of the flat area has collapsed [-].
    side_angle : float
        A torso or leg panel named for the front or back whose centroid hangs more than
        this far round the body (or its leg) from that side (:func:`side_angles`) is
        twisted [degrees] (the built-in garments: at most 5; a dress turned a quarter
        round: 84 and 92; a gore of a four-gore skirt: 45, and a princess seam's side
        panel may reach some 60-70).
    named_anchor_level : float
        The edges named for the anchor (a "waist" or "neck" edge) must hang above this
        share of the garment's height from its lowest point, or it is upside down [-]
        (the built-in garments on their bodies at 1,000 triangles: 0.91 (gathered skirt) to
        0.99; a skirt, dress or coat drawn with its grain lines pointing down: 0.01–0.03).
    round_gap : float
        A garment hung from the waist goes round the body at a height where its cloth's
        cross-section leaves no gap wider than this round the body's torso axis [degrees]
        (:func:`round_the_body_from`); the highest such height must lie within
        ``anchor_tolerance`` of the waist, unless the anchor line hangs less than ``flap``
        above it (then the anchor line's own check judges: a skirt resting at the limit
        goes round the body a few mm below its top line).
    flap : float
        Cloth standing more than this above the height where a waist garment goes round
        the body is a flap (a bib), not its waist [m].
    floor_touch : float
        A garment whose lowest point is this near the floor rests on it [m]: its drape is
        continued without the floor (:func:`patternfit.sim.drape.without_floor`) and its
        anchor line checked where that ends (:func:`floor_checked`).
    floor_iterations : int
        The most iterations of that solve without the floor, run ``floor_chunk`` at a time;
        it ends sooner at rest, when the anchor line leaves ``anchor_tolerance`` or when a
        chunk moved it less than ``floor_held`` [m] (held by the body).
    """

    below_feet: float = 0.02
    far: float = 0.30
    anchor_tolerance: float = 0.10
    top_band: float = 0.01
    min_area_ratio: float = 0.5
    side_angle: float = 75.0
    named_anchor_level: float = 0.5
    round_gap: float = 60.0
    flap: float = 0.05
    floor_touch: float = 0.01
    floor_iterations: int = 500
    floor_chunk: int = 50
    floor_held: float = 0.001


#: the thresholds every drape is checked with
ON_BODY = OnBodySettings()


@dataclass(frozen=True)
class OnBodyChecks:
    """Whether a 3D state rests on the body where its pattern says (:func:`on_body_checks`).

    Lengths in mm; ``reasons`` names every failed check in words (empty: passed).
    """

    #: vertices below the feet (y < -below_feet) and the lowest height [mm]
    below_feet_vertices: int
    lowest_mm: float | None
    #: vertices farther than ``far`` from the body surface, and the farthest [mm]
    far_vertices: int
    farthest_mm: float | None
    #: ``"waist"`` or ``"neck"`` (:attr:`Pattern.anchor`)
    anchor: str
    #: mean height of the garment's anchor line, the body's anchor height, and the first
    #: minus the second [mm]
    anchor_height_mm: float | None
    landmark_height_mm: float
    anchor_offset_mm: float | None
    #: 3D area over flat area [-]
    area_ratio: float | None
    reasons: tuple[str, ...] = ()
    #: where the edges named for the anchor (:func:`named_anchor_edges`: "waist", "neck")
    #: hang, as a share of the garment's height from its lowest point (1: at its top) [-];
    #: None without such edges
    named_anchor_level: float | None = None
    #: the largest of :func:`side_angles` [degrees]; None without torso or leg panels
    #: named for the front or back
    side_angle_max_deg: float | None = None
    #: the anchor line ended below the body's crotch: nothing of the torso holds the
    #: garment there, it fell (a skirt round the shins, its hem on the floor)
    top_below_crotch: bool = False
    #: a garment hung from the waist: the highest height at which its cloth goes round the
    #: body (:func:`round_the_body_from`) minus the waist's [mm]; None when it goes round
    #: nowhere, or hangs from the neck
    round_offset_mm: float | None = None
    #: a garment resting on the floor (its lowest point within ``floor_touch`` of it),
    #: continued without the floor (:func:`patternfit.sim.drape.without_floor`): its anchor
    #: line's height minus the landmark's where that ended, how far it dropped, in how many
    #: iterations, and whether it came to rest or was held [mm]; None when not run
    without_floor_offset_mm: float | None = None
    without_floor_drop_mm: float | None = None
    without_floor_iterations: int | None = None
    without_floor_held: bool | None = None

    @property
    def passed(self) -> bool:
        """On the body where the pattern says: no reason to fail."""
        return not self.reasons

    def to_dict(self) -> dict:
        return {"below_feet_vertices": self.below_feet_vertices, "lowest_mm": self.lowest_mm,
                "far_vertices": self.far_vertices, "farthest_mm": self.farthest_mm,
                "anchor": self.anchor, "anchor_height_mm": self.anchor_height_mm,
                "landmark_height_mm": self.landmark_height_mm,
                "anchor_offset_mm": self.anchor_offset_mm, "area_ratio_3d": self.area_ratio,
                "named_anchor_level": self.named_anchor_level,
                "side_angle_max_deg": self.side_angle_max_deg,
                "top_below_crotch": self.top_below_crotch,
                "round_offset_mm": self.round_offset_mm,
                "without_floor_offset_mm": self.without_floor_offset_mm,
                "without_floor_drop_mm": self.without_floor_drop_mm,
                "without_floor_iterations": self.without_floor_iterations,
                "without_floor_held": self.without_floor_held,
                "on_body": self.passed, "on_body_reasons": list(self.reasons)}


def anchor_line(pattern: Pattern, mesh: GarmentMesh, *, band: float = ON_BODY.top_band
                ) -> np.ndarray:
    """Flat vertex ids of the garment's anchor line: the outline vertices lying within
    ``band`` [m] of their panel's top, over the body panels whose top is within
    :data:`ANCHOR_PANELS` of the garment's top (a dress's bodice, not its skirt sewn at the
    waist), in the upright frames placement uses (:func:`~.panel_frames.upright_frames`);
    sleeves, cuffs, hoods and collars are not body panels (all panels when every one is)."""
    roles = panel_roles(pattern)
    flat = upright_frames(pattern, mesh, roles)
    boundary = np.zeros(mesh.n_vertices, dtype=bool)
    boundary[mesh.boundary_vertices] = True
    names = list(mesh.panel_names)
    chosen = [i for i, n in enumerate(names)
              if roles[n].kind not in ("sleeve", "cuff", "hood", "collar")] or range(len(names))
    tops = {i: float(flat[mesh.panel_vertices(i), 1].max()) for i in chosen}
    top = max(tops.values())
    out = []
    for i in chosen:
        if tops[i] < top - ANCHOR_PANELS:
            continue
        ids = mesh.panel_vertices(i)
        ids = ids[boundary[ids]]
        if len(ids):
            y = flat[ids, 1]
            out.append(ids[y >= y.max() - band])
    return np.concatenate(out) if out else np.zeros(0, dtype=np.int64)


def anchor_reach(pattern: Pattern, mesh: GarmentMesh, *, band: float = ON_BODY.top_band
                 ) -> np.ndarray:
    """How far [m] each vertex lies from the anchor line (:func:`anchor_line`) along the
    flat cloth, seams crossed where they sew (shortest paths over the mesh's edges at
    their flat lengths, seam pairs joined at no length: up to about 10 % longer than the
    straight way across a panel); ``(n,)``, ``inf`` for a piece sewn to nothing that holds
    the anchor line.

    The bound of the far-from-body check: cloth hanging from an anchor line on the body
    cannot stand out from the body farther than the cloth between them is long (a full
    circle skirt's hem stands out by up to its length, a sleeve's cuff by up to the
    sleeve's); a piece that flew off, or a garment displaced off the body, does.
    """
    n = mesh.n_vertices
    e = unique_edges(mesh.triangles)
    w = np.linalg.norm(mesh.vertices[e[:, 0]] - mesh.vertices[e[:, 1]], axis=1)
    pairs = np.asarray(mesh.seam_pairs, dtype=np.int64).reshape(-1, 2)
    # a seam pair sits at one point once sewn: a tiny length (csgraph drops zero weights)
    e = np.concatenate([e, pairs])
    w = np.concatenate([w, np.full(len(pairs), 1e-12)])
    graph = coo_matrix((w, (e[:, 0], e[:, 1])), shape=(n, n)).tocsr()
    line = anchor_line(pattern, mesh, band=band)
    if not len(line):
        return np.full(n, np.inf)
    return dijkstra(graph, directed=False, indices=line, min_only=True)


def named_anchor_edges(pattern: Pattern, mesh: GarmentMesh) -> list[tuple[str, str]]:
    """The (panel, edge) boundary edges of the mesh whose names say they are the garment's
    anchor (:attr:`Pattern.anchor`): "waist" in the name for a garment hung from the waist,
    "neck" for one hung from the neck; empty when the file names none so (a DXF's e1, e2)."""
    word = "waist" if pattern.anchor == "waist" else "neck"
    return [(p, e) for p, e in mesh.edge_names if word in e.lower()]


def side_angles(pattern: Pattern, mesh: GarmentMesh, body, positions) -> dict[str, float]:
    """How far round the body each panel named for the front or back (its role's
    ``side_named``, :func:`~patternfit.pattern.roles.panel_roles`) of the torso or a leg
    hangs from that side, in degrees: the angle, seen from above, between the direction
    from the part's axis to the panel's area-weighted centroid (``positions`` (n, 3) [m], y
    up, the body facing +z) and the side's direction. The torso's axis is the body's; a
    leg's is half-way between its front and its back panels' centroids (trousers turned
    back to front hung each front panel behind its leg, which the torso's axis, beside the
    legs, does not see), and a leg without both is left out. Panels of one part named for
    one side and sewn to each other count as one, under their names joined by ", " (an
    eight-gore skirt's outer front gore hangs at the side, its front at the front). A side
    read from a placement or inferred from the seams is no evidence (a four-gore skirt's
    unnamed side gores are told front or back in turn, while a file's own placement may
    hang them at the sides); panels whose centroid lies within 2 cm of the axis (one
    wrapped all round) are left out too."""
    roles = panel_roles(pattern)
    named = {}
    for i, name in enumerate(mesh.panel_names):
        role = roles[name]
        if role.part in ("torso", "leg_left", "leg_right") and role.side in ("front", "back") \
                and role.side_named:
            tris = mesh.triangles[mesh.triangle_panel == i]
            area = triangle_areas(positions, tris)
            if area.sum() > 0:
                centroid = (positions[tris].mean(axis=1) * area[:, None]).sum(axis=0)
                named[name] = (role.part, role.side, area.sum(), centroid[[0, 2]] / area.sum())
    axes = {"torso": np.asarray(body.landmarks["torso_axis"],
                                dtype=np.float64)[:, [0, 2]].mean(axis=0)}
    for leg in ("leg_left", "leg_right"):
        sides = [[c for part, side, _, c in named.values() if part == leg and side == want]
                 for want in ("front", "back")]
        if all(sides):
            axes[leg] = (np.mean(sides[0], axis=0) + np.mean(sides[1], axis=0)) / 2
    named = {k: v for k, v in named.items() if v[0] in axes}
    group = {name: name for name in named}

    def root(name):
        while group[name] != name:
            name = group[name]
        return name

    for seam in pattern.seams:
        a, b = seam.a.panel, seam.b.panel
        if a in named and b in named and named[a][:2] == named[b][:2]:
            group[root(a)] = root(b)
    out = {}
    for top in dict.fromkeys(root(name) for name in named):  # in the panels' order
        members = [name for name in named if root(name) == top]
        area = sum(named[m][2] for m in members)
        d = sum(named[m][3] * named[m][2] for m in members) / area - axes[named[top][0]]
        n = float(np.hypot(*d))
        if n < 0.02:
            continue
        want = 1.0 if named[top][1] == "front" else -1.0
        out[", ".join(members)] = float(np.degrees(np.arccos(np.clip(want * d[1] / n,
                                                                      -1.0, 1.0))))
    return out


def area_ratio(mesh: GarmentMesh, positions) -> float:
    """3D area of ``positions`` (n, 3) [m] over the flat area of ``mesh`` [-] (0 for a mesh
    without area): about 1 for a drape, near 0 for a state collapsed to a point or a line."""
    flat = float(triangle_areas(mesh.vertices, mesh.triangles).sum())
    return float(triangle_areas(positions, mesh.triangles).sum()) / flat if flat > 0 else 0.0


def on_body_checks(pattern: Pattern, mesh: GarmentMesh, body, positions, *,
                   settings: OnBodySettings = ON_BODY, spacing: float = 0.005) -> OnBodyChecks:
    """Check that ``positions`` (n, 3) [m], a 3D state of ``mesh`` (made from ``pattern``),
    rests on ``body`` (a :class:`patternfit.body.Body`) where the pattern says.

    Fails, each with its reason in words, when the state has collapsed (3D area below
    ``min_area_ratio`` of the flat area), a vertex is below the feet or far from the body
    surface (the body's distance field with grid step ``spacing`` [m]) by more than both
    ``far`` and the cloth that ties it to the anchor line (:func:`anchor_reach`), or the
    anchor line (:func:`anchor_line`) ends more than ``anchor_tolerance`` from the height of
    the body's anchor landmark (:attr:`Pattern.anchor`: waist or neck base), the edges
    named for the anchor hang in the garment's lower half (upside down), or a torso panel
    hangs far round the body from the side it faces (:func:`side_angles`). See
    :class:`OnBodySettings` for the thresholds.
    """
    s = settings
    x = np.asanyarray(positions, dtype=np.float64)
    if x.shape != (mesh.n_vertices, 3):
        raise ValueError(f"positions: expected ({mesh.n_vertices}, 3), got {x.shape}")
    anchor = pattern.anchor
    landmark = float(body.measurements[ANCHOR_HEIGHT[anchor]])
    if not np.isfinite(x).all():
        return OnBodyChecks(0, None, 0, None, anchor, None, landmark * 1e3, None, None,
                            ("positions are not finite",))
    reasons = []
    ratio = area_ratio(mesh, x)
    if ratio < s.min_area_ratio:
        reasons.append(f"garment collapsed: its 3D area is {ratio * 100:.0f}% of the flat "
                       f"pattern's (limit {s.min_area_ratio * 100:.0f}%)")
    lowest = float(x[:, 1].min())
    below = int((x[:, 1] < -s.below_feet).sum())
    if below:
        reasons.append(f"{below} vertices below the feet (lowest at y = {_length(lowest)}, "
                       f"limit {_length(-s.below_feet)})")
    d, _ = body.distance_field(spacing).query(x)
    farthest = float(d.max())
    off = d > s.far
    if off.any():  # the cloth's reach (a graph search) only where the distance alone fails
        off &= d > anchor_reach(pattern, mesh, band=s.top_band)
    far = int(off.sum())
    if far:
        reasons.append(f"{far} vertices far from the body (farthest {_length(farthest)} from "
                       f"its surface, limit {_length(s.far)} or the cloth's length from "
                       f"the garment's top)")
    line = anchor_line(pattern, mesh, band=s.top_band)
    height = float(x[line, 1].mean()) if len(line) else None
    offset = None if height is None else height - landmark
    crotch = body.measurements.get("crotch_height")
    fell = bool(height is not None and crotch is not None and height < crotch)
    if offset is not None and abs(offset) > s.anchor_tolerance:
        where = "below" if offset < 0 else "above"
        what = "waist" if anchor == "waist" else "neck base"
        reasons.append(f"garment top {_length(abs(offset))} {where} the {what} it hangs from "
                       f"(limit {_length(s.anchor_tolerance)})"
                       + (": below the crotch, it fell past the hips" if fell else ""))
    # a garment failed already lies anywhere (a panel crumpled on the floor, a skirt moved
    # 3 m aside): which way up or round it hangs then says nothing of its placement
    off_body = bool(reasons)
    # the anchor line is the garment's top in the frames placement turned upright by the
    # grain lines: a grain arrow drawn downwards hangs the garment upside down, its hem as
    # its "top" at the waist, and the line check holds; the edges named for the anchor then
    # hang at the bottom (a skirt's waist edge round the thighs, a dress's neckline at the
    # knees)
    named = named_anchor_edges(pattern, mesh)
    level = None
    if named:
        ids = np.unique(np.concatenate([mesh.edge_vertices(p, e)[0] for p, e in named]))
        span = float(np.ptp(x[:, 1]))
        level = float((x[ids, 1].mean() - lowest) / span) if span > 0 else 1.0
        if level < s.named_anchor_level and not off_body:
            names = ", ".join(f"{p}/{e}" for p, e in named)
            reasons.append(f"upside down: the edges named for the {anchor} ({names}) hang "
                           f"at {level * 100:.0f}% of the garment's height from its hem, "
                           f"{_length(float(x[ids, 1].mean()))} high (is a grain line drawn "
                           "pointing down?)")
    # nor does it see a garment turned round the body (an explicit placement turned a
    # quarter round hung a dress's front at the side, its neckline a notch on the chest)
    angles = side_angles(pattern, mesh, body, x)
    twisted = {k: a for k, a in angles.items() if a > s.side_angle}
    if twisted and not off_body:
        reasons.append("turned round the body: " + ", ".join(
            f"panel{'s' if ', ' in k else ''} '{k}' hang{'' if ', ' in k else 's'} {a:.0f}° "
            "from the side its name says"
            for k, a in twisted.items()) + f" (limit {s.side_angle:g}°)")
    round_offset = None
    if anchor == "waist":
        # the anchor line is the panels' tops: a bib or flap above a skirt's waist held it
        # at the waist while the skirt had slid to the seat ("fits", every front end)
        at = round_the_body_from(mesh, body, x, gap=s.round_gap)
        round_offset = None if at is None else at - landmark
        flap = height is not None and at is not None and height - at > s.flap
        if not off_body and (round_offset is None
                             or (round_offset < -s.anchor_tolerance and flap)):
            reasons.append(
                "does not go round the body at the waist it hangs from: its cloth "
                + ("goes round the body nowhere" if round_offset is None else
                   f"goes round it only from {_length(-round_offset)} below the waist")
                + f" (limit {_length(s.anchor_tolerance)}; what stands above is a flap, "
                "not a waist)")
    if anchor == "waist" and garment_anchor(pattern) == "neck":
        # followed as stated (placement warns), but no garment with a sleeve or shoulders
        # hangs from the waist: a dress so stated was worn as a skirt, its bodice round the
        # hips, and passed in every front end. The other way round (no shoulders, stated
        # as hung from the neck) may be a halter and is judged as it drapes.
        reasons.append("hung from the waist, as meta.anchor says, though its panels read as "
                       "hung from the neck (a sleeve, collar, hood or shoulder seams): not "
                       "where the garment is worn; check meta.anchor")
    mm = (lambda v: None if v is None else v * 1e3)
    return OnBodyChecks(below, lowest * 1e3, far, farthest * 1e3, anchor, mm(height),
                        landmark * 1e3, mm(offset), ratio, tuple(reasons), level,
                        max(angles.values()) if angles else None, fell, mm(round_offset))


def on_the_floor(onbody: OnBodyChecks, settings: OnBodySettings = ON_BODY) -> bool:
    """Whether a state that passed its on-body checks rests on the floor (its lowest point
    within ``floor_touch`` of y = 0), so that :func:`floor_checked` is to look at what
    carries it."""
    return bool(onbody.passed and onbody.lowest_mm is not None
                and onbody.lowest_mm < settings.floor_touch * 1e3)


def floor_checked(onbody: OnBodyChecks, offset: float, drop: float, iterations: int,
                  held: bool, settings: OnBodySettings = ON_BODY) -> OnBodyChecks:
    """``onbody`` with what its garment did once the floor it rests on was taken away
    (:func:`patternfit.sim.drape.without_floor`): its anchor line ``offset`` [m] from the
    anchor landmark where that solve ended, having dropped by ``drop`` [m] in
    ``iterations``, ``held`` when it came to rest or stopped moving. A garment hung from the
    waist or neck must stay there without the floor: one whose anchor line then ends more
    than ``anchor_tolerance`` from the landmark stood on the floor and fails."""
    reasons = list(onbody.reasons)
    if abs(offset) > settings.anchor_tolerance:
        what = "waist" if onbody.anchor == "waist" else "neck base"
        where = "below" if offset < 0 else "above"
        reasons.append(
            f"stands on the floor: without it the garment slides to {_length(abs(offset))} "
            f"{where} the {what} it hangs from (limit {_length(settings.anchor_tolerance)}; "
            f"{_length(drop)} down in {iterations} iterations"
            + ("" if held else ", still sliding") + ")")
    return replace(onbody, reasons=tuple(reasons), without_floor_offset_mm=offset * 1e3,
                   without_floor_drop_mm=drop * 1e3, without_floor_iterations=int(iterations),
                   without_floor_held=bool(held))


def round_the_body_from(mesh: GarmentMesh, body, positions, *, gap: float = 60.0,
                        step: float = 0.01) -> float | None:
    """The highest height [m] at which the 3D state ``positions`` (n, 3) [m] of ``mesh``
    goes round ``body``: where the points at which its cloth edges cross that level leave
    no gap wider than ``gap`` [degrees] round the body's torso axis at that height (the
    line from the hip centre to the neck base). Looked at every ``step`` [m] down from the
    garment's top to its lowest point; None when it goes round nowhere."""
    x = np.asarray(positions, dtype=np.float64)
    e = unique_edges(mesh.triangles)
    hip, neck = (np.asarray(p, dtype=np.float64) for p in body.landmarks["torso_axis"])
    y0, y1 = x[e[:, 0], 1], x[e[:, 1], 1]
    for h in np.arange(x[:, 1].max() - step / 2, x[:, 1].min(), -step):
        cut = (y0 - h) * (y1 - h) < 0
        if cut.sum() < 3:
            continue
        t = ((h - y0[cut]) / (y1[cut] - y0[cut]))[:, None]
        p = x[e[cut, 0]] * (1 - t) + x[e[cut, 1]] * t
        centre = hip + (neck - hip) * (h - hip[1]) / (neck[1] - hip[1])
        a = np.sort(np.degrees(np.arctan2(p[:, 2] - centre[2], p[:, 0] - centre[0])))
        widest = max(float(np.diff(a).max(initial=0.0)), 360.0 - float(a[-1] - a[0]))
        if widest <= gap:
            return float(h)
    return None


#: why a saved state known not to be at rest is no fit
NOT_AT_REST = ("the drape that saved this state had not come to rest (no force balance): "
               "its shape is no fit")
#: a saved state whose contact state is not known (no ``contact.npz``, or positions moved
#: since) is no rest when the 99th percentile of its rebuilt residual
#: (:func:`patternfit.sim.drape.saved_balance`) is above this many times a vertex's weight
#: [-]: drapes at rest read 0.01-0.13 (1.2-1.5K skirts, trousers, shirt, coat and dress
#: in four fabrics, the 22K coat), the same moved 1 cm up, down, aside or forward 2.8-9,300
REBUILT_P99 = 1.0
#: ... or when one vertex is off by more than this many times its weight [-]: one vertex
#: pulled 2-5 cm off a rest (1K-3K skirt, shirt, trousers), under 1 % of the vertices,
#: read 20,000-23,000 (its p99 0.03-0.05); 33 of 35 rests' largest 0.03-3.6, the others'
#: 734 (the 1.5K shirt, one contact rebuilt otherwise) and 293 (the 22K coat). Pulled 1-2 cm, one
#: vertex may read 1,000-5,000 and pass: the check is for states off rest as a whole
REBUILT_MAX = 5000.0


def _saved_rest(at_rest: bool | None, residual, unknown: str | None) -> dict:
    """The report keys of a saved state's rest: ``equilibrium``, the residual its drape
    ended at (``residual_rms`` / ``residual_p99``, None when not known: given only where
    its contact state is that of these positions) and why the rest is not known
    (``equilibrium_unknown``)."""
    rms, p99 = (None, None) if residual is None else residual
    return {"equilibrium": at_rest, "residual_rms": rms, "residual_p99": p99,
            "equilibrium_unknown": unknown if at_rest is None else None}


def unchecked_state(at_rest: bool | None, *, residual=None, unknown: str | None = None,
                    failed: list[str] | None = None) -> dict:
    """The checks of a saved 3D state read back without a body: nothing says where it rests,
    so ``passed`` is None ("not checked"), False when its drape saved it before it came to
    rest (``at_rest`` False; None: not known, ``unknown`` says why) or said it failed its
    checks on the body it was draped on (``failed``, the reasons; a skirt that fell 43.6 cm
    read "not checked", exit 0); ``residual`` (rms, p99) the one its drape ended at, when
    known."""
    reasons = ["not checked: without the body it was draped on nothing says whether it rests "
               "on it"]
    if failed:
        reasons = [f"its drape failed on the body it was draped on: {r}" for r in failed]
    if at_rest is False:
        reasons.insert(0, NOT_AT_REST)
    return {"solver_checked": False, "on_body": None, **_saved_rest(at_rest, residual, unknown),
            "passed": False if at_rest is False or failed else None, "reasons": reasons}


def saved_state_checks(pattern: Pattern, mesh: GarmentMesh, body, positions, *,
                       spacing: float = 0.005, at_rest: bool | None = None,
                       balance: Callable[[], tuple[float, float, float]] | None = None,
                       residual: tuple[float, float] | None = None,
                       unknown: str | None = None,
                       crossings: Callable[[], dict[str, int]] | None = None,
                       assumed_fabric: str | None = None,
                       floor: Callable[[OnBodyChecks], OnBodyChecks] | None = None) -> dict:
    """The checks of a 3D state read back without the solver that made it (``patternfit
    fit`` of a saved garment folder), as a report's ``checks``: the on-body checks
    (:func:`on_body_checks`), the vertices inside the body (deeper than
    ``constants.tol.penetration``), the seams' widest gap and, when ``crossings`` is given,
    what it counts (:func:`patternfit.sim.drape.saved_crossings`: cloth edges and triangles
    through the body, crossed triangle pairs), with ``passed`` and ``reasons`` in words.
    ``solver_checked`` is False: the force balance needs the drape's solver and its contact
    state, and is not re-run.

    positions : (n, 3) float, the state of ``mesh`` [m]; ``body`` a
    :class:`patternfit.body.Body`; ``spacing`` the distance field's grid step [m];
    ``at_rest`` what the drape that saved the state said of it (``contact.npz``; None: not
    known, ``unknown`` says why), ``residual`` (rms, p99) the residual it ended at: False
    fails the checks. Where it is not known and nothing else failed,
    ``balance`` (when given) is called for the state's residual rebuilt without its contact
    state, (rms, p99, largest) (:func:`patternfit.sim.drape.saved_balance`; reported as
    ``rebuilt_residual_rms`` / ``_p99`` / ``_max``): a p99 above :data:`REBUILT_P99` or a
    largest above :data:`REBUILT_MAX` is no rest (``equilibrium`` False), else it is still
    not known; ``assumed_fabric``: the name of the fabric the balance was rebuilt in when
    it is a default, not the drape's (said in that reason: a knit's true rest judged in
    the default shirting read "not at rest" without a word of the fabric). ``floor``, when
    given, is called with the on-body checks of a state that passed them resting on the
    floor (:func:`on_the_floor`) for those checks with what the garment does without the
    floor (:func:`patternfit.sim.drape.without_floor`)."""
    onbody = on_body_checks(pattern, mesh, body, positions, spacing=spacing)
    if floor is not None and on_the_floor(onbody):
        onbody = floor(onbody)
    x = np.asarray(positions, dtype=np.float64)
    reasons = list(onbody.reasons)
    inside, deepest, gap = 0, 0.0, 0.0
    if np.isfinite(x).all():
        d, _ = body.distance_field(spacing).query(x)
        inside = int((d < -tol.penetration).sum())
        deepest = float(max(0.0, -d.min()) * 1e3)
        gap = seam_gap_mm(mesh.seam_pairs, x)
    reasons += [r for r in (inside_reason(inside, deepest), seam_gap_reason(gap)) if r]
    through = crossings() if crossings is not None and np.isfinite(x).all() else {}
    reasons += crossing_reasons(**through) if through else []
    if at_rest is False:
        reasons.append(NOT_AT_REST)
    rms = p99 = top = None
    if at_rest is None and balance is not None and not reasons:
        rms, p99, top = balance()
        if p99 > REBUILT_P99 or top > REBUILT_MAX:
            at_rest = False
            reasons.append(f"not at rest: 1% of its vertices carry more than {p99:.3g} times "
                           f"their weight unbalanced, one {top:.3g} times (limits "
                           f"{REBUILT_P99:g} and {REBUILT_MAX:g}), whatever the body pushes "
                           f"and friction holds ({unknown or 'its contact state not known'}"
                           + (f"; judged in {assumed_fabric}, the default fabric: give the "
                              "drape's own" if assumed_fabric else "") + ")")
    return {**onbody.to_dict(), "inside_vertices": inside, "max_depth_mm": deepest,
            "seam_gap_max_mm": gap, **through, "solver_checked": False,
            **_saved_rest(at_rest, residual, unknown), "rebuilt_residual_rms": rms,
            "rebuilt_residual_p99": p99, "rebuilt_residual_max": top, "passed": not reasons,
            "reasons": reasons}


def _length(metres: float) -> str:
    """A length in words: cm below a metre, else m."""
    return f"{metres * 100:.1f} cm" if abs(metres) < 1.0 else f"{metres:.2f} m"
