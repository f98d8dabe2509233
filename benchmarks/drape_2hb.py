"""The Cusick test of the one published set found that gives each woven's own KES-F bending
hysteresis 2HB beside its measured drape coefficient (Matsudaira et al. 2015, four wovens),
with the frictional couple (``Fabric.bending_hysteresis`` = the measured 2HB) and without it.

Run ``python benchmarks/drape_2hb.py [--ids A B C F] [--specimen 0.254 --disc 0.127]
[--triangles 16000] [--seeds 3] [--stretch 450 --shear 50]``; prints one row per fabric
(measured drape coefficient and nodes; simulated mean (min-max) over the starts, simulated /
measured and nodes, without and with 2HB; CPU seconds) and how many are within ±15 % and in
the measured order. The source's table has no tensile or shear stiffness and, in the
transcriptions read, no tester geometry: ``--stretch`` / ``--shear`` [N/m] are put in for
both (the drape is inextensible and unsheared either way; docs/fabrics.md, "Published drape
tests"), and the geometry is a setting (docs/fabrics.md, "A set with its own 2HB").
"""

from __future__ import annotations

import argparse
import time

import _path  # noqa: F401  (tests/ on sys.path, as every benchmark)
from _table import machine, print_table
from physics import not_at_rest, order_agreement, solver_state
from patternfit.sim import fabric_test as kit
from patternfit.sim.fabric_sheets import KES_BENDING, KES_BENDING_HYSTERESIS
from patternfit.sim.fabrics import Fabric

SOURCE = ("Matsudaira, Masuda, Wada & Yokura 2015, \"Shape factor of flared skirts compared "
          "with that of circular fabrics\", J. Textile Eng. 61(6) 69-73, doi 10.4188/jte.61.69, "
          "Table 1 (KES-FB2 B, 2HB; W; T) and Table 2 (drape coefficient, nodes)")
#: id: (fabric, B [gf cm^2/cm], 2HB [gf cm/cm], W [mg/cm^2], T [mm], drape coefficient [-],
#: nodes), read from two public transcriptions of those tables (docs/fabrics.md)
MATSUDAIRA_2015 = {
    "A": ("cotton broad, 100 % cotton plain weave", 0.118, 0.124, 12.38, 0.497, 0.829, 2),
    "B": ("wool tropical, 100 % wool plain weave", 0.067, 0.033, 16.29, 0.407, 0.498, 5),
    "C": ("polyester tropical", 0.077, 0.029, 11.65, 0.340, 0.507, 5),
    "F": ("polyester faille", 0.019, 0.007, 10.43, 0.226, 0.283, 7),
}


def fabric(fid: str, stretch: float, shear: float, hysteresis: bool) -> Fabric:
    """Fabric ``fid`` of :data:`MATSUDAIRA_2015` in SI units; KES reports one B (the mean of
    the two directions), used for both; ``hysteresis`` adds its measured 2HB."""
    _, b, two_hb, w, t, _, _ = MATSUDAIRA_2015[fid]
    return Fabric(f"matsudaira2015_{fid}", density=w * 0.01, stretch_warp=stretch,
                  stretch_weft=stretch, shear=shear, bending_warp=b * KES_BENDING,
                  bending_weft=b * KES_BENDING, friction=0.4, thickness=t * 1e-3,
                  bending_hysteresis=two_hb * KES_BENDING_HYSTERESIS if hysteresis else 0.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--ids", nargs="+", default=list(MATSUDAIRA_2015),
                    choices=list(MATSUDAIRA_2015))
    ap.add_argument("--specimen", type=float, default=0.30, help="specimen diameter [m]")
    ap.add_argument("--disc", type=float, default=0.18, help="disc diameter [m]")
    ap.add_argument("--triangles", type=int, default=16000)
    ap.add_argument("--seeds", type=int, default=3, help="Cusick starts")
    ap.add_argument("--stretch", type=float, default=450.0,
                    help="tensile stiffness put in, both directions [N/m]")
    ap.add_argument("--shear", type=float, default=50.0, help="shear stiffness put in [N/m]")
    ap.add_argument("--setting", nargs="*", default=["time_limit=3000"], metavar="KEY=VALUE",
                    help="SolverSettings fields over the kit's")
    args = ap.parse_args()
    settings = kit.settings_from_pairs(args.setting)
    print(f"{time.strftime('%Y-%m-%d %H:%M')}; {machine()}; {solver_state()}; {SOURCE}")
    rows, measured, sims = [], [], {False: [], True: []}
    for fid in args.ids:
        name, *_, dc, nodes = MATSUDAIRA_2015[fid]
        row = [fid, name, f"{dc:.3f}", str(nodes)]
        measured.append(dc)
        for hyst in (False, True):
            c0 = time.process_time()
            cus = kit.cusick_test(fabric(fid, args.stretch, args.shear, hyst),
                                  specimen=args.specimen, disc=args.disc,
                                  triangles=args.triangles, seeds=tuple(range(args.seeds)),
                                  settings=settings)
            dcs = [r.drape_coefficient for r in cus.runs]
            sims[hyst].append(cus.drape_coefficient)
            row += [f"{cus.drape_coefficient:.3f} ({min(dcs):.3f}-{max(dcs):.3f})",
                    f"{cus.drape_coefficient / dc:.2f}",
                    f"{cus.nodes:.1f} ({cus.nodes_min}-{cus.nodes_max})",
                    f"{time.process_time() - c0:.0f}"]
            not_at_rest(f"{fid} 2HB {'on' if hyst else 'off'}", [r.solve for r in cus.runs])
        rows.append(tuple(row))
        print("  done:", " | ".join(row), flush=True)
    header = ["id", "fabric", "measured DC", "nodes"]
    for label in ("2HB 0", "2HB measured"):
        header += [f"{label}: DC mean (min-max)", "sim/meas", "nodes", "CPU s"]
    print_table(f"Cusick test of Matsudaira et al. 2015's wovens ({args.specimen * 100:g}/"
                f"{args.disc * 100:g} cm, {args.triangles} triangles, {args.seeds} starts, "
                f"stretch {args.stretch:g} N/m, shear {args.shear:g} N/m put in)", rows,
                tuple(header))
    for hyst in (False, True):
        right, pairs, rho = order_agreement(measured, sims[hyst])
        within = sum(abs(s / m - 1) <= 0.15 for s, m in zip(sims[hyst], measured))
        print(f"2HB {'measured' if hyst else '0'}: {within}/{len(measured)} within ±15 %; "
              f"{right}/{pairs} pairs in the measured order; Spearman rho {rho:.2f}")


if __name__ == "__main__":
    main()
