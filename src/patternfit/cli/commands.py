"""Foundation commands: ``patterns``, ``mesh``, ``fit`` and ``demo``.

Each command parses its options and calls :mod:`patternfit.api`, imported when it runs (the
API loads the solver and its compiled kernels, which ``--help`` should not wait for)."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Optional

import typer
from rich.markup import escape
from rich.table import Table

from ..defaults import DEFAULTS
from ..text import printable
from .app import (SIZE_HELP, app, console, fail, listing, finite, folder_option, print_json,
                  triangles_option, verdict_options)
from .show import (exit_if_checks_failed, exit_if_correction_failed, print_fit_summary,
                   print_pattern_warnings, run_correction, say_fresh_drape, say_body_notes)

Out = folder_option(..., "--out", "-o", help="Output folder (created if missing).")
Json = typer.Option(False, "--json", help="Print machine-readable results on stdout.")


@app.command()
def patterns(
    name: Optional[str] = typer.Argument(None, help="A built-in garment to write out."),
    size: str = typer.Option(DEFAULTS.size, "--size", "-s", help="Size: S, M, L or XL."),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="Write the pattern here: "
                                       ".json (ours), .dxf, .svg, .pdf, or "
                                       "_specification.json (GarmentCode), by the ending."),
    units: str = typer.Option("cm", help="Units written in the file: m, cm, mm or in."),
    json_out: bool = Json,
) -> None:
    """List the built-in garments, or write one in patternfit's JSON format (or another, by
    the file's ending)."""
    from ..pattern.formats import save_any_pattern
    from ..pattern.library import GARMENTS, build

    if name is None:
        rows = []
        for key, (_, chart, text, _) in GARMENTS.items():
            p = build(key, size)
            rows.append({"name": key, "description": text, "size_chart": chart,
                         "panels": len(p.panels), "seams": len(p.seams),
                         "panel_names": [q.name for q in p.panels],
                         "area_m2": round(p.area(), 5)})
        if json_out:
            print_json(rows)
            return
        table = Table(title=f"built-in garments (size {size})")
        for col in ("name", "panels", "seams", "fabric m²", "description"):
            table.add_column(col)
        for r in rows:
            table.add_row(r["name"], str(r["panels"]), str(r["seams"]), f"{r['area_m2']:.3f}",
                          r["description"])
        listing.print(table)
        return
    if name not in GARMENTS:
        fail(f"unknown garment '{name}' (built-in: {', '.join(GARMENTS)})")
    pattern = build(name, size)
    if out is None:
        fail("give --out FILE.json to write the pattern")
    # by the ending: "p.dxf" held JSON
    save_any_pattern(pattern, out, units=units)
    if json_out:
        print_json({"name": name, "size": size.upper(), "file": str(out),
                    "panels": len(pattern.panels), "seams": len(pattern.seams)})
    else:
        console.print(f"wrote {out} ({name}, size {size.upper()}, units {units})")


@app.command()
def mesh(
    pattern: str = typer.Argument(..., help="Pattern file (JSON, GarmentCode JSON, DXF) or "
                                            "built-in garment name."),
    triangles: int = triangles_option(DEFAULTS.mesh_triangles),
    min_angle: float = typer.Option(25.0, help="Minimum triangle angle \\[degrees].",
                                    callback=finite),
    size: Optional[str] = typer.Option(None, "--size", "-s", help=SIZE_HELP),
    out: Path = Out,
    json_out: bool = Json,
) -> None:
    """Mesh every panel (seams matched) and save the garment folder (pattern.json, mesh.npz)."""
    from .. import api
    from ..mesh import min_angle as smallest_angle

    pat = api.read_pattern(pattern, size=size)
    t0 = time.perf_counter()
    m = api.mesh_garment(pat, triangles=triangles, min_angle=min_angle)
    seconds = time.perf_counter() - t0
    api.save_garment(out, pat, m)
    info = {"garment": pat.name, "folder": str(out), "vertices": m.n_vertices,
            "triangles": m.n_triangles, "panels": len(m.panel_names), "seams": len(m.seam_names),
            "seam_pairs": int(len(m.seam_pairs)),
            "min_angle_deg": smallest_angle(m.vertices, m.triangles), "seconds": seconds,
            "warnings": list(pat.meta.get("warnings", []))}
    if json_out:
        print_json(info)
    else:
        print_pattern_warnings(info["warnings"])
        console.print(f"meshed '{pat.name}': {m.n_vertices} vertices, {m.n_triangles} triangles, "
                      f"min angle {info['min_angle_deg']:.1f}°, {info['seam_pairs']} seam pairs "
                      f"in {seconds * 1000:.0f} ms → {out}/")


@app.command()
def fit(
    garment: Path = typer.Option(..., "--garment", "-g",
                                 help="Saved garment folder with a 3D state (positions.npy), "
                                 "or the output folder of a drape holding it."),
    out: Path = Out,
    tight: float = typer.Option(DEFAULTS.tight, help="Area growth above which a triangle is "
                                "tight.", callback=finite),
    loose: float = typer.Option(DEFAULTS.loose, help="Area loss above which a triangle is "
                                "loose.", callback=finite),
    body: Optional[str] = typer.Option(None, "--body", "-b", help="The body it was draped "
                                       "on (built-in name or mesh file): adds the checks "
                                       "of where it rests, the fit measures and the "
                                       "verdict."),
    fabric: Optional[str] = typer.Option(None, "--fabric", "-f",
                                         help=f"Its fabric (with --body; default: the "
                                              f"one its drape saved, else "
                                              f"{DEFAULTS.fabric})."),
    pressure_max: float = verdict_options()["pressure_max"],
    stretch_limit: float = verdict_options()["stretch_limit"],
    style: str = verdict_options()["style"],
    pictures: bool = typer.Option(True, help="Write the PNG/SVG pictures."),
    json_out: bool = Json,
) -> None:
    """Evaluate the fit of a saved 3D state: ϖ, colour maps, report.json.

    With --body (the body it was draped on) also the state's checks on that body (where it
    rests, vertices inside, seams open), the fit measures (gap, ease, pressure) and the
    verdict. Exits with status 1 when the evaluation failed its checks (the garment fell,
    slid or lies off the body; a value such as ϖ is not finite)."""
    from .. import api

    if fabric is not None and body is None:
        fail("--fabric is used with --body only (the fit measures and the verdict on the "
             "body); give the body it was draped on, or leave --fabric out")
    t0 = time.perf_counter()
    rules = api.verdict_rules(pressure_max=pressure_max, stretch_limit=stretch_limit,
                              style=style)
    read = None if body is None else api.read_body(body)
    if read is not None:  # a body file's guessed unit, or its turn to face +Z, is said
        say_body_notes(read, body)
    outcome = api.evaluate_saved(garment, tight=tight, loose=loose, body=read,
                                 fabric=fabric, verdict_rules=rules)
    report = outcome.write(out, pictures=pictures)
    if json_out:
        print_json(report)
    else:
        print_fit_summary(report, out, time.perf_counter() - t0)
        if body is None and report["checks"].get("passed") is None:
            console.print("[yellow]not checked:[/] without --body nothing says whether the "
                          "garment rests on a body; ϖ alone is not a fit verdict")
        elif report["checks"].get("rebuilt_residual_p99") is not None \
                and report["checks"]["equilibrium"] is None:
            c = report["checks"]
            console.print(
                f"[yellow]equilibrium not known:[/] "
                f"{escape(printable(c['equilibrium_unknown'] or ''))}; with the body pushing "
                f"and friction holding as they may, 1% of the vertices are off by "
                f"{c['rebuilt_residual_p99']:.3g} of their weight or more, the most by "
                f"{c['rebuilt_residual_max']:.3g} (above 1 and 5000 fail); `patternfit drape "
                "--start` settles and checks it", highlight=False)
    exit_if_checks_failed(report, out)


@app.command()
def demo(
    out: Path = folder_option(Path("patternfit-demo"), "--out", "-o", help="Output folder."),
    garment: Optional[str] = typer.Option(None, help="Built-in garment (default: skirt; coat "
                                                      "with --no-drape)."),
    size: Optional[str] = typer.Option(None, "--size", "-s",
                                       help="Size: S, M, L or XL (default: the garment's "
                                            "Table 2 size, else M)."),
    triangles: Optional[int] = triangles_option(None, "Target triangle count (default 3000; "
                                                      "22000 with --no-drape)."),
    drape: bool = typer.Option(True, help="Run the design loop (drape, regions, automatic "
                                          "correction); --no-drape only places the garment."),
    json_out: bool = Json,
) -> None:
    """The design loop on a built-in garment drafted too small, from drape to corrected fit.

    Drapes it, evaluates the fit, names the regions to modify, corrects the pattern
    automatically and writes the report with before/after pictures (the paper's Fig. 1
    loop; about half a minute on a laptop CPU).

    With --no-drape, only mesh and place the garment isometrically (panels rolled onto
    cylinders around the body): its fitting ratio is 100%, the paper's Fig. 8(b).
    """
    from .. import api

    if not drape:
        return _demo_placed(out, garment or "coat", size or DEFAULTS.size, triangles or 22000,
                            json_out)
    garment = garment or DEFAULTS.garment
    t0 = time.perf_counter()
    setup = api.drafted_too_small(garment, size)
    console.print(f"[bold]{garment}[/] size {setup['size']} drafted too small (narrowed to "
                  f"{setup['narrow']:.0%} of its width) in {setup['fabric']}, on the body "
                  f"'{setup['body']}'")
    session = api.design_session(setup["pattern"], setup["body"], setup["fabric"],
                                 triangles=triangles or DEFAULTS.triangles, relax=setup["relax"])
    placed = api.placed_fitting_ratio(session)
    report = run_correction(session, out, threshold=DEFAULTS.threshold,
                            max_iterations=DEFAULTS.correction_rounds,
                            extra={"fitting_ratio_placed": placed, "narrow": setup["narrow"]})
    if json_out:
        print_json(report)
        exit_if_correction_failed(report, out)
        return
    exit_if_correction_failed(report, out)
    console.print(f"ϖ placed {placed * 100:.2f}% → first drape "
                  f"{report['iterations'][0]['fitting_ratio'] * 100:.2f}% → corrected "
                  f"[bold]{report['fitting_ratio'] * 100:.2f}%[/] (verdict "
                  f"{report['iterations'][0].get('verdict') or 'n/a'} → "
                  f"{report.get('verdict') or 'n/a'}) in "
                  f"{report['correction_rounds']} round(s), {report['edits_made']} corner "
                  f"moves; {time.perf_counter() - t0:.1f} s. Wrote {out}/: pattern.json "
                  "(corrected), report.json, regions_before/after.png, before/ and after/ "
                  "(colour maps, GLB)")
    say_fresh_drape(report)


def _demo_placed(out: Path, garment: str, size: str, triangles: int, json_out: bool) -> None:
    """The placement-only demo: mesh, place isometrically, evaluate, write every output."""
    from .. import api

    with console.status("meshing and placing (isometric roll onto cylinders)") as status:
        outcome = api.place_and_evaluate(garment, triangles=triangles, size=size)
        report = outcome.write(out, progress=lambda s: status.update(f"writing {s}"))
    if json_out:
        print_json(report)
    else:
        print_fit_summary(report, out, outcome.seconds)
