"""The fit verdict a pattern maker reads: per body region and overall, one of "too tight",
"tight", "fits", "loose", "too loose" (:data:`~patternfit.fit.verdict_rules.VERDICTS`), or
"failed" for a drape that failed its checks.

A region is judged by three measures (:class:`~patternfit.fit.measures.FitMeasures`, the
warp/weft stretch of :class:`~patternfit.fit.metrics.FitResult`) against the thresholds of
:class:`~patternfit.fit.verdict_rules.VerdictRules`:

- too tight: its pressure (p95 over its contact area) above ``pressure_max_kpa``, or its
  stretch (p90 over its area of max(warp, weft) − 1) beyond the fabric's comfortable limit;
- tight: pressure above ``pressure_comfort_kpa``, stretch beyond ``tight_share`` of the
  limit, or ease below the style's range (its least ease lowered by that share of the
  limit times the body's girth: the negative ease a knit's stretch gives back);
- loose: ease above the style's range by at most ``loose_tolerance_cm``; too loose: more;
- fits: none of these.

Overall: the first of too tight, too loose, tight, loose that a region reads, else fits.
A drape that failed its checks is "failed", with no region verdicts, and its reason says
why: one that slid off its anchor (its top more than the on-body tolerance below the waist
or neck it hangs from, :mod:`patternfit.sim.onbody`), still sewn and on the body, adds that
it is too loose to hang from it; one that fell (past the hips, to the floor or below the
feet), lies far from the body, collapsed or left seams open says only that.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..constants import limits
from ..sim.onbody import ON_BODY
from .measures import FitMeasures, _weighted_percentiles
from .metrics import FitResult
from .verdict_rules import (FAILED, VERDICTS, VerdictRules, ease_range, garment_style,
                            stretch_limit)

#: the overall verdict is the first of these that any region reads
_PRIORITY = ("too tight", "too loose", "tight", "loose")


@dataclass(frozen=True)
class RegionVerdict:
    """One region's verdict and the measures it was judged by (None: not measured there).

    ease_cm [cm], pressure_kpa_p95 [kPa], stretch_p90 [-] (max(warp, weft) − 1), area_m2
    (flat) [m²], reason in words."""

    verdict: str
    ease_cm: float | None
    pressure_kpa_p95: float | None
    stretch_p90: float | None
    area_m2: float
    reason: str

    def to_dict(self) -> dict:
        return {"verdict": self.verdict, "ease_cm": self.ease_cm,
                "pressure_kpa_p95": self.pressure_kpa_p95, "stretch_p90": self.stretch_p90,
                "area_m2": self.area_m2, "reason": self.reason}


@dataclass(frozen=True)
class Verdict:
    """The verdict of one drape: ``overall`` (a word of :data:`VERDICTS` or "failed"),
    ``regions`` (name → :class:`RegionVerdict`), ``reason`` for the overall word, and the
    ``style`` and ``stretch_limit`` [-] it was judged with."""

    overall: str
    regions: dict = field(default_factory=dict)
    reason: str = ""
    style: str | None = None
    stretch_limit: float | None = None

    def report(self) -> dict:
        """The report keys: ``verdict`` (the overall word), ``verdict_reason``,
        ``verdict_rules`` (style, stretch limit) and ``region_verdicts`` (region →
        {verdict, ease_cm, pressure_kpa_p95, stretch_p90, area_m2, reason})."""
        return {"verdict": self.overall, "verdict_reason": self.reason,
                "verdict_rules": {"style": self.style, "stretch_limit": self.stretch_limit},
                "region_verdicts": {k: v.to_dict() for k, v in self.regions.items()}}

    def worst(self, word: str) -> list[str]:
        """The regions that read ``word``."""
        return [k for k, v in self.regions.items() if v.verdict == word]


#: a garment whose lowest point is this near the floor [mm] rests on it
FLOOR_TOUCH_MM = 10.0


def slid_off(checks: dict | None) -> str | None:
    """Why the drape with these ``checks`` slid off its anchor (its top more than the
    on-body tolerance below it, the garment otherwise on the body: sewn, not fallen below
    the feet, not far from the body, not collapsed), or None: the drape failed, and its
    reason says it slid, too loose to hang from its anchor. A garment that fell or never
    closed its seams is not too loose: its drape failed for that (a pattern in millimetres
    read as metres fell 25 m, or onto the floor the body stands on, where its top lies
    within the anchor tolerance of the floor, y = 0, or past the hips, its top below the
    crotch: a skirt 125 cm round on 96 cm hips, round her shins, its hem on the floor; or
    until the floor holds it, its lowest point within :data:`FLOOR_TOUCH_MM` of it); nor
    is one that never came to rest (its ease and regions are of a state still moving: it
    read "too loose" beside a hip "too tight"), or has cloth inside the body. Crossed pairs
    pooled in a hem do not stop a slide from being said."""
    checks = checks or {}
    offset = checks.get("anchor_offset_mm")
    if offset is None or offset >= -1000.0 * ON_BODY.anchor_tolerance:
        return None
    ratio = checks.get("area_ratio_3d")
    gap = checks.get("seam_gap_max_mm")
    top = checks.get("anchor_height_mm")
    lowest = checks.get("lowest_mm")
    if (checks.get("below_feet_vertices") or checks.get("far_vertices")
            or checks.get("top_below_crotch")
            # slid until the floor holds it: a skirt 1.3 times too big stood on its hem,
            # its top 29 cm below the waist and 1 mm above the crotch
            or (lowest is not None and lowest < FLOOR_TOUCH_MM)
            # a drape still moving is no fit to judge: its ease and regions are passing
            or checks.get("equilibrium") is False
            # nor is cloth inside the body, which no drape leaves (a saved state moved
            # down 5 cm by hand, 54 vertices in the hips, read "too loose")
            or checks.get("inside_vertices")
            or (top is not None and top < 1000.0 * ON_BODY.anchor_tolerance)
            or (ratio is not None and not ratio >= ON_BODY.min_area_ratio)
            or (gap is not None and not gap < limits.seam_gap_mm)):
        return None
    return (f"slid off its anchor: its top is {-offset / 10:.1f} cm below the "
            f"{checks.get('anchor', 'anchor')}")


def _sunk_cm(checks: dict | None, rules: VerdictRules) -> float | None:
    """How far [cm] the top of a garment hung from the waist rests below the waist when
    that is more than ``rules.slid_cm`` (``checks["anchor_offset_mm"]``, the on-body
    checks'), else None."""
    checks = checks or {}
    offset = checks.get("anchor_offset_mm")
    if checks.get("anchor") != "waist" or offset is None or not -offset > 10 * rules.slid_cm:
        return None
    return -offset / 10.0


def judge_region(ease_cm, pressure, stretch, *, style: str, girth: str, limit: float,
                 rules: VerdictRules, body_cm: float | None = None,
                 body_girths: dict | None = None) -> tuple[str, str]:
    """The verdict word and its reason for one region from its ease [cm], pressure [kPa]
    and stretch [-] (each may be None: not measured). The style's least ease is lowered by
    the stretch the rules still call fitting (``tight_share × limit`` of the body's girth
    ``body_cm`` [cm]): a knit's negative ease is what its stretch gives back.
    ``body_girths`` (girth name → body girth [cm]) bounds the ease of a style cut straight
    below a girth (:func:`~patternfit.fit.verdict_rules.ease_range`)."""
    rng = ease_range(style, girth, body_girths)
    lo, hi = rng if rng is not None else (None, None)
    if lo is not None and body_cm is not None:
        lo = lo - rules.tight_share * limit * body_cm
    if pressure is not None and pressure > rules.pressure_max_kpa:
        return "too tight", (f"pressure {pressure:.2f} kPa above {rules.pressure_max_kpa:g} "
                             "kPa")
    if stretch is not None and stretch > limit:
        return "too tight", (f"stretched {stretch * 100:.0f}%, beyond the fabric's "
                             f"{limit * 100:.0f}%")
    if pressure is not None and pressure > rules.pressure_comfort_kpa:
        return "tight", (f"pressure {pressure:.2f} kPa above the comfortable "
                         f"{rules.pressure_comfort_kpa:g} kPa")
    if stretch is not None and stretch > rules.tight_share * limit:
        return "tight", (f"stretched {stretch * 100:.0f}%, over {rules.tight_share:.0%} of "
                         f"the fabric's {limit * 100:.0f}%")
    owner = f"{style}'" if style.endswith("s") else f"{style}'s"  # the trousers' 5 cm
    if ease_cm is not None and lo is not None and ease_cm < lo:
        return "tight", f"ease {ease_cm:+.1f} cm below the {owner} {lo:.1f} cm"
    if ease_cm is not None and hi is not None and ease_cm > hi:
        word = "loose" if ease_cm <= hi + rules.loose_tolerance_cm else "too loose"
        return word, f"ease {ease_cm:+.1f} cm above the {owner} {hi:g} cm"
    if ease_cm is None and rng is not None:
        return "fits", "within limits; ease not measured (the cloth does not close round " \
                       "the body here)"
    what = f"ease {ease_cm:+.1f} cm, " if ease_cm is not None else ""
    return "fits", f"{what}within limits"


def judge(fit: FitResult, measures: FitMeasures, *, style: str, limit: float,
          checks: dict | None = None, rules: VerdictRules = VerdictRules()) -> Verdict:
    """The verdict of a drape: ``fit`` its per-triangle fit, ``measures`` its measures
    (with body regions), ``style`` the garment type of the ease ranges, ``limit`` the
    fabric's comfortable stretch [-] (``rules.stretch_limit`` overrides it), ``checks``
    the drape's checks (None: passed)."""
    limit = rules.stretch_limit if rules.stretch_limit is not None else limit
    slid = slid_off(checks)
    if slid or (checks and checks.get("passed") is False):
        # one that slid off its anchor too: it is too big to hang there, but where it came
        # to rest is no fit to judge (it read "too loose" with every region "fits", exit 1,
        # and a batch counted it as too loose, not failed)
        reasons = [str(r) for r in checks.get("reasons") or []] or ["checks failed"]
        if slid:
            reasons.append(f"{slid}: too loose to hang from it")
        return Verdict(FAILED, {}, f"the drape failed: {'; '.join(reasons)}", style, limit)
    stretch = np.maximum(fit.warp, fit.weft) - 1.0
    total = float(fit.area_2d.sum())
    sections = measures.sections
    body_girths = {k: sec.body_cm for k, sec in sections.items()}
    sunk = _sunk_cm(checks, rules)
    regions = {}
    # cloth resting on a hand's hull is a sleeve too long for the arm, not too tight
    hand_t, hand_v = measures.triangle_on_hand, measures.vertex_on_hand
    for k, name in enumerate(measures.regions):
        tris = measures.triangle_region == k
        area = float(fit.area_2d[tris].sum())
        if area < rules.region_share * total:
            continue
        if hand_t is not None:
            tris = tris & ~hand_t
        s = _weighted_percentiles(stretch[tris], fit.area_2d[tris],
                                  (rules.stretch_percentile,))[0]
        verts = (measures.vertex_region == k) & measures.contact
        if hand_v is not None:
            verts = verts & ~hand_v
        p = _weighted_percentiles(measures.pressure_kpa[verts], measures.vertex_area[verts],
                                  (rules.pressure_percentile,))[0]
        sec = sections.get(name)
        e = sec.ease_cm if sec is not None else None
        down = sunk is not None and name == "waist"
        word, why = judge_region(e, None if down else p, None if down else s, style=style,
                                 girth=name, limit=limit, rules=rules,
                                 body_cm=sec.body_cm if e is not None else None,
                                 body_girths=body_girths)
        if down:
            if word not in ("loose", "too loose"):
                word, why = "loose", (f"ease {e:+.1f} cm where it rests" if e is not None
                                      else "")
            # where it came to rest it may grip hard (a band stretched 14 % at 7.3 kPa read
            # "loose" and nothing more, audit 14): say so beside the slide
            grip, _ = judge_region(None, p, s, style=style, girth=name, limit=limit,
                                   rules=rules)
            grips = [f"at {p:.2f} kPa" if p is not None else "",
                     f"stretched {s * 100:.0f}%" if s is not None else ""]
            held = ("held there " + ", ".join(g for g in grips if g)
                    if grip in ("tight", "too tight") else "")
            why = "; ".join(w for w in (f"its top rests {sunk:.1f} cm below the waist, slid "
                                        "down to where the body is as wide", held, why) if w)
        regions[name] = RegionVerdict(word, e, p, s, area, why)
    words = [v.verdict for v in regions.values()]
    for w in _PRIORITY:
        if w in words:
            where = [k for k, v in regions.items() if v.verdict == w]
            return Verdict(w, regions, f"{w} at {', '.join(where)}", style, limit)
    unmeasured = [k for k, v in regions.items()
                  if v.ease_cm is None and ease_range(style, k) is not None]
    return Verdict("fits", regions, "every region fits" + (
        f"; ease not measured at {', '.join(unmeasured)}" if unmeasured else ""), style, limit)


def judge_garment(pattern, fit: FitResult, measures: FitMeasures, fabric, checks=None,
                  rules: VerdictRules | None = None) -> Verdict:
    """:func:`judge` with the ease ranges of ``pattern``'s garment type and ``fabric``'s
    comfortable stretch (a :class:`~patternfit.sim.fabrics.Fabric` or None), unless
    ``rules`` set them."""
    rules = rules or VerdictRules()
    return judge(fit, measures, style=rules.style or garment_style(pattern),
                 limit=stretch_limit(fabric), checks=checks, rules=rules)


__all__ = ["FAILED", "RegionVerdict", "VERDICTS", "Verdict", "judge", "judge_garment", "judge_region",
           "slid_off"]
