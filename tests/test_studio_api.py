"""API tests of the studio with FastAPI's TestClient (no browser)."""

from __future__ import annotations

import time

import numpy as np
import pytest
from fastapi.testclient import TestClient

from patternfit.sim.settings import SolverSettings
from patternfit.studio import create_app
from scenes import gathered_past_the_limit

EDIT = {"op": "move_point", "args": {"panel": "front", "corner": "waist", "offset": [0.01, 0.0],
                                     "partner": True}}


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("studio")


def studio_client(app) -> TestClient:
    """A client of ``app`` that sends the page's token, as the page does."""
    return TestClient(app, headers={"X-Patternfit-Token": app.state.token})


@pytest.fixture(scope="module")
def client(folder):
    app = create_app(folder, max_upload=64 * 1024, allowed_hosts=("testserver",))
    c = studio_client(app)
    assert c.post("/api/new", json={"garment": "skirt", "triangles": 400}).status_code == 200
    return c


def test_page_and_vendored_three_are_served(client):
    assert "patternfit studio" in client.get("/").text
    for f in ("app.js", "editor.js", "view3d.js", "vendor/three.module.js",
              "vendor/three.core.js", "vendor/OrbitControls.js", "vendor/LICENSE"):
        assert client.get(f"/static/{f}").status_code == 200, f


def test_options_and_state(client):
    o = client.get("/api/options").json()
    assert "skirt" in o["garments"] and o["sizes"] and o["bodies"] and o["fabrics"]
    assert o["correct_available"] is True
    s = client.get("/api/state").json()
    assert s["history"][0]["label"] == "start" and not s["draped"] and s["fitting_ratio"] is None


def test_drag_preview_moves_vertices_without_recording(client):
    g = client.get("/api/geometry").json()
    v0 = np.array(g["vertices"]).reshape(-1, 2)
    r = client.post("/api/drag", json=EDIT)
    assert r.status_code == 200 and set(r.headers["x-moved"].split(",")) == {"front", "back"}
    v1 = np.frombuffer(r.content, dtype="<f4").reshape(-1, 2)
    assert v1.shape == v0.shape
    moved = np.linalg.norm(v1 - v0, axis=1)
    assert 0.005 < moved.max() < 0.011
    assert len(client.get("/api/state").json()["history"]) == 1
    # the linear basis predicts the exact preview of a straight-edge drag
    basis = np.frombuffer(client.post("/api/drag/basis", json={**EDIT, "args": {
        k: v for k, v in EDIT["args"].items() if k != "offset"}}).content, dtype="<f4")
    basis = basis.reshape(2, -1, 2)
    assert np.abs(v0 + 0.01 * basis[0] - v1).max() < 1e-3
    bad = client.post("/api/drag", json={"op": "insert_dart", "args": {}})
    assert bad.status_code == 400 and "drag" in bad.json()["error"]


def test_edit_undo_redo_and_refusals(client, folder):
    rev = client.get("/api/state").json()["revision"]
    r = client.post("/api/edit", json={**EDIT, "revision": rev}).json()
    assert r["ok"] and r["revision"] == rev + 1
    s = client.get("/api/state").json()
    assert len(s["history"]) == 2 and s["can_undo"] and not s["can_redo"]
    # a tab that missed the change is refused and told to reload (its undo would remove
    # the other tab's edit)
    stale = client.post("/api/undo", json={"revision": rev})
    assert stale.status_code == 409 and "reload" in stale.json()["error"]
    assert client.get("/api/state").json()["position"] == 1
    assert client.post("/api/undo", json={"revision": rev + 1}).status_code == 200
    assert client.get("/api/state").json()["position"] == 0
    assert client.post("/api/redo", json={}).status_code == 200
    assert client.post("/api/redo", json={}).status_code == 400
    unmatched = client.post("/api/edit", json={**EDIT, "args": {**EDIT["args"], "partner": False}})
    assert unmatched.status_code == 400 and "seam" in unmatched.json()["error"]
    assert client.post("/api/edit", json={"op": "rm_rf", "args": {}}).status_code == 400
    # a restarted studio continues the saved session (edits are written in the background:
    # flush waits for the writing, as the server does when it stops)
    client.app.state.studio.flush()
    again = studio_client(create_app(folder, allowed_hosts=("testserver",)))
    assert len(again.get("/api/state").json()["history"]) == 2


def test_drape_progress_stop_and_exports(client):
    assert client.get("/api/export/garment.glb").status_code == 409  # nothing draped
    assert client.post("/api/drape").status_code == 200
    assert client.post("/api/drape").status_code == 409  # one at a time
    assert client.post("/api/undo", json={}).status_code == 409  # no edits while draping
    time.sleep(0.5)
    client.post("/api/drape/stop")
    studio = client.app.state.studio
    studio.wait(60)
    job = client.get("/api/drape").json()
    assert not job["running"] and job["error"] is None
    if job["stopped"]:  # stopped before it finished: nothing of it is kept
        assert job["fraction"] < 1 and client.get("/api/state").json()["fitting_ratio"] is None
        assert client.post("/api/drape").status_code == 200
        studio.wait(120)
    job = client.get("/api/drape").json()
    assert job["fraction"] == 1.0 and job["iteration"] > 0 and not job["stopped"]
    # the last iteration's force residual, beside the rest it aims at
    assert job["residual"] >= 0.0 and job["residual_rest"] == SolverSettings().residual_rms
    s = client.get("/api/state").json()
    assert s["draped"] and 0.5 < s["fitting_ratio"] < 1.5
    g3 = client.get("/api/garment3d").json()
    m = len(g3["triangles"]) // 3
    for name in ("area_change", "warp", "weft"):
        assert len(g3["maps"][name]["values"]) == m and len(g3["maps"][name]["colors"]) == 3 * m
    assert client.get("/api/geometry").json()["colors"] is not None
    for name in ("pattern.json", "pattern.dxf", "pattern.seams.json", "pattern.svg",
                 "garment.glb", "garment.obj", "report.json"):
        r = client.get(f"/api/export/{name}")
        assert r.status_code == 200 and len(r.content) > 100, name
    exported = client.get("/api/export/report.json").json()
    assert exported["fitting_ratio"] == pytest.approx(s["fitting_ratio"])
    # what it is a fit of, as the CLI's report says (the studio's named neither)
    info = client.get("/api/state").json()["info"]
    assert (exported["body"], exported["fabric"]) == (info["body"], info["fabric"])
    assert exported["garment"] == client.app.state.studio.ensure().pattern.name
    # a failed drape's exports show no fit colour (they were green, the garment's header
    # without a word of it, while the page said "failed")
    state = studio.ensure().state
    kept = state.checks
    try:
        state.checks = {**kept, "passed": False, "reasons": ["fell below the feet"]}
        obj = client.get("/api/export/garment.obj").text
        head = obj.splitlines()[0]
        assert '"checks_passed": false' in head and "fell below the feet" in head
        colours = {tuple(line.split()[4:7]) for line in obj.splitlines()
                   if line.startswith("v ")}
        assert len(colours) == 1
        svg = client.get("/api/export/pattern.svg").text
        assert "#9e9e9e" in svg.lower() and not any(c in svg.lower() for c in ("#4dac26",
                                                                              "#99cc8c"))
    finally:
        state.checks = kept


def test_the_dxf_export_comes_with_its_side_file(client, tmp_path):
    """A DXF alone holds no seams and no stated anchor: the studio's, opened again, was
    unsewn and hung where its panels say."""
    from patternfit.pattern.dxf import load_dxf

    (tmp_path / "p.dxf").write_bytes(client.get("/api/export/pattern.dxf").content)
    (tmp_path / "p.seams.json").write_bytes(
        client.get("/api/export/pattern.seams.json").content)
    back = load_dxf(tmp_path / "p.dxf")
    pattern = client.app.state.studio.ensure().pattern
    assert back.seams == pattern.seams and pattern.seams
    assert back.meta.get("anchor") == pattern.meta.get("anchor") is not None


def test_automatic_correction_runs_in_the_background(client):
    if not client.get("/api/options").json()["correct_available"]:
        pytest.skip("patternfit.loop.correct not available")
    assert client.post("/api/correct").status_code == 200
    client.app.state.studio.wait(120)
    job = client.get("/api/drape").json()
    assert job["kind"] == "correct" and job["error"] is None and not job["running"]
    assert job["rounds"] and job["rounds"][0]["iteration"] == 0
    assert job["result"]["fitting_ratio"] == pytest.approx(
        client.get("/api/state").json()["fitting_ratio"])


def test_correction_drapes_its_pattern_afresh(tmp_path, monkeypatch):
    """As the CLI's ``correct``: the pattern a studio correction made is draped afresh, and
    a fresh drape that fails its checks is no fit reached (the studio read "Fit reached"
    where the CLI exits 1)."""
    import dataclasses

    from patternfit import api
    app = create_app(tmp_path, allowed_hosts=("testserver",))
    c = studio_client(app)
    new = {"garment": "skirt", "size": "S", "body": "female_thin", "fabric": "stretch_knit",
           "triangles": 900}
    made = []
    real_correct = api.correct
    monkeypatch.setattr(api, "correct", lambda *a, **k: made.append(real_correct(*a, **k))
                        or made[-1])

    def corrected() -> dict:
        assert c.post("/api/new", json=new).status_code == 200
        app.state.studio.session.threshold = 0.999  # as test_loop_cli: the loop edits
        assert c.post("/api/correct").status_code == 200
        app.state.studio.wait(300)
        job = c.get("/api/drape").json()
        assert job["error"] is None, job
        return job["result"]

    result = corrected()
    assert any(it.edits for it in made[0].iterations)
    fresh = result["fresh_drape"]
    assert 0.5 < fresh["fitting_ratio"] < 1.5 and fresh["passed"] is True
    assert fresh["verdict"] is not None and result["verdict"] is not None
    assert result["reached"] == made[0].reached
    # a loop that reached its fit, whose pattern fails draped afresh
    monkeypatch.setattr(api, "correct", lambda *a, **k: dataclasses.replace(made[0],
                                                                           reached=True))
    said = {"passed": False, "reasons": ["12 cloth edges through the body"]}
    monkeypatch.setattr(api, "fresh_drape", lambda *a, **k: {**fresh, **said})
    result = corrected()
    assert result["reached"] is False and result["fresh_drape"]["passed"] is False
    monkeypatch.setattr(api, "fresh_drape", lambda *a, **k: fresh)
    assert corrected()["reached"] is True


def test_a_pattern_readers_warnings_are_said(tmp_path):
    """What the reader noticed in an uploaded file (a GarmentCode gather sewn in as ease)
    was printed by the CLI and said nowhere in the studio: the upload's message and the
    exported report now carry it."""
    from patternfit import api
    from patternfit.pattern.formats import save_any_pattern

    save_any_pattern(api.read_pattern("gathered_skirt"), tmp_path / "g_specification.json")
    app = create_app(tmp_path / "studio", max_upload=64 * 1024, allowed_hosts=("testserver",))
    c = studio_client(app)
    assert c.post("/api/new", json={"garment": "skirt", "triangles": 400}).status_code == 200
    r = c.post("/api/upload", files={"file": ("g_specification.json",
                                              (tmp_path / "g_specification.json").read_bytes())})
    assert r.status_code == 200
    assert any("different length" in a for a in r.json()["assumed"]), r.json()
    assert c.post("/api/drape").status_code == 200
    app.state.studio.wait(300)
    report = c.get("/api/export/report.json").json()
    assert any("different length" in w for w in report["pattern_warnings"])


def test_an_upload_that_cannot_be_meshed_names_the_file(tmp_path):
    """A GarmentCode gather beyond 2:1 was refused at upload naming only the panel."""
    import json

    spec = gathered_past_the_limit()
    app = create_app(tmp_path / "studio", allowed_hosts=("testserver",))
    c = studio_client(app)
    assert c.post("/api/new", json={"garment": "skirt", "triangles": 400}).status_code == 200
    r = c.post("/api/upload", files={"file": ("gather_specification.json",
                                              json.dumps(spec).encode())})
    assert r.status_code == 400 and "2.5:1 gather" in r.json()["error"]
    assert r.json()["error"].startswith("gather_specification.json: "), r.json()


def test_safety(client, folder):
    assert client.get("/api/export/..%2F..%2Fetc%2Fpasswd").status_code == 404
    assert client.get("/api/state", headers={"host": "attacker.example"}).status_code == 403
    big = client.post("/api/upload", files={"file": ("p.json", b" " * (65 * 1024))})
    assert big.status_code == 413
    wrong = client.post("/api/upload", files={"file": ("../../x.py", b"print(1)")})
    assert wrong.status_code == 400
    bad = client.post("/api/upload", files={"file": ("../../evil.json", b'{"panels": [')})
    assert bad.status_code == 400 and "evil.json" in bad.json()["error"]
    assert str(folder) not in bad.json()["error"]
    assert not (folder.parent.parent / "evil.json").exists()
    assert client.get("/api/state").status_code == 200  # still serving
    good = client.get("/api/export/pattern.json").content
    ok = client.post("/api/upload", files={"file": ("mine.json", good)})
    assert ok.status_code == 200 and ok.json()["panels"] == 2
    assert client.get("/api/state").json()["info"]["source"] == "uploaded mine.json"


def test_verdict_shows_only_the_reports_verdict_keys(client, monkeypatch):
    """The page shows the report's ``verdict``/``region_verdicts`` when it has them, and
    nothing for an undraped or edited state."""
    from patternfit.studio import exports

    studio = client.app.state.studio
    if studio.session.positions is None:
        assert client.get("/api/verdict").json() == {}
        return
    assert set(client.get("/api/verdict").json()) <= set(exports.VERDICT_KEYS)
    monkeypatch.setattr(exports, "fit_report", lambda *a, **k: {
        "fitting_ratio": 1.0, "verdict": "fits", "region_verdicts": {"waist": "tight"}})
    assert client.get("/api/verdict").json() == {"verdict": "fits",
                                                 "region_verdicts": {"waist": "tight"}}
