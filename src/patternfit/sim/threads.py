"""The solver's second thread: how many threads it may use, and running two halves of a job
at once.

A laptop has two cores or more. Five jobs of a large garment's solve split in two parts that
write apart: the Newton preconditioner's sparse Cholesky (``block_cholesky``: two subtrees
of its elimination tree, then the columns above them), the conjugate gradients' products
with the Hessian (two halves of its rows), the energy (the cloth's terms, and the body
contact of the vertices and of the edge and face points), the Hessian's assembly (the
membrane's kernel, and the rest) and the self-collision search (the crossings, and the
vertex-triangle pairs). The numba kernels release the GIL, so the two parts run in
one worker thread and the calling thread at once; with one thread they run one after the
other with the same arithmetic, so the results are bit-identical either way. Garments below
:data:`PARALLEL_VERTICES` vertices use one thread.

``PATTERNFIT_THREADS`` (a whole number >= 1) sets the threads; else ``OMP_NUM_THREADS``
caps them (Ray gives each one-CPU batch task ``OMP_NUM_THREADS=1``, so the batch's
workers do not compete for cores), and they are at most two and at most the CPUs this
process may run on.
"""

from __future__ import annotations

import os
import threading
from concurrent.futures import ThreadPoolExecutor
from typing import Callable

#: the environment variable that sets the solver's threads
ENV = "PATTERNFIT_THREADS"
#: the most threads the solver uses (its jobs split in two)
MOST = 2
#: below this many vertices a job runs on one thread: handing half of it to another thread
#: costs more than that half (a solve of a 1K-vertex factor takes some 0.2 ms)
PARALLEL_VERTICES = 2000

_WORKER = "patternfit-solver"
_pool: ThreadPoolExecutor | None = None
_lock = threading.Lock()


def _whole(name: str) -> int | None:
    text = os.environ.get(name, "").strip()
    if not text:
        return None
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise ValueError(f"{name}: expected a whole number of threads >= 1, got {text!r}")
    return value


def _omp_cap() -> int | None:
    """The threads ``OMP_NUM_THREADS`` allows the outermost level (OpenMP's list syntax
    "4,2" gives one number per nesting level), or None when it is unset or not OpenMP's:
    the variable belongs to other libraries, so a value they accept must not stop a drape."""
    first = os.environ.get("OMP_NUM_THREADS", "").split(",")[0].strip()
    return int(first) if first.isdigit() and int(first) >= 1 else None


def solver_threads() -> int:
    """Threads the solver may use now: ``PATTERNFIT_THREADS`` if set, else at most
    :data:`MOST`, the CPUs this process may run on and ``OMP_NUM_THREADS`` (its first
    level) if set. ``ValueError`` naming ``PATTERNFIT_THREADS`` when it is set to something
    else than a whole number >= 1."""
    own = _whole(ENV)
    if own is not None:
        return min(own, MOST)
    cap = _omp_cap()
    return max(1, min(MOST, available_cpus(), cap if cap is not None else MOST))


def available_cpus() -> int:
    """The CPUs this process may run on (its affinity mask; all of them where the system
    has none: macOS, Windows)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def threads_for(vertices: int) -> int:
    """Threads for a job on a garment of ``vertices`` vertices: :func:`solver_threads`,
    or 1 below :data:`PARALLEL_VERTICES`."""
    return solver_threads() if vertices >= PARALLEL_VERTICES else 1


def both(first: Callable, second: Callable, *, threads: int):
    """``(first(), second())``: ``first`` in the worker thread while ``second`` runs here
    when ``threads`` >= 2, else one after the other. An exception of either is raised
    (``first``'s when both raise), after both have ended."""
    # (from the worker itself, a job queued behind the one running there would never start)
    if threads < 2 or threading.current_thread().name.startswith(_WORKER):
        return first(), second()
    global _pool
    with _lock:
        if _pool is None:
            _pool = ThreadPoolExecutor(1, thread_name_prefix=_WORKER)
    future = _pool.submit(first)
    try:
        b = second()
    finally:
        a = future.result()  # waited for even when second raised: it writes shared arrays
    return a, b
