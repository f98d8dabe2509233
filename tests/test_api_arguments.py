"""The public API refuses a bad argument with a ValueError naming it, before any work: a
wrong value used to cost a whole drape, then fail deep inside (TypeError, AttributeError,
IndexError after pattern.json was written)."""

import numpy as np
import pytest

import patternfit.api as api


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
