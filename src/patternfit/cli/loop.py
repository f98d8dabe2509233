"""``patternfit correct`` (the design loop with automatic fit correction) and
``patternfit reproduce table2`` (the paper's Table 2)."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Optional

import typer

from ..defaults import DEFAULTS
from .app import (SIZE_HELP, Group, app, console, fail, finite, folder_option, print_json,
                  triangles_option, verdict_options)
from .show import (exit_if_correction_failed, run_correction, say_fabric_notes,
                   say_fresh_drape, say_body_notes, show_iteration)

#: the correction's goals (``loop.correct.GOALS``; not imported here: the CLI loads the
#: solver only when a command runs)
GOALS = ("tight", "fits")


def _goal(value: str) -> str:
    if value not in GOALS:
        raise typer.BadParameter(f"expected one of {', '.join(GOALS)}, got {value!r}")
    return value


def goal_option(default: str = "tight"):
    """The ``--goal`` option: the worst region verdict the correction may stop at."""
    return typer.Option(default, "--goal", callback=_goal,
                        help="Stop when no region is worse than this: 'tight' (none too "
                             "tight) or 'fits' (tight regions are let out too).")

# patternfit.api and the stage modules are imported inside the commands, when they run:
# `patternfit --help` should not wait for them (see commands.py)

reproduce = typer.Typer(name="reproduce", cls=Group, no_args_is_help=True,
                        help="Reproduce the paper's experiments.")
app.add_typer(reproduce)


@app.command("correct")
def correct_command(
    body: str = typer.Option(..., "--body", "-b", help="Built-in body name or a mesh file."),
    units: str = typer.Option(None, help="Units of a body mesh file (m, cm, mm, in); guessed "
                                         "from its height when not given."),
    pattern: str = typer.Option(..., "--pattern", "-p",
                                help="Built-in garment name or a pattern file."),
    size: Optional[str] = typer.Option(None, "--size", "-s", help=SIZE_HELP),
    fabric: str = typer.Option(DEFAULTS.fabric, "--fabric", "-f",
                               help="Fabric preset name or a fabric JSON file."),
    triangles: int = triangles_option(DEFAULTS.triangles),
    threshold: float = typer.Option(DEFAULTS.threshold, help="ϖ to reach (0.9 = 90%)."),
    max_iterations: int = typer.Option(DEFAULTS.correction_rounds, "--max-iterations", "-k",
                                       min=0,
                                       help="Correction rounds (edit + re-drape) at most."),
    relax: float = typer.Option(1.0, help="Sew the first drape widened by this factor (>= 1), "
                                          "then restore the true width: for a garment "
                                          "drafted too small to be sewn on the body.",
                                callback=finite),
    take_in: bool = typer.Option(False, "--take-in", help="Also take in the regions the "
                                 "verdict calls too loose (ease above the style's range)."),
    goal: str = goal_option(),
    pressure_max: float = verdict_options()["pressure_max"],
    stretch_limit: float = verdict_options()["stretch_limit"],
    style: str = verdict_options()["style"],
    pictures: bool = typer.Option(True, help="Write the PNG/SVG pictures."),
    out: Path = folder_option(..., "--out", "-o", help="Output folder (new pattern, report)."),
    json_out: bool = typer.Option(False, "--json", help="Print the report as JSON."),
) -> None:
    """Drape, find where the garment is too tight, correct the pattern automatically.

    Each round finds the tight regions, moves the corners of the seams next to them
    outward by the fabric the drape lacks there (both panels of a seam alike, mirror-
    symmetric panels kept symmetric), re-drapes warm-started and evaluates again, until ϖ
    reaches the threshold with no region too tight by the fit verdict (pressure, stretch,
    ease), or the round limit. Regions the corner moves cannot reach (shoulders, sleeves)
    are let out by translating their edges; with --take-in, too-loose regions are taken in. Writes
    OUT/pattern.json (the corrected pattern; never the input), OUT/report.json, before/
    and after/ fit outputs and the regions outlined on the 2D pattern. A drape that failed
    only by crossed triangles is corrected from, its checks in the report. From a first
    drape that is no fit (not on the body where the pattern says: fell, slid off its
    anchor, collapsed; not at rest; cloth inside the body) it corrects nothing, writes no
    pattern and exits with status 1; a round whose re-drape is no fit is stepped back, then
    undone: the pattern written holds the edits before it, and the status is 1, as it is
    when the last drape failed its checks.
    """
    from .. import api

    if not 0 < threshold <= 1.5:
        fail(f"--threshold: expected a fraction such as 0.9, got {threshold}")
    if Path(pattern).exists() and (out / "pattern.json").resolve() == Path(pattern).resolve():
        fail("--out: would overwrite the input pattern; choose another folder")
    t0 = time.perf_counter()
    b = api.read_body(body, units=units)
    say_body_notes(b, body)
    fab, assumed = api.read_fabric_with_notes(fabric)
    say_fabric_notes(assumed, fabric)
    # refused before any work, naming the file, as drape refuses it (unsewn: no file named)
    read = api.check_drapeable(api.read_pattern(pattern, size=size), source=pattern)
    session = api.design_session(read, b, fab, triangles=triangles, threshold=threshold,
                                 relax=relax)
    rules = api.verdict_rules(pressure_max=pressure_max, stretch_limit=stretch_limit,
                              style=style)
    report = run_correction(session, out, threshold=threshold, max_iterations=max_iterations,
                            pictures=pictures, take_in=take_in, verdict_rules=rules,
                            goal=goal)
    if json_out:
        print_json(report)
        exit_if_correction_failed(report, out)
        return
    exit_if_correction_failed(report, out)
    state = "reached" if report["reached"] else "not reached"
    console.print(f"ϖ {report['iterations'][0]['fitting_ratio'] * 100:.2f}% → "
                  f"[bold]{report['fitting_ratio'] * 100:.2f}%[/] (threshold "
                  f"{threshold * 100:.0f}%), verdict "
                  f"{report['iterations'][0].get('verdict') or 'n/a'} → "
                  f"[bold]{report.get('verdict') or 'n/a'}[/]: fit {state} in "
                  f"{report['correction_rounds']} round(s), "
                  f"{report['edits_made']} edits, {time.perf_counter() - t0:.1f} s; "
                  f"wrote {out}/pattern.json and {out}/report.json")
    say_fresh_drape(report)


@reproduce.command("table2")
def table2(
    triangles: int = triangles_option(None, "Override the paper's triangle counts (for a "
                                            "quick run)."),
    garments: str = typer.Option("coat,skirt,trousers", help="Comma-separated rows to run."),
    figures: Path = folder_option(Path("reproduce"), help="Folder the colour maps go to."),
    max_iterations: int = typer.Option(DEFAULTS.table2_rounds, "--max-iterations", "-k",
                                       min=0, help="Correction rounds at most."),
    goal: str = goal_option(DEFAULTS.table2_goal),
    json_out: bool = typer.Option(False, "--json", help="Print the rows as JSON."),
) -> None:
    """The paper's Table 2: coat on the heavy male body, skirt on the thin female body,
    trousers on the thin male body, each drafted too small, corrected automatically."""
    from ..loop.correct import CorrectionSettings
    from ..loop.table2 import ROWS, format_table, run_row

    wanted = [g.strip() for g in garments.split(",") if g.strip()]
    rows = [r for r in ROWS if r.garment in wanted]
    if not rows:
        fail(f"--garments: choose from {', '.join(r.garment for r in ROWS)}")
    t0 = time.perf_counter()
    results = []
    for row in rows:
        console.print(f"[bold]{row.garment}[/] on {row.body}: {row.describe()}")
        try:
            results.append(run_row(row, triangles=triangles, figures=figures,
                                   settings=CorrectionSettings(max_iterations=max_iterations,
                                                               goal=goal),
                                   progress=show_iteration))
        except Exception as exc:  # a row that fails is reported, the others still run
            console.print(f"[red]{row.garment}: failed: {type(exc).__name__}: {exc}[/]")
    if json_out:
        print_json(results)
        return
    console.print(format_table(results), highlight=False)
    console.print(f"total wall time {time.perf_counter() - t0:.1f} s")


@reproduce.command("variants")
def variants(
    triangles: int = triangles_option(DEFAULTS.triangles),
    fabric: str = typer.Option("stretch_knit", "--fabric", "-f",
                               help="Fabric preset or JSON file."),
    figures: Path = folder_option(Path("reproduce"), help="Folder the 3D maps go to."),
    only: str = typer.Option("", help="Comma-separated figure numbers (e.g. 15a,17c)."),
    json_out: bool = typer.Option(False, "--json", help="Print the rows as JSON."),
) -> None:
    """The variants of the paper's Figs 15–17, each draped once, with its ϖ and a 3D map.

    Coat small/original/large, lengthened, shortened; skirt stretched; trousers
    original/stretched/large."""
    from ..loop.table2 import VARIANTS, run_variant

    wanted = {s.strip() for s in only.split(",") if s.strip()}
    rows = []
    for v in VARIANTS:
        if wanted and v[0] not in wanted:
            continue
        with console.status(f"Fig. {v[0]}: {v[1]}, {v[3]}"):
            try:
                rows.append(run_variant(v, triangles=triangles, fabric=fabric,
                                        figures=figures))
            except Exception as exc:  # one failing variant does not stop the others
                console.print(f"[red]Fig. {v[0]}: failed: {type(exc).__name__}: {exc}[/]")
                continue
        r = rows[-1]
        console.print(f"Fig. {r['figure']:4} {r['garment']:9} {r['variant']:24} ϖ "
                      f"{r['fitting_ratio'] * 100:6.2f}%  checks "
                      f"{'passed' if r['checks_passed'] else 'failed'}  {r['seconds']:.1f} s"
                      + "".join(f"\n    {why}" for why in r["reasons"]), highlight=False)
    if json_out:
        print_json(rows)
