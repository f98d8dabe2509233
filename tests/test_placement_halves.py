"""Placement of garments drafted as GarmentCode drafts its bodices: a left and a right half
of the front and of the back, sewn along the centre lines, every panel drawn as seen from the
front of the body (so the back halves run clockwise: their outside faces away), each in its
own frame from the centre line outwards. Written here the way GarmentCode writes such a file
(centimetres, edges by vertex index with relative curvature, stitches by edge index, the
back halves' rotation zero)."""

import warnings

import numpy as np
import pytest

from patternfit.body.builtin import load_body
from patternfit.mesh import mesh_pattern
from patternfit.pattern.garmentcode import garmentcode_from_dict
from patternfit.pattern.roles import panel_roles
from patternfit.sim.fabrics import get_fabric
from patternfit.sim.panel_frames import PlacementWarning
from patternfit.sim.placement import place_on_body
from patternfit.sim.solver import GarmentSolver

ARMHOLE = {"type": "cubic", "params": [[0.3, 0.25], [0.7, 0.1]]}
NECK = {"type": "quadratic", "params": [[0.5, 0.3]]}


def half(points, curved, name, z):
    edges = []
    for k in range(len(points)):
        e = {"endpoints": [k, (k + 1) % len(points)]}
        if k in curved:
            e["curvature"] = curved[k]
        edges.append(e)
    return name, {"translation": [0.0, 0.0, z], "rotation": [0.0, 0.0, 0.0],
                  "vertices": points, "edges": edges, "label": "body"}


def vest(y=0.0, left=25):
    """A sleeveless top in four halves; its panels at height ``y`` [cm] (0: at the feet,
    where nothing keeps the file's placement), its left halves ``left`` cm wide at the hem
    (the right ones 25)."""
    panels = dict([
        # fronts counter-clockwise: hem, side, armhole, shoulder, neckline, centre front
        half([[0, 0], [left, 0], [left, 30], [15, 45], [8, 47], [0, 38]],
             {2: ARMHOLE, 4: NECK}, "left_ftorso", 25.0),
        half([[0, 0], [0, 38], [-8, 47], [-15, 45], [-25, 30], [-25, 0]],
             {1: NECK, 3: ARMHOLE}, "right_ftorso", 25.0),
        # backs clockwise: centre back, neckline, shoulder, armhole, side, hem
        half([[0, 0], [0, 42], [8, 47], [15, 45], [left, 30], [left, 0]],
             {1: NECK, 3: ARMHOLE}, "left_btorso", -20.0),
        half([[0, 0], [-25, 0], [-25, 30], [-15, 45], [-8, 47], [0, 42]],
             {2: ARMHOLE, 4: NECK}, "right_btorso", -20.0)])
    for p in panels.values():
        p["translation"][1] = y
    pairs = [("right_ftorso", 0, "left_ftorso", 5), ("right_btorso", 5, "left_btorso", 0),
             ("left_ftorso", 1, "left_btorso", 4), ("left_ftorso", 3, "left_btorso", 2),
             ("right_ftorso", 4, "right_btorso", 1), ("right_ftorso", 2, "right_btorso", 3)]
    stitches = [[{"panel": a, "edge": i}, {"panel": b, "edge": j}] for a, i, b, j in pairs]
    return garmentcode_from_dict({
        "pattern": {"panels": panels, "stitches": stitches},
        "parameters": {}, "properties": {"curvature_coords": "relative",
                                         "units_in_meter": 100}}, name="vest")


@pytest.fixture(scope="module")
def placed():
    body = load_body("male_average")
    pattern = vest()
    mesh = mesh_pattern(pattern, triangles=800)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlacementWarning)  # at the feet: replaced
        x = place_on_body(pattern, mesh, body)
    return pattern, mesh, body, x


def test_the_halves_read_as_bodices_with_their_sides():
    roles = panel_roles(vest())
    assert {n: (r.kind, r.side) for n, r in roles.items()} == {
        "left_ftorso": ("bodice", "front"), "right_ftorso": ("bodice", "front"),
        "left_btorso": ("bodice", "back"), "right_btorso": ("bodice", "back")}


def test_halves_lie_side_by_side_each_on_its_own_side(placed):
    pattern, mesh, body, x = placed
    centre = float(np.mean(np.asarray(body.landmarks["torso_axis"])[:, 0]))
    for i, p in enumerate(pattern.panels):
        xs = x[mesh.panel_vertices(i), 0] - centre
        # the body faces +z: its left is +x, front and back alike
        if p.name.startswith("left"):
            assert np.percentile(xs, 5) > -0.02, p.name
        else:
            assert np.percentile(xs, 95) < 0.02, p.name


def test_every_seam_starts_short_and_nothing_crosses(placed):
    pattern, mesh, body, x = placed
    # the side seams join a front half to the back half on the same side of the body: a back
    # half placed as drawn (seen from inside) puts its side seam on the other side
    gaps = np.linalg.norm(x[mesh.seam_pairs[:, 0]] - x[mesh.seam_pairs[:, 1]], axis=1)
    assert gaps.max() < 0.45
    for k, s in enumerate(pattern.seams):
        if {s.a.panel[:4], s.b.panel[:4]} in ({"left"}, {"righ"}):
            sides = x[mesh.seam_pairs[mesh.seam_index == k]]
            assert np.all(np.sign(sides[:, 0, 0]) == np.sign(sides[:, 1, 0]))
    solver = GarmentSolver(mesh.vertices, mesh.triangles, mesh.grain[mesh.triangle_panel],
                           get_fabric("cotton_shirting"), seam_pairs=mesh.seam_pairs)
    assert solver.crossings(x) == 0


def lapelled(right_wrong: bool):
    """The vest with a lapel on the left front: a triangle sewn to the front's neckline,
    with GarmentCode's ``right_wrong`` (wrong side out: it folds over) or without."""
    import json
    from patternfit.pattern.garmentcode import garmentcode_to_dict
    doc = garmentcode_to_dict(vest())
    for entry in doc["pattern"]["panels"].values():
        entry.pop("patternfit_placement", None)
    doc.pop("patternfit_seam_names", None)
    neck = vest().panel("left_ftorso").edges()["e4"]
    a, b = (np.asarray(p) * 100 for p in (neck.start, neck.end))
    doc["pattern"]["panels"]["left_lapel"] = {
        "translation": [0.0, 0.0, 30.0], "rotation": [0.0, 0.0, 0.0],
        "vertices": [b.tolist(), a.tolist(), (a + [0.0, 12.0]).tolist()],
        "edges": [{"endpoints": [0, 1], "curvature": {"type": "quadratic",
                                                        "params": [[0.5, -0.3]]}},
                  {"endpoints": [1, 2]}, {"endpoints": [2, 0]}]}
    stitch = [{"panel": "left_ftorso", "edge": 4}, {"panel": "left_lapel", "edge": 0}]
    if right_wrong:
        stitch.append("right_wrong")
    doc["pattern"]["stitches"].append(stitch)
    return garmentcode_from_dict(json.loads(json.dumps(doc)), name="lapelled")


@pytest.mark.parametrize("right_wrong", [True, False])
def test_a_panel_sewn_wrong_side_out_is_turned_over(right_wrong):
    from patternfit.sim.panel_frames import _turned_over
    pattern = lapelled(right_wrong)
    turned = {pattern.panels[i].name for i in _turned_over(pattern, panel_roles(pattern))}
    # the back halves run clockwise (seen from inside) whatever the lapel
    assert {"left_btorso", "right_btorso"} <= turned
    assert ("left_lapel" in turned) == right_wrong


def test_a_dxf_round_trip_keeps_which_panels_are_turned_over(tmp_path):
    # a DXF does not say the file came from GarmentCode: the seams do (the back halves are
    # sewn end to start to the fronts although they run the other way round)
    from patternfit.pattern.dxf import load_dxf, save_dxf
    from patternfit.sim.panel_frames import _turned_over
    pattern = lapelled(True)
    back = load_dxf(save_dxf(pattern, tmp_path / "vest.dxf"))
    names = {n: {p.panels[i].name for i in _turned_over(p, panel_roles(p))}
             for n, p in (("file", pattern), ("dxf", back))}
    assert names["file"] == names["dxf"] == {"left_btorso", "right_btorso", "left_lapel"}


@pytest.mark.parametrize("left", [15, 25, 35])
def test_the_centre_seam_is_on_the_middle_however_wide_each_half(left):
    """Halves of unequal width: laid as a row, the centre front and back seams were put
    where the row's middle fell (up to 5.5 cm off the body's centre), not on the centre."""
    body = load_body("male_average")
    pattern = vest(left=left)
    mesh = mesh_pattern(pattern, triangles=800)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlacementWarning)
        x = place_on_body(pattern, mesh, body)
    centre = np.asarray(body.landmarks["torso_axis"])[:, [0, 2]].mean(axis=0)
    for k, seam in enumerate(pattern.seams[:2]):  # centre front, centre back
        pairs = mesh.seam_pairs[mesh.seam_index == k]
        assert abs(x[pairs].reshape(-1, 3)[:, 0].mean() - centre[0]) < 0.002, seam.name
