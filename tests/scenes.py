"""Scenes shared by the tests and the benchmarks: small patterns, flat meshes, distance fields,
meshed and draped built-in garments. Plain functions (fixtures live in ``conftest.py``); units
are metres, newtons and seconds throughout.

Tests import it as ``from scenes import ...`` (pytest puts ``tests/`` on ``sys.path``: the
folder has no ``__init__.py``); the benchmarks do ``import _path`` first
(``benchmarks/_path.py`` puts ``tests/`` there). Everything heavy is imported inside the
functions, so importing this module costs nothing and needs no optional dependency.
"""

from __future__ import annotations

import numpy as np

# ------------------------------------------------------------------------------- patterns


def rectangle_panel(name, w, h, *, origin=(0.0, 0.0), arc=False):
    """A ``w`` x ``h`` [m] rectangular panel with its lower left corner at ``origin``; edges
    ``bottom``, ``right``, ``top`` (from right to left), ``left``, counter-clockwise. With
    ``arc`` the top edge is a circular arc of radius ``w`` (bulging up) instead of a line."""
    from patternfit.pattern import Edge, Loop, Panel

    x0, y0 = origin
    pts = [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]
    names = ["bottom", "right", "top", "left"]
    edges = [Edge.line(n, pts[i], pts[(i + 1) % 4]) for i, n in enumerate(names)]
    if arc:
        edges[2] = Edge.arc("top", pts[2], pts[3], radius=w, sweep=True)
    return Panel(name, Loop("outline", edges))


def two_rectangles():
    """Pattern ``tube``: two 0.5 x 0.8 m rectangles A and B sewn along one side (A right to B
    left) and half of another (the lower half of A's left to the upper half of B's right)."""
    from patternfit.pattern import Pattern, Seam, SeamSide

    a = rectangle_panel("A", 0.5, 0.8)
    b = rectangle_panel("B", 0.5, 0.8)
    return Pattern("tube", (a, b), (
        Seam("s1", SeamSide("A", "right"), SeamSide("B", "left")),
        Seam("s2", SeamSide("A", "left", 0.0, 0.5), SeamSide("B", "right", 0.5, 1.0))))


def two_panels(arc=False):
    """Pattern ``test``: 0.4 x 0.6 m panels A and B side by side, A's right edge sewn to B's
    left edge (bottom to bottom, seam ``side``). With ``arc`` A's top edge is an arc."""
    from patternfit.pattern import Pattern, Seam, SeamSide

    return Pattern("test", (rectangle_panel("A", 0.4, 0.6, arc=arc),
                            rectangle_panel("B", 0.4, 0.6)),
                   (Seam("side", SeamSide("A", "right"), SeamSide("B", "left"), reverse=True),))


# ---------------------------------------------------------------- flat cloth and simple bodies


def gored_skirt(per_side: int, waist: float = 0.12, hem: float = 0.24, length: float = 0.6):
    """A skirt of ``per_side`` gores a side sewn into a ring (front_1 .. front_k, then
    back_1 .. back_k round the other way), each ``waist`` wide at the waist and ``hem`` at
    the hem, ``length`` long [m], its grain up the middle: GarmentCodeData's many-gored
    skirts."""
    from patternfit.pattern.model import (Edge, Loop, Panel, Pattern, Placement, Seam,
                                          SeamSide)

    def gore(name, side):
        w, h = waist / 2, hem / 2
        return Panel(name, Loop("outline", (
            Edge.line("hem", (-h, 0), (h, 0)), Edge.line("right", (h, 0), (w, length)),
            Edge.line("waist", (w, length), (-w, length)),
            Edge.line("left", (-w, length), (-h, 0)))),
            placement=Placement("torso", side), grainline=(0.0, 1.0))

    names = [f"front_{i}" for i in range(per_side)] + [f"back_{i}" for i in range(per_side)]
    panels = tuple(gore(n, n.split("_")[0]) for n in names)
    seams = tuple(Seam(f"s{i}", SeamSide(names[i], "right"),
                       SeamSide(names[(i + 1) % len(names)], "left"))
                  for i in range(len(names)))
    return Pattern("gored", panels, seams, {"anchor": "waist"})


def rect_mesh(length, width, max_area, *, origin=(0.0, 0.0)):
    """Constrained-Delaunay quality mesh (angles >= 30 degrees, triangles <= ``max_area``
    [m^2]) of the rectangle ``origin + [0, length] x [0, width]`` [m]: (vertices (n, 2)
    float, triangles (m, 3) int64)."""
    import triangle

    pts = np.array([[0, 0], [length, 0], [length, width], [0, width]], float) + origin
    seg = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    out = triangle.triangulate({"vertices": pts, "segments": seg}, f"pq30a{max_area:.12f}Q")
    return out["vertices"].astype(float), out["triangles"].astype(np.int64)


def square_mesh(side, triangles):
    """A ``side`` x ``side`` [m] square centred on the origin, meshed by :func:`rect_mesh` to
    about ``triangles`` triangles (Triangle's quality meshes come out finer than the area
    bound says, hence the factor 1.58)."""
    return rect_mesh(side, side, side * side / triangles * 1.58, origin=(-side / 2, -side / 2))


def grain_at(angle_deg, m):
    """(m, 2) unit grain directions at ``angle_deg`` degrees from the flat x axis."""
    a = np.radians(angle_deg)
    return np.tile([np.cos(a), np.sin(a)], (m, 1))


def sphere_field(radius, half=0.3, h=0.005):
    """Exact distance field [m] of a sphere of ``radius`` [m] at the origin on the grid
    [-half, half]^3 of spacing ``h`` [m]."""
    from patternfit.body.sdf import DistanceField

    ax = np.arange(-half, half + 1e-9, h)
    X, Y, Z = np.meshgrid(ax, ax, ax, indexing="ij")
    return DistanceField((-half, -half, -half), h, np.sqrt(X**2 + Y**2 + Z**2) - radius)


def end_line_load(v, ids, tension):
    """Forces (n, 3) [N] of a uniform line load ``tension`` [N/m] along +x on the strip end
    ``ids`` (vertices on a line x = const): each end vertex takes half its two segments."""
    order = np.argsort(v[ids, 1])
    seg = np.diff(v[ids[order], 1])
    share = np.zeros(len(ids))
    share[order[:-1]] += seg / 2
    share[order[1:]] += seg / 2
    forces = np.zeros((len(v), 3))
    forces[ids, 0] = tension * share
    return forces


# ------------------------------------------------------------------------- built-in garments


def garment(name, triangles, size="M"):
    """Built-in garment ``name`` in ``size`` meshed at about ``triangles`` triangles:
    (pattern, mesh)."""
    from patternfit.mesh import mesh_pattern
    from patternfit.pattern.library import build

    pattern = build(name, size)
    return pattern, mesh_pattern(pattern, triangles=triangles)


def draped(name, body, triangles, *, size="M", fabric="cotton", **kw):
    """Built-in garment ``name`` (``size``, about ``triangles`` triangles) draped by the static
    engine on built-in ``body`` in ``fabric``; ``kw`` go to ``sim.drape.drape``:
    (mesh, drape result)."""
    from patternfit.body.builtin import load_body
    from patternfit.sim.drape import drape

    pattern, mesh = garment(name, triangles, size)
    return mesh, drape(pattern, mesh, load_body(body), fabric, **kw)


def welded(d):
    """Positions (k, 3) [m] of a drape result ``d`` with its sewn vertex copies welded: one
    row per welded vertex (``d.result.vertex_map`` maps mesh vertices to rows)."""
    vmap = d.result.vertex_map
    x = np.zeros((vmap.max() + 1, 3))
    x[vmap] = d.positions
    return x


# ------------------------------------------------------------ GarmentCode-built patterns


def planes_placed(pattern, mesh, body):
    """``pattern`` as a file might place it: each panel a plane 25 cm in front of / behind
    the body at the height patternfit's placement gives it (a plausible imported placement,
    kept by ``place_on_body``)."""
    from dataclasses import replace

    from patternfit.sim.placement import place_on_body

    ours = place_on_body(pattern, mesh, body)
    panels = []
    for i, p in enumerate(pattern.panels):
        z = 0.25 if p.placement.side == "front" else -0.25
        panels.append(replace(p, placement=replace(
            p.placement, translation=(0.0, float(ours[mesh.panel_vertices(i), 1].min()), z),
            rotation=(0.0, 0.0 if z > 0 else 180.0, 0.0))))
    return replace(pattern, panels=tuple(panels))


def gc_panel(points, curved=None, at=(0.0, 0.0, 0.0), rot=0.0):
    """A GarmentCode panel entry: ``points`` [cm], ``curved`` {edge index: curvature},
    translation ``at`` [cm] and a rotation ``rot`` [deg] about z."""
    edges = []
    for k in range(len(points)):
        e = {"endpoints": [k, (k + 1) % len(points)]}
        if curved and k in curved:
            e["curvature"] = curved[k]
        edges.append(e)
    return {"translation": list(at), "rotation": [0.0, 0.0, rot], "vertices": points,
            "edges": edges}


def gc_pattern(panels, stitches, placed=True):
    """The pattern GarmentCode's reader makes of ``panels`` (name -> :func:`gc_panel`) and
    ``stitches`` (((panel, edge), (panel, edge)), ...), in centimetres with relative
    curvature; without ``placed``, every panel at the origin unrotated."""
    from patternfit.pattern.garmentcode import garmentcode_from_dict

    if not placed:
        for p in panels.values():
            p["translation"], p["rotation"] = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    return garmentcode_from_dict({
        "pattern": {"panels": panels, "stitches": [
            [{"panel": a, "edge": i}, {"panel": b, "edge": j}] for (a, i), (b, j) in stitches]},
        "parameters": {}, "properties": {"curvature_coords": "relative",
                                         "units_in_meter": 100}}, name="nameless")


def gc_circle_skirt(placed=True, tiers=0, *, waist=0.672, length=0.40, band=0.04):
    """A flared skirt as GarmentCode drafts one, panels numbered ``p0``...: front and back
    drawn as annulus sectors (the back clockwise, as seen from the front), sewn at their
    slanted sides, ``length`` [m] long with a ``waist`` [m] round; a waistband in a front and a
    back band ``band`` [m] high; ``tiers`` more sectors 0.30 m long stacked below, each sewn
    across the hem of the one above."""

    def sector(r0, r1, half_angle, clockwise):
        a = np.linspace(-half_angle, half_angle, 2)
        inner = [[r0 * np.sin(t), -r0 * np.cos(t)] for t in a]
        outer = [[r1 * np.sin(t), -r1 * np.cos(t)] for t in a[::-1]]
        # hem (outer, curved), side, waist (inner, curved), side: counter-clockwise
        pts = [outer[1], outer[0], inner[1], inner[0]]
        pts = [[float(x), float(y) + r1] for x, y in pts]
        # mirrored (clockwise), each arc bulges to the other side of its edge
        arc_out = {"type": "circle", "params": [r1, 0, 0 if clockwise else 1]}
        arc_in = {"type": "circle", "params": [r0, 0, 1 if clockwise else 0]}
        if clockwise:
            pts = [[-x, y] for x, y in pts]
        return pts, {0: arc_out, 2: arc_in}

    panels, stitches = {}, []
    r0 = waist * 100 / (4 * 1.2)
    r1 = r0 + length * 100
    for k, (z, cw) in enumerate(((20.0, False), (-15.0, True))):
        pts, curved = sector(r0, r1, 1.2, cw)
        panels[f"p{k}"] = gc_panel(pts, curved, (0.0, 100.0, z))
    stitches += [(("p0", 1), ("p1", 3)), (("p0", 3), ("p1", 1))]
    w, h = waist * 50, band * 100
    panels["p2"] = gc_panel([[0, 0], [w, 0], [w, h], [0, h]], at=(0.0, 105.0, 20.0))
    panels["p3"] = gc_panel([[0, 0], [w, 0], [w, h], [0, h]], at=(0.0, 105.0, -15.0))
    stitches += [(("p2", 0), ("p0", 2)), (("p3", 0), ("p1", 2)), (("p2", 1), ("p3", 3)),
                 (("p2", 3), ("p3", 1))]
    above = ("p0", "p1")
    for t in range(tiers):
        r0, r1 = r1, r1 + 30.0
        names = (f"p{4 + 2 * t}", f"p{5 + 2 * t}")
        for k, (name, cw) in enumerate(zip(names, (False, True))):
            pts, curved = sector(r0, r1, 1.2, cw)
            panels[name] = gc_panel(pts, curved, (0.0, 60.0 - 30 * t, (20.0, -15.0)[k]))
        stitches += [((names[0], 1), (names[1], 3)), ((names[0], 3), (names[1], 1)),
                     ((names[0], 2), (above[0], 0)), ((names[1], 2), (above[1], 0))]
        above = names
    return gc_pattern(panels, stitches, placed)


def assert_matched_and_mirrored(pattern, panels):
    """Every seam of ``pattern`` has sides of equal length (1e-5 m) and each of ``panels``
    is mirror-symmetric about its vertical middle (0.1 mm): a correction's edit kept both."""
    import pytest

    for seam in pattern.seams:
        assert pattern.seam_side_length(seam.a) == pytest.approx(
            pattern.seam_side_length(seam.b), abs=1e-5)
    for name in panels:
        poly = pattern.panel(name).outline.polygon()
        axis = 0.5 * (poly[:, 0].min() + poly[:, 0].max())
        mirrored = poly * [-1.0, 1.0] + [2 * axis, 0.0]
        assert np.linalg.norm(mirrored[:, None] - poly[None], axis=2).min(axis=1).max() < 1e-4


def fd_gradient(f, x, h=1e-7):
    """Central finite differences (n, 3) of the scalar ``f`` at ``x`` (n, 3), step ``h``."""
    g = np.zeros_like(x)
    for i in range(x.shape[0]):
        for c in range(3):
            xp, xm = x.copy(), x.copy()
            xp[i, c] += h
            xm[i, c] -= h
            g[i, c] = (f(xp) - f(xm)) / (2 * h)
    return g


def gathered_past_the_limit() -> dict:
    """A GarmentCode specification (cm) of two panels whose one stitch sews a 20 cm edge to
    a 50 cm one: a 2.5:1 gather, past the 2:1 a seam may gather."""
    square = [[0, 0], [20, 0], [20, 20], [0, 20]]
    wide = [[0, 0], [50, 0], [50, 20], [0, 20]]
    return {"pattern": {"panels": {
        name: {"vertices": v, "edges": [{"endpoints": [k, (k + 1) % 4]} for k in range(4)],
               "translation": [0, 100, z], "rotation": [0, 0, 0]}
        for name, v, z in (("a", square, 10), ("b", wide, -10))},
        "stitches": [[{"panel": "a", "edge": 1}, {"panel": "b", "edge": 2}]]},
        "properties": {"units_in_meter": 100}}
