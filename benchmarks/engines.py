"""Cross-check of the two drape engines: static equilibrium vs. Newton Style3D (dynamic).

Run ``python benchmarks/engines.py [--sizes coat=22000 skirt=15000 trousers=20000]
[--body female_average] [--device cpu]``. Per garment, both engines drape the same mesh on the
same body from the same placement (the Newton engine reuses the static engine's placement and
gravity-free sewing phase, whose time it includes), then a ``--from-static`` Newton run starts
at the static result. Prints seconds, iterations (static) / frames (Newton), the checks,
ϖ per panel, the mean vertex distance to the static result, the mean dihedral angle and
Newton's drift over its last second (its rest test: see docs/simulation.md). Warp's kernels are compiled
(or loaded from the cache) once before the timings; the distance field is warm.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import _path  # noqa: F401  (tests/ on sys.path)
from _table import print_table
from patternfit.body.builtin import load_body
from patternfit.fit import FitEvaluator
from patternfit.sim.drape import drape
from patternfit.sim.newton_engine import mean_dihedral, newton_drape
from scenes import garment, welded


def _checks(d) -> str:
    c = d.checks
    return (f"{c.inside_vertices}in/{c.seam_gap_max_mm:.2f}mm/{c.self_intersections}x/"
            f"{'rest' if c.equilibrium else 'NOT'}")


def _drift(d) -> str:
    """Newton's last-second drift (largest net vertex displacement over 30 frames at 30 fps)."""
    drift = d.timing.get("drift_m")
    return "-" if drift is None else f"{drift * 1e3:.3f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--sizes", nargs="+", default=["coat=22000", "skirt=15000",
                                                   "trousers=20000"])
    ap.add_argument("--body", default="female_average")
    ap.add_argument("--fabric", default="cotton")
    ap.add_argument("--device", default=None)
    args = ap.parse_args()
    body = load_body(args.body)
    body.distance_field(0.005)
    # compile / load Warp's kernels outside the timings
    warm_p, warm_m = garment("skirt", 300)
    t0 = time.perf_counter()
    newton_drape(warm_p, warm_m, body, args.fabric, device=args.device)
    print(f"Warp kernels ready in {time.perf_counter() - t0:.1f} s (compile or cache)")
    rows = []
    for item in args.sizes:
        name, n = item.split("=")
        pattern, mesh = garment(name, int(n))
        fe = FitEvaluator(mesh)
        runs = {}
        try:
            runs["static"] = drape(pattern, mesh, body, args.fabric)
        except Exception as exc:  # noqa: BLE001 - a failing engine is a row, not a crash
            print(f"{name}: static engine failed: {exc!r}")
            continue
        runs["newton"] = newton_drape(pattern, mesh, body, args.fabric, device=args.device)
        runs["from-static"] = newton_drape(pattern, mesh, body, args.fabric, device=args.device,
                                           from_static=runs["static"])
        ref = runs["static"].positions
        for engine, d in runs.items():
            r = fe(d.positions)
            x, vmap = welded(d), d.result.vertex_map
            steps = (f"{d.result.iterations + d.timing.get('sewing_iterations', 0)} it"
                     if engine == "static" else
                     f"{d.timing.get('sewing_iterations', 0)} it+{d.result.iterations} fr")
            rows.append((name, mesh.n_triangles, engine, f"{d.seconds:.1f}", steps, _checks(d),
                         f"{r.fitting_ratio * 100:.3f}",
                         " ".join(f"{v * 100:.2f}" for v in r.panel_ratio),
                         f"{np.linalg.norm(d.positions - ref, axis=1).mean() * 1e3:.1f}",
                         f"{np.degrees(mean_dihedral(x, vmap[mesh.triangles])):.2f}",
                         _drift(d)))
    print_table(f"drape engines on {args.body}, {args.fabric}, device "
                f"{args.device or 'auto'}", rows,
                ("garment", "tris", "engine", "seconds", "iter/frames",
                 "inside/seam/cross/rest", "ϖ %", "ϖ per panel %", "dist mm", "dihedral °",
                 "drift mm/s"))


if __name__ == "__main__":
    main()
