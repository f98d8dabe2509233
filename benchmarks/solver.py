"""Benchmark of the quasi-static garment solver: a square cloth dropped on a sphere.

Run ``python benchmarks/solver.py [--triangles 15000 ...]``; prints one row per size: the
first drape from flat, then a warm re-drape after a 1 % rest-shape edit (METHOD.md 5.1).
"""

from __future__ import annotations

import argparse
import resource
import time

import numpy as np
import triangle

from patternfit.body.sdf import DistanceField
from patternfit.sim.solver import GarmentSolver


def square(side, triangles):
    pts = np.array([[0, 0], [side, 0], [side, side], [0, side]], float) - side / 2
    area = side * side / triangles * 1.58  # Triangle's quality meshes come out finer
    out = triangle.triangulate({"vertices": pts, "segments": [[0, 1], [1, 2], [2, 3], [3, 0]]},
                               f"pq30a{area:.10f}Q")
    return out["vertices"].astype(float), out["triangles"].astype(np.int64)


def sphere(radius, half=0.6, h=0.005):
    ax = np.arange(-half, half + 1e-9, h)
    X, Y, Z = np.meshgrid(ax, ax, ax, indexing="ij")
    return DistanceField((-half,) * 3, h, np.sqrt(X**2 + Y**2 + Z**2) - radius)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--triangles", type=int, nargs="+", default=[2000, 15000])
    ap.add_argument("--fabric", default="cotton_shirting")
    ap.add_argument("--side", type=float, default=0.8, help="cloth side [m]")
    args = ap.parse_args()
    body = sphere(0.2)
    # compile the kernels once, outside the timings
    v, t = square(0.3, 200)
    GarmentSolver(v, t, np.tile([1.0, 0.0], (len(t), 1)), args.fabric, body=body).solve(
        np.c_[v[:, 0], np.full(len(v), 0.21), v[:, 1]])
    print(f"cloth {args.side} m square on a 0.2 m sphere, 5 mm distance field, "
          f"{args.fabric}; 2-core CPU")
    print(f"{'triangles':>9} {'run':>8} {'iters':>6} {'seconds':>8} {'factor':>6} "
          f"{'inside':>6} {'clear mm':>8} {'crossing':>8} {'conv':>5} {'peak MB':>8}")
    for m in args.triangles:
        v, t = square(args.side, m)
        grain = np.tile([1.0, 0.0], (len(t), 1))
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
                  f"{c.self_intersections:>8} {str(res.converged):>5} {peak:>8.0f}")
            if name == "first":
                solver.set_rest(v * 1.01)
                runs.append(("re-drape", res.x))


if __name__ == "__main__":
    main()
