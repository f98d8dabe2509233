"""Placement of any garment (issue 20, item 4): each panel's role (kind, body part, side)
and the garment's anchor read from the pattern, imported 3D placements judged on the body,
and other tools' files draped with every check passing.

The GarmentCode files in tests/data/garmentcode/ are written the way GarmentCode writes its
specifications (``make_garments.py`` there), with no key of ours: nothing states a body part.
"""

import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from patternfit.body.builtin import load_body
from patternfit.mesh import mesh_pattern
from patternfit.pattern.garmentcode import load_garmentcode
from patternfit.pattern.library import GARMENTS, build
from patternfit.pattern.model import Placement
from patternfit.pattern.roles import garment_anchor, panel_roles
from patternfit.sim.fabrics import get_fabric
from patternfit.sim.onbody import on_body_checks
from patternfit.sim.panel_frames import PlacementWarning, implausible_placements
from patternfit.sim.placement import place_on_body
from patternfit.sim.solver import GarmentSolver

from scenes import gored_skirt, planes_placed

GC = Path(__file__).parent / "data" / "garmentcode"

#: per file: the anchor and every panel's (kind, part, side)
EXPECTED = {
    "dress": ("neck", {"ftorso": ("bodice", "torso", "front"),
                       "btorso": ("bodice", "torso", "back"),
                       "skirt_front": ("skirt", "torso", "front"),
                       "skirt_back": ("skirt", "torso", "back")}),
    "jumpsuit": ("neck", {"ftorso": ("bodice", "torso", "front"),
                          "btorso": ("bodice", "torso", "back"),
                          "pant_f_r": ("leg", "leg_right", "front"),
                          "pant_f_l": ("leg", "leg_left", "front"),
                          "pant_b_r": ("leg", "leg_right", "back"),
                          "pant_b_l": ("leg", "leg_left", "back")}),
    "hoodie": ("neck", {"front": ("bodice", "torso", "front"),
                        "back": ("bodice", "torso", "back"),
                        "lsleeve": ("sleeve", "arm_left", "outer"),
                        "rsleeve": ("sleeve", "arm_right", "outer"),
                        "hood_left": ("hood", "torso", "left"),
                        "hood_right": ("hood", "torso", "right")}),
    "shirt": ("neck", {"front_torso": ("bodice", "torso", "front"),
                       "back_torso": ("bodice", "torso", "back"),
                       "left_sleeve": ("sleeve", "arm_left", "outer"),
                       "right_sleeve": ("sleeve", "arm_right", "outer")}),
    "tee": ("neck", {"ftorso": ("bodice", "torso", "front"),
                     "btorso": ("bodice", "torso", "back"),
                     "lsleeve": ("sleeve", "arm_left", "outer"),
                     "rsleeve": ("sleeve", "arm_right", "outer")}),
}


def gc(name):
    return load_garmentcode(GC / f"{name}_specification.json")


def unnamed(pattern):
    """The pattern with its panels called P1, P2... and no stated placement: what a DXF
    without a side file gives (the seams kept)."""
    names = {p.name: f"P{i + 1}" for i, p in enumerate(pattern.panels)}
    panels = tuple(replace(p, name=names[p.name], placement=Placement())
                   for p in pattern.panels)
    seams = tuple(replace(s, a=replace(s.a, panel=names[s.a.panel]),
                          b=replace(s.b, panel=names[s.b.panel])) for s in pattern.seams)
    return replace(pattern, panels=panels, seams=seams, meta={}), names


@pytest.mark.parametrize("garment, anchor", [("skirt", "waist"), ("shirt", "neck")])
def test_a_yoke_is_a_bodice_by_its_shoulders_not_its_name(garment, anchor):
    # a skirt's hip yoke and a shirt's shoulder yoke: every panel called yoke_<n>, no stated
    # placement; the seams decide (a skirt so named hung from the neck and failed)
    bare, names = unnamed(build(garment))
    yoked = {f"P{i + 1}": f"yoke_{i + 1}" for i in range(len(names))}
    pattern = replace(bare, panels=tuple(replace(p, name=yoked[p.name]) for p in bare.panels),
                      seams=tuple(replace(s, a=replace(s.a, panel=yoked[s.a.panel]),
                                          b=replace(s.b, panel=yoked[s.b.panel]))
                                  for s in bare.seams))
    assert garment_anchor(pattern) == pattern.anchor == anchor


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_roles_and_anchor_of_garmentcode_garments(name):
    pattern = gc(name)
    anchor, want = EXPECTED[name]
    roles = panel_roles(pattern)
    assert {k: (r.kind, r.part, r.side) for k, r in roles.items()} == want
    assert garment_anchor(pattern, roles) == anchor == pattern.anchor


@pytest.mark.parametrize("name", list(GARMENTS))
def test_roles_of_built_ins_from_seams_and_shape_alone(name):
    # no names, no stated parts: the kinds and the body part of each panel come from the
    # seams and the shapes; sides from the necklines and the seams
    pattern = build(name)
    bare, names = unnamed(pattern)
    roles = panel_roles(bare)
    stated = {names[p.name]: p.placement for p in pattern.panels}
    for n, r in roles.items():
        assert r.part == stated[n].part, (n, r)
        if r.part == "torso":
            assert r.side == stated[n].side, (n, r)
    assert bare.anchor == pattern.anchor == GARMENTS[name][3]


def test_roles_of_a_two_piece_sleeve_and_a_cuff_from_seams():
    # the tee's sleeves carry names: without them, a one-piece sleeve sewn to itself is a tube
    bare, names = unnamed(gc("tee"))
    roles = panel_roles(bare)
    assert {roles[names[n]].kind for n in ("lsleeve", "rsleeve")} == {"sleeve"}
    assert {roles[names[n]].part for n in ("lsleeve", "rsleeve")} == {"arm_left", "arm_right"}
    assert roles[names["lsleeve"]].side == "outer"


@pytest.mark.parametrize("name, reason", [("tee", "garment's top"), ("shirt", "at height"),
                                          ("jumpsuit", "at height"), ("dress", "")])
def test_broken_placements_are_named_and_replaced(name, reason):
    body = load_body("female_thin")
    pattern = gc(name)
    mesh = mesh_pattern(pattern, triangles=600)
    bad = implausible_placements(pattern, mesh, body)
    assert bad and all(reason in b for b in bad)
    # hung from the neck, the file's placement is replaced whatever it is: nothing to warn of
    assert pattern.anchor == "neck"
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlacementWarning)
        x = place_on_body(pattern, mesh, body)
    # hung from the waist, it would have been kept: the warning names the panels
    waist = replace(pattern, meta={**pattern.meta, "anchor": "waist"})
    with pytest.warns(PlacementWarning, match="every panel is placed by patternfit") as caught:
        place_on_body(waist, mesh, body)
    assert bad[0].split(" (")[0] in str(caught[0].message)
    # the garment is now around the body, at its height
    assert 0.3 < np.median(x[:, 1]) < body.measurements["neck_base_height"]
    d, _ = body.distance_field(0.005).query(x)
    assert (d > 0).mean() > 0.99 and np.median(d) < 0.15


def test_a_plausible_imported_placement_is_kept():
    body = load_body("female_thin")
    pattern = build("skirt")
    mesh = mesh_pattern(pattern, triangles=600)
    placed = planes_placed(pattern, mesh, body)
    assert implausible_placements(placed, mesh, body) == []


@pytest.mark.parametrize("name", ["tee", "shirt", "built-in shirt"])
def test_shirts_and_tees_start_untangled(name):
    body = load_body("male_average")
    pattern = build("shirt") if name.startswith("built-in") else gc(name)
    mesh = mesh_pattern(pattern, triangles=1000)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlacementWarning)  # the files' own are not around it
        x = place_on_body(pattern, mesh, body)
    solver = GarmentSolver(mesh.vertices, mesh.triangles, mesh.grain[mesh.triangle_panel],
                           get_fabric("cotton_shirting"), seam_pairs=mesh.seam_pairs)
    assert solver.crossings(x) == 0
    d, _ = body.distance_field(0.005).query(x)
    assert d.min() > 0


def test_grain_line_says_which_way_is_up():
    # a skirt panel drafted lying on its side (turned a quarter), its grain along the turn:
    # placed as the upright one
    body = load_body("female_thin")
    pattern = build("skirt")
    turn = np.array([[0.0, -1.0], [1.0, 0.0]])
    mesh = mesh_pattern(pattern, triangles=600)
    upright = place_on_body(pattern, mesh, body)
    lying = replace(pattern, panels=tuple(
        replace(p, outline=replace(p.outline, edges=tuple(e.transformed(turn)
                                                          for e in p.outline.edges)),
                grainline=tuple(turn @ np.asarray(p.grainline))) for p in pattern.panels))
    mesh2 = mesh_pattern(lying, triangles=600)
    x = place_on_body(lying, mesh2, body)
    assert np.ptp(x[:, 1]) == pytest.approx(np.ptp(upright[:, 1]), abs=0.02)
    assert x[:, 1].max() == pytest.approx(upright[:, 1].max(), abs=0.02)


def drape_checked(pattern, body_name, triangles):
    from patternfit.sim.drape import drape
    body = load_body(body_name)
    mesh = mesh_pattern(pattern, triangles=triangles)
    d = drape(pattern, mesh, body)
    assert d.result.checks.passed, d.result.checks
    assert d.onbody.passed, d.onbody.reasons
    return d


@pytest.mark.parametrize("name, body", [("dress", "female_average"), ("tee", "male_average")])
def test_garmentcode_dress_and_tee_drape_with_every_check_passing(name, body):
    d = drape_checked(gc(name), body, 1000)
    assert abs(d.onbody.anchor_offset_mm) < 50  # hangs from the neck, not the waist


@pytest.mark.slow
@pytest.mark.parametrize("name, body", [
    ("shirt", "male_average"), ("hoodie", "male_average"), ("jumpsuit", "female_average")])
def test_garmentcode_garments_drape_with_every_check_passing(name, body):
    d = drape_checked(gc(name), body, 2000)
    assert abs(d.onbody.anchor_offset_mm) < 50


@pytest.mark.slow
@pytest.mark.parametrize("name, gender", [("shirt", "male"), ("gathered_skirt", "female")])
@pytest.mark.parametrize("build_", ["thin", "average", "heavy"])
def test_new_built_ins_drape_on_every_body_of_their_gender(name, gender, build_):
    drape_checked(build(name, "M"), f"{gender}_{build_}", 3000)


@pytest.mark.parametrize("name", ["dress", "jumpsuit"])
def test_panels_drawn_in_their_own_frames_are_stacked_by_their_seams(name):
    # GarmentCode draws each panel from its own origin: the skirt's waist and the bodice's
    # hem start at different heights; stacked, the two sides of every seam between body
    # panels meet in height
    from patternfit.sim.panel_frames import upright_frames
    pattern = gc(name)
    mesh = mesh_pattern(pattern, triangles=800)
    roles = panel_roles(pattern)
    flat = upright_frames(pattern, mesh, roles)
    body = {n for n, r in roles.items() if not r.part.startswith("arm")}
    before, after = [], []
    for k, s in enumerate(pattern.seams):
        if s.a.panel in body and s.b.panel in body and s.a.panel != s.b.panel:
            pairs = mesh.seam_pairs[mesh.seam_index == k]
            before.append(abs(np.median(np.diff(mesh.vertices[pairs, 1], axis=1))))
            after.append(abs(np.median(np.diff(flat[pairs, 1], axis=1))))
    assert max(before) > 0.1 and max(after) < 0.02


@pytest.mark.parametrize("name", ["dress", "jumpsuit", "tee", "shirt"])
def test_roles_of_garmentcode_garments_without_names(name):
    # panels called P1, P2... and no placement: parts from seams and shapes alone; the
    # front is the deeper neckline, and panels sewn to it take their sides from it
    pattern = gc(name)
    bare, names = unnamed(pattern)
    roles = panel_roles(bare)
    for old, (kind, part, side) in EXPECTED[name][1].items():
        got = roles[names[old]]
        assert (got.kind, got.part, got.side) == (kind, part, side), (old, got)
    assert bare.anchor == EXPECTED[name][0]


def test_a_hood_without_names_is_read_from_its_seams():
    # the hoodie's panels called P1, P2...: the two hood halves, sewn to each other along the
    # crown and by their lower edges into the front and back necklines, are a hood (they
    # read as a bodice before: their crown seam looked like shoulders)
    bare, names = unnamed(gc("hoodie"))
    roles = panel_roles(bare)
    for old, (kind, part, side) in EXPECTED["hoodie"][1].items():
        got = roles[names[old]]
        assert (got.kind, got.part, got.side) == (kind, part, side), (old, got)
    assert "neckline" in roles[names["hood_left"]].why
    assert bare.anchor == "neck"
    # the same with its seams listed the other way round: a half's hand came from its first
    # seam into a neckline, read as the front's before the sides were known, so a half sewn
    # first to the back was put on the other hand and the hood drapes backwards, twisted
    # across the chest (an outside test's hoodie, ϖ 105.9 %, passed)
    turned = panel_roles(replace(bare, seams=bare.seams[::-1]))
    for old, (kind, part, side) in EXPECTED["hoodie"][1].items():
        assert turned[names[old]].side == side, old


def test_a_garmentcode_hood_drawn_sideways_without_names():
    # GarmentCode draws a hood's halves in their own frames and turns them a quarter about
    # the body's height (rotation [0, +-90, 0]), each at x = +-(half the neck); names that
    # say nothing: the halves are a hood, each on the side its placement says
    import json
    doc = json.loads((GC / "hoodie_specification.json").read_text())
    panels = doc["pattern"]["panels"]
    rename = {"hood_left": "piece_5", "hood_right": "piece_6"}
    for old, new in rename.items():
        entry = panels.pop(old)
        x = 10.8 if old.endswith("left") else -10.8
        entry["translation"] = [x, 149.4, -11.6]
        entry["rotation"] = [0.0, 90.0 if x > 0 else -90.0, 0.0]
        panels[new] = entry
    for st in doc["pattern"]["stitches"]:
        for side in st[:2]:
            side["panel"] = rename.get(side["panel"], side["panel"])
    from patternfit.pattern.garmentcode import garmentcode_from_dict
    roles = panel_roles(garmentcode_from_dict(doc))
    assert (roles["piece_5"].kind, roles["piece_5"].side) == ("hood", "left")
    assert (roles["piece_6"].kind, roles["piece_6"].side) == ("hood", "right")
    assert roles["front"].kind == "bodice" and roles["lsleeve"].kind == "sleeve"


@pytest.mark.parametrize("name", ["dress", "jumpsuit", "tee", "shirt"])
def test_no_panel_of_a_garment_without_a_hood_reads_as_one(name):
    bare, _ = unnamed(gc(name))
    assert all(r.kind != "hood" for r in panel_roles(bare).values())


def test_a_garment_hung_from_the_neck_is_placed_here_whatever_its_file_says():
    """GarmentCode's flat panels, front and back 45 cm apart, were kept for a top whose
    height matched the body's neck: five of its garments (shirt, hoodie, jumpsuit, pencil
    and tiered dresses) then failed on female_average, straps pulled off the shoulders and
    underarms crossed, where they drape with every check passed from patternfit's own
    placement. A skirt's plausible placement is still kept."""
    body = load_body("female_average")
    for name, kept in (("skirt", True), ("dress", False)):
        pattern = build(name)
        mesh = mesh_pattern(pattern, triangles=600)
        placed = planes_placed(pattern, mesh, body)
        assert implausible_placements(placed, mesh, body) == []  # plausible by every measure
        x = place_on_body(placed, mesh, body)
        flat_planes = [np.ptp(x[mesh.panel_vertices(i), 2]) < 1e-6
                       for i, p in enumerate(placed.panels) if p.placement.explicit]
        assert flat_planes and all(flat_planes) == kept, name


@pytest.mark.parametrize("per_side", [1, 2, 4])
def test_the_gores_of_one_side_are_placed_side_by_side(per_side):
    """GarmentCodeData's eight-gored skirt had its four front gores centred one on another,
    and the four back ones: sewn together through each other, the drape failed with 4,765
    crossed pairs. A side's gores now lie in a row in seam order round the body."""
    body = load_body("female_average")
    pattern = gored_skirt(per_side)
    mesh = mesh_pattern(pattern, triangles=300 * per_side)
    x = place_on_body(pattern, mesh, body)
    solver = GarmentSolver(mesh.vertices, mesh.triangles, mesh.grain[mesh.triangle_panel],
                           get_fabric("cotton_shirting"), seam_pairs=mesh.seam_pairs)
    assert solver.crossings(x) == 0
    # each gore's own angle round the body, its neighbours' apart
    centre = np.asarray(body.landmarks["torso_axis"])[:, [0, 2]].mean(axis=0)
    angles = []
    for i in range(len(pattern.panels)):
        c = x[mesh.panel_vertices(i)][:, [0, 2]].mean(axis=0) - centre
        angles.append(np.degrees(np.arctan2(c[0], c[1])))
    front = np.array(angles[:per_side])
    assert np.all(np.abs(front) < 90)  # on the front
    if per_side > 1:  # in seam order round the body, not centred one on another
        steps = np.diff(front)
        assert np.all(steps > 10) or np.all(steps < -10), front


def _edge_strain(mesh, x) -> np.ndarray:
    """Each triangle edge's length at ``x`` over its flat length, minus 1."""
    e = np.concatenate([mesh.triangles[:, [0, 1]], mesh.triangles[:, [1, 2]],
                        mesh.triangles[:, [2, 0]]])
    flat = np.linalg.norm(np.diff(mesh.vertices[e], axis=1)[:, 0], axis=1)
    return np.linalg.norm(np.diff(x[e], axis=1)[:, 0], axis=1) / flat - 1.0


@pytest.mark.parametrize("per_side, waist, hem", [(4, 0.10, 0.70), (2, 0.18, 0.90)])
def test_strongly_flared_gores_start_on_a_cone(per_side, waist, hem):
    """GarmentCodeData's rand_04EGGDPALT has eight gores 9 cm wide at the waist and 75 cm at
    the hem: too slanted for a row, each side's gores started centred one on another (30,714
    crossed pairs) and the drape failed tangled. A side's flared gores are now put seam to
    seam, a sector of a ring, and rolled onto a cone opening downwards round the body."""
    body = load_body("female_average")
    pattern = gored_skirt(per_side, waist, hem, 0.9)
    mesh = mesh_pattern(pattern, triangles=300 * per_side)
    x = place_on_body(pattern, mesh, body)
    solver = GarmentSolver(mesh.vertices, mesh.triangles, mesh.grain[mesh.triangle_panel],
                           get_fabric("cotton_shirting"), seam_pairs=mesh.seam_pairs)
    assert solver.crossings(x) == 0
    assert body.distance_field(0.005).query(x)[0].min() > 0.0
    strain = np.abs(_edge_strain(mesh, x))  # sheared at the top, where the cone is held wider
    assert np.median(strain) < 0.05 and np.percentile(strain, 90) < 0.1
    centre = np.asarray(body.landmarks["torso_axis"])[:, [0, 2]].mean(axis=0)
    radial = np.hypot(*(x[:, [0, 2]] - centre).T)
    top, low = x[:, 1] > x[:, 1].max() - 0.02, x[:, 1] < x[:, 1].min() + 0.02
    assert radial[low].min() > radial[top].max() + 0.2  # the hem flares out
    angles = [np.degrees(np.arctan2(*(x[mesh.panel_vertices(i)][:, [0, 2]].mean(axis=0)
                                      - centre))) for i in range(per_side)]
    steps = np.diff(angles)
    assert np.all(np.abs(angles) < 90) and (np.all(steps > 10) or np.all(steps < -10))


def test_strongly_flared_gores_drape_with_every_check_passing():
    """The flared gores' drape comes to rest: started on their cone, and with Newton taking
    over from L-BFGS by half the iterations (``SolverSettings.newton_after``: the creeping
    hem kept L-BFGS from ever handing over, 5,000 iterations at a residual of 1-10)."""
    drape_checked(gored_skirt(4, 0.10, 0.70, 0.9), "female_average", 1500)


@pytest.mark.parametrize("garment", ["shirt", "skirt"])
def test_a_stated_anchor_its_panels_deny_is_said(garment):
    """A tank top stated as hung from the waist was worn as a skirt and passed; the stated
    anchor is followed, with a warning naming what the panels say."""
    body = load_body("female_average")
    pattern = build(garment, "M")
    mesh = mesh_pattern(pattern, triangles=400)
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlacementWarning)  # the built-in: no warning
        place_on_body(pattern, mesh, body)
    other = "waist" if pattern.anchor == "neck" else "neck"
    stated = replace(pattern, meta={**pattern.meta, "anchor": other})
    with pytest.warns(PlacementWarning, match=f"hung from the {other}, as meta.anchor says, "
                                              f"though its panels read as hung from the "
                                              f"{pattern.anchor}"):
        placed = place_on_body(stated, mesh, body)
    # a garment with shoulders stated as hung from the waist is not where it is worn, and
    # fails wherever it lands (a dress so stated passed as an ankle-long skirt, its bodice
    # round the hips, in the CLI, the batch, the studio, and was corrected); a garment
    # without them stated as hung from the neck (a halter) is judged as it drapes
    said = on_body_checks(stated, mesh, body, placed).reasons
    assert any("check meta.anchor" in r for r in said) == (other == "waist"), said


@pytest.mark.parametrize("name", ["skirt", "piece1"])
def test_a_skirt_in_one_piece_goes_round_the_body(name):
    """A one-piece skirt, 95 x 50 cm sewn up its back: unnamed it was read as a leg 0.95 m
    long (the tube's width taken for its length) and fell off the left leg; named, it was
    rolled over the front alone and its sewing dragged both sides 0.93 m round the back
    (its top rose to the bust, or it fell through the floor). A tube at least
    ``TORSO_TUBE`` round goes round the body, its sides meeting behind."""
    from patternfit.pattern import Edge, Loop, Panel, Pattern, Seam, SeamSide

    w, h = 0.95, 0.50
    pts = [(0, 0), (w, 0), (w, h), (0, h)]
    names = ("hem", "right", "waist", "left")
    panel = Panel(name, Loop("outline", tuple(Edge.line(n, pts[k], pts[(k + 1) % 4])
                                              for k, n in enumerate(names))))
    tube = Pattern("tube", (panel,), (Seam("back", SeamSide(name, "right"),
                                           SeamSide(name, "left"), reverse=True),))
    role = panel_roles(tube)[name]
    assert (role.kind, role.part, role.tube) == ("skirt", "torso", True), role
    assert tube.anchor == "waist"
    body = load_body("female_average")
    mesh = mesh_pattern(tube, triangles=400)
    x = place_on_body(tube, mesh, body)
    centre = np.asarray(body.landmarks["torso_axis"])[:, [0, 2]].mean(axis=0)
    angle = np.degrees(np.arctan2(x[:, 0] - centre[0], x[:, 2] - centre[1]))
    assert angle.min() < -120 and angle.max() > 120  # round to the back both ways
    left, right = (mesh.boundary_vertices[mesh.boundary_edge == mesh.edge_names.index(
        (name, side))] for side in ("left", "right"))
    gap = np.linalg.norm(x[left].mean(axis=0) - x[right].mean(axis=0))
    assert gap < 0.35, gap  # the seam's sides start behind, the ring's rest apart
