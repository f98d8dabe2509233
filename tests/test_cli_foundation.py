import json
from pathlib import Path

import numpy as np
import pytest
import trimesh
import typer
from typer.testing import CliRunner

from patternfit.cli.main import app
from patternfit.fit.colormap import NEUTRAL
from patternfit.mesh.store import load_garment

runner = CliRunner()


def test_help_on_every_command():
    result = runner.invoke(app, ["--help"])
    assert result.exit_code == 0
    commands = [c.name or c.callback.__name__ for c in app.registered_commands]
    assert {"patterns", "mesh", "fit", "demo"} <= set(commands)
    for name in commands:
        r = runner.invoke(app, [name, "--help"])
        assert r.exit_code == 0, name
        assert "Usage" in r.output


@pytest.mark.parametrize("group", [[], ["reproduce"]])
def test_the_command_list_shows_one_line_per_command(group):
    """Each command's summary is its help's first paragraph joined on one line (Typer kept the
    docstring's line breaks there, so a summary showed as a ragged three-line entry)."""
    r = runner.invoke(app, [*group, "--help"], env={"COLUMNS": "300"})
    assert r.exit_code == 0
    panel = r.output.split("Commands")[1].split("╰")[0].splitlines()[1:]
    command = typer.main.get_command(app)
    for name in group:
        command = command.commands[name]
    assert [line.strip("│ ").split()[0] for line in panel] == list(command.commands), panel

@pytest.mark.parametrize("args, shown", [
    (["patterns"], "skirt"), (["bodies"], "female_average"), (["fabrics"], "denim"),
    (["fabrics", "denim"], "denim"), (["seams", "skirt"], "side_l")])
def test_a_listing_goes_to_standard_output(args, shown):
    """A listing is piped and kept (``patternfit fabrics | grep denim``; ``patternfit
    patterns > list.txt`` wrote an empty file: every table went to standard error); an
    error stays on standard error."""
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    assert shown in result.stdout and shown not in result.stderr
    refused = runner.invoke(app, [args[0], "no-such-thing.json"])
    assert refused.exit_code == 2 and "error" in refused.stderr and not refused.stdout


def test_patterns_json_and_write(tmp_path):
    r = runner.invoke(app, ["patterns", "--json"])
    rows = json.loads(r.stdout)
    assert {row["name"]: (row["panels"], row["seams"]) for row in rows}["trousers"] == (4, 8)
    out = tmp_path / "skirt.json"
    r = runner.invoke(app, ["patterns", "skirt", "--size", "XL", "--out", str(out)])
    assert r.exit_code == 0 and json.loads(out.read_text())["meta"]["size"] == "XL"
    r = runner.invoke(app, ["patterns", "cape", "--out", str(out)])
    assert r.exit_code == 2 and "unknown garment" in r.output


def test_demo_writes_outputs_at_perfect_fit(tmp_path):
    out = tmp_path / "demo"
    r = runner.invoke(app, ["demo", "--no-drape", "--out", str(out), "--triangles", "12000",
                            "--json"])
    assert r.exit_code == 0, r.output
    report = json.loads(r.stdout)
    # the paper's Fig. 8(b); only the chords of the curved placement differ, O(h^2)
    assert f"{report['fitting_ratio'] * 100:.2f}" == "100.00"
    assert report["fit_classes"]["fit"] == pytest.approx(1.0)
    # a placement is not a drape: nothing says it rests, so it does not pass either
    assert report["checks"]["passed"] is None and report["checks"]["equilibrium"] is None
    assert report == json.loads((out / "report.json").read_text())
    for f in ("garment.glb", "garment.obj", "fit_2d.png", "fit_2d.svg", "fit_3d.png"):
        assert (out / f).stat().st_size > 1000, f
    assert (out / "fit_2d.png").read_bytes()[:4] == b"\x89PNG"
    assert "<svg" in (out / "fit_2d.svg").read_text()[:2000]
    glb = trimesh.load(out / "garment.glb", force="mesh", process=False)
    assert len(glb.faces) == report["mesh"]["triangles"]
    # uniform neutral colour after an isometric placement
    assert np.allclose(glb.visual.vertex_colors[:, :3] / 255, NEUTRAL, atol=1 / 255)


def test_mesh_then_fit_of_saved_state(tmp_path):
    r = runner.invoke(app, ["mesh", "dress", "-n", "1200", "--out", str(tmp_path / "g"),
                            "--json"])
    info = json.loads(r.stdout)
    assert info["min_angle_deg"] >= 25
    r = runner.invoke(app, ["fit", "--garment", str(tmp_path / "g"), "--out", str(tmp_path)])
    assert r.exit_code == 2 and "no 3D state" in r.output
    # give it a state: the flat pattern stretched by 10 % in y
    from patternfit.mesh.store import save_garment
    pattern, mesh, _ = load_garment(tmp_path / "g")
    x = np.column_stack([mesh.vertices[:, 0], 1.1 * mesh.vertices[:, 1],
                         np.zeros(mesh.n_vertices)])
    save_garment(tmp_path / "g", pattern, mesh, x)
    r = runner.invoke(app, ["fit", "-g", str(tmp_path / "g"), "-o", str(tmp_path / "f"),
                            "--no-pictures", "--json"])
    assert r.exit_code == 0, r.output
    assert json.loads(r.stdout)["fitting_ratio"] == pytest.approx(1 / 1.1)


def test_mesh_reports_bad_file(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text("{")
    r = runner.invoke(app, ["mesh", str(bad), "--out", str(tmp_path / "o")])
    assert r.exit_code == 2 and "bad.json" in r.output and "not valid JSON" in r.output


def test_drape_progress_shows_how_far_from_rest():
    """The bar shows the force residual against the rest threshold when the solver gives it,
    and still runs on the four values the dynamic engine gives."""
    from patternfit.cli.show import drape_progress

    bar, callback = drape_progress(total=100, rest=0.01)
    callback(7, -0.5, 2e-4, 1.0, residual=0.345)
    info = bar.tasks[0].fields["info"]
    assert "force residual 0.345 × weight (rest ≤ 0.01)" in info and "it 7" in info
    assert bar.tasks[0].completed == 7
    callback(8, -0.5, 1e-4, 1.1, residual=1234.5)
    assert "force residual 1234 × weight" in bar.tasks[0].fields["info"]
    callback(9, -0.5, 1e-4, 1.1)  # the Newton engine: no residual
    assert "residual" not in bar.tasks[0].fields["info"]


@pytest.mark.parametrize("args", [
    ["drape", "--pattern", "skirt", "--body", "female_average"],
    ["correct", "--pattern", "skirt", "--body", "female_average"],
    ["demo"],
    ["mesh", "skirt"],
    ["batch", "--pattern", "skirt", "--sizes", "S", "--bodies", "female_average",
     "--workers", "0"],
    ["fabric-test", "strip", "--fabric", "cotton_shirting"],
])
def test_an_output_folder_that_is_a_file_is_refused_before_any_work(tmp_path, args,
                                                                      monkeypatch):
    """correct, demo and drape failed with "afile: File exists" only after the whole drape."""
    import patternfit.api as api

    def no_work(*a, **k):
        raise AssertionError("work started before --out was checked")

    for name in ("drape_and_evaluate", "design_session", "drafted_too_small", "read_pattern",
                 "read_fabric_with_notes"):
        monkeypatch.setattr(api, name, no_work)
    mine = tmp_path / "notes.txt"
    mine.write_text("mine")
    res = runner.invoke(app, [*args, "--out", str(mine)])
    said = " ".join(res.output.replace("│", " ").split())  # Rich's box, wrapped
    assert res.exit_code == 2 and "is a file, not a folder" in said, res.output
    assert mine.read_text() == "mine"
    res = runner.invoke(app, [*args, "--out", str(mine / "inside")])
    said = " ".join(res.output.replace("│", " ").split())
    assert res.exit_code == 2 and "cannot make the folder" in said, res.output
    if Path("/proc/self").is_dir():  # where access() says yes to root, and mkdir fails
        res = runner.invoke(app, [*args, "--out", "/proc/nope"])
        said = " ".join(res.output.replace("│", " ").split())
        assert res.exit_code == 2 and "cannot make the folder" in said, res.output


@pytest.mark.parametrize("error", [KeyboardInterrupt(), SystemError("returned a result")])
def test_ctrl_c_anywhere_exits_130_in_one_line(monkeypatch, error):
    """Click said "Aborted!" with status 1; an interrupt inside a numba kernel (a
    SystemError caused by it) was an "internal error", status 3."""
    import patternfit.api as api

    def interrupted(*args, **kwargs):
        if isinstance(error, SystemError):
            raise error from KeyboardInterrupt()
        raise error

    monkeypatch.setattr(api, "read_pattern", interrupted)
    res = runner.invoke(app, ["seams", "skirt"])
    assert res.exit_code == 130 and "interrupted" in res.output, res.output
    assert "internal error" not in res.output and "Aborted" not in res.output


def test_a_reader_gone_away_ends_quietly(monkeypatch):
    """``patternfit drape --help | head``: "internal error: BrokenPipeError", status 3."""
    import patternfit.api as api

    def gone(*args, **kwargs):
        raise BrokenPipeError(32, "Broken pipe")

    monkeypatch.setattr(api, "read_pattern", gone)
    res = runner.invoke(app, ["seams", "skirt"])
    assert res.exit_code == 141 and "internal error" not in res.output, res.output


def test_fit_refuses_a_fabric_without_a_body(tmp_path):
    """--fabric was never read without --body: a file that does not exist exited 0."""
    res = runner.invoke(app, ["fit", "--garment", str(tmp_path), "--fabric", "nonexistent.json",
                              "--out", str(tmp_path / "o")])
    assert res.exit_code == 2 and "--fabric is used with --body only" in res.output, res.output
    assert not (tmp_path / "o").exists()  # a refused command leaves no output folder behind


@pytest.mark.parametrize("how", ["ctrl-c", "sigterm"])
def test_a_stopped_drape_writes_the_state_reached_and_exits_130(tmp_path, monkeypatch, how):
    """The stopped drape was written and the command exited 1, a failed garment's status.
    ``timeout`` ends a command with SIGTERM: the process died at once, its log empty and
    nothing of the drape written; it now stops as Ctrl-C stops it, and the handler before
    it is back afterwards."""
    import contextlib
    import os
    import signal

    import patternfit.cli.drape as drape_cli

    def stop(iteration, *rest, **kw):
        if iteration == 3:
            if how == "sigterm":
                os.kill(os.getpid(), signal.SIGTERM)
            else:
                raise KeyboardInterrupt

    before = signal.getsignal(signal.SIGTERM)
    monkeypatch.setattr(drape_cli, "drape_progress",
                        lambda **kw: (contextlib.nullcontext(), stop))
    out = tmp_path / "d"
    res = runner.invoke(app, ["drape", "--pattern", "skirt", "--body", "female_average",
                              "--triangles", "300", "--no-pictures", "--out", str(out)])
    assert res.exit_code == 130 and "interrupted: the state reached" in res.output, res.output
    report = json.loads((out / "report.json").read_text())
    assert report["checks"]["passed"] is False and report["verdict"] == "failed"
    assert "interrupted" in json.dumps(report["checks"]["reasons"])
    assert signal.getsignal(signal.SIGTERM) is before


def test_a_saved_state_read_alone_is_not_checked_and_one_not_at_rest_fails(tmp_path):
    """fit without --body wrote checks.passed true, exit 0, green maps, for a skirt that had
    fallen past the hips; with --body, a drape saved before it came to rest read "too
    loose", exit 0 (contact.npz said at_rest false)."""
    from patternfit.mesh.triangulate import mesh_pattern
    from patternfit.mesh.store import save_garment
    from patternfit.pattern.library import build

    skirt = build("skirt", "M")
    mesh = mesh_pattern(skirt, triangles=300)
    x = np.c_[mesh.vertices, np.ones(mesh.n_vertices)]
    save_garment(tmp_path / "g", skirt, mesh, x, contact={"at_rest": np.asarray(True)})
    res = runner.invoke(app, ["fit", "--garment", str(tmp_path / "g"), "--out",
                              str(tmp_path / "a"), "--json", "--no-pictures"])
    assert res.exit_code == 0, res.output
    checks = json.loads(res.stdout)["checks"]
    assert checks["passed"] is None and "not checked" in checks["reasons"][-1]
    save_garment(tmp_path / "g", skirt, mesh, x, contact={"at_rest": np.asarray(False)})
    for body in ([], ["--body", "female_average"]):
        res = runner.invoke(app, ["fit", "--garment", str(tmp_path / "g"), "--out",
                                  str(tmp_path / "b"), "--no-pictures", *body])
        assert res.exit_code == 1 and "had not come to rest" in res.output, res.output
    # the exported garment says so too, parted from its report
    head = (tmp_path / "b" / "garment.obj").read_text().splitlines()[0]
    assert head.startswith("# patternfit ") and json.loads(head[13:])["checks_passed"] is False
    (glb,) = trimesh.load(tmp_path / "b" / "garment.glb").geometry.values()
    assert glb.metadata["patternfit"]["checks_passed"] is False
    assert any("had not come to rest" in r for r in glb.metadata["patternfit"]["reasons"])


def test_a_saved_state_moved_since_its_drape_is_not_said_to_be_at_rest(tmp_path):
    """A drape at rest, its positions then lifted 3 cm with its contact.npz kept: fit said
    "equilibrium: true" (a drape from there moved 20.6 mm over 981 iterations). The contact
    state holds the digest of the positions it was saved with; other positions are of a
    state whose rest is not known."""
    from patternfit.mesh.store import (MESH_DIGEST, POSITIONS_DIGEST, load_contact,
                                       mesh_digest, positions_digest, save_garment,
                                       saved_rest)
    from patternfit.mesh.triangulate import mesh_pattern
    from patternfit.pattern.library import build

    skirt = build("skirt", "M")
    mesh = mesh_pattern(skirt, triangles=300)
    x = np.c_[mesh.vertices, np.ones(mesh.n_vertices)]
    of = {POSITIONS_DIGEST: np.asarray(positions_digest(x)),
          MESH_DIGEST: np.asarray(mesh_digest(mesh))}
    save_garment(tmp_path / "g", skirt, mesh, x, contact={"at_rest": np.asarray(True), **of})
    contact = load_contact(tmp_path / "g")
    assert saved_rest(contact, x, mesh=mesh) == (True, None)
    assert saved_rest(contact, x + [0.0, 0.03, 0.0]) == (
        None, "contact.npz was saved for other positions (moved since)")
    # one that does not say what it is a state of (an older file) is not trusted either: an
    # edited pattern's and another body's read at rest through it
    assert saved_rest({"at_rest": np.asarray(True)}, x)[0] is None
    np.save(tmp_path / "g" / "positions.npy", x + [0.0, 0.03, 0.0])  # moved by hand
    res = runner.invoke(app, ["fit", "--garment", str(tmp_path / "g"), "--out",
                              str(tmp_path / "a"), "--json", "--no-pictures"])
    assert json.loads(res.stdout)["checks"]["equilibrium"] is None, res.output
    # a flag that is not one true or false is refused, not read as true ("False" is truthy)
    for flag in (np.asarray("False"), np.asarray(np.nan), np.asarray([True, False])):
        save_garment(tmp_path / "g", skirt, mesh, x, contact={"at_rest": flag, **of})
        res = runner.invoke(app, ["fit", "--garment", str(tmp_path / "g"), "--out",
                                  str(tmp_path / "b"), "--no-pictures"])
        assert res.exit_code == 2 and "contact.npz: array 'at_rest'" in res.output, res.output
    # ... and so are a fabric or a residual that are not one
    ok = np.asarray(True)
    for name, value in (("fabric_json", np.asarray("{not json")),
                        ("fabric_json", np.asarray('{"name": "x", "density": -1}')),
                        ("fabric_json", np.asarray([1.0, 2.0])),
                        ("residual_rms", np.asarray("0.001")),
                        ("drape_reasons", np.asarray("{not json")),
                        ("drape_reasons", np.asarray("[1, 2]")),
                        ("residual_p99", np.asarray(np.nan))):
        other = {"residual_rms": np.asarray(0.001), "residual_p99": np.asarray(0.01)}
        save_garment(tmp_path / "g", skirt, mesh, x,
                     contact={**other, **of, "at_rest": ok, name: value})
        res = runner.invoke(app, ["fit", "--garment", str(tmp_path / "g"), "--out",
                                  str(tmp_path / "b"), "--no-pictures"])
        assert res.exit_code == 2 and f"contact.npz: array '{name}'" in res.output, res.output
