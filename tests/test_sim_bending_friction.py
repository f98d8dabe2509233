"""Bending hysteresis (patternfit.sim.bending_friction; docs/simulation.md, "Bending
hysteresis"): a fold from flat carries the frictional couple HB = 2HB / 2 of KES-F on top of
B kappa, so a strip wrapped on a cylinder of curvature kappa has done the work HB kappa per
area; the energy's gradient is its derivative, its Hessian bound is PSD and at least the
true curvature, and a fabric file may give 2HB or leave it out."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from patternfit.sim.bending_friction import BendingFriction
from patternfit.sim.energies import build_terms
from patternfit.sim.fabric_sheets import KES_BENDING_HYSTERESIS
from patternfit.sim.fabrics import FabricError, get_fabric, load_fabric

from scenes import grain_at, rect_mesh


def _mesh(length, width, h):
    """A quality mesh of the rectangle with edges about ``h`` [m]."""
    return rect_mesh(length, width, np.sqrt(3) / 4 * h * h)

MEMBRANE = dict(k_warp=1e3, k_weft=1e3, k_shear=50.0)


def _friction(v, t, b_warp, b_weft, two_hb, grain_deg=0.0):
    fab = dataclasses.replace(get_fabric("denim"), bending_warp=b_warp, bending_weft=b_weft,
                              bending_hysteresis=two_hb)
    terms = build_terms(v, t, grain_at(grain_deg, len(t)), np.arange(len(v)), len(v),
                        bend_warp=b_warp, bend_weft=b_weft, **MEMBRANE)
    return BendingFriction.of(terms, fab), terms


def _cylinder(v, radius):
    """``v`` (n, 2) wrapped isometrically on a cylinder of ``radius`` [m] bending along x."""
    return np.c_[radius * np.sin(v[:, 0] / radius), v[:, 1],
                 radius * (1 - np.cos(v[:, 0] / radius))]


def _interior(v, t, margin):
    """Triangles whose corners all lie ``margin`` [m] inside the rectangle's edges."""
    lo, hi = v.min(axis=0) + margin, v.max(axis=0) - margin
    return ((v[t] > lo) & (v[t] < hi)).all(axis=(1, 2))


@pytest.mark.parametrize("b_warp, b_weft", [(10e-6, 10e-6), (10e-6, 2.5e-6)])
def test_cylinder_work_is_the_couple_times_the_curvature(b_warp, b_weft):
    v, t = _mesh(0.12, 0.12, 5e-3)
    two_hb = 1e-3  # N: HB / B = 50 1/m for the isotropic fabric
    bf, terms = _friction(v, t, b_warp, b_weft, two_hb)
    kappa = 50.0  # 1/m, ten times the stick band of the isotropic case
    x = _cylinder(v, 1 / kappa)
    inner = _interior(v, t, 0.02)
    sub = dataclasses.replace(bf, local=bf.local[inner], ids=bf.ids[inner],
                              area=bf.area[inner])
    work = sub.energy(x) / sub.area.sum()
    # bending along the warp: |K|^2 = B_warp kappa^2 / B_geo, so the couple is
    # HB sqrt(B_warp / B_geo) (= HB when isotropic); the stick band rounds |K|
    k_eff = kappa * np.sqrt(b_warp / np.sqrt(b_warp * b_weft))
    expected = 0.5 * two_hb * (np.hypot(k_eff, bf.eps) - bf.eps)
    assert work == pytest.approx(expected, rel=0.03)


def test_flat_and_rigid_motions_cost_nothing():
    v, t = _mesh(0.08, 0.06, 6e-3)
    bf, _ = _friction(v, t, 8e-6, 5e-6, 5e-4)
    rng = np.random.default_rng(3)
    q, _ = np.linalg.qr(rng.standard_normal((3, 3)))
    x = np.c_[v, np.zeros(len(v))] @ q.T + rng.standard_normal(3)
    g = np.zeros_like(x)
    # round-off only: below 1e-4 of the work of a bend of 1 m radius
    assert abs(bf.energy(x, g)) < 1e-4 * bf.moment * bf.area.sum() * 1.0
    assert np.abs(g).max() < 1e-9


def test_gradient_is_the_energys_derivative():
    v, t = _mesh(0.1, 0.08, 6e-3)
    bf, _ = _friction(v, t, 7e-6, 3e-6, 6e-4, grain_deg=30.0)
    rng = np.random.default_rng(0)
    x = np.c_[v, 0.3 * v[:, 0] ** 2 + 2e-3 * rng.standard_normal(len(v))]
    g = np.zeros_like(x)
    bf.energy(x, g)
    for _ in range(3):
        d = rng.standard_normal(x.shape)
        h = 1e-7
        fd = (bf.energy(x + h * d) - bf.energy(x - h * d)) / (2 * h)
        assert fd == pytest.approx(float(np.sum(g * d)), rel=1e-5)


def test_hessian_bound_is_psd_and_covers_the_curvature():
    v, t = _mesh(0.06, 0.05, 6e-3)
    bf, _ = _friction(v, t, 7e-6, 3e-6, 6e-4)
    rng = np.random.default_rng(1)
    x = np.c_[v, 0.5 * v[:, 0] ** 2 + 1e-3 * rng.standard_normal(len(v))]
    H = bf.hessian(x, len(v)).toarray()
    assert np.allclose(H, H.T)
    assert np.linalg.eigvalsh(H).min() > -1e-9 * np.abs(H).max()
    g0 = np.zeros_like(x)
    bf.energy(x, g0)
    for _ in range(3):  # second difference along d never exceeds d^T H d (convex, bounded)
        d = rng.standard_normal(x.shape)
        h = 1e-5
        second = (bf.energy(x + h * d) - 2 * bf.energy(x) + bf.energy(x - h * d)) / h ** 2
        assert -1e-9 <= second <= float(d.ravel() @ H @ d.ravel()) * (1 + 1e-6)


def test_no_hysteresis_no_term_and_files_may_give_it(tmp_path):
    v, t = _mesh(0.05, 0.05, 8e-3)
    bf, _ = _friction(v, t, 5e-6, 5e-6, 0.0)
    assert bf is None
    good = {"name": "mine", "density": 0.2, "stretch_warp": 5e3, "stretch_weft": 4e3,
            "shear": 40, "bending": 5e-6, "friction": 0.3, "thickness": 3e-4}
    path = tmp_path / "f.json"
    path.write_text(json.dumps(good))
    assert load_fabric(path).bending_hysteresis == 0.0
    path.write_text(json.dumps({**good, "bending_hysteresis": 0.124 * KES_BENDING_HYSTERESIS}))
    assert load_fabric(path).bending_hysteresis == pytest.approx(1.216e-3, rel=1e-3)
    path.write_text(json.dumps({**good, "bending_hysteresis": 5.0}))  # grams-force, not N
    with pytest.raises(FabricError, match="'bending_hysteresis'"):
        load_fabric(path)


def test_the_drape_test_feels_the_couple():
    """The solver adds the term (sim/solver.py): a stiff woven with the broadcloth's 2HB / B
    stands further out on the Cusick disc, at rest (docs/fabrics.md: M6 0.331 -> 0.428 at
    8K; here a coarse 1K specimen of 24 on 18 cm)."""
    from patternfit.sim.fabric_test import cusick_test

    base = get_fabric("petrak_m6")
    two_hb = 105.0 * np.sqrt(base.bending_warp * base.bending_weft)
    dc = {}
    for h in (0.0, two_hb):
        res = cusick_test(dataclasses.replace(base, bending_hysteresis=h), specimen=0.24,
                          triangles=1000, seeds=(0,))
        assert all(r.solve.at_rest for r in res.runs)
        dc[h] = res.drape_coefficient
    assert dc[two_hb] > dc[0.0] + 0.03
