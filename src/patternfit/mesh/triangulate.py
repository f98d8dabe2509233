"""Constrained quality Delaunay triangulation of a whole pattern (the ``triangle`` package).

Every edge is sampled uniformly in arc length; the two sides of a seam get the same number of
samples, so sewing pairs their vertices one to one (METHOD.md section 2). Sides of different
length (a seam's ``ease``: gathers, cap ease) are sampled alike, each spread evenly along its
own arc length, so each panel keeps its own rest lengths and the difference is sewn in.
Boundary samples are kept as they are (no Steiner points on the boundary), which keeps the
pairing exact.
"""

from __future__ import annotations

import math

import numpy as np
import triangle as tr

from ..arguments import number
from ..constants import limits, tol
from ..geometry import counter_clockwise, triangle_areas
from ..pattern.errors import PatternError
from ..pattern.model import Loop, Pattern
from ..pattern.validate import check_pattern, check_polygons
from .garment import GarmentMesh

# Fraction keys are rounded to this many digits to find shared breakpoints.
_KEY = 12


def _edge_breaks(pattern: Pattern) -> dict[tuple[str, str], list[tuple[float, float, str | None]]]:
    """Split every edge at the ends of the seam ranges on it: (start, end, seam key) pieces."""
    ranges: dict[tuple[str, str], list[tuple[float, float, str]]] = {}
    for seam in pattern.seams:
        for tag, side in (("a", seam.a), ("b", seam.b)):
            ranges.setdefault((side.panel, side.edge), []).append(
                (side.start, side.end, f"{seam.name}\x1f{tag}"))
    pieces = {}
    for panel in pattern.panels:
        for edge in panel.edges().values():
            key = (panel.name, edge.name)
            cuts = {0.0, 1.0}
            for s0, s1, _ in ranges.get(key, []):
                cuts.update((s0, s1))
            cuts = sorted(cuts)
            out = []
            for f0, f1 in zip(cuts[:-1], cuts[1:]):
                tag = next((t for s0, s1, t in ranges.get(key, [])
                            if abs(s0 - f0) < 1e-12 and abs(s1 - f1) < 1e-12), None)
                out.append((f0, f1, tag))
            pieces[key] = out
    return pieces


def _uniform_counts(pattern: Pattern, pieces, h: float) -> dict:
    """Number of boundary segments for every edge piece at even spacing ``h`` [m]; both
    sides of a seam share one."""
    counts = {}
    for seam in pattern.seams:
        la = pattern.seam_side_length(seam.a)
        lb = pattern.seam_side_length(seam.b)
        n = max(1, round(0.5 * (la + lb) / h))
        counts[f"{seam.name}\x1fa"] = counts[f"{seam.name}\x1fb"] = n
    result = {}
    for panel in pattern.panels:
        for edge in panel.edges().values():
            key = (panel.name, edge.name)
            ns = []
            for f0, f1, tag in pieces[key]:
                if tag is not None:
                    ns.append(counts[tag])
                else:
                    n = max(1, round(edge.length * (f1 - f0) / h))
                    if edge.kind != "line":
                        n = max(n, 2)
                    ns.append(n)
            result[key] = ns
    return result


def _spacing(length: float, n: int, s0: float, s1: float) -> np.ndarray:
    """(m + 1,) fractions 0..1 of ``m >= n`` segments along a piece of ``length`` [m]: even
    (``n`` segments) unless a neighbour's segment at the start (``s0``) or end (``s1``) [m]
    is much shorter, then growing from that size by at most ``tol.mesh_growth`` per segment."""
    own = length / n
    if min(s0, s1) >= tol.mesh_grade * own:
        return np.arange(n + 1) / n
    # the size grows by (1 + g) per segment: quarter steps of that near both ends
    g = tol.mesh_growth
    k = np.arange(4 * math.ceil(math.log(own / min(s0, s1)) / math.log(1 + g)) + 8)
    steps = ((1 + g) ** (k / 4) - 1) / g
    x = np.unique(np.clip(np.concatenate([np.linspace(0.0, length, 257), s0 * steps,
                                          length - s1 * steps]), 0.0, length))
    size = np.minimum(own, np.minimum(s0 + g * x, s1 + g * (length - x)))
    phi = np.concatenate([[0.0], np.cumsum(0.5 * (1 / size[1:] + 1 / size[:-1]) * np.diff(x))])
    m = max(n, round(phi[-1]))
    u = np.interp(np.arange(m + 1) / m * phi[-1], phi, x) / length
    u[0], u[-1] = 0.0, 1.0
    return u


def _sampling(pattern: Pattern, pieces, h: float) -> dict:
    """Fractions (0..1 along the piece, ``(m + 1,)``) of the boundary samples of every edge
    piece: even at about ``h`` [m], graded next to much shorter segments; both sides of a
    seam alike (mirrored where the seam runs the other way), so that they pair one to one.
    A seam grades both its sides for a short neighbour of either, which may grade the next
    piece in turn: repeated until no end segment changes by more than 1 %."""
    counts = _uniform_counts(pattern, pieces, h)
    length, rings = {}, []
    for panel in pattern.panels:
        edges = panel.edges()
        for loop in panel.loops:
            ring = [((panel.name, e.name), j) for e in loop.edges
                    for j in range(len(pieces[(panel.name, e.name)]))]
            for key, j in ring:
                f0, f1, _ = pieces[key][j]
                length[key, j] = edges[key[1]].length * (f1 - f0)
            rings.append(ring)
    where = {}
    for key, ps in pieces.items():
        for j, (_, _, tag) in enumerate(ps):
            if tag is not None:
                where[tag] = (key, j)
    out = {key: [np.arange(n + 1) / n for n in ns] for key, ns in counts.items()}
    before: dict = {}
    for _ in range(len(length)):
        ends = {}
        for ring in rings:
            for i, here in enumerate(ring):
                (kp, jp), (kn, jn) = ring[i - 1], ring[(i + 1) % len(ring)]
                up, un = out[kp][jp], out[kn][jn]
                ends[here] = (length[kp, jp] * (up[-1] - up[-2]), length[kn, jn] * (un[1] - un[0]))
        if before and all(np.allclose(ends[k], before[k], rtol=0.01, atol=0) for k in ends):
            break
        before = ends
        new = {key: [None] * len(ps) for key, ps in pieces.items()}
        for seam in pattern.seams:
            a, b = where[f"{seam.name}\x1fa"], where[f"{seam.name}\x1fb"]
            (a0, a1), (b0, b1) = ends[a], ends[b]
            if seam.reverse:
                b0, b1 = b1, b0
            u = _spacing(0.5 * (length[a] + length[b]), counts[a[0]][a[1]],
                         min(a0, b0), min(a1, b1))
            new[a[0]][a[1]] = u
            graded = seam.reverse and len(u) > 2 and not np.allclose(np.diff(u), u[1])
            new[b[0]][b[1]] = 1.0 - u[::-1] if graded else u
        for key, us in new.items():
            for j, u in enumerate(us):
                if u is None:
                    us[j] = _spacing(length[key, j], counts[key][j], *ends[key, j])
        out = new
    return out


def _sample_loop(panel_name: str, loop: Loop, pieces, sampling):
    """Boundary samples of one loop: points (k, 2), edge keys, fractions."""
    pts, keys, fracs = [], [], []
    for edge in loop.edges:
        key = (panel_name, edge.name)
        for (f0, f1, _), u in zip(pieces[key], sampling[key]):
            f = f0 + (f1 - f0) * u[:-1]
            pts.append(edge.point_at(f))
            keys += [key] * len(f)
            fracs.append(f)
    return np.concatenate(pts), keys, np.concatenate(fracs)


def inside_point(poly) -> np.ndarray:
    """A point strictly inside a simple polygon ``poly`` (k, 2) [m], e.g. to mark a hole for
    Triangle: the centroid of the largest triangle of its constrained triangulation."""
    poly = np.asarray(poly, dtype=np.float64)
    n = len(poly)
    seg = np.stack([np.arange(n), (np.arange(n) + 1) % n], axis=1)
    t = tr.triangulate({"vertices": poly, "segments": seg}, "pQ")
    a = triangle_areas(t["vertices"], t["triangles"])
    return t["vertices"][t["triangles"][int(np.argmax(a))]].mean(axis=0)


def _mesh_panel(panel, pieces, sampling, max_area: float, min_angle: float):
    loops = []
    for loop in panel.loops:
        loops.append(_sample_loop(panel.name, loop, pieces, sampling))
    # Triangle crashes on boundaries that cross, touch or fold back: check the very
    # polylines it gets (the panel's own check samples curves differently)
    try:
        check_polygons([lp[0] for lp in loops], [[k[1] for k in lp[1]] for lp in loops],
                       [lp.name for lp in panel.loops], panel=panel.name)
    except PatternError as exc:
        raise PatternError(f"cannot be meshed at this resolution: {exc.reason}",
                           panel=exc.panel, edge=exc.edge) from None
    verts = np.concatenate([lp[0] for lp in loops])
    segs, start = [], 0
    for lp in loops:
        k = len(lp[0])
        idx = start + np.arange(k)
        segs.append(np.stack([idx, np.roll(idx, -1)], axis=1))
        start += k
    data = {"vertices": verts, "segments": np.concatenate(segs)}
    if panel.inner:
        data["holes"] = np.array([inside_point(lp[0]) for lp in loops[1:]])
    out = tr.triangulate(data, f"pq{min_angle:.6f}a{max_area:.12f}YQ")
    v, t = out["vertices"], out["triangles"].astype(np.int64)
    if len(v) < len(verts) or not np.allclose(v[: len(verts)], verts, atol=1e-12, rtol=0):
        raise RuntimeError(f"panel '{panel.name}': the triangulator moved boundary vertices")
    return v, counter_clockwise(v, t), loops


def _mesh_all(pattern: Pattern, h: float, min_angle: float) -> GarmentMesh:
    max_area = math.sqrt(3) / 4 * h * h
    if max_area < tol.area:
        raise ValueError(f"mesh too fine: an edge length of {h:.3g} m makes triangles "
                         f"smaller than {tol.area:g} m^2")
    pieces = _edge_breaks(pattern)
    sampling = _sampling(pattern, pieces, h)
    boundary = sum(len(u) - 1 for us in sampling.values() for u in us)
    if boundary > limits.triangles:
        raise ValueError(f"mesh too fine: an edge length of {h:.3g} m needs {boundary} "
                         f"boundary segments, more than the limit of {limits.triangles} "
                         "triangles")
    edge_names = [(p.name, e.name) for p in pattern.panels for e in p.edges().values()]
    edge_id = {k: i for i, k in enumerate(edge_names)}
    V, T, tpan, vpan = [], [], [], []
    bv, be, bp, bl, lpan = [], [], [], [], []
    where: dict[tuple[int, float], int] = {}  # (edge id, fraction) -> vertex
    nv = 0
    for pi, panel in enumerate(pattern.panels):
        v, t, loops = _mesh_panel(panel, pieces, sampling, max_area, min_angle)
        V.append(v)
        T.append(t + nv)
        tpan.append(np.full(len(t), pi))
        vpan.append(np.full(len(v), pi))
        start = nv
        for loop, (pts, keys, fracs) in zip(panel.loops, loops):
            ids = start + np.arange(len(pts))
            eids = np.array([edge_id[k] for k in keys])
            bv.append(ids)
            be.append(eids)
            bp.append(fracs)
            bl.append(np.full(len(pts), len(lpan)))
            lpan.append(pi)
            for i, e, f in zip(ids, eids, fracs):
                where[(int(e), round(float(f), _KEY))] = int(i)
            # the end of each edge is the start of the next one in the loop
            for e_cur, e_next in zip(loop.edges, loop.edges[1:] + loop.edges[:1]):
                where[(edge_id[(panel.name, e_cur.name)], 1.0)] = \
                    where[(edge_id[(panel.name, e_next.name)], 0.0)]
            start += len(pts)
        nv += len(v)
    pairs, sidx = [], []
    for si, seam in enumerate(pattern.seams):
        ka, kb = (seam.a.panel, seam.a.edge), (seam.b.panel, seam.b.edge)
        ua = sampling[ka][[p[2] for p in pieces[ka]].index(f"{seam.name}\x1fa")]
        ub = sampling[kb][[p[2] for p in pieces[kb]].index(f"{seam.name}\x1fb")]
        fa = seam.a.start + (seam.a.end - seam.a.start) * ua
        fb = seam.b.start + (seam.b.end - seam.b.start) * ub
        if seam.reverse:
            fb = fb[::-1]
        ea, eb = edge_id[(seam.a.panel, seam.a.edge)], edge_id[(seam.b.panel, seam.b.edge)]
        for x, y in zip(fa, fb):
            pairs.append((where[(ea, round(float(x), _KEY))], where[(eb, round(float(y), _KEY))]))
            sidx.append(si)
    pairs_arr = np.array(pairs, dtype=np.int64).reshape(-1, 2)
    sidx_arr = np.array(sidx, dtype=np.int64)
    # a corner shared by two seams would be listed twice
    _, keep = np.unique(np.sort(pairs_arr, axis=1), axis=0, return_index=True)
    keep = np.sort(keep)
    return GarmentMesh(
        vertices=np.concatenate(V), triangles=np.concatenate(T),
        triangle_panel=np.concatenate(tpan), vertex_panel=np.concatenate(vpan),
        panel_names=tuple(p.name for p in pattern.panels),
        grain=np.array([p.grainline for p in pattern.panels], dtype=np.float64),
        edge_names=tuple(edge_names),
        boundary_vertices=np.concatenate(bv), boundary_edge=np.concatenate(be),
        boundary_param=np.concatenate(bp), boundary_loop=np.concatenate(bl),
        loop_panel=np.array(lpan, dtype=np.int64),
        seam_pairs=pairs_arr[keep], seam_index=sidx_arr[keep],
        seam_names=tuple(s.name for s in pattern.seams))


def mesh_pattern(pattern: Pattern, *, triangles: int = 20000, min_angle: float = 25.0,
                 edge_length: float | None = None) -> GarmentMesh:
    """Triangulate every panel of ``pattern`` into one :class:`GarmentMesh`.

    Parameters
    ----------
    pattern : Pattern
        A valid pattern (checked first).
    triangles : int
        Target triangle count for the whole garment; met within a few percent. At most
        ``limits.triangles``.
    min_angle : float
        Minimum triangle angle [degrees] (Triangle's quality bound; at most about 33).
    edge_length : float, optional
        Target edge length [m]; when given, ``triangles`` is ignored. Refused when it would
        make more than ``limits.triangles`` triangles.

    Returns
    -------
    GarmentMesh
        Flat meshes with seam sides sampled alike: ``seam_pairs`` pairs them one to one.

    Raises :class:`PatternError` for a pattern ``check_pattern`` refuses, or whose sampled
    boundary crosses or touches itself, before Triangle sees it; ``ValueError`` naming the
    argument for a bad ``triangles``, ``edge_length`` or ``min_angle``.
    """
    number(min_angle, "min_angle", low=0.0, low_open=True, high=34.0,
           rule="must be in (0, 34] degrees")
    check_pattern(pattern)
    if edge_length is not None:
        h = number(edge_length, "edge_length", low=0.0, low_open=True,
                   rule="must be a positive number")
        estimate = pattern.area() / (math.sqrt(3) / 4 * h * h)
        if estimate > limits.triangles:
            raise ValueError(f"edge_length: {h:.3g} m makes about {estimate:.3g} triangles, "
                             f"more than the limit of {limits.triangles}")
        return _mesh_all(pattern, h, min_angle)
    triangles = number(triangles, "triangles", low=1, high=limits.triangles, integer=True,
                       rule=f"must be a whole number from 1 to {limits.triangles}")
    if int(triangles) < 2 * len(pattern.panels):
        raise ValueError(f"triangles: at least {2 * len(pattern.panels)} needed, got {triangles}")
    # Triangle's refinement makes triangles smaller than the area bound: calibrate the edge
    # length on a first mesh, then correct once more.
    h = math.sqrt(4 * pattern.area() / (math.sqrt(3) * triangles)) * 1.3
    mesh = _mesh_all(pattern, h, min_angle)
    for _ in range(2):
        ratio = mesh.n_triangles / triangles
        if abs(ratio - 1) < 0.03:
            break
        h *= math.sqrt(ratio)
        mesh = _mesh_all(pattern, h, min_angle)
    return mesh
