"""Gathers finer than the mesh (issue 19 item 3): the band of a seam's longer side may shrink
by the gather at no cost, so the shorter side keeps its length."""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from scenes import rectangle_panel

from patternfit.mesh import mesh_pattern
from patternfit.pattern import Pattern, Seam, SeamSide
from patternfit.sim.gathers import (GATHER_MIN, GATHER_ROWS, OBLIQUE_DEGREES, OBLIQUE_GATHER,
                                    GatherWarning, gather_slack, gathered_edges,
                                    oblique_gathers)


def _tube(longer: float, triangles: int = 500):
    """Panel A (0.4 m wide, ``longer`` x 0.5 m tall) whose right edge is sewn to the 0.5 m
    left edge of panel B (0.4 x 0.5 m), with the ease that takes."""
    p = Pattern("tube", (rectangle_panel("A", 0.4, 0.5 * longer),
                         rectangle_panel("B", 0.4, 0.5, origin=(1.0, 0.0))),
                (Seam("side", SeamSide("A", "right"), SeamSide("B", "left"),
                      ease=max(longer - 1.0, 0.0) * 1.001),))
    return mesh_pattern(p, triangles=triangles)


def _slack(m, grain=None):
    """The slack along the seam (A's right edge, x = 0.4, vertical) and across it, (m,) each,
    with every panel's warp at ``grain`` (default the mesh's)."""
    g = m.grain[m.triangle_panel] if grain is None else np.tile(grain, (m.n_triangles, 1))
    slack = gather_slack(m.vertices, m.triangles, g, np.arange(m.n_vertices), m.seam_pairs)
    along = 0 if abs(g[0, 1]) > abs(g[0, 0]) else 1  # the yarn that runs up, with the seam
    return slack[:, along], slack[:, 1 - along], slack


def test_the_longer_side_gets_a_band_slack_by_its_gather_and_the_shorter_none():
    m = _tube(1.6)
    slack, across, _ = _slack(m)
    # a gather shortens the cloth along the seam, not down from it
    assert np.all(across == 0.0)
    a = m.triangle_panel == m.panel_names.index("A")
    assert np.all(slack[~a] == 0.0)
    band = a & (slack > 0.0)
    assert band.sum() > 10
    # the band lies along A's right edge (x = 0.4), as wide as GATHER_ROWS of its edges
    gathered, ratio = gathered_edges(m.vertices, m.triangles, np.arange(m.n_vertices),
                                     m.seam_pairs)
    assert len(gathered) and np.allclose(m.vertices[gathered, 0], 0.4)
    np.testing.assert_allclose(ratio, 1.6, rtol=1e-6)
    step = np.linalg.norm(np.diff(m.vertices[gathered], axis=1), axis=2).mean()
    centre = m.vertices[m.triangles].mean(axis=1)
    assert 0.4 - centre[band, 0].min() < (GATHER_ROWS + 1) * step
    # most at the seam, where the whole gather 1 - 1 / 1.6 is taken up, less further in
    at_seam = a & np.isin(m.triangles, gathered).any(axis=1)
    assert slack.max() < 1.0 - 1.0 / 1.6
    assert slack[at_seam].min() > 0.5 * (1.0 - 1.0 / 1.6) > slack[band & ~at_seam].min()


def test_an_equal_seam_changes_nothing():
    assert np.all(_slack(_tube(1.0))[2] == 0.0)


def test_a_yarn_at_an_angle_to_the_seam_takes_its_cos_squared_share():
    m = _tube(1.6)
    up, _, _ = _slack(m, grain=(0.0, 1.0))
    for degrees in (30.0, 45.0, 60.0):
        theta = np.radians(degrees)  # the warp this far from the seam, the weft 90 more
        _, _, both = _slack(m, grain=(np.sin(theta), np.cos(theta)))
        np.testing.assert_allclose(both[:, 0], up * np.cos(theta) ** 2, atol=1e-12)
        np.testing.assert_allclose(both[:, 1], up * np.sin(theta) ** 2, atol=1e-12)


@pytest.mark.parametrize("degrees, warned", [(0.0, False), (22.5, False), (30.0, True),
                                             (45.0, True), (70.0, False)])
def test_a_gather_far_off_the_grain_is_named(degrees, warned):
    # the seam runs up (A's right edge); the warp this far from it, the weft 90 more: the
    # nearer yarn is at most 45 degrees off, and from OBLIQUE_DEGREES the gathers are loose
    theta = np.radians(degrees)

    def turned(m):  # every panel's warp at theta
        return replace(m, grain=np.tile((np.sin(theta), np.cos(theta)), (len(m.grain), 1)))

    near = min(degrees, 90.0 - degrees)
    found = oblique_gathers(turned(_tube(1.6)))
    assert found == ([("side", 5.0 * round(near / 5.0))] if warned else [])
    assert warned == (near >= OBLIQUE_DEGREES)
    # a sleeve cap's ease at that angle is not named: it frees little across the seam
    assert oblique_gathers(turned(_tube(1.0 + 0.5 * OBLIQUE_GATHER))) == []
    # an equal seam is no gather, whatever its angle
    assert oblique_gathers(turned(_tube(1.0))) == []


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(longer=st.floats(1.0, 1.95), triangles=st.integers(120, 600))
def test_slack_only_beyond_the_gather_threshold_and_within_the_gather(longer, triangles):
    m = _tube(longer, triangles)
    slack = _slack(m)[2]
    assert slack.shape == (m.n_triangles, 2)
    assert np.all((slack >= 0.0) & (slack <= 1.0 - 1.0 / longer + 1e-9))
    b = m.triangle_panel == m.panel_names.index("B")
    assert np.all(slack[b] == 0.0)
    if longer < 1.0 + 0.7 * GATHER_MIN:
        assert np.all(slack == 0.0)
    elif longer > 1.0 + 1.5 * GATHER_MIN:
        assert slack.max() > 0.5 * (1.0 - 1.0 / longer)


@pytest.mark.parametrize("gather", [1.6, 1.9])
def test_a_gathered_waist_keeps_the_band_at_its_length(gather):
    # the skirt's waist, gather times the band's, sewn into it: with the full stiffness in
    # compression the two met half way and the band's seam stretched by 23-25 % (1,500
    # triangles, female_average)
    from patternfit.body.builtin import load_body
    from patternfit.pattern.library import build
    from patternfit.sim.drape import drape

    p = build("gathered_skirt", "M", gather=gather)
    m = mesh_pattern(p, triangles=1500)
    with warnings.catch_warnings():
        warnings.simplefilter("error", GatherWarning)  # gathered along the grain: no warning
        d = drape(p, m, load_body("female_average"), "cotton_shirting")
    assert d.passed, d.reasons
    k = next(i for i, s in enumerate(p.seams) if s.name == "waist_front")
    band = m.seam_pairs[m.seam_index == k, 1]

    def length(y):
        return float(np.linalg.norm(np.diff(y, axis=0), axis=1).sum())

    assert length(d.positions[band]) / length(m.vertices[band]) - 1.0 < 0.08
    # the skirt's band shrinks by its gathers (23 % of the area compressed by more than 1 %
    # at 1.6); counted beyond that slack, as checks.compressed_share does, little is
    assert d.solver.compressed_share(d.result.x) < 0.05


def test_a_drape_gathered_on_the_bias_warns_naming_the_seams():
    from patternfit.body.builtin import load_body
    from patternfit.pattern.library import build
    from patternfit.sim.drape import drape
    from patternfit.sim.settings import SolverSettings

    p = build("gathered_skirt", "M")
    bias = replace(p, panels=tuple(replace(q, grainline=(0.7071, 0.7071))
                                   if not q.name.startswith("band") else q
                                   for q in p.panels))
    m = mesh_pattern(bias, triangles=800)
    with pytest.warns(GatherWarning) as caught:
        drape(bias, m, load_body("female_average"), "cotton_shirting", sewing_iterations=1,
              relax_iterations=0, settings=SolverSettings(max_iterations=0), coarse=None)
    said = {str(w.message).split("'")[1] for w in caught if w.category is GatherWarning}
    assert said == {"waist_front", "waist_back"}
    assert all("45 degrees" in str(w.message) for w in caught if w.category is GatherWarning)
