"""The studio's fabric editor: a fabric's numbers tested on the virtual bench
(``patternfit.api.fabric_test``: hanging strip, Peirce cantilever, Cusick drape) in a
background thread, one test at a time, with its result and picture kept for the page.

The studio runs smaller tests than ``patternfit fabric-test``'s defaults, so that a designer
gets an answer in seconds to a minute: the cantilever on two meshes (6 and 12 edges per
bending length), the Cusick drape on 1,500 triangles from 2 perturbed starts (about 20-40 s).
"""

from __future__ import annotations

import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from .. import api
from .jobs import Background
from .words import designer_message

#: the options of each test in the studio (see the module docstring)
STUDIO_OPTIONS = {"strip": {}, "cantilever": {"meshes": (6, 12), "keep_shape": True},
                  "cusick": {"triangles": 1500, "seeds": (0, 1)}}


class StopTest(Exception):
    """Raised in the test's progress callback when Stop was pressed (between solves)."""


@dataclass
class FabricJob:
    """The fabric test running or last run, as ``GET /api/fabric/test`` reports it."""

    test: str | None = None
    fabric: str | None = None
    running: bool = False
    stop: bool = False
    stopped: bool = False
    text: str = ""
    elapsed: float = 0.0
    error: str | None = None
    result: dict | None = None
    picture: bytes | None = None

    def as_dict(self) -> dict:
        return {"test": self.test, "fabric": self.fabric, "running": self.running,
                "stopped": self.stopped, "text": self.text, "elapsed": self.elapsed,
                "error": self.error, "result": self.result,
                "picture": self.picture is not None}


class FabricLab:
    """Runs one fabric test at a time in a background thread."""

    def __init__(self):
        self._runner = Background(FabricJob(), "patternfit-fabric-test")

    @property
    def job(self) -> FabricJob:
        """The test running or last run."""
        return self._runner.job

    def start(self, test: str, fabric) -> None:
        """Test ``fabric`` (a :class:`~patternfit.sim.fabrics.Fabric`) with ``test`` (one of
        ``STUDIO_OPTIONS``); Refused while another test runs."""
        if test not in STUDIO_OPTIONS:
            raise ValueError(f"test: expected one of {', '.join(STUDIO_OPTIONS)}")
        self._runner.start(FabricJob(test=test, fabric=fabric.name, text="starting"),
                           self._run, fabric,
                           busy="a fabric test is running: stop it first, or wait for it")

    def stop(self) -> None:
        self._runner.stop()

    def wait(self, timeout: float | None = None) -> None:
        """Wait for the running test (tests, shutdown)."""
        self._runner.wait(timeout)

    @staticmethod
    def _run(job: FabricJob, fabric) -> None:
        t0 = time.perf_counter()

        def progress(text: str) -> None:
            job.text = text
            job.elapsed = time.perf_counter() - t0
            if job.stop:
                raise StopTest

        try:
            result = api.fabric_test(job.test, fabric, progress=progress,
                                     **STUDIO_OPTIONS[job.test])
            job.result = {**result.to_dict(), "passed": result.passed}
            with tempfile.TemporaryDirectory() as tmp:
                path = api.write_fabric_test_picture(result, Path(tmp) / f"{job.test}.png")
                job.picture = None if path is None else Path(path).read_bytes()
            job.text = "done"
        except StopTest:
            job.stopped, job.text = True, "stopped"
        except Exception as exc:  # shown in the page; the server keeps serving
            job.error = designer_message(exc)
