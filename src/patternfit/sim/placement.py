"""Isometric placement of the panels around the body before sewing (paper Sec. 6.1).

Each panel is rolled onto a cylinder around the body part it dresses (a cylinder is
developable: rolling keeps every length, so ϖ = 1 before sewing): a vertical elliptic one
round the torso, one along each leg's and each arm's slant, or laid in a plane in front of /
behind the body when it is too wide to wrap (kimono sleeves). The part and side come from
the pattern (:mod:`patternfit.pattern.roles`), the panels' upright frames and an imported
placement's plausibility from :mod:`patternfit.sim.panel_frames`. Seams that do not coincide
after placement are closed by the sewing phase of the solver.

World frame: metres, y up, the body facing +z, its left side at +x. A panel is drafted right
side up as seen from outside, so its +u runs towards +x on the front and towards −x on the
back; rolled panels keep their outward normal.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..arguments import array, number
from ..geometry import rotation_between
from ..mesh.garment import GarmentMesh
from ..pattern.model import Pattern
from ..pattern.roles import garment_anchor, panel_roles
from .panel_frames import PlacementWarning, implausible_placements, upright_frames
from .side_rows import Fan, Row, side_rows

#: default axis position (x, z) [m] and radius [m] of each body part, for a body-free placement
PART_AXES = {
    "torso": ((0.0, 0.0), 0.17),
    "leg_left": ((0.10, 0.0), 0.09),
    "leg_right": ((-0.10, 0.0), 0.09),
    "arm_left": ((0.30, 0.0), 0.06),
    "arm_right": ((-0.30, 0.0), 0.06),
}

_SAMPLES = 4096  # points of the arc-length table of an ellipse


class Ellipse:
    """A horizontal ellipse ``(x0 + a sin θ, z0 + b cos θ)`` parametrised by arc length.

    θ = 0 is the front meridian (+z), θ = π/2 the body's left (+x), θ = π the back.
    """

    def __init__(self, a: float, b: float, centre=(0.0, 0.0)):
        if not (a > 0 and b > 0):
            raise ValueError(f"a, b: semi-axes must be positive, got {a}, {b}")
        self.a, self.b = float(a), float(b)
        self.centre = np.asarray(centre, dtype=np.float64)
        theta = np.linspace(0.0, 2 * math.pi, _SAMPLES + 1)
        p = np.stack([self.a * np.sin(theta), self.b * np.cos(theta)], axis=1)
        self._theta = theta
        self._s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])

    @property
    def perimeter(self) -> float:
        """Circumference [m]."""
        return float(self._s[-1])

    def arc_length(self, theta: float) -> float:
        """Arc length from the front meridian to angle ``theta`` [m]."""
        return float(np.interp(theta % (2 * math.pi), self._theta, self._s))

    def point(self, s) -> np.ndarray:
        """Points (k, 2) as (x, z) [m] at arc lengths ``s`` (k,) [m], wrapping around."""
        th = np.interp(np.mod(s, self.perimeter), self._s, self._theta)
        return self.centre + np.stack([self.a * np.sin(th), self.b * np.cos(th)], axis=1)


class WingedProfile:
    """A front (or back) profile for panels too wide to wrap: an elliptic arc round the body
    that turns back outwards into two straight wings at a distance ``depth`` from the axis
    (``(x, z)`` [m], symmetric in arc length about the meridian). Panels with kimono sleeves
    get their torso round the body and their sleeves in front of / behind the arms.

    Parameters
    ----------
    a, b : float
        Semi-axes of the arc [m] (x and z).
    depth : float
        Distance of the wings from the axis [m], below ``b``.
    centre : (2,) float
        Axis position (x, z) [m].
    side : float
        +1 for the front (wings at +depth), -1 for the back (rotated half a turn).
    bend : float
        Radius of the turn from the arc into the wings [m].
    """

    def __init__(self, a: float, b: float, depth: float, centre=(0.0, 0.0), *, side: float = 1.0,
                 bend: float = 0.05):
        if not (a > 0 and b > depth > 0):
            raise ValueError(f"a, b, depth: need a > 0 and b > depth > 0, got {a}, {b}, {depth}")
        self.centre = np.asarray(centre, dtype=np.float64)
        self.side = float(side)

        def tilt(th):  # angle of the arc's tangent below the +x direction
            return math.atan2(b * math.sin(th), a * math.cos(th))

        lo, hi = 0.0, 0.5 * math.pi
        for _ in range(60):  # the wings' height falls as the arc goes on: bisect
            th = 0.5 * (lo + hi)
            z_end = b * math.cos(th) - bend * (1 - math.cos(tilt(th)))
            lo, hi = (th, hi) if z_end > depth else (lo, th)
        th1, phi = lo, tilt(lo)
        t = np.linspace(0.0, th1, 1500)
        arc = np.stack([a * np.sin(t), b * np.cos(t)], axis=1)
        centre_turn = arc[-1] + bend * np.array([math.sin(phi), math.cos(phi)])
        psi = np.linspace(-phi, 0.0, 300)[1:]
        turn = centre_turn + bend * np.stack([np.sin(psi), -np.cos(psi)], axis=1)
        wing = turn[-1] + np.outer(np.linspace(0.0, 3.0, 301)[1:], [1.0, 0.0])
        pts = np.concatenate([arc, turn, wing])
        self._pts = pts
        self._s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])

    def point(self, s) -> np.ndarray:
        """Points (k, 2) as (x, z) [m] at signed arc lengths ``s`` (k,) [m] from the meridian."""
        s = np.asanyarray(s, dtype=np.float64)
        r = np.abs(s)
        x = np.interp(r, self._s, self._pts[:, 0]) * np.sign(s)
        z = np.interp(r, self._s, self._pts[:, 1])
        return self.centre + self.side * np.stack([x, z], axis=1)


def roll_panel(uv, ellipse, *, s0: float = 0.0, height: float = 0.0) -> np.ndarray:
    """Roll flat points onto the vertical cylinder over a profile, isometrically.

    Parameters
    ----------
    uv : (k, 2) float
        Flat positions [m]; ``u`` runs along the profile (increasing arc length), ``v`` up.
    ellipse : Ellipse or WingedProfile
        The profile: anything with ``point(s) -> (k, 2)`` (x, z) [m] by arc length.
    s0 : float
        Arc length [m] where ``u = 0`` lands.
    height : float
        Added to ``v`` to give y [m].

    Returns
    -------
    (k, 3) float
        Positions [m].
    """
    p = array(uv, "uv", shape=(None, 2))
    xz = ellipse.point(s0 + p[:, 0])
    return np.stack([xz[:, 0], p[:, 1] + height, xz[:, 1]], axis=1)


def _centred(uv: np.ndarray) -> np.ndarray:
    out = uv.copy()
    out[:, 0] -= 0.5 * (uv[:, 0].min() + uv[:, 0].max())
    return out


def place_on_cylinders(pattern: Pattern, mesh: GarmentMesh, *,
                       clearance: float = 0.03) -> np.ndarray:
    """Body-free placement: every panel on a circular cylinder around its part's default axis
    (``PART_AXES``; the part from :func:`~patternfit.pattern.roles.panel_roles`), centred on
    the front or back meridian; the cylinder grows when a panel would wrap more than half
    way round. Returns positions (n, 3) [m]."""
    x = np.zeros((mesh.n_vertices, 3))
    roles = panel_roles(pattern)
    for pi, panel in enumerate(pattern.panels):
        ids = mesh.panel_vertices(pi)
        uv = _centred(mesh.vertices[ids])
        role = roles[panel.name]
        axis, r = PART_AXES.get(role.part, PART_AXES["torso"])
        r = max(r + clearance, np.ptp(uv[:, 0]) / (0.95 * math.pi))
        ring = Ellipse(r, r, axis)
        s0 = 0.0 if role.side != "back" else 0.5 * ring.perimeter
        x[ids] = roll_panel(uv, ring, s0=s0)
    return x


# -- on a body ---------------------------------------------------------------------------------
def _vertical_offset(pattern: Pattern, flat: np.ndarray, mesh: GarmentMesh, roles,
                     body) -> float:
    """Shift [m] that brings the drafted garment to its height on the body: its top 1 cm
    above the neck base when :attr:`Pattern.anchor` is ``"neck"``, else above the waist
    (the rule the on-body check measures the drape against). The top is that of the body
    panels: sleeves, hoods and collars rise above the neck."""
    tops = [flat[mesh.panel_vertices(i), 1].max() for i, p in enumerate(pattern.panels)
            if roles[p.name].kind not in ("sleeve", "cuff", "hood", "collar")]
    top = float(max(tops) if tops else flat[:, 1].max())
    m = body.measurements
    if pattern.anchor == "neck":
        return m["neck_base_height"] + 0.01 - top
    return m["waist_height"] + 0.01 - top


def _torso_extent(body, y0: float, y1: float, centre) -> tuple[float, float, float]:
    """Half-width and front/back depths [m] of the torso (and legs) between heights y0, y1."""
    v = body.vertices
    half = 0.5 * body.measurements.get("shoulder_width", 0.4) + 0.06
    sel = (v[:, 1] >= y0) & (v[:, 1] <= y1) & (np.abs(v[:, 0] - centre[0]) < max(half, 0.22))
    if not sel.any():
        return 0.15, 0.12, 0.12
    d = v[sel][:, [0, 2]] - centre
    return float(np.abs(d[:, 0]).max()), float(d[:, 1].max()), float(-d[:, 1].min())


def _place_torso(side: str, uv, body, centre, dy, clearance, width_limit,
                 arm_gap, row: Row | None = None, *, tube: bool = False) -> np.ndarray:
    """A torso panel: rolled on an ellipse clear of the body, centred on its ``side``
    (front, back, or the body's left / right for a hood's halves), or, one of a ``row``
    of panels sewn side by side, moved across by its shift on the ring the whole row's
    reach either side needs; on a winged profile when too wide to wrap. A ``tube`` (sewn
    to itself along its sides) goes all the way round, its sides meeting behind: held to
    half the ring, a one-piece skirt was rolled over the front alone and its sewing dragged
    both sides 0.93 m round the back (its top rose to the bust, or it fell)."""
    y0, y1 = uv[:, 1].min() + dy, uv[:, 1].max() + dy
    hw, front, back = _torso_extent(body, y0, y1, centre)
    depth = max(front, back)
    ring = Ellipse(hw + clearance, depth + clearance, centre)
    row = None if tube else row
    width = float(np.ptp(uv[:, 0])) if row is None else 2.0 * row.reach
    grow = width / ((1.0 if tube else 0.5) * ring.perimeter * 0.97)
    if row is None:
        uv = _centred(uv)
    else:
        uv = uv + [row.shift, 0.0]
    if tube or grow <= width_limit:
        if grow > 1:
            ring = Ellipse(ring.a * grow, ring.b * grow, centre)
        theta = {"front": 0.0, "left": 0.5 * math.pi, "back": math.pi}.get(side, 1.5 * math.pi)
        return roll_panel(uv, ring, s0=ring.arc_length(theta), height=dy)
    # too wide to wrap (kimono sleeves): torso round the body, sleeves on wings either side
    # of the arms
    facing = 1.0 if side == "front" else -1.0
    wings = WingedProfile(ring.a, ring.b, min(arm_gap, 0.8 * ring.b), centre, side=facing)
    return roll_panel(uv, wings, height=dy)


#: the widest a fan's cone opens: the sine of its half-angle. No value tried is robust:
#: GarmentCodeData's eight-gore rand_04EGGDPALT (a fan of 228 degrees a side) on
#: female_average passed every check at 4K and 5K triangles with 0.8 and slid off the
#: shoulders at 3K, 6K and 8K; with 0.9 it passed at 3K to 5K and slid at 6K and 8K, but a
#: skirt of eight gores 10 to 70 cm (the tests') then started level with the A-posed hands
#: and ended with one through it; with 0.7 it passed at 6K, not 3K; at 0.97 three drapes of
#: four slid
CONE_OPENING = 0.8


def _place_fan(fan: Fan, pi: int, uv, side: str, body, centre, dy, clearance) -> np.ndarray:
    """A panel of a ``fan`` of flared panels rolled onto a round cone about the torso axis,
    apex up. The side's fan fills 0.97 of half the cone, which a fan spreading Φ opens to
    k = Φ / (0.97 π), the sine of its half-angle: isometrically up to
    :data:`CONE_OPENING`, pressed together round it beyond. The cone's top is a circle
    round the torso at the fan's heights, ``clearance`` [m] clear of it (wider when the
    fan's own top is), at the fan's top plus ``dy`` [m]. Returns positions (k, 3) [m] of
    the flat points ``uv`` (k, 2) [m]."""
    r, theta = fan.polar(pi, uv)
    k = fan.spread / (0.97 * math.pi)
    opening = min(k, CONE_OPENING)
    drop = math.sqrt(1.0 - opening ** 2)
    top = fan.top + dy
    hw, front, back = _torso_extent(body, top - (fan.r_bottom - fan.r_top) * drop, top, centre)
    # round: a cone on the torso's ellipse stretched its rulings at the sides by a / b
    radius = max(hw, front, back) + clearance
    ring = Ellipse(radius, radius, centre)
    # through that circle at the top, however narrow the fan's own apex would have it
    grow = (max(radius, opening * fan.r_top) + opening * (r - fan.r_top)) / radius
    arc = r * theta * min(1.0, CONE_OPENING / k)  # from the side's middle, along the cone
    s0 = ring.arc_length(0.0 if side == "front" else math.pi)
    xz = centre + grow[:, None] * (ring.point(s0 + arc / grow) - centre)
    return np.column_stack([xz[:, 0], top - (r - fan.r_top) * drop, xz[:, 1]])


def _leg_radius(d: float, width: float) -> float:
    """Radius of a circle around a leg whose axis is ``d`` [m] from the midline, such that
    the arc from the front midline crossing round the outside to the back crossing holds
    ``width`` [m]."""
    r = max(d * 1.05, width / (2 * math.pi))
    while r * (2 * math.pi - 2 * math.acos(min(d / r, 1.0))) < width:
        r *= 1.02
    return r


#: the widest gap between body and panels a placement takes [m]: wider, a panel is
#: rolled round nothing (a 100 m gap left seams 187 m open)
MAX_CLEARANCE = 0.3


def checked_clearance(clearance) -> float:
    """``clearance`` [m] as a float, refused with a ``ValueError`` naming it unless
    0 <= clearance <= :data:`MAX_CLEARANCE`."""
    return number(clearance, "clearance", low=0.0, high=MAX_CLEARANCE,
                  rule=f"expected a gap between body and panels of 0 to {MAX_CLEARANCE:g} m")


def place_on_body(pattern: Pattern, mesh: GarmentMesh, body, *, clearance: float = 0.03,
                  width_limit: float = 1.6) -> np.ndarray:
    """Place every panel of ``mesh`` around ``body`` (a :class:`patternfit.body.Body`).

    Each panel's body part and side come from :func:`~patternfit.pattern.roles.panel_roles`
    (its stated placement, name, seams and shape). Each panel is first turned upright in its
    flat frame (its grain line, or an explicit placement's up, along the body's height; a
    band's length across it; a sleeve's cap towards the shoulder), and where the panels'
    flat frames do not agree in height (seams joining edges at different heights: another
    tool's frames) they are stacked so that their seams meet
    (:func:`~patternfit.sim.panel_frames.upright_frames`). The top of the body panels goes
    1 cm above the body's neck base or waist (:attr:`Pattern.anchor`).

    Torso panels are rolled onto an elliptic cylinder around the torso axis that clears the
    body by ``clearance`` [m] and holds the front and back panels side by side (enlarged up
    to ``width_limit`` times; wider panels keep their middle round the body and continue
    outwards in front of / behind the arms, :class:`WingedProfile`); a side's panels sewn to
    each other along seams that run up the body lie side by side in seam order, or, flared,
    seam to seam on a cone (:func:`~patternfit.sim.side_rows.side_rows`). Leg panels are
    rolled onto a circular cylinder around their leg, the front panel from the front midline
    and the back one from the back midline round the outside, so that the crotch seams start
    at the midline. Sleeves are rolled round the arm's axis (:func:`_place_arm`).

    Panels with an explicit 3D placement (``Placement.translation`` / ``rotation``, as
    GarmentCode files carry) keep it when it is plausible on this body
    (:func:`implausible_placements`) and the garment hangs from the waist; otherwise the
    whole garment is placed here, with a :class:`PlacementWarning` naming the panels when
    the placement is not around the body. A garment hung from the neck is always placed
    here, without a warning: GarmentCode lays its panels out flat, front and back some 45 cm
    apart, and sewing those across the shoulders and round the arms failed every one of five
    GarmentCode garments on female_average (straps pulled off the shoulders, underarms
    crossed) that drape with every check passed from this placement (docs/interchange.md).
    Returns positions (n, 3) [m], one per flat vertex.
    """
    clearance = checked_clearance(clearance)
    # a neck garment's own placement is never kept, so it is not judged either: the warning
    # came and went with the body (a GarmentCode shirt warned on male_average, not on
    # female_average) and said nothing the user could act on
    bad = implausible_placements(pattern, mesh, body) if pattern.anchor != "neck" else []
    keep = not bad and pattern.anchor != "neck"
    if bad:
        warnings.warn(PlacementWarning(
            f"the imported 3D placement is not around the body ({len(bad)} of "
            f"{len(pattern.panels)} panels: {'; '.join(bad)}): every panel is placed by "
            "patternfit instead"), stacklevel=2)
    roles = panel_roles(pattern)
    read = garment_anchor(pattern, roles)
    if read != pattern.anchor:
        # a tank top stated as hung from the waist was worn as a skirt and passed
        warnings.warn(PlacementWarning(
            f"placed hung from the {pattern.anchor}, as meta.anchor says, though its panels "
            f"read as hung from the {read} ("
            + ("a sleeve, collar, hood or shoulder seams" if read == "neck"
               else "no sleeve, collar, hood or shoulder seams")
            + "): check meta.anchor"), stacklevel=2)
    flat = upright_frames(pattern, mesh, roles)
    lm = body.landmarks
    dy = _vertical_offset(pattern, flat, mesh, roles, body)
    rows = side_rows(pattern, mesh, flat, roles)
    arm_gap = 0.5 * body.measurements.get("bicep", 0.32) / math.pi + clearance + 0.02
    x = np.zeros((mesh.n_vertices, 3))
    torso = np.asarray(lm["torso_axis"])[:, [0, 2]].mean(axis=0)
    legs: dict[str, list[int]] = {}
    arms: dict[str, list[int]] = {}
    for pi, panel in enumerate(pattern.panels):
        role = roles[panel.name]
        ids = mesh.panel_vertices(pi)
        uv = flat[ids]
        if panel.placement.explicit and keep:
            x[ids] = panel.placement.transform(mesh.vertices[ids])  # the file's own placement
        elif role.part.startswith("leg"):
            legs.setdefault(role.part, []).append(pi)
        elif role.part.startswith("arm"):
            arms.setdefault(role.part, []).append(pi)
        elif isinstance(rows.get(pi), Fan):
            x[ids] = _place_fan(rows[pi], pi, uv, role.side, body, torso, dy, clearance)
        else:
            x[ids] = _place_torso(role.side, uv, body, torso, dy, clearance, width_limit,
                                  arm_gap, rows.get(pi), tube=role.tube)
    for part, panels in legs.items():
        side = part.split("_")[1]
        top, bottom = np.asarray(lm[f"leg_axis_{side}"])
        axis = top[[0, 2]]
        # the cylinder follows the leg's slant (legs apart): a rotation, so still isometric
        turn = rotation_between((0.0, -1.0, 0.0), bottom - top)
        pivot = np.array([top[0], top[1], top[2]])
        d = abs(axis[0] - torso[0])
        width = sum(np.ptp(flat[mesh.panel_vertices(p)][:, 0]) for p in panels)
        r = _leg_radius(d, 1.05 * width + 2 * clearance)
        ring = Ellipse(r, r, axis)
        cross = math.asin(min(d / r, 1.0))  # angle where the circle meets the midline
        towards_mid = 1.0 if axis[0] < torso[0] else -1.0  # +x is towards the midline
        for pi in panels:
            ids = mesh.panel_vertices(pi)
            uv = flat[ids].copy()
            front = roles[pattern.panels[pi].name].side != "back"
            theta = (cross if front else math.pi - cross) if towards_mid > 0 \
                else (-cross if front else math.pi + cross)
            # +u runs towards +x on the front and -x on the back
            inner_is_max = (towards_mid > 0) == front
            anchor = uv[:, 0].max() if inner_is_max else uv[:, 0].min()
            gap = (clearance if inner_is_max else -clearance)
            uv[:, 0] -= anchor + gap
            rolled = roll_panel(uv, ring, s0=ring.arc_length(theta), height=dy)
            x[ids] = (rolled - pivot) @ turn.T + pivot
    placed = np.zeros(mesh.n_vertices, dtype=bool)
    for pi, panel in enumerate(pattern.panels):
        if not roles[panel.name].part.startswith("arm"):
            placed[mesh.panel_vertices(pi)] = True
    for part, panels in arms.items():
        sides = [roles[pattern.panels[p].name].side for p in panels]
        _place_arm(flat, mesh, body, part, panels, sides, x, x[placed], torso, clearance)
    # cloth placed below the floor starts on it: started inside the floor, the drape
    # pushed it up through itself (the trousers XL on female_thin at 3K: 934 crossed
    # pairs; from the floor: none at 1K, 6 at 3K; laid out flat on the floor instead,
    # friction held it stretched: 40 at 3K, "too tight" at 1K)
    x[:, 1] = np.maximum(x[:, 1], body.floor + 0.5 * clearance)
    return x + [0.0, _sewing_lift(mesh, x, body, clearance), 0.0]


def _arm_radius(body, top, direction) -> float:
    """Radius [m] of the upper arm: the 95th percentile of the body's distance from the arm
    axis between a quarter and half of the way from the shoulder to the wrist."""
    v = body.vertices - top
    t = v @ direction
    length = float(np.linalg.norm(np.asarray(body.landmarks["arm_axis_left"][1])
                                  - np.asarray(body.landmarks["arm_axis_left"][0])))
    radial = np.linalg.norm(v - np.outer(t, direction), axis=1)
    sel = (t > 0.25 * length) & (t < 0.5 * length) & (radial < 0.12)
    return float(np.percentile(radial[sel], 95)) if sel.sum() > 10 else 0.05


class _Clearance:
    """Whether points clear what is placed already: outside the placed cloth's outline
    round the torso axis (by angle, in height bands) and outside the body."""

    def __init__(self, placed, centre, body, margin: float, *, bins: int = 72,
                 band: float = 0.02):
        self.centre, self.bins, self.band = centre, bins, band
        self.field, self.margin = body.distance_field(0.005), margin
        self.y0 = float(placed[:, 1].min()) if len(placed) else 0.0
        self.radius: dict[tuple[int, int], float] = {}
        for key, r in zip(self._keys(placed), self._radial(placed)):
            self.radius[key] = max(self.radius.get(key, 0.0), float(r))

    def _radial(self, p):
        return np.hypot(p[:, 0] - self.centre[0], p[:, 2] - self.centre[1])

    def _keys(self, p):
        ang = np.arctan2(p[:, 0] - self.centre[0], p[:, 2] - self.centre[1])
        a = np.floor((ang + math.pi) / (2 * math.pi) * self.bins).astype(int) % self.bins
        b = np.floor((p[:, 1] - self.y0) / self.band).astype(int)
        return list(zip(b.tolist(), a.tolist()))

    def clear(self, p) -> bool:
        d, _ = self.field.query(p)
        if d.min() < self.margin:
            return False
        r = self._radial(p)
        for (b, a), ri in zip(self._keys(p), r):
            for db in (-1, 0, 1):
                for da in (-1, 0, 1):
                    if ri < self.radius.get((b + db, (a + da) % self.bins), 0.0) + self.margin:
                        return False
        return True


def _place_arm(flat: np.ndarray, mesh: GarmentMesh, body, part: str, panels: list[int],
               sides: list[str], x: np.ndarray, placed, torso, clearance: float) -> None:
    """Roll the panels of one arm onto a cylinder round the arm's axis (from the shoulder to
    the wrist: the cylinder follows the arm's slant, a rotation, so still isometric), each
    panel's top towards the shoulder: a one-piece sleeve (side ``"outer"``) centred on the
    top of the arm, a two-piece sleeve's halves on its front and back. The sleeve starts at
    the shoulder, or as far down the arm as it takes to clear the cloth already placed and
    the body; the sewing phase pulls it up to its armhole. Writes ``x`` in place."""
    which = part.split("_")[1]
    top, bottom = (np.asarray(p, dtype=np.float64) for p in body.landmarks[f"arm_axis_{which}"])
    direction = (bottom - top) / np.linalg.norm(bottom - top)
    turn = rotation_between((0.0, -1.0, 0.0), direction)
    width = sum(np.ptp(flat[mesh.panel_vertices(p)][:, 0]) for p in panels)
    r = max(_arm_radius(body, top, direction) + clearance, width / (0.97 * 2 * math.pi))
    ring = Ellipse(r, r)
    outer = 0.5 * math.pi if which == "left" else 1.5 * math.pi  # +x of the turned cylinder
    rolled = {}
    for pi, side in zip(panels, sides):
        uv = _centred(flat[mesh.panel_vertices(pi)])
        uv[:, 1] -= uv[:, 1].max()
        theta = {"front": 0.0, "back": math.pi}.get(side, outer)
        rolled[pi] = roll_panel(uv, ring, s0=ring.arc_length(theta)) @ turn.T
    everything = np.concatenate(list(rolled.values()))
    room = _Clearance(placed, torso, body, 0.5 * clearance)
    for t in np.arange(0.0, 0.40, 0.01):
        if room.clear(everything + top + t * direction):
            break
    for pi, p in rolled.items():
        x[mesh.panel_vertices(pi)] = p + top + t * direction


def _sewing_lift(mesh: GarmentMesh, x, body, clearance: float, *, most: float = 0.06) -> float:
    """Upward shift [m] that takes the most seams' straight sewing paths off the body.

    Sewing pulls the two sides of a seam straight towards each other; where the midpoint of
    a pair lies inside the body (a shoulder seam under a "roof" over the shoulder), the
    garment is lifted until the path clears it, if lifting helps at all. Gravity brings it
    back down once sewn.
    """
    if not len(mesh.seam_pairs):
        return 0.0
    mid = 0.5 * (x[mesh.seam_pairs[:, 0]] + x[mesh.seam_pairs[:, 1]])
    field = body.distance_field(0.005)
    best, best_lift = None, 0.0
    for lift in np.arange(0.0, most + 1e-9, 0.01):
        d, _ = field.query(mid + [0.0, lift, 0.0])
        blocked = int(np.sum(d < 0.005))
        if best is None or blocked < best:
            best, best_lift = blocked, float(lift)
        if blocked == 0:
            break
    return best_lift
