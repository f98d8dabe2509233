"""``patternfit drape``: place, sew and drape a garment on a body, then evaluate the fit."""

from __future__ import annotations

import time
from pathlib import Path

import typer
from rich.markup import escape

from .app import app, console, fail, finite, print_json, triangles_option
from .commands import exit_if_checks_failed, load_pattern_arg, num, print_fit_summary


def load_body_arg(body: str, units: str | None = None):
    """A built-in body name or a body mesh file (``units`` of the file; guessed from the
    body's height when None, and the guess printed)."""
    from ..body.builtin import list_bodies, load_body
    from ..body.mesh_io import load_body_mesh

    path = Path(body)
    if path.suffix and path.exists():
        b = load_body_mesh(path, units=units)
        say_guessed_units(b, path)
        return b
    try:
        return load_body(body)
    except ValueError:
        fail(f"'{body}' is neither a built-in body ({', '.join(list_bodies())}) nor a mesh file")


def say_guessed_units(body, path: Path) -> None:
    """Print the unit a body mesh file was read in when it was guessed, not given: a wrong
    guess (a child's body in inches read as centimetres) changes every result."""
    import numpy as np

    if not body.meta.get("units_guessed"):
        return
    unit = body.meta["units"]
    console.print(f"[yellow]note:[/] {escape(str(path))}: units guessed as '{unit}' from the "
                  f"body's height ({np.ptp(body.vertices[:, 1]):.2f} m); give --units if "
                  "that is wrong", highlight=False)


def drape_progress(console_, *, total: int):
    """A rich progress bar and the solver callback that feeds it (iteration, energy, step)."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    bar = Progress(TextColumn("[bold]draping"), BarColumn(), TextColumn("{task.fields[info]}"),
                   TimeElapsedColumn(), console=console_, transient=True)
    task = bar.add_task("drape", total=total, info="")

    def callback(it, energy, step, elapsed):
        bar.update(task, completed=min(it, total),
                   info=f"it {it}  E {energy:.4g} J  step {step * 1000:.3f} mm")
    return bar, callback


@app.command()
def drape(
    body: str = typer.Option("female_average", "--body", "-b",
                             help="Built-in body name (see `patternfit bodies`) or a mesh file."),
    pattern: str = typer.Option("skirt", "--pattern", "-p",
                                help="Built-in garment name or a pattern file (JSON, "
                                     "GarmentCode JSON, DXF)."),
    size: str = typer.Option("M", "--size", "-s", help="Size of a built-in garment: S–XL."),
    fabric: str = typer.Option("cotton", "--fabric", "-f",
                               help="Fabric preset name or a fabric JSON file."),
    triangles: int = triangles_option(3000),
    clearance: float = typer.Option(0.03, help="Gap between body and panels at placement [m].",
                                    callback=finite),
    max_iterations: int = typer.Option(5000, min=0, help="Iteration limit of the drape."),
    time_limit: float = typer.Option(300.0, help="Time limit of the drape [s].",
                                     callback=finite),
    units: str = typer.Option(None, help="Units of a body mesh file (m, cm, mm, in); guessed "
                                         "from its height when not given."),
    engine: str = typer.Option("static", help="static (equilibrium, default) or newton "
                                              "(dynamic, Style3D; pip install "
                                              "\"patternfit[newton]\")."),
    device: str = typer.Option(None, help="newton: Warp device (cpu, cuda); default CUDA "
                                          "when present, else cpu."),
    from_static: bool = typer.Option(False, "--from-static", help="newton: start at the static "
                                     "equilibrium, slightly perturbed, so that folds form."),
    pictures: bool = typer.Option(True, help="Write the PNG/SVG pictures."),
    out: Path = typer.Option(..., "--out", "-o", help="Output folder."),
    json_out: bool = typer.Option(False, "--json", help="Print the report as JSON."),
) -> None:
    """Drape a garment on a body to static equilibrium and evaluate its fit.

    Writes the draped garment (GLB/OBJ with fit colours), the 2D and 3D colour maps and
    report.json with the checks (vertices inside the body, seam gaps, self-intersections,
    equilibrium) and the timing. Ctrl-C stops the drape cleanly and keeps the last state.
    """
    from ..fit.metrics import FitEvaluator
    from ..fit.outputs import write_fit_outputs
    from ..mesh.triangulate import mesh_pattern
    from ..sim.fabrics import get_fabric
    from ..sim.newton_engine import ENGINES, NewtonMissingError, drape_with
    from ..sim.solver import SolverSettings

    t0 = time.perf_counter()
    if engine not in ENGINES or (engine == "static" and (from_static or device)):
        fail(f"--engine: one of {', '.join(ENGINES)}; --device and --from-static need newton")
    b = load_body_arg(body, units)
    pat = load_pattern_arg(pattern, size)
    fab = get_fabric(fabric)
    m = mesh_pattern(pat, triangles=triangles)
    settings = SolverSettings(max_iterations=max_iterations, time_limit=time_limit)
    bar, callback = drape_progress(console, total=max_iterations)
    with bar:
        try:
            d = drape_with(engine, pat, m, b, fab, settings=settings, device=device,
                           from_static=from_static, clearance=clearance, progress=callback)
        except NewtonMissingError as exc:
            fail(str(exc))
    evaluator = FitEvaluator(m)
    placed_ratio = evaluator.metrics(d.placed)[1]
    result = evaluator(d.positions)
    extra = d.report_extra()
    extra.update(body=b.name, fabric=fab.name, fitting_ratio_placed=placed_ratio)
    report = write_fit_outputs(out, pat, m, d.positions, result, state="draped",
                               body=(b.vertices, b.faces), pictures=pictures, extra=extra)
    if json_out:
        print_json(report)
    else:
        print_fit_summary(report, out, time.perf_counter() - t0)
        c = report["checks"]
        verdict = "[green]passed[/]" if c["passed"] else "[bold red]FAILED[/]"
        console.print(f"checks {verdict}: {c['inside_vertices']} vertices inside the body "
                      f"(deepest {num(c['max_depth_mm'], '.2f')} mm), seam gap "
                      f"{num(c['seam_gap_max_mm'], '.2f')} mm, {c['self_intersections']} "
                      f"self-intersections, equilibrium {c['equilibrium']} "
                      f"({c['stop_reason']}); {report['timing']['iterations']} iterations in "
                      f"{num(report['timing']['seconds'], '.1f')} s; ϖ after placement "
                      f"{num(report['fitting_ratio_placed'], '.2f', 100)}%")
    exit_if_checks_failed(report, out)
