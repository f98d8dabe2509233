"""Writes the GarmentCode-style garments of this folder (run from the repository root:
``python tests/data/garmentcode/make_garments.py``).

Each is written the way GarmentCode writes a specification: centimetres, panels by name with
2D vertices, edges by vertex index with relative curvature, a 3D translation and XYZ Euler
rotation per panel, stitches by edge index; none of patternfit's own keys (no
``patternfit_*``), so nothing says which body part a panel dresses. Names follow
GarmentCode's (``ftorso``, ``lfsleeve``, ``pant_b_r``...). Placements: the tee's panels all
lie at the feet (y = 0), the shirt's 25 m below, the jumpsuit's 25 m below; the dress and
the hoodie carry none (every translation and rotation zero, as a template that leaves
placement to the simulator). Every panel is drawn in its own frame, its lowest left corner at
the origin.
"""

import json
import math
from dataclasses import replace
from pathlib import Path

from patternfit.pattern.edges import Edge
from patternfit.pattern.garmentcode import garmentcode_to_dict
from patternfit.pattern.library import _mirror_panel, shirt, trousers
from patternfit.pattern.model import Loop, Panel, Pattern, Placement, Seam, SeamSide
from patternfit.pattern.sizes import size_chart

HERE = Path(__file__).parent
FEMALE, MALE = size_chart("female", "M"), size_chart("male", "M")


def bodice(m, length):
    """Front and back of a sleeveless shirt cut ``length`` [m] below the neck point."""
    p = shirt(m, length=length)
    return p.panel("front"), p.panel("back"), [s for s in p.seams
                                               if s.name.startswith(("side", "shoulder"))]


def write(pattern: Pattern, name: str, rename: dict, placement) -> None:
    doc = garmentcode_to_dict(pattern)
    spec = doc["pattern"]
    for k in [k for k in doc if k.startswith("patternfit")]:
        del doc[k]
    panels = {}
    for old, entry in spec["panels"].items():
        del entry["patternfit_placement"]
        # every panel in its own frame, its lowest left corner at the origin, as GarmentCode
        # draws them: the frames no longer say how the panels stand in height
        lo = [min(v[k] for v in entry["vertices"]) for k in (0, 1)]
        entry["vertices"] = [[round(v[0] - lo[0], 6), round(v[1] - lo[1], 6)]
                             for v in entry["vertices"]]
        entry["translation"], entry["rotation"] = placement(rename[old], entry)
        panels[rename[old]] = entry
    spec["panels"] = panels
    for st in spec["stitches"]:
        for side in st[:2]:
            side["panel"] = rename[side["panel"]]
    doc["properties"] = {"curvature_coords": "relative", "normalize_panel_translation": False,
                         "units_in_meter": 100, "normalized_edge_loops": True}
    (HERE / f"{name}_specification.json").write_text(json.dumps(doc, indent=1) + "\n")


def at_feet(name, entry):
    z = -15.0 if "b" in name.split("_")[0].replace("sleeve", "").replace("torso", "") else 15.0
    return [0.0, 0.0, z], [0.0, 0.0, 0.0]


def deep_below(name, entry):
    return [0.0, -2500.0, 20.0], [0.0, 0.0, 0.0]


def none(name, entry):
    return [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]


def tee():
    p = shirt(MALE, length=MALE.back_length + 0.22, sleeve_length=0.22)
    write(p, "tee", {"front": "ftorso", "back": "btorso", "sleeve_l": "lsleeve",
                     "sleeve_r": "rsleeve"}, at_feet)


def long_shirt():
    p = shirt(MALE)
    write(p, "shirt", {"front": "front_torso", "back": "back_torso", "sleeve_l": "left_sleeve",
                       "sleeve_r": "right_sleeve"}, deep_below)


def gathered_skirt_panel(name, half_width, length, top, placement):
    edges = (Edge.line("hem", (-half_width, top - length), (half_width, top - length)),
             Edge.line("side_l", (half_width, top - length), (half_width, top)),
             Edge.line("waist", (half_width, top), (-half_width, top)),
             Edge.line("side_r", (-half_width, top), (-half_width, top - length)))
    return Panel(name, Loop("outline", edges), placement=placement)


def dress():
    front, back, seams = bodice(FEMALE, FEMALE.back_length)
    hem = front.edge("hem").length
    skirt_f = gathered_skirt_panel("skirt_f", 1.3 * hem / 2, 0.55, 0.0, Placement())
    skirt_b = _mirror_panel(skirt_f, "skirt_b", Placement())
    seams = seams + [
        Seam("waist_f", SeamSide("skirt_f", "waist"), SeamSide("front", "hem"), ease=0.3),
        Seam("waist_b", SeamSide("skirt_b", "waist"), SeamSide("back", "hem"), ease=0.3),
        Seam("skirt_side_l", SeamSide("skirt_f", "side_l"), SeamSide("skirt_b", "side_l")),
        Seam("skirt_side_r", SeamSide("skirt_f", "side_r"), SeamSide("skirt_b", "side_r"))]
    p = Pattern("dress", (front, back, skirt_f, skirt_b), tuple(seams))
    write(p, "dress", {"front": "ftorso", "back": "btorso", "skirt_f": "skirt_front",
                       "skirt_b": "skirt_back"}, none)


def _longer(edge: Edge, ratio: float) -> Edge:
    """The cubic ``edge`` with its control points pushed out until it is ``ratio`` times as
    long (same ends)."""
    p = [tuple(c) for c in edge.points]
    d = (edge.end - edge.start)
    n = (-d[1] / math.hypot(*d), d[0] / math.hypot(*d))
    lo, hi = 0.0, 0.2
    for _ in range(60):
        k = 0.5 * (lo + hi)
        e = edge.with_points([p[0], (p[1][0] - k * n[0], p[1][1] - k * n[1]),
                              (p[2][0] - k * n[0], p[2][1] - k * n[1]), p[3]])
        lo, hi = (k, hi) if e.length < ratio * edge.length else (lo, k)
    return e


def jumpsuit():
    front, back, seams = bodice(FEMALE, FEMALE.back_length)
    legs = trousers(FEMALE)
    panels = [front, back]
    for leg in legs.panels:
        if leg.name.startswith("back"):  # the back hip 26.0 cm against the front's 23.6
            leg = leg.with_edge(_longer(leg.edge("hip"), 26.0 / 23.6))
        panels.append(replace(leg, placement=Placement()))
    seams = seams + list(legs.seams) + [
        # the front's hem runs from the body's right to its left, the back's the other way
        Seam("waist_fl", SeamSide("front_l", "waist"), SeamSide("front", "hem", 0.5, 1.0)),
        Seam("waist_fr", SeamSide("front_r", "waist"), SeamSide("front", "hem", 0.0, 0.5)),
        Seam("waist_bl", SeamSide("back_l", "waist"), SeamSide("back", "hem", 0.0, 0.5)),
        Seam("waist_br", SeamSide("back_r", "waist"), SeamSide("back", "hem", 0.5, 1.0))]
    p = Pattern("jumpsuit", tuple(panels), tuple(seams))
    write(p, "jumpsuit", {"front": "ftorso", "back": "btorso", "front_l": "pant_f_l",
                          "front_r": "pant_f_r", "back_l": "pant_b_l", "back_r": "pant_b_r"},
          deep_below)


def hoodie():
    p = shirt(MALE)
    lf = p.panel("front").edge("neckline").length / 2
    lb = p.panel("back").edge("neckline").length / 2
    a, b, c = (0.0, 0.0), (lf, 0.0), (lf + lb, 0.02)
    d, e = (lf + lb + 0.03, 0.30), (0.06, 0.36)
    edges = (Edge.line("neck_front", a, b), Edge.line("neck_back", b, c),
             Edge.cubic("back", c, (c[0] + 0.08, 0.10), (d[0] + 0.02, 0.22), d),
             Edge.cubic("crown", d, (d[0] - 0.02, 0.38), (0.20, 0.40), e),
             Edge.line("face", e, a))
    hood_l = Panel("hood_l", Loop("outline", edges))
    hood_r = _mirror_panel(hood_l, "hood_r", Placement())
    seams = list(p.seams) + [
        Seam("hood_back", SeamSide("hood_l", "back"), SeamSide("hood_r", "back")),
        Seam("hood_crown", SeamSide("hood_l", "crown"), SeamSide("hood_r", "crown")),
        Seam("neck_fl", SeamSide("hood_l", "neck_front"), SeamSide("front", "neckline", 0.0, 0.5)),
        Seam("neck_bl", SeamSide("hood_l", "neck_back"), SeamSide("back", "neckline", 0.5, 1.0)),
        Seam("neck_fr", SeamSide("hood_r", "neck_front"), SeamSide("front", "neckline", 0.5, 1.0)),
        Seam("neck_br", SeamSide("hood_r", "neck_back"), SeamSide("back", "neckline", 0.0, 0.5))]
    pattern = Pattern("hoodie", (*p.panels, hood_l, hood_r), tuple(seams))
    write(pattern, "hoodie", {"front": "front", "back": "back", "sleeve_l": "lsleeve",
                              "sleeve_r": "rsleeve", "hood_l": "hood_left",
                              "hood_r": "hood_right"}, none)


if __name__ == "__main__":
    for make in (tee, long_shirt, dress, jumpsuit, hoodie):
        make()
