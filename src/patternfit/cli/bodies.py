"""``patternfit bodies`` (built-in bodies) and ``patternfit body`` (a custom anny body)."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer
from rich.table import Table

from .app import app, console, fail, finite, print_json

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
    json_: bool = typer.Option(False, "--json", help="Print the result as JSON."),
) -> None:
    """List the built-in bodies with their measurements [m], or write one as a mesh."""
    from ..body import ALIASES, list_bodies, load_body

    if name is None:
        if out is not None:
            fail("--out needs a body NAME")
        loaded = [load_body(n) for n in list_bodies()]
        if json_:
            print_json({"bodies": [_summary(b) for b in loaded], "aliases": ALIASES})
            return

        table = Table("name", *(f"{k} [m]" for k in _MAIN))
        for b in loaded:
            table.add_row(b.name, *(f"{b.measurements[k]:.3f}" for k in _MAIN))
        console.print(table)
        console.print("aliases: " + ", ".join(f"'{a}' = {n}" for a, n in ALIASES.items()))
        return
    body = load_body(name)
    if out is not None:
        _write(body, out)
    if json_:
        print_json(_summary(body) | {"landmarks_m": {k: v.round(4).tolist()
                                                      for k, v in body.landmarks.items()}})
    elif out is None:
        for k, v in sorted(body.measurements.items()):
            console.print(f"{k:18s} {v:.3f} m")


@app.command()
def body(
    out: Path = typer.Option(..., "--out", help="Mesh file to write (.ply, .obj, .stl, .glb)."),
    gender: float = typer.Option(0.5, help="0 = male, 1 = female.", callback=finite),
    weight: float = typer.Option(0.5, help="0 = thin, 1 = heavy.", callback=finite),
    muscle: float = typer.Option(0.5, help="0 = little, 1 = much muscle.", callback=finite),
    height: Optional[float] = typer.Option(None, help="Standing height [m]; anny's average "
                                           "when omitted.", callback=finite),
    json_: bool = typer.Option(False, "--json", help="Print the measurements as JSON."),
) -> None:
    """Make a custom body with the anny model and write it with its measurements (needs
    anny: pip install torch==2.13.0, then pip install anny)."""
    try:
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
