"""Pictures of the fit: the flat 2D colour map (SVG, PNG) and the 3D garment (PNG, front and
back, rendered off-screen on the CPU with pyvista/VTK so that hidden parts stay hidden)."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np

from ..figures import pyplot
from ..mesh.garment import GarmentMesh
from .colormap import FitScale, vertex_values
from .metrics import FitResult

_GAP = 0.08  # space between panels in the flat layout [m]

# matplotlib and pyvista/VTK are imported inside the functions that draw: they are heavy
# (and matplotlib's backend is chosen first), and only pictures need them


def flat_layout(mesh: GarmentMesh) -> np.ndarray:
    """Panels side by side, left to right, bottoms aligned: (n, 2) float [m]."""
    out = np.empty_like(mesh.vertices)
    x0 = 0.0
    for i in range(len(mesh.panel_names)):
        ids = mesh.panel_vertices(i)
        v = mesh.vertices[ids]
        out[ids] = v - [v[:, 0].min() - x0, v[:, 1].min()]
        x0 += np.ptp(v[:, 0]) + _GAP
    return out


def _legend(ax, scale: FitScale) -> None:
    from matplotlib.patches import Patch
    handles = [Patch(facecolor=rgb, edgecolor="0.3", label=label)
               for _, rgb, label in reversed(scale.legend())]
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8,
              title="S3/S2 − 1", title_fontsize=8, frameon=False)


def picture_title(fit: FitResult, title: str | None, failed: str | None = None) -> str:
    """The picture's title: ϖ, or "FAILED: <reason>" for a drape that failed its checks
    (whose ϖ is no fit)."""
    head = f"{title} — " if title else ""
    if failed:
        return "\n".join(textwrap.wrap(f"{head}FAILED: {failed} (ϖ is not a fit)", 110))
    return (f"{head}fitting ratio ϖ = {fit.fitting_ratio * 100:.2f}%  "
            f"(symmetric {fit.fitting_ratio_symmetric * 100:.2f}%)")


def title_colour(failed: str | None) -> str:
    """Red for the title of a failed drape's picture, else black."""
    return "#c00000" if failed else "black"


def wrapped(text: str, width_in: float, fontsize: float) -> str:
    """``text`` wrapped to lines that fit a figure ``width_in`` [inch] wide at ``fontsize``
    [pt] (a failed drape's title on the one-girth sections picture, 3.2 inches, was cut at
    both sides, "FAILED" out of sight)."""
    chars = max(20, int(width_in * 72 / (0.6 * fontsize)))
    return "\n".join(textwrap.wrap(" ".join(text.split()), chars))


#: the colour of a garment whose drape failed its checks: no fit colour may suggest a fit
FAILED_GREY = np.array([0.62, 0.62, 0.62])


def fit_colours(scale: FitScale, values, failed: str | None) -> np.ndarray:
    """(k, 3) fit colours of ``values``, or all grey for a failed drape."""
    if failed:
        return np.broadcast_to(FAILED_GREY, (len(values), 3)).copy()
    return scale.colors(values)


def plot_flat_map(mesh: GarmentMesh, fit: FitResult, paths, *, scale: FitScale | None = None,
                  title: str | None = None, show_mesh: bool = False,
                  failed: str | None = None) -> list[Path]:
    """Draw the flat pattern coloured by area change, with outlines, names and a legend.

    ``paths`` is one path or a list; each is written in the format of its ending (.png, .svg,
    .pdf). ``failed``: why the drape failed its checks; the title then says
    "FAILED: <failed>" in red instead of ϖ. Returns the paths written.
    """
    plt = pyplot()
    from matplotlib.collections import PolyCollection

    scale = scale or FitScale(band=fit.thresholds[0])
    xy = flat_layout(mesh)
    width, height = np.ptp(xy[:, 0]), np.ptp(xy[:, 1])
    fig_w = min(16.0, 3.0 + 10.0 * width / max(width, height))
    fig, ax = plt.subplots(figsize=(fig_w, 8.0 * height / max(width, height) + 1.5))
    colors = fit_colours(scale, fit.area_change, failed)
    ax.add_collection(PolyCollection(xy[mesh.triangles], facecolors=colors,
                                     edgecolors="0.35" if show_mesh else colors,
                                     linewidths=0.15 if show_mesh else 0.3))
    for loop in range(len(mesh.loop_panel)):
        ids = mesh.boundary_vertices[mesh.boundary_loop == loop]
        ring = xy[np.append(ids, ids[0])]
        ax.plot(ring[:, 0], ring[:, 1], color="k", lw=0.8)
    for i, name in enumerate(mesh.panel_names):
        ids = mesh.panel_vertices(i)
        c = xy[ids].mean(axis=0)
        label = f"{name}\n(failed)" if failed else f"{name}\nϖ {fit.panel_ratio[i] * 100:.1f}%"
        ax.text(c[0], c[1], label, ha="center", va="center", fontsize=9, color="k")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("m")
    ax.set_title(picture_title(fit, title, failed), fontsize=10, color=title_colour(failed))
    if not failed:
        _legend(ax, scale)
    fig.tight_layout()
    written = []
    for p in ([paths] if isinstance(paths, (str, Path)) else paths):
        fig.savefig(p, dpi=150)
        written.append(Path(p))
    plt.close(fig)
    return written


def render_views(positions, triangles, vertex_rgb, *, body=None, size=(700, 900)) -> list:
    """Front and back renderings of a coloured garment (and the body, grey), as RGB arrays.

    Parameters
    ----------
    positions : (n, 3) float
        Garment vertices [m], y up, the body facing +z.
    triangles : (m, 3) int
    vertex_rgb : (n, 3) float in [0, 1]
    body : tuple of ((k, 3) float, (f, 3) int), optional
        Body vertices [m] and faces.
    """
    import pyvista as pv
    from vtkmodules.vtkCommonCore import vtkLogger

    # with no X display VTK falls back to off-screen rendering, after a warning worth nothing
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
    pv.OFF_SCREEN = True
    x = np.asanyarray(positions, dtype=np.float64)
    faces = np.hstack([np.full((len(triangles), 1), 3), triangles]).ravel()
    garment = pv.PolyData(x, faces)
    garment.point_data["rgb"] = (np.clip(vertex_rgb, 0, 1) * 255).astype(np.uint8)
    pts = x if body is None else np.vstack([x, body[0]])
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    extent = float(np.ptp(pts, axis=0).max())
    images = []
    for direction in (+1.0, -1.0):
        pl = pv.Plotter(off_screen=True, window_size=size)
        pl.set_background("white")
        if body is not None:
            bfaces = np.hstack([np.full((len(body[1]), 1), 3), body[1]]).ravel()
            pl.add_mesh(pv.PolyData(np.asanyarray(body[0], dtype=np.float64), bfaces),
                        color=(0.82, 0.80, 0.78), smooth_shading=True)
        pl.add_mesh(garment, scalars="rgb", rgb=True, smooth_shading=True)
        pl.camera.focal_point = centre
        pl.camera.position = centre + np.array([0.0, 0.0, direction * 3.2 * extent])
        pl.camera.up = (0.0, 1.0, 0.0)
        pl.camera.view_angle = 22.0
        images.append(pl.screenshot(return_img=True))
        pl.close()
    return images


def plot_3d_map(positions, mesh: GarmentMesh, fit: FitResult, path, *,
                scale: FitScale | None = None, body=None, title: str | None = None,
                failed: str | None = None) -> Path:
    """PNG of the 3D garment coloured by area change, front and back, with the legend;
    ``failed`` (why the drape failed its checks) replaces ϖ in the title, in red."""
    plt = pyplot()

    scale = scale or FitScale(band=fit.thresholds[0])
    values = vertex_values(mesh.triangles, fit.area_change, mesh.n_vertices, fit.area_2d)
    front, back = render_views(positions, mesh.triangles, fit_colours(scale, values, failed),
                               body=body)
    fig, axes = plt.subplots(1, 2, figsize=(11, 7.2))
    for ax, img, label in zip(axes, (front, back), ("front", "back")):
        ax.imshow(img)
        ax.set_title(label, fontsize=10)
        ax.axis("off")
    fig.suptitle(picture_title(fit, title, failed), fontsize=11, color=title_colour(failed))
    if not failed:  # a legend of fit colours beside a grey, failed garment would mislead
        _legend(axes[1], scale)
    fig.tight_layout(rect=(0, 0, 1, 0.96))  # room for the suptitle above "front"/"back"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)


def plot_sections(sections: dict, path, *, title: str | None = None,
                  failed: str | None = None) -> Path:
    """Draw each girth's section, seen from above (bust, waist, hip horizontal: x across,
    z front up; a bicep in the plane across the arm): the body's section (grey, filled
    hull), the garment's section points (blue dots) and its convex hull (blue line),
    titled with the girth's ease in cm ("not all around" where the garment leaves a gap);
    girths the garment does not reach are left out.

    ``sections``: name → :class:`~patternfit.fit.measures.Section`; ``failed``: why the
    drape failed (the title in red). Returns the path."""
    plt = pyplot()

    path = Path(path)
    # the girths the garment reaches at all (a skirt has no bust to show)
    names = [k for k, s in sections.items() if len(s.garment)] or ["none"]
    cols = min(len(names), 4)
    rows = -(-len(names) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 3.4 * rows + 0.4), squeeze=False)
    for ax in axes.ravel():
        ax.set_axis_off()
    for ax, name in zip(axes.ravel(), names):
        s = sections.get(name)
        ax.set_axis_on()
        ax.set_aspect("equal")
        ax.tick_params(labelsize=6)
        if s is None:
            ax.set_title("no girth measured", fontsize=9)
            continue
        if len(s.body_hull):
            ax.fill(100 * s.body_hull[:, 0], 100 * s.body_hull[:, 1], color="0.82",
                    edgecolor="0.45", lw=0.8, label="body")
        if len(s.body):
            ax.plot(100 * s.body[:, 0], 100 * s.body[:, 1], ".", color="0.35", ms=1)
        if len(s.garment):
            ax.plot(100 * s.garment[:, 0], 100 * s.garment[:, 1], ".", color="#1f5fbf", ms=2)
        if len(s.garment_hull):
            ax.plot(100 * s.garment_hull[:, 0], 100 * s.garment_hull[:, 1], "-",
                    color="#1f5fbf", lw=1, label="garment")
        head = (f"ease {s.ease_cm:+.1f} cm" if s.ease_cm is not None
                else "not all around")
        if s.below_cm:
            head += f", cut {s.below_cm:.0f} cm lower"
        ax.set_title(f"{name}: {head}\nbody {s.body_cm:.1f} cm", fontsize=9,
                     color="black" if s.covered else "0.45")
        ax.set_xlabel("cm", fontsize=7)
    fig.suptitle(wrapped(f"{title + ' — ' if title else ''}girth sections, top view",
                         3.2 * cols, 10), fontsize=10, color=title_colour(failed))
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
