"""Built-in parametric patterns, drafted from body measurements (metres).

The paper's three garments — a coat with kimono sleeves in two panels (front, back), a skirt in
two panels, trousers in four — and a one-piece dress (front, back). Every panel is drafted
right side up as seen from outside the body; seams pair edges of equal length (the front and
back of a side seam are drafted congruent), so every garment can be sewn as it is.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Callable

import numpy as np

from .edges import Edge
from .model import Loop, Panel, Pattern, Placement, Seam, SeamSide
from .sizes import SIZE_NAMES, Measurements, size_chart
from .validate import check_pattern, measured_ease

_MIRROR = np.diag([-1.0, 1.0])


def _swap_side(name: str) -> str:
    if name.endswith("_l"):
        return name[:-2] + "_r"
    return name


def _mirror_loop(loop: Loop, rename: Callable[[str], str]) -> Loop:
    """Mirror a loop in x and reverse it, so that it stays counter-clockwise."""
    edges = [replace(e.transformed(_MIRROR).reversed(), name=rename(e.name))
             for e in reversed(loop.edges)]
    return Loop(loop.name, tuple(edges))


def _symmetric_loop(half: list[Edge], middle_top: Edge, middle_bottom: Edge | None) -> Loop:
    """Outline of a front panel symmetric about x = 0 from its half at x > 0.

    Seen from the front, the panel's +x is the body's left: ``half``'s edges are named
    ``*_l`` and their mirror images ``*_r``. ``half`` runs counter-clockwise from the bottom
    centre's right end to the top centre's right end; ``middle_top`` crosses x = 0 at the top
    (right to left), ``middle_bottom`` at the bottom (left to right).
    """
    left = _mirror_loop(Loop("x", tuple(half)), _swap_side).edges
    edges = ([middle_bottom] if middle_bottom else []) + half + [middle_top] + list(left)
    return Loop("outline", tuple(edges))


def _mirror_panel(panel: Panel, name: str, placement: Placement) -> Panel:
    """The panel mirrored in x (a back from a front-drafted panel): seen from behind, its
    edges stay on the same side of the body, so they keep their names."""
    return Panel(name, _mirror_loop(panel.outline, lambda s: s),
                 tuple(_mirror_loop(lp, lambda s: s) for lp in panel.inner),
                 panel.grainline, placement)


def _seams(a: str, b: str, edges: list[str]) -> tuple[Seam, ...]:
    """Seams joining the same-named edges of a front ``a`` and the back ``b`` made from it by
    :func:`_mirror_panel`: the two run opposite ways, as for any two panels right side up."""
    return tuple(Seam(e, SeamSide(a, e), SeamSide(b, e), reverse=True) for e in edges)


def _neckline(nw: float, top: float, depth: float) -> Edge:
    """Round neckline from the right neck point to the left one, ``depth`` [m] deep."""
    return Edge.cubic("neckline", (nw, top), (0.6 * nw, top - depth / 0.75),
                      (-0.6 * nw, top - depth / 0.75), (-nw, top))


# -- coat ----------------------------------------------------------------------------------
def coat(m: Measurements, *, ease: float = 0.12, sleeve_angle: float = 42.0) -> Pattern:
    """A hip-length coat with kimono sleeves, in two panels (front, back).

    Parameters
    ----------
    m : Measurements
        Body measurements [m].
    ease : float
        Girth added at the chest and hip [m].
    sleeve_angle : float
        Angle of the sleeve from the vertical [degrees] (the body's A-pose).
    """
    a = math.radians(sleeve_angle)
    d = np.array([math.sin(a), -math.cos(a)])           # down the arm
    n = np.array([-math.cos(a), -math.sin(a)])          # across the arm, under it
    length = m.back_length + 0.32
    wc = (m.bust + ease) / 4
    wh = max((m.hip + ease) / 4, wc)
    nw = m.neck / 6 + 0.01
    tip = np.array([m.shoulder / 2, length - 0.045])
    cuff_top = tip + (m.arm_length + 0.02) * d
    cuff_bottom = cuff_top + (m.wrist + 0.20) / 2 * n
    pit = np.array([wc, length - (m.bust / 8 + 0.15)])

    def panel(name: str, neck_depth: float, side: str) -> Panel:
        half = [Edge.line("side_l", (wh, 0.0), pit),
                Edge.line("underarm_l", pit, cuff_bottom),
                Edge.line("cuff_l", cuff_bottom, cuff_top),
                Edge.line("overarm_l", cuff_top, tip),
                Edge.line("shoulder_l", tip, (nw, length))]
        loop = _symmetric_loop(half, _neckline(nw, length, neck_depth),
                               Edge.line("hem", (-wh, 0.0), (wh, 0.0)))
        return Panel(name, loop, placement=Placement("torso", side))

    front = panel("front", m.neck / 6 + 0.03, "front")
    back = _mirror_panel(panel("back", 0.02, "back"), "back", Placement("torso", "back"))
    edges = [f"{e}_{s}" for s in "rl" for e in ("side", "underarm", "overarm", "shoulder")]
    return Pattern("coat", (front, back), _seams("front", "back", edges))


# -- skirt ---------------------------------------------------------------------------------
def skirt(m: Measurements, *, ease: float = 0.04, length: float = 0.60,
          flare: float = 0.06) -> Pattern:
    """A flared skirt from the waist, in two panels (front, back).

    ``length`` is the centre length [m]; ``flare`` widens each side at the hem [m].
    """
    ww = (m.waist + ease / 2) / 4
    hw = (m.hip + ease) / 4
    hd = 0.20
    hem_w = hw + flare

    def panel(name: str, dip: float, side: str) -> Panel:
        hip = (hw, length - hd)
        half = [Edge.line("side_l", (hem_w, 0.0), hip),
                Edge.cubic("hip_l", hip, (hw, length - 0.45 * hd),
                           (ww + 0.3 * (hw - ww), length - 0.08 * hd), (ww, length))]
        waist = Edge.quadratic("waist", (ww, length), (0.0, length - dip), (-ww, length))
        hem = Edge.quadratic("hem", (-hem_w, 0.0), (0.0, -0.02), (hem_w, 0.0))
        return Panel(name, _symmetric_loop(half, waist, hem), placement=Placement("torso", side))

    front = panel("front", 0.015, "front")
    back = _mirror_panel(panel("back", 0.025, "back"), "back", Placement("torso", "back"))
    edges = [f"{e}_{s}" for s in "rl" for e in ("side", "hip")]
    return Pattern("skirt", (front, back), _seams("front", "back", edges))


# -- trousers ------------------------------------------------------------------------------
def _leg(m: Measurements, *, quarter: float, extension: float, hem_outer: float,
         side_in: float, inseam_length: float | None, waist_rise: float,
         name: str, hem: float = 0.0) -> tuple[Panel, float]:
    """Right leg panel drafted as seen from the front (outer side at x < 0).

    ``side_in`` is the waist's inset from the side line [m], the same on front and back so
    that their hip seams match. Returns the panel and its inseam length [m]; with
    ``inseam_length`` given, the hem's inner corner is placed so that the inseam has exactly
    that length. The hem lies ``hem`` [m] above the floor (y = 0).
    """
    top = m.inseam + m.rise
    hd = 0.20
    wq = (m.waist + 0.02) / 4
    x_side, x_cf = -0.5 * quarter, 0.5 * quarter
    crotch = np.array([x_cf + extension, m.inseam])
    h_out = np.array([x_side + hem_outer, hem])
    if inseam_length is None:
        h_in = np.array([h_out[0] + 0.20, hem])
    else:
        h_in = np.array([crotch[0] - math.sqrt(inseam_length**2 - (m.inseam - hem)**2), hem])
    w_side = np.array([x_side + side_in, top])
    w_centre = np.array([x_side + wq + side_in, top + waist_rise])
    hip = np.array([x_side, top - hd])
    edges = (
        Edge.line("hem", h_out, h_in),
        Edge.line("inseam", h_in, crotch),
        Edge.cubic("crotch", crotch, (x_cf + 0.15 * extension, m.inseam),
                   (x_cf, m.inseam + 0.55 * m.rise), w_centre),
        Edge.line("waist", w_centre, w_side),
        Edge.cubic("hip", w_side, (w_side[0] - 0.6 * (w_side[0] - x_side), top - 0.06),
                   (x_side, top - 0.6 * hd), hip),
        Edge.line("outseam", hip, h_out),
    )
    inseam = float(np.linalg.norm(crotch - h_in))
    return Panel(name, Loop("outline", edges)), inseam


def trousers(m: Measurements, *, ease: float = 0.04, hem: float = 0.04) -> Pattern:
    """Full-length trousers in four panels: front and back of each leg; the hem ``hem`` [m]
    above the floor when the waist is at the body's waist (clear of the feet)."""
    q = (m.hip + ease) / 4
    side_in = 0.6 * (q - (m.waist + 0.02) / 4)
    front_r, inseam = _leg(m, quarter=q - 0.02, extension=m.hip / 20, hem_outer=0.03,
                           side_in=side_in, inseam_length=None, waist_rise=0.0,
                           name="front_r", hem=hem)
    back_r_drafted, _ = _leg(m, quarter=q + 0.02, extension=m.hip / 10, hem_outer=0.03,
                             side_in=side_in, inseam_length=inseam, waist_rise=0.03,
                             name="back_r", hem=hem)
    front_r = replace(front_r, placement=Placement("leg_right", "front"))
    back_r = Panel("back_r", _mirror_loop(back_r_drafted.outline, lambda s: s),
                   placement=Placement("leg_right", "back"))
    front_l = Panel("front_l", _mirror_loop(front_r.outline, lambda s: s),
                    placement=Placement("leg_left", "front"))
    back_l = Panel("back_l", _mirror_loop(back_r.outline, lambda s: s),
                   placement=Placement("leg_left", "back"))
    seams = []
    for s in "rl":
        for e in ("hip", "outseam", "inseam"):
            seams.append(Seam(f"{e}_{s}", SeamSide(f"front_{s}", e), SeamSide(f"back_{s}", e)))
    seams.append(Seam("centre_front", SeamSide("front_r", "crotch"), SeamSide("front_l", "crotch")))
    seams.append(Seam("centre_back", SeamSide("back_r", "crotch"), SeamSide("back_l", "crotch")))
    return Pattern("trousers", (front_r, front_l, back_r, back_l), tuple(seams))


# -- dress ---------------------------------------------------------------------------------
def dress(m: Measurements, *, ease: float = 0.06, length: float | None = None) -> Pattern:
    """A sleeveless one-piece dress (bodice and skirt cut in one), front and back panels.

    ``length`` is from the neck point to the hem [m] (default: to the knee).
    """
    total = length or (m.back_length + 0.58)
    bw = (m.bust + ease) / 4
    ww = (m.waist + ease) / 4
    hw = (m.hip + ease) / 4
    hem_w = hw + 0.05
    y_waist = total - m.back_length
    y_hip = y_waist - 0.20
    y_bust = total - (m.bust / 8 + 0.09)
    nw = m.neck / 6 + 0.015
    tip = np.array([m.shoulder / 2 - 0.01, total - 0.045])

    def panel(name: str, neck_depth: float, side: str) -> Panel:
        under = np.array([bw, y_bust])
        half = [Edge.line("skirt_side_l", (hem_w, 0.0), (hw, y_hip)),
                Edge.cubic("bodice_side_l", (hw, y_hip), (ww - 0.01, y_waist - 0.08),
                           (ww - 0.01, y_waist + 0.06), under),
                Edge.cubic("armhole_l", under, (bw - 0.05, y_bust + 0.01),
                           (tip[0] - 0.03, tip[1] - 0.09), tip),
                Edge.line("shoulder_l", tip, (nw, total))]
        loop = _symmetric_loop(half, _neckline(nw, total, neck_depth),
                               Edge.quadratic("hem", (-hem_w, 0.0), (0.0, -0.02), (hem_w, 0.0)))
        return Panel(name, loop, placement=Placement("torso", side))

    front = panel("front", m.neck / 6 + 0.04, "front")
    back = _mirror_panel(panel("back", 0.025, "back"), "back", Placement("torso", "back"))
    edges = [f"{e}_{s}" for s in "rl" for e in ("skirt_side", "bodice_side", "shoulder")]
    return Pattern("dress", (front, back), _seams("front", "back", edges))


# -- shirt with set-in sleeves -------------------------------------------------------------
def _fit_length(make: Callable[[float], Edge], target: float, lo: float, hi: float) -> Edge:
    """The edge ``make(w)`` whose length is ``target`` [m], ``w`` found by bisection in
    [lo, hi] (the length grows with ``w``)."""
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if make(mid).length < target else (lo, mid)
    return make(0.5 * (lo + hi))


def _sleeve(*, front: float, back: float, ease: float, cap_height: float, length: float,
            cuff: float, full_length: float) -> Panel:
    """A one-piece set-in sleeve for the left arm, drafted as seen from outside (its centre
    line on the top of the arm, +x towards the back): its cap's back half ``cap_back`` is
    ``(1 + ease)`` times the back armhole ``back`` [m] long and its front half ``cap_front``
    as much longer than the front armhole ``front`` [m]; the front cap is the more scooped,
    as the front armhole is. The sleeve narrows from its width under the cap to ``cuff`` [m]
    at ``full_length`` [m]; a shorter sleeve is that one cut off (a short sleeve's hem
    stays as wide as the upper arm). The underarm edges have equal lengths (the hem is
    shifted by the difference of the cap's halves)."""
    y0 = length - cap_height

    def half(w: float, sign: float, full: float) -> Edge:  # from the underarm up to the top
        return Edge.cubic("cap", (sign * w, y0), (sign * full * w, y0 + 0.12 * cap_height),
                          (sign * 0.45 * w, length), (0.0, length))

    cap_b = _fit_length(lambda w: half(w, 1.0, 0.68), (1 + ease) * back, 0.02, 0.5)
    cap_f = _fit_length(lambda w: half(w, -1.0, 0.58), (1 + ease) * front, 0.02, 0.5)
    wb, wf = float(cap_b.start[0]), -float(cap_f.start[0])
    hem = wb + wf + (cuff - wb - wf) * min(1.0, y0 / max(full_length - cap_height, 1e-9))
    cb, cf = hem / 2 + (wb - wf) / 2, hem / 2 - (wb - wf) / 2
    edges = (Edge.line("hem", (-cf, 0.0), (cb, 0.0)),
             Edge.line("underarm_b", (cb, 0.0), (wb, y0)),
             replace(cap_b, name="cap_back"),
             replace(cap_f.reversed(), name="cap_front"),
             Edge.line("underarm_f", (-wf, y0), (-cf, 0.0)))
    return Panel("sleeve_l", Loop("outline", edges), placement=Placement("arm_left", "outer"))


def shirt(m: Measurements, *, ease: float = 0.10, length: float | None = None,
          sleeve_length: float | None = None, cap_ease: float = 0.03,
          cap_height: float = 0.11) -> Pattern:
    """A hip-length shirt with long set-in sleeves: front, back and two one-piece sleeves.

    Parameters
    ----------
    m : Measurements
        Body measurements [m].
    ease : float
        Girth added at the chest and hip [m].
    length : float, optional
        From the neck point to the hem [m] (default: back length + 27 cm).
    sleeve_length : float, optional
        From the top of the cap to the hem [m] (default: arm length + 3 cm, to the wrist;
        a shorter sleeve keeps the long one's width where it is cut).
    cap_ease : float
        How much longer the sleeve cap is than the armhole [m] (2–4 cm in a set-in sleeve),
        shared by the front and back halves in proportion; stated as the cap seams' ``ease``.
    cap_height : float
        From the underarm line of the sleeve to the top of its cap [m].
    """
    total = length or (m.back_length + 0.27)
    bw = (m.bust + ease) / 4
    hw = max((m.hip + ease) / 4, bw)
    nw = m.neck / 6 + 0.01
    tip = np.array([m.shoulder / 2, total - 0.045])
    y_pit = tip[1] - (m.bust / 8 + 0.085)

    def panel(name: str, neck_depth: float, scoop: float, side: str) -> Panel:
        under = np.array([bw, y_pit])
        half = [Edge.line("side_l", (hw, 0.0), under),
                Edge.cubic("armhole_l", under, (bw - scoop, y_pit),
                           (tip[0] - 0.3 * scoop, y_pit + 0.45 * (tip[1] - y_pit)), tip),
                Edge.line("shoulder_l", tip, (nw, total))]
        loop = _symmetric_loop(half, _neckline(nw, total, neck_depth),
                               Edge.line("hem", (-hw, 0.0), (hw, 0.0)))
        return Panel(name, loop, placement=Placement("torso", side))

    front = panel("front", m.neck / 6 + 0.02, 0.06, "front")
    back = _mirror_panel(panel("back", 0.02, 0.03, "back"), "back", Placement("torso", "back"))
    la_f, la_b = front.edge("armhole_l").length, back.edge("armhole_l").length
    left = _sleeve(front=la_f, back=la_b, ease=cap_ease / (la_f + la_b),
                   cap_height=cap_height, length=sleeve_length or (m.arm_length + 0.03),
                   cuff=m.wrist + 0.10, full_length=m.arm_length + 0.03)
    right = _mirror_panel(left, "sleeve_r", Placement("arm_right", "outer"))
    seams = list(_seams("front", "back", [f"{e}_{s}" for s in "rl" for e in ("side", "shoulder")]))
    for s, sleeve in (("l", left), ("r", right)):
        name = f"sleeve_{s}"
        for half, body in (("front", front), ("back", back)):
            la = body.edge(f"armhole_{s}").length
            lc = sleeve.edge(f"cap_{half}").length
            seams.append(Seam(f"cap_{half}_{s}", SeamSide(name, f"cap_{half}"),
                              SeamSide(half, f"armhole_{s}"),
                              ease=measured_ease(lc, la)))
        seams.append(Seam(f"underarm_{s}", SeamSide(name, "underarm_b"),
                          SeamSide(name, "underarm_f")))
    return Pattern("shirt", (front, back, left, right), tuple(seams))


# -- gathered skirt ------------------------------------------------------------------------
def gathered_skirt(m: Measurements, *, ease: float = 0.02, length: float = 0.58,
                   gather: float = 1.6, band: float = 0.04) -> Pattern:
    """A skirt of two straight panels gathered into a waistband (front and back halves).

    ``length`` is the skirt's length below the band [m]; ``gather`` the ratio of the skirt's
    waist to the band's (1.6: 1.6 cm of skirt gathered into each cm of band; at most
    ``1 + limits.seam_ease``), stated as the waist seams' ``ease``; ``band`` the band's
    height [m]. The band's quarter is ``(waist + ease) / 4`` wide.
    """
    bw = (m.waist + ease) / 4
    sw = gather * bw

    def skirt_panel(name: str, side: str) -> Panel:
        loop = _symmetric_loop([Edge.line("side_l", (sw, 0.0), (sw, length))],
                               Edge.line("waist", (sw, length), (-sw, length)),
                               Edge.line("hem", (-sw, 0.0), (sw, 0.0)))
        return Panel(name, loop, placement=Placement("torso", side))

    def band_panel(name: str, side: str) -> Panel:
        top = length + band
        loop = _symmetric_loop([Edge.line("side_l", (bw, length), (bw, top))],
                               Edge.line("top", (bw, top), (-bw, top)),
                               Edge.line("bottom", (-bw, length), (bw, length)))
        return Panel(name, loop, placement=Placement("torso", side))

    front, band_front = skirt_panel("front", "front"), band_panel("band_front", "front")
    back = _mirror_panel(skirt_panel("back", "back"), "back", Placement("torso", "back"))
    band_back = _mirror_panel(band_panel("band_back", "back"), "band_back",
                              Placement("torso", "back"))
    sides = [f"side_{s}" for s in "rl"]
    gathered = measured_ease(2 * sw, 2 * bw)
    seams = (_seams("front", "back", sides)
             + tuple(replace(s, name=f"band_{s.name}")
                     for s in _seams("band_front", "band_back", sides))
             + (Seam("waist_front", SeamSide("front", "waist"), SeamSide("band_front", "bottom"),
                     ease=gathered),
                Seam("waist_back", SeamSide("back", "waist"), SeamSide("band_back", "bottom"),
                     ease=gathered)))
    return Pattern("gathered_skirt", (front, back, band_front, band_back), seams)


#: name -> (drafting function, size chart used by default, description, where it hangs from)
GARMENTS: dict[str, tuple[Callable[..., Pattern], str, str, str]] = {
    "coat": (coat, "male", "hip-length coat, kimono sleeves, 2 panels (front, back)", "neck"),
    "skirt": (skirt, "female", "flared skirt, 2 panels (front, back)", "waist"),
    "trousers": (trousers, "male", "full-length trousers, 4 panels (front/back of each leg)",
                 "waist"),
    "dress": (dress, "female", "sleeveless one-piece dress, 2 panels (front, back)", "neck"),
    "shirt": (shirt, "male", "hip-length shirt, long set-in sleeves with cap ease, 4 panels "
              "(front, back, 2 sleeves)", "neck"),
    "gathered_skirt": (gathered_skirt, "female", "skirt gathered 1.6:1 into a waistband, 4 "
                       "panels (front, back, 2 band halves)", "waist"),
}


def build(name: str, size: str = "M", *, measurements: Measurements | None = None,
          **options) -> Pattern:
    """A built-in garment drafted for ``size`` (S–XL) or for explicit ``measurements``.

    ``options`` go to the drafting function (ease, lengths). The result is validated and
    carries ``meta`` with the garment, size, measurements and ``anchor`` (``"neck"`` or
    ``"waist"``: the height on the body its top is placed at).
    """
    if name not in GARMENTS:
        raise ValueError(f"name: unknown garment {name!r} (built-in: {', '.join(GARMENTS)})")
    fn, gender, _, anchor = GARMENTS[name]
    if measurements is None:
        if size.upper() not in SIZE_NAMES:
            raise ValueError(f"size: expected one of {', '.join(SIZE_NAMES)}, got {size!r}")
        measurements = size_chart(gender, size)
        size = size.upper()
    else:
        size = "custom"
    pattern = fn(measurements, **options)
    pattern = replace(pattern, meta={"garment": name, "size": size, "chart": gender,
                                     "anchor": anchor,
                                     "measurements_m": measurements.as_dict()})
    check_pattern(pattern)
    return pattern
