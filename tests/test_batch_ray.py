"""`patternfit batch` on a local Ray cluster: 2 sizes × 2 bodies at 1K triangles, stopped
with Ctrl-C (SIGINT) after its first row, then resumed; and a task that raises on a worker
becoming a failed row."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("ray")

from patternfit.api import read_body  # noqa: E402
from patternfit.batch import (Inputs, ResultLog, Task, TaskOptions,  # noqa: E402
                              read_rows, run_on_ray)

SRC = Path(__file__).resolve().parents[1] / "src"
ARGS = ["batch", "--pattern", "skirt", "--sizes", "S,M", "--bodies",
        "female_thin,female_average", "--fabrics", "cotton_shirting", "--triangles", "1000"]


def _batch(out, *extra, workers=2, **kw):
    env = {**os.environ, "PYTHONPATH": f"{SRC}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}
    command = [sys.executable, "-m", "patternfit.cli.main", *ARGS, "--workers", str(workers),
               "--out", str(out), *extra]
    # SIGINT back to its default in the child: a runner started in the background (nohup,
    # `&` without job control) hands it down ignored, and Python keeps an ignored SIGINT
    return subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True, preexec_fn=lambda: signal.signal(signal.SIGINT,
                                                                        signal.SIG_DFL), **kw)


def _rows_written(csv_path) -> int:
    return len(read_rows(csv_path)) if csv_path.is_file() else 0


def test_a_batch_stopped_after_its_first_row_resumes_without_redoing_it(tmp_path):
    out = tmp_path / "batch"
    # one worker: one task in flight when the first row arrives, so Ctrl-C always finds work
    # left (with two, both of the last tasks could finish before the signal is handled)
    first = _batch(out, workers=1)
    deadline = time.monotonic() + 900
    while _rows_written(out / "results.csv") == 0:
        assert first.poll() is None, first.communicate()[0]
        assert time.monotonic() < deadline, "no row within 15 minutes"
        time.sleep(0.5)
    first.send_signal(signal.SIGINT)  # Ctrl-C
    try:
        text = first.communicate(timeout=120)[0]
    except subprocess.TimeoutExpired:
        first.kill()
        text = first.communicate()[0]
        pytest.fail(f"Ctrl-C did not stop the batch within 2 minutes:\n{text}")
    before = read_rows(out / "results.csv")
    assert 1 <= len(before) < 4, text
    assert first.returncode == 130 and "--resume" in text, text

    # without --resume the folder is refused; with it the batch finishes
    refused = _batch(out)
    assert refused.wait(timeout=300) == 2
    second = _batch(out, "--resume")
    text = second.communicate(timeout=1800)[0]
    assert second.returncode == 0, text
    rows = read_rows(out / "results.csv")
    keys = [(r["size"], r["body"]) for r in rows]
    assert len(keys) == len(set(keys)) == 4
    assert set(keys) == {(s, b) for s in ("S", "M") for b in ("female_thin", "female_average")}
    assert rows[:len(before)] == before  # the finished rows were not redone
    assert f"resuming: {len(before)} of 4" in text
    for r in rows:
        assert r["status"] in ("ok", "failed") and r["seconds"] > 0 and r["worker"]
        if r["status"] == "ok":
            assert 0.5 < r["fitting_ratio"] < 1.5 and r["checks_passed"]
            assert (out / r["thumbnail"]).stat().st_size > 500
    assert (out / "matrix.png").stat().st_size > 5000
    page = (out / "matrix.html").read_text()
    assert page.count("<img") == sum(bool(r["thumbnail"]) for r in rows) >= 1
    assert "skirt in cotton_shirting, S:" in text and "skirt in cotton_shirting, M:" in text
    if (out / "results.parquet").exists():
        import pyarrow.parquet as pq

        assert pq.read_table(out / "results.parquet").num_rows == 4


def test_a_task_that_raises_on_a_worker_is_a_failed_row(tmp_path):
    body = read_body("female_thin")
    tasks = [Task("skirt", "S", "female_thin", str(tmp_path / "missing_fabric.json")),
             Task(str(tmp_path / "missing_pattern.json"), "S", "female_thin", "cotton")]
    log = ResultLog(tmp_path, resume=False)
    run_on_ray(tasks, Inputs({"female_thin": body}, {}, {}), log,
               TaskOptions(triangles=300, time_limit=60.0), workers=1)
    rows = read_rows(log.path)
    assert [r["status"] for r in rows] == ["failed", "failed"]
    assert "FabricError" in rows[0]["reasons"] and "PatternError" in rows[1]["reasons"]
    assert all(r["worker"] and r["worker"] != f"{os.uname().nodename}:{os.getpid()}"
               for r in rows)  # they ran in Ray's worker processes
