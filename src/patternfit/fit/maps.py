"""Maps of the fit measures: body–garment gap and clothing pressure per vertex, on the 3D
garment (front and back) and on the flat pattern, like the area-change maps of
:mod:`patternfit.fit.pictures`."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..figures import pyplot
from ..mesh.garment import GarmentMesh
from .pictures import flat_layout, render_views, title_colour, wrapped


@dataclass(frozen=True)
class MeasureScale:
    """How one measure maps to colour: ``label`` (with its unit), the value range
    ``(low, high)`` the colours span (clipped beyond), a matplotlib colormap name and
    reference ``marks`` ((value, label) drawn on the colour bar)."""

    label: str
    low: float
    high: float
    cmap: str
    marks: tuple = ()

    def colors(self, values) -> np.ndarray:
        """(k, 3) RGB in [0, 1] of ``values`` (k,)."""
        from matplotlib import colormaps
        v = np.clip((np.asanyarray(values, dtype=np.float64) - self.low)
                    / (self.high - self.low), 0.0, 1.0)
        return colormaps[self.cmap](np.nan_to_num(v))[:, :3]


def gap_scale(high_mm: float = 50.0) -> MeasureScale:
    """Gap [mm]: dark where the cloth rests on the body, light where it stands off."""
    return MeasureScale("gap to the body [mm]", 0.0, high_mm, "viridis")


def pressure_scale(comfort_kpa: float = 1.3, max_kpa: float = 2.0) -> MeasureScale:
    """Pressure [kPa] from 0 to 1.25 × the daily-wear maximum, the comfortable and the
    maximum pressure marked."""
    return MeasureScale("clothing pressure [kPa]", 0.0, 1.25 * max_kpa, "inferno_r",
                        ((comfort_kpa, "comfortable"), (max_kpa, "max daily")))


def _colorbar(fig, ax, scale: MeasureScale) -> None:
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize
    sm = ScalarMappable(norm=Normalize(scale.low, scale.high), cmap=colormaps[scale.cmap])
    bar = fig.colorbar(sm, ax=ax, fraction=0.04, pad=0.02)
    marks = ", ".join(f"{v:g} {text}" for v, text in scale.marks)
    bar.set_label(scale.label + (f"\nblue lines: {marks}" if marks else ""), fontsize=8)
    bar.ax.tick_params(labelsize=7)
    for value, _ in scale.marks:  # named in the label: text beside the bar hid the ticks
        bar.ax.axhline(value, color="#1f5fbf", lw=1.5)


def plot_measure_maps(mesh: GarmentMesh, positions, values, scale: MeasureScale, stem, *,
                      body=None, title: str | None = None,
                      failed: str | None = None) -> list[Path]:
    """Write ``<stem>_3d.png`` (the garment coloured by ``values`` (n,) per vertex, front
    and back, the body grey) and ``<stem>_2d.png`` (the flat pattern, each triangle the
    mean of its corners). ``positions`` (n, 3) [m]; ``body`` optional (vertices, faces);
    ``failed``: why the drape failed (the titles in red: the map shows why, not a fit).
    Returns the two paths."""
    plt = pyplot()
    from matplotlib.collections import PolyCollection

    v = np.asanyarray(values, dtype=np.float64)
    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    head = f"{title} — " if title else ""
    front, back = render_views(positions, mesh.triangles, scale.colors(v), body=body)
    fig, axes = plt.subplots(1, 2, figsize=(11, 7.2))
    for ax, img, label in zip(axes, (front, back), ("front", "back")):
        ax.imshow(img)
        ax.set_title(label, fontsize=10)
        ax.axis("off")
    fig.suptitle(wrapped(f"{head}{scale.label}", 11, 11), fontsize=11,
                 color=title_colour(failed))
    _colorbar(fig, axes[1], scale)
    path3 = stem.with_name(stem.name + "_3d.png")
    fig.savefig(path3, dpi=100)
    plt.close(fig)

    xy = flat_layout(mesh)
    width, height = np.ptp(xy[:, 0]), np.ptp(xy[:, 1])
    size = (min(16.0, 3.0 + 10.0 * width / max(width, height)),
            8.0 * height / max(width, height) + 1.5)
    fig, ax = plt.subplots(figsize=size)
    colors = scale.colors(v[mesh.triangles].mean(axis=1))
    ax.add_collection(PolyCollection(xy[mesh.triangles], facecolors=colors,
                                     edgecolors=colors, linewidths=0.3))
    for loop in range(len(mesh.loop_panel)):
        ids = mesh.boundary_vertices[mesh.boundary_loop == loop]
        ring = xy[np.append(ids, ids[0])]
        ax.plot(ring[:, 0], ring[:, 1], color="k", lw=0.8)
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("m")
    # (over the axes, beside the colour bar: narrower than the figure)
    ax.set_title(wrapped(f"{head}{scale.label} on the flat pattern", 0.7 * size[0], 10),
                 fontsize=10, color=title_colour(failed))
    _colorbar(fig, ax, scale)
    fig.tight_layout()
    path2 = stem.with_name(stem.name + "_2d.png")
    fig.savefig(path2, dpi=120)
    plt.close(fig)
    return [path3, path2]
