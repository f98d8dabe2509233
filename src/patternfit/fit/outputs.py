"""Everything a fit evaluation writes: coloured garment (GLB, OBJ), 2D map (SVG, PNG), 3D
picture (PNG), ``report.json`` and the garment state that ``patternfit fit`` reads back."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from typing import Any

from ..mesh.garment import GarmentMesh
from ..mesh.store import GARMENT, save_garment
from ..pattern.model import Pattern
from .colormap import FitScale, vertex_values
from .export import export_garment
from .maps import gap_scale, plot_measure_maps, pressure_scale
from .metrics import FitResult
from .pictures import FAILED_GREY, picture_title, plot_3d_map, plot_flat_map, plot_sections
from .report import failure, fit_report, write_report


def write_fit_outputs(folder, pattern: Pattern, mesh: GarmentMesh, positions, fit: FitResult, *,
                      state: str = "placed", body=None, pictures: bool = True,
                      extra: dict[str, Any] | None = None, progress=None,
                      measures=None, contact=None) -> dict[str, Any]:
    """Write all outputs of one fit evaluation into ``folder`` and return the report.

    ``positions`` (n, 3) [m] is the garment's 3D state; ``body`` an optional
    (vertices (k, 3), faces (f, 3)) pair drawn in the 3D picture; ``progress`` an optional
    callable taking a short message per file. The garment folder is written as one step
    (:func:`~patternfit.mesh.store.save_garment`).

    ``contact`` (named arrays, optional): the drape's contact state at ``positions``, saved
    with them so that a drape started from the folder continues this one.

    The report (:func:`~patternfit.fit.report.fit_report`) holds no NaN or infinity: a value
    that is not finite is None and ``report["checks"]["passed"]`` is False, and a front end
    must then report a failed fit; the pictures' titles then say "FAILED: <reason>"
    (:func:`~patternfit.fit.report.failure`: the drape's ``extra["checks"]["reasons"]``)
    instead of ϖ.

    ``measures`` (a :class:`~patternfit.fit.measures.FitMeasures`, optional) adds the
    report keys ``gap_mm``, ``ease_cm``, ``pressure_kpa`` and the pictures
    ``sections.png``, ``gap_{3d,2d}.png`` and ``pressure_{3d,2d}.png``; a verdict in
    ``extra`` (``verdict``, :meth:`patternfit.fit.verdict.Verdict.report`) goes into their
    titles.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    say = progress or (lambda msg: None)
    scale = FitScale(band=fit.thresholds[0])
    say("garment state")
    save_garment(folder / GARMENT, pattern, mesh, positions, contact=contact)
    files = {"garment": f"{GARMENT}/"}
    files.update({f"garment_{kind}": f"garment.{kind}" for kind in ("glb", "obj")})
    if pictures:
        files.update(fit_2d_png="fit_2d.png", fit_2d_svg="fit_2d.svg", fit_3d_png="fit_3d.png")
        if measures is not None:
            files["sections_png"] = "sections.png"
            for kind in ("gap", "pressure"):
                files.update({f"{kind}_{d}_png": f"{kind}_{d}.png" for d in ("3d", "2d")})
    extra = {**(measures.report() if measures is not None else {}), **(extra or {})}
    # the report first: its checks decide whether the pictures show ϖ or "FAILED"
    report = fit_report(mesh, fit, state=state, extra={
        "garment": pattern.name, "size": pattern.meta.get("size"),
        "colour_scale": {"limit": scale.limit, "band": scale.band,
                         "description": scale.describe()},
        "files": files, **extra})
    failed = failure(report)
    checks = report["checks"]
    # a state nobody checked on a body (a placement, a saved one read back alone) says so
    # on its maps
    name = pattern.name if checks.get("passed") is not None else \
        f"{pattern.name} (placed, not draped: ϖ alone)" if state == "placed" else \
        f"{pattern.name} (NOT CHECKED on a body: ϖ alone)"
    for kind in ("glb", "obj"):
        say(f"garment.{kind}")
        write_garment(folder / f"garment.{kind}", pattern, mesh, positions, fit, report,
                      state=state, scale=scale)
    if pictures:
        say("2D colour map")
        plot_flat_map(mesh, fit, [folder / "fit_2d.png", folder / "fit_2d.svg"], scale=scale,
                      title=name, failed=failed)
        say("3D picture")
        plot_3d_map(positions, mesh, fit, folder / "fit_3d.png", scale=scale, body=body,
                    title=name, failed=failed)
        if measures is not None:
            verdict = report.get("verdict")
            # a failed drape's gap and pressure say why it failed, as its fit maps do (a
            # skirt round the shins read "comfortable" under a small "failed")
            head = picture_title(fit, pattern.name, failed) if failed else \
                f"{pattern.name}: {verdict}" if verdict else pattern.name
            say("girth sections")
            plot_sections(measures.sections, folder / "sections.png", title=head,
                          failed=failed)
            say("gap and pressure maps")
            plot_measure_maps(mesh, positions, measures.gap_mm, gap_scale(), folder / "gap",
                              body=body, title=head, failed=failed)
            plot_measure_maps(mesh, positions, measures.pressure_kpa, pressure_scale(),
                              folder / "pressure", body=body, title=head, failed=failed)
    write_report(report, folder / "report.json")
    return report


def write_garment(path, pattern: Pattern, mesh: GarmentMesh, positions, fit: FitResult,
                  report: dict, *, state: str, scale: FitScale | None = None) -> Path:
    """Write the draped garment ``positions`` (n, 3) [m] of ``mesh`` to ``path`` (.glb, .obj,
    .ply) coloured by ``fit``'s area change on ``scale``, or all grey when ``report`` (its
    :func:`~patternfit.fit.report.fit_report`) says the drape failed: its colours would read
    as a fit. The file carries the report's status (checks passed, verdict, ϖ, reasons;
    :func:`~patternfit.fit.export.export_garment`)."""
    scale = scale or FitScale(band=fit.thresholds[0])
    failed = failure(report)
    rgb = scale.colors(vertex_values(mesh.triangles, fit.area_change, mesh.n_vertices,
                                     fit.area_2d))
    if failed:
        rgb = np.broadcast_to(FAILED_GREY, rgb.shape).copy()
    checks = report["checks"]
    status = {"garment": pattern.name, "state": state, "checks_passed": checks.get("passed"),
              "verdict": report.get("verdict"),
              "fitting_ratio": None if failed else report.get("fitting_ratio"),
              "reasons": [str(r) for r in checks.get("reasons") or []]}
    return export_garment(positions, mesh.triangles, rgb, path, status=status)
