"""The bending energy means the fabric's rigidity: a flat strip wrapped on a cylinder of
radius R stores B / (2 R^2) per area, B the rigidity for curvature along the bending
direction (patternfit.sim.energies; docs/simulation.md, "Bending")."""

from __future__ import annotations

import numpy as np
import pytest

from patternfit.sim.energies import build_terms

from scenes import grain_at, rect_mesh

MEMBRANE = dict(k_warp=1e3, k_weft=1e3, k_shear=50.0)


def _terms(v, t, grain_deg, b_warp, b_weft):
    return build_terms(v, t, grain_at(grain_deg, len(t)), np.arange(len(v)), len(v),
                       bend_warp=b_warp, bend_weft=b_weft, **MEMBRANE)


def _energy(terms, x):
    return 0.5 * float(np.einsum("ij,ij->", x, terms.bending @ x))


def _cylinder(v, radius, bend_deg):
    """The flat vertices ``v`` (n, 2) wrapped isometrically on a cylinder of ``radius`` [m]
    curving along the in-plane direction ``bend_deg``: (n, 3) [m]."""
    a = np.radians(bend_deg)
    d, p = np.array([np.cos(a), np.sin(a)]), np.array([-np.sin(a), np.cos(a)])
    s, q = v @ d, v @ p
    return (np.sin(s / radius) * radius)[:, None] * np.r_[d, 0.0] + q[:, None] \
        * np.r_[p, 0.0] + (radius * (1 - np.cos(s / radius)))[:, None] * np.array([0, 0, 1.0])


@pytest.mark.parametrize("h", [8e-3, 4e-3])
@pytest.mark.parametrize("grain_deg, b_warp, b_weft", [
    (0.0, 10e-6, 10e-6),   # isotropic
    (0.0, 10e-6, 4e-6),    # bending along the warp: B_warp
    (90.0, 10e-6, 4e-6),   # along the weft: B_weft
    (30.0, 10e-6, 4e-6),   # 30 deg off the warp: (sqrt(Bw) cos^2 + sqrt(Bf) sin^2)^2
])
def test_a_strip_on_a_cylinder_stores_b_over_2r2_per_area(h, grain_deg, b_warp, b_weft):
    """A 0.4 x 0.12 m strip (Triangle's quality mesh, edges ~h, free ends and sides
    included) bent along its length on R = 0.1 m: energy / area = B(phi) / (2 R^2) within
    2 %, phi the angle between the bending direction and the warp."""
    v, t = rect_mesh(0.4, 0.12, np.sqrt(3) / 4 * h * h)
    terms = _terms(v, t, grain_deg, b_warp, b_weft)
    radius = 0.1
    phi = np.radians(grain_deg)
    b_phi = (np.sqrt(b_warp) * np.cos(phi) ** 2 + np.sqrt(b_weft) * np.sin(phi) ** 2) ** 2
    per_area = _energy(terms, _cylinder(v, radius, 0.0)) / terms.area.sum()
    assert per_area == pytest.approx(b_phi / (2 * radius ** 2), rel=0.02)


def test_bending_has_no_poisson_coupling():
    """The rigidity of a fabric strip is that of a beam: bending along x and along y are
    independent (no bending Poisson ratio), so a bowl costs the sum of the two cylinders
    (the edge-by-edge hinge energy this replaced coupled them as a plate with nu = -1/3:
    the bowl cost 4/3 of one cylinder instead of 2)."""
    v, t = rect_mesh(0.2, 0.2, np.sqrt(3) / 4 * 4e-3 ** 2)
    terms = _terms(v, t, 0.0, 10e-6, 10e-6)
    c = v - v.mean(axis=0)
    zx, zy = np.zeros((len(v), 3)), np.zeros((len(v), 3))
    zx[:, 2] = c[:, 0] ** 2 / 2  # small height fields: the energy is exact in z
    zy[:, 2] = c[:, 1] ** 2 / 2
    ex, ey, bowl = _energy(terms, zx), _energy(terms, zy), _energy(terms, zx + zy)
    assert ex == pytest.approx(ey, rel=0.02)
    assert bowl / (ex + ey) == pytest.approx(1.0, abs=0.02)
