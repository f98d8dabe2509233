"""KES-F and FAST measurement sheets read in their instruments' units (sim.fabric_sheets)."""

from __future__ import annotations

import json
import math

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from patternfit import api
from patternfit.cli.main import app
from patternfit.sim.fabrics import MAX_BULK_DENSITY, Fabric, FabricError, load_fabric

from fabric_files import read_or_refused_by_name, within, write

#: Matsudaira et al. 2015's wool tropical (docs/fabrics.md): B 0.067 gf cm^2/cm, 2HB 0.033
#: gf cm/cm, W 162.9 g/m^2, T 0.407 mm; the tensile and shear values are a typical woven's
WOOL = {"name": "wool tropical", "instrument": "KES-F", "W": 16.29, "T": 0.407, "B": 0.067,
        "2HB": 0.033, "G": [0.60, 0.64], "EMT": [4.0, 6.5], "friction": 0.4,
        "LT-1": 0.71, "LT-2": 0.74, "WT": 7.2, "RT": 68.0, "2HG": 0.9, "MIU-1": 0.19,
        "MIU-2": 0.2, "SMD": 3.1}
SUITING = {"name": "suiting", "instrument": "FAST", "W": 205, "T2": 0.42, "C": [19.8, 17.1],
           "E100": [2.9, 4.1], "G": 32, "friction": 0.4, "F1": 0.3, "EB5": 3.8}


def test_a_kes_sheet_reads_in_si(tmp_path):
    fab = load_fabric(write(tmp_path, WOOL))
    # by hand: 1 gf = 9.80665e-3 N, 1 cm = 1e-2 m, 1 mg/cm^2 = 1e-2 kg/m^2
    assert fab.name == "wool tropical"
    assert fab.density == pytest.approx(0.1629)
    assert fab.thickness == pytest.approx(0.407e-3)
    assert fab.bending_warp == fab.bending_weft == pytest.approx(0.067 * 9.80665e-3 * 1e-2)
    assert fab.bending_hysteresis == pytest.approx(0.033 * 9.80665e-3)
    # G per degree of shear -> per radian; the model's one shear takes the mean
    assert fab.shear == pytest.approx(0.62 * 0.980665 * 180 / math.pi)
    # EMT: the strain [%] under 500 gf/cm = 490.3 N/m
    assert fab.stretch_warp == pytest.approx(490.3325 / 0.040)
    assert fab.stretch_weft == pytest.approx(490.3325 / 0.065)
    # the bending length the docs give for this fabric (16.0 mm)
    assert fab.bending_length == pytest.approx(0.0160, abs=5e-5)


def test_a_weight_in_grams_per_square_metre_written_as_kes_w_is_refused(tmp_path):
    """W is mg/cm²: 162.9 g/m² written there is ten times the wool's weight, in range
    field by field, and draped without a word (4,000 kg/m³ of cloth)."""
    with pytest.raises(FabricError, match=r"fields 'W -> density' and 'T -> thickness': "
                                          r".*4,002 kg/m³ of cloth"):
        load_fabric(write(tmp_path, {**WOOL, "W": 162.9}))
    assert load_fabric(write(tmp_path, WOOL)).density * 1e3 / 0.407 < 1600  # 400 kg/m³


def test_a_kes_sheet_without_bending_friction_and_a_windows_byte_order_mark(tmp_path):
    """2HB 0 (no bending friction, as the SI field allows) was refused as not positive, and
    a file Notepad saved with a byte-order mark was "not valid JSON ... utf-8-sig"."""
    fab = load_fabric(write(tmp_path, {**WOOL, "2HB": 0}))
    assert fab.bending_hysteresis == 0.0
    path = tmp_path / "notepad.json"
    path.write_bytes(b"\xef\xbb\xbf" + json.dumps(WOOL).encode())
    assert load_fabric(path) == load_fabric(write(tmp_path, WOOL))
    with pytest.raises(FabricError, match=r"field '2HB': expected a number >= 0"):
        load_fabric(write(tmp_path, {**WOOL, "2HB": -0.1}))
    # a byte that is not UTF-8 after the mark is named where it is in the file
    path.write_bytes(b"\xef\xbb\xbf" + b'{"name": "\xff"}')
    with pytest.raises(FabricError, match=r"not UTF-8 text \(byte 13: 0xff\)"):
        load_fabric(path)


def test_a_fast_sheet_takes_the_bending_length_it_reports(tmp_path):
    fab = load_fabric(write(tmp_path, SUITING))
    assert fab.density == pytest.approx(0.205)
    assert fab.thickness == pytest.approx(0.42e-3)
    assert fab.bending_length == pytest.approx(0.0198, rel=1e-12)
    assert fab.bending_length_weft == pytest.approx(0.0171, rel=1e-12)
    assert fab.stretch_warp == pytest.approx(98.0665 / 0.029)
    assert fab.shear == 32
    assert fab.bending_hysteresis == 0.0
    by_b = load_fabric(write(tmp_path, {**{k: v for k, v in SUITING.items() if k != "C"},
                                         "B1": 12.0, "B2": 9.0}, "b.json"))
    assert (by_b.bending_warp, by_b.bending_weft) == pytest.approx((12e-6, 9e-6))


def test_a_sheets_two_spellings_of_a_direction_agree(tmp_path):
    pair = load_fabric(write(tmp_path, {**WOOL, "B": [0.07, 0.05]}, "a.json"))
    split = {k: v for k, v in WOOL.items() if k != "B"} | {"B-1": 0.07, "B-2": 0.05}
    assert load_fabric(write(tmp_path, split, "b.json")) == pair
    assert pair.bending_warp > pair.bending_weft


@pytest.mark.parametrize("spelling", [" kes f ", "KES FB", "Kes-FB", "siro fast", "Siro-FAST",
                                      "fast"])
def test_an_instrument_is_read_whatever_its_case_spaces_and_hyphens(tmp_path, spelling):
    """"KES F" was refused though spaces were said to be ignored ("KES-F" was read)."""
    sheet = WOOL if "k" in spelling.lower() else SUITING
    fab = load_fabric(write(tmp_path, {**sheet, "instrument": spelling}))
    assert fab == load_fabric(write(tmp_path, sheet, "as_written.json"))


@pytest.mark.parametrize("change, place, words", [
    ({"instrument": "Instron"}, "instrument", "KES-F"),
    ({"instrument": 5}, "instrument", "KES-F"),
    ({"friction": None}, "friction", "MIU"),
    ({"Bend": 0.07}, "Bend", "unknown"),
    ({"B-1": 0.07}, "B", "both"),
    # one direction in both of the sheet's spellings: the first was read, the other dropped
    ({"B": None, "B-1": 0.07, "B-2": 0.06, "B1": 7, "B2": 6}, "B",
     "given both as ['B-1', 'B-2'] and as ['B1', 'B2']"),
    ({"B": None, "B-1": 0.07, "B-2": 0.06, "B2": 6}, "B", "as ['B-1', 'B-2'] and as ['B2']"),
    ({"B": [0.07, 0.05, 0.06]}, "B", "3 values"),
    ({"B": -0.07}, "B", "positive"),
    ({"B": [0.07, "0.05"]}, "B[1]", "positive"),
    ({"EMT": 0.0001}, "EMT -> stretch_warp", "plausible range"),
    ({"W": 1600}, "W -> density", "plausible range"),
    ({"T": None}, "T", "missing"),
    ({"friction": 3.0}, "friction", "plausible range"),
])
def test_a_bad_kes_sheet_is_refused_naming_the_file_and_the_field(tmp_path, change, place,
                                                                   words):
    data = {**WOOL, **change}
    data = {k: v for k, v in data.items() if v is not None}
    path = write(tmp_path, data)
    with pytest.raises(FabricError) as err:
        load_fabric(path)
    assert err.value.file == str(path)
    assert err.value.place == f"field {place!r}"
    assert words in str(err.value)


def test_a_full_sirofast_report_with_both_b_and_c_reads(tmp_path):
    """A SiroFAST report prints the bending length C1/C2 and the rigidity B1/B2 together;
    such a sheet was refused ("not both"). When they agree (B = W g C^3 within 5%), B is
    read: the same fabric as from C alone."""
    from patternfit.constants import GRAVITY

    b = [round(SUITING["W"] * 1e-3 * GRAVITY * (c * 1e-3) ** 3 * 1e6, 2) for c in SUITING["C"]]
    both = load_fabric(write(tmp_path, {**SUITING, "B1": b[0], "B2": b[1]}, "both.json"))
    alone = load_fabric(write(tmp_path, SUITING, "alone.json"))
    assert both.bending_warp == pytest.approx(b[0] * 1e-6)
    assert both.bending_warp == pytest.approx(alone.bending_warp, rel=1e-3)
    assert both.bending_weft == pytest.approx(alone.bending_weft, rel=1e-3)


@pytest.mark.parametrize("change, place, words", [
    ({"B1": 12.0, "B2": 9.0}, "B", "B1 12 uN m and the bending length C1 19.8 mm disagree"),
    ({"C": None}, "B", "missing: the bending rigidity"),
    ({"C": None, "B1": 12.0}, "B2", "given 'B1'"),
    ({"T": 0.4}, "T2", "both"),
    ({"E100": None}, "E100", "missing"),
])
def test_a_bad_fast_sheet_is_refused_naming_the_field(tmp_path, change, place, words):
    data = {k: v for k, v in {**SUITING, **change}.items() if v is not None}
    with pytest.raises(FabricError) as err:
        load_fabric(write(tmp_path, data))
    assert err.value.place == f"field {place!r}"
    assert words in str(err.value)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(density=within("density"), warp=within("stretch_warp"), weft=within("stretch_weft"),
       shear=within("shear"), bw=within("bending_warp"), bf=within("bending_weft"),
       thick=within("thickness"), hb=within("bending_hysteresis"))
def test_a_fabric_written_as_a_kes_sheet_reads_back(tmp_path, density, warp, weft, shear, bw,
                                                     bf, thick, hb):
    assume(density <= MAX_BULK_DENSITY * thick)  # no cloth is denser
    fab = Fabric("x", density, warp, weft, shear, bw, bf, 0.3, thick, hb)
    gf = 9.80665e-3
    sheet = {"name": "x", "instrument": "kes-f", "W": density / 0.01, "T": thick * 1e3,
             "B": [bw / (gf * 0.01), bf / (gf * 0.01)], "2HB": hb / gf,
             "G": shear / (0.980665 * 180 / math.pi),
             "EMT": [100 * 500 * 0.980665 / warp, 100 * 500 * 0.980665 / weft],
             "friction": 0.3}
    back = load_fabric(write(tmp_path, sheet))
    for key, value in fab.to_dict().items():
        assert getattr(back, key) == (value if isinstance(value, str)
                                      else pytest.approx(value, rel=1e-9)), key


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(field=st.sampled_from(["W", "T", "B", "G", "EMT", "2HB", "friction", "B-1"]),
       value=st.one_of(st.none(), st.booleans(), st.text(max_size=5),
                       st.floats(allow_nan=False), st.integers(),
                       st.lists(st.floats(allow_nan=False), max_size=3),
                       st.dictionaries(st.text(max_size=2), st.integers(), max_size=2)))
def test_any_value_in_a_kes_sheet_reads_or_is_refused_by_name(tmp_path, field, value):
    path = write(tmp_path, {**WOOL, field: value})
    read_or_refused_by_name(path)


@pytest.mark.parametrize("sheet, change, place", [
    # each converts to 0 or infinity (a strain of 5e-324 %: its hundredth is 0), where
    # Python's floats raised ZeroDivisionError or OverflowError, an internal error
    (WOOL, {"EMT": 5e-324}, "EMT -> stretch_warp"),
    (SUITING, {"E100": [5e-324, 4.1]}, "E100 -> stretch_warp"),
    (SUITING, {"C": 1e120}, "C -> bending_warp"),
    (SUITING, {"C": 1e-120, "B": 5.0}, "B"),
    (SUITING, {"W": 5e-324, "B": 5.0}, "B"),
    (SUITING, {"W": 5e-324}, "W -> density"),
])
def test_a_sheet_value_that_converts_to_zero_or_infinity_is_refused_by_name(
        tmp_path, sheet, change, place):
    with pytest.raises(FabricError) as err:
        load_fabric(write(tmp_path, {**sheet, **change}))
    assert err.value.place == f"field {place!r}", str(err.value)


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(field=st.sampled_from(["W", "T2", "B", "C", "G", "E100", "C1"]),
       value=st.one_of(st.floats(allow_nan=False, allow_subnormal=True),
                       st.sampled_from([5e-324, 1e-300, 1e300, 1.7e308]),
                       st.lists(st.floats(allow_nan=False), min_size=2, max_size=2)))
def test_any_value_in_a_fast_sheet_reads_or_is_refused_by_name(tmp_path, field, value):
    data = {**SUITING, field: value}
    if field == "C1":
        del data["C"]
        data["C2"] = 17.1
    read_or_refused_by_name(write(tmp_path, data))


def test_a_fabric_name_with_a_control_character_is_refused(tmp_path):
    """An escape sequence in a name reached the terminal through the tables."""
    path = write(tmp_path, {**WOOL, "name": "\x1b[31mred\x07"})
    with pytest.raises(FabricError) as err:
        load_fabric(path)
    assert err.value.place == "field 'name'" and "control character" in str(err.value)
    r = CliRunner().invoke(app, ["fabrics", str(path)])
    assert r.exit_code == 2 and "\x1b" not in r.output and "\\x1b[31mred" in r.output, r.output


def test_the_cli_shows_a_sheet_in_si_and_the_api_reads_it(tmp_path):
    path = write(tmp_path, WOOL)
    out = CliRunner().invoke(app, ["fabrics", str(path), "denim", "--json"])
    assert out.exit_code == 0, out.output
    rows = json.loads(out.stdout)["fabrics"]
    assert [r["kind"] for r in rows] == ["file", "preset"]
    assert rows[0]["constants"] == load_fabric(path).to_dict()
    assert rows[0]["bending_length_m"]["warp"] == pytest.approx(0.0160, abs=5e-5)
    assert rows[1]["kit"] is not None
    # what --json prints is an SI fabric file
    si = write(tmp_path, rows[0]["constants"], "si.json")
    assert api.read_fabric(si) == api.read_fabric(path)
    bad = write(tmp_path, {**WOOL, "EMT": "4%"}, "bad.json")
    out = CliRunner().invoke(app, ["fabrics", str(bad)])
    assert out.exit_code == 2
    assert "bad.json" in out.output and "'EMT'" in out.output


@pytest.mark.parametrize("change, said", [
    ({"B": 6.96}, "warp bending length 75.3 mm"),                # uN m where gf cm^2/cm go
    ({"W": 162.9, "T": 1.2}, "1,358 kg/m³ of cloth"),            # g/m^2 where mg/cm^2 go
])
def test_a_kes_sheet_with_a_unit_slipped_is_noted(tmp_path, change, said):
    """Within every range and read, yet no cloth: a KES bending rigidity in uN m made a
    163 g/m² suiting 75 mm stiff, a thick sheet's weight in g/m² ten times too heavy (the
    bulk check's 1,600 kg/m³ let it through). Each is said."""
    from patternfit.sim.fabrics import read_fabric_file

    fab, notes = read_fabric_file(write(tmp_path, {**WOOL, **change}))
    assert any(said in n and "unit" in n for n in notes), notes
    _, plain = read_fabric_file(write(tmp_path, WOOL, "plain.json"))
    assert plain == ()


def test_every_preset_and_published_fabric_is_usual():
    from patternfit.sim.fabrics import FABRICS, get_fabric, published_drapes, unusual

    assert all(unusual(get_fabric(n)) == () for n in [*FABRICS, *published_drapes()])


def test_a_missing_fabric_file_is_named_as_a_file_not_a_preset(tmp_path):
    from patternfit.sim.fabrics import get_fabric

    with pytest.raises(FabricError, match="no such file") as err:
        get_fabric(tmp_path / "lab" / "wool")
    assert err.value.file == str(tmp_path / "lab" / "wool")
    with pytest.raises(FabricError, match="unknown preset 'woll'"):
        get_fabric("woll")


def test_a_fabric_name_is_printed_as_written(tmp_path, monkeypatch):
    """Rich markup in a fabric's name ("[bold]...") was read as markup in the tables."""
    from patternfit.cli.app import console, listing

    for c in (console, listing):  # the name's cell unwrapped (the table is a listing's)
        monkeypatch.setattr(c, "width", 200)
    path = write(tmp_path, {**WOOL, "name": "[bold]wool[/bold] [red]x"})
    r = CliRunner().invoke(app, ["fabrics", str(path)])
    assert r.exit_code == 0 and r.output.count("[bold]wool[/bold] [red]x") == 2, r.output
