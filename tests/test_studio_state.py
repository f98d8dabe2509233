"""The studio's session state through its API (TestClient): the session fields a reload
restores, a stopped drape (nothing recorded, no "reached"), the drape's phases and monotone
progress, and the version every change carries (a stale tab is refused with 409)."""

from __future__ import annotations

import json
import threading
from itertools import pairwise
from types import SimpleNamespace

import pytest
from fastapi.testclient import TestClient

from patternfit.studio import create_app
from patternfit.studio import state as studio_state

EDIT = {"op": "move_point", "args": {"panel": "front", "corner": "waist", "offset": [0.01, 0.0],
                                     "partner": True}}


def make_client(folder) -> TestClient:
    app = create_app(folder, allowed_hosts=("testserver",))
    return TestClient(app, headers={"X-Patternfit-Token": app.state.token})


@pytest.fixture()
def client(tmp_path):
    c = make_client(tmp_path)
    assert c.post("/api/new", json={"garment": "skirt", "triangles": 400}).status_code == 200
    return c


@pytest.fixture()
def callbacks(monkeypatch):
    """Every progress callback the drape tracker sees: (solver iteration, phase, fraction,
    iterations counted); ``callbacks.stop_after = n`` presses Stop after n callbacks."""
    class Seen(list):
        stop_after = None
        studio = None

    seen = Seen()
    update = studio_state.DrapeTracker.update

    def spy(self, it):
        update(self, it)
        seen.append((it, self.phase, self.fraction, self.iterations))
        if seen.stop_after is not None and len(seen) >= seen.stop_after:
            seen.studio.stop_drape()

    monkeypatch.setattr(studio_state.DrapeTracker, "update", spy)
    return seen


def test_state_holds_every_session_field(tmp_path):
    c = make_client(tmp_path)
    fields = {"garment": "skirt", "size": "L", "body": "female_thin", "fabric": "denim",
              "engine": "static", "triangles": 600}
    assert c.post("/api/new", json=fields).status_code == 200
    assert c.get("/api/state").json()["fields"] == fields
    # a restarted studio (a reload after a restart) shows the same fields
    assert make_client(tmp_path).get("/api/state").json()["fields"] == fields
    assert c.post("/api/new", json={**fields, "engine": "warp"}).status_code == 400


def test_stop_records_nothing_and_correction_never_reports_reached(client, callbacks):
    studio = callbacks.studio = client.app.state.studio
    before = client.get("/api/state").json()
    callbacks.stop_after = 30
    assert client.post("/api/drape", json={"revision": before["revision"]}).status_code == 200
    studio.wait(60)
    job = client.get("/api/drape").json()
    assert job["stopped"] and not job["running"] and job["error"] is None
    assert 0 < job["fraction"] < 1 and job["iteration"] >= 30
    s = client.get("/api/state").json()
    assert s["history"][0]["fitting_ratio"] is None and s["history"][0]["stopped"]
    assert [h["label"] for h in s["history"]] == [h["label"] for h in before["history"]]
    assert s["fitting_ratio"] is None and not s["draped"] and s["stopped"]
    assert s["revision"] == before["revision"]  # nothing was saved
    # a correction stopped inside its first drape reports no outcome, never "reached"
    callbacks.clear()
    assert client.post("/api/correct").status_code == 200
    studio.wait(60)
    job = client.get("/api/drape").json()
    assert job["stopped"] and job["result"]["stopped"] and job["result"]["reached"] is False
    assert job["rounds"] == [] and client.get("/api/state").json()["fitting_ratio"] is None
    # unstopped, the correction drapes the state first (round 0 is a full drape)
    callbacks.clear()
    callbacks.stop_after = None
    assert client.post("/api/correct").status_code == 200
    studio.wait(120)
    job = client.get("/api/drape").json()
    assert not job["stopped"] and job["error"] is None and job["rounds"]
    assert callbacks[0][1] == "sewing"
    assert job["result"]["fitting_ratio"] == pytest.approx(
        client.get("/api/state").json()["fitting_ratio"])


def monotone(values) -> bool:
    return all(b >= a for a, b in pairwise(values))


def test_progress_follows_the_phases_monotonically(client, callbacks):
    studio = callbacks.studio = client.app.state.studio
    fractions, iterations = [], []
    assert client.post("/api/drape").status_code == 200
    while True:  # what the page polls
        job = client.get("/api/drape").json()
        fractions.append(job["fraction"])
        iterations.append(job["iteration"])
        if not job["running"]:
            break
    assert job["fraction"] == 1.0 and job["phases"] == ["sewing", "relaxing", "draping"]
    assert monotone(fractions) and monotone(iterations)
    solver_its = [it for it, _, _, _ in callbacks]
    assert not monotone(solver_its)  # the solver counts each run from 1 ...
    assert monotone([n for _, _, _, n in callbacks])  # ... the studio counts on
    assert monotone([f for _, _, f, _ in callbacks]) and callbacks[-1][2] < 1
    phases = [p for _, p, _, _ in callbacks]
    assert [p for i, p in enumerate(phases) if i == 0 or p != phases[i - 1]] == \
        ["sewing", "relaxing", "draping"]
    # no phase fills the bar on its own: each ends below the next one's share
    assert max(f for _, p, f, _ in callbacks if p == "sewing") < 0.5
    # a re-drape after an edit only settles
    callbacks.clear()
    rev = client.get("/api/state").json()["revision"]
    assert client.post("/api/edit", json={**EDIT, "revision": rev}).status_code == 200
    assert client.post("/api/drape").status_code == 200
    studio.wait(60)
    assert client.get("/api/drape").json()["phases"] == ["settling"]
    assert monotone([f for _, _, f, _ in callbacks]) and monotone([n for *_, n in callbacks])


def _walk(tracker, runs):
    """Feed ``tracker`` the runner's phases and the solver's callbacks: (name, iterations)
    pairs; the (phase, iterations, fraction) after each callback."""
    seen = []
    for name, its in runs:
        tracker.enter(name)
        for it in range(1, its + 1):
            tracker.update(it)
            seen.append((tracker.phase, tracker.iterations, tracker.fraction))
    return seen


def test_tracker_follows_the_phases_the_runner_names():
    """The relaxed first drape of a session: sew, relax, drape the widened garment, then a
    staged re-drape; the stages count as the settling, iterations add up over the runs."""
    tracker = studio_state.DrapeTracker()
    tracker.plan = [(n, 100.0) for n in ("sewing", "relaxing", "draping", "settling")]
    seen = _walk(tracker, (("sewing", 5), ("relaxing", 3), ("draping", 4), ("stage 1 of 2", 2),
                           ("settling", 3)))
    phases = [p for p, _, _ in seen]
    assert [p for i, p in enumerate(phases) if i == 0 or p != phases[i - 1]] == \
        ["sewing", "relaxing", "draping", "settling"]
    assert [n for _, n, _ in seen] == list(range(1, 18))
    assert monotone([f for *_, f in seen]) and seen[-1][2] > 0.75
    # a sewing again (from farther out) goes back to it; the fraction waits
    tracker.plan = [(n, 100.0) for n in ("sewing", "relaxing", "draping")]
    tracker.index, tracker.last, tracker.done, tracker.fraction = 0, 0, 0, 0.0
    seen = _walk(tracker, (("sewing", 40), ("relaxing", 30), ("sewing", 20), ("relaxing", 10),
                           ("draping", 5)))
    assert [p for i, (p, *_) in enumerate(seen) if i == 0 or p != seen[i - 1][0]] == \
        ["sewing", "relaxing", "sewing", "relaxing", "draping"]
    assert monotone([f for *_, f in seen]) and tracker.iterations == 105
    # a carried start refused for its faults is draped cold: the plan gets those phases
    tracker.plan = [("settling", 300.0)]
    tracker.index, tracker.last, tracker.done, tracker.fraction = 0, 0, 0, 0.0
    seen = _walk(tracker, (("sewing", 30), ("relaxing", 20), ("draping", 10)))
    assert [p for i, (p, *_) in enumerate(seen) if i == 0 or p != seen[i - 1][0]] == \
        ["sewing", "relaxing", "draping"]
    assert [n for n, _ in tracker.plan] == ["sewing", "relaxing", "draping", "settling"]
    assert monotone([f for *_, f in seen]) and seen[-1][2] < 1.0
    # a name no drape phase has moves the bar on by one
    tracker.plan = [("sewing", 1.0), ("draping", 1.0)]
    tracker.index, tracker.last, tracker.done = 0, 4, 0
    tracker.enter("unplanned")
    assert tracker.phase == "draping" and tracker.iterations == 4


def test_large_mesh_plan_drapes_coarse_then_settles():
    mesh = SimpleNamespace(n_triangles=22000)
    session = SimpleNamespace(state=SimpleNamespace(mesh=mesh), next_start=lambda: "cold")
    plan = studio_state.drape_plan(session)
    assert [p for p, _ in plan] == ["sewing", "relaxing", "draping", "settling"]
    assert plan[-1][1] > sum(w for _, w in plan[:-1])  # the fine settling costs the most


def test_a_stale_version_is_refused_with_409(client):
    rev = client.get("/api/state").json()["revision"]
    assert client.post("/api/edit", json={**EDIT, "revision": rev}).status_code == 200
    state = client.get("/api/state").json()
    for path, kwargs in [("/api/edit", {"json": {**EDIT, "revision": rev}}),
                         ("/api/undo", {"json": {"revision": rev}}),
                         ("/api/redo", {"json": {"revision": rev}}),
                         ("/api/new", {"json": {"garment": "skirt", "revision": rev}}),
                         ("/api/drape", {"json": {"revision": rev}}),
                         ("/api/correct", {"json": {"revision": rev}}),
                         (f"/api/upload?kind=fabric&revision={rev}",
                          {"files": {"file": ("f.json", b"{}")}})]:
        r = client.post(path, **kwargs)
        assert r.status_code == 409, (path, r.text)
        body = r.json()
        assert body["stale"] and body["revision"] == rev + 1 and "reload" in body["error"]
        assert "last write wins" not in body["error"]
    assert client.get("/api/state").json() == state  # nothing changed
    assert not client.get("/api/drape").json()["running"]
    assert client.post("/api/undo", json={"revision": rev + 1}).status_code == 200
    assert client.post("/api/upload?kind=fabric&revision=x",
                       files={"file": ("f.json", b"{}")}).status_code == 400


def states_on_disk(session_folder) -> int:
    return sum(1 for p in (session_folder / "states").iterdir() if not p.name.startswith("."))


def test_a_replaced_session_is_kept_in_the_archive(client):
    """A new session, an opened file and a fabric used each start a new history; the one
    they replace, with its last edit (not yet written by the background saver), is moved to
    archive/<time>/ in the session folder, a session folder of its own, and the answer
    says where. Before, the next save deleted every state of the old history."""
    folder = client.app.state.studio.folder
    for _ in range(3):
        assert client.post("/api/edit", json=EDIT).status_code == 200
    r = client.post("/api/new", json={"garment": "skirt", "size": "L"})
    assert r.status_code == 200
    first = r.json()["archived"]
    assert first.startswith("archive/") and states_on_disk(folder / first / "session") == 4
    assert states_on_disk(folder / "session") == 1
    assert client.post("/api/undo", json={}).status_code == 400  # a new history
    # the archive is a session folder the studio continues: the 3 edits, the last current
    kept = make_client(folder / first).get("/api/state").json()
    assert len(kept["history"]) == 4 and kept["position"] == 3
    assert kept["fields"]["size"] == "M"  # its own studio.json went with it
    # an opened pattern and a fabric used replace the session too: each kept apart
    pattern = client.get("/api/export/pattern.json").content
    assert client.post("/api/edit", json=EDIT).status_code == 200
    opened = client.post("/api/upload", files={"file": ("mine.json", pattern)}).json()
    fabric = client.get("/api/fabric").json()["presets"]["denim"]
    used = client.post("/api/fabric", json={"fabric": fabric}).json()
    assert len({first, opened["archived"], used["archived"]}) == 3
    assert states_on_disk(folder / opened["archived"] / "session") == 2
    assert len(list((folder / "archive").iterdir())) == 3


def test_an_upload_refused_while_draping_changes_nothing(client, monkeypatch):
    """An upload refused with 409 because a drape runs, whether the drape was running when
    it came or started while the file was read, leaves the session's stored copy of the
    last opened file as it was (it was replaced before the refusal)."""
    studio = client.app.state.studio
    folder = studio.folder
    pattern = client.get("/api/export/pattern.json").content
    assert client.post("/api/upload", files={"file": ("mine.json", pattern)}).status_code == 200
    stored = (folder / "uploads" / "pattern.json").read_bytes()
    other = json.loads(pattern)
    other["name"] = "another"
    other = json.dumps(other).encode()
    gate = threading.Event()
    monkeypatch.setattr(studio_state.Studio, "_run_drape", lambda self, job: gate.wait(30))
    read_upload = studio_state._read_upload

    def drape_starts_meanwhile(*args):
        studio.start_drape()
        return read_upload(*args)

    try:
        assert client.post("/api/drape").status_code == 200  # running from here
        state = client.get("/api/state").json()
        r = client.post("/api/upload", files={"file": ("other.json", other)})
        assert r.status_code == 409 and "drape is running" in r.json()["error"]
        gate.set()
        studio.wait(10)
        gate.clear()
        monkeypatch.setattr(studio_state, "_read_upload", drape_starts_meanwhile)
        r = client.post("/api/upload", files={"file": ("other.json", other)})
        assert r.status_code == 409 and "drape is running" in r.json()["error"]
    finally:
        gate.set()
        studio.wait(10)
    assert (folder / "uploads" / "pattern.json").read_bytes() == stored
    assert [p.name for p in (folder / "uploads").iterdir()] == ["pattern.json"]
    assert client.get("/api/state").json()["history"] == state["history"]
