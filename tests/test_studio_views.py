"""The page's payloads are made once per history state and drape (``payload.Views``): what
is kept equals what a fresh making gives, a re-drape (a new positions array) is made again,
and two requests at once share one making."""

from __future__ import annotations

import threading
from dataclasses import replace

import numpy as np
import pytest

from patternfit import api
from patternfit.studio import payload


@pytest.fixture(scope="module")
def state():
    s = api.design_session("skirt", triangles=400)
    st = s.state
    # a 3D state as a drape gives one: the flat mesh lifted, stretched 3 % across
    st.positions = np.c_[st.mesh.vertices * [1.03, 1.0], np.full(st.mesh.n_vertices, 1.0)]
    return st


def same(a: payload.Payload, b: payload.Payload) -> None:
    assert a.header == b.header and a.arrays.keys() == b.arrays.keys()
    for k in a.arrays:
        np.testing.assert_array_equal(a.arrays[k], b.arrays[k], err_msg=k)
    assert a.binary() == b.binary()


def test_kept_payloads_equal_fresh_ones_and_follow_a_redrape(state):
    views = payload.Views()
    for kind, make in payload.MAKERS.items():
        kept = views.get(kind, state)
        assert views.get(kind, state) is kept
        same(kept, make(state))
    old = views.get("geometry", state)
    # a re-drape replaces the positions array: everything of the state is made again
    state.positions = state.positions * [1.0, 1.02, 1.0]
    new = views.get("geometry", state)
    assert new is not old
    same(new, payload.geometry(state))
    assert not np.array_equal(new.arrays["area_change"], old.arrays["area_change"])
    assert views.fit(state).fitting_ratio == api.evaluate_drape(state.mesh,
                                                                state.positions).fitting_ratio


def test_states_are_kept_apart_and_only_the_last_few(state):
    views = payload.Views(keep=2)
    others = [replace(state, key=f"other{i}") for i in range(3)]
    made = [views.get("geometry", s) for s in others]
    assert len({id(p) for p in made}) == 3
    assert views.get("geometry", others[2]) is made[2]
    assert views.get("geometry", others[0]) is not made[0]  # dropped: made again


def test_two_requests_at_once_share_one_making(state):
    views, calls, gate = payload.Views(), [], threading.Event()

    def slow(st, _views):
        calls.append(st.key)
        gate.wait(5)
        return object()

    out = []
    threads = [threading.Thread(target=lambda: out.append(views.get("slow", state, slow)))
               for _ in range(2)]
    for t in threads:
        t.start()
    gate.set()
    for t in threads:
        t.join(10)
    assert calls == [state.key] and len(out) == 2 and out[0] is out[1]


def test_the_maps_of_a_failed_drape_are_grey(state):
    """The page colours a failed drape grey with one "not a fit" swatch, as the CLI's
    pictures do (its maps read green, "fits ±2 %", under the red "failed")."""
    from patternfit.fit.pictures import FAILED_GREY

    fine = payload.garment3d(state)
    assert fine.header["failed"] is None and len(fine.header["maps"]["area_change"]["legend"]) > 1
    failed = replace(state, checks={"passed": False, "reasons": ["fell below the feet"]})
    grey = np.round(FAILED_GREY * 255)
    flat = payload.geometry(failed).arrays["colors"]
    assert (flat == grey).all()
    body = payload.garment3d(failed)
    assert body.header["failed"] == "fell below the feet"
    for name, m in body.header["maps"].items():
        assert [row["label"] for row in m["legend"]] == ["the drape failed its checks: not a fit"]
        assert (body.arrays[f"maps.{name}.colors"] == grey).all()


def test_the_report_judges_the_drape_as_the_cli_does():
    """The studio's report.json (and so /api/verdict) has the fit measures and verdict the
    CLI's report has (it had none: the page showed ϖ alone), and "failed" with why for a
    failed drape."""
    from patternfit.studio import exports

    s = api.design_session("skirt", triangles=600)
    s.redrape()
    fit = api.evaluate_drape(s.mesh, s.positions)
    assert s.state.checks["passed"]
    r = exports.report(s, fit)
    outcome = api.drape_and_evaluate(s.state.pattern, s.body, s.fabric, start=s.positions,
                                     triangles=600)
    assert r["verdict"] == outcome.verdict != "failed" and r["region_verdicts"]
    assert set(r["region_verdicts"]) == set(outcome.region_verdicts)
    assert "ease_cm" in r and "pressure_kpa" in r
    s.state.checks = {"passed": False, "reasons": ["fell below the feet"]}
    r = exports.report(s, fit)
    assert r["verdict"] == "failed" and "fell below the feet" in r["verdict_reason"]
    assert r["region_verdicts"] == {}
