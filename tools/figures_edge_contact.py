"""docs/figures/edge_contact.png: a coarse coat at rest with body contact at its vertices
only and with the edge contact points (``SolverSettings.edge_contact``), the body in grey:
where it shows through the cloth, the body passes between the cloth's vertices.

Close-ups of the shoulders from the front and the back, and the count of
edges through the body (``checks.edges_in_body``). Run ``python tools/figures_edge_contact.py
[--garment coat] [--body male_average] [--triangles 1500] [--size M] [--out PATH]``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from patternfit.body.builtin import load_body
from patternfit.figures import pyplot
from patternfit.mesh import mesh_pattern
from patternfit.pattern.library import build
from patternfit.sim.drape import drape
from patternfit.sim.solver import SolverSettings

from figures_crossings import render  # (tools/ is the script's folder)

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures" / "edge_contact.png"
CLOTH = (0.35, 0.55, 0.80)
#: close-ups: (name, focus as shares of the body's height (x, y, z from its bounding box
#: centre), camera direction from the focus, up vector)
VIEWS = (("right shoulder, front", (-0.11, 0.82, 0.0), (-0.3, 0.2, 1.0), (0.0, 1.0, 0.0)),
         ("left shoulder, front", (0.11, 0.82, 0.0), (0.3, 0.2, 1.0), (0.0, 1.0, 0.0)),
         ("right shoulder, back", (-0.11, 0.82, 0.0), (-0.3, 0.2, -1.0), (0.0, 1.0, 0.0)))


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--garment", default="coat")
    ap.add_argument("--body", default="male_average")
    ap.add_argument("--triangles", type=int, default=1500)
    ap.add_argument("--size", default="M")
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args()
    body = load_body(args.body)
    bm = body.to_trimesh()
    lo, hi = bm.bounds
    centre, height = 0.5 * (lo + hi), float(hi[1] - lo[1])
    pattern = build(args.garment, args.size)
    mesh = mesh_pattern(pattern, triangles=args.triangles)
    plt = pyplot()
    fig, axes = plt.subplots(2, len(VIEWS), figsize=(4.2 * len(VIEWS), 9.0), squeeze=False)
    for row, spacing in zip(axes, (0.0, SolverSettings().edge_contact)):
        d = drape(pattern, mesh, body, "cotton_shirting",
                  settings=SolverSettings(edge_contact=spacing))
        c = d.checks
        for ax, (name, share, direction, up) in zip(row, VIEWS):
            focus = np.array([centre[0] + share[0] * height, lo[1] + share[1] * height,
                              centre[2] + share[2] * height])
            rgb = np.tile(CLOTH, (len(mesh.triangles), 1))
            ax.imshow(render(d.positions, mesh.triangles, rgb, focus, 0.45, direction, up,
                             body=(bm.vertices, bm.faces)))
            ax.set_title(name, fontsize=9)
            ax.axis("off")
        where = "vertices only" if not spacing else f"also inside edges, {spacing * 100:g} cm"
        row[0].text(-0.05, 0.5, f"contact: {where}\n{c.edges_in_body} edges through the "
                    f"body\n{c.inside_vertices} vertices inside\n"
                    f"{'at rest' if c.equilibrium else 'not at rest'}",
                    transform=row[0].transAxes, ha="right", va="center", fontsize=10)
    fig.suptitle(f"{args.garment} {args.size} on {args.body}, {mesh.n_triangles} triangles, "
                 "cotton shirting: grey is body showing through the cloth", fontsize=11)
    fig.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=90)
    print(args.out)


if __name__ == "__main__":
    main()
