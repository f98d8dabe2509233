"""One long job at a time in a background thread, with a stop flag: the skeleton the studio's
drape (:mod:`.state`) and its fabric tests (:mod:`.fabric_lab`) share."""

from __future__ import annotations

import threading
import time
from typing import Callable


class Refused(RuntimeError):
    """A request that cannot be done in the session's present state (HTTP 409): a change
    while a drape runs, an export of a drape that is not there."""


class Background:
    """Runs one job at a time in a daemon thread named ``name``.

    A job is a record the page reads (a dataclass) with ``running``, ``stop`` and
    ``elapsed`` [s] fields; :attr:`job` is the one running or the last one run.
    """

    def __init__(self, job, name: str):
        self.job = job
        self.name = name
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None

    def start(self, job, target: Callable, *args, busy: str) -> None:
        """Run ``target(job, *args)`` in the background; :class:`Refused` with the message
        ``busy`` while another job runs. ``job.running`` is true from here until ``target``
        returned or raised, and ``job.elapsed`` then holds its seconds."""
        with self._lock:
            if self.job.running:
                raise Refused(busy)
            job.running = True
            self.job = job
            self._thread = threading.Thread(target=self._run, args=(job, target, args),
                                            daemon=True, name=self.name)
            self._thread.start()

    @staticmethod
    def _run(job, target: Callable, args: tuple) -> None:
        t0 = time.perf_counter()
        try:
            target(job, *args)
        finally:
            job.elapsed = time.perf_counter() - t0
            job.running = False

    def stop(self) -> None:
        """Ask the running job to stop (it looks at ``job.stop`` between its steps)."""
        self.job.stop = True

    def wait(self, timeout: float | None = None) -> None:
        """Wait for the job running (tests, shutdown)."""
        if self._thread is not None:
            self._thread.join(timeout)
