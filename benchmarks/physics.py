"""The virtual fabric-testing kit on every preset (hanging strip, Peirce's cantilever,
Cusick), and the Cusick test of the published fabrics against their measured drape
coefficients.

Run ``python benchmarks/physics.py [--only presets|published] [--fabrics denim ...]
[--triangles N] [--seeds 5] [--meshes 6,12,24] [--compression 1.0,0.05] [--hysteresis 0]
[--specimen 0.30 --disc 0.18]
[--figures DIR] [--json FILE]``; prints one table row per preset (strip
stretch over rho g L^2 / (2 k); cantilever bending length measured / expected, finest mesh,
and the change between the two finest; Cusick drape coefficient mean (min-max over the
starts), nodes, and the share of the free area shrunk by more than 1 %; solves at rest;
seconds per test; ``--setting stop=kinematic ...`` passes SolverSettings fields over the
kit's), then the cantilever's mesh series; then one row per published fabric (measured
drape coefficient, simulated mean (min-max) and simulated / measured at each
``--compression``, nodes, area shrunk by more than 1 %, the source's own CLO3D figure) and
how well the simulated order follows the measured one (``--hysteresis Q`` gives every
published fabric a bending hysteresis 2HB = Q B_geo [Q in 1/m]: their sources do not report
2HB, so this is a sensitivity, docs/fabrics.md). The machine and the solver's source state (commit and a hash
of the working tree's solver sources, ``SOLVER_SOURCES`` and kernels/) are printed with it, since
the solver changes under the kit (docs/fabrics.md, "Testing a fabric").
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import subprocess
import time
from pathlib import Path

import _path  # noqa: F401  (tests/ on sys.path, as every benchmark)
from _table import machine, print_table
from patternfit.files import dumps_finite_json
from patternfit.sim import fabric_test as kit
from patternfit.sim.fabrics import FABRICS, published_drapes

ROOT = Path(__file__).resolve().parent.parent
#: the files of sim/ the solver's numbers depend on (with kernels/)
SOLVER_SOURCES = ("solver.py", "model.py", "state.py", "total_energy.py", "outer_updates.py",
                  "preconditioners.py", "lbfgs.py", "stop_rule.py", "settings.py",
                  "energies.py", "bending_friction.py")


def solver_state() -> str:
    """``<commit> + solver sources <hash>``: which solver the numbers come from."""
    try:
        rev = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                             capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        rev = "?"
    h = hashlib.sha1()
    sim = ROOT / "src" / "patternfit" / "sim"
    for path in (*(sim / name for name in SOLVER_SOURCES),
                 *sorted((sim / "kernels").glob("*.py"))):
        h.update(path.read_bytes())
    return f"commit {rev}, solver sources sha1 {h.hexdigest()[:10]}"


def fmt(value, spec, scale=1.0):
    return "n/a" if value is None else format(value * scale, spec)


def presets(args, settings, dump):
    """The strip, cantilever and Cusick tests of every preset in ``args.fabrics``."""
    meshes = tuple(int(m) for m in args.meshes.split(","))
    rows, series = [], []
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
                     cus.triangles, f"{cus.nodes:.1f} ({cus.nodes_min}-{cus.nodes_max})",
                     f"{shrunk * 100:.1f}", f"{rest}/{len(solves)}",
                     f"{strip.seconds:.1f} / {cant.seconds:.1f} / {cus.seconds:.1f}"))
        for m in cant.meshes:
            series.append((name, f"{m.edge_m * 1e3:.2f}", m.triangles, len(m.runs),
                           f"{m.overhang_m * 1e3:.1f}", f"{m.tip_angle_deg:.2f}",
                           fmt(m.bending_length_m, ".2f", 1e3),
                           fmt(m.bending_length_m and m.bending_length_m
                               / cant.bending_length_expected_m, ".3f")))
        not_at_rest(name, solves)
        if args.figures:
            args.figures.mkdir(parents=True, exist_ok=True)
            kit.write_cusick_picture(cus, args.figures / f"cusick_{name}.png")
        dump[name] = {"strip": strip.to_dict(), "cantilever": cant.to_dict(),
                      "cusick": cus.to_dict()}
    print_table(f"fabric tests (strip 0.5 x 0.05 m; cantilever {args.meshes} edges per "
                f"bending length, 25 mm strip; Cusick 30/18 cm, {mesh_text(args)}, "
                f"{args.seeds} starts)", rows,
                ("fabric", "strip ratio", "bending length mm (meas / exp)", "ratio",
                 "mesh Δ %", "Cusick DC mean (min-max)", "triangles", "nodes", "shrunk %",
                 "at rest", "seconds strip / cant / Cusick"))
    print_table("cantilever mesh series (finest last; ratio = reading / expected)", series,
                ("fabric", "edge mm", "triangles", "solves", "overhang mm", "tip °",
                 "bending length mm", "ratio"))


def mesh_text(args) -> str:
    """The Cusick mesh of a table title."""
    return (f"{args.triangles} triangles" if args.triangles
            else "the kit's mesh (2.5 edges per bending length, 4K-24K triangles)")


def not_at_rest(name, solves):
    bad = sorted({(s.stop_reason, fmt((s.residual or {}).get("residual_rms")
                                      if isinstance(s.residual, dict) else None, ".3g"))
                  for s in solves if not s.at_rest})
    if bad:
        print(f"  {name}: solves not at rest (stop reason, residual rms): {bad}")


def ranks(values):
    order = sorted(range(len(values)), key=values.__getitem__)
    out = [0] * len(values)
    for rank, i in enumerate(order):
        out[i] = rank
    return out


def order_agreement(measured, simulated):
    """(pairs ordered as measured, pairs, Spearman's rho) over all pairs of fabrics."""
    n = len(measured)
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n)
             if measured[i] != measured[j]]
    right = sum((measured[i] - measured[j]) * (simulated[i] - simulated[j]) > 0
                for i, j in pairs)
    rm, rs = ranks(measured), ranks(simulated)
    rho = 1 - 6 * sum((a - b) ** 2 for a, b in zip(rm, rs)) / (n * (n * n - 1)) if n > 1 \
        else float("nan")
    return right, len(pairs), rho


def published(args, settings_text, dump):
    """The Cusick test of every published fabric at each compression share, against its
    measured drape coefficient."""
    comps = [float(c) for c in args.compression.split(",")]
    table = {k: v for k, v in published_drapes().items() if not args.ids or k in args.ids}
    if args.hysteresis:
        table = {k: dataclasses.replace(v, fabric=dataclasses.replace(
            v.fabric, bending_hysteresis=args.hysteresis * (
                v.fabric.bending_warp * v.fabric.bending_weft) ** 0.5))
            for k, v in table.items()}
    rows, sims = [], {c: [] for c in comps}
    for fid, pub in table.items():
        row = [fid, pub.description, f"{pub.drape_coefficient:.3f}"]
        for c in comps:
            st = kit.settings_from_pairs([*settings_text, f"compression={c}"])
            cus = kit.cusick_test(pub.fabric, specimen=args.specimen, disc=args.disc,
                                  triangles=args.triangles, seeds=tuple(range(args.seeds)),
                                  settings=st)
            dcs = [r.drape_coefficient for r in cus.runs]
            shrunk = max(r.compressed_share for r in cus.runs)
            sims[c].append(cus.drape_coefficient)
            row += [f"{cus.drape_coefficient:.3f} ({min(dcs):.3f}-{max(dcs):.3f})",
                    f"{cus.drape_coefficient / pub.drape_coefficient:.2f}", str(cus.triangles),
                    f"{cus.nodes:.1f} ({cus.nodes_min}-{cus.nodes_max})",
                    f"{shrunk * 100:.1f}", f"{cus.seconds:.0f}"]
            not_at_rest(f"{fid} compression {c}", [r.solve for r in cus.runs])
            if args.figures:
                args.figures.mkdir(parents=True, exist_ok=True)
                kit.write_cusick_picture(cus, args.figures / f"cusick_{fid}_c{c:g}.png")
            dump.setdefault(fid, {})[f"cusick_compression_{c:g}"] = cus.to_dict()
        row.append(fmt(pub.drape_coefficient_reference, ".3f"))
        rows.append(tuple(row))
        print("  done:", " | ".join(row), flush=True)
        if args.json:
            args.json.write_text(dumps_finite_json(dump, indent=1) + "\n")
    header = ["fabric", "what", "measured DC"]
    for c in comps:
        header += [f"sim DC c={c:g} mean (min-max)", "sim/meas", "triangles", "nodes",
                   "shrunk %", "s"]
    header.append("CLO3D DC (source)")
    print_table(f"Cusick drape test of published fabrics ({args.specimen * 100:g}/"
                f"{args.disc * 100:g} cm, {mesh_text(args)}, "
                f"{args.seeds} starts; c = stretch stiffness kept in compression; "
                f"bending hysteresis 2HB = {args.hysteresis:g} 1/m x B); sources: "
                f"docs/fabrics.md", rows, tuple(header))
    measured = [p.drape_coefficient for p in table.values()]
    for c in comps:
        right, pairs, rho = order_agreement(measured, sims[c])
        within = sum(abs(s / m - 1) <= 0.15 for s, m in zip(sims[c], measured))
        print(f"compression {c:g}: {within}/{len(measured)} within ±15 % of the measured DC; "
              f"{right}/{pairs} pairs in the measured order; Spearman rho {rho:.2f}")
    ref = [p.drape_coefficient_reference for p in table.values()]
    if all(r is not None for r in ref):
        right, pairs, rho = order_agreement(measured, ref)
        within = sum(abs(r / m - 1) <= 0.15 for r, m in zip(ref, measured))
        print(f"the sources' CLO3D: {within}/{len(measured)} within ±15 %; {right}/{pairs} "
              f"pairs in order; Spearman rho {rho:.2f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--only", choices=("presets", "published"),
                    help="run one of the two sections (default both)")
    ap.add_argument("--fabrics", nargs="+", default=list(FABRICS))
    ap.add_argument("--ids", nargs="+", help="published fabrics to run (default all)")
    ap.add_argument("--triangles", type=int, default=None,
                    help="Cusick mesh (default: the kit's, by each fabric's bending length)")
    ap.add_argument("--seeds", type=int, default=5, help="Cusick starts")
    ap.add_argument("--meshes", default="6,12,24",
                    help="cantilever mesh sizes, edges per bending length")
    ap.add_argument("--compression", default="1.0,0.05",
                    help="published fabrics: stretch stiffness kept in compression, a share "
                         "per column group")
    ap.add_argument("--specimen", type=float, default=0.30,
                    help="published fabrics: Cusick specimen diameter [m] (the transcription "
                         "of their source gives no tester geometry)")
    ap.add_argument("--disc", type=float, default=0.18,
                    help="published fabrics: Cusick disc diameter [m]")
    ap.add_argument("--hysteresis", type=float, default=0.0, metavar="Q",
                    help="published fabrics: bending hysteresis 2HB = Q x sqrt(B_warp B_weft), "
                         "Q in 1/m (their sources give no 2HB; 105 is Matsudaira et al.'s "
                         "broadcloth); default 0")
    ap.add_argument("--figures", type=Path, help="write the Cusick top views here")
    ap.add_argument("--json", type=Path, help="write every result here")
    ap.add_argument("--setting", nargs="*", default=[], metavar="KEY=VALUE",
                    help="SolverSettings fields for every solve over the kit's "
                         f"{kit.AT_REST}, e.g. compression=0.05")
    args = ap.parse_args()
    settings = kit.settings_from_pairs(args.setting)
    # compile the solver's kernels outside the timings
    kit.strip_test("denim", length=0.1)
    print(f"{time.strftime('%Y-%m-%d %H:%M')}; {machine()}; {solver_state()}; settings: kit "
          f"{kit.AT_REST} {' '.join(args.setting)}")
    dump = {}
    if args.only in (None, "presets"):
        presets(args, settings, dump)
    if args.only in (None, "published"):
        published(args, args.setting, dump)
    if args.json:
        args.json.write_text(dumps_finite_json(dump, indent=1) + "\n")
        print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
