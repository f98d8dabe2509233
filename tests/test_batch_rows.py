"""The batch's bookkeeping without Ray: the plan, the result rows appended and read back to
resume (a partial last line from a killed batch dropped), the matrix and its one-line
answers, and a task whose drape raises becoming a failed row."""

from __future__ import annotations

import csv
import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patternfit.batch import (COLUMNS, Inputs, ResultLog, Task, TaskOptions, parse_sizes,
                              plan, read_rows, run_local, run_task, summary_lines,
                              verdict_of, write_matrix)
from patternfit.batch.rows import CSV_NAME, failed_row
from patternfit.errors import InputError


def _row(task, status="ok", ratio=0.97, **extra):
    row = {**task._asdict(), "status": status, "fitting_ratio": ratio,
           "fitting_ratio_symmetric": ratio, "checks_passed": status == "ok",
           "seconds": 1.5, "worker": "host:1"}
    return row | extra


def test_the_plan_holds_every_4_tuple_once():
    tasks = plan(["skirt"], ["S", "M", "S"], ["a", "b"], ["cotton", "denim"])
    assert len(tasks) == 2 * 2 * 2 == len(set(tasks))
    assert tasks[0] == Task("skirt", "S", "a", "cotton")
    for bad in ("", " ", "two\nlines", "cr\r"):
        with pytest.raises(ValueError, match="body: .* cannot name a task"):
            plan(["skirt"], ["S"], ["a", bad], ["cotton"])


def test_sizes_all_and_lists(tmp_path):
    assert parse_sizes("all", "skirt") == ["S", "M", "L", "XL"]
    assert parse_sizes("s, m", "skirt") == ["S", "M"]
    with pytest.raises(ValueError, match="--sizes: XXXL"):
        parse_sizes("M,XXXL", "skirt")
    with pytest.raises(ValueError, match="one size"):
        parse_sizes("all", str(tmp_path / "my.json"))
    # a graded DXF holds its sizes (they were refused: "drafted in one size")
    from test_dxf_aama import accumark, graded

    dxf = str(graded(accumark, tmp_path / "g.dxf"))
    assert parse_sizes("all", dxf) == ["34", "36", "38"]
    assert parse_sizes("34,38", dxf) == ["34", "38"]
    with pytest.raises(ValueError, match="40 not one of the file's sizes, 34, 36, 38"):
        parse_sizes("36,40", dxf)


def test_rows_survive_a_resume_and_a_killed_write(tmp_path):
    log = ResultLog(tmp_path, resume=False)
    done = plan(["skirt"], ["S", "M"], ["a"], ["cotton"])
    log.append(_row(done[0], ease_hip_cm=4.25, reasons="line one\nline two, \"quoted\""))
    log.append(_row(done[1], status="failed", ratio=None, failed_checks="on_body"))
    # a batch killed in the middle of its third write leaves half a line
    with open(tmp_path / CSV_NAME, "a") as fh:
        fh.write("skirt,L,a,cot")
    with pytest.raises(InputError, match="--resume"):
        ResultLog(tmp_path, resume=False)
    again = ResultLog(tmp_path, resume=True)
    assert again.done() == set(done)
    assert again.rows[0]["ease_hip_cm"] == 4.25 and again.rows[0]["fitting_ratio"] == 0.97
    assert again.rows[0]["reasons"] == "line one line two, \"quoted\""
    assert again.rows[1]["status"] == "failed" and again.rows[1]["fitting_ratio"] is None
    assert again.rows[1]["checks_passed"] is False
    # the partial line is gone from the file, the next row starts a line of its own
    again.append(_row(Task("skirt", "L", "a", "cotton")))
    with open(tmp_path / CSV_NAME, newline="") as fh:
        lines = list(csv.reader(fh))
    assert lines[0] == list(COLUMNS) and len(lines) == 4
    assert all(len(line) == len(COLUMNS) for line in lines)
    assert [r["size"] for r in read_rows(tmp_path / CSV_NAME)] == ["S", "M", "L"]


def test_another_csv_is_refused_by_name(tmp_path):
    (tmp_path / CSV_NAME).write_text("a,b,c\n1,2,3\n")
    with pytest.raises(InputError, match="not a patternfit batch result"):
        ResultLog(tmp_path, resume=True)
    header = ",".join(COLUMNS)
    (tmp_path / CSV_NAME).write_text(header + "\nskirt,S,a,cotton,ok\n")
    with pytest.raises(InputError, match="line 2"):
        read_rows(tmp_path / CSV_NAME)


def _one_line(s: str) -> bool:
    return bool(s.strip()) and " ".join(s.splitlines()) == s


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.text(min_size=1, max_size=12).filter(_one_line),
                          st.text(max_size=40),
                          st.floats(allow_nan=False, allow_infinity=False, width=32)),
                min_size=1, max_size=6, unique_by=lambda t: t[0]))
def test_any_text_round_trips(tmp_path_factory, items):
    folder = tmp_path_factory.mktemp("rows")
    log = ResultLog(folder, resume=True)
    for task, (_, reason, ratio) in zip(plan(["skirt"], ["M"], [b for b, _, _ in items],
                                             ["cotton"]), items):
        log.append(_row(task, ratio=ratio, reasons=reason))
    back = read_rows(folder / CSV_NAME)
    assert [r["body"] for r in back] == [b for b, _, _ in items]
    for r, (_, reason, ratio) in zip(back, items):
        assert r["fitting_ratio"] == pytest.approx(ratio, rel=1e-5, abs=1e-30)
        assert (r["reasons"] or "") == " ".join(reason.splitlines())


def test_verdicts_and_one_line_per_size():
    t = plan(["skirt"], ["S", "M"], ["a", "b", "c", "d"], ["cotton"])
    rows = [_row(t[0], ratio=0.80, verdict="fits", pressure_p99_kpa=1.9),
            _row(t[1], ratio=0.80, verdict="tight", ease_hip_cm=-2.0, ease_waist_cm=3.0,
                 verdict_regions="hip"),
            _row(t[2], status="failed", failed_checks="on_body"),
            # too tight at the waist by its pressure, though the hip has less ease: the
            # summary named the hip, where the drape's verdict said it fits
            _row(t[3], ratio=1.1, verdict="too tight", pressure_p99_kpa=8.2, ease_hip_cm=0.7,
                 ease_waist_cm=2.0, verdict_regions="waist"),
            _row(t[4], verdict="too tight", ease_waist_cm=-1.0, pressure_p99_kpa=0.5,
                 verdict_regions="waist thigh_left"),
            _row(t[5], verdict="fits", pressure_p99_kpa=3.0), _row(t[6], verdict="fits"),
            _row(t[7], status="failed", failed_checks="seams crossings", verdict="fits")]
    # the drape's own verdict, whatever ϖ or the pressure say (the verdict weighed them);
    # a failed drape is failed whatever it reads
    assert [verdict_of(r) for r in rows] == ["fits", "tight", "failed", "too tight",
                                             "too tight", "fits", "fits", "failed"]
    assert verdict_of(_row(t[0], ratio=0.5, pressure_p99_kpa=9.0)) == "no verdict"
    # a failed drape is failed whatever its row's verdict says (one written by an older
    # version, which read a slide as too loose)
    assert verdict_of(_row(t[0], status="failed", failed_checks="on_body crossings",
                           verdict="too loose")) == "failed"
    assert summary_lines(rows) == [
        "skirt in cotton, S: fits 1 of 4 bodies; tight on 1 at the hip; too tight on 1 at "
        "the waist; failed on 1 (on_body 1)",
        "skirt in cotton, M: fits 2 of 4 bodies; too tight on 1 at the waist 1, thigh left 1; "
        "failed on 1 (seams 1, crossings 1)"]


def test_the_matrix_has_a_cell_per_task(tmp_path):
    t = plan(["skirt"], ["S", "M"], ["a", "b"], ["cotton"])
    rows = [_row(t[0]), _row(t[1], status="failed", failed_checks="seams", reasons="open")]
    out = write_matrix(tmp_path, rows, tasks=t)
    assert out["png"].stat().st_size > 1000
    page = out["html"].read_text()
    assert page.count("<td") == 4 and page.count("no result yet") == 2
    assert "ϖ 97.0%" in page and "seams: open" in page
    assert "ϖ" not in page.split("seams: open")[0].rsplit("<td", 1)[1]  # no ϖ on a failure
    assert "thumbnails: the garment coloured by its area change, not its verdict" in page


def test_a_drape_that_raises_is_a_failed_row(tmp_path):
    task = Task("skirt", "M", "female_average", str(tmp_path / "no_such_fabric.json"))
    options = TaskOptions(triangles=300, time_limit=5.0)
    row = run_task(task, "female_average", options)
    assert row["status"] == "failed" and row["checks_passed"] is False
    assert "FabricError" in row["reasons"] and "no_such_fabric" in row["reasons"]
    log = ResultLog(tmp_path / "batch", resume=False)
    run_local([task], Inputs({"female_average": "female_average"}, {}, {}), log, options)
    assert [r["status"] for r in read_rows(log.path)] == ["failed"]
    assert failed_row(task, "x")["failed_checks"] == "error"


def test_ctrl_c_in_a_drape_stops_the_batch_without_a_row(tmp_path, monkeypatch):
    """The solver stops on Ctrl-C with its last state; the batch recorded that state as a
    failed row ("no equilibrium (stopped: interrupted)"), which --resume never redid, and
    went on with the next task."""
    from patternfit.batch import work

    real, seen = work.drape_and_evaluate, []

    def interrupted(*args, **kwargs):
        def progress(iteration, *rest, **kw):
            if iteration >= 3:
                raise KeyboardInterrupt
        outcome = real(*args, progress=progress, **kwargs)
        seen.append(outcome.interrupted)
        return outcome

    monkeypatch.setattr(work, "drape_and_evaluate", interrupted)
    log = _stopped_batch(tmp_path)
    assert seen == [True]
    assert not log.path.exists() or read_rows(log.path) == []


def _stopped_batch(tmp_path) -> ResultLog:
    """Two tasks run in this process, the first stopped by Ctrl-C: the batch's log."""
    tasks = [Task("skirt", s, "female_average", "cotton_shirting") for s in ("S", "M")]
    log = ResultLog(tmp_path / "batch", resume=False)
    with pytest.raises(KeyboardInterrupt):
        run_local(tasks, Inputs({"female_average": "female_average"}, {}, {}), log,
                  TaskOptions(triangles=300, time_limit=5.0))
    return log


def test_ctrl_c_in_a_compiled_kernel_before_the_solve_stops_the_batch(tmp_path, monkeypatch):
    """Ctrl-C landing in a numba kernel outside the solve (a body's first distance lookup)
    surfaces as a SystemError with the KeyboardInterrupt as its cause: it was a failed row
    ("SystemError: CPUDispatcher(...) returned a result with an exception set"), which
    --resume never redid, and the batch went on."""
    from patternfit.batch import work

    def in_kernel(*args, **kwargs):
        raise SystemError("CPUDispatcher(<function smooth_sdf_query>) returned a result "
                          "with an exception set") from KeyboardInterrupt()

    monkeypatch.setattr(work, "drape_and_evaluate", in_kernel)
    assert read_rows(_stopped_batch(tmp_path).path) == []


def test_the_command_line_loads_neither_ray_nor_the_solver_for_help():
    import subprocess
    import sys

    code = ("import sys; import patternfit.cli.main; "
            "print(sorted(m for m in ('ray', 'patternfit.api', 'patternfit.batch') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "[]"


def test_without_ray_the_batch_says_how_to_get_it(monkeypatch):
    import sys

    from patternfit.batch import RAY_MISSING, start_ray

    monkeypatch.setitem(sys.modules, "ray", None)
    with pytest.raises(ImportError, match=r"patternfit\[batch\].*--workers 0") as info:
        start_ray(2, None)
    assert str(info.value) == RAY_MISSING


def test_a_failed_drapes_thumbnail_has_no_fit_colours():
    """A thumbnail is grey where the drape failed its checks, as every failed picture: the
    fit colours (red to blue) are a passed drape's only."""
    import io
    from types import SimpleNamespace

    import numpy as np
    from PIL import Image

    from patternfit.batch.work import thumbnail_png

    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.1]], float)
    mesh = SimpleNamespace(triangles=np.array([[0, 1, 2], [1, 3, 2]]))
    fit = SimpleNamespace(area_change=np.array([0.1, -0.1]))

    def colourful(passed):
        png = thumbnail_png(SimpleNamespace(body=None, positions=v, mesh=mesh, fit=fit,
                                            passed=passed))
        rgb = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
        return (rgb.max(axis=2) - rgb.min(axis=2) > 40).mean()

    assert colourful(True) > 0.2 and colourful(False) == 0.0


def test_a_resume_with_other_settings_or_files_is_refused(tmp_path):
    """A resume at 300 triangles of a batch draped at 1,200 put both kinds of rows under
    one matrix, nothing in them to tell which; the summary counted the old batch's rows."""
    from patternfit import edit
    from patternfit.api import read_pattern, write_pattern
    from patternfit.batch import run_batch

    pattern = tmp_path / "skirt.json"
    write_pattern(read_pattern("skirt", size="M"), pattern)
    out = tmp_path / "b"
    first = run_batch(str(pattern), "M", "female_average,female_thin", "cotton_shirting", out,
                      triangles=300, workers=0, thumbnails=False)
    assert first["rows"] == 2 and (out / "batch.json").is_file()
    with pytest.raises(InputError, match="triangles = 300, this run with 200"):
        run_batch(str(pattern), "M", "female_average", "cotton_shirting", out,
                  triangles=200, workers=0, thumbnails=False, resume=True)
    # fewer bodies: the rows stay in the file, the answer is this run's task only
    again = run_batch(str(pattern), "M", "female_average", "cotton_shirting", out,
                      triangles=300, workers=0, thumbnails=False, resume=True)
    assert again["skipped"] == 1 and again["rows"] == 1 and len(read_rows(out / CSV_NAME)) == 2
    edited = read_pattern(str(pattern))  # the pattern file edited since: its hem let down
    write_pattern(edit.move_edge(edited, "front", "hem", (0.0, -0.02), partner=True), pattern)
    with pytest.raises(InputError, match="the file .*skirt.json is not the one"):
        run_batch(str(pattern), "M", "female_average", "cotton_shirting", out,
                  triangles=300, workers=0, thumbnails=False, resume=True)
    # a user's own batch.json is never replaced
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "batch.json").write_text('{"my": "notes"}')
    with pytest.raises(InputError, match="not a batch settings file"):
        run_batch("skirt", "M", "female_average", "cotton_shirting", mine, triangles=300,
                  workers=0, thumbnails=False)
    assert (mine / "batch.json").read_text() == '{"my": "notes"}'


def test_a_batch_says_what_its_patterns_reader_noticed(tmp_path):
    """A GarmentCode gather sewn in as ease was printed by ``drape`` and said by no batch
    (nor could a batch of a GarmentCode file run: it names no size, and every label the
    batch asked for, as --sizes M, was refused as "no size 'M' in the file")."""
    from typer.testing import CliRunner

    from patternfit.api import read_pattern, write_pattern
    from patternfit.cli.main import app

    pattern = tmp_path / "g_specification.json"
    write_pattern(read_pattern("gathered_skirt", size="M"), pattern)
    r = CliRunner().invoke(app, ["batch", "--pattern", str(pattern), "--sizes", "M",
                                 "--bodies", "female_average", "--fabrics", "cotton_shirting",
                                 "--triangles", "300", "--workers", "0", "--out",
                                 str(tmp_path / "b"), "--json"])
    assert r.exit_code == 0, r.output
    said = json.loads(r.stdout)["pattern_warnings"]
    assert said and all("different length" in w for w in said)


def test_a_pattern_that_cannot_drape_is_refused_before_the_tasks(tmp_path):
    """As ``drape`` refuses it (exit 2, naming the file): an unsewn pattern was a failed row
    for every task, exit 0, its reasons naming code lines and a command with 'PATTERN'."""
    from dataclasses import replace

    from typer.testing import CliRunner

    from patternfit.api import read_pattern, write_pattern
    from patternfit.cli.main import app

    pattern = tmp_path / "unsewn.json"
    write_pattern(replace(read_pattern("skirt", size="M"), seams=()), pattern)
    r = CliRunner().invoke(app, ["batch", "--pattern", str(pattern), "--sizes", "M",
                                 "--bodies", "female_average", "--fabrics", "cotton_shirting",
                                 "--triangles", "300", "--workers", "0", "--out",
                                 str(tmp_path / "b")])
    said = " ".join(r.output.split())
    assert r.exit_code == 2 and "unsewn.json" in said and "no seams between them" in said, said
    assert not (tmp_path / "b" / CSV_NAME).exists()


def test_a_resume_may_name_fewer_or_more_files(tmp_path):
    """Only a file given both times with other contents is refused (one fabric left out
    was refused as "not the one the batch was draped with")."""
    import json

    from patternfit.batch.settings import SETTINGS_NAME, keep_settings

    def run(files, resume=True):
        keep_settings(tmp_path, {"triangles": 300, "time_limit": 5.0, "files": files},
                      resume=resume)

    run({"a.json": "1", "b.json": "2"}, resume=False)
    run({"a.json": "1"})
    run({"a.json": "1", "c.json": "3"})
    kept = json.loads((tmp_path / SETTINGS_NAME).read_text())["files"]
    assert kept == {"a.json": "1", "b.json": "2", "c.json": "3"}
    with pytest.raises(InputError, match="the file b.json is not the one .* changed since"):
        run({"b.json": "9"})


def test_a_resume_naming_a_file_another_way_redoes_nothing(tmp_path, monkeypatch):
    """A batch run with /abs/heavyknit.json and resumed with heavyknit.json (the same
    file) redid its drapes and doubled their rows: a file is named as the run named it."""
    import json

    from patternfit.api import read_fabric
    from patternfit.batch import run_batch

    fabric = tmp_path / "knit.json"
    fabric.write_text(json.dumps({**read_fabric("cotton_shirting").to_dict(), "name": "knit"}))
    out = tmp_path / "batch"
    first = run_batch("skirt", "M", "female_average", str(fabric), out, triangles=300,
                      workers=0, thumbnails=False)
    monkeypatch.chdir(tmp_path)
    again = run_batch("skirt", "M", "female_average", "knit.json", out, triangles=300,
                      workers=0, thumbnails=False, resume=True)
    assert first["rows"] == 1 and again["skipped"] == 1 and again["rows"] == 1
    assert len(ResultLog(out, resume=True).rows) == 1
    # run from one folder and resumed from another (the first name is no path from there;
    # a file by that name with the same contents): the first run's name
    out2 = tmp_path / "batch2"
    run_batch("skirt", "M", "female_average", "knit.json", out2, triangles=300, workers=0,
              thumbnails=False)
    (tmp_path / "sub").mkdir()
    monkeypatch.chdir(tmp_path / "sub")
    third = run_batch("skirt", "M", "female_average", "../knit.json", str(out2),
                      triangles=300, workers=0, thumbnails=False, resume=True)
    assert third["skipped"] == 1 and len(ResultLog(out2, resume=True).rows) == 1


def test_a_preset_is_one_fabric_however_it_is_spelled(tmp_path):
    """A batch run with "cotton" and resumed with "cotton_shirting" (the preset's name, as
    a drape's report gives it) draped its tasks again: the rows name the preset."""
    from patternfit.batch import run_batch

    out = tmp_path / "batch"
    first = run_batch("skirt", "M", "female_average", "cotton,shirting", out, triangles=300,
                      workers=0, thumbnails=False)
    again = run_batch("skirt", "M", "female_average", "cotton_shirting", out, triangles=300,
                      workers=0, thumbnails=False, resume=True)
    assert first["tasks"] == 1 and again["skipped"] == 1
    assert [r["fabric"] for r in ResultLog(out, resume=True).rows] == ["cotton_shirting"]


def test_ctrl_c_is_read_through_a_chain_of_kernel_errors():
    """A kernel dispatched from another raises a SystemError caused by a SystemError caused
    by the KeyboardInterrupt: an outside test's batch recorded it as a failed row."""
    from patternfit.errors import ctrl_c

    def nested():
        try:
            try:
                raise KeyboardInterrupt
            except KeyboardInterrupt as stop:
                raise SystemError("inner returned a result with an exception set") from stop
        except SystemError as inner:
            raise SystemError("outer returned a result with an exception set") from inner

    with pytest.raises(SystemError) as info:
        nested()
    assert ctrl_c(info.value)
    assert not ctrl_c(SystemError("returned a result with an exception set"))
    assert not ctrl_c(ValueError("x"))
