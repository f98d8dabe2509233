"""Fit across a size range and a body population: one drape per (pattern, size, body,
fabric), run on Ray, each a row of ``results.csv`` as it arrives, resumable, summed up as a
fit matrix (``matrix.png``, ``matrix.html``) with a one-line answer per size.

A front end beside the CLI and the studio: it runs the pipeline through
:mod:`patternfit.api` only. Ray is the optional extra ``patternfit[batch]``, imported when a
batch runs on it. See ``docs/batch.md``.
"""

from .cluster import RAY_MISSING, hard_limit, run_local, run_on_ray, start_ray
from .matrix import summary_lines, verdict_of, write_matrix
from .rows import COLUMNS, CSV_NAME, ResultLog, Task, plan, read_rows
from .run import parse_sizes, run_batch
from .work import Inputs, TaskOptions, outcome_row, run_task, thumbnail_png

__all__ = ["COLUMNS", "CSV_NAME", "Inputs", "RAY_MISSING", "ResultLog", "Task", "TaskOptions",
           "hard_limit", "outcome_row", "parse_sizes", "plan", "read_rows", "run_batch",
           "run_local", "run_on_ray", "run_task", "start_ray", "summary_lines", "verdict_of",
           "thumbnail_png", "write_matrix"]
