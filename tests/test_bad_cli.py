"""Bad command-line inputs end in one clean line on standard error (the CLI's one error
boundary), never a traceback, an exhausted memory or an accepted garment that is no garment."""

import json
import os
import re
import subprocess
import sys
import warnings

import numpy as np
import pytest
from typer.testing import CliRunner

from patternfit.cli.main import app
from patternfit.files import read_json_file
from patternfit.mesh import GarmentMesh, mesh_pattern
from patternfit.mesh.store import save_garment
from patternfit.pattern import load_pattern, save_pattern

from scenes import two_panels

runner = CliRunner()


def refused(r, *names, code=2):
    """``r`` failed with ``code``, one clean message naming each of ``names``."""
    assert r.exit_code == code, r.output
    assert "Traceback" not in r.output, r.output
    assert r.exception is None or isinstance(r.exception, SystemExit), repr(r.exception)
    for n in names:
        assert n in r.output, (n, r.output)


@pytest.fixture
def pattern_file(tmp_path):
    path = tmp_path / "p.json"
    save_pattern(two_panels(), path, units="cm")
    return path


def test_missing_files_are_named(tmp_path):
    missing = str(tmp_path / "nowhere.json")
    refused(runner.invoke(app, ["mesh", missing, "-o", str(tmp_path / "m")]), "nowhere.json")
    refused(runner.invoke(app, ["convert", missing, str(tmp_path / "x.svg")]), "nowhere.json")
    refused(runner.invoke(app, ["fit", "-g", str(tmp_path / "gone"), "-o", str(tmp_path / "f")]),
            "gone")
    refused(runner.invoke(app, ["edit", missing, "grade", "--sx", "2", "-o",
                                str(tmp_path / "q.json")]), "nowhere.json")


def test_a_long_path_is_printed_whole_on_one_line(tmp_path, pattern_file):
    """A path longer than a terminal (a CI log's 80 columns) is not broken across lines, in
    an error of ours or of an option check, so that it can be copied from the message."""
    deep = tmp_path.joinpath(*["a_folder_with_a_long_name"] * 6)
    deep.mkdir(parents=True)
    missing, mesh = str(deep / "nowhere.json"), str(deep / "nowhere.npz")
    for whole, args in ((missing, ["mesh", missing, "-o", str(tmp_path / "m")]),
                        (missing, ["edit", missing, "grade", "--sx", "2", "-o",
                                   str(tmp_path / "q.json")]),
                        (mesh, ["edit", str(pattern_file), "grade", "--sx", "2", "--mesh", mesh,
                                "-o", str(tmp_path / "q.json")])):
        r = runner.invoke(app, args)
        refused(r, whole)
        assert any(whole in line for line in r.output.splitlines()), r.output
    assert not (tmp_path / "q.json").exists()  # the missing mesh was refused before writing


def test_non_utf8_pattern_is_named(tmp_path):
    bad = tmp_path / "latin1.json"
    bad.write_bytes(b'{"format": "patternfit-pattern", "name": "caf\xe9"}')
    refused(runner.invoke(app, ["mesh", str(bad), "-o", str(tmp_path / "m")]), "latin1.json")
    refused(runner.invoke(app, ["convert", str(bad), str(tmp_path / "x.svg")]), "latin1.json")


def test_device_as_fabric_is_refused_before_reading_it(tmp_path):
    r = runner.invoke(app, ["drape", "-f", "/dev/zero", "-n", "200", "-o", str(tmp_path / "d")])
    refused(r, "/dev/zero")


@pytest.mark.parametrize("value", ["1e23", "100000000000000000000000", "0", "-5"])
@pytest.mark.parametrize("command", [["mesh", "skirt"], ["drape"], ["demo"],
                                     ["correct", "-b", "female_thin", "-p", "skirt"],
                                     ["reproduce", "variants"], ["reproduce", "table2"]])
def test_absurd_triangle_counts_are_refused_by_every_command(tmp_path, command, value):
    r = runner.invoke(app, [*command, "--triangles", value, "-o", str(tmp_path / "o")]
                      if command[0] != "reproduce" else [*command, "--triangles", value])
    refused(r, "--triangles")
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("command", [["mesh", "skirt"], ["drape"], ["demo"], ["fit", "-g", "x"],
                                     ["correct", "-b", "female_thin", "-p", "skirt"],
                                     ["batch", "--pattern", "skirt"],
                                     ["reproduce", "variants", "--figures"],
                                     ["reproduce", "table2", "--figures"],
                                     ["studio", "--no-browser", "--session"]])
def test_an_empty_output_folder_is_refused_by_every_command(tmp_path, command, monkeypatch):
    """Read as ".", it wrote into the current folder unasked (found on fabric-test; the
    studio's session went there too)."""
    monkeypatch.chdir(tmp_path)
    option = [] if command[-1] in ("--figures", "--session") else ["--out"]
    refused(runner.invoke(app, [*command, *option, ""]), "empty")
    assert not os.listdir(tmp_path)
    # and a default folder taken as it is (the demo's, the figures' and the studio's are
    # paths: the parser read one as text, an internal error); refused on another option
    default = {"studio": (["studio", "--port", "-1"], 2),
               "demo": (["demo", "--no-drape", "--triangles", "300"], 0),
               "reproduce": ([*command[:-1], "--triangles", "-1"], 2)}.get(command[0])
    if default:
        r = runner.invoke(app, default[0])
        assert r.exit_code == default[1] and "internal error" not in r.output, r.output


@pytest.mark.parametrize("args, names", [
    (["--time-limit", "0"], ["--time-limit", "> 0"]),
    (["--time-limit", "-5"], ["--time-limit"]),
    (["--pressure-max", "-1"], ["--pressure-max"]),
    (["--clearance", "-0.1"], ["clearance", "0.3 m"]),
    (["--clearance", "100"], ["clearance", "100"]),
    (["--units", "furlong"], ["units", "furlong"]),
])
def test_drape_options_out_of_their_range_are_refused_before_draping(tmp_path, args, names):
    """Each refused at once with its name (a 0 s time limit used to run no iteration and
    report the sewing failed; a 100 m clearance draped for a minute with seams 187 m open;
    an unknown unit was ignored with a built-in body)."""
    refused(runner.invoke(app, ["drape", "-n", "200", "-o", str(tmp_path / "d"), *args]),
            *names)
    assert not (tmp_path / "d" / "report.json").exists()


def test_help_texts_and_tables_show_their_units():
    """Rich reads "[m]" as a style tag and drops it unless escaped."""
    def shown(*args):  # the words, without the boxes and line breaks
        return re.sub(r"[\s│]+", " ", runner.invoke(app, list(args)).output)

    text = shown("drape", "--help")
    for unit in ("placement [m]", "drape [s]", "tight [kPa]", "patternfit[new"):
        assert unit in text, unit
    assert "hip [m]" in shown("bodies")
    assert "Offset in x [m]" in shown("edit", "--help")


@pytest.mark.parametrize("args, names", [
    (["grade", "--sx", "1e300"], ["sx", "[0.1, 10]"]),
    (["grade", "--panel", "A", "--sy", "0"], ["sy", "panel 'A'"]),
    (["grade", "--sx", "-1"], ["sx"]),
    (["grade", "--sx", "nan"], ["sx"]),
    (["lengthen", "--panel", "A", "--a", "0.2,0", "--b", "0.2,0.6", "--amount", "-10"],
     ["panel 'A'", "amount=-10", "inside out"]),
    (["lengthen", "--panel", "A", "--a", "0.2,0", "--b", "0.2,0.6", "--amount", "-10",
      "--partner"], ["panel 'A'", "amount=-10", "inside out"]),
    (["lengthen", "--panel", "A", "--a", "0.2,0", "--b", "0.2,0.6", "--amount", "1e30"],
     ["panel 'A'", "amount"]),
    (["move-edge", "--panel", "A", "--edge", "top", "--dy", "1e30", "--partner"],
     ["panel 'A'", "offset"]),
    (["move-point", "--panel", "A", "--edge", "left", "--dx", "1e30"], ["panel 'A'", "offset"]),
    (["edit-curve", "--panel", "A", "--edge", "top", "--dy", "-1e30"], ["panel 'A'", "offset"]),
    (["move-edge", "--panel", "A", "--edge", "left", "--dx", "25"],
     ["panel 'A'", "offset=(25, 0) m", "beyond the limit of 20 m"]),
    (["move-edge", "--panel", "Z", "--edge", "top", "--dy", "0.1"], ["panel 'Z'", "A, B"]),
    (["move-edge", "--panel", "A", "--edge", "hem", "--dy", "0.1"], ["edge 'hem'"]),
    (["insert-dart", "--panel", "A", "--dart", "d", "--centre", "0.2,0.3", "--length", "1e30",
      "--width", "0.02"], ["panel 'A'", "length"]),
    (["insert-dart", "--panel", "A", "--dart", "d", "--centre", "0.2,0.3", "--length", "0.1",
      "--width", "0"], ["panel 'A'", "width"]),
])
def test_edits_that_are_no_garment_are_refused(tmp_path, pattern_file, args, names):
    out = tmp_path / "q.json"
    before = pattern_file.read_bytes()
    refused(runner.invoke(app, ["edit", str(pattern_file), *args, "-o", str(out)]), *names)
    assert not out.exists() and pattern_file.read_bytes() == before


def test_fit_of_a_collapsed_state_fails_with_a_message(tmp_path):
    p = two_panels()
    m = mesh_pattern(p, triangles=200)
    save_garment(tmp_path / "g", p, m, np.zeros((m.n_vertices, 3)))
    out = tmp_path / "f"
    r = runner.invoke(app, ["fit", "-g", str(tmp_path / "g"), "-o", str(out), "--no-pictures",
                            "--json"])
    refused(r, "failed its checks", "not finite", "fitting_ratio", code=1)
    text = (out / "report.json").read_text()
    assert "NaN" not in text and "Infinity" not in text
    assert json.loads(text)["checks"]["passed"] is False


def test_unexpected_error_is_one_line_with_a_debug_hint(tmp_path, monkeypatch):
    def boom(*args, **kwargs):
        raise RuntimeError("kaboom\nsecond line")

    monkeypatch.setattr("patternfit.api.read_pattern", boom)
    r = runner.invoke(app, ["mesh", "skirt", "-o", str(tmp_path / "m")])
    refused(r, "internal error: RuntimeError: kaboom", "PATTERNFIT_DEBUG=1", code=3)
    assert "second line" not in r.output
    monkeypatch.setenv("PATTERNFIT_DEBUG", "1")
    r = runner.invoke(app, ["mesh", "skirt", "-o", str(tmp_path / "m")])
    assert isinstance(r.exception, RuntimeError)


def test_entry_point_has_the_same_boundary(tmp_path):
    env = {**os.environ, "PATTERNFIT_DEBUG": ""}
    r = subprocess.run([sys.executable, "-m", "patternfit.cli.main", "edit", str(tmp_path),
                        "grade"], capture_output=True, text=True, env=env, timeout=60)
    assert r.returncode == 2 and "Traceback" not in r.stderr + r.stdout
    bad = tmp_path / "bad.json"
    bad.write_text("{ not json")
    r = subprocess.run([sys.executable, "-m", "patternfit.cli.main", "convert", str(bad),
                        str(tmp_path / "x.svg")], capture_output=True, text=True, env=env,
                       timeout=60)
    assert r.returncode == 2 and r.stderr.startswith("error:") and "bad.json" in r.stderr
    assert "Traceback" not in r.stderr + r.stdout


def test_guessed_body_units_are_printed(tmp_path):
    import trimesh

    from patternfit.body import load_body

    b = load_body("female_average")
    # in a folder deep enough that the note's path is longer than a CI log's 80 columns
    deep = tmp_path.joinpath(*["a_folder_with_a_long_name"] * 4)
    deep.mkdir(parents=True)
    mesh_file = deep / "body_cm.ply"
    trimesh.Trimesh(b.vertices * 100, b.faces, process=False).export(mesh_file)
    # the fabric is refused after the body is read: the note comes without a drape
    r = runner.invoke(app, ["drape", "-b", str(mesh_file), "-f", "/dev/zero", "-o",
                            str(tmp_path / "d")])
    refused(r, "units guessed as 'cm'", "/dev/zero")
    assert any(f"{mesh_file}: units guessed" in line for line in r.output.splitlines()), r.output
    r = runner.invoke(app, ["drape", "-b", str(mesh_file), "--units", "cm", "-f", "/dev/zero",
                            "-o", str(tmp_path / "d")])
    refused(r, "/dev/zero")
    assert "guessed" not in r.output


def _fail_at_mesh_rename(monkeypatch, mesh_path):
    """Make the group write stop (as a kill would) just before the mesh is renamed."""
    real = os.replace

    def replace(src, dst):
        if os.path.realpath(dst) == os.path.realpath(mesh_path):
            raise OSError("killed")
        real(src, dst)

    monkeypatch.setattr("patternfit.files.os.replace", replace)


def test_in_place_edit_replaces_pattern_and_mesh_as_one_step(tmp_path, monkeypatch):
    src = tmp_path / "p.json"
    save_pattern(two_panels(), src, units="cm")
    mesh = tmp_path / "p.npz"
    mesh_pattern(two_panels(), triangles=300).save(mesh)
    _fail_at_mesh_rename(monkeypatch, mesh)
    r = runner.invoke(app, ["edit", str(src), "edit-curve", "--panel", "A", "--edge", "top",
                            "--dy", "0.05", "--in-place", "--mesh", str(mesh)])
    assert r.exit_code == 3 and "Traceback" not in r.output     # the "kill"
    monkeypatch.undo()
    # the next read finishes the replacement from the journal: both files are new
    assert read_json_file(src)["units"] == "cm"
    assert load_pattern(src).panel("A").edge("top").kind == "quadratic"
    m = GarmentMesh.load(mesh)
    top = [i for i, e in enumerate(m.edge_names) if e == ("A", "top")][0]
    on_top = m.vertices[m.boundary_vertices[m.boundary_edge == top]]
    assert on_top[:, 1].max() > 0.6 + 0.01      # the mesh followed the curve
    assert not [n for n in os.listdir(tmp_path) if n.startswith(".")]


def test_edit_writes_nothing_when_the_write_fails_before_the_journal(tmp_path, monkeypatch):
    src = tmp_path / "p.json"
    save_pattern(two_panels(), src, units="cm")
    mesh = tmp_path / "p.npz"
    mesh_pattern(two_panels(), triangles=300).save(mesh)
    before = src.read_bytes(), mesh.read_bytes()

    def no_journal(path, data):
        raise OSError("disk full")

    monkeypatch.setattr("patternfit.files.atomic_write_bytes", no_journal)
    r = runner.invoke(app, ["edit", str(src), "edit-curve", "--panel", "A", "--edge", "top",
                            "--dy", "0.05", "--in-place", "--mesh", str(mesh)])
    assert r.exit_code == 3 and "OSError: disk full" in r.output
    monkeypatch.undo()
    assert (src.read_bytes(), mesh.read_bytes()) == before


def test_a_library_warning_is_one_plain_line():
    """A warning raised inside a command (a placement replaced) reads ``warning: ...``, not
    Python's ``path.py:223: PlacementWarning: ...``."""
    import typer

    from patternfit.cli.app import _Boundary
    from patternfit.sim.panel_frames import PlacementWarning

    tool = typer.Typer(cls=_Boundary)

    @tool.command()
    def warn():
        warnings.warn(PlacementWarning("the placement of 'front' was replaced"))
        # the same text from another line (a drape's coarse and fine placements): once
        warnings.warn(PlacementWarning("the placement of 'front' was replaced"))

    @tool.command()
    def other():
        pass

    r = runner.invoke(tool, ["warn"])
    assert r.exit_code == 0, r.output
    assert "warning: the placement of 'front' was replaced" in r.output
    assert "PlacementWarning" not in r.output and ".py:" not in r.output
    assert r.output.count("was replaced") == 1


def test_a_journal_that_came_with_a_folder_replaces_nothing_elsewhere(pattern_file, tmp_path):
    """A ``.patternfit-commit-*.json`` naming a rename outside its folder (as a downloaded
    pattern folder could hold) is left alone: reading the pattern overwrote the named file."""
    victim = tmp_path / "elsewhere" / "notes.txt"
    victim.parent.mkdir()
    victim.write_text("mine")
    payload = pattern_file.parent / "payload.txt"
    payload.write_text("theirs")
    journal = pattern_file.parent / ".patternfit-commit-abc.json"
    journal.write_text(json.dumps({"renames": [[str(payload), str(victim)]]}))
    r = runner.invoke(app, ["seams", str(pattern_file)])
    assert r.exit_code == 0, r.output
    assert victim.read_text() == "mine" and payload.exists() and journal.exists()


@pytest.mark.parametrize("target", ["folder", "file as folder", "pipe"])
def test_an_output_that_cannot_be_a_file_is_refused_naming_it(pattern_file, tmp_path, target):
    """A folder, a file where a folder must be, a named pipe: exit 2 naming the path (they
    were internal errors, a pipe was replaced by a file) and no journal left behind (an
    edit whose mesh went to a folder left one, and every later read in the folder failed)."""
    out = tmp_path / "out"
    if target == "folder":
        out.mkdir()
        mesh = tmp_path / "m.npz"
        mesh_pattern(load_pattern(pattern_file), triangles=200).save(mesh)
        args = ["edit", str(pattern_file), "move-edge", "--panel", "A", "--edge", "top",
                "--dy", "0.01", "--partner", "--out", str(tmp_path / "e.json"),
                "--mesh", str(mesh), "--mesh-out", str(out)]
    elif target == "file as folder":
        out.write_text("mine")
        args = ["mesh", str(pattern_file), "-n", "200", "--out", str(out)]
    else:
        os.mkfifo(out)
        args = ["convert", str(pattern_file), str(out), "--to", "svg"]
    refused(runner.invoke(app, args), str(out))
    assert not [n for n in os.listdir(tmp_path) if n.startswith(".patternfit-commit")]
    if target == "pipe":
        assert not out.is_file()
    r = runner.invoke(app, ["seams", str(pattern_file)])
    assert r.exit_code == 0, r.output


def test_a_named_pipe_as_input_is_refused_not_waited_on(tmp_path):
    pipe = tmp_path / "in.json"
    os.mkfifo(pipe)
    refused(runner.invoke(app, ["convert", str(pipe), str(tmp_path / "o.json")]),
            "not a regular file")


def test_an_output_that_is_an_input_is_refused(pattern_file, tmp_path):
    """``convert x.dxf x.dxf`` replaced the CAD file; a mesh written over the pattern read,
    or over the pattern written, lost it (exit 0)."""
    before = pattern_file.read_bytes()
    refused(runner.invoke(app, ["convert", str(pattern_file), str(pattern_file)]),
            str(pattern_file), "is the input pattern")
    mesh = tmp_path / "m.npz"
    mesh_pattern(load_pattern(pattern_file), triangles=200).save(mesh)
    out = tmp_path / "e.json"
    for mesh_out in (out, pattern_file):
        refused(runner.invoke(app, ["edit", str(pattern_file), "move-edge", "--panel", "A",
                                    "--edge", "top", "--dy", "0.01", "--partner", "--out",
                                    str(out), "--mesh", str(mesh), "--mesh-out",
                                    str(mesh_out)]), "--mesh-out")
    assert pattern_file.read_bytes() == before and not out.exists()


def test_patterns_writes_the_format_its_ending_names(tmp_path):
    from patternfit.pattern.dxf import load_dxf

    out = tmp_path / "skirt.dxf"
    r = runner.invoke(app, ["patterns", "skirt", "--out", str(out)])
    assert r.exit_code == 0, r.output
    assert {p.name for p in load_dxf(out).panels} == {"front", "back"}  # it held JSON


def test_a_file_name_is_printed_as_it_is(pattern_file, tmp_path):
    """Rich read ":fire:" in a file name as an emoji code."""
    named = tmp_path / "coat:fire:v2.json"
    named.write_bytes(pattern_file.read_bytes())
    r = runner.invoke(app, ["convert", str(named), str(tmp_path / "o.json")])
    assert r.exit_code == 0 and "coat:fire:v2.json" in " ".join(r.output.split()), r.output


def test_a_pattern_read_but_not_writable_names_both_files(tmp_path):
    """A GarmentCode stitch joining a 40 cm edge to an 8 cm one is read (with a warning) but
    refused by our writer's check: the message said neither file."""
    from test_garmentcode import _doc, _square

    small = _square()
    small["vertices"] = [[x / 5, y / 5] for x, y in small["vertices"]]
    src = tmp_path / "gc_specification.json"
    src.write_text(json.dumps(_doc({"a": _square(), "b": small},
                                   [[{"panel": "a", "edge": 0}, {"panel": "b", "edge": 0}]])))
    out = tmp_path / "o.json"
    refused(runner.invoke(app, ["convert", str(src), str(out)]), str(src), str(out),
            "joins sides of different length")


def test_edit_of_another_format_says_to_convert_it(tmp_path):
    dxf = tmp_path / "skirt.dxf"
    assert runner.invoke(app, ["convert", "skirt", str(dxf)]).exit_code == 0
    refused(runner.invoke(app, ["edit", str(dxf), "move-edge", "--panel", "front", "--edge",
                                "hem", "--dy", "0.01", "--out", str(tmp_path / "e.json")]),
            "edit works on a patternfit JSON pattern", "patternfit convert")


def test_a_users_file_named_as_a_side_file_is_not_replaced(tmp_path):
    """Writing ``x.dxf`` writes ``x.seams.json`` beside it: a file of the user's own under
    that name was replaced without a word; one our writer made is replaced as before."""
    mine = tmp_path / "x.seams.json"
    mine.write_text("my notes")
    refused(runner.invoke(app, ["convert", "skirt", str(tmp_path / "x.dxf")]),
            "is not a side file patternfit wrote")
    assert mine.read_text() == "my notes" and not (tmp_path / "x.dxf").exists()
    for _ in range(2):
        r = runner.invoke(app, ["convert", "skirt", str(tmp_path / "y.dxf")])
        assert r.exit_code == 0, r.output


@pytest.mark.parametrize("content, said", [
    (b"", "empty file"), (b"  \n\t", "empty file"),
    (b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR", "a PNG image, not a JSON text file"),
    (b"%PDF-1.7\n", "a PDF document"), (b"PK\x03\x04\x14\0", "a ZIP archive")])
@pytest.mark.parametrize("command", [["fabrics"], ["convert"]])
def test_an_empty_or_binary_file_is_named_for_what_it_is(tmp_path, content, said, command):
    """A PNG picked for a fabric read "not UTF-8 text (byte 0: 0x89)", an empty file as a
    JSON syntax error at line 1, column 1."""
    f = tmp_path / "picked.json"
    f.write_bytes(content)
    args = [*command, str(f)] + ([str(tmp_path / "out.dxf")] if command == ["convert"] else [])
    r = runner.invoke(app, args)
    assert r.exit_code == 2 and said in " ".join(r.output.split()), r.output
    assert "picked.json" in r.output and "Traceback" not in r.output
