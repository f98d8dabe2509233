"""A batch from start to end: the tasks of a pattern over sizes × bodies × fabrics, run on Ray
(or in this process), each row written as it arrives, then Parquet and the fit matrix."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Callable

from ..api import (DEFAULTS, check_drapeable, list_garments, list_sizes, read_bodies,
                   read_fabric_with_notes, read_pattern)
from ..arguments import number
from .cluster import run_local, run_on_ray
from .matrix import write_matrix
from .rows import CSV_NAME, ResultLog, plan, read_rows, task_of
from .settings import file_digests, keep_settings, saved_files
from .work import Inputs, TaskOptions


def parse_sizes(sizes: str, pattern: str, *, read=None) -> list[str]:
    """``"S,M,L"`` or ``"all"`` (every size of a built-in garment, or of a graded DXF) as
    a list. Any other pattern file is drafted in one size: its list is that one label.
    ``read``: the file ``pattern`` as read without a size, when the caller has it (else
    it is read here, when it is there). Raises ``ValueError`` naming ``--sizes``."""
    built_in = pattern in list_garments()
    if read is None and not built_in and Path(pattern).is_file():
        read = read_pattern(pattern)
    # a graded DXF holds its sizes (the batch said "drafted in one size" of one); a file
    # that is not there is named by its reading, later
    graded = [] if read is None else [str(g).strip().upper()
                                      for g in read.meta.get("sizes") or []]
    if sizes.strip().lower() == "all":
        if graded:
            return list(dict.fromkeys(graded))
        if not built_in:
            raise ValueError("--sizes: 'all' needs a built-in garment or a graded DXF; a "
                             "pattern file is drafted in one size: give its label, such as "
                             "--sizes M")
        return list_sizes()
    out = [s.strip().upper() for s in sizes.split(",")]
    if not all(out):
        raise ValueError(f"--sizes: an empty size in {sizes!r}")
    if built_in:
        wrong = [s for s in out if s not in list_sizes()]
        if wrong:
            raise ValueError(f"--sizes: {', '.join(wrong)} not one of "
                             f"{', '.join(list_sizes())} (or 'all')")
    elif graded:
        wrong = [s for s in out if s not in graded]
        if wrong:
            raise ValueError(f"--sizes: {', '.join(wrong)} not one of the file's sizes, "
                             f"{', '.join(graded)} (or 'all')")
    elif len(out) > 1:
        raise ValueError("--sizes: a pattern file is drafted in one size; give one label")
    return list(dict.fromkeys(out))


def run_batch(pattern: str, sizes: str, bodies: str, fabrics: str, out, *,
              triangles: int = DEFAULTS.triangles, workers: int = 2,
              address: str | None = None, resume: bool = False,
              time_limit: float = DEFAULTS.time_limit, thumbnails: bool = True,
              on_plan: Callable | None = None,
              progress: Callable | None = None) -> dict:
    """Drape ``pattern`` (a built-in garment or a pattern file) in every size of ``sizes``
    on every body of ``bodies`` (see :func:`patternfit.api.read_bodies`) in every fabric of
    ``fabrics`` (comma-separated presets or files), one task per (pattern, size, body,
    fabric), and write into ``out``: ``results.csv`` (a row per task as it arrives),
    ``results.parquet`` (with pyarrow), ``thumbs/``, ``matrix.png``, ``matrix.html``.

    ``workers`` CPUs of a local Ray cluster (0: a plain loop in this process, no Ray), or
    the cluster at ``address``; ``resume`` skips the tasks ``out`` already holds a row of;
    ``time_limit`` is the solver's limit per drape [s]. ``on_plan(total, done)`` is called
    once the tasks are known, ``progress(row)`` after each row. On KeyboardInterrupt the rows
    written stay and the Parquet file and matrix are still written, then it propagates.

    Returns ``{"tasks", "skipped", "rows", "failed", "files", "lines", "pattern_warnings",
    "fabric_assumed"}`` (what the pattern's reader noticed, ``meta["warnings"]``, and, by
    fabric, what was assumed for values its file does not carry; the CLI prints both).
    """
    number(workers, "--workers", low=0, integer=True)
    number(time_limit, "--time-limit", low=0.0, low_open=True, unit="s")
    # a pattern file read once without a size: its sizes, and itself where it names none
    own = None if pattern in list_garments() else read_pattern(pattern)
    size_list = parse_sizes(sizes, pattern, read=own)
    fabric_list = list(dict.fromkeys(f.strip() for f in fabrics.split(",")))
    # read here, once: the workers get objects, not files (they may be other machines)
    read = {f: read_fabric_with_notes(f) for f in fabric_list}
    # each input's name in the rows (the task), and the path it is read from; a preset by
    # its own name, as a drape's report names it ("cotton" and "cotton_shirting" were two
    # fabrics, and a resume given the other spelling draped every task again)
    named = {pattern: pattern, **{f: f if os.path.isfile(f) else read[f][0].name
                                  for f in fabric_list}}
    if resume:  # a file named as the earlier run named it: its rows are its tasks
        earlier = [task_of(r) for r in read_rows(Path(out) / CSV_NAME)]
        digests = saved_files(out)
        named[pattern] = _as_before(pattern, {t.pattern for t in earlier}, digests)
        named.update((f, _as_before(named[f], {t.fabric for t in earlier}, digests))
                     for f in fabric_list)
    inputs = Inputs({}, {(named[pattern], s): _read_sized(pattern, s, own)
                         for s in size_list},
                    {named[f]: read[f][0] for f in fabric_list})
    # what was assumed for a fabric file's missing values, said once for the batch
    notes = {f: read[f][1] for f in fabric_list if read[f][1]}
    body_list = read_bodies(bodies)
    tasks = plan([named[pattern]], size_list, [b.name for b in body_list],
                 list(dict.fromkeys(named[f] for f in fabric_list)))
    log = ResultLog(out, resume=resume)
    files = file_digests([pattern, *fabric_list, *(b.meta.get("source", "") for b in body_list)])
    keep_settings(out, {"triangles": int(triangles), "time_limit": float(time_limit),
                        "files": {named.get(k, k): v for k, v in files.items()}},
                  resume=resume)
    # what the reader noticed in the pattern (its sizes read alike), said once for the batch
    said = list(dict.fromkeys(w for p in inputs.patterns.values()
                              for w in p.meta.get("warnings") or []))
    done = log.done()
    todo = [t for t in tasks if t not in done]
    if on_plan:
        on_plan(len(tasks), len(tasks) - len(todo))
    options = TaskOptions(triangles=triangles, time_limit=float(time_limit),
                          thumbnails=thumbnails)
    needed = {t.body for t in todo}
    inputs.bodies.update((b.name, b) for b in body_list if b.name in needed)
    try:
        if todo and workers == 0 and not address:
            run_local(todo, inputs, log, options, progress=progress)
        elif todo:
            run_on_ray(todo, inputs, log, options, workers=max(workers, 1), address=address,
                       progress=progress)
    finally:  # also after Ctrl-C: the rows so far in Parquet and in the matrix
        files = {"csv": log.path, "parquet": log.write_parquet()}
        # the matrix and the counts are this run's tasks: a resume with fewer sizes or
        # bodies keeps the other rows in the files, not in the answer
        wanted = set(tasks)
        rows = [r for r in log.rows if task_of(r) in wanted]
        matrix = write_matrix(out, rows, tasks=tasks) if rows else None
    if matrix:
        files |= {"png": matrix["png"], "html": matrix["html"]}
    return {"tasks": len(tasks), "skipped": len(tasks) - len(todo), "rows": len(rows),
            "failed": sum(r["status"] != "ok" for r in rows), "files": files,
            "lines": matrix["lines"] if matrix else [], "pattern_warnings": said,
            "fabric_assumed": notes}


def _read_sized(pattern: str, size: str, own):
    """``pattern`` (a built-in garment or a file; ``own``: the file read without a size,
    None for a built-in) in ``size``. A file that names no size of its own (a GarmentCode
    file, a patternfit JSON without ``meta.size``, a DXF of one unnamed size) is read as it
    is, ``size`` its label in the rows: read in the size the
    batch asked to label it with, it was refused ("no size 'M' in the file"), and no size
    was accepted, so no batch of it could run. A pattern that cannot drape (unsewn, not
    meshable, of no garment's size) is refused naming the file, as ``drape`` refuses it
    (:func:`~patternfit.api.check_drapeable`): it was a failed row for every task, exit 0,
    its reasons naming code lines."""
    if own is not None and own.meta.get("size") is None and not own.meta.get("sizes"):
        return check_drapeable(own, source=pattern)
    return check_drapeable(read_pattern(pattern, size=size), source=pattern)


def _as_before(name: str, before: set[str], digests: dict[str, str]) -> str:
    """``name`` as an earlier run of the batch spelled the same file, else as it is: the
    same file by path, or, named from another folder, the one earlier name of the file's
    name whose contents ``digests`` (``batch.json``'s) says were these. A resume given
    ``heavyknit.json`` for ``/tmp/b/heavyknit.json``, or ``b/heavyknit.json`` run from
    ``/tmp``, redid its 4 drapes and doubled their rows."""
    if name in before or not os.path.isfile(name):
        return name
    for old in sorted(before):
        try:
            if os.path.isfile(old) and os.path.samefile(old, name):
                return old
        except OSError:  # unreadable: not the same file as far as can be told
            continue
    mine = file_digests([name]).get(name)
    alike = [old for old in sorted(before) if Path(old).name == Path(name).name
             and digests.get(old) == mine]
    return alike[0] if len(alike) == 1 else name
