"""``load_any_pattern`` / ``save_any_pattern`` dispatch and the ``patternfit convert`` command."""

import json

import pytest
from typer.testing import CliRunner

from patternfit.cli.main import app
from patternfit.pattern import (Edge, Loop, Panel, Pattern, PatternError, Seam, SeamSide,
                                save_pattern)
from patternfit.pattern.formats import load_any_pattern, save_any_pattern, sniff_format


def _pattern():
    def panel(name):
        return Panel(name, Loop("outline", (
            Edge.line("hem", (0, 0), (0.3, 0)), Edge.line("side", (0.3, 0), (0.3, 0.4)),
            Edge.quadratic("top", (0.3, 0.4), (0.15, 0.45), (0, 0.4)),
            Edge.line("centre", (0, 0.4), (0, 0)))))
    return Pattern("p", (panel("front"), panel("back")),
                   (Seam("side", SeamSide("front", "side"), SeamSide("back", "centre")),))


def test_dispatch_by_ending_and_content(tmp_path):
    p = _pattern()
    ours = save_pattern(p, tmp_path / "ours.json")
    (gc,) = save_any_pattern(p, tmp_path / "x_specification.json")
    (gc2,) = save_any_pattern(p, tmp_path / "plain.json", fmt="garmentcode")
    dxf, side = save_any_pattern(p, tmp_path / "p.dxf")
    assert side.name == "p.seams.json"
    assert [sniff_format(f) for f in (ours, gc, gc2, dxf)] == \
        ["patternfit", "garmentcode", "garmentcode", "dxf"]
    for f in (ours, gc, gc2, dxf):
        q = load_any_pattern(f)
        assert [x.name for x in q.panels] == ["front", "back"]
        assert q.seams == p.seams
        assert q.panel("front").outline.length == pytest.approx(p.panel("front").outline.length,
                                                                rel=1e-6)
    assert load_any_pattern(gc).meta["source_format"] == "garmentcode"


@pytest.mark.parametrize("name", ["p.dxf", "p_specification.json", "p.json"])
def test_a_stated_anchor_is_kept_by_every_writer(tmp_path, name):
    """A skirt stated as hung from the neck failed its drape as JSON and passed converted to
    DXF or GarmentCode ("loose"): the stated anchor was dropped, and the garment read back
    hung from where its panels say. Not stated, none is written."""
    from dataclasses import replace

    from patternfit.pattern.validate import check_pattern

    p = _pattern()
    stated = replace(p, meta={**p.meta, "anchor": "neck"})
    save_any_pattern(stated, tmp_path / name)
    assert load_any_pattern(tmp_path / name).meta.get("anchor") == "neck"
    save_any_pattern(p, tmp_path / name)
    assert "anchor" not in load_any_pattern(tmp_path / name).meta
    # a bad one is refused, written or read back (read, naming the file and its key: a
    # GarmentCode file's was taken, and meshing failed naming neither)
    bad = replace(p, meta={**p.meta, "anchor": "bust"})
    with pytest.raises(PatternError, match="anchor"):
        save_any_pattern(bad, tmp_path / name)
        check_pattern(load_any_pattern(tmp_path / name))
    save_any_pattern(stated, tmp_path / name)
    written = next(f for f in (tmp_path / "p.seams.json", tmp_path / name)
                   if f.exists() and f.suffix == ".json" and "anchor" in f.read_text())
    written.write_text(written.read_text().replace('"neck"', '"hips"'))
    with pytest.raises(PatternError, match="'hips'") as info:
        load_any_pattern(tmp_path / name)
    assert written.name in str(info.value) or name in str(info.value)


def test_a_converted_file_is_read_by_the_json_reader_and_keeps_its_origin(tmp_path):
    """convert coat.dxf coat.json, then coat.json read back said "(dxf-aama)"."""
    dxf, _ = save_any_pattern(_pattern(), tmp_path / "p.dxf")
    (back,) = save_any_pattern(load_any_pattern(dxf), tmp_path / "p.json")
    q = load_any_pattern(back)
    assert q.meta["source_format"] == "patternfit" and q.meta["converted_from"] == "dxf-aama"
    ours = save_pattern(_pattern(), tmp_path / "o.json")
    assert "converted_from" not in load_any_pattern(ours).meta


def test_unknown_inputs_are_refused(tmp_path):
    (tmp_path / "a.json").write_text(json.dumps({"hello": 1}))
    with pytest.raises(PatternError, match="neither") as info:
        load_any_pattern(tmp_path / "a.json")
    assert info.value.file == str(tmp_path / "a.json")
    (tmp_path / "a.obj").write_text("v 0 0 0")
    with pytest.raises(PatternError, match="cannot read '.obj'"):
        load_any_pattern(tmp_path / "a.obj")
    with pytest.raises(ValueError, match="cannot tell"):
        save_any_pattern(_pattern(), tmp_path / "x.txt")
    with pytest.raises(ValueError, match="fmt"):
        save_any_pattern(_pattern(), tmp_path / "x.json", fmt="obj")


def test_cli_convert_chain(tmp_path):
    runner = CliRunner()
    src = save_pattern(_pattern(), tmp_path / "p.json")
    r = runner.invoke(app, ["convert", str(src), str(tmp_path / "p.dxf"), "--json"])
    assert r.exit_code == 0, r.output
    out = json.loads(r.stdout)
    assert out["source_format"] == "patternfit" and out["seams"] == 1
    r = runner.invoke(app, ["convert", str(tmp_path / "p.dxf"), str(tmp_path / "g.json"),
                            "--to", "garmentcode", "--json"])
    assert r.exit_code == 0, r.output
    assert "pattern" in json.loads((tmp_path / "g.json").read_text())
    for target in ("p.svg", "p.pdf", "back.json"):
        r = runner.invoke(app, ["convert", str(tmp_path / "g.json"), str(tmp_path / target)])
        assert r.exit_code == 0, r.output
        assert (tmp_path / target).stat().st_size > 0
    r = runner.invoke(app, ["convert", str(tmp_path / "missing.json"), str(tmp_path / "x.dxf")])
    assert r.exit_code == 2 and "cannot read file" in r.output


def test_from_units_reads_a_dxf_whose_unit_is_not_said(tmp_path):
    """A DXF drawn in inches with no unit in it reads in millimetres, 25 times too small;
    the warning offers every plausible reading and the way to pick one on the command
    line, ``--from-units``, which a JSON file (stating its own units) refuses."""
    pattern = _pattern()
    dxf = tmp_path / "p.dxf"
    save_any_pattern(pattern, dxf)
    text = dxf.read_text()
    dxf.write_text(text.replace("Units: METRIC", "Units: none"))  # a file that says nothing
    runner = CliRunner()
    r = runner.invoke(app, ["convert", str(dxf), str(tmp_path / "mm.json"), "--json"])
    assert r.exit_code == 0, r.output
    plain = load_any_pattern(dxf)
    r = runner.invoke(app, ["convert", str(dxf), str(tmp_path / "in.json"), "--from-units",
                            "in"])
    assert r.exit_code == 0, r.output
    inches = load_any_pattern(tmp_path / "in.json")
    assert inches.panels[0].area() == pytest.approx(plain.panels[0].area() * 25.4 ** 2,
                                                    rel=1e-6)
    r = runner.invoke(app, ["convert", str(tmp_path / "in.json"), str(tmp_path / "x.json"),
                            "--from-units", "in"])
    assert r.exit_code == 2 and "set for a DXF only" in r.output
