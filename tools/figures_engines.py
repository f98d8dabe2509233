"""docs/figures/drape_engines.png: one garment draped by both engines, side by side.

Static equilibrium, Newton Style3D from the sewn placement, and Newton started at the static
equilibrium (``--from-static``), front view close up, shaded so that folds show.
Run ``python tools/figures_engines.py [--garment skirt] [--triangles 8000]``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib
import numpy as np

from patternfit.body.builtin import load_body
from patternfit.fit import FitEvaluator
from patternfit.mesh import mesh_pattern
from patternfit.pattern.library import build
from patternfit.sim.drape import drape
from patternfit.sim.newton_engine import mean_dihedral, newton_drape

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures" / "drape_engines.png"


def render(x, tris, body, centre, extent, size=(600, 800)):
    import pyvista as pv

    pv.OFF_SCREEN = True
    pl = pv.Plotter(off_screen=True, window_size=size)
    pl.set_background("white")
    bf = np.hstack([np.full((len(body.faces), 1), 3), body.faces]).ravel()
    pl.add_mesh(pv.PolyData(np.asarray(body.vertices, float), bf), color=(0.82, 0.80, 0.78),
                smooth_shading=True)
    gf = np.hstack([np.full((len(tris), 1), 3), tris]).ravel()
    pl.add_mesh(pv.PolyData(x, gf), color=(0.35, 0.55, 0.80), smooth_shading=True,
                specular=0.3)
    pl.camera.focal_point = centre
    pl.camera.position = centre + np.array([0.6, 0.25, 3.0]) * extent
    pl.camera.up = (0.0, 1.0, 0.0)
    pl.camera.view_angle = 24.0
    img = pl.screenshot(return_img=True)
    pl.close()
    return img


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--garment", default="skirt")
    ap.add_argument("--body", default="female_average")
    ap.add_argument("--triangles", type=int, default=8000)
    args = ap.parse_args()
    body = load_body(args.body)
    pattern = build(args.garment, "M")
    mesh = mesh_pattern(pattern, triangles=args.triangles)
    fe = FitEvaluator(mesh)
    static = drape(pattern, mesh, body, "cotton")
    runs = [("static engine", static),
            ("Newton Style3D", newton_drape(pattern, mesh, body, "cotton")),
            ("Newton --from-static", newton_drape(pattern, mesh, body, "cotton",
                                                   from_static=static))]
    vmap = static.result.vertex_map
    tris = vmap[mesh.triangles]
    x0 = static.positions
    centre = 0.5 * (x0.min(axis=0) + x0.max(axis=0))
    extent = float(np.ptp(x0, axis=0).max())
    fig, axes = plt.subplots(1, 3, figsize=(13, 6.4))
    for ax, (name, d) in zip(axes, runs):
        x = np.zeros((vmap.max() + 1, 3))
        x[d.result.vertex_map] = d.positions
        ax.imshow(render(x, tris, body, centre, extent))
        c = d.checks
        ax.set_title(f"{name}\nϖ {fe(d.positions).fitting_ratio * 100:.2f}%, mean dihedral "
                     f"{np.degrees(mean_dihedral(x, tris)):.1f}°, {c.inside_vertices} inside, "
                     f"{d.seconds:.0f} s", fontsize=9)
        ax.axis("off")
    fig.suptitle(f"{args.garment} M, {mesh.n_triangles} triangles, cotton shirting, "
                 f"{args.body} (2-core CPU)", fontsize=11)
    fig.tight_layout()
    fig.savefig(OUT, dpi=110)
    print(OUT)


if __name__ == "__main__":
    main()
