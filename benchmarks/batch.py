"""Benchmark of ``patternfit batch``: the same batch in a plain loop, on Ray with 1 worker
and on Ray with 2 workers, in one run.

Run ``python benchmarks/batch.py [--sizes S,M] [--bodies female_thin,female_average]
[--triangles 1000]``; prints per run the wall time (Ray's start apart), the mean drape time
inside the tasks, and the speed-up of 2 workers over 1 (target: >= 1.5 on a 2-core
machine), and the per-drape overhead of Ray against the plain loop (wall time per task
beyond the loop's, with one worker). A warm-up drape in this process first fills the
compiled-kernel and distance-field caches that every run then reads; each Ray run first
warms its workers (one drape each, timed apart: a batch pays it once per worker).
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

from _table import print_table

from patternfit.api import read_bodies, read_fabric, read_pattern
from patternfit.batch import (Inputs, ResultLog, TaskOptions, plan, run_local, run_on_ray,
                              run_task)
from patternfit.batch.cluster import start_ray


def _run(tasks, inputs, folder, options, workers):
    """(wall time of the tasks [s], Ray's start [s] and its workers' warm-up [s] or 0, rows).
    The warm-up is one drape per worker, at once: a new worker process imports patternfit
    and loads the compiled kernels on its first drape, once per worker and batch."""
    log = ResultLog(folder, resume=False)
    t_start = t_warm = 0.0
    ray = None
    if workers:
        t0 = time.perf_counter()
        ray, _ = start_ray(workers, None)
        t_start = time.perf_counter() - t0
        t0 = time.perf_counter()
        run_on_ray([tasks[0]] * workers, inputs, ResultLog(f"{folder}-warm", resume=False),
                   options, workers=workers)
        t_warm = time.perf_counter() - t0
    t0 = time.perf_counter()
    try:
        if workers:
            run_on_ray(tasks, inputs, log, options, workers=workers)
        else:
            run_local(tasks, inputs, log, options)
        wall = time.perf_counter() - t0
    finally:
        if ray is not None:
            ray.shutdown()
    return wall, t_start, t_warm, log.rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pattern", default="skirt")
    parser.add_argument("--sizes", default="S,M")
    parser.add_argument("--bodies", default="female_thin,female_average",
                        help="body names, a set or a folder (more bodies: more tasks)")
    parser.add_argument("--fabric", default="cotton_shirting")
    parser.add_argument("--triangles", type=int, default=1000)
    args = parser.parse_args()
    bodies = {b.name: b for b in read_bodies(args.bodies)}
    sizes = args.sizes.split(",")
    tasks = plan([args.pattern], sizes, list(bodies), [args.fabric])
    inputs = Inputs(bodies, {(args.pattern, s): read_pattern(args.pattern, size=s)
                             for s in sizes}, {args.fabric: read_fabric(args.fabric)})
    with tempfile.TemporaryDirectory() as tmp:
        options = TaskOptions(triangles=args.triangles, time_limit=300.0)
        body, pattern, fabric = inputs.of(tasks[0])
        warm = run_task(tasks[0], body, options, pattern, fabric)  # fills the caches
        rows, walls = [], {}
        for name, workers in (("plain loop", 0), ("ray, 1 worker", 1), ("ray, 2 workers", 2)):
            wall, t_start, t_warm, result = _run(tasks, inputs, os.path.join(tmp, name), options,
                                         workers)
            walls[name] = wall
            drape = sum(r["seconds"] for r in result) / len(result)
            ok = sum(r["status"] == "ok" for r in result)
            rows.append((name, len(result), f"{ok}/{len(result)}", f"{t_start:.1f}",
                         f"{t_warm:.1f}",
                         f"{wall:.1f}", f"{wall / len(result):.1f}", f"{drape:.1f}",
                         len({r['worker'] for r in result})))
    speedup = walls["ray, 1 worker"] / walls["ray, 2 workers"]
    overhead = (walls["ray, 1 worker"] - walls["plain loop"]) / len(tasks)
    print_table(f"batch: {args.pattern} {args.sizes} x {args.bodies} x {args.fabric}, "
                f"{args.triangles} triangles (warm-up drape {warm['seconds']:.1f} s, load "
                f"average {os.getloadavg()[0]:.1f})", rows,
                ("run", "tasks", "passed", "ray start [s]", "warm-up [s]", "wall [s]",
                 "wall/task [s]",
                 "drape in task [s]", "workers"))
    print(f"\n2 workers vs 1: {speedup:.2f}x faster (target >= 1.5 on 2 cores)")
    print(f"Ray's overhead per drape against the plain loop (1 worker): {overhead:+.2f} s "
          f"({100 * overhead / (walls['plain loop'] / len(tasks)):+.0f}%)")


if __name__ == "__main__":
    main()
