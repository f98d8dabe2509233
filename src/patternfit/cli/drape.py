"""``patternfit drape``: place, sew and drape a garment on a body, then evaluate the fit."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from ..defaults import DEFAULTS
from .app import (INTERRUPTED, SIZE_HELP, app, console, fail, finite, folder_option, positive,
                  print_json, triangles_option, verdict_options)
from .show import (drape_progress, exit_if_checks_failed, print_drape_checks, print_fit_summary,
                   print_pattern_warnings, say_body_notes, say_fabric_notes)

# patternfit.api and the stage modules are imported inside the commands, when they run:
# `patternfit --help` should not wait for them (see commands.py)


@app.command()
def drape(
    body: str = typer.Option(DEFAULTS.body, "--body", "-b",
                             help="Built-in body name (see `patternfit bodies`) or a mesh file."),
    pattern: str = typer.Option(DEFAULTS.garment, "--pattern", "-p",
                                help="Built-in garment name or a pattern file (JSON, "
                                     "GarmentCode JSON, DXF)."),
    size: Optional[str] = typer.Option(None, "--size", "-s", help=SIZE_HELP),
    fabric: str = typer.Option(DEFAULTS.fabric, "--fabric", "-f",
                               help="Fabric preset name or a fabric JSON file."),
    triangles: int = triangles_option(DEFAULTS.triangles),
    clearance: float = typer.Option(DEFAULTS.clearance, help="Gap between body and panels at "
                                    "placement \\[m].", callback=finite),
    max_iterations: int = typer.Option(DEFAULTS.max_iterations, min=0,
                                       help="Iteration limit of the drape under gravity "
                                            "(sewing and relaxing have their own)."),
    time_limit: float = typer.Option(DEFAULTS.time_limit,
                                     help="Time limit of each solve of the drape \\[s] "
                                          "(sewing, relaxing, draping, each retried sewing: a "
                                          "drape that sews again takes several times it).",
                                     callback=positive),
    units: str = typer.Option(None, help="Units of a body mesh file (m, cm, mm, in); guessed "
                                         "from its height when not given."),
    engine: str = typer.Option("static", help="static (equilibrium, default) or newton "
                                              "(dynamic, Style3D; pip install "
                                              "\"patternfit\\[newton]\")."),
    device: str = typer.Option(None, help="newton: Warp device (cpu, cuda); default CUDA "
                                          "when present, else cpu."),
    from_static: bool = typer.Option(False, "--from-static", help="newton: start at the static "
                                     "equilibrium, slightly perturbed, so that folds form."),
    start: Path = typer.Option(None, "--start", help="Continue from a saved drape of the same "
                               "pattern, on its own mesh (--triangles is not used): its "
                               "garment/ folder (pattern.json, mesh.npz, positions.npy, "
                               "contact.npz), or the output folder holding it (patternfit "
                               "drape's, or correct's before/ and after/). From a drape at "
                               "rest, with the contact.npz saved beside its positions, it "
                               "stops at once; without it, the contact is found afresh and "
                               "the cloth may settle a few millimetres."),
    pictures: bool = typer.Option(True, help="Write the PNG/SVG pictures."),
    pressure_max: float = verdict_options()["pressure_max"],
    stretch_limit: float = verdict_options()["stretch_limit"],
    style: str = verdict_options()["style"],
    out: Path = folder_option(..., "--out", "-o", help="Output folder."),
    json_out: bool = typer.Option(False, "--json", help="Print the report as JSON."),
) -> None:
    """Drape a garment on a body to static equilibrium and evaluate its fit.

    Writes the draped garment (GLB/OBJ with fit colours), the 2D and 3D colour maps, the
    gap and pressure maps, the girth sections and report.json with the fit verdict (too
    tight, tight, fits, loose, too loose; per region: ease, pressure, stretch), the checks
    (vertices inside the body, seam gaps, self-intersections, equilibrium, and whether it
    rests on the body where its pattern says) and the timing; a failed drape exits with
    status 1 and says why. Ctrl-C stops the drape cleanly and keeps the last state.
    """
    from .. import api
    from ..sim.newton_engine import ENGINES, NewtonMissingError
    from ..sim.settings import SolverSettings

    if engine not in ENGINES or (engine == "static" and (from_static or device)):
        fail(f"--engine: one of {', '.join(ENGINES)}; --device and --from-static need newton")
    if start is not None:
        if engine != "static":
            fail("--start: a saved drape is continued by the static engine only")
    b = api.read_body(body, units=units)
    say_body_notes(b, body)
    fab, assumed = api.read_fabric_with_notes(fabric)
    say_fabric_notes(assumed, fabric)
    settings = SolverSettings(max_iterations=max_iterations, time_limit=time_limit)
    rules = api.verdict_rules(pressure_max=pressure_max, stretch_limit=stretch_limit,
                              style=style)
    bar, callback = drape_progress(total=max_iterations, rest=settings.residual_rms)
    with bar:
        try:
            outcome = api.drape_and_evaluate(pattern, b, fab, triangles=triangles, size=size,
                                             engine=engine, settings=settings, device=device,
                                             from_static=from_static, clearance=clearance,
                                             start=start, progress=callback,
                                             verdict_rules=rules)
        except NewtonMissingError as exc:
            fail(str(exc))
    if assumed:
        outcome.extra["fabric_assumed"] = list(assumed)
    report = outcome.write(out, pictures=pictures)
    if json_out:
        print_json(report)
    else:
        print_pattern_warnings(report.get("pattern_warnings"))
        print_fit_summary(report, out, outcome.seconds)
        print_drape_checks(report)
    if outcome.interrupted:
        # the state reached is written (--start continues it), marked failed; the status
        # is Ctrl-C's, not a garment's failed checks
        console.print(f"interrupted: the state reached is in {out}/ (no equilibrium: not a "
                      f"fit); continue it with --start {out}", highlight=False)
        raise typer.Exit(INTERRUPTED)
    exit_if_checks_failed(report, out)
