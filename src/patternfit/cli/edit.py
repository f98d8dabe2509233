"""``patternfit edit``: apply one editing tool to a pattern file (and carry its mesh over)."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from ..files import read_json_file
from .app import app, console, fail, print_json

# patternfit.api and the stage modules are imported inside the commands, when they run:
# `patternfit --help` should not wait for them (see commands.py)

OPERATIONS = ("move-point", "move-edge", "edit-curve", "lengthen", "grade", "insert-dart",
              "move-dart", "resize-dart")


def _pair(text: Optional[str], name: str):
    if text is None:
        return None
    try:
        x, y = (float(v) for v in text.split(","))
    except ValueError:
        fail(f"{name}: expected two numbers 'x,y' in metres, got {text!r}")
    return (x, y)


def _need(value, name: str, op: str):
    if value is None:
        fail(f"operation '{op}' needs {name}")
    return value


def _apply(pattern, op: str, o: dict):
    from .. import edit

    panel = o["panel"]
    offset = (o["dx"], o["dy"])
    if op == "grade":
        return edit.grade(pattern, panel, o["sx"], o["sy"], about=o["about"],
                          partner=o["partner"])
    panel = _need(panel, "--panel", op)
    if op == "move-point":
        return edit.move_point(pattern, panel, _need(o["edge"], "--edge (the edge starting at "
                               "the corner)", op), offset, partner=o["partner"])
    if op == "move-edge":
        return edit.move_edge(pattern, panel, _need(o["edge"], "--edge", op), offset,
                              partner=o["partner"])
    if op == "edit-curve":
        return edit.edit_curve(pattern, panel, _need(o["edge"], "--edge", op), offset,
                               control=o["control"], partner=o["partner"])
    if op == "lengthen":
        return edit.lengthen(pattern, panel, _need(o["a"], "--a", op), _need(o["b"], "--b", op),
                             _need(o["amount"], "--amount", op), partner=o["partner"])
    dart = _need(o["dart"], "--dart", op)
    if op == "insert-dart":
        return edit.insert_dart(pattern, panel, dart, _need(o["centre"], "--centre", op),
                                length=_need(o["length"], "--length", op),
                                width=_need(o["width"], "--width", op),
                                axis=o["axis"] or (0.0, 1.0), shape=o["shape"])
    if op == "move-dart":
        return edit.move_dart(pattern, panel, dart, offset)
    return edit.resize_dart(pattern, panel, dart, length=o["length"], width=o["width"])


@app.command("edit")
def edit_command(
    pattern_file: Path = typer.Argument(..., help="Pattern JSON file to edit."),
    operation: str = typer.Argument(..., help="One of: " + ", ".join(OPERATIONS) + "."),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="Where to write the edited "
                                       "pattern (never the input, unless --in-place)."),
    in_place: bool = typer.Option(False, "--in-place", help="Overwrite the input files "
                                  "(atomically)."),
    panel: Optional[str] = typer.Option(None, help="Panel to edit (grade: all if omitted)."),
    edge: Optional[str] = typer.Option(None, help="Edge name (move-point: the edge that "
                                       "starts at the corner)."),
    dx: float = typer.Option(0.0, help="Offset in x \\[m]."),
    dy: float = typer.Option(0.0, help="Offset in y \\[m]."),
    control: int = typer.Option(1, help="edit-curve: Bézier control point number."),
    a: Optional[str] = typer.Option(None, help="lengthen: a point 'x,y' \\[m] before the "
                                          "cut; the panel is lengthened along a→b (not "
                                          "along the cut line: a and b lie across it), cut "
                                          "at their midpoint, square to a–b."),
    b: Optional[str] = typer.Option(None, help="lengthen: a point 'x,y' \\[m] beyond the "
                                          "cut, in the direction the part beyond it moves "
                                          "(e.g. --a 0,0.3 --b 0,0.1 lowers a hem)."),
    amount: Optional[float] = typer.Option(None, help="lengthen: added length \\[m] "
                                           "(negative shortens)."),
    sx: float = typer.Option(1.0, help="grade: scale in x."),
    sy: float = typer.Option(1.0, help="grade: scale in y."),
    about: Optional[str] = typer.Option(None, help="grade: centre 'x,y' \\[m] (default: the "
                                        "panel centroid)."),
    dart: Optional[str] = typer.Option(None, help="Dart (inner loop) name."),
    centre: Optional[str] = typer.Option(None, help="insert-dart: centre 'x,y' \\[m]."),
    length: Optional[float] = typer.Option(None, help="Dart length \\[m]."),
    width: Optional[float] = typer.Option(None, help="Dart width \\[m]."),
    axis: Optional[str] = typer.Option(None, help="insert-dart: long axis 'x,y' (default "
                                       "0,1)."),
    shape: str = typer.Option("diamond", help="insert-dart: diamond or triangle."),
    partner: bool = typer.Option(False, help="Edit seam partner edges to keep seams "
                                 "matching."),
    mesh: Optional[Path] = typer.Option(None, "--mesh", help="Mesh (.npz) of the pattern "
                                        "to carry over to the edited one."),
    mesh_out: Optional[Path] = typer.Option(None, "--mesh-out", help="Where to write the "
                                            "updated mesh (default: beside --out, .npz)."),
    json_out: bool = typer.Option(False, "--json", help="Print the result as JSON."),
) -> None:
    """Apply one editing tool to PATTERN_FILE and write the result (lengths in metres).

    With --mesh, the panel mesh follows the edit smoothly (coordinates, no re-meshing unless
    quality requires it) and is written beside the new pattern.
    """
    from .. import api
    from ..edit import update_mesh
    from ..mesh import GarmentMesh
    from ..mesh.store import replace_pattern_and_mesh
    from ..pattern import PatternError, save_pattern
    from ..pattern.formats import json_kind, sniff_format
    from ..pattern.io import pattern_from_document

    if operation not in OPERATIONS:
        fail(f"unknown operation '{operation}' (expected one of {', '.join(OPERATIONS)})")
    if out is None and not in_place:
        fail("give --out NEW.json (or --in-place to overwrite the input)")
    out = pattern_file if out is None else out
    if out.resolve() == pattern_file.resolve() and not in_place:
        fail(f"--out is the input file {pattern_file}; pass --in-place to overwrite it")
    if mesh is not None:
        mesh_out = mesh_out or (mesh if in_place else out.with_suffix(".npz"))
        if mesh_out.resolve() == mesh.resolve() and not in_place:
            fail(f"--mesh-out is the input mesh {mesh}; pass --in-place to overwrite it")
        if mesh_out.resolve() in (out.resolve(), pattern_file.resolve()):
            fail(f"--mesh-out {mesh_out} is the pattern file written or read: name another "
                 "file for the mesh")
    # the file is read once: its format, its pattern and its units from one reading
    if pattern_file.suffix.lower() == ".json":
        data = read_json_file(pattern_file, error=PatternError)
        kind = json_kind(data, pattern_file)
    else:
        data, kind = None, sniff_format(pattern_file)  # (an ending no reader takes: refused)
    if kind != "patternfit":
        fail(f"{pattern_file}: edit works on a patternfit JSON pattern; convert it first "
             f"(patternfit convert {pattern_file} "
             f"{pattern_file.stem.removesuffix('_specification')}.json)")
    old = pattern_from_document(data, pattern_file)
    # the edited pattern is written in the units of the input (the reader checked them)
    units = data.get("units", "m")
    opts = dict(panel=panel, edge=edge, dx=dx, dy=dy, control=control, a=_pair(a, "--a"),
                b=_pair(b, "--b"), amount=amount, sx=sx, sy=sy, about=_pair(about, "--about"),
                dart=dart, centre=_pair(centre, "--centre"), length=length, width=width,
                axis=_pair(axis, "--axis"), shape=shape, partner=partner)
    new = _apply(old, operation, opts)
    result = {"operation": operation, "pattern": str(out), "area_before_m2": old.area(),
              "area_after_m2": new.area()}
    if mesh is not None:
        m = GarmentMesh.load(mesh)
        try:
            m2, rep = update_mesh(old, new, m, return_report=True)
            result["mesh"] = {"file": str(mesh_out), "moved_panels": list(rep.moved),
                              "steps": rep.steps, "remeshed_panels": list(rep.remeshed),
                              "inverted_triangles": rep.inverted,
                              "min_angle_deg": rep.min_angle}
        except PatternError as exc:   # the edit changed the panels' edges (a new dart)
            m2 = api.mesh_garment(new, triangles=m.n_triangles)
            result["mesh"] = {"file": str(mesh_out), "remeshed_panels": "all",
                              "reason": exc.reason}
    if mesh is None:
        save_pattern(new, out, units=units)
    else:  # one step: a crash never leaves the new pattern beside the old mesh
        replace_pattern_and_mesh(out, new, mesh_out, m2, units=units)
    if json_out:
        print_json(result)
        return
    console.print(f"{operation}: wrote {out} (area {old.area():.4f} → {new.area():.4f} m²)")
    if mesh is not None:
        info = result["mesh"]
        if info.get("remeshed_panels") == "all":
            console.print(f"mesh re-built ({info['reason']}): wrote {mesh_out}")
        else:
            console.print(f"mesh updated: wrote {mesh_out}; moved {info['moved_panels']}, "
                          f"re-meshed {info['remeshed_panels']}, min angle "
                          f"{info['min_angle_deg']:.1f}°, 0 inverted triangles")
