"""ARCSim material files (Wang et al. 2011's measured fabrics) read as fabrics (sim.fabric_arcsim)."""

from __future__ import annotations

import json
import math

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from patternfit import api
from patternfit.cli.main import app
from patternfit.sim.fabric_arcsim import ARCSIM_BENDING_FACTOR
from patternfit.sim.fabrics import (FABRICS, MAX_BULK_DENSITY, TYPICAL_BULK_DENSITY, Fabric,
                                    FabricError, load_fabric, read_fabric_file)

from fabric_files import read_or_refused_by_name, within, write

#: Wang et al. 2011's gray-interlock as ARCSim's materials/ distribute it: four-space indents,
#: a tab before the last bending row, exponents written e-6
GRAY_INTERLOCK = """{
    "density": 0.187,
    "stretching": [
        [16.593832, -14.695990, 34.477123, 36.860302],
        [46.364765, 53.694656, 261.013855, -29.691301],
        [49.285110, 87.596100, 206.373993, 22.768457],
        [123.989220, 105.181770, 365.966217, 44.217571],
        [139.686325, 73.592560, 413.553162, -174.43853],
        [127.443810, 85.848587, 405.872833, 32.238411]
    ],
    "bending": [
        [23.191698e-6, 32.932217e-6, 34.406498e-6, 39.014420e-6, 23.382786e-6],
        [24.749964e-6, 18.651314e-6, 16.370552e-6, 25.095791e-6, 8.860165e-6],
\t[14.267624e-6, 7.052906e-6, 14.515154e-6, 24.665127e-6, 19.383726e-6]
    ]
}
"""

#: a material of the same shape with round numbers, for hand-computed conversions
ROUND = {"density": 0.3, "stretching": [[200.0, 10.0, 1000.0, 50.0]] + [[1.0, 2.0, 3.0, 4.0]] * 5,
         "bending": [[60e-6, 1, 2, 3, 4], [0, 0, 0, 0, 0], [100e-6, 5, 6, 7, 8]]}


def test_wangs_file_as_distributed_is_the_jersey_preset(tmp_path):
    """The jersey preset was typed from this file: reading the file gives it back (the preset's
    stretch and shear rounded to three digits, its thickness assumed apart)."""
    fab, assumed = read_fabric_file(write(tmp_path, GRAY_INTERLOCK, "gray-interlock.json"))
    preset = FABRICS["jersey_knit"]
    assert fab.name == "gray-interlock"
    assert fab.density == preset.density
    assert fab.bending_warp == preset.bending_warp
    assert fab.bending_weft == preset.bending_weft
    for key in ("stretch_warp", "stretch_weft", "shear"):
        assert getattr(fab, key) == pytest.approx(getattr(preset, key), rel=2e-3), key
    assert fab.friction == preset.friction
    assert fab.thickness == pytest.approx(0.187 / TYPICAL_BULK_DENSITY)
    assert len(assumed) == 2
    assert "friction 0.4 assumed" in assumed[0] and "thickness 0.45 mm" in assumed[1]


def test_a_material_with_arcsims_comments_reads(tmp_path):
    """ARCSim's own paper.json and aluminium.json begin with "//" lines of notes, which its
    reader (jsoncpp) skips: here they gave "not valid JSON (line 1, column 1)"."""
    noted = ("// Wang et al. 2011, gray interlock\n// density in kg/m^2 /* not a block */\n"
             + GRAY_INTERLOCK.replace('"density": 0.187,', '"density": 0.187, /* measured */'))
    fab, _ = read_fabric_file(write(tmp_path, noted, "noted.json"))
    plain, _ = read_fabric_file(write(tmp_path, GRAY_INTERLOCK, "noted2.json"))
    assert fab.to_dict() | {"name": ""} == plain.to_dict() | {"name": ""}


JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers() | st.text(),
    lambda inner: st.lists(inner) | st.dictionaries(st.text(), inner), max_leaves=12)


@settings(max_examples=60, deadline=None)
@given(value=JSON_VALUES, note=st.text().filter(lambda t: "\n" not in t and "*/" not in t))
def test_comments_are_blanked_and_strings_kept(value, note):
    from patternfit.files import without_comments

    text = json.dumps(value)
    assert without_comments(text) == text  # strings holding "//" or "/*" kept
    noted = f"// {note}\n{text} /* {note} */"
    assert json.loads(without_comments(noted)) == value
    assert len(without_comments(noted)) == len(noted)


@pytest.mark.parametrize("text, place", [
    ('{"density": 0.2} /* oops', "line 1, column 18"),
    ('// a note\n{"density": 0.2,\n  /* cut short "stretching": []', "line 3, column 3"),
])
def test_a_comment_never_closed_is_refused_naming_the_file_and_the_line(tmp_path, text, place):
    """Blanked to the end of the file, it hid whatever followed it: a file cut short read
    as if whole."""
    path = write(tmp_path, text, "cut.json")
    with pytest.raises(FabricError) as err:
        load_fabric(path)
    assert err.value.file == str(path)
    assert f"not valid JSON ({place}: a /* comment not closed by */)" in str(err.value)


def test_the_zero_strain_and_zero_curvature_samples_convert_by_hand(tmp_path):
    fab = load_fabric(write(tmp_path, ROUND))
    # ARCSim's k = 2 x row 0; axis 0 is the weft; G01 = shear / 2, so k3 / 4 = c3 / 2
    assert fab.stretch_warp == 2000.0
    assert fab.stretch_weft == 400.0
    assert fab.shear == 25.0
    assert fab.bending_warp == pytest.approx(ARCSIM_BENDING_FACTOR * 60e-6, rel=1e-15)
    assert fab.bending_weft == pytest.approx(ARCSIM_BENDING_FACTOR * 100e-6, rel=1e-15)
    assert fab.bending_hysteresis == 0.0


def test_friction_thickness_and_name_added_to_the_file_are_used(tmp_path):
    path = write(tmp_path, {**ROUND, "friction": 0.25, "thickness": 0.0011, "name": "denim"})
    fab, assumed = read_fabric_file(path)
    assert (fab.name, fab.friction, fab.thickness, assumed) == ("denim", 0.25, 0.0011, ())


#: Wang et al. 2011's navy-sparkle-sweat as ARCSim's materials/ distribute it: row 0 of its
#: stretching, whose coupling c1 is past what c0 and c2 allow (c1² = 395 ≥ c0 c2 = 40.9)
NAVY_ROW0 = [12.486332, -19.875324, 3.272434, 17.616289]


def test_a_coupling_past_the_files_own_stretches_is_noted_not_refused(tmp_path):
    """ARCSim ships and runs navy-sparkle-sweat and the linear model takes nothing from c1:
    the file was refused, "no stable material"."""
    path = write(tmp_path, {**ROUND, "density": 0.224,
                            "stretching": [NAVY_ROW0] + ROUND["stretching"][1:]})
    fab, notes = read_fabric_file(path)
    assert fab.stretch_warp == 2 * 3.272434 and fab.stretch_weft == 2 * 12.486332
    assert fab.shear == 17.616289 / 2
    said = [n for n in notes if "c1 = -19.8753 N/m not used" in n]
    assert len(said) == 1 and "stretching[0][1]" in said[0] and "positive definite" in said[0]
    r = CliRunner().invoke(app, ["fabrics", str(path)])
    assert r.exit_code == 0 and "c1 = -19.8753 N/m not used" in r.output, r.output
    # a coupling within what the stretches allow says nothing
    assert not any("c1" in n for n in read_fabric_file(write(tmp_path, ROUND, "r.json"))[1])


@pytest.mark.parametrize("change, place, words", [
    ({"damping": 0.1}, "damping", "unknown in an ARCSim material"),
    ({"bending": None}, "bending", "missing"),
    ({"density": None}, "density", "missing"),
    ({"stretching": ROUND["stretching"][:5]}, "stretching", "6 rows of 4 numbers, got 5 rows"),
    ({"stretching": {"0": 1}}, "stretching", "got dict"),
    ({"bending": [[1e-5] * 5, [1e-5] * 4, [1e-5] * 5]}, "bending', row 1", "got 4 numbers"),
    ({"bending": [[1e-5] * 5, [1e-5] * 5, [1e-5, "x", 1, 1, 1]]}, "bending[2][1]",
     "finite number"),
    ({"density": "0.3"}, "density", "finite number"),
    ({"density": 30.0}, "density", "plausible range"),
    ({"stretching": [[200.0, 0.0, -5.0, 50.0]] + [[0.0] * 4] * 5},
     "stretching[0][2] x 2 -> stretch_warp", "plausible range"),
    # ARCSim's aluminium.json: E h = 1.8e6 N/m, far past any cloth
    ({"stretching": [[1.8e6, 0.0, 1.8e6, 1.8e6]] * 6}, "stretching[0][2] x 2 -> stretch_warp",
     "plausible range"),
    ({"bending": [[0.0] * 5] * 3}, "bending[0][0] x 0.25 -> bending_warp", "plausible range"),
    ({"friction": 5.0}, "friction", "plausible range"),
    ({"thickness": 0.5}, "thickness", "plausible range"),
])
def test_a_bad_material_is_refused_naming_the_file_and_the_entry(tmp_path, change, place,
                                                                 words):
    data = {k: v for k, v in {**ROUND, **change}.items() if v is not None}
    path = write(tmp_path, data)
    with pytest.raises(FabricError) as err:
        load_fabric(path)
    assert err.value.file == str(path)
    assert place in err.value.place
    assert words in str(err.value)


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(density=within("density"), warp=within("stretch_warp"), weft=within("stretch_weft"),
       shear=within("shear"), bw=within("bending_warp"), bf=within("bending_weft"),
       thick=within("thickness"), noise=st.floats(-1e3, 1e3))
def test_a_fabric_written_as_an_arcsim_material_reads_back(tmp_path, density, warp, weft,
                                                           shear, bw, bf, thick, noise):
    assume(density <= MAX_BULK_DENSITY * thick)  # no cloth is denser
    fab = Fabric("x", density, warp, weft, shear, bw, bf, 0.3, thick)
    # the samples at strain and curvature are read and not used: any numbers there; the
    # coupling neither, within what a stable material allows
    coupling = math.copysign(min(abs(noise), 0.99 * math.sqrt(weft * warp) / 2), noise)
    material = {"density": density, "friction": 0.3, "thickness": thick,
                "stretching": [[weft / 2, coupling, warp / 2, 2 * shear]] + [[noise] * 4] * 5,
                "bending": [[bw / ARCSIM_BENDING_FACTOR] + [noise] * 4, [noise] * 5,
                            [bf / ARCSIM_BENDING_FACTOR] + [noise] * 4]}
    back = load_fabric(write(tmp_path, material, "x.json"))
    for key, value in fab.to_dict().items():
        assert getattr(back, key) == (value if isinstance(value, str)
                                      else pytest.approx(value, rel=1e-12)), key


@settings(max_examples=80, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(field=st.sampled_from(["density", "stretching", "bending", "friction", "thickness"]),
       value=st.one_of(st.none(), st.booleans(), st.text(max_size=5), st.floats(allow_nan=False),
                       st.integers(), st.lists(st.floats(allow_nan=False), max_size=6),
                       st.lists(st.lists(st.floats(allow_nan=False), min_size=4, max_size=5),
                                min_size=3, max_size=6)))
def test_any_value_in_a_material_reads_or_is_refused_by_name(tmp_path, field, value):
    path = write(tmp_path, {**ROUND, field: value})
    read_or_refused_by_name(path)


def test_the_cli_says_what_it_assumed(tmp_path):
    path = write(tmp_path, GRAY_INTERLOCK, "gray-interlock.json")
    out = CliRunner().invoke(app, ["fabrics", str(path), "--json"])
    assert out.exit_code == 0, out.output
    row = json.loads(out.stdout)["fabrics"][0]
    assert row["kind"] == "file"
    assert row["constants"] == api.read_fabric(path).to_dict()
    assert [a.split(" assumed")[0] for a in row["assumed"]] == ["friction 0.4",
                                                                "thickness 0.45 mm"]
    shown = CliRunner().invoke(app, ["fabrics", str(path)])
    assert shown.exit_code == 0
    assert "assumed" in shown.output and "gray-interlock" in shown.output
    # an SI file says nothing was assumed
    si = write(tmp_path, row["constants"], "si.json")
    assert api.describe_fabric(si)["assumed"] == []


def test_the_kit_tests_a_material_and_reports_what_it_assumed(tmp_path):
    path = write(tmp_path, GRAY_INTERLOCK, "gray-interlock.json")
    out = CliRunner().invoke(app, ["fabric-test", "strip", "--fabric", str(path), "--length",
                                   "0.3", "--json"])
    assert out.exit_code == 0, out.output
    d = json.loads(out.stdout)
    assert d["fabric"] == "gray-interlock" and d["passed"]
    assert d["ratio"] == pytest.approx(1.0, abs=0.05)
    assert len(d["fabric_assumed"]) == 2
    assert "friction 0.4 assumed" in out.stderr
    preset = CliRunner().invoke(app, ["fabric-test", "strip", "--fabric", "jersey", "--length",
                                      "0.3", "--json"])
    assert json.loads(preset.stdout)["fabric_assumed"] == []


def test_drape_correct_and_batch_say_what_was_assumed(tmp_path):
    """The studio and fabric-test said an ARCSim file's friction and thickness were
    assumed; drape, correct and the batch did not, nor did the drape's report."""
    from typer.testing import CliRunner

    from patternfit.cli.main import app

    path = tmp_path / "round.json"
    path.write_text(json.dumps(ROUND))
    r = CliRunner().invoke(app, ["drape", "-p", "skirt", "-b", "female_thin", "-f", str(path),
                                 "-n", "300", "--no-pictures", "-o", str(tmp_path / "d")])
    said = " ".join(r.output.split())
    assert "note: fabric" in said and "friction" in said, said
    report = json.loads((tmp_path / "d" / "report.json").read_text())
    assert any("friction" in a for a in report["fabric_assumed"])
    r = CliRunner().invoke(app, ["batch", "-p", "skirt", "-s", "M", "-b", "female_thin",
                                 "-f", str(path), "-n", "300", "-w", "0", "--no-thumbnails",
                                 "-o", str(tmp_path / "b"), "--json"])
    assert any("friction" in a for a in json.loads(r.stdout)["fabric_assumed"][str(path)])
