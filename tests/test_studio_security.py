"""Hostile requests to the studio (FastAPI's TestClient, no browser): other sites' pages,
client paths, oversized and malformed bodies, heavy work next to light requests, exports
during edits."""

from __future__ import annotations

import asyncio
import json
import threading
import time
from dataclasses import replace

import pytest
import trimesh
from fastapi.testclient import TestClient

from patternfit.constants import limits
from patternfit.loop import DesignSession
from patternfit.studio import create_app

LIMIT = 64 * 1024
EDIT = {"op": "move_edge", "args": {"panel": "front", "edge": "hem", "offset": [0.0, -0.002],
                                    "partner": True}}


@pytest.fixture()
def app(tmp_path):
    app = create_app(tmp_path / "studio", max_upload=LIMIT, allowed_hosts=("testserver",))
    c = TestClient(app, headers={"X-Patternfit-Token": app.state.token})
    assert c.post("/api/new", json={"garment": "skirt", "triangles": 300}).status_code == 200
    return app


@pytest.fixture()
def client(app):
    return TestClient(app, headers={"X-Patternfit-Token": app.state.token})


def files_of(folder) -> dict:
    return {str(p.relative_to(folder)): p.stat().st_mtime_ns
            for p in folder.rglob("*") if p.is_file()}


def test_changes_need_the_pages_token(app, client):
    folder = app.state.studio.folder
    before, revision = files_of(folder), client.get("/api/state").json()["revision"]
    foreign = TestClient(app)  # what a page of another site can send: no token
    for path, kwargs in (("/api/new", {"json": {"garment": "coat"}}), ("/api/edit", {"json": EDIT}),
                         ("/api/undo", {}), ("/api/drape", {}),
                         ("/api/upload", {"files": {"file": ("p.json", b"{}")}})):
        r = foreign.post(path, **kwargs)
        assert r.status_code == 403 and "Token" in r.json()["error"], path
        wrong = foreign.post(path, headers={"X-Patternfit-Token": "guessed"}, **kwargs)
        assert wrong.status_code == 403, path
    assert foreign.get("/api/export/pattern.json").status_code == 403  # heavy: token too
    assert foreign.get("/api/state").status_code == 200  # reading needs none
    assert client.get("/api/state").json()["revision"] == revision
    assert files_of(folder) == before  # nothing replaced, no snapshot deleted
    # the page gets the token, unframeable and uncached
    page = client.get("/")
    assert f'content="{app.state.token}"' in page.text
    assert page.headers["x-frame-options"] == "DENY" and page.headers["cache-control"] == "no-store"
    other = create_app(folder.parent / "other", allowed_hosts=("testserver",))
    assert other.state.token != app.state.token


def test_origin_and_host_must_be_the_studios_own(app, client, tmp_path):
    for origin in ("http://evil.example", "http://testserver:8080", "null",
                   "http://testserver.evil.example", "https://testserver"):
        r = client.post("/api/new", json={"garment": "coat"}, headers={"Origin": origin})
        assert r.status_code == 403 and "other sites" in r.json()["error"], origin
        assert client.get("/api/state", headers={"Origin": origin}).status_code == 403
    assert client.post("/api/undo", json={}, headers={"Origin": "http://testserver"}
                       ).status_code in (200, 400)
    assert client.get("/api/state", headers={"Host": "evil.example"}).status_code == 403
    assert client.get("/api/state", headers={"Host": "testserver:8080"}).status_code == 403
    # by default only 127.0.0.1 / localhost on the server's own port are answered
    default = create_app(tmp_path / "default")
    assert TestClient(default).get("/api/state").status_code == 403


def test_bodies_must_be_json_or_multipart(client):
    r = client.post("/api/new", content=b'{"garment": "coat"}',
                    headers={"Content-Type": "text/plain"})
    assert r.status_code == 415 and "application/json" in r.json()["error"]
    assert client.post("/api/edit", data={"op": "move_point"}).status_code == 415  # form
    assert client.post("/api/new", content=b'{"garment": "coat"}',
                       headers={"Content-Type": ""}).status_code == 415
    assert client.post("/api/upload", json={"file": "x"}).status_code == 415
    assert client.post("/api/upload", content=b"x", headers={"Content-Type": "text/plain"}
                       ).status_code == 415
    assert client.get("/api/state").json()["info"]["garment"] == "skirt"


def test_a_bodyless_post_needs_no_type():
    """A POST without a body passes with Content-Length 0 or with no length at all (curl
    -X POST sends none; it was refused 415); a chunked one without a type does not."""
    from patternfit.studio.guard import TOKEN_HEADER, Guard

    guard = Guard(None, hosts=("127.0.0.1",), token="t")

    def scope(*headers):
        raw = [(b"host", b"127.0.0.1:8000"), (TOKEN_HEADER.lower().encode(), b"t"),
               *((k.encode(), v.encode()) for k, v in headers)]
        return {"type": "http", "path": "/api/drape/stop", "method": "POST",
                "server": ("127.0.0.1", 8000), "headers": raw}

    assert guard.refusal(scope()) is None
    assert guard.refusal(scope(("content-length", "0"))) is None
    assert guard.refusal(scope(("transfer-encoding", "chunked")))[0] == 415
    assert guard.refusal(scope(("content-length", "12")))[0] == 415


@pytest.mark.parametrize("field, value", [
    ("body", "/etc/passwd"), ("body", "/nonexistent/body.npz"),
    ("body", "../../../../etc/shadow"), ("body", "female_thin/../../x"),
    ("fabric", "/dev/zero"), ("fabric", "/etc/passwd"), ("fabric", "../studio.json"),
    ("garment", "/etc/passwd"), ("size", ["M"]), ("body", {"path": "/etc/passwd"})])
def test_no_client_path_is_opened(client, field, value):
    r = client.post("/api/new", json={field: value})
    assert r.status_code == 400
    error = r.json()["error"]
    assert error.startswith(f"{field}: expected one of")
    # the same answer whatever the path: nothing about the server's files is revealed
    for leak in ("passwd", "shadow", "zero", "No such", "Errno", "directory", "keys"):
        assert leak not in error


def test_uploads_over_the_limit_are_refused_before_reading(app, client):
    uploads = app.state.studio.folder / "uploads"
    big = b" " * (LIMIT + 1)
    r = client.post("/api/upload", files={"file": ("p.json", big)})
    assert r.status_code == 413
    # the limit the user knows, not the one with room for the multipart wrapping
    assert r.json()["error"] == f"upload: larger than {LIMIT // 1024} KiB", r.text
    huge = client.post("/api/upload", content=b"", headers={
        "Content-Type": "multipart/form-data; boundary=x", "Content-Length": str(10 ** 9)})
    assert huge.status_code == 413
    assert huge.json()["error"] == f"upload: larger than {LIMIT // 1024} KiB", huge.text

    def chunks():  # no Content-Length: counted as it arrives
        for _ in range(100):
            yield b"x" * 8192

    chunked = client.post("/api/upload", content=chunks(),
                          headers={"Content-Type": "multipart/form-data; boundary=x"})
    assert chunked.status_code == 413
    assert not uploads.exists() or not any(uploads.iterdir())
    too_big_json = client.post("/api/edit", content=b" " * (2 * 1024 * 1024),
                               headers={"Content-Type": "application/json"})
    assert too_big_json.status_code == 413


def test_an_oversized_stream_is_not_read_to_its_end(app):
    """At the ASGI level: the server stops pulling the body once it passed the limit."""
    pulled = []

    async def receive():
        pulled.append(1)
        return {"type": "http.request", "body": b"x" * 8192, "more_body": len(pulled) < 10_000}

    sent = []

    async def send(message):
        sent.append(message)

    scope = {"type": "http", "asgi": {"version": "3.0"}, "http_version": "1.1",
             "method": "POST", "scheme": "http", "path": "/api/upload", "raw_path": b"/api/upload",
             "query_string": b"", "root_path": "", "server": ("testserver", 80),
             "client": ("127.0.0.1", 5000),
             "headers": [(b"host", b"testserver"),
                         (b"x-patternfit-token", app.state.token.encode()),
                         (b"content-type", b"multipart/form-data; boundary=x"),
                         (b"transfer-encoding", b"chunked")]}
    asyncio.run(app(scope, receive, send))
    assert sent[0]["status"] == 413
    assert len(pulled) * 8192 < LIMIT + 128 * 1024  # the limit plus framing, not 80 MB


@pytest.mark.parametrize("body", [
    b"{", b"[" * 5000, b'{"op": NaN}', b'{"op": "move_point", "args": {"offset": [Infinity, 0]}}',
    b'{"op": 1e999}', b"[1, 2]", b'"move_point"', b"\xff\xfe", b'{"op": 5}',
    b'{"op": "move_point", "args": [1, 2]}', b'{"args": {}}', b'{"op": "move_point"}',
    b'{"op": "move_point", "args": {"panel": 1, "corner": [], "offset": "up"}}',
    b'{"op": "move_point", "args": {"panel": "front", "corner": "waist", "offset": [1, 2, 3]}}',
    b'{"op": "move_point", "args": {"panel": "front", "corner": "waist", "offset": [[0.1]]}}',
    b'{"op": "move_point", "args": {"label": "x"}}',
    b'{"op": "grade", "args": {"panel": "front", "sx": "big", "sy": null}}',
    b'{"op": "lengthen", "args": {"panel": "front", "a": 1, "b": {}, "amount": true}}',
    b'{"op": "insert_dart", "args": {"panel": "front", "name": 3, "centre": [0, 0]}}',
    b'{"op": "__init__", "args": {}}', b'{"op": "move_point", "revision": "3"}',
    b'{"op": "move_point", "args": {"panel": "front", "corner": "waist", "offset": [0, 0],'
    b' "evil": 1}}'])
def test_malformed_bodies_are_answered_400(client, body):
    history = client.get("/api/state").json()["history"]
    for path in ("/api/edit", "/api/drag", "/api/drag/basis"):
        r = client.post(path, content=body, headers={"Content-Type": "application/json"})
        assert r.status_code == 400, (path, r.text)
        assert r.json()["error"]
    # the other endpoints ignore the fields they do not take (but check a revision)
    for path in ("/api/new", "/api/undo", "/api/redo"):
        if body.startswith(b"{") and (path == "/api/new" or b"revision" not in body):
            continue
        r = client.post(path, content=body, headers={"Content-Type": "application/json"})
        assert r.status_code == 400, (path, r.text)
    assert client.get("/api/state").json()["history"] == history


CURVE = {"op": "edit_curve", "args": {"panel": "front", "edge": "hem", "offset": [0.0, -0.002],
                                      "control": 1, "partner": True}}


@pytest.mark.parametrize("edit, change, error", [
    # truthy strings the tools would take as "the partner follows"
    (EDIT, {"partner": "yes"}, "args.partner: expected true or false, got 'yes'"),
    (EDIT, {"partner": "false"}, "args.partner: expected true or false, got 'false'"),
    (EDIT, {"partner": 0}, "args.partner: expected true or false, got 0"),
    # a bool is control point 1 to the tool, a float an index error about the outline
    (CURVE, {"control": True}, "args.control: expected a whole number, got True"),
    (CURVE, {"control": 1.0}, "args.control: expected a whole number, got 1.0"),
    (EDIT, {"offset": [0, "1"]}, "args.offset[1]: expected a number, got '1'"),
    (EDIT, {"offset": [True, 0]}, "args.offset[0]: expected a number, got True"),
    (EDIT, {"offset": {"x": 0, "y": 1}}, "args.offset: expected a point [x, y]"),
    (EDIT, {"panel": ["front"]}, "args.panel: expected a name (text), got ['front']"),
    (EDIT, {"corner": "waist"}, "args.corner: move_edge takes no such argument (it takes "
                                "panel, edge, offset, partner)"),
    ({"op": "grade", "args": {"panel": "front", "sx": "1.1", "sy": 1.0}},
     {}, "args.sx: expected a number, got '1.1'"),
    ({"op": "set_seam_ease", "args": {"name": "side_l", "ease": None}},
     {}, "args.ease: expected a number, got None"),
    ({"op": "add_seam", "args": {"a": ["front", "hem"], "b": {"panel": "back", "edge": "hem"}}},
     {}, "args.a: expected a seam side"),
    ({"op": "add_seam", "args": {"a": {"panel": "front", "edge": "hem"},
                                 "b": {"panel": "back", "edge": "hem"}, "reverse": "no"}},
     {}, "args.reverse: expected true or false, got 'no'"),
])
def test_edit_arguments_of_the_wrong_kind_are_refused_naming_them(client, edit, change, error):
    history = client.get("/api/state").json()["history"]
    body = {**edit, "args": {**edit["args"], **change}}
    paths = ("/api/edit", "/api/drag") if edit["op"] in ("move_edge", "edit_curve") \
        else ("/api/edit",)
    for path in paths:
        r = client.post(path, json=body)
        assert r.status_code == 400, (path, r.text)
        assert r.json()["error"].startswith(error), (path, r.json())
    assert client.get("/api/state").json()["history"] == history


def test_edit_arguments_of_the_right_kind_pass():
    """Each tool's arguments as the page sends them, null where the tool's default is None,
    pass the check; the check lists exactly the arguments each editing tool takes."""
    import inspect

    from patternfit import edit as tools
    from patternfit.loop.session import EDIT_OPS
    from patternfit.studio.requests import EDIT_ARGS, Edit

    assert set(EDIT_ARGS) == set(EDIT_OPS)
    for op, kinds in EDIT_ARGS.items():
        assert list(kinds) == list(inspect.signature(getattr(tools, op)).parameters)[1:], op
    for op, args in (("grade", {"panel": None, "sx": 1, "sy": 1.0, "about": None,
                                "partner": False}),
                     ("edit_curve", CURVE["args"]),
                     ("insert_dart", {"panel": "front", "name": "d1", "centre": [0, 0.1],
                                      "length": 0.1, "width": 0.02, "axis": [0, 1],
                                      "shape": "diamond"}),
                     ("resize_dart", {"panel": "front", "name": "d1", "length": None,
                                      "width": 0.03}),
                     ("add_seam", {"a": {"panel": "front", "edge": "hem", "start": 0},
                                   "b": {"panel": "back", "edge": "hem"}, "name": None,
                                   "ease": None, "reverse": True})):
        assert Edit.model_validate({"op": op, "args": args}).args == args


@pytest.mark.parametrize("body", [{"triangles": "many"}, {"triangles": True},
                                  {"triangles": 10 ** 9}, {"triangles": 1.5},
                                  {"garment": None}, {"size": 3}])
def test_malformed_new_is_answered_400(client, body):
    r = client.post("/api/new", json=body)
    assert r.status_code == 400 and r.json()["error"]


def test_malformed_multipart_is_answered_400(client):
    r = client.post("/api/upload", content=b"--x\r\ngarbage", headers={
        "Content-Type": "multipart/form-data; boundary=x"})
    assert r.status_code == 400
    r = client.post("/api/upload", data={"other": "field"}, files={"x": ("a.json", b"{}")})
    assert r.status_code == 400 and "file" in r.json()["error"]
    r = client.post("/api/upload?kind=script", files={"file": ("a.json", b"{}")})
    assert r.status_code == 400 and "kind" in r.json()["error"]


def test_heavy_work_does_not_stall_other_requests(app, monkeypatch):
    """A slow upload (reading it) and a slow edit (under the session lock) run in worker
    threads: /api/state keeps answering at once meanwhile."""
    from patternfit.studio import state as state_module

    real_read, real_apply = state_module._read_upload, DesignSession.apply

    def slow_read(*args):
        time.sleep(1.5)
        return real_read(*args)

    def slow_apply(self, *args, **kwargs):
        time.sleep(1.5)
        return real_apply(self, *args, **kwargs)

    monkeypatch.setattr(state_module, "_read_upload", slow_read)
    monkeypatch.setattr(DesignSession, "apply", slow_apply)
    pattern = TestClient(app, headers={"X-Patternfit-Token": app.state.token}).get(
        "/api/export/pattern.json").content
    # one event loop for every request, as under uvicorn
    with TestClient(app, headers={"X-Patternfit-Token": app.state.token}) as c:
        for path, kwargs in (("/api/upload", {"files": {"file": ("mine.json", pattern)}}),
                             ("/api/edit", {"json": EDIT})):
            answers = []
            heavy = threading.Thread(target=lambda: answers.append(c.post(path, **kwargs)))
            heavy.start()
            time.sleep(0.3)
            t0 = time.perf_counter()
            assert c.get("/api/state").status_code == 200
            assert time.perf_counter() - t0 < 0.5, path
            assert heavy.is_alive()  # the heavy request was still running
            heavy.join(10)
            assert answers[0].status_code == 200, answers[0].text


def test_heavy_work_has_a_time_limit(client, monkeypatch):
    from patternfit.studio import requests as app_module

    real_apply = DesignSession.apply

    def slow_apply(self, *args, **kwargs):
        time.sleep(1.0)
        return real_apply(self, *args, **kwargs)

    monkeypatch.setattr(app_module, "limits", replace(limits, request_seconds=0.2))
    monkeypatch.setattr(DesignSession, "apply", slow_apply)
    t0 = time.perf_counter()
    r = client.post("/api/edit", json=EDIT)
    assert r.status_code == 503 and "0.2 s" in r.json()["error"]
    assert time.perf_counter() - t0 < 0.9
    time.sleep(1.2)  # the edit itself finishes in the background, under the lock
    assert len(client.get("/api/state").json()["history"]) == 2


def test_exports_during_edits_are_always_complete(app, client):
    folder = app.state.studio.folder
    stop, failures, sizes = threading.Event(), [], []

    def editing():
        while not stop.is_set():
            client.post("/api/edit", json=EDIT)
            client.post("/api/undo", json={})

    worker = threading.Thread(target=editing)
    worker.start()
    try:
        for _ in range(30):
            r = client.get("/api/export/pattern.json")
            try:
                assert r.status_code == 200
                sizes.append(len(json.loads(r.content)["panels"]))
            except (AssertionError, ValueError) as exc:
                failures.append(exc)
    finally:
        stop.set()
        worker.join(30)
    assert not failures and set(sizes) == {2}
    r = client.get("/api/export/pattern.json")
    assert r.headers["content-disposition"] == 'attachment; filename="pattern.json"'
    assert not any((folder / "exports").iterdir())  # each export's folder is removed


def test_uploaded_fabric_and_body_are_kept_in_the_session(tmp_path):
    from patternfit.body.mesh_io import save_body_mesh

    app = create_app(tmp_path / "studio", max_upload=2 * 1024 * 1024,
                     allowed_hosts=("testserver",))
    client = TestClient(app, headers={"X-Patternfit-Token": app.state.token})
    assert client.post("/api/new", json={"garment": "skirt", "triangles": 300}).status_code == 200
    fabric = {"density": 0.2, "stretch_warp": 5000, "stretch_weft": 4000, "shear": 40,
              "bending": 6e-6, "friction": 0.4, "thickness": 0.0003}
    r = client.post("/api/upload?kind=fabric",
                    files={"file": ("../../my poplin.json", json.dumps(fabric).encode())})
    assert r.status_code == 200 and r.json()["name"] == "my poplin"
    assert client.get("/api/state").json()["fabric"] == "my poplin"
    bad = client.post("/api/upload?kind=fabric", files={"file": ("bad.json", b'{"density": -1}')})
    assert bad.status_code == 400 and "bad.json" in bad.json()["error"]
    assert str(app.state.studio.folder) not in bad.json()["error"]
    assert client.post("/api/upload?kind=body", files={"file": ("x.json", b"{}")}
                       ).status_code == 400
    save_body_mesh(app.state.studio.session.body, tmp_path / "mine.obj")
    r = client.post("/api/upload?kind=body",
                    files={"file": ("mine.obj", (tmp_path / "mine.obj").read_bytes())})
    assert r.status_code == 200, r.text
    assert client.get("/api/body").json()["name"] == "mine"
    # what was guessed or done in reading it is said, as the CLI says it (a body facing -Z,
    # turned to face +Z, was not mentioned)
    assert any("units guessed as 'm'" in a for a in r.json()["assumed"])
    body = app.state.studio.session.body
    trimesh.Trimesh(body.vertices * [-1, 1, -1], body.faces, process=False).export(
        tmp_path / "away.obj")
    r = client.post("/api/upload?kind=body",
                    files={"file": ("away.obj", (tmp_path / "away.obj").read_bytes())})
    assert r.status_code == 200, r.text
    assert any("turned to face +Z" in a for a in r.json()["assumed"])
    save_body_mesh(body, tmp_path / "mine.obj")
    r = client.post("/api/upload?kind=body",
                    files={"file": ("mine.obj", (tmp_path / "mine.obj").read_bytes())})
    # a restarted studio continues with both, read from the session folder
    again = TestClient(create_app(app.state.studio.folder, allowed_hosts=("testserver",)))
    assert again.get("/api/state").json()["fabric"] == "my poplin"
    assert again.get("/api/body").json()["name"] == "mine"
