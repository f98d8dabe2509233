"""The fit matrix of a batch: sizes × bodies, one panel per (pattern, fabric), coloured by
the drape's fit verdict (:mod:`patternfit.fit.verdict`), as
``matrix.png`` and ``matrix.html`` (each cell with its drape's thumbnail), and a one-line
answer per size."""

from __future__ import annotations

import html
import io
import textwrap
from pathlib import Path

import numpy as np

from ..figures import literal_text
from ..files import atomic_write_bytes, atomic_write_text

#: a verdict's colour (the fit-verdict words), a failed drape's, and a cell without a row's
VERDICT_COLOURS = {"too tight": "#b2182b", "tight": "#ef8a62", "fits": "#4dac26",
                   "loose": "#67a9cf", "too loose": "#2166ac"}
FAILED = "#404040"
MISSING = "#f0f0f0"


def verdict_of(row: dict) -> str:
    """A row's verdict: the drape's own (``FitOutcome.verdict``, judged by
    :class:`~patternfit.fit.verdict_rules.VerdictRules`), ``failed`` for a failed drape
    whatever else it reads (one that slid off its anchor too: its reason says it is too
    loose to hang there), or ``no verdict`` for a row written without one."""
    if row["status"] != "ok":
        return "failed"
    return row.get("verdict") or "no verdict"


def _axes(rows, tasks=None):
    """Panels (pattern, fabric), sizes and bodies in the order of ``tasks`` (the batch's
    plan, rows or no rows), else in the order they first appear in ``rows``."""
    items = list(tasks or ()) + [(r["pattern"], r["size"], r["body"], r["fabric"])
                                 for r in rows]
    panels = list(dict.fromkeys((p, f) for p, _, _, f in items))
    sizes = list(dict.fromkeys(s for _, s, _, _ in items))
    bodies = list(dict.fromkeys(b for _, _, b, _ in items))
    return panels, sizes, bodies


def summary_lines(rows: list[dict]) -> list[str]:
    """One answer per (pattern, fabric, size): ``"skirt in denim, M: fits 34 of 50 bodies;
    tight on 9 at the hip 7, waist 2; failed on 2 (on_body 2)"``: the regions each tight
    drape's verdict names (``verdict_regions``), the failed checks of each failed one."""
    panels, sizes, _ = _axes(rows)
    out = []
    for pattern, fabric in panels:
        for size in sizes:
            cell = [r for r in rows if (r["pattern"], r["fabric"], r["size"])
                    == (pattern, fabric, size)]
            if not cell:
                continue
            groups: dict[str, list] = {}
            for r in cell:
                groups.setdefault(verdict_of(r), []).append(r)
            parts = [f"fits {len(groups.pop('fits', []))} of {len(cell)} bodies"]
            failed = groups.pop("failed", [])
            for word, members in sorted(groups.items(), key=lambda kv: -len(kv[1])):
                where: dict[str, int] = {}
                for r in members:
                    named = (r.get("verdict_regions") or "").split() if "tight" in word else []
                    for g in named:
                        where[g.replace("_", " ")] = where.get(g.replace("_", " "), 0) + 1
                at = ", ".join(f"{k} {n}" if len(where) > 1 else k for k, n in
                               sorted(where.items(), key=lambda kv: -kv[1]))
                parts.append(f"{word} on {len(members)}" + (f" at the {at}" if at else ""))
            if failed:
                why: dict[str, int] = {}
                for r in failed:
                    for c in (r.get("failed_checks") or "error").split():
                        why[c] = why.get(c, 0) + 1
                parts.append(f"failed on {len(failed)} (" + ", ".join(
                    f"{c} {n}" for c, n in sorted(why.items(), key=lambda kv: -kv[1])) + ")")
            out.append(f"{Path(pattern).stem} in {fabric}, {size}: " + "; ".join(parts))
    return out


def _cell_colour(row):
    v = verdict_of(row)
    return FAILED if v == "failed" else VERDICT_COLOURS.get(v, "#999999")


def write_matrix(folder, rows: list[dict], *, tasks=None) -> dict:
    """Write ``matrix.png`` and ``matrix.html`` of ``rows`` into ``folder`` (atomically),
    with a cell for every task of ``tasks`` (the plan) when given; returns ``{"png",
    "html", "lines"}`` (paths and :func:`summary_lines`). Cells are coloured by
    :func:`verdict_of`; failed drapes dark grey, tasks without a row light grey."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    literal_text()  # pattern and body names are the user's
    folder = Path(folder)
    panels, sizes, bodies = _axes(rows, tasks)
    lines = summary_lines(rows)
    by_key = {(r["pattern"], r["fabric"], r["size"], r["body"]): r for r in rows}
    width = max(7.0, 1.4 + 0.45 * len(bodies))  # [in]; room for the lines below
    notes = [w for s in lines + [_legend()]
             for w in textwrap.wrap(s, int(17 * width), subsequent_indent="    ")]
    fig = Figure(figsize=(width, (1.4 + 0.35 * len(sizes)) * len(panels)
                          + 0.14 * len(notes) + 0.3), dpi=110)
    grid = fig.subplots(len(panels), 1, squeeze=False)[:, 0]
    for ax, (pattern, fabric) in zip(grid, panels):
        for i, size in enumerate(sizes):
            for j, body in enumerate(bodies):
                row = by_key.get((pattern, fabric, size, body))
                colour = MISSING if row is None else _cell_colour(row)
                ax.add_patch(_rect(j, i, colour))
                if row is not None:  # a failed drape's ϖ is no fit: not shown
                    ax.text(j + 0.5, i + 0.5, f"{100 * row['fitting_ratio']:.0f}"
                            if row["status"] == "ok" else "failed",
                            ha="center", va="center", fontsize=6,
                            color="white" if colour in (FAILED, "#b2182b", "#2166ac")
                            else "black")
        ax.set_xlim(0, len(bodies))
        ax.set_ylim(len(sizes), 0)
        ax.set_xticks(np.arange(len(bodies)) + 0.5, bodies, rotation=60, ha="right",
                      fontsize=6)
        ax.set_yticks(np.arange(len(sizes)) + 0.5, sizes, fontsize=7)
        ax.set_title(f"{Path(pattern).stem} in {fabric}: size × body (ϖ % in the cells)",
                     fontsize=8)
        ax.tick_params(length=0)
    fig.text(0.01, 0.01, "\n".join(notes), fontsize=6.5, va="bottom", family="monospace")
    fig.tight_layout(rect=(0, (0.14 * len(notes) + 0.1) / fig.get_figheight(), 1, 1))
    buf = io.BytesIO()
    FigureCanvasAgg(fig).print_png(buf)
    png = atomic_write_bytes(folder / "matrix.png", buf.getvalue())
    page = atomic_write_text(folder / "matrix.html",
                             _html(rows, panels, sizes, bodies, lines))
    return {"png": png, "html": page, "lines": lines}


def _rect(x, y, colour):
    from matplotlib.patches import Rectangle

    return Rectangle((x + 0.04, y + 0.04), 0.92, 0.92, facecolor=colour, edgecolor="none")


#: what a cell's thumbnail shows (``work.thumbnail_png``), which is not its verdict
THUMBNAIL_LEGEND = ("thumbnails: the garment coloured by its area change, not its verdict: "
                    "red stretched, yellow unchanged, blue compressed (±10%); a failed "
                    "drape's in grey")


def _legend() -> str:
    words = ("too tight dark red, tight orange, fits green, loose light blue, too loose blue; "
             "dark grey: failed drape (no fit); ϖ % in the cells")
    return f"colours: the drape's verdict: {words}"


def _html(rows, panels, sizes, bodies, lines) -> str:
    by_key = {(r["pattern"], r["fabric"], r["size"], r["body"]): r for r in rows}
    esc = html.escape
    out = ["<!doctype html><html><head><meta charset='utf-8'><title>fit matrix</title>",
           "<style>body{font:13px sans-serif;margin:16px}table{border-collapse:separate;border-spacing:3px}"
           "td,th{border:1px solid #ccc;padding:3px;text-align:center;vertical-align:top;max-width:170px}"
           "td img{display:block;height:120px;margin:auto}"
           "td div{font-size:11px;padding:2px}</style></head><body>",
           "<h1>Fit matrix</h1><ul>", *(f"<li>{esc(s)}</li>" for s in lines), "</ul>",
           f"<p>{esc(_legend())}</p>",
           # the thumbnails show another measure than the cells' colour: said beside them
           f"<p>{esc(THUMBNAIL_LEGEND)}</p>"]
    for pattern, fabric in panels:
        out.append(f"<h2>{esc(Path(pattern).stem)} in {esc(fabric)}</h2><table><tr><th></th>")
        out += [f"<th>{esc(b)}</th>" for b in bodies]
        out.append("</tr>")
        for size in sizes:
            out.append(f"<tr><th>{esc(size)}</th>")
            for body in bodies:
                row = by_key.get((pattern, fabric, size, body))
                if row is None:
                    out.append(f"<td style='background:{MISSING}'>no result yet</td>")
                    continue
                colour = _cell_colour(row)
                ratio = row["fitting_ratio"]
                text = verdict_of(row)
                if row["status"] == "ok":
                    text += f" · ϖ {100 * ratio:.1f}%"
                else:
                    text += f"<br>{esc(row.get('failed_checks') or '')}: " \
                            f"{esc((row.get('reasons') or '')[:120])}"
                img = (f"<img src='{esc(row['thumbnail'])}' alt='drape'>"
                       if row.get("thumbnail") else "")
                out.append(f"<td style='border:6px solid {colour}'>{img}"
                           f"<div>{text}</div></td>")
            out.append("</tr>")
        out.append("</table>")
    out.append("</body></html>")
    return "\n".join(out)
