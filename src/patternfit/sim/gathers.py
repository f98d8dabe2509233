"""Gathers finer than the mesh: the band along a seam's longer side that shrinks freely.

A seam whose sides differ in length (a gather, a sleeve cap's ease; GarmentCode sews edges
of different length throughout) is meshed with the same number of vertices on both sides, so
closing it draws the longer side in. Real cloth takes that up in gathers, folds of a few
millimetres, far finer than a garment mesh's 1-4 cm edges. A mesh that keeps its stretch
stiffness in compression cannot fold that finely and splits the difference instead: in
GarmentCodeData's rand_04EGGDPALT (5K triangles) the skirt gores, the shorter side, were
stretched by 25-36 % along the waist seam and the bodice drawn in only to 0.69-0.72, and the
fit read that stretch as a tight waist (outside audit 13). So the triangles of the longer
side within :data:`GATHER_ROWS` of its edges' lengths from the seam may shrink along the seam
at no cost by the gather there (``1 - short / long``), by less further in, and by nothing at
the band's edge: the gathers the mesh cannot resolve, while the shorter side keeps its length.
Beyond that slack a triangle resists as any other (a gather packs no tighter than its ratio),
and across the seam it does not shrink at all. Further away the mesh resolves the folds
itself. Measured and dropped (docs/simulation.md, "Gathers finer than the mesh"): no
stiffness at all in the band's compression left the built-in gathered skirt's band stretched
by 3.5-4.2 % along its seam (1.8-1.9 % with the slack, 23-25 % before); a slack on both
yarns alike, free to shrink down from the seam too, kept GarmentCodeData's rand_04ANOD2PBA
from coming to rest.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra

from ..geometry import boundary_edges, unique_edges

#: a seam edge counts as gathered where its side is longer than its partner's by more than
#: this share [-]: above the seam tolerance (0.5 %) and the chord difference of a curved side
#: sewn to a straight one, below a sleeve cap's usual ease (5-10 %)
GATHER_MIN = 0.02
#: the band's width, in lengths of the gathered side's own mesh edges [-]: wide enough that
#: the first rows of triangles can take up a 2:1 gather between them
GATHER_ROWS = 3.0
#: a gather of more than OBLIQUE_GATHER (longer / shorter - 1) whose seam runs this far or
#: further from both yarns of its longer side is taken up loosely [degrees]: at 45 a
#: shortening along the seam and one across it strain both yarns alike, so the slack frees
#: the band across the seam too; outside audit 14's 1.6:1 skirt held at 0-22.5 degrees and
#: slid or fell at 30 and 45. A sleeve cap's ease (the built-in shirt's 8 %, its curve at
#: 30 degrees) frees little across the seam and drapes as it should.
OBLIQUE_DEGREES = 25.0
OBLIQUE_GATHER = 0.25


class GatherWarning(UserWarning):
    """A gathered seam runs at an angle to the grain that the gathers' slack models
    loosely (:data:`OBLIQUE_DEGREES`)."""


def oblique_gathers(mesh) -> list[tuple[str, float]]:
    """Each seam of ``mesh`` (a :class:`~patternfit.mesh.garment.GarmentMesh`) gathered by
    more than :data:`OBLIQUE_GATHER` whose longer side runs at :data:`OBLIQUE_DEGREES` or
    more from both its yarns, as ``(seam name, angle [degrees])`` with the angle its gathered
    edges make with the nearer yarn (median, rounded to 5 degrees, 0-45)."""
    gathered, ratio = gathered_edges(mesh.vertices, mesh.triangles,
                                     np.arange(mesh.n_vertices), mesh.seam_pairs)
    gathered = gathered[ratio > 1.0 + OBLIQUE_GATHER]
    seams_of: dict[int, set[int]] = {}  # a corner is on two seams: an edge's ends share one
    for v, k in zip(mesh.seam_pairs.ravel().tolist(),
                    np.repeat(mesh.seam_index, 2).tolist()):
        seams_of.setdefault(v, set()).add(k)
    angles: dict[int, list[float]] = {}
    for a, b in gathered.tolist():
        u = mesh.vertices[b] - mesh.vertices[a]
        g = mesh.grain[mesh.vertex_panel[a]]
        c = abs(float(u @ g)) / (np.linalg.norm(u) * np.linalg.norm(g))
        angle = np.degrees(np.arccos(min(c, 1.0)))
        seam = min(seams_of[a] & seams_of[b] or seams_of[a] | seams_of[b])
        angles.setdefault(seam, []).append(min(angle, 90.0 - angle))
    return [(str(mesh.seam_names[k]), 5.0 * round(float(np.median(a)) / 5.0))
            for k, a in sorted(angles.items()) if np.median(a) >= OBLIQUE_DEGREES]


def gather_slack(rest, triangles, grain, vertex_map, seam_pairs) -> np.ndarray:
    """How far each triangle's warp and weft may shrink at no cost [-], ``(m, 2)`` in [0, 1):
    0 everywhere but in the band of a gathered seam side. There a gather shortens the cloth
    along the seam by ``1 - short / long`` of the nearest gathered edge, falling linearly to
    0 across the band, and a yarn at angle ``theta`` to the seam takes ``cos(theta)^2`` of
    that: a yarn across the seam none (a gather does not shorten the cloth down from it).

    Parameters
    ----------
    rest : (n, 2) float
        Flat vertex positions [m].
    triangles : (m, 3) int
        Flat triangles.
    grain : (m, 2) float
        Unit warp direction of each triangle in the flat frame.
    vertex_map : (n,) int
        Simulated vertex of each flat vertex.
    seam_pairs : (k, 2) int
        Sewn pairs of simulated vertices.
    """
    rest = np.asarray(rest, dtype=np.float64)
    triangles = np.asarray(triangles, dtype=np.int64)
    slack = np.zeros((len(triangles), 2))
    if not len(seam_pairs):
        return slack
    gathered, ratio = gathered_edges(rest, triangles, vertex_map, seam_pairs)
    if not len(gathered):
        return slack
    edges = unique_edges(triangles)
    lengths = np.linalg.norm(rest[edges[:, 0]] - rest[edges[:, 1]], axis=1)
    n = len(rest)
    graph = sp.coo_matrix((lengths, (edges[:, 0], edges[:, 1])), shape=(n, n)).tocsr()
    along = rest[gathered[:, 1]] - rest[gathered[:, 0]]
    step = np.linalg.norm(along, axis=1)
    width = GATHER_ROWS * float(step.mean())
    # each seam vertex takes up the larger gather of its two edges, along their mean line
    # (u u^T summed, so that the edges' senses do not matter)
    at_seam = np.zeros(n)
    np.maximum.at(at_seam, gathered.ravel(), np.repeat(1.0 - 1.0 / ratio, 2))
    line = np.zeros((n, 2, 2))
    u = along / step[:, None]
    np.add.at(line, gathered.ravel(), np.repeat(u[:, :, None] * u[:, None, :], 2, axis=0))
    line /= np.maximum(np.trace(line, axis1=1, axis2=2), 1e-300)[:, None, None]
    distance, _, source = dijkstra(graph, directed=False, indices=np.unique(gathered),
                                   limit=width, min_only=True, return_predecessors=True)
    near = source >= 0
    amount = np.zeros(n)
    amount[near] = at_seam[source[near]] * np.clip(1.0 - distance[near] / width, 0.0, 1.0)
    seam_line = np.zeros((n, 2, 2))
    seam_line[near] = line[source[near]]
    grain = np.asarray(grain, dtype=np.float64)
    for k, yarn in enumerate((grain, np.column_stack([-grain[:, 1], grain[:, 0]]))):
        share = np.einsum("ti,tjik,tk->tj", yarn, seam_line[triangles], yarn)  # cos^2
        slack[:, k] = (amount[triangles] * share).mean(axis=1)
    return slack


def gathered_edges(rest, triangles, vertex_map, seam_pairs) -> tuple[np.ndarray, np.ndarray]:
    """The flat boundary edges sewn to a partner edge shorter by more than
    :data:`GATHER_MIN` of its length (the side that gathers), ``(g, 2)`` int, and each one's
    length over its partner's, ``(g,)`` float; arguments as in :func:`gather_slack`."""
    vertex_map = np.asarray(vertex_map, dtype=np.int64)
    border = boundary_edges(triangles)
    if not len(border):
        return np.zeros((0, 2), np.int64), np.zeros(0)
    length = np.linalg.norm(rest[border[:, 0]] - rest[border[:, 1]], axis=1)
    sim = np.sort(vertex_map[border], axis=1)
    by_key = {(int(a), int(b)): float(L) for (a, b), L in zip(sim, length)}
    partners: dict[int, list[int]] = {}
    for a, b in np.asarray(seam_pairs, dtype=np.int64):
        partners.setdefault(int(a), []).append(int(b))
        partners.setdefault(int(b), []).append(int(a))
    rows, ratio = [], []
    for k, (a, b) in enumerate(sim):
        other = [by_key[key] for p in partners.get(int(a), ()) for q in partners.get(int(b), ())
                 if (key := (min(p, q), max(p, q))) in by_key]
        if other and length[k] > (1.0 + GATHER_MIN) * max(other):
            rows.append(k)
            ratio.append(length[k] / max(other))
    return border[rows].reshape(-1, 2), np.array(ratio)
