"""Shared fixtures: small patterns built in code."""

from __future__ import annotations

import os

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")


def rectangle_panel(name, w, h, *, origin=(0.0, 0.0)):
    from patternfit.pattern import Edge, Loop, Panel
    x0, y0 = origin
    pts = [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]
    names = ["bottom", "right", "top", "left"]
    return Panel(name, Loop("outline", [Edge.line(n, pts[i], pts[(i + 1) % 4])
                                        for i, n in enumerate(names)]))


@pytest.fixture
def two_rectangles():
    """Two 0.5 x 0.8 m rectangles sewn along one side and half of another."""
    from patternfit.pattern import Pattern, Seam, SeamSide
    a = rectangle_panel("A", 0.5, 0.8)
    b = rectangle_panel("B", 0.5, 0.8)
    return Pattern("tube", (a, b), (
        Seam("s1", SeamSide("A", "right"), SeamSide("B", "left")),
        Seam("s2", SeamSide("A", "left", 0.0, 0.5), SeamSide("B", "right", 0.5, 1.0))))


def end_line_load(v, ids, tension):
    """Forces (n, 3) [N] of a uniform line load ``tension`` [N/m] along +x on the strip end
    ``ids`` (vertices on a line x = const): each end vertex takes half its two segments."""
    import numpy as np

    order = np.argsort(v[ids, 1])
    seg = np.diff(v[ids[order], 1])
    share = np.zeros(len(ids))
    share[order[:-1]] += seg / 2
    share[order[1:]] += seg / 2
    forces = np.zeros((len(v), 3))
    forces[ids, 0] = tension * share
    return forces
