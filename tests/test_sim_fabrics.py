"""Fabric presets and user fabrics (patternfit.sim.fabrics)."""

from __future__ import annotations

import json

import pytest

from patternfit.sim.fabrics import FABRICS, Fabric, FabricError, get_fabric, load_fabric


def test_presets_cover_the_required_fabrics_in_si_ranges():
    for name in ("cotton_shirting", "denim", "wool_coating", "jersey_knit", "stretch_knit"):
        f = FABRICS[name]
        assert 0.05 < f.density < 1.0  # kg/m^2
        assert 10 < f.stretch_weft <= f.stretch_warp < 1e5  # N/m; a knit at low strain ~30
        assert 1e-7 < f.bending_weft <= f.bending_warp < 1e-3  # N m
        assert 0 < f.thickness < 5e-3  # m
    assert FABRICS["denim"].bending_warp > FABRICS["cotton_shirting"].bending_warp
    assert FABRICS["stretch_knit"].stretch_weft < FABRICS["cotton_shirting"].stretch_weft


@pytest.mark.parametrize("name, row0, density", [
    ("cotton_shirting", (2016.55, 9.17, 2034.98, 104.76), None),      # royal-target
    ("jersey_knit", (16.594, -14.696, 34.477, 36.860), 0.187),        # gray-interlock
    ("stretch_knit", (42.871, -0.235, 65.166, 83.176), 0.276),        # ivory-rib-knit
])
def test_presets_follow_their_wang_2011_samples(name, row0, density):
    """docs/fabrics.md: zero-strain row [c0..c3] of Wang et al. 2011 (ARCSim material file)
    -> warp 2 c2, weft 2 c0, shear c3 / 2 [N/m]."""
    f = FABRICS[name]
    assert f.stretch_warp == pytest.approx(2 * row0[2], rel=5e-3)
    assert f.stretch_weft == pytest.approx(2 * row0[0], rel=5e-3)
    assert f.shear == pytest.approx(row0[3] / 2, rel=5e-3)
    if density is not None:
        assert f.density == density


def test_shirting_thickness_follows_penava_2014():
    """docs/fabrics.md: 100 % cotton plain weave, Penava et al. 2014 Table 1, T = 0.318 mm."""
    assert FABRICS["cotton_shirting"].thickness == pytest.approx(0.318e-3, rel=1e-9)


def test_names_and_aliases():
    assert get_fabric("cotton") is FABRICS["cotton_shirting"]
    assert get_fabric("Wool-Coating") is FABRICS["wool_coating"]
    assert get_fabric(FABRICS["denim"]) is FABRICS["denim"]
    with pytest.raises(FabricError, match="unknown preset"):
        get_fabric("chainmail")


def _write(tmp_path, data):
    path = tmp_path / "mine.json"
    path.write_text(json.dumps(data))
    return path


GOOD = {"density": 0.2, "stretch_warp": 5e3, "stretch_weft": 3e3, "shear": 30,
        "bending": 5e-6, "friction": 0.3, "thickness": 3e-4}


def test_user_fabric_from_json(tmp_path):
    f = get_fabric(str(_write(tmp_path, GOOD)))
    assert isinstance(f, Fabric) and f.name == "mine"
    assert f.bending_warp == f.bending_weft == 5e-6


@pytest.mark.parametrize("field, value", [("density", -1), ("shear", "soft"),
                                          ("friction", -0.1), ("thickness", None)])
def test_user_fabric_errors_name_file_and_field(tmp_path, field, value):
    path = _write(tmp_path, {**GOOD, field: value})
    with pytest.raises(FabricError) as err:
        load_fabric(path)
    assert str(path) in str(err.value) and f"'{field}'" in str(err.value)


def test_user_fabric_missing_and_unknown_fields(tmp_path):
    data = dict(GOOD)
    del data["shear"]
    with pytest.raises(FabricError, match="'shear': missing"):
        load_fabric(_write(tmp_path, data))
    with pytest.raises(FabricError, match="'colour': unknown"):
        load_fabric(_write(tmp_path, {**GOOD, "colour": "red"}))
