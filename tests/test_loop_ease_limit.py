"""A let-out stops at the style's ease range (``loop.ease_limit``): the width of a panel
across its grain at a height (a rectangle's is its width, whatever its turn), and the
corner moves that would widen a coat's hip past its most ease scaled back to the room left,
the others left alone (flat panels, no drape)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patternfit.fit.body_regions import REGIONS
from patternfit.fit.measures import FitMeasures, Section
from patternfit.fit.verdict import RegionVerdict, Verdict
from patternfit.fit.verdict_rules import ease_range
from patternfit.loop.correct import CornerMove
from patternfit.loop.ease_limit import cap_moves, girth_levels, growth, width_at
from patternfit.mesh.triangulate import mesh_pattern
from patternfit.pattern.library import build


@settings(max_examples=100, deadline=None)
@given(w=st.floats(0.05, 1.0), h=st.floats(0.05, 1.0), at=st.floats(0.05, 0.95),
       turn=st.floats(-np.pi, np.pi), shift=st.tuples(st.floats(-1, 1), st.floats(-1, 1)))
def test_width_of_a_turned_rectangle_is_its_width(w, h, at, turn, shift):
    g = np.array([-np.sin(turn), np.cos(turn)])  # the grain, turned
    c = np.array([-g[1], g[0]])
    corners = np.array([[0, 0], [w, 0], [w, h], [0, h]], dtype=np.float64)
    outline = corners[:, :1] * c + corners[:, 1:] * g + np.asarray(shift)
    height = float(np.asarray(shift) @ g) + at * h
    axis = float(np.asarray(shift) @ c) + 0.5 * w
    assert width_at(outline, g, height, axis) == pytest.approx(w, rel=1e-9, abs=1e-12)
    assert width_at(outline, g, height + 2 * h, axis) is None  # above it


def test_width_at_a_notch_is_the_stretch_that_holds_the_axis():
    # a U: two legs 0.1 wide, 0.3 apart at the bottom, joined above y = 0.5
    u = np.array([[0, 0], [0.1, 0], [0.1, 0.5], [0.4, 0.5], [0.4, 0], [0.5, 0], [0.5, 1],
                  [0, 1]], dtype=np.float64)
    g = np.array([0.0, 1.0])
    assert width_at(u, g, 0.25, 0.45) == pytest.approx(0.1)
    assert width_at(u, g, 0.25, 0.25) == pytest.approx(0.1)  # none holds it: the widest
    assert width_at(u, g, 0.75, 0.25) == pytest.approx(0.5)


# the Table 2 body (male_heavy): bust 101.8, waist 90.4, hip 104.2 cm
_BODY = {"bust": 101.8, "waist": 90.4, "hip": 104.2}


def _section(name, ease):
    z = np.zeros((0, 2))
    return Section(name, np.zeros(3), np.array([0.0, 1.0, 0.0]), z, z, z, z, _BODY[name],
                   _BODY[name] + ease, ease, True)


@pytest.fixture(scope="module")
def coat():
    pattern = build("coat", "M")
    return pattern, mesh_pattern(pattern, triangles=1200)


def _measures(mesh, hip_ease):
    """Measures whose hip region is every triangle below 25 cm (flat), the bust the rest."""
    y = mesh.vertices[mesh.triangles].mean(axis=1)[:, 1]
    tri = np.where(y < 0.25, REGIONS.index("hip"), REGIONS.index("bust"))
    n = mesh.n_vertices
    return FitMeasures(np.zeros(n), np.zeros(n), np.zeros(n, bool), np.ones(n),
                       {"bust": _section("bust", 10.0), "hip": _section("hip", hip_ease)},
                       np.zeros(n, int), tri)


def _verdict(hip_word):
    return Verdict(hip_word, {"hip": RegionVerdict(hip_word, None, 0.1, 0.01, 0.5, ""),
                              "bust": RegionVerdict("tight", None, 0.1, 0.12, 0.5, "")},
                   style="coat", stretch_limit=0.2)


def _hem_and_sleeve_moves(d):
    # the four hem corners out by d (the hip widens by 4 d) and a shoulder point out
    return [CornerMove("front", "hem", (-d, 0.0)), CornerMove("front", "side_l", (d, 0.0)),
            CornerMove("back", "hem", (-d, 0.0)), CornerMove("back", "side_r", (d, 0.0)),
            CornerMove("front", "shoulder_l", (0.02, 0.0))]


@pytest.mark.parametrize("ease", [15.0, 24.0, 30.0])
def test_a_let_out_stops_at_the_coats_most_hip_ease(coat, ease):
    pattern, mesh = coat
    measures = _measures(mesh, ease)
    most = ease_range("coat", "hip", _BODY)[1]
    moves = _hem_and_sleeve_moves(0.03)
    capped = cap_moves(pattern, mesh, measures, _verdict("fits"), moves)
    levels = girth_levels(mesh, measures, "hip")
    grown = 100 * growth(pattern, _moved(pattern, capped), mesh, levels)
    room = max(most - ease, 0.0)
    assert grown <= room + 0.05  # never past the most ease ...
    assert grown == pytest.approx(min(room, 100 * growth(
        pattern, _moved(pattern, moves), mesh, levels)), abs=0.05)  # ... and up to it
    # the shoulder point feeds no hip: left as asked
    assert [m for m in capped if m.edge == "shoulder_l"] == [moves[-1]]


def test_a_girth_read_tight_is_never_held_back(coat):
    pattern, mesh = coat
    moves = _hem_and_sleeve_moves(0.03)
    assert cap_moves(pattern, mesh, _measures(mesh, 30.0), _verdict("tight"), moves) == moves


def _moved(pattern, moves):
    from patternfit.edit import move_corner
    for mv in moves:
        pattern = pattern.with_panel(move_corner(pattern.panel(mv.panel), mv.edge,
                                                 np.asarray(mv.offset)))
    return pattern
