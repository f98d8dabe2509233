"""Load any body mesh (OBJ, PLY, STL, GLB/glTF, OFF through trimesh; a body saved as
``.npz``) and write bodies out.

A loaded body is brought to patternfit's frame: metres, Y up, feet on y = 0, near the Y axis
(moved onto it from farther than 0.5 m), facing +Z. It must be closed and a standing adult
in an A-pose: small holes are filled, anything else is refused with a :class:`BodyMeshError`
that names the file and says what is wrong (the missing landmark of a sphere, the unit
guessed for an absurd size, ...).

The unit of a mesh is guessed when not given: ``body.meta["units"]`` names the unit used
and ``body.meta["units_guessed"]`` is True when it was guessed, so that front ends can say
so (a body in inches must not pass silently as centimetres).
"""

from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np
import trimesh
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import breadth_first_order, connected_components

from ..constants import UNITS, limits
from ..errors import InputError
from ..files import atomic_write_bytes, read_bytes_capped
from ..geometry import rotation_between
from .measure import LandmarkError, measure
from .model import Body

#: plausible adult standing heights [m] (the built-in bodies are 1.65 and 1.78 m tall): a
#: mesh outside is in other units than given or guessed, or no adult
HEIGHT_RANGE = (1.0, 2.3)
#: the guessed unit is the one that makes the mesh's height closest to this [m]
_TYPICAL_HEIGHT = 1.7
_UNIT_NAMES = {"m": "metres", "cm": "centimetres", "mm": "millimetres", "in": "inches"}
#: holes bounded by at most this many edges are filled: a missing vertex leaves a hole of
#: its valence (5 to 7 on a body mesh); larger openings are cuts the user must close
_MAX_HOLE_EDGES = 8
#: bytes a mesh file may take per allowed vertex (an ASCII OBJ with normals and texture
#: coordinates takes about 150), so that the file cap follows ``limits.body_vertices``
_FILE_BYTES_PER_VERTEX = 200
#: the mesh formats read (trimesh also opens archives, which could expand without bound)
_FORMATS = ("obj", "ply", "stl", "glb", "gltf", "off")
_AXES = {"x": 0, "y": 1, "z": 2}
#: a body facing more than this away from +Z about the vertical is turned to face +Z
#: [degrees]: the built-in bodies read 0.0, each turned 10, 45, 90, 180 or -135 degrees
#: read its turn to 0.1
_HEADING_TOLERANCE = 2.0
#: a body whose box is centred farther than this from the Y axis is moved onto it [m]
_NEAR_AXIS = 0.5
#: separate pieces of a body mesh with less than this share of the largest one's area are
#: left out (a scan's specks, a character's eyes); a larger one is refused [-] ...
_DEBRIS = 0.01
#: ... a piece with this share or more before the unit is guessed from the height (a
#: chair: 88 %, a floor slab: more than the body), so that it is named rather than read as
#: part of the body's height [-]
_OTHER_OBJECT = 0.05
#: the feet (up to this share of the height) and the shins above them (between these
#: shares): the toes reach 18-21 cm forward of the shins' middle and the heels 5-7 cm back
_FEET, _SHINS = 0.025, (0.06, 0.09)
#: the toes tell front from back only when they reach this much farther forward than the
#: heels back [m] (without feet, the head's level cut this much forward of the calves') ...
_TOE_REACH = 0.03
#: ... the heights of the head's and the calves' cuts, as shares of the height
_HEAD_CALVES = (0.90, 0.15)
#: ... and the left-right axis is the body's widest across only when its spread is this
#: many times the front-back one (A-posed arms: 9 to 13 on the built-in bodies) [-]
_WIDE = 2.0


class BodyMeshError(InputError):
    """A body mesh that cannot be used, with the reason and the file."""


def _guess_units(extent: float, file) -> str:
    """The unit (a key of ``UNITS``) in which a mesh ``extent`` file units tall has the most
    typical adult height; refused when even that height is no adult's."""
    unit = min(UNITS, key=lambda u: abs(math.log(extent * UNITS[u] / _TYPICAL_HEIGHT)))
    height = extent * UNITS[unit]
    if not HEIGHT_RANGE[0] <= height <= HEIGHT_RANGE[1]:
        raise BodyMeshError(
            f"absurd size: the mesh is {extent:.4g} units tall; the nearest adult height is "
            f"{height:.3g} m, taken as {_UNIT_NAMES[unit]} (guessed), outside "
            f"{HEIGHT_RANGE[0]}-{HEIGHT_RANGE[1]} m; give the units", file=file, place="units")
    return unit


def _guess_up(vertices) -> str:
    """The up axis of a standing body (``"y"``, ``"-z"``, ...): the longest side is
    vertical, and the centre of the vertices lies above mid-height (torso and head carry
    more surface than the legs; a scan with denser legs is read the other way up, which
    :func:`body_from_arrays` then tries)."""
    axis = int(np.argmax(np.ptp(vertices, axis=0)))
    mid = 0.5 * (vertices[:, axis].min() + vertices[:, axis].max())
    return ("" if vertices[:, axis].mean() >= mid else "-") + "xyz"[axis]


def _up_rotation(up: str) -> np.ndarray:
    """(3, 3) rotation taking the up direction ``up`` (``"y"``, ``"-z"``, ...) to +Y."""
    key = up.strip().lower()
    sign = -1.0 if key.startswith("-") else 1.0
    key = key.lstrip("+-")
    if key not in _AXES:
        raise ValueError(f"up: expected one of x, y, z, -x, -y, -z, got {up!r}")
    src = np.zeros(3)
    src[_AXES[key]] = sign
    return rotation_between(src, (0.0, 1.0, 0.0))  # -y up: the half turn about x


def _heading(vertices, faces) -> float | None:
    """Angle [degrees] about +Y from +Z to the way a standing body (Y up, feet on y = 0)
    faces, positive towards +X; None when it cannot be told. The left-right axis is the
    widest across (the area-weighted spread of the surface seen from above: A-posed arms,
    shoulders, hips); the front is the side the toes point to, or without feet the side
    the head is carried to."""
    tm = trimesh.Trimesh(vertices, faces, process=False)
    area = tm.area_faces
    across = tm.triangles_center[:, [0, 2]]
    across = across - area @ across / area.sum()
    spread, axes = np.linalg.eigh((area[:, None] * across).T @ across)
    if spread[1] < _WIDE * spread[0]:
        return None
    forward = np.array([-axes[1, 1], axes[0, 1]])  # (x, z) across the widest axis
    height = np.ptp(vertices[:, 1])
    feet = vertices[vertices[:, 1] < _FEET * height][:, [0, 2]] @ forward
    low, high = _SHINS[0] * height, _SHINS[1] * height
    shins = vertices[(vertices[:, 1] > low) & (vertices[:, 1] < high)][:, [0, 2]] @ forward
    if not len(feet) or not len(shins):
        return None
    ahead = 0.5 * (feet.max() + feet.min()) - shins.mean()  # the toes
    if abs(ahead) < _TOE_REACH:
        # no feet to tell by (a scan cut at the ankles): the head is carried forward of
        # the calves (5-9 cm on the built-in bodies)
        head, calves = (_section_centre(tm, share * height, forward) for share in _HEAD_CALVES)
        if head is None or calves is None or abs(head - calves) < _TOE_REACH:
            return None
        ahead = head - calves
    forward *= np.sign(ahead)
    return float(np.degrees(np.arctan2(forward[0], forward[1])))


def _section_centre(tm: trimesh.Trimesh, y: float, forward) -> float | None:
    """Where the body's level cut at height ``y`` [m] lies along ``forward`` ((x, z) unit):
    the area-weighted centre of its closed outlines [m], None where it cuts nothing."""
    section = tm.section(plane_origin=(0.0, y, 0.0), plane_normal=(0.0, 1.0, 0.0))
    if section is None:
        return None
    moment = total = 0.0
    for ring in section.discrete:  # each outline's own centre (the cut's turn either way)
        p = ring[:, [0, 2]] @ np.column_stack([forward, [-forward[1], forward[0]]])
        nxt = np.roll(p, -1, axis=0)
        cross = p[:, 0] * nxt[:, 1] - nxt[:, 0] * p[:, 1]
        area = float(cross.sum()) / 2.0
        if abs(area) > 1e-8:
            moment += abs(area) * float(((p[:, 0] + nxt[:, 0]) * cross).sum()) / (6.0 * area)
            total += abs(area)
    return moment / total if total > 0.0 else None


def _the_body_alone(tm: trimesh.Trimesh, file, *, refuse: float,
                    unit: str = "file units") -> trimesh.Trimesh | None:
    """``tm`` (its copies of a vertex merged) cut to its largest connected piece (by area)
    with the pieces of under ``refuse`` of its area, without those under :data:`_DEBRIS` of
    it, in place; None when it is one piece (nothing cut) (a scan's specks, a character's eyes: 5 m off, one read the body as 5.6 units tall);
    a larger second piece (a floor, a chair, a second body) is a :class:`BodyMeshError`
    naming ``file`` and the two largest pieces' sizes (in ``unit``): it was measured as part
    of the body (a slab under the feet made the body 2 cm taller) or broke the landmarks
    with a message about a leg or an arm. Read twice: before the unit is guessed from the
    height, refusing what is as large as a floor or a chair, then for loose pieces."""
    if len(tm.faces) == 0:
        return None
    label = trimesh.graph.connected_component_labels(tm.face_adjacency, len(tm.faces))
    area = np.bincount(label, weights=tm.area_faces)
    if len(area) == 1:
        return None
    order = np.argsort(area)[::-1]
    if area[order[1]] >= refuse * area[order[0]]:
        sizes = [" x ".join(f"{x:.3g}" for x in np.ptp(
            tm.vertices[np.unique(tm.faces[label == k])], axis=0)) for k in order[:2]]
        raise BodyMeshError(
            f"{int((area >= _DEBRIS * area[order[0]]).sum())} separate objects, not one body: "
            f"{sizes[0]} and {sizes[1]} {unit} across the two largest (the second "
            f"{area[order[1]] / area[order[0]] * 100:.0f}% of the first's surface; a floor, a "
            "chair or another body?); keep the body alone", file=file, place="faces")
    tm.update_faces(np.isin(label, order[area[order] >= _DEBRIS * area[order[0]]]))
    tm.remove_unreferenced_vertices()  # a speck's vertices 5 m off set the height
    return tm


def _consistent_winding(faces) -> np.ndarray:
    """(m, 3) ``faces`` with every connected patch wound one way.

    trimesh.repair.fix_winding needs networkx; this walks a scipy breadth-first tree of the
    face adjacency instead: each face is flipped when the faces on its path to the patch's
    first face disagree an odd number of times.
    """
    f = np.asarray(faces, dtype=np.int64)
    m = len(f)
    pairs, edges = trimesh.graph.face_adjacency(f, return_edges=True)

    def forward(face_ids):  # does the shared edge run edges[:, 0] -> edges[:, 1] in the face?
        fv = f[face_ids]
        return ((fv == edges[:, :1]) & (np.roll(fv, -1, axis=1) == edges[:, 1:])).any(axis=1)

    flip_rel = forward(pairs[:, 0]) == forward(pairs[:, 1])
    _, label = connected_components(coo_matrix((np.ones(len(pairs)), pairs.T), shape=(m, m)),
                                    directed=False)
    # one extra node m joins every patch's first face, so that a single search covers all
    firsts = np.unique(label, return_index=True)[1]
    rows = np.concatenate([pairs[:, 0], firsts])
    cols = np.concatenate([pairs[:, 1], np.full(len(firsts), m)])
    weight = np.concatenate([flip_rel + 1.0, np.ones(len(firsts))])  # 0 would be no edge
    graph = coo_matrix((weight, (rows, cols)), shape=(m + 1, m + 1)).tocsr()
    graph = graph + graph.T
    order, pred = breadth_first_order(graph, m, directed=False, return_predecessors=True)
    node = order[1:]
    anc = np.full(m + 1, m)
    anc[node] = pred[node]
    odd = np.zeros(m + 1, dtype=bool)
    odd[node] = np.asarray(graph[node, pred[node]]).ravel() == 2.0
    while (anc != m).any():  # pointer jumping: parity along the path to the root
        odd = odd ^ odd[anc]
        anc = anc[anc]
    out = f.copy()
    out[odd[:m]] = out[odd[:m]][:, ::-1]
    return out


def _hole_fans(faces) -> np.ndarray:
    """(k, 3) triangles closing every hole of ``faces`` (consistently wound) bounded by a
    simple loop of at most ``_MAX_HOLE_EDGES`` edges, wound like the rest.

    trimesh.repair.fill_holes needs networkx; the loops are found here from trimesh's edge
    grouping and scipy's connected components.
    """
    edges = trimesh.geometry.faces_to_edges(faces)
    boundary = edges[trimesh.grouping.group_rows(np.sort(edges, axis=1), require_count=1)]
    fans = []
    for loop in trimesh.graph.connected_components(boundary, min_len=3):
        if len(loop) > _MAX_HOLE_EDGES:
            continue
        sub = boundary[np.isin(boundary[:, 0], loop)]
        after = dict(sub.tolist())
        if len(sub) != len(loop) or len(after) != len(loop) or len(set(after.values())) != \
                len(loop):
            continue  # a vertex where two holes touch: no single loop to fill
        ring = [int(loop[0])]
        for _ in range(len(loop) - 1):
            ring.append(after[ring[-1]])
        # the loop runs like the faces around it, so new faces run it backwards
        fans += [(ring[0], ring[i + 1], ring[i]) for i in range(1, len(ring) - 1)]
    return np.array(fans, dtype=np.int64).reshape(-1, 3)


def body_from_arrays(vertices, faces, *, units: str | None = None, up: str | None = None,
                     name: str = "body", file=None, guessed: bool = False) -> Body:
    """Check, repair and normalise a body mesh given as arrays.

    Parameters
    ----------
    vertices : (n, 3) float
        Vertices in ``units``; at most ``limits.body_vertices``.
    faces : (m, 3) int
        Triangles, indices into ``vertices``.
    units : str, optional
        One of ``m``, ``cm``, ``mm``, ``in``. When None, the unit that makes the height
        closest to a typical adult's is guessed.
    up : str, optional
        The mesh's up axis (``y``, ``z``, ``-z``, ...); guessed when None (the longest side,
        the way most of the surface lies; the other way when no body's landmarks are found
        that way up: ``meta["up_guessed"]``).
    guessed : bool
        ``up`` was guessed (recorded in ``meta``).
    name : str
        Name of the body.
    file : path, optional
        Where the arrays come from, named in errors.

    Returns a :class:`Body` in metres, Y up, feet on y = 0, near the Y axis, facing +Z (a
    body facing elsewhere is turned about the vertical: ``meta["turned_deg"]``, the angle
    from +Z to where it faced, positive towards +X; ``meta["facing_known"]`` False where
    nothing told), with its measurements and landmarks; ``meta`` also holds ``units`` (the
    unit used), ``units_guessed``, ``scale_to_m``, ``up`` and ``up_guessed``.

    Raises :class:`BodyMeshError` naming ``file`` (and the place: ``units``, ``faces``, a
    landmark) when the mesh is empty, too large, has NaN coordinates or bad face indices, a
    height outside :data:`HEIGHT_RANGE` in the given or guessed unit, is open beyond small
    holes, or is no standing human in an A-pose (a sphere, a box: the first landmark that
    cannot be found is named).
    """
    v = np.asanyarray(vertices)
    f = np.asanyarray(faces)
    if v.ndim != 2 or v.shape[1] != 3 or len(v) == 0 or f.ndim != 2 or len(f) == 0:
        raise BodyMeshError("empty mesh: no vertices or no triangles", file=file)
    if f.shape[1] != 3:
        raise BodyMeshError(f"faces must be triangles, got {f.shape[1]} corners", file=file)
    if len(v) > limits.body_vertices:
        raise BodyMeshError(f"{len(v)} vertices, more than the limit of "
                            f"{limits.body_vertices}", file=file)
    if v.dtype.kind not in "iuf":
        raise BodyMeshError(f"vertices must be numbers, got {v.dtype}", file=file)
    if f.dtype.kind not in "iu":
        raise BodyMeshError(f"faces must be vertex indices (integers), got {f.dtype}",
                            file=file, place="faces")
    v = v.astype(np.float64)
    if not np.isfinite(v).all():
        raise BodyMeshError(f"{int((~np.isfinite(v)).any(axis=1).sum())} vertices are NaN or "
                            "infinite", file=file)
    if f.min() < 0 or f.max() >= len(v):
        bad = int(f.min()) if f.min() < 0 else int(f.max())
        raise BodyMeshError(f"vertex index {bad} out of range: the mesh has {len(v)} "
                            "vertices", file=file, place="faces")
    if units is not None and units not in UNITS:
        raise ValueError(f"units: expected one of {', '.join(UNITS)}, got {units!r}")
    if not guessed:  # before the up axis and the unit are read from the body's extent
        whole = trimesh.Trimesh(v, f, process=True)
        whole.update_faces(whole.nondegenerate_faces())
        if _the_body_alone(whole, file, refuse=_OTHER_OBJECT) is not None:
            v, f = np.asarray(whole.vertices, np.float64), np.asarray(whole.faces, np.int64)
    if up is None:
        guess = _guess_up(v)
        try:
            return body_from_arrays(v, f, units=units, up=guess, name=name, file=file,
                                    guessed=True)
        except BodyMeshError as exc:
            if not (exc.place or "").startswith("landmark"):
                raise
            other = guess[1:] if guess.startswith("-") else "-" + guess
            try:
                return body_from_arrays(v, f, units=units, up=other, name=name, file=file,
                                        guessed=True)
            except BodyMeshError:
                raise exc from None
    v = v @ _up_rotation(up).T
    extent = float(np.ptp(v[:, 1]))
    if not 0.0 < extent < np.inf:
        raise BodyMeshError("the mesh has no height (flat or beyond float range)", file=file)
    unit = units or _guess_units(extent, file)
    scale = UNITS[unit]
    height = extent * scale
    if not HEIGHT_RANGE[0] <= height <= HEIGHT_RANGE[1]:
        raise BodyMeshError(f"absurd size: {height:.4g} m tall in {_UNIT_NAMES[unit]} (given),"
                            f" outside {HEIGHT_RANGE[0]}-{HEIGHT_RANGE[1]} m", file=file,
                            place="units")
    v = v * scale

    tm = trimesh.Trimesh(v, f, process=True)  # merges the copies of split vertices (STL)
    tm.update_faces(tm.unique_faces() & tm.nondegenerate_faces())
    tm.remove_unreferenced_vertices()
    if len(tm.faces) == 0:
        raise BodyMeshError("empty mesh: every triangle is degenerate", file=file)
    _the_body_alone(tm, file, refuse=_DEBRIS, unit="m")
    faces_out = np.asarray(tm.faces, dtype=np.int64)
    if not tm.is_winding_consistent:
        faces_out = _consistent_winding(faces_out)
    faces_out = np.concatenate([faces_out, _hole_fans(faces_out)])
    tm = trimesh.Trimesh(tm.vertices, faces_out, process=False)
    if not tm.is_watertight:
        edges = trimesh.grouping.group_rows(tm.edges_sorted, require_count=2)
        bad = len(tm.edges_sorted) - 2 * len(edges)
        raise BodyMeshError(f"not a closed surface: {bad} edges are open or shared by more "
                            f"than two triangles, beyond hole filling (holes of up to "
                            f"{_MAX_HOLE_EDGES} edges are filled); close the mesh first",
                            file=file)
    if not tm.is_winding_consistent:
        raise BodyMeshError("the surface has no consistent outside (non-orientable)",
                            file=file)
    if tm.volume < 0:
        tm.invert()
    v = np.asarray(tm.vertices, dtype=np.float64)
    faces_out = np.asarray(tm.faces, dtype=np.int64)
    meta = {"source": str(file) if file else "arrays", "units": unit,
            "units_guessed": units is None, "scale_to_m": scale, "up": up,
            "up_guessed": guessed}
    v = _centred(v)
    heading = _heading(v, faces_out)
    meta["facing_known"] = heading is not None
    if heading is not None and abs(heading) > _HEADING_TOLERANCE:
        # placement puts fronts at +Z and left sides at +X: a body facing elsewhere got
        # its garments back to front (-Z), or twisted (45 degrees), and passed
        turn = trimesh.transformations.rotation_matrix(np.radians(-heading), (0, 1, 0))
        v = v @ turn[:3, :3].T
        meta["turned_deg"] = round(heading, 1)
    try:
        meas, lm = measure(v, faces_out)
        return Body(v, faces_out, name=name, measurements=meas, landmarks=lm, meta=meta)
    except LandmarkError as exc:
        raise BodyMeshError(f"no standing human body in an A-pose: {exc}", file=file,
                            place=f"landmark '{exc.landmark}'") from None


def _centred(v: np.ndarray) -> np.ndarray:
    """Vertices (n, 3) [m] moved so that the feet are on y = 0 and, when the box round the
    body is centred more than :data:`_NEAR_AXIS` from the Y axis, that it is centred on it
    (a body near the axis stays where it is: a built-in body, 3.8 cm off it, written out
    and read back came back 3.8 cm away, and its own drape read 136 vertices inside it)."""
    centre = 0.5 * (v.min(axis=0) + v.max(axis=0))
    shift = np.array([0.0, v[:, 1].min(), 0.0])
    if np.hypot(centre[0], centre[2]) > _NEAR_AXIS:
        shift[[0, 2]] = centre[[0, 2]]
    return v - shift


def body_notes(body: Body) -> list[tuple[str, str]]:
    """What was guessed or done in reading a body mesh, as (level, sentence) pairs
    (``"note"`` or ``"warning"``) for the front ends to say: a unit guessed from the height
    (a wrong guess changes every result), a body taken as facing +Z where nothing told,
    or turned to face it."""
    meta, out = body.meta, []
    if meta.get("units_guessed"):
        out.append(("note", f"units guessed as '{meta['units']}' from the body's height "
                            f"({np.ptp(body.vertices[:, 1]):.2f} m); give the units if that "
                            "is wrong"))
    if meta.get("facing_known") is False:
        out.append(("warning", "cannot tell which way the body faces (no feet, and its head "
                               "not forward of its calves); taken as facing +Z as read: turn "
                               "it in the file if garments go on backwards"))
    if meta.get("turned_deg") is not None:
        out.append(("note", f"the body faced {meta['turned_deg']:+.1f}° from +Z about the "
                            "vertical (where its toes point, or its head without feet); "
                            "turned to face +Z, where garments are placed"))
    return out


def load_body_mesh(path, *, units: str | None = None, up: str | None = None) -> Body:
    """Load a body mesh file (OBJ, PLY, STL, GLB/glTF, OFF) as a :class:`Body`, or a body
    saved as ``.npz`` (:func:`patternfit.body.builtin.save_body`: metres, Y up, measured).

    Scenes are merged into one mesh. See :func:`body_from_arrays` for units, ``up`` and the
    checks; the file may take at most 200 bytes per allowed vertex. Errors are
    :class:`BodyMeshError` naming the file.
    """
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".")
    if fmt == "npz":
        from .builtin import read_body  # builtin imports this module for BodyMeshError

        if units not in (None, "m") or up not in (None, "y"):
            raise ValueError("units, up: a saved body (.npz) is in metres with Y up")
        return read_body(path)
    if fmt not in _FORMATS:
        raise BodyMeshError(f"unsupported mesh format {path.suffix!r}; use "
                            f"{', '.join('.' + x for x in _FORMATS)} or .npz", file=path)
    if not path.exists():
        raise BodyMeshError("no such file", file=path)
    data = read_bytes_capped(path, limit=_FILE_BYTES_PER_VERTEX * limits.body_vertices,
                             error=BodyMeshError)
    try:
        mesh = trimesh.load(io.BytesIO(data), file_type=fmt, force="mesh", process=False,
                            resolver=_Resolver(path.parent))
    except Exception as exc:  # trimesh raises many kinds for unreadable files
        raise BodyMeshError(f"cannot read the mesh: {exc}", file=path) from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise BodyMeshError("empty mesh: no triangles", file=path)
    return body_from_arrays(mesh.vertices, mesh.faces, units=units, up=up, name=path.stem,
                            file=path)


class _Resolver(trimesh.resolvers.FilePathResolver):
    """The files a mesh file names (an OBJ's materials, a glTF's buffers), read as every
    input is: inside the mesh's folder, regular files only (an OBJ naming a pipe as its
    material library waited on it for ever), within the size limit of a body file."""

    def get(self, name: str) -> bytes:
        return read_bytes_capped(self.absolute(name),
                                 limit=_FILE_BYTES_PER_VERTEX * limits.body_vertices,
                                 error=BodyMeshError)


def save_body_mesh(body: Body, path) -> Path:
    """Write ``body`` as a mesh file; the format follows the suffix (.ply, .obj, .stl, .glb).
    Vertices are written in metres, Y up."""
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".")
    if fmt not in ("ply", "obj", "stl", "glb", "gltf", "off"):
        raise ValueError(f"path: unsupported mesh format {path.suffix!r}; use .ply, .obj, "
                         ".stl or .glb")
    data = body.to_trimesh().export(file_type=fmt)
    if isinstance(data, str):
        data = data.encode("utf-8")
    if isinstance(data, dict):
        raise ValueError("path: .gltf writes several files; use .glb")
    return atomic_write_bytes(path, data)
