"""Every threshold of the fit verdict, in one place, with where each number comes from.

The sources are quoted in ``docs/fit-correction.md`` ("The verdict"); a number without a
published source says so there. Pressures in kPa, ease in cm, stretch as a fraction
(0.05 = 5 % longer than the flat pattern along a yarn).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from ..arguments import number

#: the verdict words, tightest first; a drape that failed its checks reads :data:`FAILED`
VERDICTS = ("too tight", "tight", "fits", "loose", "too loose")
FAILED = "failed"


@dataclass(frozen=True)
class VerdictRules:
    """The thresholds of :func:`patternfit.fit.verdict.judge`.

    pressure_max_kpa : float      a region whose pressure (its ``pressure_percentile``)
                                  exceeds this is too tight [kPa] (Kawabata: 2.0 kPa, the
                                  most for daily wear).
    pressure_comfort_kpa : float  ... exceeds this, tight [kPa] (Kawabata: about 1.3 kPa
                                  comfortable).
    stretch_limit : float or None the fabric's comfortable stretch along a yarn [-]; None:
                                  the fabric's own (:func:`stretch_limit`). A region whose
                                  stretch (its ``stretch_percentile`` of max(warp, weft) − 1)
                                  exceeds it is too tight ...
    tight_share : float           ... and exceeds this share of it, tight [-].
    loose_tolerance_cm : float    ease up to this far above the style's range reads loose;
                                  farther, too loose [cm].
    style : str or None           the garment type whose ease ranges apply
                                  (:data:`EASE_RANGES`); None: the pattern's own
                                  (:func:`garment_style`).
    region_share : float          regions smaller than this share of the garment's flat
                                  area get no verdict (a few triangles at a wrist) [-].
    pressure_percentile, stretch_percentile : float
                                  the area-weighted percentiles a region is judged by [%]:
                                  a spot of one vertex does not make a region tight.
    length_tolerance_cm : float   a sleeve's or trouser leg's end may rise this far along
                                  the limb from where the first drape had it before the
                                  correction lengthens it again [cm] (spec sheets allow
                                  ±1/4–1/2" on a jacket's sleeve length, up to ±1" on
                                  loose garments; 2.5 cm is that 1": a drape's folds
                                  move a sleeve's end as well).
    slid_cm : float               a garment hung from the waist whose top rests more
                                  than this far below it (the on-body checks'
                                  ``anchor_offset_mm``) slid down to where the body is as
                                  wide: its waist reads at least loose, judged by its ease
                                  over the waist alone, since its stretch and pressure are
                                  those of the hip it grips [cm].
    """

    pressure_max_kpa: float = 2.0
    pressure_comfort_kpa: float = 1.3
    stretch_limit: float | None = None
    tight_share: float = 0.5
    loose_tolerance_cm: float = 4.0
    style: str | None = None
    region_share: float = 0.01
    pressure_percentile: float = 95.0
    stretch_percentile: float = 90.0
    length_tolerance_cm: float = 2.5
    slid_cm: float = 5.0

    def __post_init__(self):
        # number() refuses a bool, a string or NaN, which the comparisons let through or
        # failed on with a TypeError
        number(self.pressure_max_kpa, "pressure_max_kpa", low=0.0, low_open=True, unit="kPa")
        number(self.pressure_comfort_kpa, "pressure_comfort_kpa", low=0.0, low_open=True,
               high=self.pressure_max_kpa, unit="kPa",
               rule=f"need 0 < comfort <= max ({self.pressure_max_kpa} kPa)")
        if self.stretch_limit is not None:
            number(self.stretch_limit, "stretch_limit", low=0.0, low_open=True, high=5.0,
                   high_open=True, rule="expected a fraction such as 0.05")
        number(self.tight_share, "tight_share", low=0.0, low_open=True, high=1.0,
               rule="expected a share in (0, 1]")
        for name in ("loose_tolerance_cm", "length_tolerance_cm", "slid_cm"):
            number(getattr(self, name), name, low=0.0, unit="cm")
        number(self.region_share, "region_share", low=0.0, high=1.0)
        if self.style is not None and (not isinstance(self.style, str)
                                       or self.style not in EASE_RANGES):
            raise ValueError(f"style: one of {', '.join(EASE_RANGES)}, got {self.style!r:.60}")
        for name in ("pressure_percentile", "stretch_percentile"):
            number(getattr(self, name), name, low=0.0, low_open=True, high=100.0,
                   rule="a percentile in (0, 100]")

    def with_options(self, **options) -> "VerdictRules":
        """These rules with the options that are not None replaced."""
        return replace(self, **{k: v for k, v in options.items() if v is not None})


#: ease ranges [cm] (garment girth − body girth) per garment type and girth: (least, most);
#: None: no bound (a straight coat is not shaped to the waist). Sources and the reasoning
#: per number: docs/fit-correction.md, "Ease ranges".
EASE_RANGES: dict[str, dict[str, tuple[float | None, float | None]]] = {
    "skirt": {"waist": (2.5, 5.1), "hip": (5.1, 15.2)},
    "trousers": {"waist": (2.5, 5.1), "hip": (5.1, 15.2), "thigh": (2.5, 20.0)},
    "coat": {"bust": (6.4, 25.4), "waist": (2.5, None), "hip": (5.1, None),
             "bicep": (2.5, 20.0)},
    "dress": {"bust": (6.4, 20.3), "waist": (2.5, None), "hip": (5.1, 20.3)},
    "shirt": {"bust": (9.0, 20.0), "waist": (5.0, None), "bicep": (2.5, 15.0)},
}
#: garment types cut straight below a girth (name → that girth): their most ease at a girth
#: below it with no bound of its own is that girth's most ease plus what the body lacks
#: there against it (:func:`ease_range`): a straight coat hangs from the chest, so its
#: waist and hip are as wide as its chest (men's jackets: hip girth within −3.8 to +1.3 cm
#: of the chest girth; docs/fit-correction.md, "Ease ranges"); the loosest dress, a shift,
#: hangs straight from the bust too (a dress 1.3 times too big, waist +43 cm, read "fits")
STRAIGHT_BELOW = {"coat": "bust", "dress": "bust"}

#: the type of a garment not named in :data:`EASE_RANGES`, by the pattern's anchor
_BY_ANCHOR = {"waist": "skirt", "neck": "dress"}

#: comfortable stretch along a yarn [-] of the fabric presets (docs/fit-correction.md,
#: "Stretch limits"): woven without elastane, knit, knit with elastane
STRETCH_LIMITS = {"cotton_shirting": 0.03, "denim": 0.03, "wool_coating": 0.03,
                  "jersey_knit": 0.10, "stretch_knit": 0.20}
#: a fabric not in :data:`STRETCH_LIMITS` stiffer than this along both yarns is taken as a
#: woven (the presets: wovens 1.7-8.9 kN/m, knits 33-130 N/m) [N/m]
WOVEN_STIFFNESS = 1000.0
WOVEN_LIMIT, KNIT_LIMIT = 0.03, 0.10


def stretch_limit(fabric) -> float:
    """The comfortable stretch [-] of ``fabric`` (a :class:`~patternfit.sim.fabrics.Fabric`
    or None): the preset's (:data:`STRETCH_LIMITS`), else by its stiffness (woven or knit)."""
    if fabric is None:
        return WOVEN_LIMIT
    if fabric.name in STRETCH_LIMITS:
        return STRETCH_LIMITS[fabric.name]
    woven = min(fabric.stretch_warp, fabric.stretch_weft) >= WOVEN_STIFFNESS
    return WOVEN_LIMIT if woven else KNIT_LIMIT


def garment_style(pattern) -> str:
    """The garment type of ``pattern`` whose ease ranges apply: its ``meta["garment"]`` or
    name when that is a type of :data:`EASE_RANGES`, else by its anchor (waist: skirt,
    neck: dress)."""
    for name in (str((pattern.meta or {}).get("garment", "")), pattern.name):
        for style in EASE_RANGES:
            if style in name.lower():
                return style
    if "trouser" in pattern.name.lower() or "pant" in pattern.name.lower():
        return "trousers"
    return _BY_ANCHOR.get(pattern.anchor, "dress")


def ease_range(style: str, girth: str, body_cm: dict | None = None
               ) -> tuple[float | None, float | None] | None:
    """(least, most) ease [cm] of ``girth`` (``"thigh_left"`` reads ``"thigh"``) in a
    garment of type ``style``; None where the style sets none. ``body_cm`` (girth name →
    the body's girth [cm]) gives a style cut straight below a girth
    (:data:`STRAIGHT_BELOW`) its most ease there: the upper girth's most ease plus how much
    smaller the body is here, (body there − body here)⁺."""
    base = girth.rsplit("_", 1)[0] if girth.endswith(("_left", "_right")) else girth
    rng = EASE_RANGES.get(style, {}).get(base)
    top = STRAIGHT_BELOW.get(style)
    if rng is None or rng[1] is not None or top is None or base == top or not body_cm:
        return rng
    most = EASE_RANGES[style][top][1]
    if most is None or body_cm.get(top) is None or body_cm.get(girth) is None:
        return rng
    return rng[0], most + max(body_cm[top] - body_cm[girth], 0.0)
