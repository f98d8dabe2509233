"""Foundation commands: ``patterns``, ``mesh``, ``fit`` and ``demo``."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Optional

import typer

from .app import CHECKS_FAILED, app, console, fail, finite, print_json, triangles_option

Out = typer.Option(..., "--out", "-o", help="Output folder (created if missing).")
Json = typer.Option(False, "--json", help="Print machine-readable results on stdout.")


def num(value, spec: str, scale: float = 1.0) -> str:
    """``value * scale`` formatted with ``spec``, or ``n/a`` for a value the report could
    not give (None: it was not finite)."""
    return "n/a" if value is None else format(value * scale, spec)


def print_fit_summary(report: dict, out: Path, seconds: float) -> None:
    from rich.table import Table

    table = Table(title=f"fit of '{report.get('garment')}' ({report['state']})", show_lines=False)
    for col in ("panel", "area 2D [m²]", "area 3D [m²]", "ϖ"):
        table.add_column(col, justify="right" if col != "panel" else "left")
    for p in report["panels"]:
        table.add_row(p["name"], num(p["area_2d_m2"], ".4f"), num(p["area_3d_m2"], ".4f"),
                      num(p["fitting_ratio"], ".2f", 100) + "%")
    console.print(table)
    fc = report["fit_classes"]
    console.print(f"fitting ratio ϖ = [bold]{num(report['fitting_ratio'], '.2f', 100)}%[/]  "
                  f"(symmetric {num(report['fitting_ratio_symmetric'], '.2f', 100)}%)  tight "
                  f"{num(fc['tight'], '.1f', 100)}% · fit {num(fc['fit'], '.1f', 100)}% · loose "
                  f"{num(fc['loose'], '.1f', 100)}% of the area")
    console.print(f"mesh: {report['mesh']['vertices']} vertices, {report['mesh']['triangles']} "
                  f"triangles, min angle {num(report['mesh']['min_angle_deg'], '.1f')}°")
    console.print(f"wrote {out}/ in {seconds:.1f} s: "
                  + ", ".join(sorted(v for v in report["files"].values())))


def load_pattern_arg(pattern: str, size: str):
    """A built-in garment name or a pattern file in any format patternfit reads."""
    from ..pattern.formats import load_any_pattern
    from ..pattern.library import GARMENTS, build

    if pattern in GARMENTS:
        return build(pattern, size)
    path = Path(pattern)
    if not path.exists():
        fail(f"'{pattern}' is neither a built-in garment ({', '.join(GARMENTS)}) nor a file")
    return load_any_pattern(path)


def exit_if_checks_failed(report: dict, out: Path) -> None:
    """Exit with status 1, saying why, when the fit ``report`` (written to ``out``) did not
    pass its checks: a drape check failed, or a value was not finite (``checks.non_finite``
    names it; the report holds None there), so that no script takes it for a result."""
    checks = report.get("checks") or {}
    if checks.get("passed") is not False:
        return
    bad = checks.get("non_finite") or []
    more = f" and {len(bad) - 5} more" if len(bad) > 5 else ""
    why = f"not finite: {', '.join(bad[:5])}{more}" if bad else "see 'checks' in report.json"
    fail(f"the fit in {out}/ failed its checks ({why})", CHECKS_FAILED)


@app.command()
def patterns(
    name: Optional[str] = typer.Argument(None, help="A built-in garment to write out."),
    size: str = typer.Option("M", "--size", "-s", help="Size: S, M, L or XL."),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="Write the pattern JSON here."),
    units: str = typer.Option("cm", help="Units written in the file: m, cm, mm or in."),
    json_out: bool = Json,
) -> None:
    """List the built-in garments, or write one in patternfit's JSON format."""
    from ..pattern.io import save_pattern
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
        from rich.table import Table
        table = Table(title=f"built-in garments (size {size})")
        for col in ("name", "panels", "seams", "fabric m²", "description"):
            table.add_column(col)
        for r in rows:
            table.add_row(r["name"], str(r["panels"]), str(r["seams"]), f"{r['area_m2']:.3f}",
                          r["description"])
        console.print(table)
        return
    if name not in GARMENTS:
        fail(f"unknown garment '{name}' (built-in: {', '.join(GARMENTS)})")
    pattern = build(name, size)
    if out is None:
        fail("give --out FILE.json to write the pattern")
    save_pattern(pattern, out, units=units)
    if json_out:
        print_json({"name": name, "size": size.upper(), "file": str(out),
                    "panels": len(pattern.panels), "seams": len(pattern.seams)})
    else:
        console.print(f"wrote {out} ({name}, size {size.upper()}, units {units})")


@app.command()
def mesh(
    pattern: str = typer.Argument(..., help="Pattern file (JSON) or built-in garment name."),
    triangles: int = triangles_option(20000),
    min_angle: float = typer.Option(25.0, help="Minimum triangle angle [degrees].",
                                    callback=finite),
    size: str = typer.Option("M", "--size", "-s", help="Size of a built-in garment."),
    out: Path = Out,
    json_out: bool = Json,
) -> None:
    """Mesh every panel (seams matched) and save the garment folder (pattern.json, mesh.npz)."""
    from ..mesh.quality import min_angle as smallest_angle
    from ..mesh.store import save_garment
    from ..mesh.triangulate import mesh_pattern

    pat = load_pattern_arg(pattern, size)
    t0 = time.perf_counter()
    m = mesh_pattern(pat, triangles=triangles, min_angle=min_angle)
    seconds = time.perf_counter() - t0
    save_garment(out, pat, m)
    info = {"garment": pat.name, "folder": str(out), "vertices": m.n_vertices,
            "triangles": m.n_triangles, "panels": len(m.panel_names), "seams": len(m.seam_names),
            "seam_pairs": int(len(m.seam_pairs)),
            "min_angle_deg": smallest_angle(m.vertices, m.triangles), "seconds": seconds}
    if json_out:
        print_json(info)
    else:
        console.print(f"meshed '{pat.name}': {m.n_vertices} vertices, {m.n_triangles} triangles, "
                      f"min angle {info['min_angle_deg']:.1f}°, {info['seam_pairs']} seam pairs "
                      f"in {seconds * 1000:.0f} ms → {out}/")


@app.command()
def fit(
    garment: Path = typer.Option(..., "--garment", "-g",
                                 help="Saved garment folder with a 3D state (positions.npy)."),
    out: Path = Out,
    tight: float = typer.Option(0.02, help="Area growth above which a triangle is tight.",
                                callback=finite),
    loose: float = typer.Option(0.02, help="Area loss above which a triangle is loose.",
                                callback=finite),
    pictures: bool = typer.Option(True, help="Write the PNG/SVG pictures."),
    json_out: bool = Json,
) -> None:
    """Evaluate the fit of a saved 3D state: ϖ, colour maps, report.json. Exits with status 1
    when the evaluation failed its checks (a value such as ϖ is not finite)."""
    from ..fit.metrics import FitEvaluator
    from ..fit.outputs import write_fit_outputs
    from ..mesh.store import load_garment

    t0 = time.perf_counter()
    pat, m, x = load_garment(garment)
    if x is None:
        fail(f"{garment} holds no 3D state (positions.npy): place or drape the garment first")
    try:
        result = FitEvaluator(m, tight=tight, loose=loose)(x)
    except ValueError as exc:
        fail(f"{garment}: {exc}")
    report = write_fit_outputs(out, pat, m, x, result, state="saved", pictures=pictures)
    if json_out:
        print_json(report)
    else:
        print_fit_summary(report, out, time.perf_counter() - t0)
    exit_if_checks_failed(report, out)


@app.command()
def demo(
    out: Path = typer.Option(Path("patternfit-demo"), "--out", "-o", help="Output folder."),
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
    """The design loop on a built-in garment drafted too small: drape it, evaluate the fit,
    name the regions to modify, correct the pattern automatically, write the report with
    before/after pictures (the paper's Fig. 1 loop; about half a minute on a laptop CPU).

    With --no-drape, only mesh and place the garment isometrically (panels rolled onto
    cylinders around the body): its fitting ratio is 100%, the paper's Fig. 8(b).
    """
    if not drape:
        return _demo_placed(out, garment or "coat", size or "M", triangles or 22000, json_out)
    from ..edit import grade
    from ..loop.table2 import ROWS
    from ..loop.session import DesignSession
    from ..body.builtin import load_body
    from ..fit.metrics import FitEvaluator
    from ..pattern.library import build
    from ..sim.placement import place_on_body
    from .loop import run_correction

    garment = garment or "skirt"
    row = {r.garment: r for r in ROWS}.get(garment)
    body, narrow, fabric, relax = (row.body, row.narrow, row.fabric, row.relax) if row \
        else ("female_average", 0.8, "stretch_knit", 1.0)
    size = size or (row.size if row else "M")
    t0 = time.perf_counter()
    pat = grade(build(garment, size), None, narrow, 1.0)
    console.print(f"[bold]{garment}[/] size {size.upper()} drafted too small (narrowed to "
                  f"{narrow:.0%} of its width) in {fabric}, on the body '{body}'")
    session = DesignSession(pat, load_body(body), fabric, triangles or 3000, 0.90,
                            relax=relax)
    placed = FitEvaluator(session.mesh).metrics(place_on_body(pat, session.mesh,
                                                              session.body))[1]
    report = run_correction(session, threshold=0.90, max_iterations=3, out=out,
                            extra={"fitting_ratio_placed": placed, "narrow": narrow})
    if json_out:
        print_json(report)
        return
    console.print(f"ϖ placed {placed * 100:.2f}% → first drape "
                  f"{report['iterations'][0]['fitting_ratio'] * 100:.2f}% → corrected "
                  f"[bold]{report['fitting_ratio'] * 100:.2f}%[/] in "
                  f"{report['correction_rounds']} round(s), {report['edits_made']} corner "
                  f"moves; {time.perf_counter() - t0:.1f} s. Wrote {out}/: pattern.json "
                  "(corrected), report.json, regions_before/after.png, before/ and after/ "
                  "(colour maps, GLB)")


def _demo_placed(out: Path, garment: str, size: str, triangles: int, json_out: bool) -> None:
    """The placement-only demo: mesh, place isometrically, evaluate, write every output."""
    from ..fit.metrics import FitEvaluator
    from ..fit.outputs import write_fit_outputs
    from ..mesh.triangulate import mesh_pattern
    from ..pattern.library import build
    from ..sim.placement import place_on_cylinders

    t0 = time.perf_counter()
    with console.status("meshing") as status:
        pat = build(garment, size)
        m = mesh_pattern(pat, triangles=triangles)
        status.update("placing (isometric roll onto cylinders)")
        x = place_on_cylinders(pat, m)
        result = FitEvaluator(m)(x)
        report = write_fit_outputs(out, pat, m, x, result, state="placed",
                                   progress=lambda s: status.update(f"writing {s}"))
    if json_out:
        print_json(report)
    else:
        print_fit_summary(report, out, time.perf_counter() - t0)
