"""What the commands print: fit summaries, drape progress, loop iterations, failed checks.
Every command module imports these from here (and ``app``), never from another command."""

from __future__ import annotations

from pathlib import Path

from rich.markup import escape
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from .app import CHECKS_FAILED, console, fail, listing, say_warning


def num(value, spec: str, scale: float = 1.0, unit: str = "") -> str:
    """``value * scale`` formatted with ``spec`` and followed by `` unit``, or ``n/a`` (no
    unit) for a value the report could not give (None: it was not finite)."""
    if value is None:
        return "n/a"
    return format(value * scale, spec) + (unit if unit in ("", "%") else f" {unit}")


def print_pattern_warnings(warnings) -> None:
    """What the reader noticed in a pattern file (``meta["warnings"]``: a piece of an
    implausible size, a grain line on its side...), one yellow line each; every command
    that reads a pattern says it, not only some."""
    for w in warnings or ():
        say_warning(str(w))


def say_fabric_notes(assumed, source) -> None:
    """What was assumed for values a fabric file does not carry (an ARCSim material's
    friction and thickness: ``api.read_fabric_with_notes``), one line each, as the studio
    and ``fabric-test`` say it: ``drape``, ``correct`` and ``batch`` said nothing."""
    for note in assumed or ():
        console.print(f"[yellow]note:[/] fabric {escape(str(source))}: {escape(str(note))}",
                      highlight=False)


def print_fit_summary(report: dict, out: Path, seconds: float) -> None:
    """The per-panel table, ϖ, fit classes and mesh of a fit ``report`` written to ``out``."""
    failed = (report.get("checks") or {}).get("passed") is False
    table = Table(title=f"fit of '{report.get('garment')}' ({report['state']})"
                  + (" — FAILED, not a fit" if failed else ""), show_lines=False)
    for col in ("panel", "area 2D \\[m²]", "area 3D \\[m²]", "ϖ"):
        table.add_column(col, justify="right" if col != "panel" else "left")
    for p in report["panels"]:
        table.add_row(p["name"], num(p["area_2d_m2"], ".4f"), num(p["area_3d_m2"], ".4f"),
                      num(p["fitting_ratio"], ".2f", 100) + "%")
    console.print(table)
    fc = report["fit_classes"]
    if failed:  # a failed drape's ϖ is no fit: never printed as one
        console.print(f"[bold red]FAILED[/]: the drape failed its checks (below), so ϖ = "
                      f"{num(report['fitting_ratio'], '.2f', 100)}% is not a fit")
    # a failed drape's area shares are no fit either: "fit 100% of the area" read as one
    shares = "" if failed else (f"  tight {num(fc['tight'], '.1f', 100)}% · fit "
                                f"{num(fc['fit'], '.1f', 100)}% · loose "
                                f"{num(fc['loose'], '.1f', 100)}% of the area")
    console.print(f"{'(not a fit) ' if failed else ''}"
                  f"fitting ratio ϖ = [bold]{num(report['fitting_ratio'], '.2f', 100)}%[/]  "
                  f"(symmetric {num(report['fitting_ratio_symmetric'], '.2f', 100)}%)"
                  + shares)
    print_verdict(report)
    console.print(f"mesh: {report['mesh']['vertices']} vertices, {report['mesh']['triangles']} "
                  f"triangles, min angle {num(report['mesh']['min_angle_deg'], '.1f')}°")
    console.print(f"wrote {out}/ in {seconds:.1f} s: "
                  + ", ".join(sorted(v for v in report["files"].values())))


_VERDICT_STYLE = {"too tight": "bold red", "tight": "red", "fits": "green", "loose": "blue",
                  "too loose": "bold blue", "failed": "bold red"}


def verdict_text(word: str | None) -> str:
    """The verdict word coloured for the console ("n/a" when there is none)."""
    if not word:
        return "n/a"
    return f"[{_VERDICT_STYLE.get(word, 'bold')}]{escape(word)}[/]"


def print_verdict(report: dict) -> None:
    """The fit verdict beside ϖ and the paper's threshold, then a line per region (ease,
    pressure p95, stretch p90, why); nothing for a report without one (no body)."""
    if "verdict" not in report:
        return
    p = report.get("pressure_kpa") or {}
    measured = "" if report["verdict"] == "failed" else (
        f"; ϖ {num(report.get('fitting_ratio'), '.2f', 100, '%')}; pressure p99 "
        f"{num(p.get('p99'), '.2f', unit='kPa')}")
    console.print(f"verdict: [bold]{verdict_text(report['verdict'])}[/] "
                  f"({escape(report.get('verdict_reason') or '')}){measured}", highlight=False)
    for name, r in (report.get("region_verdicts") or {}).items():
        console.print(f"   {name:15} {verdict_text(r['verdict']):>20}  ease "
                      f"{num(r['ease_cm'], '+.1f', unit='cm')}  pressure "
                      f"{num(r['pressure_kpa_p95'], '.2f', unit='kPa')}  stretch "
                      f"{num(r['stretch_p90'], '.1f', 100, '%')}  {escape(r['reason'])}",
                      highlight=False)


def print_drape_checks(report: dict) -> None:
    """The drape's checks, iterations and time, and ϖ after placement; then whether the
    garment is on the body (anchor height, lowest point, farthest vertex); then, for a
    failed drape, why."""
    c = report["checks"]
    verdict = "[green]passed[/]" if c["passed"] else "[bold red]FAILED[/]"
    console.print(f"checks {verdict}: {c['inside_vertices']} vertices inside the body "
                  f"(deepest {num(c['max_depth_mm'], '.2f')} mm), "
                  f"{c.get('edges_in_body', 0)} edges and {c.get('faces_in_body', 0)} "
                  f"triangles through it, seam gap "
                  f"{num(c['seam_gap_max_mm'], '.2f')} mm, {c['self_intersections']} "
                  f"self-intersections, equilibrium {c['equilibrium']} "
                  f"({c['stop_reason']}); {report['timing']['iterations']} iterations in "
                  f"{num(report['timing']['seconds'], '.1f')} s; ϖ after placement "
                  f"{num(report.get('fitting_ratio_placed'), '.2f', 100)}%")
    if "on_body" in c:
        where = "[green]yes[/]" if c["on_body"] else "[bold red]no[/]"
        console.print(f"on the body {where}: top {num(c['anchor_offset_mm'], '+.1f', 0.1)} cm "
                      f"from the {c['anchor']} (its line at "
                      f"{num(c['anchor_height_mm'], '.3f', 1e-3)} m), lowest point "
                      f"{num(c['lowest_mm'], '.3f', 1e-3)} m, farthest from the body "
                      f"{num(c['farthest_mm'], '.3f', 1e-3)} m")
    reasons = c.get("reasons") or []
    if not c["passed"] and reasons:
        console.print("[bold red]failed:[/] " + escape("; ".join(reasons)), highlight=False)


def exit_if_checks_failed(report: dict, out: Path) -> None:
    """Exit with status 1, saying why, when the fit ``report`` (written to ``out``) did not
    pass its checks: a drape check failed, or a value was not finite (``checks.non_finite``
    names it; the report holds None there), so that no script takes it for a result."""
    checks = report.get("checks") or {}
    if checks.get("passed") is not False:
        return
    reasons = [str(r) for r in checks.get("reasons") or [] if r]
    bad = checks.get("non_finite") or []
    more = f" and {len(bad) - 5} more" if len(bad) > 5 else ""
    if reasons:
        why = "; ".join(reasons)
    else:
        why = f"not finite: {', '.join(bad[:5])}{more}" if bad else "see 'checks' in report.json"
    fail(f"the fit in {out}/ failed its checks ({why}); ϖ is not a fit", CHECKS_FAILED)


def exit_if_correction_failed(report: dict, out: Path) -> None:
    """Exit with status 1, saying why, when the correction loop stopped on a drape that is
    no fit (off the body or ϖ not finite: ``report["failed"]``): the first, with no
    correction made, or a later one, whose round was undone; when its last drape failed
    its checks (the edits were made from drapes that failed theirs); or when the corrected
    pattern draped afresh failed its checks (``report["fresh_drape"]``)."""
    last = (report.get("iterations") or [{}])[-1].get("checks") or {}
    fresh = report.get("fresh_drape") or {}
    if not report.get("failed") and last.get("passed") is not False \
            and fresh.get("passed") is False:
        # the loop's drapes went on from its first; the pattern made and put on did not
        # drape (a coat: 8 edges through the body, 24 crossed pairs), read "fit reached"
        why = "; ".join(str(r) for r in fresh.get("reasons") or []) or "see report.json"
        fail(f"the corrected pattern draped afresh failed its checks ({why}): fit not "
             f"reached; {out}/pattern.json holds {report.get('edits_made', 0)} edits",
             CHECKS_FAILED)
    if not report.get("failed") and last.get("passed") is False:
        why = "; ".join(str(r) for r in last.get("reasons") or []) or "see report.json"
        fail(f"the last drape failed its checks ({why}): fit not reached; "
             f"{out}/pattern.json holds {report.get('edits_made', 0)} edits, ϖ "
             f"{report['iterations'][0]['fitting_ratio'] * 100:.2f}% → "
             f"{report['fitting_ratio'] * 100:.2f}%", CHECKS_FAILED)
    if not report.get("failed"):
        return
    if report.get("edits_made"):
        fail(f"correction stopped ({out}/report.json): {report['failed']}; "
             f"{out}/pattern.json holds the {report['edits_made']} edits made before, fit not "
             "reached", CHECKS_FAILED)
    fail(f"no correction made ({out}/report.json): {report['failed']}", CHECKS_FAILED)


def say_body_notes(body, source) -> None:
    """Print what was guessed or done in reading a body mesh file
    (:func:`patternfit.body.mesh_io.body_notes`): its unit guessed from the height (a wrong
    guess, a child's body in inches read as centimetres, changes every result), its turn
    to face +Z."""
    from ..body.mesh_io import body_notes

    for level, sentence in body_notes(body):
        console.print(f"[yellow]{level}:[/] {escape(str(source))}: {escape(sentence)}",
                      highlight=False)


def drape_progress(*, total: int, rest: float | None = None):
    """A rich progress bar and the solver callback that feeds it (iteration, energy, step and,
    from the static engine, the force residual against ``rest``, the rms at which the drape
    counts as at rest; default ``SolverSettings().residual_rms``)."""
    if rest is None:
        from ..sim.settings import SolverSettings
        rest = SolverSettings().residual_rms
    bar = Progress(TextColumn("[bold]draping"), BarColumn(), TextColumn("{task.fields[info]}"),
                   TimeElapsedColumn(), console=console, transient=True)
    task = bar.add_task("drape", total=total, info="")

    def callback(it, energy, step, elapsed, residual=None):
        # how far from a force balance says more than the energy about how long is left
        balance = ""
        if residual is not None:  # no exponents for a designer
            size = f"{residual:.0f}" if residual >= 100 else f"{residual:.3g}"
            balance = f"  force residual {size} × weight (rest ≤ {rest:g})"
        bar.update(task, completed=min(it, total),
                   info=f"it {it}{balance}  E {energy:.4g} J  step {step * 1000:.3f} mm")
    return bar, callback


def show_iteration(it) -> None:
    """One line per loop iteration, its regions and edits (for the console)."""
    what = "first drape" if it.index == 0 else f"after round {it.index}"
    reasons = "; ".join(str(r) for r in (it.checks or {}).get("reasons") or [])
    ok = "" if not it.checks or it.checks.get("passed") else \
        f"  [yellow](drape checks failed{': ' + escape(reasons) if reasons else ''})[/]"
    verdict = "" if it.verdict is None else \
        f"  verdict {verdict_text(it.verdict.overall)} ({escape(it.verdict.reason)})"
    console.print(f"[bold]{what}[/]: ϖ = {it.fitting_ratio * 100:.2f}%{verdict}  "
                  f"({it.seconds:.1f} s){ok}", highlight=False)
    ends = (it.measures or {}).get("lengths_cm") or {}
    if ends:
        risen = "".join(f"; {k} rose {v * 100:.1f} cm (beyond the length tolerance)"
                        for k, v in it.risen.items())
        console.print("   cm short of the wrist/ankle (− beyond): " + ", ".join(
            f"{k} {v:+.1f}" for k, v in ends.items()) + risen, highlight=False)
    for why in it.stepped_back:
        console.print(f"   [yellow]stepped back (the edit halved): the re-drape was worse: "
                      f"{escape(why)}[/]", highlight=False)
    for r in it.regions[:6]:
        console.print(f"   {'▲' if r.kind == 'tight' else '▽'} {r.describe()}", highlight=False)
    if len(it.regions) > 6:
        console.print(f"   … and {len(it.regions) - 6} smaller region(s)")
    if it.edits:
        moves = ", ".join(f"{e.panel}/{e.edge} {e.to_dict()['cm']:.1f}" for e in it.edits)
        console.print(f"   edits (corner moves, cm): {moves}", highlight=False)


def run_correction(session, out: Path, *, threshold: float, max_iterations: int,
                   extra: dict | None = None, pictures: bool = True, take_in: bool = False,
                   verdict_rules=None, goal: str = "tight") -> dict:
    """:func:`patternfit.api.correct_design` with a progress bar and a line per iteration;
    returns the report."""
    from .. import api  # the API pulls in the solver: loaded when a command runs, not at --help

    bar, callback = drape_progress(total=5000)
    with bar:
        return api.correct_design(
            session, out, threshold=threshold, max_iterations=max_iterations,
            pictures=pictures, extra=extra, drape_progress=callback, take_in=take_in,
            verdict_rules=verdict_rules, goal=goal,
            progress=lambda it: bar.console.print() or show_iteration(it),
            write_progress=lambda s: bar.update(bar.task_ids[0], info=f"writing {s}"))


def say_fresh_drape(report: dict) -> None:
    """Print what the corrected pattern reads draped afresh (``report["fresh_drape"]``),
    and say so when its verdict is not the loop's: the loop's drapes go on from its first,
    and a garment made from the pattern may sit elsewhere."""
    fresh = report.get("fresh_drape")
    if not fresh:
        return
    ratio = fresh.get("fitting_ratio")
    said = (f"the corrected pattern draped afresh (placed, sewn and draped from the start): "
            f"ϖ {ratio * 100:.2f}%, verdict {fresh.get('verdict') or 'n/a'}"
            if ratio is not None else "the corrected pattern draped afresh: ϖ not finite")
    if fresh.get("passed") is False:
        said += f" (failed: {'; '.join(fresh.get('reasons') or [])})"
    console.print(escape(said), highlight=False)
    if fresh.get("verdict") != report.get("verdict"):
        console.print(f"[yellow]note:[/] that is not the loop's verdict "
                      f"({escape(str(report.get('verdict')))}): its drapes went on from the "
                      "first one, where the garment may sit otherwise than a garment made from "
                      "the pattern and put on", highlight=False)


def _side_text(side: dict) -> str:
    span = "" if (side["start"], side["end"]) == (0.0, 1.0) else \
        f" [{side['start']:g}–{side['end']:g}]"
    return f"{side['panel']}.{side['edge']}{span}"


def print_seams(name: str, rows: list[dict], pieces: int) -> None:
    """The seams of pattern ``name`` as ``api.seam_table`` gives them: sides, their lengths
    [cm], the difference [mm], the measured ratio and the stated ease."""
    if not rows:
        listing.print(f"'{escape(name)}' ({pieces} pieces) has no seams"
                      + (": see --suggest" if pieces > 1 else ""))
        return
    table = Table(title=f"seams of '{escape(name)}' ({pieces} pieces)")
    for col in ("seam", "side a", "cm", "side b", "cm", "Δ mm", "ratio", "ease"):
        table.add_column(col, justify="left" if col.startswith(("seam", "side")) else "right")
    for r in rows:
        table.add_row(escape(r["name"]), escape(_side_text(r["a"])),
                      f"{r['a']['length_cm']:.2f}", escape(_side_text(r["b"])),
                      f"{r['b']['length_cm']:.2f}", f"{r['difference_mm']:+.1f}",
                      f"{r['ratio']:.3f}", f"{r['ease']:g}")
    listing.print(table)


def print_seam_suggestions(items: list, *, accepted: bool) -> None:
    """Suggested seams: (seam row, score, reasons) each, best first; ``accepted`` says they
    were sewn."""
    if not items:
        listing.print("no seams to suggest")
        return
    table = Table(title="suggested seams" + (" (accepted)" if accepted else ""))
    for col in ("score", "side a", "cm", "side b", "cm", "ease", "why"):
        table.add_column(col, justify="left" if col in ("side a", "side b", "why") else "right")
    for row, score, reasons in items:
        table.add_row(f"{score:.2f}", escape(_side_text(row["a"])),
                      f"{row['a']['length_cm']:.2f}", escape(_side_text(row["b"])),
                      f"{row['b']['length_cm']:.2f}", f"{row['ease']:g}",
                      escape("; ".join(reasons)))
    listing.print(table)
    if not accepted:
        listing.print("sew them with --accept (and --out FILE), or one by one with --set")
