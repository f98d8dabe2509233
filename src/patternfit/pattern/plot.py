"""Pattern plots at true scale: an SVG sheet and a multi-page PDF of printer tiles.

Pieces are laid out on one sheet (rows, tallest first) with their names, grain lines, notches
(the pieces' own, red slits into the fabric, and one at the middle of each seam side) and seam
labels, and what a CAD file draws on them: the cut line around the sew line (thin grey), internal
lines (dashed blue) and drill holes (blue circled crosses); optionally the per-triangle 2D fit colours lie under the outlines. The SVG is
sized in millimetres so that it prints at 1:1; the PDF cuts the sheet into A4 or letter tiles
(with the tile's name and borders to align) after a cover page that carries a 10 cm check
square, the tile map and the piece list. Lengths are metres inside.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import escape

import numpy as np

from ..figures import pyplot
from ..files import atomic_write_bytes, atomic_write_text
from .dxf import notch_marks
from .dxf_notches import notch_slits
from .edges import Edge
from .model import Loop, Pattern

# matplotlib is imported inside the functions that need it (the PDF, and fit colours without
# triangle_panel): it is heavy, and the SVG sheet is written without it.

__all__ = ["PAPERS", "Sheet", "layout", "write_pdf", "write_svg"]

#: paper sizes (width, height) [m]
PAPERS = {"a4": (0.210, 0.297), "letter": (0.2159, 0.2794)}
_GAP = 0.04  # space between pieces on the sheet [m]
_MM = 1000.0


@dataclass(frozen=True)
class Sheet:
    """Pieces placed on one sheet: ``offsets[name]`` is added to the panel's points [m]."""

    pattern: Pattern
    offsets: dict
    size: tuple[float, float]
    fit: tuple | None = None


def _coerce_fit(pattern: Pattern, fit) -> tuple | None:
    """(vertices (n,2), triangles (m,3), rgb (m,3) in [0, 1], triangle_panel (m,)) or None."""
    if fit is None:
        return None
    if len(fit) not in (3, 4):
        raise ValueError("fit: expected (vertices, triangles, rgb[, triangle_panel])")
    v = np.asanyarray(fit[0], dtype=np.float64)
    t = np.asanyarray(fit[1])
    rgb = np.asanyarray(fit[2], dtype=np.float64)
    if v.ndim != 2 or v.shape[1] != 2:
        raise ValueError(f"fit: vertices must be (n, 2), got {v.shape}")
    if t.ndim != 2 or t.shape[1] != 3 or not np.issubdtype(t.dtype, np.integer) or \
            (t.size and (t.min() < 0 or t.max() >= len(v))):
        raise ValueError("fit: triangles must be (m, 3) indices into vertices")
    if rgb.shape != (len(t), 3):
        raise ValueError(f"fit: rgb must be (m, 3) = ({len(t)}, 3), got {rgb.shape}")
    if rgb.size and rgb.max() > 1.0:
        rgb = rgb / 255.0
    if len(fit) == 4:
        tp = np.asanyarray(fit[3]).astype(int)
        if tp.shape != (len(t),) or (tp.size and (tp.min() < 0 or tp.max() >= len(pattern.panels))):
            raise ValueError("fit: triangle_panel must be (m,) panel indices")
    else:  # the panel whose outline holds the triangle's centroid
        from matplotlib.path import Path as MplPath

        centroids = v[t].mean(axis=1)
        tp = np.full(len(t), -1)
        for k, panel in enumerate(pattern.panels):
            inside = MplPath(panel.outline.polygon(16)).contains_points(centroids)
            tp[(tp < 0) & inside] = k
        if (tp < 0).any():
            raise ValueError("fit: some triangles lie outside every panel; pass triangle_panel")
    return v, t, np.clip(rgb, 0.0, 1.0), tp


def layout(pattern: Pattern, *, width: float = 1.5, fit=None) -> Sheet:
    """Place the pieces in rows no wider than ``width`` [m] (or the widest piece).

    fit : optional ``(vertices (n, 2), triangles (m, 3), rgb (m, 3))`` flat mesh colours,
        vertices in each panel's frame [m], with an optional fourth array ``triangle_panel``
        (m,) of panel indices (else taken from the outline that holds each triangle).
    """
    boxes = {}
    for p in pattern.panels:
        # the cut line lies outside the sew line: the piece takes the room of both
        poly = np.vstack([p.outline.polygon(16), np.asarray(p.cut_line).reshape(-1, 2)])
        boxes[p.name] = (poly.min(axis=0), poly.max(axis=0))
    order = sorted(pattern.panels, key=lambda p: -(boxes[p.name][1][1] - boxes[p.name][0][1]))
    width = max(width, max(float(hi[0] - lo[0]) for lo, hi in boxes.values()) + 2 * _GAP)
    rows, row, x = [], [], _GAP
    for p in order:
        lo, hi = boxes[p.name]
        if row and x + float(hi[0] - lo[0]) + _GAP > width:
            rows.append(row)
            row, x = [], _GAP
        row.append(p.name)
        x += float(hi[0] - lo[0]) + _GAP
    rows.append(row)
    heights = [max(float(boxes[n][1][1] - boxes[n][0][1]) for n in r) for r in rows]
    total_h = sum(heights) + _GAP * (len(rows) + 1) + 0.10  # room for the scale bar
    offsets, top, used_w = {}, total_h - _GAP, 0.0
    for r, h in zip(rows, heights):
        x = _GAP
        for n in r:
            lo, hi = boxes[n]
            offsets[n] = np.array([x - lo[0], top - hi[1]])
            x += float(hi[0] - lo[0]) + _GAP
        used_w = max(used_w, x)
        top -= h + _GAP
    return Sheet(pattern, offsets, (max(used_w, 0.14), total_h), _coerce_fit(pattern, fit))


# -- shared geometry ----------------------------------------------------------------------------
def _labels(sheet: Sheet):
    """Text and marks in sheet coordinates [m]: pieces, grain lines, notches, seam labels."""
    pat = sheet.pattern
    size = pat.meta.get("size") if isinstance(pat.meta, dict) else None
    names, grains = [], []
    for p in pat.panels:
        off = sheet.offsets[p.name]
        poly = p.outline.polygon(16) + off
        lo, hi = poly.min(axis=0), poly.max(axis=0)
        centre = 0.5 * (lo + hi)
        g = np.asarray(p.grainline)
        half = 0.3 * float(np.abs(hi - lo) @ np.abs(g))
        grains.append((centre - half * g, centre + half * g))
        text = p.name if not size else f"{p.name} ({size})"
        names.append((centre + np.array([0.0, 0.03]), text))
    notches, seams = [], []
    for pname, seam, at, inner in notch_marks(pat, length=0.008):
        off = sheet.offsets[pname]
        notches.append((at + off, inner + off))
        seams.append((inner + off + 2.5 * (inner - at), seam))
    return names, grains, notches, seams


def _marks(sheet: Sheet):
    """What is drawn on the pieces, in sheet coordinates [m]: the pieces' notches as slits
    into the fabric ((2, 2) each), cut lines (closed, (k, 2)), internal lines ((k, 2)) and
    drill holes ((2,) each)."""
    slits, cuts, lines, holes = [], [], [], []
    for p in sheet.pattern.panels:
        off = sheet.offsets[p.name]
        slits += [s + off for s in notch_slits(p, length=0.008)]
        if p.cut_line:
            cuts.append(np.asarray(p.cut_line) + off)
        lines += [np.asarray(ln.points) + off for ln in p.lines]
        holes += [np.asarray(h) + off for h in p.drill_holes]
    return slits, cuts, lines, holes


def _fit_polys(sheet: Sheet) -> tuple[np.ndarray, np.ndarray] | tuple[None, None]:
    if sheet.fit is None:
        return None, None
    v, t, rgb, tp = sheet.fit
    shift = np.array([sheet.offsets[p.name] for p in sheet.pattern.panels])[tp]
    return v[t] + shift[:, None, :], rgb


# -- SVG --------------------------------------------------------------------------------------
def _svg_edge(e: Edge, off: np.ndarray) -> str:
    pts = (np.asarray(e.points) + off) * _MM
    tail = " ".join(f"{x:.4f} {y:.4f}" for x, y in pts[1:])
    if e.kind == "line":
        return f"L {tail}"
    if e.kind == "quadratic":
        return f"Q {tail}"
    if e.kind == "cubic":
        return f"C {tail}"
    # inside the y-up group the user frame is ours, so the flags keep their meaning
    r = max(e.radius, 0.5 * float(np.linalg.norm(e.end - e.start))) * _MM
    return f"A {r:.4f} {r:.4f} 0 {int(e.large_arc)} {int(e.sweep)} {tail}"


def _svg_loop(loop: Loop, off: np.ndarray) -> str:
    x, y = (loop.edges[0].start + off) * _MM
    return f"M {x:.4f} {y:.4f} " + " ".join(_svg_edge(e, off) for e in loop.edges) + " Z"


def svg_text(sheet: Sheet) -> str:
    """The SVG document of a laid-out sheet, 1 user unit = 1 mm."""
    w, h = (s * _MM for s in sheet.size)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w:.3f}mm" height="{h:.3f}mm" '
           f'viewBox="0 0 {w:.3f} {h:.3f}">',
           f"<title>{escape(sheet.pattern.name)}</title>",
           f'<g transform="matrix(1 0 0 -1 0 {h:.3f})" fill="none" stroke-linejoin="round">']
    polys, rgb = _fit_polys(sheet)
    if polys is not None:
        out.append('<g stroke-width="0.3">')  # hides anti-aliasing seams
        for tri, c in zip(polys * _MM, rgb):
            col = "#%02x%02x%02x" % tuple(int(round(255 * x)) for x in c)
            pts = " ".join(f"{x:.3f},{y:.3f}" for x, y in tri)
            out.append(f'<polygon points="{pts}" fill="{col}" stroke="{col}"/>')
        out.append("</g>")
    for p in sheet.pattern.panels:
        off = sheet.offsets[p.name]
        d = " ".join(_svg_loop(lp, off) for lp in p.loops)
        fill = "none" if polys is not None else "#f3efe6"
        out.append(f'<path class="piece" d="{d}" fill="{fill}" fill-rule="evenodd" '
                   f'stroke="#000" stroke-width="0.5"><title>{escape(p.name)}</title></path>')
    names, grains, notches, seams = _labels(sheet)
    for a, b in grains:
        (x0, y0), (x1, y1) = a * _MM, b * _MM
        out.append(f'<line class="grain" x1="{x0:.3f}" y1="{y0:.3f}" x2="{x1:.3f}" '
                   f'y2="{y1:.3f}" stroke="#000" stroke-width="0.35"/>')
        u = (b - a) / max(np.linalg.norm(b - a), 1e-300)
        for tip, s in ((b, 1), (a, -1)):  # arrow heads at both ends
            base = tip - s * 0.008 * u
            n = np.array([-u[1], u[0]]) * 0.003
            pts = " ".join(f"{x:.3f},{y:.3f}" for x, y in (tip * _MM, (base + n) * _MM,
                                                           (base - n) * _MM))
            out.append(f'<polygon points="{pts}" fill="#000"/>')
    slits, cuts, lines, holes = _marks(sheet)
    for a, b in notches + [tuple(s) for s in slits]:
        (x0, y0), (x1, y1) = a * _MM, b * _MM
        out.append(f'<line class="notch" x1="{x0:.3f}" y1="{y0:.3f}" x2="{x1:.3f}" '
                   f'y2="{y1:.3f}" stroke="#c00" stroke-width="0.5"/>')

    def points(pts):
        return " ".join(f"{x:.3f},{y:.3f}" for x, y in pts * _MM)

    for c in cuts:
        out.append(f'<polygon class="cut" points="{points(c)}" stroke="#555" '
                   f'stroke-width="0.3"/>')
    for ln in lines:
        out.append(f'<polyline class="line" points="{points(ln)}" stroke="#1f5fa8" '
                   f'stroke-width="0.35" stroke-dasharray="3 1.5"/>')
    for at in holes:
        x, y = at * _MM
        out.append(f'<g class="drill" stroke="#1f5fa8" stroke-width="0.3">'
                   f'<circle cx="{x:.3f}" cy="{y:.3f}" r="1.5"/>'
                   f'<path d="M {x - 2.5:.3f} {y:.3f} H {x + 2.5:.3f} M {x:.3f} {y - 2.5:.3f} '
                   f'V {y + 2.5:.3f}"/></g>')
    sq = 100.0
    out.append(f'<rect class="check" x="{_GAP * _MM:.3f}" y="{_GAP * _MM * 0.5:.3f}" '
               f'width="{sq}" height="{sq * 0.2:.3f}" stroke="#000" stroke-width="0.3"/>')
    out.append("</g>")

    def text(at, s, size, cls, weight="normal"):
        x, y = at * _MM
        out.append(f'<text class="{cls}" x="{x:.3f}" y="{h - y:.3f}" font-size="{size}" '
                   f'font-family="sans-serif" font-weight="{weight}" text-anchor="middle">'
                   f"{escape(s)}</text>")

    for at, s in names:
        text(at, s, 9, "name", "bold")
    for at, s in seams:
        text(at, s, 3.5, "seam")
    text(np.array([_GAP + 0.05, _GAP * 0.5 + 0.006]), "100 mm scale bar", 4, "check")
    out.append("</svg>")
    return "\n".join(out) + "\n"


def write_svg(pattern: Pattern, path, *, fit=None, width: float = 1.5) -> Path:
    """Write ``pattern`` as a true-scale SVG (millimetres) atomically; see :func:`layout`."""
    atomic_write_text(path, svg_text(layout(pattern, width=width, fit=fit)))
    return Path(path)


# -- PDF --------------------------------------------------------------------------------------
def _draw(ax, sheet: Sheet, *, text_scale: float = 1.0) -> None:
    """Draw the sheet on a matplotlib axes whose data unit is the millimetre; ``text_scale``
    shrinks the text for a reduced overview (seam labels are left out below 1)."""
    from matplotlib.collections import LineCollection, PolyCollection
    from matplotlib.patches import FancyArrowPatch, PathPatch
    from matplotlib.path import Path as MplPath

    polys, rgb = _fit_polys(sheet)
    if polys is not None:
        ax.add_collection(PolyCollection(polys * _MM, facecolors=rgb, edgecolors=rgb,
                                         linewidths=0.4, rasterized=len(rgb) > 20000))
    for p in sheet.pattern.panels:
        off = sheet.offsets[p.name]
        verts, codes = [], []
        for lp in p.loops:
            poly = (lp.polygon(64) + off) * _MM
            verts += [*poly, poly[0]]
            codes += [MplPath.MOVETO] + [MplPath.LINETO] * (len(poly) - 1) + [MplPath.CLOSEPOLY]
        ax.add_patch(PathPatch(MplPath(verts, codes), facecolor="none" if polys is not None
                               else "#f3efe6", edgecolor="black", linewidth=1.2))
    names, grains, notches, seams = _labels(sheet)
    for a, b in grains:
        ax.add_patch(FancyArrowPatch(a * _MM, b * _MM, arrowstyle="<|-|>", mutation_scale=12,
                                     color="black", lw=0.9))
    slits, cuts, lines, holes = _marks(sheet)
    ax.add_collection(LineCollection([np.array([a, b]) * _MM for a, b in notches]
                                     + [s * _MM for s in slits],
                                     colors="#c00000", linewidths=1.2))
    ax.add_collection(LineCollection([np.vstack([c, c[:1]]) * _MM for c in cuts],
                                     colors="#555555", linewidths=0.6))
    ax.add_collection(LineCollection([ln * _MM for ln in lines], colors="#1f5fa8",
                                     linewidths=0.8, linestyles=(0, (4, 2))))
    if holes:
        at = np.array(holes) * _MM
        for marker in ("o", "+"):  # a drill hole: a circle with a cross
            ax.plot(at[:, 0], at[:, 1], linestyle="none", marker=marker, markersize=7,
                    markerfacecolor="none", color="#1f5fa8", markeredgewidth=0.8)
    for at, s in names:
        ax.text(*(at * _MM), s, ha="center", va="center", fontsize=16 * text_scale,
                weight="bold")
    if text_scale >= 1.0:
        for at, s in seams:
            ax.text(*(at * _MM), s, ha="center", va="center", fontsize=6, color="#333")


def _inked_tiles(sheet: Sheet, tw: float, th: float, nx: int, ny: int) -> list[tuple[int, int]]:
    """Tiles (row, column) that some piece touches: outline samples or a tile centre inside."""
    from matplotlib.path import Path as MplPath

    pts, paths = [], []
    for p in sheet.pattern.panels:
        poly = p.outline.polygon(64) + sheet.offsets[p.name]
        seg = np.roll(poly, -1, axis=0) - poly
        n = np.maximum(1, np.ceil(np.linalg.norm(seg, axis=1) / 0.005)).astype(int)
        pts += [poly[k] + seg[k] * f[:, None] for k in range(len(poly))
                for f in [np.arange(n[k]) / n[k]]]
        paths.append(MplPath(poly))
    pts = np.concatenate(pts)
    top = sheet.size[1]
    out = []
    for j in range(ny):
        for i in range(nx):
            x0, y0 = i * tw, top - (j + 1) * th
            hit = np.any((pts[:, 0] >= x0) & (pts[:, 0] <= x0 + tw) & (pts[:, 1] >= y0)
                         & (pts[:, 1] <= y0 + th))
            centre = (x0 + 0.5 * tw, y0 + 0.5 * th)
            if hit or any(pa.contains_point(centre) for pa in paths):
                out.append((j, i))
    return out


def write_pdf(pattern: Pattern, path, *, paper: str = "a4", margin: float = 0.01, fit=None,
              width: float = 1.5) -> int:
    """Write ``pattern`` as a printable PDF of true-scale tiles; returns the number of pages.

    paper : ``"a4"`` or ``"letter"``. margin [m] around each tile's printable area. The first
    page holds the 10 cm check square (print at 100 %, no fit-to-page), the tile map and the
    piece list; the tiles follow row by row from the top left, named A1, A2, ... B1, ...;
    tiles no piece touches are left out.
    """
    plt = pyplot()
    from matplotlib.backends.backend_pdf import PdfPages
    from matplotlib.patches import Rectangle

    if paper not in PAPERS:
        raise ValueError(f"paper: expected one of {sorted(PAPERS)}, got {paper!r}")
    pw, ph = PAPERS[paper]
    if not 0.0 <= margin < 0.25 * min(pw, ph):
        raise ValueError(f"margin: expected 0 <= margin < {0.25 * min(pw, ph)} m, got {margin}")
    sheet = layout(pattern, width=width, fit=fit)
    tw, th = pw - 2 * margin, ph - 2 * margin
    nx, ny = math.ceil(sheet.size[0] / tw), math.ceil(sheet.size[1] / th)
    inch = 0.0254
    buf = io.BytesIO()
    with PdfPages(buf) as pdf:
        fig = plt.figure(figsize=(pw / inch, ph / inch))
        ax = fig.add_axes([margin / pw, margin / ph, tw / pw, th / ph])
        ax.set_xlim(0, tw * _MM)
        ax.set_ylim(0, th * _MM)
        ax.set_axis_off()
        ax.add_patch(Rectangle((0, th * _MM - 120), 100, 100, fill=False, lw=1.0))
        ax.text(50, th * _MM - 70, "10 cm x 10 cm\ncheck square", ha="center", va="center",
                fontsize=10)
        tiles = _inked_tiles(sheet, tw, th, nx, ny)
        lines = [f"{pattern.name}: {len(pattern.panels)} pieces, {len(tiles)} {paper} tiles "
                 f"on a {nx} x {ny} grid",
                 "Print at 100 % (no page scaling); measure the square.",
                 "Tiles run left to right (1, 2, ...) and top to bottom (A, B, ...).",
                 "Pieces: " + ", ".join(p.name for p in pattern.panels)]
        ax.text(0, th * _MM - 140, "\n".join(lines), va="top", fontsize=9)
        scale = min(tw * _MM / sheet.size[0], (th * _MM - 200) / sheet.size[1]) / _MM
        mini = fig.add_axes([margin / pw, margin / ph, sheet.size[0] * scale / pw,
                             sheet.size[1] * scale / ph])
        mini.set_xlim(0, sheet.size[0] * _MM)
        mini.set_ylim(0, sheet.size[1] * _MM)
        mini.set_axis_off()
        _draw(mini, sheet, text_scale=0.4)
        for j, i in tiles:
            mini.add_patch(Rectangle((i * tw * _MM, sheet.size[1] * _MM - (j + 1) * th * _MM),
                                     tw * _MM, th * _MM, fill=False, ls="--", lw=0.5,
                                     color="#0060c0"))
            mini.text((i + 0.5) * tw * _MM, sheet.size[1] * _MM - (j + 0.5) * th * _MM,
                      f"{chr(65 + j % 26)}{i + 1}", color="#0060c0", ha="center",
                      fontsize=8)
        pdf.savefig(fig)
        plt.close(fig)
        for j, i in tiles:
            fig = plt.figure(figsize=(pw / inch, ph / inch))
            ax = fig.add_axes([margin / pw, margin / ph, tw / pw, th / ph])
            y1 = sheet.size[1] - j * th
            ax.set_xlim(i * tw * _MM, (i + 1) * tw * _MM)
            ax.set_ylim((y1 - th) * _MM, y1 * _MM)
            ax.set_xticks([])
            ax.set_yticks([])
            for s in ax.spines.values():
                s.set_linewidth(0.4)
                s.set_color("#0060c0")
            _draw(ax, sheet)
            fig.text(0.5, 1 - 0.6 * margin / ph, f"{pattern.name}  tile "
                     f"{chr(65 + j % 26)}{i + 1}  (row {j + 1}/{ny}, column {i + 1}/{nx})",
                     ha="center", va="center", fontsize=7, color="#0060c0")
            pdf.savefig(fig)
            plt.close(fig)
    atomic_write_bytes(path, buf.getvalue())
    return 1 + len(tiles)
