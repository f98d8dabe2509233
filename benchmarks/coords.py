"""Coordinates and mesh-update timings for one panel of ~10K interior and ~300 boundary nodes.

Run ``python benchmarks/coords.py``; prints a table (seconds, best of a few runs).
Targets (issue 4): MVC < 0.5 s, MEC < 2 s, update < 2 ms.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from patternfit.coords import max_entropy_coordinates, mean_value_coordinates
from patternfit.edit import CoordinateCache, edit_curve, update_mesh
from patternfit.edit.update import boundary_positions
from patternfit.mesh import mesh_pattern
from patternfit.pattern.library import build


def best(fn, repeat=3):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main():
    full = build("skirt", "M")
    panel = full.panel("front")
    pattern = replace(full, panels=(panel,), seams=())
    mesh = mesh_pattern(pattern, edge_length=panel.outline.length / 300)
    control = mesh.loops(0)[0]
    interior = np.setdiff1d(np.arange(mesh.n_vertices), control)
    nodes, pts = mesh.vertices[control], mesh.vertices[interior]
    rows = [("panel", f"{len(pts)} interior x {len(nodes)} boundary nodes", "")]
    mean_value_coordinates([nodes], pts[:10])  # compile the kernel
    t, _ = best(lambda: mean_value_coordinates([nodes], pts))
    rows.append(("MVC (robust)", f"{t:.3f} s", "target < 0.5 s"))
    for prior in ("bisector", "edge", "bisector_literal", "uniform", "gaussian"):
        t, (w, info) = best(lambda: max_entropy_coordinates(nodes, pts, prior=prior,
                                                            return_info=True), repeat=1)
        rows.append((f"MEC {prior}", f"{t:.3f} s",
                     f"Newton iterations mean {info.mean_iterations:.2f}, max "
                     f"{info.max_iterations}"))
    new = edit_curve(pattern, "front", "hem", (0.0, -0.02))
    cache = CoordinateCache(mesh)
    update_mesh(pattern, new, mesh, cache=cache)
    pc = cache.get(0)
    delta = boundary_positions(new, mesh)[pc.rows] - mesh.vertices[pc.control]
    t, _ = best(lambda: pc.displace(delta), repeat=50)
    rows.append(("update: interior (fused mat-vec)", f"{t * 1e3:.2f} ms", "target < 2 ms"))
    t, _ = best(lambda: update_mesh(pattern, new, mesh, cache=cache), repeat=10)
    rows.append(("update_mesh (cached, with checks)", f"{t * 1e3:.2f} ms",
                 "edge re-placement, flip and angle checks"))
    width = max(len(r[0]) for r in rows)
    for name, value, note in rows:
        print(f"{name:<{width}}  {value:>12}  {note}")


if __name__ == "__main__":
    main()
