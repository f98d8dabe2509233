"""Load any body mesh (OBJ, PLY, STL, GLB/glTF, ... through trimesh) and write bodies out.

A loaded body is brought to patternfit's frame: metres, Y up, feet on y = 0, centred on the
Y axis. It must be closed: small holes are filled, anything worse is refused with a
:class:`BodyMeshError` that says what is wrong.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..constants import UNITS
from ..errors import InputError
from ..files import atomic_write_bytes
from .measure import measure
from .model import Body

#: plausible standing heights [m]: anything outside is taken as wrong units or not a body
_HEIGHT_RANGE = (0.3, 2.8)
_AXES = {"x": 0, "y": 1, "z": 2}


class BodyMeshError(InputError):
    """A body mesh that cannot be used, with the reason and the file."""


def _guess_units(extent: float, file) -> float:
    for name in ("m", "cm", "mm", "in"):
        if _HEIGHT_RANGE[0] <= extent * UNITS[name] <= _HEIGHT_RANGE[1]:
            return UNITS[name]
    raise BodyMeshError(f"absurd size: the body is {extent:.4g} units tall, which is no "
                        "human height in m, cm, mm or inches; give the units", file=file)


def _up_rotation(vertices, up: str | None) -> np.ndarray:
    """(3, 3) rotation taking the given (or guessed) up direction to +Y."""
    if up is None:
        # Standing body: the longest side is vertical, and the centre of the vertices lies
        # above mid-height (torso and head carry more surface than the legs).
        ext = np.ptp(vertices, axis=0)
        axis = int(np.argmax(ext))
        mid = 0.5 * (vertices[:, axis].min() + vertices[:, axis].max())
        sign = 1.0 if vertices[:, axis].mean() >= mid else -1.0
    else:
        key = up.strip().lower()
        sign = -1.0 if key.startswith("-") else 1.0
        key = key.lstrip("+-")
        if key not in _AXES:
            raise ValueError(f"up: expected one of x, y, z, -x, -y, -z, got {up!r}")
        axis = _AXES[key]
    src = np.zeros(3)
    src[axis] = sign
    dst = np.array([0.0, 1.0, 0.0])
    if np.allclose(src, dst):
        return np.eye(3)
    if np.allclose(src, -dst):
        return np.diag([1.0, -1.0, -1.0])
    k = np.cross(src, dst)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + kx + kx @ kx / (1.0 + src @ dst)


def body_from_arrays(vertices, faces, *, units: str | None = None, up: str | None = None,
                     name: str = "body", file=None) -> Body:
    """Check, repair and normalise a body mesh given as arrays.

    Parameters
    ----------
    vertices : (n, 3) float
        Vertices in ``units`` (guessed from the height when None).
    faces : (m, 3) int
        Triangles.
    units : str, optional
        One of ``m``, ``cm``, ``mm``, ``in``.
    up : str, optional
        The mesh's up axis (``y``, ``z``, ``-z``, ...); guessed when None.
    name : str
        Name of the body.

    Returns a :class:`Body` in metres, Y up, feet on y = 0, with measurements and landmarks
    when the pose allows (the reason is kept in ``meta["measure_error"]`` otherwise).
    """
    import trimesh

    v = np.asanyarray(vertices, dtype=np.float64)
    f = np.asanyarray(faces)
    if v.ndim != 2 or v.shape[1] != 3 or len(v) == 0 or f.ndim != 2 or len(f) == 0:
        raise BodyMeshError("empty mesh: no vertices or no triangles", file=file)
    if f.shape[1] != 3:
        raise BodyMeshError(f"faces must be triangles, got {f.shape[1]} corners", file=file)
    if not np.isfinite(v).all():
        raise BodyMeshError(f"{int((~np.isfinite(v)).any(axis=1).sum())} vertices are NaN or "
                            "infinite", file=file)
    if units is not None and units not in UNITS:
        raise ValueError(f"units: expected one of {', '.join(UNITS)}, got {units!r}")
    rot = _up_rotation(v, up)
    v = v @ rot.T
    scale = UNITS[units] if units else _guess_units(float(np.ptp(v[:, 1])), file)
    height = float(np.ptp(v[:, 1])) * scale
    if not _HEIGHT_RANGE[0] <= height <= _HEIGHT_RANGE[1]:
        raise BodyMeshError(f"absurd size: {height:.4g} m tall in {units}", file=file)
    v = v * scale

    tm = trimesh.Trimesh(v, f, process=True, validate=True)
    if not tm.is_watertight:
        trimesh.repair.fill_holes(tm)
    if not tm.is_watertight:
        edges = trimesh.grouping.group_rows(tm.edges_sorted, require_count=2)
        bad = len(tm.edges_sorted) - 2 * len(edges)
        raise BodyMeshError(f"not a closed surface: {bad} edges are open or shared by more "
                            "than two triangles, beyond hole filling; close the mesh first",
                            file=file)
    trimesh.repair.fix_winding(tm)
    if tm.volume < 0:
        tm.invert()
    v = np.asarray(tm.vertices, dtype=np.float64)
    v -= [0.5 * (v[:, 0].min() + v[:, 0].max()), v[:, 1].min(),
          0.5 * (v[:, 2].min() + v[:, 2].max())]
    faces_out = np.asarray(tm.faces, dtype=np.int64)
    meta = {"source": str(file) if file else "arrays", "units": units or "guessed",
            "scale_to_m": scale}
    try:
        meas, lm = measure(v, faces_out)
    except ValueError as exc:
        meas, lm = {}, {}
        meta["measure_error"] = str(exc)
    return Body(v, faces_out, name=name, measurements=meas, landmarks=lm, meta=meta)


def load_body_mesh(path, *, units: str | None = None, up: str | None = None) -> Body:
    """Load a body mesh file (OBJ, PLY, STL, GLB/glTF, OFF, ...) as a :class:`Body`.

    Scenes are merged into one mesh. See :func:`body_from_arrays` for units, ``up`` and the
    checks; errors are :class:`BodyMeshError` naming the file.
    """
    import trimesh

    path = Path(path)
    if not path.is_file():
        raise BodyMeshError("no such file", file=path)
    try:
        mesh = trimesh.load(path, force="mesh", process=False)
    except Exception as exc:  # trimesh raises many kinds for unreadable files
        raise BodyMeshError(f"cannot read the mesh: {exc}", file=path) from exc
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise BodyMeshError("empty mesh: no triangles", file=path)
    return body_from_arrays(mesh.vertices, mesh.faces, units=units, up=up, name=path.stem,
                            file=path)


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
