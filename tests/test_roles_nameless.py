"""Roles read from seams and shape alone, on garments built the way GarmentCode builds its
published ones, with every panel's name replaced by a number (and, in one variant, no 3D
placement either): bodices in left and right halves sewn at the centre lines (backs drawn
clockwise, as seen from the front), darts sewn into a panel, sleeves in a front and a back
half drawn sideways, a collar in small pieces sewn into the neckline, a circle skirt whose
slanted side seams run across its top, tiers stacked under it, and a waistband in two bands.
Centimetres, edges by vertex index with relative curvature, as GarmentCode writes them."""

from __future__ import annotations

import pytest

from patternfit.pattern.roles import garment_anchor, panel_roles
from scenes import gc_circle_skirt as circle_skirt
from scenes import gc_panel as _panel
from scenes import gc_pattern as _garment

ARMHOLE = {"type": "cubic", "params": [[0.3, 0.25], [0.7, 0.1]]}
NECK = {"type": "quadratic", "params": [[0.5, 0.3]]}
CAP = {"type": "quadratic", "params": [[0.5, 0.25]]}      # bulging left of the edge
CAP_CCW = {"type": "quadratic", "params": [[0.5, -0.25]]}  # bulging right of it


def _mirror(points, curved):
    """A panel's mirror image (x -> -x), its outline run the same way round again."""
    n = len(points)
    pts = [[-x, y] for x, y in reversed(points)]
    flipped = {}
    for k, c in (curved or {}).items():
        # edge k (k -> k+1) becomes edge n-2-k (reversed direction): the bulge stays outside
        flipped[(n - 2 - k) % n] = c
    return pts, flipped


def _halves(prefix_f, prefix_b, z_f=25.0, z_b=-20.0, y=90.0, dart=False):
    """A bodice in four halves: panels and the stitches joining them (by names given)."""
    front = [[0, 0], [25, 0], [25, 30], [15, 45], [8, 47], [0, 38]]
    front_c = {2: ARMHOLE, 4: NECK}
    back = [[0, 0], [0, 44], [8, 47], [15, 45], [25, 30], [25, 0]]   # clockwise
    back_c = {1: NECK, 3: ARMHOLE}
    if dart:  # a waist dart in each front half: two short edges sewn together
        front = [[0, 0], [9, 0], [11, 9], [13, 0], [25, 0], [25, 30], [15, 45], [8, 47],
                 [0, 38]]
        front_c = {5: ARMHOLE, 7: NECK}
    panels = {}
    lf, rf = f"{prefix_f}0", f"{prefix_f}1"
    lb, rb = f"{prefix_b}0", f"{prefix_b}1"
    panels[lf] = _panel(front, front_c, (0.0, y, z_f))
    panels[rf] = _panel(*_mirror(front, front_c), at=(0.0, y, z_f))
    panels[lb] = _panel(back, back_c, (0.0, y, z_b))
    panels[rb] = _panel(*_mirror(back, back_c), at=(0.0, y, z_b))
    nf, nb = len(front), len(back)
    # edge numbers: front: centre front is the last edge; the mirror reverses the order
    ff = {"hem": 0, "side": 1 if not dart else 4,
          "arm": 2 if not dart else 5, "shoulder": 3 if not dart else 6,
          "neck": 4 if not dart else 7, "centre": nf - 1}
    bb = {"centre": 0, "neck": 1, "shoulder": 2, "arm": 3, "side": 4, "hem": 5}

    def m(idx, n):
        return (n - 2 - idx) % n

    stitches = [((lf, ff["centre"]), (rf, m(ff["centre"], nf))),
                ((lb, bb["centre"]), (rb, m(bb["centre"], nb))),
                ((lf, ff["side"]), (lb, bb["side"])),
                ((lf, ff["shoulder"]), (lb, bb["shoulder"])),
                ((rf, m(ff["side"], nf)), (rb, m(bb["side"], nb))),
                ((rf, m(ff["shoulder"], nf)), (rb, m(bb["shoulder"], nb)))]
    if dart:
        stitches += [((lf, 1), (lf, 2)), ((rf, m(1, nf)), (rf, m(2, nf)))]
    arms = {lf: ff["arm"], rf: m(ff["arm"], nf), lb: bb["arm"], rb: m(bb["arm"], nb)}
    necks = {lf: ff["neck"], rf: m(ff["neck"], nf), lb: bb["neck"], rb: m(bb["neck"], nb)}
    return panels, stitches, arms, necks


def _sleeves(panels, stitches, arms, names):
    """Each sleeve in a front and a back half drawn sideways: the cap (left end, curved)
    sewn into the armhole, the over-arm (top) and underarm (bottom) seams between halves."""
    lf, rf, lb, rb = names["bodice"]
    for k, (front, back) in enumerate(((lf, lb), (rf, rb))):
        sf, sb = names["sleeve"][2 * k], names["sleeve"][2 * k + 1]
        side = 1 if k == 0 else -1
        pts = [[0, 0], [50, 4], [50, 16], [0, 19]]   # underarm, wrist, over-arm, cap
        # the back half clockwise (seen from the front): over-arm, wrist, underarm, cap
        panels[sf] = _panel(pts, {3: CAP_CCW}, (side * 50.0, 110.0, 20.0), rot=-50.0 * side)
        panels[sb] = _panel([[x, y] for x, y in reversed(pts)], {3: CAP},
                            (side * 50.0, 110.0, -10.0), rot=-50.0 * side)
        stitches += [((sf, 3), (front, arms[front])), ((sb, 3), (back, arms[back])),
                     ((sf, 2), (sb, 0)), ((sf, 0), (sb, 2))]


def _collar(panels, stitches, necks, names):
    """A standing collar in four small pieces: a front piece per side sewn to the front
    neckline, a back piece per side to the back neckline, joined at centre back."""
    lf, rf, lb, rb = names["bodice"]
    cf0, cf1, cb0, cb1 = names["collar"]
    panels[cf0] = _panel([[0, 0], [4, 0], [7, 12], [3, 12]], at=(10.0, 150.0, 30.0))
    panels[cf1] = _panel([[0, 0], [4, 0], [1, 12], [-3, 12]], at=(-10.0, 150.0, 30.0))
    panels[cb0] = _panel([[0, 0], [9, 0], [9, 5], [0, 5]], at=(5.0, 150.0, -12.0))
    panels[cb1] = _panel([[0, 0], [9, 0], [9, 5], [0, 5]], at=(-5.0, 150.0, -12.0))
    stitches += [((cf0, 0), (lf, necks[lf])), ((cf1, 0), (rf, necks[rf])),
                 ((cb0, 0), (lb, necks[lb])), ((cb1, 0), (rb, necks[rb])),
                 ((cb0, 3), (cb1, 1)), ((cf0, 2), (cb0, 2)), ((cf1, 2), (cb1, 2))]


def shirt(placed=True, dart=False):
    names = {"bodice": ["p0", "p1", "p2", "p3"], "sleeve": ["p4", "p5", "p6", "p7"]}
    panels, stitches, arms, _ = _renamed_halves(dart)
    _sleeves(panels, stitches, arms, names)
    return _garment(panels, stitches, placed)


def _renamed_halves(dart=False):
    """:func:`_halves` with the panels named by number: fronts p0, p1, backs p2, p3."""
    panels, stitches, arms, necks = _halves("f", "b", dart=dart)
    rename = {"f0": "p0", "f1": "p1", "b0": "p2", "b1": "p3"}
    panels = {rename[k]: v for k, v in panels.items()}
    stitches = [((rename[a], i), (rename[b], j)) for (a, i), (b, j) in stitches]
    arms = {rename[k]: v for k, v in arms.items()}
    necks = {rename[k]: v for k, v in necks.items()}
    return panels, stitches, arms, necks


WANT_SHIRT = {"p0": ("bodice", "torso", "front"), "p1": ("bodice", "torso", "front"),
              "p2": ("bodice", "torso", "back"), "p3": ("bodice", "torso", "back"),
              "p4": ("sleeve", "arm_left", "front"), "p5": ("sleeve", "arm_left", "back"),
              "p6": ("sleeve", "arm_right", "front"), "p7": ("sleeve", "arm_right", "back")}


def _roles(pattern):
    return {n: (r.kind, r.part, r.side) for n, r in panel_roles(pattern).items()}


@pytest.mark.parametrize("placed", [True, False])
@pytest.mark.parametrize("dart", [False, True])
def test_a_shirt_in_halves_without_names(placed, dart):
    pattern = shirt(placed=placed, dart=dart)
    assert _roles(pattern) == WANT_SHIRT
    assert garment_anchor(pattern) == "neck"


@pytest.mark.parametrize("placed", [True, False])
def test_a_collar_in_small_pieces_without_names(placed):
    panels, stitches, arms, necks = _renamed_halves()
    names = {"bodice": ["p0", "p1", "p2", "p3"], "collar": ["p4", "p5", "p6", "p7"]}
    _collar(panels, stitches, necks, names)
    roles = _roles(_garment(panels, stitches, placed))
    assert {n: r[0] for n, r in roles.items()} == {
        "p0": "bodice", "p1": "bodice", "p2": "bodice", "p3": "bodice",
        "p4": "collar", "p5": "collar", "p6": "collar", "p7": "collar"}
    assert [roles[n][2] for n in ("p0", "p2", "p4", "p6")] == ["front", "back", "front",
                                                               "back"]


@pytest.mark.parametrize("placed", [True, False])
@pytest.mark.parametrize("tiers", [0, 2])
def test_a_circle_skirt_is_a_skirt_with_a_waistband(placed, tiers):
    pattern = circle_skirt(placed, tiers)
    roles = _roles(pattern)
    assert roles["p0"] == ("skirt", "torso", "front")
    assert roles["p1"] == ("skirt", "torso", "back")
    assert roles["p2"][0] == roles["p3"][0] == "waistband"
    for t in range(tiers):  # stacked tiers face as the panel they hang from
        assert roles[f"p{4 + 2 * t}"] == ("skirt", "torso", "front")
        assert roles[f"p{5 + 2 * t}"] == ("skirt", "torso", "back")
    assert garment_anchor(pattern) == "waist"
