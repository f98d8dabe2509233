"""``patternfit correct`` (the design loop with automatic fit correction) and
``patternfit reproduce table2`` (the paper's Table 2)."""

from __future__ import annotations

import time
from pathlib import Path

import typer

from .app import app, console, fail, finite, print_json, triangles_option
from .commands import load_pattern_arg
from .drape import load_body_arg

reproduce = typer.Typer(name="reproduce", no_args_is_help=True,
                        help="Reproduce the paper's experiments.")
app.add_typer(reproduce)


def show_iteration(it) -> None:
    """One line per loop iteration, its regions and edits (for the console)."""
    what = "first drape" if it.index == 0 else f"after round {it.index}"
    ok = "" if not it.checks or it.checks.get("passed") else "  [yellow](drape checks failed)[/]"
    console.print(f"[bold]{what}[/]: ϖ = {it.fitting_ratio * 100:.2f}%  "
                  f"({it.seconds:.1f} s){ok}")
    for r in it.regions[:6]:
        console.print(f"   {'▲' if r.kind == 'tight' else '▽'} {r.describe()}", highlight=False)
    if len(it.regions) > 6:
        console.print(f"   … and {len(it.regions) - 6} smaller region(s)")
    if it.edits:
        moves = ", ".join(f"{e.panel}/{e.edge} {e.to_dict()['cm']:.1f}" for e in it.edits)
        console.print(f"   edits (corner moves, cm): {moves}", highlight=False)


def run_correction(session, *, threshold: float, max_iterations: int, out: Path,
                   extra: dict | None = None, pictures: bool = True):
    """Drape, correct with a progress display, write the outputs; returns the report."""
    from ..loop.correct import CorrectionSettings, correct
    from ..loop.outputs import write_correction_outputs
    from .drape import drape_progress

    settings = CorrectionSettings(threshold=threshold, max_iterations=max_iterations)
    bar, callback = drape_progress(console, total=5000)
    with bar:
        result = correct(session, settings=settings, drape_progress=callback,
                         progress=lambda it: bar.console.print() or show_iteration(it))
    with console.status("writing outputs") as status:
        report = write_correction_outputs(out, session, result, extra=extra, pictures=pictures,
                                          progress=lambda s: status.update(f"writing {s}"))
    return report


@app.command("correct")
def correct_command(
    body: str = typer.Option(..., "--body", "-b", help="Built-in body name or a mesh file."),
    units: str = typer.Option(None, help="Units of a body mesh file (m, cm, mm, in); guessed "
                                         "from its height when not given."),
    pattern: str = typer.Option(..., "--pattern", "-p",
                                help="Built-in garment name or a pattern file."),
    size: str = typer.Option("M", "--size", "-s", help="Size of a built-in garment: S–XL."),
    fabric: str = typer.Option("cotton", "--fabric", "-f",
                               help="Fabric preset name or a fabric JSON file."),
    triangles: int = triangles_option(3000),
    threshold: float = typer.Option(0.9, help="ϖ to reach (0.9 = 90%)."),
    max_iterations: int = typer.Option(3, "--max-iterations", "-k", min=0,
                                       help="Correction rounds (edit + re-drape) at most."),
    relax: float = typer.Option(1.0, help="Sew the first drape widened by this factor (>= 1), "
                                          "then restore the true width: for a garment "
                                          "drafted too small to be sewn on the body.",
                                callback=finite),
    pictures: bool = typer.Option(True, help="Write the PNG/SVG pictures."),
    out: Path = typer.Option(..., "--out", "-o", help="Output folder (new pattern, report)."),
    json_out: bool = typer.Option(False, "--json", help="Print the report as JSON."),
) -> None:
    """Drape, find where the garment is too tight, correct the pattern automatically.

    Each round finds the tight regions, moves the corners of the seams next to them
    outward by the fabric the drape lacks there (both panels of a seam alike, mirror-
    symmetric panels kept symmetric), re-drapes warm-started and evaluates again, until ϖ
    reaches the threshold with no region much too tight, or the round limit. Writes
    OUT/pattern.json (the corrected pattern; never the input), OUT/report.json, before/
    and after/ fit outputs and the regions outlined on the 2D pattern.
    """
    from ..loop.session import DesignSession
    from ..sim.fabrics import get_fabric

    if not 0 < threshold <= 1.5:
        fail(f"--threshold: expected a fraction such as 0.9, got {threshold}")
    pat = load_pattern_arg(pattern, size)
    if Path(pattern).exists() and (out / "pattern.json").resolve() == Path(pattern).resolve():
        fail("--out: would overwrite the input pattern; choose another folder")
    b = load_body_arg(body, units)
    fab = get_fabric(fabric)
    t0 = time.perf_counter()
    session = DesignSession(pat, b, fab, triangles, threshold, relax=relax)
    report = run_correction(session, threshold=threshold, max_iterations=max_iterations,
                            out=out, pictures=pictures)
    if json_out:
        print_json(report)
        return
    state = "reached" if report["reached"] else "not reached"
    console.print(f"ϖ {report['iterations'][0]['fitting_ratio'] * 100:.2f}% → "
                  f"[bold]{report['fitting_ratio'] * 100:.2f}%[/] (threshold "
                  f"{threshold * 100:.0f}% {state}) in {report['correction_rounds']} round(s), "
                  f"{report['edits_made']} edits, {time.perf_counter() - t0:.1f} s; "
                  f"wrote {out}/pattern.json and {out}/report.json")


@reproduce.command("table2")
def table2(
    triangles: int = triangles_option(None, "Override the paper's triangle counts (for a "
                                            "quick run)."),
    garments: str = typer.Option("coat,skirt,trousers", help="Comma-separated rows to run."),
    figures: Path = typer.Option(Path("docs/figures"), help="Where the colour maps go."),
    max_iterations: int = typer.Option(3, "--max-iterations", "-k", min=0,
                                       help="Correction rounds at most."),
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
                                   settings=CorrectionSettings(max_iterations=max_iterations),
                                   progress=show_iteration))
        except Exception as exc:  # a row that fails is reported, the others still run
            console.print(f"[red]{row.garment}: failed: {type(exc).__name__}: {exc}[/]")
    if json_out:
        print_json(results)
        return
    console.print(format_table(results), highlight=False, soft_wrap=True)
    console.print(f"total wall time {time.perf_counter() - t0:.1f} s")


@reproduce.command("variants")
def variants(
    triangles: int = triangles_option(3000),
    fabric: str = typer.Option("stretch_knit", "--fabric", "-f",
                               help="Fabric preset or JSON file."),
    figures: Path = typer.Option(Path("docs/figures"), help="Where the 3D maps go."),
    only: str = typer.Option("", help="Comma-separated figure numbers (e.g. 15a,17c)."),
    json_out: bool = typer.Option(False, "--json", help="Print the rows as JSON."),
) -> None:
    """The variants of the paper's Figs 15–17 (coat small/original/large, lengthened,
    shortened; skirt stretched; trousers original/stretched/large), each draped once, with
    its ϖ and a 3D colour map."""
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
                      f"{'passed' if r['checks_passed'] else 'failed'}  {r['seconds']:.1f} s",
                      highlight=False)
    if json_out:
        print_json(rows)
