"""Body benchmarks: distance-field build and lookup, loading and measuring a body.

Run: ``python benchmarks/body.py``. Targets (issue 5): build of a 15K-vertex body at 5 mm
< 10 s (then cached), lookup of 20K points < 2 ms.
"""

from __future__ import annotations

import time

import numpy as np

from patternfit.body import DistanceField, load_body, measure


def best(fn, repeat=5):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> None:
    rows = []
    body = load_body("male_heavy")
    rows.append(("load built-in body", best(lambda: load_body("male_heavy")), ""))
    rows.append(("measure (girths, landmarks)", best(lambda: measure(body.vertices, body.faces), 2), ""))
    t = time.perf_counter()
    field = DistanceField.from_mesh(body.vertices, body.faces, spacing=0.005, cache=False)
    rows.append(("SDF build 5 mm, no cache", time.perf_counter() - t,
                 f"{len(body.vertices)} vertices, grid {field.shape}, target < 10 s"))
    DistanceField.from_mesh(body.vertices, body.faces, spacing=0.005)  # fill the cache
    rows.append(("SDF from disk cache", best(lambda: DistanceField.from_mesh(
        body.vertices, body.faces, spacing=0.005), 3), ""))
    rng = np.random.default_rng(0)
    pts = body.vertices[rng.integers(0, len(body.vertices), 20_000)] + rng.normal(0, 0.02, (20_000, 3))
    field.query(pts)  # compile / load the numba kernel
    rows.append(("SDF lookup 20K points", best(lambda: field.query(pts), 20),
                 "distance + gradient, target < 2 ms"))
    print(f"{'step':32s} {'time':>10s}  note")
    for name, sec, note in rows:
        print(f"{name:32s} {sec * 1e3:8.2f} ms  {note}")


if __name__ == "__main__":
    main()
