"""docs/figures/crossings_untangled.png: the trousers' crotch at rest without and with the
solver's untangling (``SolverSettings.untangle``), crossed triangles in red.

Close-ups from the front, from below and from the back, each panel in its own colour.
Run ``python tools/figures_crossings.py [--garment trousers] [--body male_thin]
[--triangles 2000] [--size M] [--out PATH]``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib
import numpy as np

from patternfit.body.builtin import load_body
from patternfit.mesh import mesh_pattern
from patternfit.pattern.library import build
from patternfit.sim.kernels import crossed_pairs
from patternfit.sim.drape import drape
from patternfit.sim.solver import SolverSettings

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures" / "crossings_untangled.png"
PANEL_RGB = np.array([[0.35, 0.55, 0.80], [0.55, 0.75, 0.45], [0.85, 0.72, 0.40],
                      [0.62, 0.50, 0.75], [0.55, 0.55, 0.55]])
#: camera directions (from the focus) of the close-ups, and their up vectors
VIEWS = {"front, from below": ((0.0, -0.6, 1.0), (0.0, 1.0, 0.0)),
         "from below": ((0.0, -1.0, 0.05), (0.0, 0.0, 1.0)),
         "back, from below": ((0.0, -0.6, -1.0), (0.0, 1.0, 0.0))}


def render(x, tris, rgb, focus, distance, direction, up, size=(420, 420), body=None):
    """RGB image of the triangles ``tris`` at ``x`` [m], one colour (3,) per triangle in
    ``rgb``, seen from ``distance`` [m] along ``direction`` from ``focus``, edges drawn;
    ``body``: (vertices (k, 3) [m], faces (f, 3)) drawn grey and smooth with them."""
    import pyvista as pv

    pv.OFF_SCREEN = True
    mesh = pv.PolyData(x, np.hstack([np.full((len(tris), 1), 3), tris]).ravel())
    mesh.cell_data["rgb"] = (rgb * 255).astype(np.uint8)
    pl = pv.Plotter(off_screen=True, window_size=size)
    pl.set_background("white")
    if body is not None:
        faces = np.hstack([np.full((len(body[1]), 1), 3), body[1]]).ravel()
        pl.add_mesh(pv.PolyData(np.asarray(body[0], float), faces), color=(0.75, 0.72, 0.70),
                    smooth_shading=True)
    pl.add_mesh(mesh, scalars="rgb", rgb=True, show_edges=True, edge_color=(0.2, 0.2, 0.2),
                line_width=0.5)
    d = np.asarray(direction, float)
    pl.camera.focal_point = focus
    pl.camera.position = focus + distance * d / np.linalg.norm(d)
    pl.camera.up = up
    pl.camera.view_angle = 30.0
    img = pl.screenshot(return_img=True)
    pl.close()
    return img


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--garment", default="trousers")
    ap.add_argument("--body", default="male_thin")
    ap.add_argument("--triangles", type=int, default=2000)
    ap.add_argument("--size", default="M")
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args()
    body = load_body(args.body)
    pattern = build(args.garment, args.size)
    mesh = mesh_pattern(pattern, triangles=args.triangles)
    runs = []
    for untangle in (False, True):
        d = drape(pattern, mesh, body, "cotton", settings=SolverSettings(untangle=untangle))
        # one row per welded vertex, so that triangles meeting across a seam are neighbours
        vmap = d.result.vertex_map
        x = np.zeros((vmap.max() + 1, 3))
        x[vmap] = d.positions
        tris = vmap[mesh.triangles]
        crossed = crossed_pairs(x, tris, d.solver.terms.edge_length, np.arange(len(x)))
        runs.append((untangle, d, x, tris, np.unique(crossed.ravel())))
    # both close-ups look at the crossings of the run without untangling (or the crotch)
    x0, tris0, bad0 = runs[0][2], runs[0][3], runs[0][4]
    focus = (x0[tris0[bad0]].reshape(-1, 3).mean(axis=0) if len(bad0)
             else x0[np.argmin(np.abs(x0[:, 0]) + x0[:, 1])])
    fig, axes = plt.subplots(2, len(VIEWS), figsize=(4.2 * len(VIEWS), 9.0), squeeze=False)
    for row, (untangle, d, x, tris, bad) in zip(axes, runs):
        rgb = PANEL_RGB[mesh.triangle_panel % len(PANEL_RGB)].copy()
        rgb[bad] = (0.9, 0.1, 0.1)
        c = d.checks
        for ax, (name, (direction, up)) in zip(row, VIEWS.items()):
            ax.imshow(render(x, tris, rgb, focus, 0.3, direction, up))
            ax.set_title(f"{name}", fontsize=9)
            ax.axis("off")
        row[0].text(-0.05, 0.5, f"untangle {'on' if untangle else 'off'}\n"
                    f"{c.self_intersections} crossed pairs (red)\n"
                    f"{'at rest' if c.equilibrium else 'not at rest'}, rms "
                    f"{c.residual_rms:.3f}", transform=row[0].transAxes, ha="right",
                    va="center", fontsize=10)
    fig.suptitle(f"{args.garment} {args.size} on {args.body}, {mesh.n_triangles} triangles, "
                 "cotton: the crotch at rest", fontsize=11)
    fig.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=90)
    print(args.out)


if __name__ == "__main__":
    main()
