"""Reproduce the paper's coordinate figures (Fig. 3/4, 7, 13, 14) as PNGs in docs/figures/.

Run ``python tools/figures_coords.py``. Fig. 3/4: one node's maximum entropy coordinate
under three priors on a garment outline and on a concave polygon; Fig. 7: an enhanced mean
value coordinate on a star; Fig. 13: a rectangle mesh whose internal quadrilateral moves by
one unit in x and y (enhanced MVC); Fig. 14: a boundary modification (MEC, bisector prior).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import triangle as tr  # noqa: E402

from patternfit.coords import max_entropy_coordinates, mean_value_coordinates  # noqa: E402
from patternfit.edit import move_point, update_mesh  # noqa: E402
from patternfit.mesh import mesh_pattern  # noqa: E402
from patternfit.pattern import Edge, Loop, Panel, Pattern  # noqa: E402
from patternfit.pattern.library import build  # noqa: E402

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures"


def _fine(poly, area):
    n = len(poly)
    seg = np.stack([np.arange(n), (np.arange(n) + 1) % n], axis=1)
    t = tr.triangulate({"vertices": poly, "segments": seg}, f"pq30a{area}Q")
    return t["vertices"], t["triangles"]


def _field(ax, poly, node, values, verts, tris, title):
    im = ax.tripcolor(verts[:, 0], verts[:, 1], tris, values, shading="gouraud",
                      cmap="viridis", vmin=0, vmax=1)
    closed = np.vstack([poly, poly[:1]])
    ax.plot(closed[:, 0], closed[:, 1], "k-", lw=0.8)
    ax.plot(*poly[node], "o", ms=9, mfc="none", mec="red", mew=2)
    ax.set_title(title, fontsize=10)
    ax.set_aspect("equal")
    ax.axis("off")
    return im


def fig_priors(name, poly, node, area):
    verts, tris = _fine(poly, area)
    fig, axes = plt.subplots(1, 3, figsize=(12, 4.4))
    for ax, prior, label in zip(axes, ("edge", "uniform", "bisector"),
                                ("edge prior (Hormann–Sukumar)", "uniform prior",
                                 "angle-bisector prior (ours, product form)")):
        w = max_entropy_coordinates(poly, verts, prior=prior)
        im = _field(ax, poly, node, w[:, node], verts, tris, label)
    fig.colorbar(im, ax=axes, shrink=0.7, label="coordinate value")
    fig.suptitle(f"MEC basis function of the red node: {name}")
    fig.savefig(OUT / f"coords_{name.split()[0].lower()}_priors.png", dpi=110,
                bbox_inches="tight")
    plt.close(fig)


def star(n=5, inner=0.45):
    t = np.linspace(0, 2 * np.pi, 2 * n, endpoint=False) + np.pi / 2
    r = np.where(np.arange(2 * n) % 2 == 0, 1.0, inner)
    return np.stack([r * np.cos(t), r * np.sin(t)], axis=1)


def fig7():
    poly = star()
    node = 1  # a concave vertex
    verts, tris = _fine(poly, 0.0004)
    w = mean_value_coordinates([poly], verts)[:, node]
    fig, ax = plt.subplots(figsize=(5.5, 5))
    im = _field(ax, poly, node, w, verts, tris, "enhanced MVC of a concave vertex")
    for i in range(len(poly)):   # the lines through consecutive nodes (eq. 19 territory)
        a, b = poly[i], poly[(i + 1) % len(poly)]
        ax.plot(*np.stack([a - 2 * (b - a), b + 2 * (b - a)]).T, ":", c="w", lw=0.6)
    ax.set_xlim(-1.05, 1.05)
    ax.set_ylim(-1.0, 1.1)
    fig.colorbar(im, ax=ax, shrink=0.8)
    fig.savefig(OUT / "coords_fig7_star_mvc.png", dpi=110, bbox_inches="tight")
    plt.close(fig)


def _mesh_pair(m0, m1, title0, title1, file, highlight=None):
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
    for ax, m, title in zip(axes, (m0, m1), (title0, title1)):
        ax.triplot(m.vertices[:, 0], m.vertices[:, 1], m.triangles, lw=0.5, c="0.35")
        b = m.boundary_vertices
        if highlight is not None:
            ax.plot(*m.vertices[b[~highlight]].T, ".", c="red", ms=4)
            ax.plot(*m.vertices[b[highlight]].T, "o", c="royalblue", ms=4)
        ax.set_title(title, fontsize=10)
        ax.set_aspect("equal")
        ax.axis("off")
    fig.savefig(OUT / file, dpi=110, bbox_inches="tight")
    plt.close(fig)


def fig13():
    outer = Loop("outline", (Edge.line("b", (0, 0), (20, 0)), Edge.line("r", (20, 0), (20, 12)),
                             Edge.line("t", (20, 12), (0, 12)), Edge.line("l", (0, 12), (0, 0))))
    quad = [(3, 6), (6, 6), (6, 9), (3, 9)]
    inner = Loop("quad", tuple(Edge.line(f"q{i}", quad[i], quad[(i + 1) % 4]) for i in range(4)))
    p = Pattern("fig13", (Panel("rect", outer, (inner,)),))
    m = mesh_pattern(p, triangles=1500)
    moved = tuple(e.transformed(np.eye(2), (1.0, 1.0)) for e in inner.edges)
    q = p.with_panel(Panel("rect", outer, (Loop("quad", moved),)))
    m2, rep = update_mesh(p, q, m, min_angle=0.0, return_report=True)
    _mesh_pair(m, m2, "(a) original mesh (blue: internal quadrilateral, red: fixed boundary)",
               f"(b) quadrilateral moved by (1, 1), enhanced MVC: {rep.inverted} inverted, "
               f"min angle {rep.min_angle:.1f}°", "coords_fig13_internal_move.png",
               highlight=m.boundary_loop == 1)
    return rep


def fig14():
    full = build("skirt", "M")
    p = replace(full, panels=(full.panel("front"),), seams=())
    m = mesh_pattern(p, triangles=1500)
    q = move_point(p, "front", "side_r", (0.06, -0.05))
    m2, rep = update_mesh(p, q, m, min_angle=0.0, return_report=True)
    _mesh_pair(m, m2, "(a) original mesh (skirt front panel)",
               f"(b) corner moved by (6, -5) cm, MEC bisector prior: {rep.inverted} inverted, "
               f"min angle {rep.min_angle:.1f}°", "coords_fig14_boundary_move.png")
    return rep


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    skirt = build("skirt", "M").panel("front").outline.polygon(6)
    fig_priors("garment outline (skirt front)", skirt, 12, 0.0002)
    concave = np.array([[0, 0], [3, 0], [3, 2], [2.2, 2], [2.2, 0.8], [1.4, 0.8], [1.4, 2.6],
                        [0.6, 2.6], [0.6, 1.6], [0, 1.6]], float)
    fig_priors("concave polygon", concave, 6, 0.002)
    fig7()
    print("fig 13:", fig13())
    print("fig 14:", fig14())
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
