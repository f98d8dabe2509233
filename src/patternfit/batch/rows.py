"""The batch's tasks and its result rows: one row per (pattern, size, body, fabric), appended
to ``results.csv`` as it arrives, read back to resume.

A row is appended with one ``write`` of a whole line on a file opened for appending, then
flushed and synced: a batch killed mid-write leaves at most one partial last line, which
:func:`read_rows` drops (its task is redone); a task counts as done once its row is whole.
"""

from __future__ import annotations

import csv
import io
import os
from pathlib import Path
from typing import NamedTuple

from ..api import GIRTHS
from ..errors import InputError
from ..files import atomic_write_bytes, atomic_write_text

#: the result file of a batch folder (Parquet beside it: :data:`PARQUET`)
CSV_NAME = "results.csv"
PARQUET = "results.parquet"


class Task(NamedTuple):
    """One drape of a batch; its identity (a row's key) is the 4-tuple."""

    pattern: str
    size: str
    body: str
    fabric: str


#: the columns of a row, in order: the task, the result (ϖ [-], symmetric ratio [-],
#: verdict and the regions it names, space-separated), ease at each girth [cm], contact
#: pressure p95 / p99 [kPa], the checks (passed, the failed checks' names, the reasons in
#: words), the residual force rms / p99 [-], wall time [s], the worker, and the
#: thumbnail's file name
COLUMNS = (*Task._fields, "status", "fitting_ratio", "fitting_ratio_symmetric", "verdict",
           "verdict_regions",
           *(f"ease_{g}_cm" for g in GIRTHS), "pressure_p95_kpa", "pressure_p99_kpa",
           "checks_passed", "failed_checks", "reasons", "residual_rms", "residual_p99",
           "seconds", "worker", "thumbnail")

#: float columns, parsed back from the CSV
FLOATS = {"fitting_ratio", "fitting_ratio_symmetric", *(f"ease_{g}_cm" for g in GIRTHS),
          "pressure_p95_kpa", "pressure_p99_kpa", "residual_rms", "residual_p99", "seconds"}


def plan(patterns, sizes, bodies, fabrics) -> list[Task]:
    """Every (pattern, size, body, fabric) of the four lists, in that nesting order, each
    once (strings; bodies by name).

    Raises ``ValueError`` naming a value that cannot name a task in a row: empty, blank or
    on several lines."""
    for key, values in zip(Task._fields, (patterns, sizes, bodies, fabrics)):
        for v in values:
            if not str(v).strip() or " ".join(str(v).splitlines()) != str(v):
                raise ValueError(f"{key}: {str(v)!r} cannot name a task (blank, or a line "
                                 "break in it)")
    tasks = [Task(str(p), str(s), str(b), str(f))
             for p in patterns for s in sizes for b in bodies for f in fabrics]
    return list(dict.fromkeys(tasks))


def task_of(row: dict) -> Task:
    return Task(*(row[k] for k in Task._fields))


def failed_row(task: Task, reason: str, *, seconds: float = 0.0, worker: str = "") -> dict:
    """The row of a task whose drape gave no result (an exception, a time-out): status
    ``failed``, the reason in words, no measures."""
    return {**task._asdict(), "status": "failed", "checks_passed": False,
            "failed_checks": "error", "reasons": reason, "seconds": seconds, "worker": worker}


def _csv_line(row: dict) -> str:
    buf = io.StringIO()
    csv.DictWriter(buf, COLUMNS, extrasaction="raise", lineterminator="\n").writerow(
        {k: _cell(row.get(k)) for k in COLUMNS})
    return buf.getvalue()


def _cell(v):
    """A CSV cell: empty for None, floats to 6 digits, text on one line (a row is a line:
    see :func:`read_rows`)."""
    if v is None:
        return ""
    if isinstance(v, float):
        return f"{v:.6g}"
    return " ".join(str(v).splitlines())


def _parse(raw: dict) -> dict:
    row = {}
    for k in COLUMNS:
        v = raw[k]
        if k in FLOATS:
            row[k] = float(v) if v != "" else None
        elif k == "checks_passed":
            row[k] = v == "True"
        else:
            row[k] = v if v != "" else None
    return row


def read_rows(path) -> list[dict]:
    """The whole rows of a result CSV, parsed (floats, None for empty cells); a partial
    last line (a batch killed mid-write) is dropped. Missing file: no rows.

    Raises :class:`InputError` naming the file when its header is not this batch's
    columns (another file, or a batch of an older layout), and the line of a row that is
    not one (cells missing, a number that is none)."""
    path = Path(path)
    if not path.is_file():
        return []
    text = path.read_text(encoding="utf-8")
    if not text.endswith("\n"):  # cut mid-row: only whole lines count
        text = text[:text.rfind("\n") + 1]
    reader = csv.DictReader(io.StringIO(text))
    if text and tuple(reader.fieldnames or ()) != COLUMNS:
        raise InputError("is not a patternfit batch result (its header differs); give "
                         "another --out folder", file=path)
    rows = []
    for r in reader:
        if None in r or None in r.values():  # a short or long line: not a row written here
            raise InputError(f"holds a line of {len(r) - (None in r)} cells, not "
                             f"{len(COLUMNS)}", file=path, place=f"line {reader.line_num}")
        try:
            rows.append(_parse(r))
        except ValueError as exc:
            raise InputError(str(exc), file=path, place=f"line {reader.line_num}") from None
    return rows


class ResultLog:
    """The append-only result file of a batch folder.

    ``ResultLog(folder, resume=True)`` reads the rows already there (:attr:`rows`) and
    :meth:`done` tells which tasks they finished; ``resume=False`` refuses a folder that
    holds results, so that a new batch never mixes with an old one silently."""

    def __init__(self, folder, *, resume: bool):
        self.folder = Path(folder)
        self.path = self.folder / CSV_NAME
        self.rows = read_rows(self.path)
        if self.rows and not resume:
            raise InputError(f"already holds {len(self.rows)} results: give --resume to "
                             "finish that batch, or another --out folder", file=self.folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self._trim()

    def _trim(self) -> None:
        """Rewrite the file as its whole rows (drops a partial last line) and a header."""
        text = ",".join(COLUMNS) + "\n" + "".join(_csv_line(r) for r in self.rows)
        if not self.path.is_file() or self.path.read_text(encoding="utf-8") != text:
            atomic_write_text(self.path, text)

    def done(self) -> set[Task]:
        """The tasks that have a row."""
        return {task_of(r) for r in self.rows}

    def append(self, row: dict) -> None:
        """Append ``row`` as one line, flushed and synced to disk."""
        line = _csv_line(row).encode("utf-8")
        fd = os.open(self.path, os.O_WRONLY | os.O_APPEND)
        try:
            os.write(fd, line)
            os.fsync(fd)
        finally:
            os.close(fd)
        self.rows.append(_parse(next(csv.DictReader(io.StringIO(
            ",".join(COLUMNS) + "\n" + line.decode("utf-8"))))))

    def write_parquet(self) -> Path | None:
        """Write every row as ``results.parquet`` (atomically) when pyarrow is installed;
        returns its path, or None without pyarrow."""
        try:
            import pyarrow as pa
            import pyarrow.parquet as pq
        except ImportError:
            return None
        table = pa.table({k: [r[k] for r in self.rows] for k in COLUMNS})
        buf = pa.BufferOutputStream()
        pq.write_table(table, buf)
        return atomic_write_bytes(self.folder / PARQUET, buf.getvalue().to_pybytes())
