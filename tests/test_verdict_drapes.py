"""The verdict on real drapes (small meshes) and the correction's edits for it: a size S
skirt reads tighter than an XL on the same body; XL trousers too large for the body rest on
it and read "too loose"; a region too tight is let out by translating its
edges (seams matched, symmetry kept); the Table 2 coat goes from too tight to no region too
tight (slow)."""

from __future__ import annotations

import numpy as np
import pytest
from scenes import assert_matched_and_mirrored

import patternfit as pf
from patternfit.fit.metrics import FitEvaluator
from patternfit.fit.verdict import Verdict
from patternfit.fit.verdict_rules import VERDICTS
from patternfit.loop.correct import CorrectionSettings, apply_moves, finish_moves, fit_reached
from patternfit.loop.widen import let_out_moves, region_strain
from patternfit.mesh.triangulate import mesh_pattern
from patternfit.pattern.library import build
from patternfit.pattern.validate import check_pattern


def test_a_size_s_skirt_reads_tighter_than_an_xl_on_the_same_body():
    small = pf.drape_and_evaluate("skirt", "female_heavy", "cotton", triangles=1000, size="S")
    large = pf.drape_and_evaluate("skirt", "female_heavy", "cotton", triangles=1000,
                                  size="XL")
    # measured: S too tight at the waist, hip ease +1.2 cm (tight); the XL slid 17 cm down
    # to the hips, hip ease +11.7 cm: a failed drape, too loose to hang from the waist
    assert small.verdict == "too tight" and large.verdict == "failed"
    assert small.region_verdicts["hip"]["ease_cm"] + 5.0 < \
        large.measures.sections["hip"].ease_cm
    assert small.region_verdicts["hip"]["verdict"] in ("tight", "too tight")
    assert "below the waist" in large.judgement.reason
    assert large.judgement.reason.endswith("too loose to hang from it")


def test_trousers_too_large_for_the_body_rest_on_it_and_read_too_loose(tmp_path):
    import json

    from patternfit.sim.onbody import ON_BODY

    # measured (1K triangles, at rest, no crossed pair): the XL on the thin woman rests with
    # its hems on her feet (its legs are longer than hers) and its waistband about 1 cm
    # above her waist; hip and thighs read "too loose", some 24 cm of ease. Until the body
    # contact acted inside the triangles, her feet passed through the coarse hems, the
    # trousers slid 8 cm to her hips and hung 12 cm below her feet (failed); under the
    # earlier kinematic stop they read "slid 10+ cm, too loose"
    o = pf.drape_and_evaluate("trousers", "female_thin", "cotton", triangles=1000, size="XL")
    c = o.checks
    assert c["self_intersections"] == 0 and c["equilibrium"], c
    assert c["faces_in_body"] == 0 and c["below_feet_vertices"] == 0 and o.passed, c
    assert abs(c["anchor_offset_mm"]) < 1000.0 * ON_BODY.anchor_tolerance
    assert o.verdict == "too loose"
    report = o.write(tmp_path, pictures=False)
    saved = json.loads((tmp_path / "report.json").read_text())
    assert saved["verdict"] == report["verdict"] == "too loose"
    assert saved["region_verdicts"]["hip"]["verdict"] == "too loose"
    for region in ("hip", "thigh_left", "thigh_right"):
        # a thigh's ease (23-34 cm) can sit at the 24 cm between loose and too loose (the
        # trousers' 20 cm and loose_tolerance_cm's 4), which side by the CPU's rounding
        assert saved["region_verdicts"][region]["verdict"] in ("loose", "too loose")
        assert saved["region_verdicts"][region]["ease_cm"] > 10.0


def test_a_skirt_wider_than_the_waist_slides_below_it_and_reads_loose_there():
    # the skirt M (waist 78 cm) on female_average (68.5 cm): measured at 1.5K, its top
    # rests 5.6 cm below her waist, cut 7 cm down with 6.3 cm of ease; it read "fits" with
    # no waist measured (3K: 6.1 cm down, +5.6 cm)
    o = pf.drape_and_evaluate("skirt", "female_average", "cotton", triangles=1500)
    assert o.passed and o.checks["anchor_offset_mm"] < -50.0, o.checks
    waist = o.region_verdicts["waist"]
    assert waist["verdict"] in ("loose", "too loose") and o.verdict in ("loose", "too loose")
    assert "below the waist" in waist["reason"] and waist["ease_cm"] > 2.5
    assert o.measures.sections["waist"].below_cm > 0.0


def _stretched(pattern, mesh, factor, above):
    """3D positions of ``mesh`` flat in z = 0, every panel stretched across by ``factor``
    about its axis where higher than ``above`` [m] (linearly blended over 5 cm)."""
    x = np.zeros((mesh.n_vertices, 3))
    x[:, :2] = mesh.vertices
    for pi, name in enumerate(mesh.panel_names):
        sel = mesh.vertex_panel == pi
        axis = float(np.median(pattern.panel(name).outline.polygon()[:, 0]))
        w = np.clip((mesh.vertices[sel, 1] - above) / 0.05, 0.0, 1.0)
        x[sel, 0] = axis + (1.0 + (factor - 1.0) * w) * (x[sel, 0] - axis)
    return x


def test_a_too_tight_region_is_let_out_at_its_edges_with_seams_matched_and_symmetry_kept():
    pattern = build("skirt", "M")
    mesh = mesh_pattern(pattern, triangles=1200)
    x = _stretched(pattern, mesh, 1.2, 0.45)
    top = np.flatnonzero(mesh.vertices[mesh.triangles].mean(axis=1)[:, 1] > 0.5)
    d, s = region_strain(mesh, x, top)
    assert abs(d[0]) > 0.99 and s == pytest.approx(1.2, rel=0.02)
    offsets = let_out_moves(pattern, mesh, x, top, target=0.0)
    assert offsets  # the hip seams (hip_l, hip_r) of both panels
    new = apply_moves(pattern, finish_moves(pattern, mesh, offsets))
    check_pattern(new)
    for seam in new.seams:
        assert new.seam_side_length(seam.a) == pytest.approx(new.seam_side_length(seam.b),
                                                             abs=1e-5)
    for name in ("front", "back"):
        old_w = np.ptp(pattern.panel(name).outline.polygon()[:, 0][
            pattern.panel(name).outline.polygon()[:, 1] > 0.55])
        new_poly = new.panel(name).outline.polygon()
        new_w = np.ptp(new_poly[:, 0][new_poly[:, 1] > 0.55])
        # the top of each panel was stretched 20% across: it grows by about that
        assert new_w / old_w == pytest.approx(1.2, abs=0.05)
        axis = 0.5 * (new_poly[:, 0].min() + new_poly[:, 0].max())
        mirrored = new_poly * [-1.0, 1.0] + [2 * axis, 0.0]
        gap = np.linalg.norm(mirrored[:, None] - new_poly[None], axis=2).min(axis=1).max()
        assert gap < 1e-4  # still mirror-symmetric
    # a re-mesh of the let-out pattern drapes no worse: its flat top is wider
    assert FitEvaluator(mesh_pattern(new, triangles=600)).area_2d.sum() > \
        FitEvaluator(mesh_pattern(pattern, triangles=600)).area_2d.sum()


def test_the_loop_stops_only_when_no_region_is_too_tight():
    from types import SimpleNamespace

    fit = SimpleNamespace(fitting_ratio=0.95)
    ok = Verdict("tight", {"hip": SimpleNamespace(verdict="tight")})
    bad = Verdict("too tight", {"hip": SimpleNamespace(verdict="too tight")})
    loose = Verdict("too loose", {"hip": SimpleNamespace(verdict="too loose")})
    s = CorrectionSettings(threshold=0.9)
    assert fit_reached(fit, ok, s) and not fit_reached(fit, bad, s)
    assert fit_reached(fit, loose, s) and not fit_reached(fit, loose, CorrectionSettings(
        threshold=0.9, take_in=True))
    assert not fit_reached(SimpleNamespace(fitting_ratio=0.85), ok, s)
    assert not fit_reached(fit, Verdict("failed"), s)
    # with the goal "fits", a tight region keeps the loop going too
    fits = CorrectionSettings(threshold=0.9, goal="fits")
    assert not fit_reached(fit, ok, fits)
    assert fit_reached(fit, Verdict("fits", {"hip": SimpleNamespace(verdict="fits")}), fits)
    with pytest.raises(ValueError, match="goal"):
        CorrectionSettings(goal="loose")
    from patternfit.cli.loop import GOALS as CLI_GOALS
    from patternfit.loop.correct import GOALS
    assert set(CLI_GOALS) == set(GOALS)


def test_a_too_tight_region_is_let_out_until_it_is_no_longer_too_tight():
    from patternfit.body.builtin import load_body
    from patternfit.loop.correct import correct
    from patternfit.loop.session import DesignSession

    # measured (1K triangles, 2-core CPU, 4 s): a size S skirt on the heavy woman in
    # shirting reads ϖ 99.7 % (the paper's fit) with its waist pressed at 3.18 kPa (too
    # tight); two let-outs of its side seams bring it to 2.74 and 1.69 kPa: tight, no
    # longer too tight
    pattern = build("skirt", "S")
    session = DesignSession(pattern, load_body("female_heavy"), "cotton_shirting", 1000)
    out = correct(session, settings=CorrectionSettings(max_iterations=4))
    first, last = out.iterations[0], out.iterations[-1]
    assert first.fitting_ratio >= 0.9 and first.verdict.regions["waist"].verdict == "too tight"
    assert out.reached and len(out.iterations) > 1
    assert not last.verdict.worst("too tight")
    waist = [it.verdict.regions["waist"].pressure_kpa_p95 for it in out.iterations]
    assert all(b < a for a, b in zip(waist, waist[1:]))  # each let-out eases it
    assert all(it.checks["passed"] for it in out.iterations)
    # every round one recorded, undoable edit of the side seams, both panels alike
    assert len(session.history) == len(out.iterations)
    for it, state in zip(out.iterations[:-1], session.history[1:]):
        assert state.edit["op"] == "correct" and it.edits
        assert {m.panel for m in it.edits} == {"front", "back"}
    new = session.pattern
    assert_matched_and_mirrored(new, ("front", "back"))
    session.undo()
    assert session.pattern == session.history[-2].pattern != new


def test_a_re_drape_is_worse_when_it_fails_or_a_region_turns_too_tight():
    from types import SimpleNamespace

    from patternfit.loop.correct import Iteration, _worse

    def verdict(*words):
        return Verdict("fits", {f"r{k}": SimpleNamespace(verdict=w) for k, w in enumerate(words)},
                       f"{words}")

    ok = {"passed": True}
    bad = {"passed": False, "reasons": ["no equilibrium (stopped: time)"]}
    tight = Iteration(1, 0.95, [], [], 0.0, ok, verdict("tight", "fits"))
    assert _worse(tight, ok, verdict("tight", "tight"), 0.95) is None
    assert _worse(tight, bad, verdict("fits"), 0.95) == "no equilibrium (stopped: time)"
    assert _worse(tight, ok, verdict("too tight", "fits"), 0.95) == "('too tight', 'fits')"
    # from a drape that was too tight or failed already, nothing is worse
    worse_already = Iteration(1, 0.95, [], [], 0.0, ok, verdict("too tight"))
    assert _worse(worse_already, ok, verdict("too tight"), 0.95) is None
    failed = Iteration(1, 0.95, [], [], 0.0, bad, Verdict("failed"))
    assert _worse(failed, bad, verdict("too tight"), 0.95) is None
    # but off the body is worse than on it, even from a drape that failed the solver's checks
    off = {"passed": False, "on_body": False, "on_body_reasons": ["garment top 24.2 cm below"]}
    assert _worse(failed, off, Verdict("failed"), 0.95) == \
        "the drape failed: garment top 24.2 cm below"
    assert _worse(Iteration(1, 0.95, [], [], 0.0, off, Verdict("failed")), off,
                  Verdict("failed"), 0.95) is None


def test_a_re_drape_that_fails_after_an_edit_steps_back_to_half_the_edit():
    from patternfit.body.builtin import load_body
    from patternfit.loop.correct import correct
    from patternfit.loop.session import DesignSession

    def run(fail_once: bool):
        session = DesignSession(build("skirt", "S"), load_body("female_heavy"),
                                "cotton_shirting", 1000)
        real, drapes = session.redrape, []

        def redrape(**kw):
            result = real(**kw)
            drapes.append(session.position)
            if fail_once and len(drapes) == 2:  # the first re-drape after an edit
                session.state.checks = {**session.state.checks, "passed": False,
                                        "reasons": ["3 crossed triangle pairs (limit 0)"]}
            return result

        session.redrape = redrape
        return session, correct(session, settings=CorrectionSettings(max_iterations=1))

    _, plain = run(False)
    session, out = run(True)
    assert out.iterations[1].stepped_back == ["3 crossed triangle pairs (limit 0)"]
    # the failed state was undone: the history holds the start and the halved edit only
    assert len(session.history) == 2 and "stepped back" in session.history[1].label
    assert all(s.checks["passed"] for s in session.history)
    for half, full in zip(out.iterations[0].edits, plain.iterations[0].edits):
        assert (half.panel, half.edge) == (full.panel, full.edge)
        assert np.allclose(half.offset, 0.5 * np.asarray(full.offset))
    assert out.to_dict()["iterations"][1]["stepped_back"]


@pytest.mark.slow
def test_table2_coat_is_too_tight_first_and_none_too_tight_after_correction():
    from patternfit.defaults import DEFAULTS
    from patternfit.loop.correct import CorrectionSettings
    from patternfit.loop.table2 import ROWS, run_row

    coat = {r.garment: r for r in ROWS}["coat"]
    # 22K triangles and the settings of `patternfit reproduce table2` (benchmarks/table2.py)
    row = run_row(coat, settings=CorrectionSettings(goal=DEFAULTS.table2_goal,
                                                    max_iterations=DEFAULTS.table2_rounds))
    assert row["verdicts"][0] == "too tight"
    # measured (force stop, 2-core CPU, 2 min, with the mittens): too tight (p99 1.83 kPa)
    # → too tight (ϖ 91.08%) → tight (95.54%) → fits (97.80%, p99 0.60 kPa). Under the
    # loop's own defaults (goal "tight", 3 rounds) it stopped one round short: the left
    # sleeve's end had risen 4 cm from the first drape (10.2 → 6.2 cm past the wrist), and
    # a risen limb end is lengthened before the fit counts as reached
    assert row["verdicts"][-1] in ("tight", "fits") and row["reached"]
    assert all(v["verdict"] != "too tight" for v in row["region_verdicts"].values())
    assert row["final"] >= 0.90 and row["pressure_kpa_p99"][-1] <= 2.0
    assert all(row["checks_passed"])


@pytest.mark.slow
def test_table2_coat_3k_is_too_tight_first_and_fits_after_correction():
    from patternfit.loop.table2 import ROWS, run_row

    coat = {r.garment: r for r in ROWS}["coat"]
    # measured (2-core CPU, loaded, 60 s): 68.47 → 92.32 → 96.15 → 97.66 → 97.87 %, too
    # tight → too tight → too tight → tight → fits, pressure p99 1.98 → 0.41 kPa
    row = run_row(coat, triangles=3000,
                  settings=CorrectionSettings(goal="fits", max_iterations=5))
    assert row["verdicts"][0] == "too tight" and row["verdicts"][-1] == "fits"
    assert row["reached"] and row["final"] >= 0.90
    assert row["pressure_kpa_p99"][-1] <= 2.0 and all(row["checks_passed"])
    assert all(v["verdict"] == "fits" for v in row["region_verdicts"].values())
    ease = row["ease_cm"]
    assert ease["hip"] <= 25.4 and ease["waist"] <= 25.4 + 101.8 - 90.4  # the coat's ranges


def test_take_in_a_too_loose_dress_is_a_recorded_symmetric_edit():
    from patternfit.body.builtin import load_body
    from patternfit.loop import DesignSession
    from patternfit.loop.correct import correct

    # measured (800 triangles): hip ease +33 cm, too loose; taken in 4.8-5.0 cm at each
    # side seam of both panels, symmetric: hip ease +14.5 cm (fits; the bust then reads
    # too tight: the bodice's side seam is taken in with the skirt's)
    session = DesignSession(build("dress", "XL"), load_body("female_thin"), "cotton", 800)
    result = correct(session, settings=CorrectionSettings(take_in=True, max_iterations=1))
    first, last = result.iterations[0], result.iterations[-1]
    assert first.verdict.regions["hip"].verdict == "too loose" and first.edits
    assert last.verdict.regions["hip"].ease_cm < first.verdict.regions["hip"].ease_cm - 5.0
    new, old = result.pattern, session.history[0].pattern
    for seam in new.seams:
        assert new.seam_side_length(seam.a) == pytest.approx(new.seam_side_length(seam.b),
                                                             abs=1e-5)
    for name in ("front", "back"):
        poly = new.panel(name).outline.polygon()
        assert new.panel(name).area() < old.panel(name).area() - 0.005  # taken in
        axis = 0.5 * (poly[:, 0].min() + poly[:, 0].max())
        mirrored = poly * [-1.0, 1.0] + [2 * axis, 0.0]
        assert np.linalg.norm(mirrored[:, None] - poly[None], axis=2).min(axis=1).max() < 1e-4
    assert session.state.edit["op"] == "correct"
    session.undo()
    assert session.pattern == old


def test_trousers_resting_below_a_waist_too_small_for_them_are_taken_in_there():
    from patternfit.body.builtin import load_body
    from patternfit.loop import DesignSession
    from patternfit.loop.correct import correct

    # the trousers M (waist 90 cm) on female_average (68.5 cm) rest 3.5-4 cm below her
    # waist: measured there, too loose (+18.5 cm at 1K; before, no waist ease and "fits",
    # so nothing to take in); one round takes the waist in (3K: +16.6 -> +6.1 cm, loose)
    session = DesignSession(build("trousers", "M"), load_body("female_average"), "cotton", 1000)
    result = correct(session, settings=CorrectionSettings(take_in=True, max_iterations=1))
    first, last = result.iterations[0], result.iterations[-1]
    waist = first.verdict.regions["waist"]
    assert waist.verdict == "too loose" and waist.ease_cm > 10.0 and first.edits
    assert last.verdict.regions["waist"].ease_cm < waist.ease_cm - 5.0
    old = session.history[0].pattern
    assert sum(e.length for p in result.pattern.panels for n, e in p.edges().items()
               if n == "waist") < sum(e.length for p in old.panels
                                      for n, e in p.edges().items() if n == "waist") - 0.05


def test_fit_of_a_saved_drape_with_its_body_has_the_verdict(tmp_path):
    import json

    from typer.testing import CliRunner

    from patternfit.cli.main import app

    o = pf.drape_and_evaluate("skirt", "female_average", "cotton", triangles=600)
    o.write(tmp_path / "d", pictures=False)
    run = CliRunner().invoke(app, ["fit", "-g", str(tmp_path / "d" / "garment"), "-b",
                                   "female_average", "-f", "cotton", "-o",
                                   str(tmp_path / "f"), "--no-pictures", "--json"])
    assert run.exit_code == 0, run.output
    saved = json.loads((tmp_path / "f" / "report.json").read_text())
    assert saved["verdict"] == o.verdict
    assert saved["ease_cm"]["hip"] == pytest.approx(o.measures.report()["ease_cm"]["hip"])
    bare = pf.evaluate_saved(tmp_path / "d" / "garment")
    assert bare.verdict is None and bare.region_verdicts == {}
