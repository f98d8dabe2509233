"""The paper's Table 2, automatically: each garment drafted too small for its body, draped,
and corrected by :func:`patternfit.loop.correct` until ϖ reaches the threshold.

Setup of each row (METHOD.md section 6): the built-in garment in the size nearest the
body's girths (``Row.size``), every panel narrowed across its grainline by ``narrow``
(``edit.grade(pattern, None, narrow, 1)``), in a stretch knit so that the body can still
get in; the narrowing is chosen so that the first drape starts in the paper's range
(60–75%). The coat and the skirt are sewn widened back to their drafted width and then
shrunk to their true width (``DesignSession.relax``): sewn directly, the narrowed coat
crosses itself and a narrowed skirt slides off the hips (docs/fit-correction.md).
"""

from __future__ import annotations

import os
import platform
import time
from dataclasses import dataclass
from pathlib import Path

from ..body.builtin import load_body
from ..edit import grade
from ..fit.metrics import FitEvaluator
from ..fit.maps import gap_scale, plot_measure_maps, pressure_scale
from ..fit.pictures import plot_3d_map, plot_sections
from ..fit.report import failure
from ..pattern.library import build
from ..sim.placement import place_on_body
from .correct import CorrectionSettings, correct
from .outputs import compress_png, plot_regions
from .session import DesignSession


@dataclass(frozen=True)
class Row:
    """One garment of the experiment and the paper's numbers for it (fractions).

    The pattern is the built-in garment in ``size`` narrowed across the grain to ``narrow``
    of its width; ``relax`` is the session's width factor of the first drape."""

    garment: str
    body: str
    triangles: int
    size: str
    narrow: float
    fabric: str
    relax: float
    paper: tuple  # (after simulation, 1st edit, 2nd edit, output, manual seconds)

    def pattern(self):
        """The row's too-small pattern."""
        return grade(build(self.garment, self.size), None, self.narrow, 1.0)

    def describe(self) -> str:
        """The setup in words."""
        sewn = f", sewn at {self.narrow * self.relax:.0%}" if self.relax > 1.0 else ""
        return (f"size {self.size} narrowed to {self.narrow:.0%} of its width{sewn}, "
                f"{self.fabric}")


ROWS = (
    Row("coat", "male_heavy", 22000, "M", 0.65, "stretch_knit", 1.0 / 0.65,
        (0.6523, 0.7249, 0.8573, 0.9143, 10.3)),
    Row("skirt", "female_thin", 15000, "S", 0.60, "stretch_knit", 1.0 / 0.60,
        (0.7096, 0.7856, 0.8329, 0.9234, 12.6)),
    Row("trousers", "male_thin", 20000, "S", 0.50, "stretch_knit", 1.0,
        (0.6371, 0.7083, 0.7555, 0.9019, 15.9)),
)


def run_row(row: Row, *, triangles: int | None = None, settings=CorrectionSettings(),
            figures: Path | None = None, progress=None) -> dict:
    """Run one row: drape, correct, and (with ``figures``) write the before/after maps as
    ``figures/table2_<garment>_{before,after}_{2d,3d}.png``, with the girth sections
    (``..._sections.png``) and the gap and pressure maps (``..._{gap,pressure}_{3d,2d}.png``).
    Returns the row's numbers, with the verdict and pressure p99 [kPa] of every drape
    (``verdicts``, ``pressure_kpa_p99``), how far each limb's cloth stops short of the
    wrist or ankle per drape (``lengths_cm``, cm) and the final ``ease_cm``."""
    t0 = time.perf_counter()
    pattern = row.pattern()
    session = DesignSession(pattern, load_body(row.body), row.fabric,
                            triangles or row.triangles, settings.threshold,
                            relax=row.relax)
    placed = place_on_body(pattern, session.mesh, session.body)
    placed_ratio = FitEvaluator(session.mesh).metrics(placed)[1]
    result = correct(session, settings=settings, progress=progress)
    seconds = time.perf_counter() - t0
    if figures is not None:
        figures.mkdir(parents=True, exist_ok=True)
        body = (session.body.vertices, session.body.faces)
        for name, state, it in (("before", session.history[0], result.iterations[0]),
                                ("after", session.state, result.iterations[-1])):
            fit = FitEvaluator(state.mesh)(state.positions)
            stem = figures / f"table2_{row.garment}_{name}"
            failed = failure(state.checks)  # a failed drape's maps say so, never a fit
            plot_regions(state.mesh, fit, it.regions, f"{stem}_2d.png",
                         title=f"{row.garment} on {row.body} ({name})", failed=failed)
            plot_3d_map(state.positions, state.mesh, fit, f"{stem}_3d.png", body=body,
                        title=f"{row.garment} on {row.body} ({name})", failed=failed)
            compress_png(f"{stem}_3d.png", f"{stem}_3d.png")
            if it.measured is not None:
                head = (f"{row.garment} on {row.body} ({name}): "
                        f"{it.verdict.overall if it.verdict else 'n/a'}")
                plot_sections(it.measured.sections, f"{stem}_sections.png", title=head,
                              failed=failed)
                for kind, values, scale in (("gap", it.measured.gap_mm, gap_scale()),
                                            ("pressure", it.measured.pressure_kpa,
                                             pressure_scale())):
                    for path in plot_measure_maps(state.mesh, state.positions, values, scale,
                                                  f"{stem}_{kind}", body=body, title=head,
                                                  failed=failed):
                        compress_png(path, path)
    return {"garment": row.garment, "body": row.body, "fabric": row.fabric,
            "narrow": row.narrow, "relax": row.relax, "size": row.size,
            "triangles": int(session.mesh.n_triangles),
            "vertices": int(session.mesh.n_vertices), "panels": len(pattern.panels),
            "placed": placed_ratio, "ratios": [it.fitting_ratio for it in result.iterations],
            "final": result.fitting_ratio, "reached": result.reached,
            "rounds": len(result.iterations) - 1,
            "edits": sum(len(it.edits) for it in result.iterations),
            "edit_cm": sum(e.to_dict()["cm"] for it in result.iterations for e in it.edits),
            "checks_passed": [bool(it.checks and it.checks.get("passed"))
                              for it in result.iterations],
            "verdicts": [it.verdict.overall if it.verdict is not None else None
                         for it in result.iterations],
            "pressure_kpa_p99": [(it.measures or {}).get("pressure_kpa", {}).get("p99")
                                 for it in result.iterations],
            "ease_cm": (result.iterations[-1].measures or {}).get("ease_cm", {}),
            "lengths_cm": [(it.measures or {}).get("lengths_cm", {})
                           for it in result.iterations],
            "region_verdicts": result.to_dict()["region_verdicts"],
            "seconds": seconds, "device": device_name(), "paper": row.paper}


def device_name() -> str:
    """The CPU this runs on, in words."""
    name = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                name = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{name}, {os.cpu_count()} cores (CPU)"


def format_table(rows: list[dict]) -> str:
    """The results beside the paper's rows, as plain text; under each of ours, the stricter
    verdict per drape with its pressure p99 [kPa], and the final ease [cm]."""
    head = (f"{'garment':9} {'body':12} {'#vert,#tri,#pan':17} {'placed':>7} {'1st drape':>9} "
            f"{'after edits':28} {'final':>7} {'rounds':>6} {'edits':>9} {'time':>7}  checks")
    out = [head, "-" * len(head)]
    for r in rows:
        p = r["paper"]
        mid = " / ".join(f"{x * 100:.2f}%" for x in r["ratios"][1:]) or "—"
        size = f"{r['vertices'] / 1e3:.1f}K,{r['triangles'] / 1e3:.1f}K,{r['panels']}"
        ok = "".join("✓" if c else "✗" for c in r["checks_passed"])
        out.append(f"{r['garment']:9} {r['body']:12} {size:17} {r['placed'] * 100:6.2f}% "
                   f"{r['ratios'][0] * 100:8.2f}% {mid:28} {r['final'] * 100:6.2f}% "
                   f"{r['rounds']:6d} {r['edits']:3d} {r['edit_cm']:4.0f}cm "
                   f"{r['seconds']:6.1f}s  {ok}")
        verdicts = " → ".join(
            f"{v or 'n/a'} ({'n/a' if q is None else f'{q:.2f}'} kPa)"
            for v, q in zip(r.get("verdicts", []), r.get("pressure_kpa_p99", [])))
        ease = ", ".join(f"{k} {v:+.1f}" for k, v in (r.get("ease_cm") or {}).items()
                         if v is not None)
        out.append(f"{'  verdict':9} {verdicts} (pressure p99); final ease cm: {ease or 'none'}")
        ends = " → ".join(" / ".join(f"{v:+.1f}" for v in d.values()) or "—"
                          for d in r.get("lengths_cm", []))
        limbs = " / ".join(next((d for d in r.get("lengths_cm", []) if d), {}))
        if limbs:
            out.append(f"{'  length':9} cm short of the wrist or ankle ({limbs}): {ends}")
        out.append(f"{'  paper':9} {'':12} {'':17} {100:6.2f}% {p[0] * 100:8.2f}% "
                   f"{p[1] * 100:.2f}% / {p[2] * 100:.2f}%{'':11} {p[3] * 100:6.2f}% "
                   f"{2:6d} {'manual':>9} {p[4]:6.1f}s")
    return "\n".join(out)


#: The variants of the paper's Figs 15–17: (figure, garment, body, label, size, (sx, sy)),
#: (sx, sy) a grading of every panel across / along the grain about its centre. The original
#: size is the Table 2 row's (the thin bodies wear S: an M skirt or trousers slides more than
#: 10 cm below their waist), the large one the next size up.
VARIANTS = (
    ("15a", "coat", "male_heavy", "original size", "M", (1.0, 1.0)),
    ("15b", "coat", "male_heavy", "small (65% width)", "M", (0.65, 1.0)),
    ("15c", "coat", "male_heavy", "large size", "L", (1.0, 1.0)),
    ("15d", "coat", "male_heavy", "lengthened 10%", "M", (1.0, 1.1)),
    ("15e", "coat", "male_heavy", "shortened 10%", "M", (1.0, 0.9)),
    ("16a", "skirt", "female_thin", "original size", "S", (1.0, 1.0)),
    ("16b", "skirt", "female_thin", "stretched 15% in length", "S", (1.0, 1.15)),
    ("16c", "skirt", "female_thin", "small (size S, 60% width)", "S", (0.6, 1.0)),
    ("17a", "trousers", "male_thin", "original size", "S", (1.0, 1.0)),
    ("17b", "trousers", "male_thin", "stretched 10% in length", "S", (1.0, 1.1)),
    ("17d", "trousers", "male_thin", "small (size S, 50% width)", "S", (0.5, 1.0)),
    ("17c", "trousers", "male_thin", "large size (M)", "M", (1.0, 1.0)),
)


def run_variant(variant, *, triangles: int = 3000, fabric: str = "stretch_knit",
                figures: Path | None = None) -> dict:
    """Drape one variant of Figs 15–17 once (no correction, sewn as it is, in the fabric of
    Table 2) and return its ϖ; with
    ``figures``, write ``figures/fig<N>_<garment>_<label>.png`` (3D colour map)."""
    fig, garment, body, label, size, (sx, sy) = variant
    t0 = time.perf_counter()
    pattern = build(garment, size)
    if (sx, sy) != (1.0, 1.0):
        pattern = grade(pattern, None, sx, sy)
    # the small variants are the Table 2 rows, sewn as those are
    relax = next((r.relax for r in ROWS if (r.garment, r.size, r.narrow) == (garment, size, sx)),
                 1.0)
    session = DesignSession(pattern, load_body(body), fabric, triangles, relax=relax)
    session.redrape()
    fit = session.evaluate()
    if figures is not None:
        figures.mkdir(parents=True, exist_ok=True)
        path = figures / f"fig{fig}_{garment}_{label.split()[0]}.png"
        plot_3d_map(session.positions, session.mesh, fit, path,
                    body=(session.body.vertices, session.body.faces),
                    title=f"Fig. {fig}: {garment}, {label}",
                    failed=failure(session.state.checks))
        compress_png(path, path)
    return {"figure": fig, "garment": garment, "body": body, "variant": label, "size": size,
            "fabric": fabric, "fitting_ratio": fit.fitting_ratio,
            "checks_passed": bool(session.state.checks["passed"]),
            "reasons": list(session.state.checks.get("reasons", [])),
            "seconds": time.perf_counter() - t0}
