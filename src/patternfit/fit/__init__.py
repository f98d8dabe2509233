"""Fit evaluation (METHOD.md section 3): per-triangle area change, the fitting ratio ϖ,
stretch along the grain, fit classes, colour maps and the report."""

from ..geometry import triangle_areas
from .colormap import FitScale, vertex_values
from .metrics import CLASS_NAMES, FIT, LOOSE, TIGHT, FitEvaluator, FitResult, evaluate_fit
from .report import fit_report, write_report

__all__ = ["CLASS_NAMES", "FIT", "FitEvaluator", "FitResult", "FitScale", "LOOSE", "TIGHT",
           "evaluate_fit", "fit_report", "triangle_areas", "vertex_values", "write_report"]
