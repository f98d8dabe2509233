"""``patternfit seams PATTERN``: list a pattern's seams, suggest seams for an unsewn one,
accept the suggestions or sew, unpick and ease seams one by one, and write the result."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import List, Optional

import typer

from ..errors import InputError
from .app import app, console, fail, print_json
from .show import print_pattern_warnings, print_seam_suggestions, print_seams

# patternfit.api and the stage modules are imported inside the commands, when they run:
# `patternfit --help` should not wait for them (see commands.py)


def _side(text: str, spec: str) -> dict:
    """PANEL.EDGE[@START-END] (arc-length fractions) → a seam side dict."""
    text, at, span = text.partition("@")
    panel, dot, edge = text.partition(".")
    if not (panel and dot and edge):
        fail(f"--set {spec}: a side is PANEL.EDGE[@START-END], got {text!r}")
    side = {"panel": panel, "edge": edge}
    if at:
        start, dash, end = span.partition("-")
        try:
            side.update(start=float(start), end=float(end))
        except ValueError:
            fail(f"--set {spec}: a span is @START-END, fractions of the edge such as "
                 f"@0-0.5, got {span!r}")
    return side


def _parse_set(spec: str) -> tuple[str, dict, dict, float | None]:
    """NAME=A_PANEL.EDGE:B_PANEL.EDGE[:ease] → (name, side a, side b, ease or None)."""
    name, eq, rest = spec.partition("=")
    parts = rest.split(":")
    if not (name and eq and len(parts) in (2, 3)):
        fail(f"--set {spec}: expected NAME=A_PANEL.EDGE:B_PANEL.EDGE[:ease]")
    ease = None
    if len(parts) == 3:
        try:
            ease = float(parts[2])
        except ValueError:
            fail(f"--set {spec}: the ease must be a number (longer / shorter - 1), got "
                 f"{parts[2]!r}")
    return name, _side(parts[0], spec), _side(parts[1], spec), ease


@app.command()
def seams(
    pattern: str = typer.Argument(..., help="Pattern file (JSON, GarmentCode JSON, DXF) or a "
                                  "built-in garment name."),
    suggest: bool = typer.Option(False, "--suggest", help="Suggest seams for the unsewn "
                                 "edges, with their score and reasons."),
    set_: Optional[List[str]] = typer.Option(None, "--set", help="Sew a seam: NAME=A_PANEL."
                                             "EDGE:B_PANEL.EDGE[:ease] (ease = longer / "
                                             "shorter - 1, measured when left out; a side "
                                             "may be part of its edge: PANEL.EDGE@0-0.5); "
                                             "replaces a seam of that name. Repeatable."),
    remove: Optional[List[str]] = typer.Option(None, "--remove", help="Unpick the seam NAME. "
                                               "Repeatable."),
    accept: bool = typer.Option(False, "--accept", help="Sew every suggested seam."),
    json_out: bool = typer.Option(False, "--json", help="Print machine-readable results."),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="Where to write the edited "
                                       "pattern (.json, .dxf...; default <name>-sewn.json "
                                       "beside the input, never replaced; never the input "
                                       "itself)."),
) -> None:
    """List a pattern's seams (sides, lengths, difference, ease); suggest, accept or edit
    them and write the pattern."""
    from .. import api

    p = api.read_pattern(pattern)
    changed = False
    try:
        for name in remove or ():
            p, changed = api.remove_seam(p, name), True
        for spec in set_ or ():
            name, a, b, ease = _parse_set(spec)
            if any(s.name == name for s in p.seams):
                p = api.remove_seam(p, name)
            p, changed = api.add_seam(p, a, b, name=name, ease=ease), True
    except InputError as err:  # a seam or edge the file does not have: say which file
        if err.file is None and Path(pattern).suffix:
            raise err.located(pattern) from None
        raise
    suggestions = api.suggest_seams(p) if (suggest or accept) else []
    if accept and suggestions:
        p, changed = api.accept_seams(p, suggestions), True
    written: list[Path] = []
    if changed or out is not None:
        source = Path(pattern) if Path(pattern).suffix else None
        target = out if out is not None else Path(
            f"{source.with_suffix('') if source else pattern}-sewn.json")
        if out is None and target.exists():
            # a file the user named is theirs to overwrite; one named for them is not
            fail(f"{target} already exists (an earlier run's?): name the file to write with "
                 "--out, that one to replace it")
        written = api.write_pattern(p, target, source=source)
    rows = api.seam_table(p)
    if json_out:
        print_json({"pattern": p.name, "panels": [q.name for q in p.panels], "seams": rows,
                    "suggestions": [{**api.seam_table(_one(p, s.seam))[-1],
                                     "score": s.score, "reasons": list(s.reasons)}
                                    for s in suggestions],
                    "accepted": bool(accept and suggestions),
                    "written": [str(w) for w in written],
                    "warnings": list(p.meta.get("warnings", []))})
        return
    print_pattern_warnings(p.meta.get("warnings"))
    print_seams(p.name, rows, len(p.panels))
    if suggest or accept:
        print_seam_suggestions([(api.seam_table(_one(p, s.seam))[-1], s.score, s.reasons)
                                for s in suggestions], accepted=accept)
    if written:
        console.print("wrote " + ", ".join(str(w) for w in written), highlight=False)


def _one(pattern, seam):
    """``pattern`` with only ``seam`` (to measure a suggestion the way a seam is listed)."""
    return replace(pattern, seams=(seam,))
