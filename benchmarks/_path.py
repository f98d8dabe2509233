"""Puts ``tests/`` on ``sys.path`` so that the benchmarks build their scenes with the tests'
own helpers: ``import _path`` (first), then ``from scenes import ...`` (tests/scenes.py)."""

from __future__ import annotations

import sys
from pathlib import Path

TESTS = str(Path(__file__).resolve().parent.parent / "tests")
if TESTS not in sys.path:
    sys.path.insert(0, TESTS)
