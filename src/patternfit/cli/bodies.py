"""``patternfit bodies`` (built-in bodies) and ``patternfit body`` (a custom anny body)."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer
from rich.table import Table

from .app import app, console, fail, finite, listing, print_json

# the body stage and anny (an optional extra) are imported inside the commands, when they run:
# `patternfit --help` should not wait for them (see commands.py)

_MAIN = ("height", "bust", "waist", "hip", "arm_length", "inseam")


def _summary(body) -> dict:
    return {"name": body.name, "vertices": len(body.vertices), "faces": len(body.faces),
            "measurements_m": {k: round(v, 4) for k, v in sorted(body.measurements.items())}}


def _write(body, out: Path) -> None:
    from ..body import save_body_mesh

    path = save_body_mesh(body, out)
    console.print(f"wrote {path} ({len(body.vertices)} vertices, metres, Y up)")


@app.command()
def bodies(
    name: Optional[str] = typer.Argument(None, help="A built-in body (or alias such as "
                                         "'fat man') to show or write; all when omitted."),
    out: Optional[Path] = typer.Option(None, "--out", help="Write the body to this mesh file "
                                       "(.ply, .obj, .stl, .glb)."),
    set_: Optional[str] = typer.Option(None, "--set", help="List a body set instead of the "
                                       "built-in bodies ('population': women's and men's "
                                       "XS-XXL; 'all': every set)."),
    json_: bool = typer.Option(False, "--json", help="Print the result as JSON."),
) -> None:
    """List the built-in bodies (or a body set) with their measurements \\[m], or write one
    as a mesh."""
    from ..body import ALIASES, load_body
    from ..api import list_body_sets

    if name is None:
        if out is not None:
            fail("--out needs a body NAME")
        sets = list_body_sets()
        if set_ not in (None, "all") and set_ not in sets:
            fail(f"--set: no body set {set_!r}; known: {', '.join(sets)}, all")
        chosen = {k: v for k, v in sets.items() if set_ == "all" or k == (set_ or "builtin")}
        loaded = {k: [load_body(n) for n in v] for k, v in chosen.items()}
        if json_:
            print_json({"bodies": [_summary(b) | {"set": k} for k, v in loaded.items()
                                   for b in v], "aliases": ALIASES, "sets": sets})
            return

        table = Table("set", "name", *(f"{k} \\[m]" for k in _MAIN))
        for k, v in loaded.items():
            for b in v:
                table.add_row(k, b.name, *(f"{b.measurements[m]:.3f}" for m in _MAIN))
        listing.print(table)
        listing.print("aliases: " + ", ".join(f"'{a}' = {n}" for a, n in ALIASES.items()))
        listing.print("body sets (--set NAME, or `patternfit batch --bodies NAME`): "
                      + ", ".join(f"{k} ({len(v)})" for k, v in sets.items()))
        return
    body = load_body(name)
    if out is not None:
        _write(body, out)
    if json_:
        print_json(_summary(body) | {"landmarks_m": {k: v.round(4).tolist()
                                                      for k, v in body.landmarks.items()}})
    elif out is None:
        for k, v in sorted(body.measurements.items()):
            listing.print(f"{k:18s} {v:.3f} m")


@app.command()
def body(
    out: Path = typer.Option(..., "--out", help="Mesh file to write (.ply, .obj, .stl, .glb)."),
    gender: float = typer.Option(0.5, help="0 = male, 1 = female.", callback=finite),
    weight: float = typer.Option(0.5, help="0 = thin, 1 = heavy.", callback=finite),
    muscle: float = typer.Option(0.5, help="0 = little, 1 = much muscle.", callback=finite),
    height: Optional[float] = typer.Option(None, help="Standing height \\[m]; anny's average "
                                           "when omitted.", callback=finite),
    from_measurements: bool = typer.Option(False, "--from-measurements", help="Aim at "
                                           "--height, --bust, --waist and --hip instead of "
                                           "--weight and --muscle (about a minute)."),
    bust: Optional[float] = typer.Option(None, help="--from-measurements: bust or chest "
                                         "girth \\[m].", callback=finite),
    waist: Optional[float] = typer.Option(None, help="--from-measurements: waist girth \\[m].",
                                          callback=finite),
    hip: Optional[float] = typer.Option(None, help="--from-measurements: hip girth \\[m].",
                                        callback=finite),
    json_: bool = typer.Option(False, "--json", help="Print the measurements as JSON."),
) -> None:
    """Make a custom body with the anny model and write it with its measurements.

    Needs anny: torch's CPU build (pip install torch --index-url
    https://download.pytorch.org/whl/cpu), then pip install "patternfit\\[anny]". With
    --from-measurements anny's weight is searched so that bust + waist + hip match, at the
    height given."""
    girths = dict(height=height, bust=bust, waist=waist, hip=hip)
    if from_measurements and None in girths.values():
        fail("--from-measurements needs " + ", ".join(f"--{k}" for k, v in girths.items()
                                                      if v is None))
    if not from_measurements and {bust, waist, hip} != {None}:
        fail("--bust, --waist and --hip go with --from-measurements")
    try:
        if from_measurements:
            from ..api import body_from_measurements

            result = body_from_measurements(gender=gender, name=out.stem, **girths)
        else:
            from ..body.anny import anny_body

            result = anny_body(gender=gender, weight=weight, muscle=muscle, stature=height,
                               name=out.stem)
    except ImportError as exc:  # anny is optional; the message says how to install it
        fail(str(exc))
    _write(result, out)
    if json_:
        print_json(_summary(result))
    else:
        for k in _MAIN:
            console.print(f"{k:12s} {result.measurements[k]:.3f} m")
