"""``patternfit batch``: fit a pattern across sizes × bodies × fabrics on Ray."""

from __future__ import annotations

from pathlib import Path

import typer
from rich.progress import (BarColumn, MofNCompleteColumn, Progress, TextColumn,
                           TimeElapsedColumn, TimeRemainingColumn)

from ..defaults import DEFAULTS
from .app import (INTERRUPTED, app, console, fail, folder_option, positive, print_json,
                  triangles_option)
from .show import print_pattern_warnings, say_fabric_notes

# the batch (and through it patternfit.api and Ray) is imported inside the command, when it
# runs: `patternfit --help` should not wait for them (see commands.py)


@app.command()
def batch(
    pattern: str = typer.Option(DEFAULTS.garment, "--pattern", "-p",
                                help="Built-in garment name or a pattern file."),
    sizes: str = typer.Option("all", "--sizes", "-s",
                              help="Comma-separated sizes (S,M,L,XL) or 'all'."),
    bodies: str = typer.Option("population", "--bodies", "-b",
                               help="A body set (`patternfit bodies --set all`: "
                                    "population, builtin), comma-separated body names or patterns "
                                    "(women_*), or a folder of body meshes."),
    fabrics: str = typer.Option(DEFAULTS.fabric, "--fabrics", "-f",
                                help="Comma-separated fabric presets or fabric JSON files."),
    triangles: int = triangles_option(DEFAULTS.triangles),
    workers: int = typer.Option(2, "--workers", "-w", min=0,
                                help="CPUs of the local Ray cluster started for the batch; "
                                     "0 drapes in this process without Ray."),
    address: str = typer.Option(None, "--address", help="Join a running Ray cluster "
                                "(ray://HOST:10001 or HOST:6379) instead of starting one."),
    time_limit: float = typer.Option(DEFAULTS.time_limit, help="The solver's time limit per "
                                     "solve, in seconds (a drape sews, relaxes and drapes); "
                                     "a task running past twice it plus a minute is "
                                     "cancelled.",
                                     callback=positive),
    thumbnails: bool = typer.Option(True, help="Draw a thumbnail per drape for the matrix."),
    out: Path = folder_option(..., "--out", "-o", help="Batch folder: results.csv, "
                              "results.parquet, thumbs/, matrix.png, matrix.html."),
    resume: bool = typer.Option(False, "--resume", help="Finish a batch in --out: redo "
                                "nothing that has a row."),
    json_out: bool = typer.Option(False, "--json", help="Print the summary as JSON."),
) -> None:
    """Drape a pattern in every size on every body in every fabric, and sum up the fit.

    One task each, on a Ray cluster; a row per drape is written as it arrives, and the fit
    is summed up as a matrix of sizes × bodies with one line per size.

    A drape that fails (its checks, an error, a time-out) is a failed row, never a failed
    batch. Ctrl-C stops cleanly (the rows written stay; --resume finishes the batch).
    """
    from ..batch import run_batch

    bar = Progress(TextColumn("[bold]batch"), BarColumn(), MofNCompleteColumn(),
                   TextColumn("{task.fields[last]}"), TimeElapsedColumn(),
                   TextColumn("ETA"), TimeRemainingColumn(), console=console)
    job = bar.add_task("batch", total=None, last="")

    def on_plan(total, done):
        bar.update(job, total=total, completed=done)
        if done:
            console.print(f"resuming: {done} of {total} tasks have a row")

    def progress(row):
        state = "ok" if row["status"] == "ok" else "failed"
        bar.update(job, advance=1, last=f"{row['size']} {row['body']} {row['fabric']}: {state}")

    try:
        with bar:
            result = run_batch(pattern, sizes, bodies, fabrics, out, triangles=triangles,
                               workers=workers, address=address, resume=resume,
                               time_limit=time_limit, thumbnails=thumbnails,
                               on_plan=on_plan, progress=progress)
    except KeyboardInterrupt:
        console.print(f"interrupted: the rows written stay in {out}; finish the batch with "
                      "--resume")
        raise typer.Exit(INTERRUPTED)
    except ImportError as exc:  # Ray, an optional extra; the message says how to get it
        fail(str(exc))
    result["files"] = {k: str(v) for k, v in result["files"].items() if v}
    if json_out:
        print_json(result)
        return
    print_pattern_warnings(result["pattern_warnings"])
    for source, assumed in result["fabric_assumed"].items():
        say_fabric_notes(assumed, source)
    for line in result["lines"]:
        console.print(line, highlight=False)
    console.print(f"{result['rows']} rows ({result['failed']} failed) of {result['tasks']} "
                  f"tasks; {result['skipped']} were done before")
    for path in result["files"].values():
        console.print(f"wrote {path}", highlight=False)
