"""Benchmark of the quasi-static garment solver: a square cloth dropped on a sphere.

Run ``python benchmarks/solver.py [--triangles 15000 ...]``; prints one row per size: the
first drape from flat, then a warm re-drape after a 1 % rest-shape edit (METHOD.md 5.1).
"""

from __future__ import annotations

import argparse
import resource
import time

import numpy as np

import _path  # noqa: F401  (tests/ on sys.path)
from patternfit.sim.solver import GarmentSolver
from scenes import grain_at, sphere_field, square_mesh


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--triangles", type=int, nargs="+", default=[2000, 15000])
    ap.add_argument("--fabric", default="cotton_shirting")
    ap.add_argument("--side", type=float, default=0.8, help="cloth side [m]")
    args = ap.parse_args()
    body = sphere_field(0.2, half=0.6)
    # compile the kernels once, outside the timings
    v, t = square_mesh(0.3, 200)
    GarmentSolver(v, t, grain_at(0, len(t)), args.fabric, body=body).solve(
        np.c_[v[:, 0], np.full(len(v), 0.21), v[:, 1]])
    print(f"cloth {args.side} m square on a 0.2 m sphere, 5 mm distance field, "
          f"{args.fabric}; 2-core CPU")
    print(f"{'triangles':>9} {'run':>8} {'iters':>6} {'seconds':>8} {'factor':>6} "
          f"{'inside':>6} {'clear mm':>8} {'crossing':>8} {'conv':>5} {'rms':>7} {'p99':>7} "
          f"{'peak MB':>8}")
    for m in args.triangles:
        v, t = square_mesh(args.side, m)
        grain = grain_at(0, len(t))
        x0 = np.c_[v[:, 0], np.full(len(v), 0.21), v[:, 1]]
        solver = GarmentSolver(v, t, grain, args.fabric, body=body)
        runs = [("first", x0)]
        for name, start in runs:
            t0 = time.perf_counter()
            res = solver.solve(start)
            wall = time.perf_counter() - t0
            c = res.checks
            peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
            print(f"{len(t):>9} {name:>8} {res.iterations:>6} {wall:>8.2f} "
                  f"{res.factorizations:>6} {c.inside_vertices:>6} {c.min_clearance_mm:>8.3f} "
                  f"{c.self_intersections:>8} {str(res.converged):>5} {c.residual_rms:>7.4f} "
                  f"{c.residual_p99:>7.4f} {peak:>8.0f}")
            if name == "first":
                solver.set_rest(v * 1.01)
                runs.append(("re-drape", res.x))


if __name__ == "__main__":
    main()
