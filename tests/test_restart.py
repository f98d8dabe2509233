"""A drape continued from its own rest does not move: in memory (the solver that made it)
and from its saved garment folder, whose ``contact.npz`` keeps what positions alone cannot
give back (each contact's stiffening, the friction anchors, the self pairs); a damaged or
foreign ``contact.npz`` is refused naming the file and the array."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from hypothesis.extra import numpy as hnp

from patternfit import api
from patternfit.errors import GarmentFileError, InputError
from patternfit.mesh.store import CONTACT, load_contact, save_garment
from patternfit.sim.outer_updates import saved_contact_scale
from patternfit.sim.settings import SolverSettings
from patternfit.sim.state import SAVED, ContactState, SavedStateError
from patternfit.sim.total_energy import distance, edge_points

#: a heavy man in a coat: contacts at the shoulders stiffened up to x64, self pairs held by
#: the Newton phase (a restart from the positions alone moved 4.4 mm over 105 iterations)
GARMENT, BODY, TRIANGLES = "coat", "male_heavy", 1500


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    """The coat draped and written as ``patternfit drape --out`` writes it: (outcome,
    garment folder)."""
    out = tmp_path_factory.mktemp("coat")
    outcome = api.drape_and_evaluate(GARMENT, BODY, "cotton", triangles=TRIANGLES)
    outcome.write(out, pictures=False)
    return outcome, out / "garment"


def test_the_drape_is_at_rest_with_stiffened_contacts(saved):
    outcome, folder = saved
    d = outcome.drape
    assert d.checks.equilibrium, d.reasons
    assert (d.solver.state.contact_scale > 1).sum() >= 5
    assert (folder / CONTACT).is_file()


def test_a_warm_start_from_a_reported_rest_does_not_move(saved):
    outcome, _ = saved
    d = outcome.drape
    x = d.result.x.copy()
    again = d.solver.solve(x)
    assert again.iterations == 0, again.stop_reason
    assert np.array_equal(again.x, x)
    assert again.checks.equilibrium


def test_a_drape_started_from_its_folder_continues_it(saved):
    outcome, folder = saved
    again = api.drape_and_evaluate(GARMENT, BODY, "cotton", triangles=TRIANGLES, start=folder)
    assert again.drape.timing["start"] == "saved"
    assert again.drape.result.iterations == 0, again.drape.result.stop_reason
    assert np.abs(again.positions - outcome.positions).max() == 0.0
    assert again.drape.checks.residual_rms == pytest.approx(
        outcome.drape.checks.residual_rms, rel=1e-9)


def test_a_rest_in_another_fabric_is_not_taken_for_one_in_this(saved, tmp_path):
    """Only the friction differing (the one constant the contact state holds), the start
    was continued frozen: 0 iterations, "equilibrium: true", where the frictionless coat is
    off balance. The drape now updates friction first and goes on to its own rest."""
    from dataclasses import replace

    from patternfit.sim.drape import saved_balance

    outcome, folder = saved
    slippery = replace(api.read_fabric("cotton"), name="slippery", friction=0.0)
    again = api.drape_and_evaluate(GARMENT, BODY, slippery, triangles=TRIANGLES, start=folder)
    assert again.drape.result.iterations > 0
    rms = saved_balance(outcome.mesh, outcome.body, slippery, outcome.positions)[0]
    assert rms > 0.01  # the cotton rest is no rest without friction ...
    assert again.drape.checks.equilibrium  # ... and the drape found one
    # the same fabric still continues its rest at once
    same = api.drape_and_evaluate(GARMENT, BODY, "cotton", triangles=TRIANGLES, start=folder)
    assert same.drape.result.iterations == 0


def test_the_pattern_written_to_a_file_continues_its_built_ins_drape(saved, tmp_path):
    """``patternfit patterns coat --out coat.json`` (cm) then ``drape --pattern coat.json
    --start`` from the built-in's drape was refused as "another version of 'coat'": the
    coordinates read back differ in their last bit."""
    from patternfit.pattern.formats import save_any_pattern

    outcome, folder = saved
    save_any_pattern(outcome.pattern, tmp_path / "coat.json", units="cm")
    read = api.read_pattern(tmp_path / "coat.json")
    assert read != outcome.pattern and read.same_cut(outcome.pattern)
    again = api.drape_and_evaluate(tmp_path / "coat.json", BODY, "cotton",
                                   triangles=TRIANGLES, start=folder)
    assert again.drape.result.iterations == 0


def test_a_restart_at_rest_with_no_iteration_to_spare_is_at_rest(saved):
    # the iteration limit was checked before the rest: rms 0.004 read "no equilibrium"
    outcome, folder = saved
    again = api.drape_and_evaluate(GARMENT, BODY, "cotton", triangles=TRIANGLES, start=folder,
                                   settings=SolverSettings(max_iterations=0))
    assert again.drape.result.iterations == 0
    assert again.drape.result.stop_reason == "converged"
    assert again.drape.checks.equilibrium and again.drape.passed, again.drape.reasons


def test_contact_scales_are_read_back_away_from_self_pairs(saved):
    """Without ``contact.npz`` each contact's stiffness is read back from the force balance:
    exact wherever no self pair couples vertices (their repulsion scales with it too), nor
    an edge contact point two vertices of different scales (its stiffness is theirs)."""
    outcome, _ = saved
    d = outcome.drape
    model, state = d.solver.model, d.solver.state.copy()
    got = saved_contact_scale(model, state, model.reduce(d.result.x), settings=d.solver.settings)
    paired = np.zeros(model.n, bool)
    paired[state.pairs[:, 0]] = True
    paired[model.terms.tris[state.pairs[:, 1]].ravel()] = True
    paired[state.near_edges[state.edge_pairs].ravel()] = True
    pts = edge_points(model, d.solver.settings)
    touching = distance(model, pts.matrix @ model.reduce(d.result.x))[0] < model.reach(
        d.solver.settings)
    scale = state.contact_scale[pts.ids]
    paired[pts.ids[touching & (scale[:, 0] != scale[:, 1])].ravel()] = True
    assert np.array_equal(got[~paired], state.contact_scale[~paired])
    assert (got[~paired] > 1).any()


def test_a_new_state_without_contact_replaces_the_old_one(saved, tmp_path):
    outcome, folder = saved
    save_garment(tmp_path, outcome.pattern, outcome.mesh, outcome.positions,
                 contact=outcome.drape.saved_contact())
    assert load_contact(tmp_path) is not None
    save_garment(tmp_path, outcome.pattern, outcome.mesh, outcome.positions)
    assert not (tmp_path / CONTACT).exists() and load_contact(tmp_path) is None


def _spoilt(arrays, name, value):
    out = dict(arrays)
    if value is None:
        del out[name]
    else:
        out[name] = value(out[name])
    return out


@pytest.mark.parametrize("name, spoil, says", [
    ("contact_scale", lambda a: a[:-1], "expected shape"),
    ("contact_scale", lambda a: np.where(np.arange(len(a)) == 0, 1e9, a), "outside 1"),
    ("pairs", lambda a: a + 10 ** 6, "indices outside"),
    ("pair_normal", lambda a: np.full_like(a, np.nan), "NaN"),
    ("edge_pairs", lambda a: a.astype(float) + 0.5, "integers"),
    ("anchor_of", lambda a: np.where(np.isnan(a), 0.0, a) * np.array([1.0, np.nan, 1.0]),
     "all NaN"),
    ("bary", None, "missing"),
    ("at_rest", lambda a: np.asarray("yes"), "true or false"),
])
def test_a_foreign_contact_file_is_refused_naming_file_and_array(saved, tmp_path, name,
                                                                spoil, says):
    outcome, _ = saved
    folder = tmp_path / "garment"
    arrays = _spoilt(outcome.drape.saved_contact(), name, spoil)
    save_garment(folder, outcome.pattern, outcome.mesh, outcome.positions, contact=arrays)
    with pytest.raises(GarmentFileError) as e:
        api.drape_and_evaluate(GARMENT, BODY, "cotton", triangles=TRIANGLES, start=folder)
    text = str(e.value)
    assert CONTACT in text and f"'{name}'" in text and says in text


def test_a_start_that_is_no_drape_is_refused(saved, tmp_path):
    """A folder that is not there, a drape of the same garment in another size, and a
    state collapsed to a point (it ran 5,000 iterations into 595 crossings) are each
    refused before anything is draped, naming the file."""
    outcome, folder = saved
    with pytest.raises(InputError, match="does not exist"):
        api.drape_and_evaluate(GARMENT, BODY, "cotton", start=tmp_path / "nowhere")
    with pytest.raises(InputError, match=r"size M.*not of this '.*' size XL"):
        api.drape_and_evaluate(GARMENT, BODY, "cotton", size="XL", start=folder)
    flat = tmp_path / "garment"
    save_garment(flat, outcome.pattern, outcome.mesh, np.zeros_like(outcome.positions))
    with pytest.raises(InputError, match=r"positions\.npy.*collapsed state.*3D area is 0%"):
        api.drape_and_evaluate(GARMENT, BODY, "cotton", start=flat)
    with pytest.raises(ValueError, match="collapsed"):
        api.drape_and_evaluate(GARMENT, BODY, "cotton", triangles=TRIANGLES,
                               start=np.zeros_like(outcome.positions))


def test_a_damaged_contact_file_is_refused(saved, tmp_path):
    outcome, _ = saved
    folder = tmp_path / "garment"
    save_garment(folder, outcome.pattern, outcome.mesh, outcome.positions,
                 contact=outcome.drape.saved_contact())
    data = (folder / CONTACT).read_bytes()
    (folder / CONTACT).write_bytes(data[: len(data) // 2])
    with pytest.raises(GarmentFileError, match=CONTACT):
        api.drape_and_evaluate(GARMENT, BODY, "cotton", triangles=TRIANGLES, start=folder)


_SHAPES = hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=6)
_ARRAY = (hnp.arrays(np.float64, _SHAPES, elements=st.floats(-1e3, 1e3) | st.just(np.nan))
          | hnp.arrays(st.sampled_from([np.int64, np.int32]), _SHAPES,
                       elements=st.integers(-10, 10)))


@settings(max_examples=200, deadline=None)
@given(st.dictionaries(st.sampled_from(SAVED + ("at_rest",)), _ARRAY))
def test_any_saved_arrays_give_a_state_or_a_named_refusal(arrays):
    try:
        state = ContactState.from_saved(arrays, n=6, n_triangles=4, x=np.zeros((6, 3)))
    except SavedStateError as e:
        assert e.array in SAVED + ("at_rest",)
        return
    assert state.contact_scale.shape == (6,) and state.friction_on
    assert np.isfinite(state.contact_scale).all()
    assert ((state.pairs >= 0).all() and (state.pairs[:, 0] < 6).all()
            and (state.pairs[:, 1] < 4).all())


def test_the_saved_state_reads_back_field_for_field(saved):
    outcome, folder = saved
    d = outcome.drape
    model, state = d.solver.model, d.solver.state
    arrays = load_contact(folder)
    back = ContactState.from_saved(arrays, n=model.n, n_triangles=len(model.terms.tris),
                                   x=d.result.x)
    for name in SAVED:
        a, b = getattr(state, name), getattr(back, name)
        assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), name
    assert back.at_rest == state.at_rest is True and back.friction_on


def test_a_drape_started_from_an_outcome_continues_it(saved):
    outcome, _ = saved
    again = api.drape_and_evaluate(GARMENT, BODY, "cotton", triangles=TRIANGLES,
                                   start=outcome)
    assert again.drape.result.iterations == 0
    assert np.array_equal(again.positions, outcome.positions)
    # its own mesh, whatever the triangle count asked for
    again = api.drape_and_evaluate(GARMENT, BODY, "cotton", triangles=TRIANGLES + 500,
                                   start=outcome)
    assert again.mesh is outcome.mesh and again.drape.result.iterations == 0
    with pytest.raises(ValueError, match="same pattern"):
        api.drape_and_evaluate("skirt", BODY, "cotton", triangles=TRIANGLES, start=outcome)


def test_a_redrape_without_an_edit_does_not_move(saved):
    """The design loop's re-drape of an unchanged pattern continues the rest it has."""
    from patternfit.sim.drape import redrape
    outcome, _ = saved
    again = redrape(outcome.drape, outcome.mesh)
    assert again.result.iterations == 0
    assert np.array_equal(again.positions, outcome.positions)


def test_a_drape_stopped_while_sewing_is_continued_from_its_positions(tmp_path):
    """Stopped before the seams were welded, a drape's contact arrays are the unwelded
    model's: saved, a drape continued from them (which welds at once) refused them
    ("expected shape (770), got (840,)"), though the CLI said to continue it so."""
    from patternfit.body.builtin import load_body
    from patternfit.mesh.triangulate import mesh_pattern
    from patternfit.pattern.library import build
    from patternfit.sim.drape import drape

    calls = []

    def stop(*_):
        calls.append(1)
        if len(calls) == 5:
            raise KeyboardInterrupt

    skirt = build("skirt", "M")
    mesh = mesh_pattern(skirt, triangles=400)
    body = load_body("female_average")
    stopped = drape(skirt, mesh, body, "cotton", progress=stop, coarse=None)
    assert stopped.result.interrupted and not stopped.solver.model.welded
    kept = stopped.saved_contact(mesh)
    assert "contact_scale" not in kept and not kept["at_rest"]  # what it says of itself
    save_garment(tmp_path / "g", skirt, mesh, stopped.positions, contact=kept)
    again = api.drape_and_evaluate(skirt, body, "cotton", start=tmp_path / "g",
                                   settings=SolverSettings(max_iterations=3))
    assert again.drape.timing["start"] == "saved"
    # and read back it is no rest (saving nothing, it read "not checked", exit 0)
    assert api.evaluate_saved(tmp_path / "g").checks["passed"] is False
