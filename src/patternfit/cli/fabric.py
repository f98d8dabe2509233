"""``patternfit fabric-test``: the virtual fabric-testing kit (hanging strip, Peirce's
cantilever, Cusick drape) of ``patternfit.sim.fabric_test`` on a preset or a fabric file."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer
from rich.markup import escape
from rich.table import Table

from ..defaults import DEFAULTS
from .app import (CHECKS_FAILED, app, between, console, fail, folder_option, listing,
                  print_json)

# patternfit.api and the stage modules are imported inside the command, when it runs:
# `patternfit --help` should not wait for the solver's compiled kernels

TESTS = ("strip", "cantilever", "cusick")
#: which options belong to which test (an option given to another test is refused)
_OWN = {"direction": ("strip", "cantilever"), "length": ("strip",), "meshes": ("cantilever",),
        "triangles": ("cusick",), "seeds": ("cusick",), "specimen": ("cusick",),
        "disc": ("cusick",), "mesh-check": ("cusick",)}


def _mm(value, digits: int = 2) -> str:
    return "n/a" if value is None else f"{value * 1e3:.{digits}f} mm"


def _num(value, spec: str) -> str:
    return "n/a" if value is None else format(value, spec)


def _residual(res) -> str:
    if isinstance(res, dict) and res:
        return ", ".join(f"{k.removeprefix('residual_')} {_num(v, '.3g')}"
                         for k, v in res.items())
    return "n/a" if res is None else str(res)


def _meshes(text: str) -> tuple[int, ...]:
    try:
        sizes = tuple(int(p) for p in text.replace(" ", "").split(",") if p)
    except ValueError:
        fail(f"--meshes: expected comma-separated whole numbers (edges per bending length), "
             f"got {text!r}")
    if not sizes or any(not 2 <= s <= 60 for s in sizes):
        fail(f"--meshes: one to several numbers from 2 to 60, got {text!r}")
    if "" in text.replace(" ", "").split(",") or list(sizes) != sorted(set(sizes)):
        # the reading is the finest mesh's and the convergence check the two finest
        fail(f"--meshes: distinct sizes from coarse to fine, e.g. 6,12,24; got {text!r}")
    return sizes


def _show_strip(r) -> None:
    table = Table(title=f"hanging strip, {escape(r.fabric)} ({r.direction}), "
                        f"{r.length_m:.3g} × {r.width_m:.3g} m, {r.triangles} triangles")
    for col in ("quantity", "value"):
        table.add_column(col)
    table.add_row("elongation measured", _mm(r.elongation_measured_m, 4))
    table.add_row("elongation expected ρgL²/(2k)", _mm(r.elongation_expected_m, 4))
    table.add_row("ratio", _num(r.ratio, ".4f"))
    table.add_row("strain at the clamp ρgL/k", f"{r.strain_top * 100:.3f} %")
    listing.print(table)


def _show_cantilever(r) -> None:
    table = Table(title=f"Peirce cantilever (ASTM D1388), {escape(r.fabric)} ({r.direction}), "
                        f"strip {r.width_m * 1e3:.0f} mm wide")
    for col in ("edge", "triangles", "overhang", "tip angle", "bending length",
                "overhang / 2"):
        table.add_column(col, justify="right")
    for m in r.meshes:
        table.add_row(_mm(m.edge_m), str(m.triangles), _mm(m.overhang_m, 1),
                      f"{m.tip_angle_deg:.2f}°", _mm(m.bending_length_m),
                      _mm(m.astm_length_m))
    listing.print(table)
    if r.bending_length_expected_m == r.bending_length_elastic_m:
        expected = f"(B/(ρg))^(1/3) = {_mm(r.bending_length_expected_m)}"
    else:
        expected = (f"{_mm(r.bending_length_expected_m)} with its bending friction "
                    f"((B/(ρg))^(1/3) = {_mm(r.bending_length_elastic_m)} without)")
    peirce = ("" if r.peirce_length_m is None
              else f"Peirce's formula {_mm(r.peirce_length_m)}; ")
    listing.print(f"bending length measured {_mm(r.bending_length_measured_m)}, expected "
                  f"{expected}, ratio "
                  f"{_num(r.ratio, '.4f')}; {peirce}"
                  f"change between the two finest meshes "
                  f"{_num(None if r.mesh_change is None else r.mesh_change * 100, '.2f')} %")


def _show_cusick(r) -> None:
    table = Table(title=f"Cusick drape, {escape(r.fabric)}: {r.specimen_diameter_m * 100:.0f} cm "
                        f"specimen on a {r.disc_diameter_m * 100:.0f} cm disc, "
                        f"{r.triangles} triangles")
    for col in ("seed", "DC", "nodes", "hem drop", "compressed", "iterations", "s"):
        table.add_column(col, justify="right")
    for run in r.runs:
        table.add_row(str(run.seed), f"{run.drape_coefficient:.3f}", str(run.nodes),
                      _mm(run.hem_drop_m, 1), f"{run.compressed_share * 100:.1f} %",
                      str(run.solve.iterations), f"{run.solve.seconds:.1f}")
    listing.print(table)
    listing.print(f"drape coefficient {r.drape_coefficient:.3f} (spread "
                  f"{r.drape_coefficient_spread:.3f}, sd {r.drape_coefficient_std:.3f}); "
                  f"nodes {r.nodes:.1f} ({r.nodes_min}–{r.nodes_max})")
    if r.mesh_change is None:
        listing.print("mesh not checked: the spread is over the starts only (--mesh-check "
                      "drapes the first again on twice the triangles)", highlight=False)
    else:
        listing.print(f"mesh check: start {r.runs[0].seed} on {r.mesh_check_triangles} "
                      f"triangles moved the drape coefficient by {r.mesh_change:+.3f}",
                      highlight=False)
    for note in r.notes:
        listing.print(f"note: {escape(note)}", highlight=False)


def _solves(result) -> list:
    if hasattr(result, "runs") and result.runs and hasattr(result.runs[0], "solve"):
        return [run.solve for run in result.runs]
    if hasattr(result, "meshes"):
        return [run.solve for m in result.meshes for run in m.runs]
    return [result.solve]


@app.command("fabric-test")
def fabric_test(
    test: str = typer.Argument(..., help="strip (stretch under its own weight), cantilever "
                               "(Peirce / ASTM D1388 bending length) or cusick (drape "
                               "coefficient and nodes)."),
    fabric: str = typer.Option(DEFAULTS.fabric, "--fabric", "-f",
                               help="Fabric preset name or a fabric JSON file."),
    direction: Optional[str] = typer.Option(None, help="strip, cantilever: warp (default) or "
                                            "weft, the yarns along the strip."),
    length: Optional[float] = typer.Option(None, callback=between(0.001, 10.0),
                                           help="strip: hanging length \\[m], 0.001 to 10 (default "
                                                "0.5)."),
    meshes: Optional[str] = typer.Option(None, help="cantilever: mesh sizes, edges per "
                                         "bending length, coarse to fine (default 6,12,24)."),
    triangles: Optional[int] = typer.Option(None, "--triangles", "-n", min=50, max=200_000,
                                            help="cusick: triangles of the specimen "
                                                 "(default: 2.5 edges per bending length of "
                                                 "the fabric, 4,000 to 24,000)."),
    seeds: Optional[int] = typer.Option(None, min=1, max=50, help="cusick: perturbed flat "
                                        "starts, seeds 0..N-1 (default 5)."),
    mesh_check: bool = typer.Option(False, "--mesh-check", help="cusick: drape the first "
                                    "start again on twice the triangles; fails when its "
                                    "drape coefficient moves by more than 0.03 (a stiff "
                                    "membrane, e.g. from a KES-F or FAST sheet, locks the "
                                    "folds of a mesh its bending length says is fine)."),
    specimen: Optional[float] = typer.Option(None, callback=between(0.02, 2.0),
                                             help="cusick: specimen diameter \\[m], 0.02 "
                                                  "to 2 (default 0.30)."),
    disc: Optional[float] = typer.Option(None, callback=between(0.005, 2.0),
                                         help="cusick: support disc diameter \\[m], "
                                              "0.005 to 2 (default 0.18)."),
    out: Optional[Path] = folder_option(None, "--out", "-o", help="Write the result "
                                        "(fabric_test_<test>.json) and the pictures here "
                                        "(cusick: top view; cantilever: side view)."),
    json_out: bool = typer.Option(False, "--json", help="Print the result as JSON."),
    set_: Optional[list[str]] = typer.Option(None, "--set", metavar="KEY=VALUE",
                                             help="A solver setting for every solve, over "
                                                  "the kit's (force stop, Newton, "
                                                  "compression=1.0), e.g. --set "
                                                  "compression=0.05; repeatable."),
) -> None:
    """Test a fabric on the virtual bench: hanging strip, cantilever or Cusick drape.

    strip: the hanging strip's stretch against ρgL²/(2k); cantilever: Peirce's bending
    length against (B/(ρg))^(1/3); cusick: the drape coefficient and number of nodes (mean
    and spread over perturbed starts).

    Exits with status 1 when the result failed its checks: a solve that did not end at
    rest, a strip or bending length more than 5 % off or not shown mesh-converged, a drape
    coefficient outside [0, 1] or moved by the mesh check.
    """
    test = test.strip().lower()
    if test not in TESTS:
        fail(f"TEST: one of {', '.join(TESTS)}, got {test!r}")
    given = {"direction": direction, "length": length, "meshes": meshes,
             "triangles": triangles, "seeds": seeds, "specimen": specimen, "disc": disc,
             "mesh-check": mesh_check or None}
    for name, value in given.items():
        if value is not None and test not in _OWN[name]:
            fail(f"--{name} applies to {' and '.join(_OWN[name])}, not to {test}")
    if direction is not None and direction.strip().lower() not in ("warp", "weft"):
        fail(f"--direction: warp or weft, got {direction!r}")
    sizes = _meshes(meshes) if meshes is not None else None
    if not fabric.strip():
        fail("--fabric: empty; a preset name or a fabric JSON file")
    from .. import api
    from ..sim import fabric_test as kit

    try:
        settings = kit.settings_from_pairs(set_ or [])
    except ValueError as err:
        fail(f"--set: {err}")
    fab, assumed = api.read_fabric_with_notes(fabric)
    for note in assumed:
        console.print(f"{escape(fab.name)}: {escape(note)}", highlight=False)
    with console.status(f"[bold]{test}[/] test of {escape(fab.name)}") as status:
        def progress(text: str) -> None:
            status.update(f"[bold]{escape(text)}")

        if test == "strip":
            result = kit.strip_test(fab, direction=direction or "warp",
                                    length=0.5 if length is None else length,
                                    settings=settings, progress=progress)
        elif test == "cantilever":
            result = kit.cantilever_test(fab, direction=direction or "warp",
                                         meshes=sizes or (6, 12, 24), keep_shape=out is not None,
                                         settings=settings, progress=progress)
        else:
            result = kit.cusick_test(
                fab, specimen=kit.CUSICK_SPECIMEN if specimen is None else specimen,
                disc=kit.CUSICK_DISC if disc is None else disc,
                triangles=triangles,
                seeds=tuple(range(5 if seeds is None else seeds)), settings=settings,
                mesh_check=mesh_check, progress=progress)
    report = {**result.to_dict(), "fabric_constants": fab.to_dict(), "fabric_assumed": assumed}
    files = []
    if out is not None:
        from ..files import atomic_write_text, dumps_finite_json

        picture = {"cusick": ("cusick_top.png", kit.write_cusick_picture),
                   "cantilever": ("cantilever_side.png", kit.write_cantilever_picture)}
        name, draw = picture.get(test, (None, None))
        report["files"] = ([name] if name else []) + [f"fabric_test_{test}.json"]
        # the result first: minutes of solves are not lost to a picture that fails
        files.append(atomic_write_text(out / f"fabric_test_{test}.json",
                                       dumps_finite_json(report, indent=1) + "\n"))
        if draw is not None:
            files.insert(0, draw(result, out / name))
    if json_out:
        print_json(report)
    else:
        {"strip": _show_strip, "cantilever": _show_cantilever, "cusick": _show_cusick}[test](
            result)
        solves = _solves(result)
        last = solves[-1]
        at_rest = sum(s.at_rest for s in solves)
        listing.print(f"{at_rest}/{len(solves)} solves at rest; last: {last.stop_reason}, "
                      f"{last.iterations} iterations, residual {_residual(last.residual)}; "
                      f"{result.seconds:.1f} s")
        if files:
            console.print(f"wrote {', '.join(str(p) for p in files)}")
    if not result.passed:
        fail(f"the {test} test of {fab.name} failed its checks: "
             f"{'; '.join(result.failures)}", CHECKS_FAILED)


@app.command("fabrics")
def fabrics(
    sources: Optional[list[str]] = typer.Argument(
        None, metavar="[FABRIC]...",
        help="Show these instead of the catalogue: presets, or fabric files (SI, or a KES-F / "
             "FAST measurement sheet in its own units, or an ARCSim material file, converted "
             "to SI)."),
    json_out: bool = typer.Option(False, "--json", help="Print the catalogue as JSON (each "
                                  "fabric's 'constants': an SI fabric file)."),
) -> None:
    """List the fabric presets and the published test fabrics with their bending length and
    drape coefficient, or show given fabrics' constants in SI.

    For each: Peirce's bending length from its constants and as the virtual cantilever read
    it, the Cusick drape coefficient and nodes the virtual drape test gave (stored from the
    runs in docs/fabrics.md), the measured drape coefficient of the published ones, and
    where the numbers come from. Given fabrics (names or files), shows those, with their
    constants in SI (a sheet's conversion)."""
    from .. import api

    if sources:
        rows = [api.describe_fabric(s) for s in sources]
        if json_out:
            print_json({"fabrics": rows})
            return
        _print_constants(rows)
        return
    rows = api.fabric_catalogue()
    if json_out:
        print_json({"fabrics": rows})
        return
    table = Table(title="fabrics: c = bending length (B/(ρg))^(1/3) warp / weft, and as the "
                        "virtual cantilever read it (warp); DC = Cusick drape coefficient, "
                        "30 cm on 18 cm, simulated (min–max over starts 0–2; fabric-test "
                        "cusick runs 5 by default) and measured")
    for col in ("name", "g/m²", "c \\[mm]", "c kit", "DC sim", "nodes", "DC meas"):
        table.add_column(col, overflow="fold")
    for r in rows:
        kit = r["kit"] or {}
        c = r["bending_length_m"]
        dc = kit.get("drape_coefficient")
        table.add_row(
            escape(r["name"]), f"{r['constants']['density'] * 1e3:.0f}",
            f"{c['warp'] * 1e3:.1f} / {c['weft'] * 1e3:.1f}",
            _num(None if kit.get("bending_length") is None else kit["bending_length"] * 1e3,
                 ".1f"),
            "n/a" if dc is None else f"{dc:.3f} ({kit['drape_coefficient_min']:.3f}–"
                                     f"{kit['drape_coefficient_max']:.3f})",
            _num(kit.get("nodes"), ".1f"), _num(r.get("drape_coefficient_measured"), ".3f"))
    listing.print(table)
    for r in rows:
        what = r["source"] if r["kind"] == "preset" else f"{r['description']}; {r['source']}"
        listing.print(f"[bold]{escape(r['name'])}[/]: {escape(what)}", highlight=False)
    listing.print("sources in full: docs/fabrics.md, or --json")


def _print_constants(rows: list[dict]) -> None:
    table = Table(title="fabrics in SI: warp / weft; c = bending length (B/(ρg))^(1/3)")
    for col in ("name", "g/m²", "stretch N/m", "shear N/m", "B µN·m", "c mm", "2HB mN",
                "thick mm", "friction"):
        table.add_column(col, overflow="fold")
    for r in rows:
        k, c = r["constants"], r["bending_length_m"]
        table.add_row(
            escape(r["name"]), f"{k['density'] * 1e3:.1f}",
            f"{k['stretch_warp']:.0f} / {k['stretch_weft']:.0f}", f"{k['shear']:.3g}",
            f"{k['bending_warp'] * 1e6:.3g} / {k['bending_weft'] * 1e6:.3g}",
            f"{c['warp'] * 1e3:.1f} / {c['weft'] * 1e3:.1f}",
            f"{k['bending_hysteresis'] * 1e3:.3g}", f"{k['thickness'] * 1e3:.3g}",
            f"{k['friction']:.2g}")
    listing.print(table)
    for r in rows:
        if r["kind"] == "file":
            listing.print(f"[bold]{escape(r['name'])}[/]: {escape(r['source'])}",
                          highlight=False)
            for note in r["assumed"]:
                listing.print(f"  {escape(note)}", highlight=False)
