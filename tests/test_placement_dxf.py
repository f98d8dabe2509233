"""A DXF round trip keeps where every built-in garment hangs from (issue 20, item 4): a
round trip of the built-in dress and coat once slid them to the hips, their anchor kept only
in ``meta``, which a DXF does not carry. The round trip is the user's:
``patternfit convert X.json X.dxf``, then the DXF read back (with its side file)."""

import json
import warnings

import numpy as np
import pytest
from typer.testing import CliRunner

from patternfit import api
from patternfit.body.builtin import load_body
from patternfit.cli.main import app
from patternfit.mesh import mesh_pattern
from patternfit.pattern.dxf import load_dxf
from patternfit.pattern.formats import load_any_pattern
from patternfit.pattern.library import GARMENTS, build
from patternfit.pattern.roles import garment_anchor, panel_roles
from patternfit.sim.drape import drape
from patternfit.sim.fabrics import get_fabric
from patternfit.sim.placement import place_on_body
from patternfit.sim.solver import GarmentSolver
from test_dxf_aama import SIZES, accumark, half_front, skirt_piece, sleeve

BODY = {"female": "female_average", "male": "male_average"}


def round_trip(name, tmp_path):
    src = tmp_path / f"{name}.json"
    assert CliRunner().invoke(app, ["convert", name, str(src)]).exit_code == 0
    dxf = tmp_path / f"{name}.dxf"
    result = CliRunner().invoke(app, ["convert", str(src), str(dxf)])
    assert result.exit_code == 0, result.output
    return load_any_pattern(dxf)


@pytest.mark.parametrize("name", list(GARMENTS))
def test_a_dxf_round_trip_keeps_the_anchor(name, tmp_path):
    back = round_trip(name, tmp_path)
    # the stated anchor goes with the side file; the panels alone (a DXF without it, as a
    # CAD tool writes one) tell the same
    assert back.meta["anchor"] == build(name).meta["anchor"]
    assert garment_anchor(back) == back.anchor == build(name).anchor == GARMENTS[name][3]


def _drapes_on_the_body(name, tmp_path):
    back = round_trip(name, tmp_path)
    body = load_body(BODY[GARMENTS[name][1]])
    mesh = mesh_pattern(back, triangles=1200)
    d = drape(back, mesh, body)
    assert d.result.checks.passed, d.result.checks
    assert d.onbody.passed, d.onbody.reasons


@pytest.mark.parametrize("name", ["dress", "coat"])
def test_the_dress_and_coat_drape_at_the_neck_after_a_dxf_round_trip(name, tmp_path):
    _drapes_on_the_body(name, tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("name", [n for n in GARMENTS if n not in ("dress", "coat")])
def test_every_built_in_drapes_after_a_dxf_round_trip_as_it_did_before(name, tmp_path):
    """The round trip changes nothing of where the garment hangs: the same checks pass, the
    same on-body verdict, the top within 1 cm of where the original's is. (Not whether size
    M fits the body: the gathered skirt's band, 78 cm round, sits 6-11 cm below
    female_average's 68.5 cm waist by the mesh, past the 10 cm limit at 1,200 triangles,
    before the round trip as after it.)"""
    back = round_trip(name, tmp_path)
    body = load_body(BODY[GARMENTS[name][1]])
    after = drape(back, mesh_pattern(back, triangles=1200), body)
    before = drape(build(name), mesh_pattern(build(name), triangles=1200), body)
    assert after.result.checks.passed, after.result.checks
    assert after.onbody.passed == before.onbody.passed, (after.onbody.reasons,
                                                         before.onbody.reasons)
    assert after.onbody.anchor_offset_mm == pytest.approx(before.onbody.anchor_offset_mm,
                                                          abs=10.0)


# -- other tools' DXF files, built to the AAMA layer rules (tests/test_dxf_aama.py's writer) -----
def _placed(path, size):
    # as a user would: the DXF has no seams, the suggested ones are accepted
    pattern = load_dxf(path, size=size)
    pattern = api.accept_seams(pattern, api.suggest_seams(pattern))
    body = load_body("female_average")
    mesh = mesh_pattern(pattern, triangles=800)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing imported to replace: no warning
        x = place_on_body(pattern, mesh, body)
    centre = np.asarray(body.landmarks["torso_axis"]).mean(axis=0)
    at = {p.name: x[mesh.panel_vertices(i)] - centre for i, p in enumerate(pattern.panels)}
    return pattern, panel_roles(pattern), body, mesh, x, at


@pytest.mark.parametrize("size", ["34", "38"])
def test_an_accumark_top_with_folds_pairs_and_sizes_is_placed_by_its_names(tmp_path, size):
    blocks = []
    for s, g in SIZES.items():
        blocks += [{"name": "FRONT", "size": s, "runs": half_front(g), "fold": ((0, 0), (0, 410))},
                   {"name": "BACK", "size": s, "runs": half_front(g), "fold": ((0, 0), (0, 410))},
                   {"name": "SLEEVE", "size": s, "quantity": 2, "runs": sleeve(g)}]
    path = accumark(tmp_path / "top.dxf", blocks, sample="36", scale=25.4)
    pattern, roles, body, mesh, x, at = _placed(path, size)
    assert {n: (r.kind, r.part, r.side) for n, r in roles.items()} == {
        "FRONT": ("bodice", "torso", "front"), "BACK": ("bodice", "torso", "back"),
        "SLEEVE_L": ("sleeve", "arm_left", "outer"), "SLEEVE_R": ("sleeve", "arm_right", "outer")}
    assert pattern.anchor == "neck"
    assert np.median(at["FRONT"][:, 2]) > 0 > np.median(at["BACK"][:, 2])
    assert np.median(at["SLEEVE_L"][:, 0]) > 0.15 and np.median(at["SLEEVE_R"][:, 0]) < -0.15
    top = max(float(x[mesh.panel_vertices(i), 1].max()) for i, p in enumerate(pattern.panels)
              if p.name in ("FRONT", "BACK"))
    assert top == pytest.approx(body.measurements["neck_base_height"] + 0.01, abs=0.07)
    solver = GarmentSolver(mesh.vertices, mesh.triangles, mesh.grain[mesh.triangle_panel],
                           get_fabric("cotton_shirting"), seam_pairs=mesh.seam_pairs)
    assert solver.crossings(x) == 0


@pytest.mark.parametrize("grain", [((100, 100), (100, 300)), ((100, 300), (100, 100))])
def test_an_accumark_skirt_with_allowance_hangs_from_the_waist(tmp_path, grain):
    """Its grain line written either way (a LINE is an axis: which end comes first is the
    CAD tool's choice; drawn from the waist down, the skirt was hung upside down, its hem
    at her waist, and passed as a fit)."""
    blocks = []
    for name in ("FRONT SKIRT", "BACK SKIRT"):
        piece = skirt_piece()
        piece["name"] = name
        piece["grain"] = grain
        blocks.append(piece)
    path = accumark(tmp_path / "skirt.dxf", blocks, scale=1.0)
    pattern, roles, body, mesh, x, at = _placed(path, None)
    assert [p.cut_line is not None for p in pattern.panels] == [True, True]  # allowance kept
    assert {n: (r.kind, r.side) for n, r in roles.items()} == {
        "FRONT SKIRT": ("skirt", "front"), "BACK SKIRT": ("skirt", "back")}
    assert pattern.anchor == "waist"
    # the sew line is what is placed: its top 1 cm above the waist
    assert float(x[:, 1].max()) == pytest.approx(body.measurements["waist_height"] + 0.01,
                                                 abs=0.02)
    assert np.median(at["FRONT SKIRT"][:, 2]) > 0 > np.median(at["BACK SKIRT"][:, 2])
    # the waist (the top of the pieces as drawn) at the top: upright, not upside down
    assert np.corrcoef(mesh.vertices[:, 1], x[:, 1])[0, 1] > 0.9


@pytest.mark.parametrize("grain, warned", [(((100, 200), (300, 200)), True),
                                           (((300, 230), (100, 200)), True),
                                           (((100, 100), (140, 300)), False)])
def test_a_grain_line_lying_on_its_side_is_warned(tmp_path, grain, warned):
    """AccuMark draws many pieces on their side: a horizontal grain line says nothing of
    which end is up, and the order of its two points decided it without a word (a real
    AccuMark half back hung with its hem up, or not, by which point came first)."""
    piece = skirt_piece()
    piece["grain"] = grain
    pattern = load_any_pattern(accumark(tmp_path / "s.dxf", [piece], scale=1.0))
    said = [w for w in pattern.meta.get("warnings", []) if "grain line within 20°" in w]
    assert bool(said) == warned
    if warned:
        assert f"panel '{piece['name']}'" in said[0] and "side file" in said[0]


def test_a_sideways_grain_set_in_the_side_file_or_a_band_is_not_warned(tmp_path):
    """The warning stayed after the side file gave the grain line it asks for, and a
    waistband drawn lengthwise (its up taken from its shape) was warned too."""
    piece = skirt_piece()
    piece["grain"] = ((100, 200), (300, 200))
    band = {"name": "WAISTBAND", "grain": ((100, 20), (600, 20)),
            "runs": [np.array([(0, 0), (700, 0)]), np.array([(700, 0), (700, 40)]),
                     np.array([(700, 40), (0, 40)]), np.array([(0, 40), (0, 0)])]}
    path = accumark(tmp_path / "s.dxf", [piece, band], scale=1.0)
    said = [w for w in load_any_pattern(path).meta.get("warnings", [])
            if "grain line within 20°" in w]
    assert len(said) == 1 and "panel 'SKIRT'" in said[0]
    (tmp_path / "s.seams.json").write_text(json.dumps(
        {"format": "patternfit-dxf-sidecar", "panels": {"SKIRT": {"grainline": [0, 1]}}}))
    pattern = load_any_pattern(path)
    assert pattern.panel("SKIRT").grainline == (0.0, 1.0)
    assert not [w for w in pattern.meta.get("warnings", []) if "grain line within" in w]


def test_every_command_that_reads_a_pattern_says_its_warnings(tmp_path):
    """convert and drape printed what the reader noticed; mesh and seams said nothing,
    even with --json."""
    piece = skirt_piece()
    piece["grain"] = ((100, 200), (300, 200))
    path = accumark(tmp_path / "s.dxf", [piece], scale=1.0)
    runner = CliRunner()
    for args in (["mesh", str(path), "--triangles", "200", "--out", str(tmp_path / "m")],
                 ["seams", str(path)]):
        said = runner.invoke(app, args)
        assert said.exit_code == 0, said.output
        assert "warning:" in said.output and "grain line within 20°" in said.output
        as_json = json.loads(runner.invoke(app, [*args, "--json"]).output)
        assert any("grain line within 20°" in w for w in as_json["warnings"])
