"""Fixtures only (the scenes they return are built by ``scenes.py``), and the ``--slow``
option: tests marked ``slow`` (acceptance drapes: full garments draped to rest, Table 2 rows,
engine comparisons) are skipped unless pytest runs with ``--slow``."""

from __future__ import annotations

import os

import pytest

import scenes

os.environ.setdefault("MPLBACKEND", "Agg")


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
