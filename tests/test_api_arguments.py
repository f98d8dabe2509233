"""The public API refuses a bad argument with a ValueError naming it, before any work: a
wrong value used to cost a whole drape, then fail deep inside (TypeError, AttributeError,
IndexError after pattern.json was written)."""

import numpy as np
import pytest

import patternfit.api as api
from patternfit.mesh.store import load_garment


@pytest.mark.parametrize("call, name", [
    (lambda: api.drape_and_evaluate("skirt", tight="x"), "tight"),
    (lambda: api.drape_and_evaluate("skirt", loose=float("nan")), "loose"),
    (lambda: api.drape_and_evaluate("skirt", verdict_rules=5), "verdict_rules"),
    (lambda: api.drape_and_evaluate("skirt", settings={"time_limit": 5}), "settings"),
    (lambda: api.drape_and_evaluate("skirt", progress=5), "progress"),
    (lambda: api.read_pattern("skirt", size=5), "size"),
    (lambda: api.design_session("skirt", threshold=True), "threshold"),
    (lambda: api.design_session("skirt", relax="x"), "relax"),
    (lambda: api.place_and_evaluate("skirt", triangles=300, loose=True), "loose"),
    (lambda: api.suggest_seams("skirt", min_score=float("nan")), "min_score"),
    (lambda: api.accept_seams(api.read_pattern("skirt"), None), "suggestions"),
    (lambda: api.accept_seams(None, []), "pattern"),
    (lambda: api.read_bodies(""), "bodies"),
    # a wrong object or an empty name, which was read as a file named by its repr or as "."
    (lambda: api.read_pattern(""), "pattern"),
    (lambda: api.mesh_garment(api.read_body("female_average")), "pattern"),
    (lambda: api.read_body(api.read_pattern("skirt")), "body"),
    (lambda: api.read_fabric(api.read_pattern("skirt")), "fabric"),
    (lambda: api.describe_fabric(api.read_body("female_average")), "fabric"),
    (lambda: api.design_session("skirt", "female_average", api.read_body("female_average")),
     "fabric"),
    (lambda: api.read_pattern("skirt", size=""), "size"),
    (lambda: api.drafted_too_small("skirt", size=5), "size"),
    (lambda: api.read_body("female_average", units=["cm"]), "units"),
    # units of a built-in body were ignored without a word
    (lambda: api.drape_and_evaluate("skirt", "female_average", units="cm"), "units"),
    (lambda: api.verdict_rules(stretch_limit=True), "stretch_limit"),
    (lambda: api.verdict_rules(stretch_limit="x"), "stretch_limit"),
    (lambda: api.verdict_rules(style=["fitted"]), "style"),
    (lambda: api.fabric_test("cusick", seeds=-1), "seeds"),
    (lambda: api.write_fabric_test_picture(None, "p.png"), "result"),
])
def test_a_bad_argument_is_named_before_any_work(call, name, monkeypatch):
    monkeypatch.setattr(api, "mesh_pattern", lambda *a, **k: pytest.fail("work started"))
    with pytest.raises(ValueError, match=rf"^{name}: "):
        call()


def test_correct_design_checks_its_options_before_the_first_drape(tmp_path):
    session = api.design_session("skirt", threshold=np.float32(0.9), triangles=300)
    assert session.threshold == pytest.approx(0.9)  # a NumPy number is a number
    for options, name in (({"threshold": "x"}, "threshold"), ({"max_iterations": -1},
                          "max_iterations"), ({"verdict_rules": 5}, "verdict_rules")):
        with pytest.raises(ValueError, match=rf"^{name}: "):
            api.correct_design(session, tmp_path / "out", **options)
    assert not (tmp_path / "out").exists() and session.state.positions is None


@pytest.mark.parametrize("call, name", [
    (lambda p, m, b: api.check_sewn(None), "pattern"),
    (lambda p, m, b: api.check_sewn("skirt"), "pattern"),
    (lambda p, m, b: api.seam_table(None), "pattern"),
    (lambda p, m, b: api.write_pattern(None, "x.json"), "pattern"),
    (lambda p, m, b: api.write_pattern(p, None), "out"),
    (lambda p, m, b: api.remove_seam(None, "x"), "pattern"),
    (lambda p, m, b: api.set_seam_ease("skirt", "x", 0.01), "pattern"),
    (lambda p, m, b: api.check_bulk("cotton"), "fabric"),
    (lambda p, m, b: api.with_distance_field(p), "body"),
    (lambda p, m, b: api.placed_fitting_ratio(None), "session"),
    (lambda p, m, b: api.correct_design(None, "out"), "session"),
    (lambda p, m, b: api.evaluate_saved(None), "folder"),
    (lambda p, m, b: api.evaluate_drape(p, np.zeros((3, 3))), "mesh"),
    (lambda p, m, b: api.evaluate_drape(m, np.zeros((m.n_vertices, 3), complex)), "positions"),
    (lambda p, m, b: api.judge_state(p, m, np.zeros((m.n_vertices, 3)), None, b,
                                     api.read_fabric("cotton")), "fit"),
    (lambda p, m, b: api.save_garment(None, p, m), "folder"),
    (lambda p, m, b: api.save_garment("g", p, None), "mesh"),
])
def test_a_wrong_object_is_named_not_an_attribute_error(call, name):
    p = api.read_pattern("skirt")
    m = api.mesh_garment(p, triangles=200)
    with pytest.raises(ValueError, match=rf"^{name}: "):
        call(p, m, api.read_body("female_average"))


def test_seam_table_takes_a_name_as_every_pattern_argument_does():
    assert api.seam_table("skirt") == api.seam_table(api.read_pattern("skirt"))


def test_a_fractional_triangle_count_is_refused():
    with pytest.raises(ValueError, match="^triangles: must be a whole number"):
        api.mesh_garment("skirt", triangles=300.5)


def test_a_mistyped_option_names_the_public_function():
    with pytest.raises(TypeError, match=r"mesh_garment\(\) got an unexpected keyword "
                                        r"argument 'foo' \(options: min_angle"):
        api.mesh_garment("skirt", triangles=200, foo=1)
    with pytest.raises(TypeError, match=r"fabric_test\(\) .* 'lenght' .*length"):
        api.fabric_test("strip", lenght=0.2)


def test_save_garment_refuses_a_mesh_of_another_pattern(tmp_path):
    """A skirt's pattern.json beside a dress's mesh.npz was written, and refused only when
    read back."""
    skirt = api.read_pattern("skirt")
    with pytest.raises(ValueError, match="^mesh: not a mesh of this pattern"):
        api.save_garment(tmp_path / "g", skirt, api.mesh_garment("dress", triangles=300))
    assert not (tmp_path / "g").exists()
    (tmp_path / "file").write_text("mine")
    with pytest.raises(api.InputError, match="is a file"):
        api.save_garment(tmp_path / "file", skirt, api.mesh_garment(skirt, triangles=300))
    assert (tmp_path / "file").read_text() == "mine"
    mesh = api.mesh_garment(skirt, triangles=300)
    pattern, back, x = load_garment(api.save_garment(tmp_path / "ok", skirt, mesh))
    assert pattern == skirt and back.n_triangles == mesh.n_triangles and x is None


def test_units_go_to_body_mesh_files_only(tmp_path):
    """A built-in body's units were ignored without a word; in a list, they are the files'."""
    from patternfit.body.mesh_io import save_body_mesh

    save_body_mesh(api.read_body("female_thin"), tmp_path / "thin.obj")
    spec = f"female_average,{tmp_path / 'thin.obj'}"
    assert [b.name for b in api.read_bodies(spec, units="m")] == ["female_average", "thin"]
    for call in (lambda: api.read_bodies("female_average", units="cm"),
                 lambda: api.read_body("female_average", units="cm")):
        with pytest.raises(ValueError, match="^units: set for .*body mesh file"):
            call()
