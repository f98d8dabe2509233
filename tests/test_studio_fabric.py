"""The studio's fabric editor through its requests (FastAPI's TestClient): a fabric's edited
numbers tested on the virtual bench, refused when implausible, put into the session."""

from __future__ import annotations

import pytest
from fastapi.testclient import TestClient

from patternfit.studio import create_app
from patternfit.studio import fabric_lab


@pytest.fixture()
def client(tmp_path):
    app = create_app(tmp_path / "studio", allowed_hosts=("testserver",))
    c = TestClient(app, headers={"X-Patternfit-Token": app.state.token})
    assert c.post("/api/new", json={"garment": "skirt", "triangles": 300}).status_code == 200
    return c


def edited(client, **changes) -> dict:
    f = client.get("/api/fabric").json()
    assert set(f["presets"]) >= {"cotton_shirting", "denim"}
    assert f["session"]["name"] == "cotton_shirting"
    return {**f["session"], "name": "heavy cotton", **changes}


def run(client, test, fabric) -> dict:
    r = client.post("/api/fabric/test", json={"test": test, "fabric": fabric})
    assert r.status_code == 200, r.text
    client.app.state.fabric_lab.wait(120)
    job = client.get("/api/fabric/test").json()
    assert not job["running"] and job["error"] is None and job["fabric"] == "heavy cotton"
    return job


def test_a_strip_test_reads_the_edited_density(client):
    light = run(client, "strip", edited(client))["result"]
    heavy = run(client, "strip", edited(client, density=2 * edited(client)["density"]))
    heavy = heavy["result"]
    assert light["passed"] and heavy["passed"]
    # the strip stretches as rho g L^2 / 2k: twice the density, twice the elongation
    assert heavy["elongation_measured_m"] == pytest.approx(
        2 * light["elongation_measured_m"], rel=0.02)
    assert client.get("/api/fabric/test/picture").status_code == 409  # a strip has none


def test_a_cusick_test_gives_its_coefficient_and_top_view(client, monkeypatch):
    monkeypatch.setitem(fabric_lab.STUDIO_OPTIONS, "cusick", {"triangles": 300, "seeds": (0,)})
    job = run(client, "cusick", edited(client))
    assert 0.0 <= job["result"]["drape_coefficient"] <= 1.0 and job["picture"]
    png = client.get("/api/fabric/test/picture")
    assert png.status_code == 200 and png.content.startswith(b"\x89PNG")


@pytest.mark.parametrize("changes, field", [({"density": 30.0}, "density"),
                                            ({"friction": -0.5}, "friction"),
                                            ({"name": "../x"}, "name"),
                                            ({"shear": "stiff"}, "shear"),
                                            # each in range, 2,000 kg/m³ of cloth together
                                            ({"density": 0.2, "thickness": 1e-4},
                                             "'density' and 'thickness'")])
def test_implausible_numbers_are_refused(client, changes, field):
    fabric = edited(client, **changes)
    r = client.post("/api/fabric/test", json={"test": "strip", "fabric": fabric})
    assert r.status_code == 400 and field in r.json()["error"], r.text
    assert not client.get("/api/fabric/test").json()["running"]


def test_a_preset_is_tested_by_its_name_and_a_wrong_one_said_in_words(client):
    """``{"fabric": "denim"}`` was refused "Input should be a dictionary or an instance of
    Fabric"; a name is a preset's, never a file's."""
    r = client.post("/api/fabric/test", json={"test": "strip", "fabric": "denim"})
    assert r.status_code == 200, r.text
    client.app.state.fabric_lab.wait(120)
    job = client.get("/api/fabric/test").json()
    assert job["fabric"] == "denim" and job["result"]["passed"]
    # a preset's short name and a published fabric's id, as the CLI and the API read them
    for name, read in (("cotton", "cotton_shirting"), ("petrak_m1", "petrak_m1")):
        r = client.post("/api/fabric/test", json={"test": "strip", "fabric": name})
        assert r.status_code == 200, r.text
        client.app.state.fabric_lab.wait(120)
        assert client.get("/api/fabric/test").json()["fabric"] == read
    for wrong in ("/etc/passwd", "velvet", "cotton.json", 3):
        r = client.post("/api/fabric/test", json={"test": "strip", "fabric": wrong})
        error = r.json()["error"]
        assert r.status_code == 400 and error.startswith("fabric:"), r.text
        assert "Fabric" not in error and "dictionary" not in error and "passwd" not in error


def test_the_edited_fabric_goes_into_the_session(client):
    rev = client.get("/api/state").json()["revision"]
    fabric = edited(client, friction=0.7)
    foreign = TestClient(client.app)  # no token: another site's page
    assert foreign.post("/api/fabric", json={"fabric": fabric}).status_code == 403
    r = client.post("/api/fabric", json={"fabric": fabric, "revision": rev})
    assert r.status_code == 200, r.text
    s = client.get("/api/state").json()
    assert s["fabric"] == "heavy cotton" and s["fields"]["fabric"] == "heavy cotton"
    assert client.get("/api/fabric").json()["session"]["friction"] == 0.7
    assert client.post("/api/fabric", json={"fabric": fabric, "revision": rev}
                       ).status_code == 409  # a stale tab


def test_a_kes_sheet_uploaded_is_the_sessions_fabric_in_si(client):
    import json

    sheet = {"name": "wool tropical", "instrument": "KES-F", "W": 16.29, "T": 0.407,
             "B": 0.067, "2HB": 0.033, "G": 0.62, "EMT": [4.0, 6.5], "friction": 0.4}
    rev = client.get("/api/state").json()["revision"]
    r = client.post(f"/api/upload?kind=fabric&revision={rev}",
                    files={"file": ("wool.json", json.dumps(sheet).encode())})
    assert r.status_code == 200, r.text
    f = client.get("/api/fabric").json()["session"]
    assert f["name"] == "wool tropical"
    assert f["density"] == pytest.approx(0.1629)
    assert f["bending_warp"] == pytest.approx(0.067 * 9.80665e-5)
    assert f["bending_hysteresis"] == pytest.approx(0.033 * 9.80665e-3)
    rev = client.get("/api/state").json()["revision"]
    bad = client.post(f"/api/upload?kind=fabric&revision={rev}",
                      files={"file": ("wool.json", json.dumps({**sheet, "EMT": "4%"}).encode())})
    assert bad.status_code == 400 and "'EMT'" in bad.json()["error"], bad.text


def test_an_arcsim_material_uploaded_is_named_after_its_file(client):
    import json

    material = {"density": 0.324,
                "stretching": [[205.35, 10.23, 1013.89, 53.39]] + [[230.0, 40.0, 1050.0, 70.0]] * 5,
                "bending": [[64.2e-6] * 5, [73.4e-6] * 5, [96.95e-6] * 5]}
    rev = client.get("/api/state").json()["revision"]
    r = client.post(f"/api/upload?kind=fabric&revision={rev}",
                    files={"file": ("11oz-black-denim.json", json.dumps(material).encode())})
    assert r.status_code == 200, r.text
    assert [a.split(" assumed")[0] for a in r.json()["assumed"]] == ["friction 0.4",
                                                                     "thickness 0.77 mm"]
    f = client.get("/api/fabric").json()["session"]
    assert f["name"] == "11oz-black-denim"
    assert f["stretch_warp"] == pytest.approx(2 * 1013.89)
    assert f["bending_weft"] == pytest.approx(96.95e-6 / 4)
    rev = client.get("/api/state").json()["revision"]
    bad = client.post(f"/api/upload?kind=fabric&revision={rev}", files={"file": (
        "m.json", json.dumps({**material, "bending": material["bending"][:2]}).encode())})
    assert bad.status_code == 400 and "'bending'" in bad.json()["error"], bad.text
