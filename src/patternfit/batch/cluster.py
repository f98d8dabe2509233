"""Running a batch's tasks: on Ray (a local cluster of N workers, or one joined by its
address) or in a plain loop in this process, writing each row as it arrives.

Each body, with its distance field computed once, goes into Ray's object store
(``ray.put``); every task of that body receives the shared object. At most as many tasks are
in flight as the cluster has CPUs, so a task starts when it is submitted and its time can be
bounded from there: a task running past :func:`hard_limit` is cancelled and becomes a failed
row. A KeyboardInterrupt (Ctrl-C) cancels the tasks in flight, keeps the rows written,
shuts down the Ray it started and propagates.
"""

from __future__ import annotations

import time
from typing import Callable

from ..api import with_distance_field
from ..files import atomic_write_bytes
from .rows import ResultLog, Task, failed_row
from .work import PNG, Inputs, TaskOptions, run_task

#: Ray is an optional extra (``patternfit[batch]``); the message says how to get it
RAY_MISSING = ("the batch runs on Ray, which is not installed: pip install "
               "\"patternfit[batch]\" (or pip install \"ray>=2.9\"), or give --workers 0 to "
               "drape in this process")


def hard_limit(options: TaskOptions) -> float:
    """Seconds after which a task in flight is cancelled [s]: the solver's own time limit
    (it stops there and reports no equilibrium) plus room for meshing, placement, sewing
    and the fit measures."""
    return 2.0 * options.time_limit + 60.0


def run_local(tasks: list[Task], inputs: Inputs, log: ResultLog, options: TaskOptions, *,
              progress: Callable | None = None) -> None:
    """Drape ``tasks`` one after another in this process (no Ray), appending each row to
    ``log``; ``progress(row)`` is called after each row."""
    for task in tasks:
        body, pattern, fabric = inputs.of(task)
        _record(log, run_task(task, body, options, pattern, fabric), progress)


def _ray():
    try:  # the optional extra, imported only when a batch runs on Ray
        import ray
    except ImportError as exc:
        raise ImportError(RAY_MISSING) from exc
    return ray


def start_ray(workers: int, address: str | None):
    """Join the cluster at ``address`` (``ray://host:10001`` or ``host:6379``), or start a
    local one of ``workers`` CPUs. Returns (ray, whether this call started it)."""
    ray = _ray()
    if ray.is_initialized():
        return ray, False
    if address:
        ray.init(address=address, log_to_driver=False)
    else:
        ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False,
                 configure_logging=False)
    return ray, True


def run_on_ray(tasks: list[Task], inputs: Inputs, log: ResultLog, options: TaskOptions, *,
               workers: int = 2, address: str | None = None,
               progress: Callable | None = None, poll: float = 0.5) -> None:
    """Drape ``tasks`` on Ray (see the module's docstring): the bodies (with their distance
    field), patterns and fabrics of ``inputs`` go into the object store once each; each row
    is appended to ``log`` as it arrives; ``progress(row)`` is called after each. A task
    that raises, crashes its worker or runs past :func:`hard_limit` becomes a failed row."""
    ray, started = start_ray(workers, address)
    limit = hard_limit(options)
    pending: dict = {}
    try:
        remote = ray.remote(num_cpus=1, max_retries=0)(run_task)
        shared = Inputs({k: ray.put(with_distance_field(b)) for k, b in inputs.bodies.items()},
                        {k: ray.put(p) for k, p in inputs.patterns.items()},
                        {k: ray.put(f) for k, f in inputs.fabrics.items()})
        slots = max(1, int(ray.cluster_resources().get("CPU", workers)))
        todo = list(reversed(tasks))
        while todo or pending:
            while todo and len(pending) < slots:
                task = todo.pop()
                body, pattern, fabric = shared.of(task)
                pending[remote.remote(task, body, options, pattern, fabric)] = \
                    (task, time.monotonic())
            ready, _ = ray.wait(list(pending), num_returns=1, timeout=poll)
            now = time.monotonic()
            for ref in ready:
                task, t0 = pending.pop(ref)
                try:
                    row = ray.get(ref)
                except Exception as exc:  # a crashed worker, a cancelled task
                    row = failed_row(task, f"{type(exc).__name__}: "
                                           f"{(str(exc).strip().splitlines() or [''])[0]}",
                                     seconds=now - t0)
                _record(log, row, progress)
            for ref, (task, t0) in list(pending.items()):
                if now - t0 > limit:
                    ray.cancel(ref, force=True)
                    del pending[ref]
                    _record(log, failed_row(task, f"timed out after {limit:.0f} s",
                                            seconds=now - t0), progress)
    finally:  # Ctrl-C included: nothing left running, the rows written stay
        for ref in pending:
            ray.cancel(ref, force=True)
        if started:
            ray.shutdown()


def _record(log: ResultLog, row: dict, progress: Callable | None) -> None:
    """Write the row's thumbnail (see :data:`~patternfit.batch.work.PNG`), then the row."""
    png = row.pop(PNG, None)
    if png is not None:
        atomic_write_bytes(log.folder / row["thumbnail"], png)
    log.append(row)
    if progress:
        progress(row)
