"""Built-in bodies shipped with patternfit (compressed NumPy files, no torch needed).

Six anny bodies: ``female_thin``, ``female_average``, ``female_heavy``, ``male_thin``,
``male_average``, ``male_heavy``, and the paper's names as aliases ("fat man", "thin woman",
"thin man"); and body sets in sub-folders, such as ``population`` (women's and men's bodies
spanning a size chart, XS to XXL, for fitting a size range). Provenance and licence:
``docs/bodies.md``.
"""

from __future__ import annotations

import io
import json
from importlib.resources import as_file, files
from pathlib import Path

import numpy as np

from ..constants import limits
from ..files import atomic_write_bytes, parse_json_text, read_npz
from .measure import LandmarkError
from .mesh_io import BodyMeshError
from .model import Body

#: the paper's body names (Table 2) and friendly spellings
ALIASES = {"fat man": "male_heavy", "thin woman": "female_thin", "thin man": "male_thin",
           "fat woman": "female_heavy", "man": "male_average", "woman": "female_average"}


def _dir():
    return files("patternfit") / "data" / "bodies"


#: size words a body set's names may end with (``women_xs``), listed in this order
_SIZE_WORDS = ("xxs", "xs", "s", "m", "l", "xl", "xxl", "xxxl")


def _in_size_order(name: str):
    stem, _, size = name.rpartition("_")
    return (stem, _SIZE_WORDS.index(size), "") if size in _SIZE_WORDS else (name, -1, name)


def _names(folder) -> list[str]:
    """The bodies in ``folder`` by name, a common stem's sizes from small to large."""
    return sorted((p.name[:-4] for p in folder.iterdir() if p.name.endswith(".npz")),
                  key=_in_size_order)


def list_bodies() -> list[str]:
    """Names of the built-in bodies, sorted (not those of the body sets)."""
    return _names(_dir())


def list_body_sets() -> dict[str, list[str]]:
    """The body sets: set name -> names of its bodies, sorted (sizes from small to large:
    ``women_xs``, ``women_s``...); ``"builtin"`` is
    :func:`list_bodies`, every other set is a sub-folder of the shipped bodies."""
    sets = {"builtin": list_bodies()}
    for p in sorted(_dir().iterdir(), key=lambda p: p.name):
        if p.is_dir() and _names(p):
            sets[p.name] = _names(p)
    return sets


def _resource(canon: str):
    """The shipped file of body ``canon``: a built-in, else a member of a body set."""
    res = _dir() / f"{canon}.npz"
    if not res.is_file():
        for name, members in list_body_sets().items():
            if name != "builtin" and canon in members:
                return _dir() / name / f"{canon}.npz"
    return res


def _canonical(name: str) -> str:
    key = " ".join(str(name).strip().lower().replace("-", " ").replace("_", " ").split())
    return ALIASES.get(key, key.replace(" ", "_"))


def load_body(name: str) -> Body:
    """The built-in body ``name`` (or an alias such as ``"fat man"``), or a body of a body
    set (:func:`list_body_sets`).

    Returns a :class:`Body` with vertices (n, 3) [m], Y up, feet on y = 0, facing +Z, and its
    stored measurements [m] and landmarks [m]. Raises ``ValueError`` naming the known bodies
    when ``name`` is not one of them.
    """
    canon = _canonical(name)
    res = _resource(canon)
    if not res.is_file():
        sets = [s for s in list_body_sets() if s != "builtin"]
        raise ValueError(f"name: no built-in body {name!r}; known: {', '.join(list_bodies())} "
                         f"(aliases: {', '.join(sorted(ALIASES))}; body sets: "
                         f"{', '.join(sets) or 'none'}, listed by `patternfit bodies --set`)")
    with as_file(res) as path:
        return read_body(path, name=canon)


#: the largest body file [bytes], unpacked: float32 vertices and int32 faces (about twice as
#: many as vertices) take 36 bytes per vertex; landmarks and measurements are small
_BODY_BYTES = 36 * limits.body_vertices + (1 << 20)


def read_body(path, *, name: str | None = None) -> Body:
    """A body from a ``.npz`` file written by :func:`save_body`: vertices (n, 3) and
    landmarks [m], faces (m, 3), measurements [m].

    Raises :class:`~patternfit.body.mesh_io.BodyMeshError` naming the file and the array
    (or the landmark) when it is unreadable, damaged, no body (an array missing, of the
    wrong kind or shape, NaN, a face index out of range, more than ``limits.body_vertices``
    vertices) or lacks a landmark or measurement.
    """
    z = read_npz(path, limit=_BODY_BYTES, error=BodyMeshError)

    def bad(key, why):
        return BodyMeshError(why, file=path, place=f"array '{key}'")

    for key, kind, ndim in _BODY_LAYOUT:
        if key not in z:
            raise bad(key, "missing (not a body saved by patternfit)")
        if z[key].dtype.kind not in kind or z[key].ndim != ndim:
            raise bad(key, f"expected a {ndim}-d array of kind {kind!r}, got {z[key].dtype} "
                           f"{z[key].shape}")
    v, f = z["vertices"].astype(np.float64), z["faces"].astype(np.int64)
    if v.shape[1] != 3 or f.shape[1] != 3 or not len(v) or not len(f):
        raise bad("vertices" if v.shape[1] != 3 or not len(v) else "faces",
                  f"expected (n, 3) vertices and (m, 3) faces, got {v.shape}, {f.shape}")
    if len(v) > limits.body_vertices:
        raise bad("vertices", f"{len(v)} vertices, more than the limit of "
                              f"{limits.body_vertices}")
    if not np.isfinite(v).all():
        raise bad("vertices", "NaN or infinite coordinates")
    if f.min() < 0 or f.max() >= len(v):
        raise bad("faces", f"vertex index out of range: the body has {len(v)} vertices")
    names, values = z["measurement_names"], z["measurement_values"]
    if names.shape != values.shape:
        raise bad("measurement_values", f"{values.shape} values for {names.shape} names")
    meta = parse_json_text(str(z["meta"]), file=path, error=BodyMeshError)
    if not isinstance(meta, dict):
        raise bad("meta", "expected a JSON object")
    landmarks = {k[len("landmark_"):]: a for k, a in z.items() if k.startswith("landmark_")}
    stem = Path(str(path)).stem
    try:
        return Body(v, f, name=name or str(meta.get("name", stem)),
                    measurements=dict(zip(names.tolist(), values.tolist())),
                    landmarks=landmarks, meta=meta)
    except LandmarkError as exc:
        raise BodyMeshError(str(exc), file=path, place=f"landmark '{exc.landmark}'") from None
    except ValueError as exc:  # a landmark that is no array of numbers
        raise BodyMeshError(str(exc), file=path) from None


#: what :func:`read_body` expects of each array: name, dtype kinds, dimensions
_BODY_LAYOUT = (("vertices", "f", 2), ("faces", "iu", 2), ("measurement_names", "U", 1),
                ("measurement_values", "f", 1), ("meta", "U", 0))


def save_body(body: Body, path) -> Path:
    """Write ``body`` in the built-in format (compressed ``.npz``, float32 vertices)."""
    buf = io.BytesIO()
    meta = {"name": body.name, **body.meta}
    names = sorted(body.measurements)
    np.savez_compressed(
        buf, vertices=body.vertices.astype(np.float32), faces=body.faces.astype(np.int32),
        measurement_names=np.array(names), meta=np.array(json.dumps(meta)),
        measurement_values=np.array([body.measurements[k] for k in names]),
        **{f"landmark_{k}": np.asarray(p, dtype=np.float32) for k, p in body.landmarks.items()})
    return atomic_write_bytes(path, buf.getvalue())
