"""What the design loop writes: the corrected pattern, before/after fit outputs, the regions
outlined on the 2D pattern, and ``report.json`` with every iteration."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
from PIL import Image

from ..figures import pyplot
from ..files import atomic_write_text, dumps_finite_json
from ..fit.colormap import FitScale
from ..fit.metrics import FitEvaluator, FitResult
from ..fit.outputs import write_fit_outputs
from ..fit.pictures import fit_colours, flat_layout, picture_title, title_colour
from ..fit.report import failure
from ..geometry import boundary_edges
from ..mesh.garment import GarmentMesh
from ..pattern.io import save_pattern
from .correct import Correction
from .regions import Region

# matplotlib is imported inside plot_regions: it is heavy and only that picture needs it.


def region_outline(mesh: GarmentMesh, triangles) -> np.ndarray:
    """Boundary edges of a set of triangles (edges used by exactly one of them): (k, 2) int."""
    return boundary_edges(mesh.triangles[np.asanyarray(triangles)])


def plot_regions(mesh: GarmentMesh, fit: FitResult, regions: list[Region], path, *,
                 title: str | None = None, failed: str | None = None) -> Path:
    """The flat pattern coloured by area change with each region outlined and numbered
    (dark red: tight, blue: loose); the numbers are listed with each region's description.
    ``failed``: why the drape failed its checks; the pattern is then grey and the title says
    "FAILED: <failed>" in red (no region is found on a failed drape)."""
    plt = pyplot()
    from matplotlib.collections import LineCollection, PolyCollection

    scale = FitScale(band=fit.thresholds[0])
    xy = flat_layout(mesh)
    width, height = np.ptp(xy[:, 0]), np.ptp(xy[:, 1])
    lines = max(len(regions), 1)
    text_h = 0.25 + 0.14 * lines  # [inch] the list of regions below the picture
    fig_w = min(16.0, 3.0 + 10.0 * width / max(width, height))
    fig_h = 8.0 * height / max(width, height) + 1.5 + text_h
    fig, ax = plt.subplots(figsize=(fig_w, fig_h))
    colors = fit_colours(scale, fit.area_change, failed)
    ax.add_collection(PolyCollection(xy[mesh.triangles], facecolors=colors, edgecolors=colors,
                                     linewidths=0.3))
    for loop in range(len(mesh.loop_panel)):
        ids = mesh.boundary_vertices[mesh.boundary_loop == loop]
        ring = xy[np.append(ids, ids[0])]
        ax.plot(ring[:, 0], ring[:, 1], color="k", lw=0.8)
    legend = []
    for k, r in enumerate(regions, start=1):
        colour = "#b2182b" if r.kind == "tight" else "#2166ac"
        ax.add_collection(LineCollection(xy[region_outline(mesh, r.triangles)], colors=colour,
                                         linewidths=1.6))
        c = xy[mesh.triangles[r.triangles]].mean(axis=(0, 1))
        ax.text(c[0], c[1], str(k), ha="center", va="center", fontsize=10, weight="bold",
                color=colour, bbox=dict(boxstyle="circle,pad=0.15", fc="white", ec=colour))
        legend.append(f"{k}. {r.describe()}")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("m")
    head = f"{title} — " if title else ""
    if failed:
        ax.set_title(picture_title(fit, title, failed), fontsize=10,
                     color=title_colour(failed))
    else:
        ax.set_title(f"{head}ϖ = {fit.fitting_ratio * 100:.2f}%: {len(regions)} region(s) "
                     "to modify", fontsize=10)
    note = ("no region is sought on a drape that failed its checks" if failed else
            "no region tighter or looser than the band")
    fig.text(0.01, 0.01, "\n".join(legend) or note, fontsize=7, va="bottom", ha="left")
    fig.tight_layout(rect=(0, text_h / fig_h, 1, 0.97))
    buf = io.BytesIO()
    fig.savefig(buf, dpi=150, format="png")
    plt.close(fig)
    return compress_png(buf, path)


def compress_png(source, path) -> Path:
    """Write the PNG ``source`` (a path or file object) to ``path`` with a palette of 128
    colours: plenty for colour maps and text, and files about 3 times smaller."""
    Image.open(source).convert("RGB").quantize(colors=128).save(path, optimize=True)
    return Path(path)


def write_correction_outputs(folder, session, correction: Correction, *, start: int = 0,
                             pictures: bool = True, extra: dict | None = None,
                             progress=None) -> dict:
    """Write the loop's results into ``folder`` and return the report.

    ``folder/pattern.json`` is the corrected pattern; ``before/`` and ``after/`` hold the fit
    outputs of history state ``start`` (the first drape) and of the current state;
    ``regions_before.png`` / ``regions_after.png`` outline the regions on the 2D pattern;
    ``report.json`` holds ``fitting_ratio`` (final ϖ), ``iterations`` (per iteration: ϖ,
    regions, edits in cm, seconds; 0 = the first drape) and ``regions`` (of the final drape).
    A correction refused from a drape that is no fit (``correction.failed``, no edit made)
    writes ``before/`` and the report only: no pattern that could pass for a corrected one.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    say = progress or (lambda msg: None)
    refused = bool(correction.failed) and not any(it.edits for it in correction.iterations)
    files = {}
    if not refused:
        save_pattern(correction.pattern, folder / "pattern.json")
        files["pattern"] = "pattern.json"
    body = (session.body.vertices, session.body.faces)
    states = [("before", session.history[start], correction.iterations[0])]
    if not refused:
        states.append(("after", session.state, correction.iterations[-1]))
    for name, state, it in states:
        say(f"{name}: fit outputs")
        fit = FitEvaluator(state.mesh)(state.positions)
        verdict = it.verdict.report() if it.verdict is not None else {}
        write_fit_outputs(folder / name, state.pattern, state.mesh, state.positions, fit,
                          state="draped", body=body, pictures=pictures,
                          extra={"checks": state.checks, **verdict,
                                 "regions": [r.to_dict() for r in it.regions]},
                          measures=it.measured, contact=session.saved_contact(state))
        files[name] = f"{name}/"
        if pictures:
            say(f"{name}: regions picture")
            plot_regions(state.mesh, fit, it.regions, folder / f"regions_{name}.png",
                         title=f"{state.pattern.name} ({name})", failed=failure(state.checks))
            files[f"regions_{name}_png"] = f"regions_{name}.png"
    report = {**correction.to_dict(), "regions": [r.to_dict() for r in
                                                  correction.iterations[-1].regions],
              "garment": correction.pattern.name, "body": session.body.name,
              "fabric": session.fabric.name, "triangles": int(session.mesh.n_triangles),
              "threshold": session.threshold, "relax": session.relax, "files": files,
              **(extra or {})}
    atomic_write_text(folder / "report.json", dumps_finite_json(report, indent=1))
    return report

