"""``report.json``: the stable contract of a fit evaluation (keys are added, never renamed)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from ..files import atomic_write_text, json_default
from ..mesh.garment import GarmentMesh
from ..mesh.quality import min_angle
from .metrics import FitResult

FORMAT = "patternfit-report"
VERSION = 1


def fit_report(mesh: GarmentMesh, fit: FitResult, *, state: str = "placed",
               extra: dict[str, Any] | None = None) -> dict[str, Any]:
    """The report of one fit evaluation as a JSON-ready dict.

    Keys: ``fitting_ratio`` (eq. 2, a fraction, 1.0 = 100 %), ``fitting_ratio_symmetric``,
    ``panels`` (name, area_2d_m2, area_3d_m2, fitting_ratio), ``fit_classes`` (area fraction
    per class), ``fit_thresholds``, ``stretch``, ``mesh`` (vertices, triangles,
    min_angle_deg, seams, seam_pairs, panels), ``state`` and ``units``. ``extra`` is merged
    in at the top level (later stages add ``checks``, ``timing``...).
    """
    panels = []
    for i, name in enumerate(mesh.panel_names):
        sel = mesh.triangle_panel == i
        panels.append({"name": name, "area_2d_m2": float(fit.area_2d[sel].sum()),
                       "area_3d_m2": float(fit.area_3d[sel].sum()),
                       "fitting_ratio": float(fit.panel_ratio[i])})
    report = {
        "format": FORMAT, "version": VERSION,
        "state": state,
        "fitting_ratio": float(fit.fitting_ratio),
        "fitting_ratio_symmetric": float(fit.fitting_ratio_symmetric),
        "panels": panels,
        "fit_classes": fit.class_fractions(),
        "fit_thresholds": {"tight": fit.thresholds[0], "loose": fit.thresholds[1]},
        "stretch": {
            "area_change_min": float(fit.area_change.min()),
            "area_change_max": float(fit.area_change.max()),
            "warp_max": float(fit.warp.max()), "weft_max": float(fit.weft.max()),
        },
        "mesh": {"vertices": int(mesh.n_vertices), "triangles": int(mesh.n_triangles),
                 "panels": len(mesh.panel_names), "min_angle_deg": min_angle(
                     mesh.vertices, mesh.triangles),
                 "seams": len(mesh.seam_names), "seam_pairs": int(len(mesh.seam_pairs))},
        "units": {"length": "m", "area": "m^2", "fitting_ratio": "fraction (1.0 = 100%)",
                  "area_change": "fraction (S3/S2 - 1)"},
    }
    if extra:
        report.update(extra)
    return report


def write_report(report: dict[str, Any], path) -> Path:
    """Write ``report`` as indented JSON, atomically."""
    return atomic_write_text(path, json.dumps(report, indent=1, default=json_default) + "\n")
