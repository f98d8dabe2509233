"""``patternfit convert IN OUT``: pattern interchange between patternfit JSON, GarmentCode
JSON, DXF-AAMA, and SVG / PDF plots, chosen from the file endings."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from ..pattern.errors import PatternError
from .app import SIZE_HELP, app, console, fail, print_json
from .show import print_pattern_warnings

# patternfit.api and the stage modules are imported inside the commands, when they run:
# `patternfit --help` should not wait for them (see commands.py)


@app.command()
def convert(
    source: Path = typer.Argument(..., help="Pattern to read: .json (patternfit or GarmentCode, "
                                  "told apart by content) or .dxf (DXF-AAMA; a side file "
                                  "<name>.seams.json beside it supplies seams)."),
    target: Path = typer.Argument(..., help="File to write: .json, .dxf, .svg or .pdf "
                                  "(a name ending in _specification.json writes GarmentCode)."),
    to: Optional[str] = typer.Option(None, "--to", help="Writer, overriding the ending: "
                                     "patternfit, garmentcode, dxf, svg or pdf."),
    units: str = typer.Option("m", "--units", help="Length unit of a patternfit JSON output "
                              "(m, cm, mm, in)."),
    from_units: Optional[str] = typer.Option(None, "--from-units", help="Length unit of a "
                                             "DXF source (mm, cm, in, m), over what the file "
                                             "says or the reader guesses."),
    paper: str = typer.Option("a4", "--paper", help="PDF tile paper: a4 or letter."),
    size: Optional[str] = typer.Option(None, "--size", "-s", help=SIZE_HELP),
    json_out: bool = typer.Option(False, "--json", help="Print machine-readable results."),
) -> None:
    """Convert a sewing pattern between formats (lengths keep their true size)."""
    from .. import api

    pattern = api.read_pattern(source, size=size, units=from_units)
    try:
        written = api.write_pattern(pattern, target, source=source, fmt=to, units=units,
                                    paper=paper)
    except PatternError as exc:  # the writer's checks, stricter than what a reader keeps
        fail(f"{source} was read but cannot be written to {target}: {exc}")
    # an unsewn import (a DXF without its side file): the seams the user can accept
    suggested = [{"a": {"panel": g.seam.a.panel, "edge": g.seam.a.edge},
                  "b": {"panel": g.seam.b.panel, "edge": g.seam.b.edge},
                  "reverse": g.seam.reverse, "ease": g.seam.ease, "score": g.score}
                 for g in (api.suggest_seams(pattern) if not pattern.seams else [])]
    warnings = pattern.meta.get("warnings", [])
    result = {"source": str(source), "source_format": pattern.meta.get("source_format"),
              "pattern": pattern.name, "panels": [p.name for p in pattern.panels],
              "seams": len(pattern.seams), "suggested_seams": suggested,
              "warnings": warnings, "written": [str(p) for p in written],
              "size": pattern.meta.get("size"), "sizes": pattern.meta.get("sizes", [])}
    if json_out:
        print_json(result)
        return
    graded = (f", size {result['size']} of {', '.join(map(str, result['sizes']))} (--size "
              "for another)" if len(result["sizes"]) > 1 else "")
    console.print(f"read {source} ({result['source_format']}): {len(pattern.panels)} pieces, "
                  f"{len(pattern.seams)} seams{graded}", highlight=False)
    print_pattern_warnings(warnings)
    if suggested:
        console.print(f"{len(suggested)} seams suggested (not applied; review and sew them "
                      f"with: patternfit seams {source} --suggest --accept):",
                      highlight=False)
        for s in suggested:
            console.print(f"  {s['a']['panel']}/{s['a']['edge']} -- "
                          f"{s['b']['panel']}/{s['b']['edge']}  score {s['score']:.2f}",
                          highlight=False)
    console.print("wrote " + ", ".join(str(p) for p in written))
