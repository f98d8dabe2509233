"""The virtual fabric-testing kit on every preset: hanging strip, Peirce's cantilever, Cusick.

Run ``python benchmarks/physics.py [--fabrics denim ...] [--triangles 4000] [--seeds 5]
[--meshes 6,12,24] [--figures DIR] [--json FILE]``; prints one table row per preset (strip
stretch over rho g L^2 / (2 k); cantilever bending length measured / expected, finest mesh,
and the change between the two finest; Cusick drape coefficient mean (min-max over the
starts), nodes, and the share of the free area shrunk by more than 1 %; solves at rest;
seconds per test; ``--setting stop=kinematic ...`` passes SolverSettings fields), then
the cantilever's mesh series. The machine and the solver's source state (commit and a hash
of the working tree's sim/solver.py, kernels.py, energies.py) are printed with it, since
the solver changes under the kit (docs/fabrics.md, "Testing a fabric").
"""

from __future__ import annotations

import argparse
import hashlib
import subprocess
import time
from pathlib import Path

import _path  # noqa: F401  (tests/ on sys.path, as every benchmark)
from _table import machine, print_table
from patternfit.files import dumps_finite_json
from patternfit.sim import fabric_test as kit
from patternfit.sim.fabrics import FABRICS

ROOT = Path(__file__).resolve().parent.parent


def solver_state() -> str:
    """``<commit> + solver sources <hash>``: which solver the numbers come from."""
    try:
        rev = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                             capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        rev = "?"
    h = hashlib.sha1()
    for name in ("solver.py", "kernels.py", "energies.py"):
        h.update((ROOT / "src" / "patternfit" / "sim" / name).read_bytes())
    return f"commit {rev}, sim/solver.py+kernels.py+energies.py sha1 {h.hexdigest()[:10]}"


def solver_settings(pairs):
    """SolverSettings with ``KEY=VALUE`` fields (numbers, true/false or text), or None."""
    if not pairs:
        return None
    from patternfit.sim.solver import SolverSettings

    values = {}
    for pair in pairs:
        key, _, text = pair.partition("=")
        low = text.lower()
        if low in ("true", "false"):
            values[key] = low == "true"
            continue
        try:
            values[key] = int(text)
        except ValueError:
            try:
                values[key] = float(text)
            except ValueError:
                values[key] = text
    return SolverSettings(**values)


def fmt(value, spec, scale=1.0):
    return "n/a" if value is None else format(value * scale, spec)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--fabrics", nargs="+", default=list(FABRICS))
    ap.add_argument("--triangles", type=int, default=4000, help="Cusick mesh")
    ap.add_argument("--seeds", type=int, default=5, help="Cusick starts")
    ap.add_argument("--meshes", default="6,12,24",
                    help="cantilever mesh sizes, edges per bending length")
    ap.add_argument("--figures", type=Path, help="write the Cusick top views here")
    ap.add_argument("--json", type=Path, help="write every result here")
    ap.add_argument("--setting", nargs="*", default=[], metavar="KEY=VALUE",
                    help="SolverSettings fields for every solve, e.g. stop=kinematic compression=0.05")
    args = ap.parse_args()
    meshes = tuple(int(m) for m in args.meshes.split(","))
    settings = solver_settings(args.setting)
    # compile the solver's kernels outside the timings
    kit.strip_test("denim", length=0.1)
    print(f"{time.strftime('%Y-%m-%d %H:%M')}; {machine()}; {solver_state()}; settings "
          f"{' '.join(args.setting) or f'kit default {kit.AT_REST}'}")
    rows, series, dump = [], [], {}
    for name in args.fabrics:
        strip = kit.strip_test(name, settings=settings)
        cant = kit.cantilever_test(name, meshes=meshes, settings=settings)
        cus = kit.cusick_test(name, triangles=args.triangles, seeds=tuple(range(args.seeds)),
                              settings=settings)
        solves = [strip.solve] + [r.solve for m in cant.meshes for r in m.runs] + \
            [r.solve for r in cus.runs]
        rest = sum(s.at_rest for s in solves)
        shrunk = max(r.compressed_share for r in cus.runs)
        dcs = [r.drape_coefficient for r in cus.runs]
        rows.append((name, fmt(strip.ratio, ".4f"),
                     (f"{fmt(cant.bending_length_measured_m, '.2f', 1e3)} / "
                      f"{cant.bending_length_expected_m * 1e3:.2f}"),
                     fmt(cant.ratio, ".3f"), fmt(cant.mesh_change, ".1f", 100),
                     f"{cus.drape_coefficient:.3f} ({min(dcs):.3f}-{max(dcs):.3f})",
                     f"{cus.nodes:.1f} ({cus.nodes_min}-{cus.nodes_max})",
                     f"{shrunk * 100:.1f}", f"{rest}/{len(solves)}",
                     f"{strip.seconds:.1f} / {cant.seconds:.1f} / {cus.seconds:.1f}"))
        for m in cant.meshes:
            series.append((name, f"{m.edge_m * 1e3:.2f}", m.triangles, len(m.runs),
                           f"{m.overhang_m * 1e3:.1f}", f"{m.tip_angle_deg:.2f}",
                           fmt(m.bending_length_m, ".2f", 1e3),
                           fmt(m.bending_length_m and m.bending_length_m
                               / cant.bending_length_expected_m, ".3f")))
        bad = sorted({(s.stop_reason, fmt((s.residual or {}).get("residual_rms")
                                          if isinstance(s.residual, dict) else None, ".3g"))
                      for s in solves if not s.at_rest})
        if bad:
            print(f"  {name}: solves not at rest (stop reason, residual rms): {bad}")
        if args.figures:
            args.figures.mkdir(parents=True, exist_ok=True)
            kit.write_cusick_picture(cus, args.figures / f"cusick_{name}.png")
        dump[name] = {"strip": strip.to_dict(), "cantilever": cant.to_dict(),
                      "cusick": cus.to_dict()}
    print_table(f"fabric tests (strip 0.5 x 0.05 m; cantilever {args.meshes} edges per "
                f"bending length, 25 mm strip; Cusick 30/18 cm, {cus.triangles} triangles, "
                f"{args.seeds} starts)", rows,
                ("fabric", "strip ratio", "bending length mm (meas / exp)", "ratio",
                 "mesh Δ %", "Cusick DC mean (min-max)", "nodes", "shrunk %",
                 "at rest", "seconds strip / cant / Cusick"))
    print_table("cantilever mesh series (finest last; ratio = reading / expected)", series,
                ("fabric", "edge mm", "triangles", "solves", "overhang mm", "tip °",
                 "bending length mm", "ratio"))
    if args.json:
        args.json.write_text(dumps_finite_json(dump, indent=1) + "\n")
        print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
