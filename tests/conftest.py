"""Fixtures only (the scenes they return are built by ``scenes.py``), the ``--slow``
option: tests marked ``slow`` (acceptance drapes: full garments draped to rest, Table 2 rows,
engine comparisons) are skipped unless pytest runs with ``--slow``, and the processes
``-n auto`` starts."""

from __future__ import annotations

import os

import pytest

from patternfit.sim.threads import available_cpus

import scenes

os.environ.setdefault("MPLBACKEND", "Agg")


#: what one test process may take at its peak [bytes] (measured: two processes and their Ray
#: and browser children peaked at 3.0 GB together)
WORKER_MEMORY = 1.5e9


def _cgroup_value(name: str) -> list[str] | None:
    try:
        with open(f"/sys/fs/cgroup/{name}") as f:
            return f.read().split()
    except OSError:
        return None


def _cpus() -> int:
    """The CPUs this process may run on, within its container's quota (cgroup v2 cpu.max)."""
    cpus = available_cpus()
    quota = _cgroup_value("cpu.max")
    if quota and quota[0] != "max":
        cpus = min(cpus, max(1, -(-int(quota[0]) // int(quota[1]))))
    return cpus


def _memory() -> float | None:
    """Memory available to this process [bytes]: the system's MemAvailable, within its
    container's limit (cgroup v2 memory.max less memory.current); None when unknown."""
    free = None
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    free = 1024.0 * int(line.split()[1])
    except OSError:
        pass
    limit, used = _cgroup_value("memory.max"), _cgroup_value("memory.current")
    if limit and used and limit[0] != "max":
        room = float(int(limit[0]) - int(used[0]))
        free = room if free is None else min(free, room)
    return free


@pytest.hookimpl(optionalhook=True)  # without pytest-xdist (`-p no:xdist`) nothing asks
def pytest_xdist_auto_num_workers(config):
    """``-n auto`` (the README's command): one test process a CPU this process may use, not
    a CPU of the host (pytest-xdist's own count, through psutil when it is installed, sees
    the host's cores from inside a container), and no more than the memory holds.
    ``PYTEST_XDIST_AUTO_NUM_WORKERS`` still decides when it is set (pytest-xdist reads it)."""
    if os.environ.get("PYTEST_XDIST_AUTO_NUM_WORKERS"):
        return None
    cpus, memory = _cpus(), _memory()
    fits = cpus if memory is None else int(memory // WORKER_MEMORY)
    return max(1, min(cpus, fits))


def pytest_addoption(parser):
    parser.addoption("--slow", action="store_true", default=False,
                     help="also run the slow acceptance drapes (tests marked slow)")


def pytest_collection_modifyitems(config, items):
    if config.getoption("--slow"):
        return
    skip = pytest.mark.skip(reason="slow acceptance drape: run with --slow")
    for item in items:
        if item.get_closest_marker("slow") is not None:
            item.add_marker(skip)


@pytest.fixture
def two_rectangles():
    """Two 0.5 x 0.8 m rectangles sewn along one side and half of another
    (``scenes.two_rectangles``)."""
    return scenes.two_rectangles()
