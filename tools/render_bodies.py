"""Render the built-in bodies, front and side, to ``docs/figures/bodies.png`` (dev only)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pyvista as pv

from patternfit.body import list_bodies, load_body

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures" / "bodies.png"


def main() -> None:
    order = ["thin", "average", "heavy"]
    names = sorted(list_bodies(), key=lambda n: (n.split("_")[0], order.index(n.split("_")[1])
                   if n.split("_")[-1] in order else 9))
    pl = pv.Plotter(off_screen=True, window_size=(2400, 1600), shape=(2, 1))
    for row, (view, dx) in enumerate((("xy", np.array([1.15, 0, 0])),
                                      ("zy", np.array([0, 0, 0.75])))):
        pl.subplot(row, 0)
        for n, name in enumerate(names):
            body = load_body(name)
            faces = np.hstack([np.full((len(body.faces), 1), 3), body.faces]).ravel()
            pl.add_mesh(pv.PolyData(body.vertices + n * dx, faces), color="tan",
                        smooth_shading=True)
            label = f"{name}, waist {body.measurements['waist']:.2f} m"
            pl.add_point_labels([body.vertices.mean(axis=0) * [1, 0, 1] + n * dx + [0, -0.12, 0]],
                                [label], font_size=16, shape=None, show_points=False)
        getattr(pl, f"view_{view}")()
        pl.camera.zoom(2.4)
    OUT.parent.mkdir(parents=True, exist_ok=True)
    pl.screenshot(OUT)
    print(OUT)


if __name__ == "__main__":
    main()
