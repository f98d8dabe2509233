"""The live drag preview keeps the mesh's topology (issue 22, bug 2): a dart dragged far
enough that its panel would need re-meshing previews the stretched mesh with the same
vertices, the drop re-meshes."""

from __future__ import annotations

import numpy as np
import pytest
from fastapi.testclient import TestClient

from patternfit.edit import move_dart, update_mesh
from patternfit.studio import create_app

DART = {"panel": "back", "name": "d1"}


@pytest.fixture(scope="module")
def client(tmp_path_factory):
    app = create_app(tmp_path_factory.mktemp("studio-drag"), allowed_hosts=("testserver",))
    c = TestClient(app, headers={"X-Patternfit-Token": app.state.token})
    assert c.post("/api/new", json={"garment": "skirt", "triangles": 1500}).status_code == 200
    r = c.post("/api/edit", json={"op": "insert_dart", "args": {
        **DART, "centre": [0.1, 0.45], "length": 0.12, "width": 0.02}})
    assert r.status_code == 200, r.text
    c.app_state = app.state
    return c


def vertex_count(client) -> int:
    return len(client.get("/api/geometry").json()["vertices"]) // 2


@pytest.mark.parametrize("offset", [(0.02, 0.0), (0.05, 0.0), (0.08, 0.0), (-0.08, 0.0),
                                    (0.0, -0.05)])
def test_dart_drag_preview_keeps_the_vertex_count(client, offset):
    n = vertex_count(client)
    r = client.post("/api/drag", json={"op": "move_dart", "args": {**DART, "offset": offset}})
    assert r.status_code == 200, r.text
    v = np.frombuffer(r.content, dtype="<f4").reshape(-1, 2)
    assert v.shape == (n, 2) and np.isfinite(v).all()
    assert r.headers["x-moved"] == "back"
    basis = client.post("/api/drag/basis", json={"op": "move_dart", "args": DART})
    assert basis.status_code == 200 and len(basis.content) == 4 * 2 * n * 2
    assert len(client.get("/api/state").json()["history"]) == 2  # nothing recorded


def test_far_dart_drag_would_remesh_and_the_drop_does(client):
    st = client.app_state.studio.session.state
    new = move_dart(st.pattern, "back", "d1", (0.08, 0.0))
    mesh, report = update_mesh(st.pattern, new, st.mesh, min_angle=0.0, remesh=False,
                               return_report=True)
    assert report.needs_remesh == ("back",) and report.remeshed == ()
    assert np.array_equal(mesh.triangles, st.mesh.triangles)
    # the same edit applied re-meshes the panel
    _, applied = update_mesh(st.pattern, new, st.mesh, min_angle=0.0, return_report=True)
    assert applied.remeshed == ("back",) and applied.inverted == 0


def test_refused_dart_drag_preview_is_a_400_with_a_message(client):
    n = vertex_count(client)
    r = client.post("/api/drag", json={"op": "move_dart", "args": {**DART,
                                                                    "offset": [0.6, 0.0]}})
    assert r.status_code == 400 and "refused" in r.json()["error"], r.text
    # the next preview inside the panel is answered again, same topology
    r = client.post("/api/drag", json={"op": "move_dart", "args": {**DART,
                                                                    "offset": [0.03, 0.0]}})
    assert r.status_code == 200 and len(r.content) == 4 * 2 * n
