"""Benchmark of the drape of the built-in garments on the built-in bodies (static engine).

Run ``python benchmarks/drape.py [--garments coat skirt trousers] [--rules force kinematic]
[--cold] [--figures DIR] [--edits N] [--samples N]``; prints, per garment (the paper's
sizes: coat 22K, skirt 15K, trousers 20K triangles) and stopping rule, the first drape
(placement, sewing, drape under gravity), the first drape continued from its own saved rest
(``restart``: positions and contact state, as ``patternfit drape --start DIR``; it must stop
at once and move nothing) and a warm re-drape after a 3 cm hem edit: iterations, seconds,
peak memory, the checks (residual rms / p99, equilibrium) and the fitting ratio. The rules
side by side: ``force`` is the solver's default (L-BFGS, then Newton steps to a force
balance, full stiffness in compression); ``kinematic`` the earlier one (L-BFGS stopped by
small steps, 5 % stiffness in compression), whose states are not at rest by the force
measure. Each garment runs in its own process so that the peak memory is its own. ``--cold``
also times the first drape with an empty distance-field cache (the field is computed, not
read). ``--edits N`` goes on with N - 1 more hem edits (lengths in ``HEM_STEPS``), each
re-draped from the last equilibrium as in a design session: the iterations a re-drape needs
depend on where the folds land, so one edit is one sample. ``--samples N`` runs every
garment N times, sample k (k > 0) with its flat vertices moved by a seeded random ``JITTER``
[m] and its coarse start meshed at ``COARSE + COARSE_STEP * k`` triangles, and ends with
each run's median and range (wall and CPU seconds): a difference in rounding alone sends
the folds elsewhere and changes a 22K first drape's Newton steps up to threefold
(docs/simulation.md, "The contact points' cost"), so two variants of the solver are
compared over several samples, not one. ``PATTERNFIT_THREADS=1`` runs the solver on one
thread (the same results bit for bit).
The solver's wall-clock ``time_limit`` is lifted (``COMMON``); ``--set time_limit=S`` puts
one back. ``--remeshed`` also makes the first 3 cm hem edit with every moved panel re-meshed
(``update_mesh(min_angle=89)``) and drapes it twice from the first drape's state: carried
over to the new mesh (``rm carried``, as a design session does: ``drape(start=...,
start_rest=...)``) and cold from the placement (``rm cold``, what a session did before).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

import _path  # noqa: F401  (tests/ on sys.path)

from patternfit.sim.threads import solver_threads

#: garment -> (body, triangles) as in the paper's Table 2
CASES = {"coat": ("male_heavy", 22000), "skirt": ("female_thin", 15000),
         "trousers": ("male_thin", 20000)}

#: the stopping rules compared: SolverSettings fields of each
RULES = {"force": {}, "kinematic": {"stop": "kinematic", "compression": 0.05}}

#: SolverSettings fields every rule gets: no wall-clock stop before rest (on a machine shared
#: with other jobs the solver's 300 s default stopped 15-22K solves after 12-25 s of CPU)
COMMON = {"time_limit": 3600.0}

#: ``--samples``: the flat vertices of sample k > 0 move by this much [m] (normal, seeded by
#: k), far below any physical effect, and its coarse start has COARSE_STEP * k triangles
#: more than ``drape``'s default COARSE (a sample at 1e-9 relative gravity drew the same
#: coarse start each time, whose 2K L-BFGS path rounding does not change)
JITTER = 1e-7
COARSE = 2000
COARSE_STEP = 25

#: successive hem moves [m] of ``--edits`` (down is negative: -0.03 lengthens by 3 cm)
HEM_STEPS = (-0.03, 0.02, -0.01, 0.03, -0.02, 0.01)


def _moved_mm(x, before) -> float:
    """Largest vertex displacement [mm] from ``before`` to ``x`` ((n, 3) [m] each)."""
    return float(np.linalg.norm(x - before, axis=1).max()) * 1e3


def _peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def run_one(garment: str, figures: str | None, edits: int = 1, knobs: dict | None = None,
            sample: int = 0, remeshed: bool = False) -> list:
    """First drape and ``edits`` warm re-drapes of one garment; returns the table's rows.
    ``knobs``: SolverSettings fields to change (name -> value); ``sample`` k > 0: the mesh
    jittered and the coarse start re-meshed (``JITTER``); ``remeshed``: the re-meshed hem
    edit carried and cold (``--remeshed``)."""
    from patternfit.body.builtin import load_body
    from patternfit.edit import move_edge, update_mesh
    from patternfit.fit import FitEvaluator
    from patternfit.mesh.transfer import transfer
    from patternfit.sim.drape import drape, redrape
    from patternfit.sim.settings import SolverSettings
    from scenes import garment as meshed

    body_name, triangles = CASES[garment]
    body = load_body(body_name)
    pattern, mesh = meshed(garment, triangles)
    if sample:
        moved = np.random.default_rng(sample).normal(scale=JITTER, size=mesh.vertices.shape)
        mesh = dataclasses.replace(mesh, vertices=mesh.vertices + moved)
    rows = []
    t0, c0 = time.perf_counter(), time.process_time()
    first = drape(pattern, mesh, body, "cotton", settings=SolverSettings(**(knobs or {})),
                  coarse=COARSE + COARSE_STEP * sample)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    fit = FitEvaluator(mesh)(first.positions)
    # (read now: a re-drape gives the solver the edited rest shapes)
    rows.append(("first", first, wall, cpu, fit.fitting_ratio,
                 first.solver.compressed_share(first.result.x), float("nan")))
    # continued from its own saved rest (``patternfit drape --start DIR``: positions and
    # contact.npz): it must stop at once and move nothing (issue 19 item 1)
    t0, c0 = time.perf_counter(), time.process_time()
    again = drape(pattern, mesh, body, "cotton", settings=SolverSettings(**(knobs or {})),
                  start=first.positions, start_contact=first.saved_contact())
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    rows.append(("restart", again, wall, cpu, FitEvaluator(mesh)(again.positions).fitting_ratio,
                 again.solver.compressed_share(again.result.x),
                 _moved_mm(again.positions, first.positions)))
    if figures:
        from patternfit.fit.pictures import plot_3d_map
        os.makedirs(figures, exist_ok=True)  # a new folder: a sample is not lost to its picture
        plot_3d_map(first.positions, mesh, fit, os.path.join(figures, f"drape_{garment}.png"),
                    body=(body.vertices, body.faces),
                    title=f"{garment} M on {body_name}, {len(mesh.triangles)} triangles, cotton")
    panel = "front" if any(p.name == "front" for p in pattern.panels) else pattern.panels[0].name
    if remeshed:
        edited = move_edge(pattern, panel, "hem", (0.0, HEM_STEPS[0]), partner=True)
        new_mesh, report = update_mesh(pattern, edited, mesh, min_angle=89.0,
                                       return_report=True)
        both = transfer(report.moved_mesh, np.hstack([first.positions, mesh.vertices]),
                        new_mesh)
        for name, start in (("rm carried", {"start": both[:, :3], "start_rest": both[:, 3:]}),
                            ("rm cold", {})):
            t0, c0 = time.perf_counter(), time.process_time()
            d = drape(edited, new_mesh, body, "cotton", settings=SolverSettings(**(knobs or {})),
                      coarse=COARSE + COARSE_STEP * sample, **start)
            wall, cpu = time.perf_counter() - t0, time.process_time() - c0
            rows.append((name, d, wall, cpu, FitEvaluator(new_mesh)(d.positions).fitting_ratio,
                         d.solver.compressed_share(d.result.x), float("nan")))
    last = first
    for k in range(edits):
        step = HEM_STEPS[k % len(HEM_STEPS)]
        pattern_next = move_edge(pattern, panel, "hem", (0.0, step), partner=True)
        mesh = update_mesh(pattern, pattern_next, mesh)
        pattern = pattern_next
        t0, c0 = time.perf_counter(), time.process_time()
        previous = last.positions
        last = redrape(last, mesh)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        name = "re-drape" if edits == 1 else f"hem {step * 100:+.0f}cm"
        rows.append((name, last, wall, cpu, FitEvaluator(mesh)(last.positions).fitting_ratio,
                     last.solver.compressed_share(last.result.x),
                     _moved_mm(last.positions, previous)))
    out = []
    for name, d, wall, cpu, ratio, compressed, moved in rows:
        c = d.checks
        out.append({"garment": garment, "body": body_name,
                    "triangles": len(d.solver.model.triangles),
                    "run": name, "sample": sample,
                    "iterations": d.report_extra()["timing"]["iterations"],
                    "seconds": wall, "cpu": cpu,
                    "sdf_seconds": d.timing.get("distance_field_seconds", 0.0),
                    "coarse": f"{d.timing['coarse_iterations']}/{d.timing['coarse_seconds']:.1f}"
                    if "coarse_iterations" in d.timing else "-",
                    "peak_mb": _peak_mb(), "inside": c.inside_vertices,
                    "clear_mm": c.min_clearance_mm, "seam_mm": c.seam_gap_max_mm,
                    "crossing": c.self_intersections, "equilibrium": c.equilibrium,
                    "rms": c.residual_rms if c.residual_rms is not None else float("nan"),
                    "p99": c.residual_p99 if c.residual_p99 is not None else float("nan"),
                    "compressed": compressed, "moved_mm": moved,
                    "start": str(d.timing.get("start", "-")),
                    "ratio": ratio})
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--garments", nargs="+", default=list(CASES), choices=list(CASES))
    ap.add_argument("--cold", action="store_true",
                    help="also run each first drape with an empty distance-field cache")
    ap.add_argument("--figures", default=None, help="directory for drape_<garment>.png")
    ap.add_argument("--edits", type=int, default=1,
                    help="successive hem edits re-draped after the first drape (HEM_STEPS)")
    ap.add_argument("--rules", nargs="+", default=list(RULES), choices=list(RULES),
                    help="stopping rules to compare (RULES)")
    ap.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE",
                    help="SolverSettings fields to change (over the rule's), e.g. refresh=50")
    ap.add_argument("--samples", type=int, default=1,
                    help="runs of each garment, mesh jittered (JITTER); median and range")
    ap.add_argument("--remeshed", action="store_true",
                    help="also the first hem edit with its panels re-meshed: carried and cold")
    ap.add_argument("--one", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--sample", type=int, default=0, help=argparse.SUPPRESS)
    args = ap.parse_args()
    def value(v):
        try:
            return int(v)
        except ValueError:
            try:
                return float(v)
            except ValueError:
                return v

    knobs = {k: value(v) for k, v in (item.split("=", 1) for item in args.set)}
    if args.one:
        print(json.dumps(run_one(args.one, args.figures, args.edits, knobs, args.sample,
                                 args.remeshed)))
        return
    print("built-in garments (size M, cotton) on built-in bodies, 5 mm distance field, "
          "contact margin 3 mm; re-drapes after hem edits (front, or the first panel, and "
          "its seam partner; -3 cm = 3 cm longer), each from the last equilibrium; "
          f"{os.cpu_count()} CPUs, solver threads {solver_threads()} (PATTERNFIT_THREADS)")
    print("iters, seconds (wall) and cpu (the process's CPU seconds: on a shared machine the "
          "fairer measure) of the whole run; coarse: iterations/seconds of the whole "
          "coarse drape (2K triangles: placement, sewing, drape) that starts the fine one; "
          "rms / p99: residual |F_i| / (m_i g) at the end (rest: <= 0.01 / 0.1); compr: share "
          "of the area compressed by more than 1 %; moved: largest vertex motion [mm] from "
          "the rest it started at (restart: the first drape continued from its saved rest, "
          "positions and contact.npz, as --start does); rule: force (default) or kinematic "
          "(the earlier stop)")
    print(f"{'garment':>8} {'rule':>9} {'tri':>6} {'run':>10} {'iters':>6} {'seconds':>8} {'cpu':>7} {'sdf s':>6} "
          f"{'coarse':>9} {'peak MB':>8} {'inside':>6} {'clear mm':>8} {'seam mm':>7} {'cross':>5} "
          f"{'equil':>5} {'rms':>7} {'p99':>7} {'compr':>6} {'moved':>7} {'ratio':>7} {'start':>8}")
    if args.samples < 1:
        ap.error("--samples: at least 1")
    # (garment, rule, run) -> (wall, CPU) seconds of each sample
    times: dict[tuple, list[tuple[float, float]]] = {}
    for garment, rule, k in ((g, r, k) for g in args.garments for r in args.rules
                             for k in range(args.samples)):
        runs = [("warm", None)]
        if args.cold:
            runs.append(("cold", tempfile.mkdtemp(prefix="patternfit-cache-")))
        rule_set = [f"{k}={v}" for k, v in {**COMMON, **RULES[rule]}.items()] + args.set
        for label, cache in runs:
            env = dict(os.environ)
            if cache:
                env["PATTERNFIT_CACHE"] = cache
            cmd = [sys.executable, __file__, "--one", garment, "--edits", str(args.edits),
                   "--sample", str(k), "--set", *rule_set] \
                + (["--remeshed"] if args.remeshed and label == "warm" else [])
            if args.figures and label == "warm" and rule == args.rules[0] and k == 0:
                cmd += ["--figures", args.figures]
            done = subprocess.run(cmd, env=env, capture_output=True, text=True)
            if done.returncode:
                print(f"{garment}: failed\n{done.stderr[-2000:]}")
                continue
            for r in json.loads(done.stdout.strip().splitlines()[-1]):
                if label == "cold" and r["run"] != "first":
                    continue
                run = r["run"] + (" cold" if label == "cold" else "")
                times.setdefault((garment, rule, run), []).append((r["seconds"], r["cpu"]))
                run += f" #{r['sample']}" if r["sample"] else ""
                print(f"{garment:>8} {rule:>9} {r['triangles']:>6} {run:>10} {r['iterations']:>6} "
                      f"{r['seconds']:>8.2f} {r['cpu']:>7.2f} {r['sdf_seconds']:>6.2f} {r['coarse']:>9} "
                      f"{r['peak_mb']:>8.0f} "
                      f"{r['inside']:>6} {r['clear_mm']:>8.3f} {r['seam_mm']:>7.3f} "
                      f"{r['crossing']:>5} {str(r['equilibrium']):>5} {r['rms']:>7.4f} "
                      f"{r['p99']:>7.4f} {r['compressed']:>6.3f} {r['moved_mm']:>7.2f} "
                      f"{r['ratio']:>7.4f} "
                      f"{r['start']:>8}",
                      flush=True)
    if args.samples > 1:
        print(f"\nseconds over {args.samples} samples (JITTER {JITTER:g} m, coarse + "
              f"{COARSE_STEP} k triangles): wall (what one waits; the solver's threads run "
              f"at once) and CPU (all threads' seconds)")
        print(f"{'garment':>8} {'rule':>9} {'run':>10} {'wall med':>8} {'min':>7} {'max':>7} "
              f"{'cpu med':>7} {'min':>7} {'max':>7}")
        for (garment, rule, run), pairs in times.items():
            wall, cpu = (np.array(t) for t in zip(*pairs))
            print(f"{garment:>8} {rule:>9} {run:>10} {np.median(wall):>8.2f} {wall.min():>7.2f} "
                  f"{wall.max():>7.2f} {np.median(cpu):>7.2f} {cpu.min():>7.2f} "
                  f"{cpu.max():>7.2f}")

if __name__ == "__main__":
    main()
