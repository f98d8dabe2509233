import warnings

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial.transform import Rotation

from patternfit.fit import FIT, LOOSE, TIGHT, FitEvaluator, FitScale, fit_report
from patternfit.fit.colormap import NEUTRAL
from patternfit.mesh import mesh_pattern
from patternfit.pattern.library import build
from patternfit.sim.placement import Ellipse, place_on_cylinders, roll_panel


@pytest.fixture(scope="module")
def coat():
    p = build("coat", "M")
    return p, mesh_pattern(p, triangles=2000)


def _flat3(mesh):
    return np.column_stack([mesh.vertices, np.zeros(mesh.n_vertices)])


@settings(max_examples=25, deadline=None)
@given(st.floats(-np.pi, np.pi), st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1),
       st.floats(-2, 2), st.floats(-2, 2), st.floats(-2, 2))
def test_rigid_motion_is_perfect_fit(coat, angle, ax, ay, az, tx, ty, tz):
    _, mesh = coat
    axis = np.array([ax, ay, az])
    axis = axis / np.linalg.norm(axis) if np.linalg.norm(axis) > 1e-3 else np.array([0, 0, 1.0])
    x = Rotation.from_rotvec(angle * axis).apply(_flat3(mesh)) + [tx, ty, tz]
    r = FitEvaluator(mesh)(x)
    assert r.fitting_ratio == pytest.approx(1.0, abs=1e-9)
    assert r.fitting_ratio_symmetric == pytest.approx(1.0, abs=1e-9)
    assert np.abs(r.gamma).max() < 1e-12
    assert np.allclose(r.warp, 1) and np.allclose(r.weft, 1) and np.allclose(r.principal, 1)
    assert np.all(r.fit_class == FIT)


@pytest.mark.parametrize("s", [0.8, 1.05, 1.25])
def test_uniform_stretch(coat, s):
    _, mesh = coat
    r = FitEvaluator(mesh)(s * _flat3(mesh))
    assert r.fitting_ratio == pytest.approx(1 / s**2, rel=1e-12)
    assert np.allclose(r.warp, s) and np.allclose(r.weft, s)
    assert np.allclose(r.gamma, r.area_2d * (1 - s * s))
    assert np.all(r.fit_class == (TIGHT if s > 1 else LOOSE))
    sym = min(s * s, 1 / (s * s))
    assert r.fitting_ratio_symmetric == pytest.approx(sym, rel=1e-12)


def test_stretch_along_grain_only(coat):
    _, mesh = coat
    x = _flat3(mesh)
    x[:, 1] *= 1.1  # the built-in grainline is +y (warp)
    r = FitEvaluator(mesh)(x)
    assert np.allclose(r.warp, 1.1) and np.allclose(r.weft, 1.0)
    assert np.allclose(r.principal[:, 0], 1.1) and np.allclose(r.principal[:, 1], 1.0)


def test_cylinder_roll_is_isometric(coat):
    pattern, mesh = coat
    errors = []
    for n in (1000, 4000, 16000):
        m = mesh_pattern(pattern, triangles=n)
        r = FitEvaluator(m)(place_on_cylinders(pattern, m))
        errors.append(abs(r.fitting_ratio - 1))
    # only the chords of the curved surface differ from the flat triangles: O(h^2)
    assert errors[0] < 1e-3 and errors[1] < errors[0] / 2.5 and errors[2] < errors[1] / 2.5


def test_roll_panel_keeps_lengths():
    u = np.linspace(-0.3, 0.3, 3001)
    ring = Ellipse(0.25, 0.15)
    p = roll_panel(np.column_stack([u, np.zeros_like(u)]), ring, s0=0.1)
    assert np.linalg.norm(np.diff(p, axis=0), axis=1).sum() == pytest.approx(0.6, rel=1e-4)
    assert np.allclose((p[:, 0] / 0.25) ** 2 + (p[:, 2] / 0.15) ** 2, 1.0)
    back = roll_panel(np.array([[0.05, 0.0]]), ring, s0=0.5 * ring.perimeter)
    assert back[0, 0] < 0 and back[0, 2] < 0  # the back's +u runs towards -x
    assert ring.perimeter == pytest.approx(np.pi * (3 * 0.4 - np.sqrt((3 * .25 + .15) * (.25 + 3 * .15))), rel=1e-4)


def test_panel_ratios_and_classes(coat):
    pattern, mesh = coat
    x = _flat3(mesh)
    front = mesh.vertex_panel == 0
    x[front] *= 1.1
    r = FitEvaluator(mesh)(x)
    assert r.panel_ratio[0] == pytest.approx(1 / 1.21) and r.panel_ratio[1] == pytest.approx(1)
    fr = r.class_fractions()
    a0 = r.area_2d[mesh.triangle_panel == 0].sum() / r.area_2d.sum()
    assert fr["tight"] == pytest.approx(a0) and fr["fit"] == pytest.approx(1 - a0)
    rep = fit_report(mesh, r)
    assert rep["fitting_ratio"] == pytest.approx(r.fitting_ratio)
    assert [p["name"] for p in rep["panels"]] == ["front", "back"]
    assert set(rep) >= {"fitting_ratio", "fitting_ratio_symmetric", "panels", "fit_classes",
                        "mesh", "units"}
    assert set(rep["mesh"]) >= {"vertices", "triangles", "min_angle_deg", "seams"}


def test_bad_positions(coat):
    _, mesh = coat
    ev = FitEvaluator(mesh)
    with pytest.raises(ValueError, match="positions"):
        ev(np.zeros((3, 3)))
    x = _flat3(mesh)
    x[5, 0] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        ev(x)


def test_colour_scale():
    scale = FitScale(limit=0.15, band=0.02)
    c = scale.colors([0.0, 0.019, -0.019, 0.05, 0.15, 0.5, -0.05, -0.15, -0.5])
    assert np.allclose(c[:3], NEUTRAL)  # inside the band: the neutral colour
    lum = c @ [0.299, 0.587, 0.114]
    assert lum[4] < lum[3]  # tighter is darker
    assert lum[7] > lum[6]  # looser is lighter
    assert np.allclose(c[4], c[5]) and np.allclose(c[7], c[8])  # saturates at the limit
    rows = scale.legend()
    assert [r[0] for r in rows] == sorted(r[0] for r in rows)
    assert any("fits (±2%)" in r[2] for r in rows)
    assert "tight" in scale.describe() and "loose" in scale.describe()
    with pytest.raises(ValueError):
        FitScale(limit=0.01, band=0.02)


def test_a_collapsed_state_is_no_fit_and_no_console_warning(coat):
    """A failed drape that collapsed to a point has no 3D area: ϖ is infinite (the report's
    checks then refuse it), and numpy prints nothing on the way."""
    pattern, mesh = coat
    x = np.zeros((mesh.n_vertices, 3))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fit = FitEvaluator(mesh)(x)
    assert not np.isfinite(fit.fitting_ratio)
    assert not np.isfinite(fit.panel_ratio).any()
