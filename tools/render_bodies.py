"""Render the built-in bodies, front and side, to ``docs/figures/bodies.png``, or a body
set to ``docs/figures/bodies_<set>.png`` (``python tools/render_bodies.py population``;
dev only)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pyvista as pv

from patternfit.api import list_body_sets
from patternfit.body import list_bodies, load_body

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures" / "bodies.png"


def main(body_set: str | None = None) -> None:
    order = ["thin", "average", "heavy"]
    names = list_body_sets()[body_set] if body_set else sorted(
        list_bodies(), key=lambda n: (n.split("_")[0], order.index(n.split("_")[1])
                                      if n.split("_")[-1] in order else 9))
    out = OUT.with_name(f"bodies_{body_set}.png") if body_set else OUT
    pl = pv.Plotter(off_screen=True, window_size=(300 * len(names), 1400), shape=(2, 1))
    for row, (view, dx) in enumerate((("xy", np.array([1.15, 0, 0])),
                                      ("zy", np.array([0, 0, 0.75])))):
        pl.subplot(row, 0)
        for n, name in enumerate(names):
            body = load_body(name)
            faces = np.hstack([np.full((len(body.faces), 1), 3), body.faces]).ravel()
            pl.add_mesh(pv.PolyData(body.vertices + n * dx, faces), color="tan",
                        smooth_shading=True)
            m = body.measurements
            label = (f"{name}, waist {m['waist']:.2f} m" if not body_set else
                     f"{name}\n{m['bust']:.2f}/{m['waist']:.2f}/{m['hip']:.2f}")
            pl.add_point_labels([body.vertices.mean(axis=0) * [1, 0, 1] + n * dx + [0, -0.12, 0]],
                                [label], font_size=16, shape=None, show_points=False)
        getattr(pl, f"view_{view}")()
        pl.camera.zoom(2.4 * len(names) / 6 if body_set else 2.4)
    out.parent.mkdir(parents=True, exist_ok=True)
    pl.screenshot(out)
    print(out)


if __name__ == "__main__":
    main(*sys.argv[1:2])
