"""``report.json``: the stable contract of a fit evaluation (keys are added, never renamed).

A report never holds ``NaN`` or ``Infinity``: a value that is not finite (ϖ of a garment
collapsed to zero area, say) is written as ``null`` and the report's ``checks`` fail
(``fit_finite`` false, ``non_finite`` listing the values, ``passed`` false).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from ..files import atomic_write_text, dumps_finite_json
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
    min_angle_deg, seams, seam_pairs, panels), ``state``, ``units`` and ``checks``.
    ``extra`` is merged in at the top level (later stages add ``timing``...; a drape's fit
    measures, :meth:`patternfit.fit.measures.FitMeasures.report`, add ``gap_mm`` (p5, p50,
    p95 [mm]), ``ease_cm`` (girth name → garment − body girth [cm], the girths covered all
    around) and ``pressure_kpa`` (p50, p95, p99, max [kPa] over the contact area, None
    without contact)); its
    ``checks`` (the drape's) are merged into the report's.

    ``checks`` holds ``fit_finite`` (every number of the report is finite), ``passed``
    (``fit_finite`` and the drape's ``passed``; None when no checks were given: nothing
    was checked), ``equilibrium``, ``residual_rms`` and ``residual_p99`` (the drape's, None
    where not known) and, when a value is not finite,
    ``non_finite``: where it was (``"fitting_ratio"``, ``"panels[0].area_3d_m2"``); the value
    itself is ``None``. A report that did not pass is a failed fit: ``reasons`` then says
    why in words (the drape's reasons, on-body first, and the values not finite), and
    :func:`failure` joins them for a title or a message.
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
                  "area_change": "fraction (S3/S2 - 1)", "gap_mm": "mm", "ease_cm": "cm",
                  "pressure_kpa": "kPa"},
    }
    extra = dict(extra or {})
    drape_checks = extra.pop("checks", None) or {}
    report.update(extra)
    report["checks"] = dict(drape_checks)
    non_finite: list[str] = []
    report = _finite_or_none(report, "", non_finite)
    checks = report["checks"]
    # every report says whether its state is at rest and how near, null where not known
    # (a placement, a saved state read back alone)
    for key in ("equilibrium", "residual_rms", "residual_p99"):
        checks.setdefault(key, None)
    checks["fit_finite"] = not non_finite
    said = checks.get("passed")
    # None: nothing checked (a placement; a saved state without its body), never turned
    # into a pass: a placement never draped read "passed: true"
    checks["passed"] = False if said is False or non_finite else (None if said is None
                                                                  else True)
    if non_finite:
        checks["non_finite"] = non_finite
        more = f" and {len(non_finite) - 5} more" if len(non_finite) > 5 else ""
        checks["reasons"] = list(checks.get("reasons") or []) + [
            f"not finite: {', '.join(non_finite[:5])}{more}"]
    return report


def failure(report: dict[str, Any] | None) -> str | None:
    """Why the fit ``report`` (or its ``checks``) failed, in words; None when it passed."""
    checks = (report or {}).get("checks", report) or {}
    if checks.get("passed") is not False:
        return None
    reasons = [str(r) for r in checks.get("reasons") or [] if r]
    return "; ".join(reasons) if reasons else "the drape's checks failed"


def _finite_or_none(value, where: str, found: list[str]):
    """``value`` made JSON-ready with every non-finite number replaced by None, its place
    appended to ``found``."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    elif isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, dict):
        return {k: _finite_or_none(v, f"{where}.{k}" if where else str(k), found)
                for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite_or_none(v, f"{where}[{i}]", found) for i, v in enumerate(value)]
    if isinstance(value, float) and not math.isfinite(value):
        found.append(where)
        return None
    return value


def write_report(report: dict[str, Any], path) -> Path:
    """Write ``report`` as indented JSON, atomically; ``ValueError`` if it holds a NaN or
    an infinity (:func:`fit_report` replaces them, failing the checks)."""
    return atomic_write_text(path, dumps_finite_json(report, indent=1) + "\n")
