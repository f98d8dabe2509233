"""Meshing and fit evaluation of the built-in garments (targets: coat 22K meshed < 1 s,
fit metrics < 2 ms, with colours < 20 ms). Run: python benchmarks/foundation.py"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import _path  # noqa: E402, F401  (tests/ on sys.path)
from _table import median_time, print_table  # noqa: E402

from patternfit.fit import FitEvaluator, FitScale, vertex_values  # noqa: E402
from patternfit.mesh import mesh_pattern  # noqa: E402
from patternfit.sim.placement import place_on_cylinders  # noqa: E402
from scenes import garment  # noqa: E402


def main() -> None:
    rows = []
    for name, n in (("coat", 22000), ("skirt", 15000), ("trousers", 20000), ("dress", 20000)):
        pattern, mesh = garment(name, n)
        t_mesh = median_time(lambda: mesh_pattern(pattern, triangles=n), repeat=5)
        x = place_on_cylinders(pattern, mesh)
        ev = FitEvaluator(mesh)
        scale = FitScale()
        t_metrics = median_time(lambda: ev.metrics(x), repeat=50, warmup=3)
        t_full = median_time(lambda: ev(x), repeat=20, warmup=2)

        def with_colours():
            r = ev(x)
            scale.colors(r.area_change)
            scale.colors(vertex_values(mesh.triangles, r.area_change, mesh.n_vertices, r.area_2d))
        t_col = median_time(with_colours, repeat=20, warmup=2)
        rows.append((name, mesh.n_triangles, mesh.n_vertices, f"{t_mesh * 1000:.0f}",
                     f"{t_metrics * 1000:.2f}", f"{t_full * 1000:.1f}", f"{t_col * 1000:.1f}"))
    print_table("foundation: meshing and fit evaluation (median times)", rows,
                ("garment", "triangles", "vertices", "mesh ms", "ϖ+areas ms",
                 "all metrics ms", "metrics+colours ms"))


if __name__ == "__main__":
    main()
