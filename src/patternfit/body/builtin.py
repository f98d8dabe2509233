"""Built-in bodies shipped with patternfit (compressed NumPy files, no torch needed).

Six anny bodies: ``female_thin``, ``female_average``, ``female_heavy``, ``male_thin``,
``male_average``, ``male_heavy``, and the paper's names as aliases ("fat man", "thin woman",
"thin man"). Provenance and licence: ``docs/bodies.md``.
"""

from __future__ import annotations

import io
import json
from importlib.resources import files
from pathlib import Path

import numpy as np

from ..files import atomic_write_bytes
from .model import Body

#: the paper's body names (Table 2) and friendly spellings
ALIASES = {"fat man": "male_heavy", "thin woman": "female_thin", "thin man": "male_thin",
           "fat woman": "female_heavy", "man": "male_average", "woman": "female_average"}


def _dir():
    return files("patternfit") / "data" / "bodies"


def list_bodies() -> list[str]:
    """Names of the built-in bodies, sorted."""
    return sorted(p.name[:-4] for p in _dir().iterdir() if p.name.endswith(".npz"))


def _canonical(name: str) -> str:
    key = " ".join(str(name).strip().lower().replace("-", " ").replace("_", " ").split())
    return ALIASES.get(key, key.replace(" ", "_"))


def load_body(name: str) -> Body:
    """The built-in body ``name`` (or an alias such as ``"fat man"``).

    Returns a :class:`Body` with vertices (n, 3) [m], Y up, feet on y = 0, facing +Z, and its
    stored measurements [m] and landmarks [m]. Raises ``ValueError`` naming the known bodies
    when ``name`` is not one of them.
    """
    canon = _canonical(name)
    res = _dir() / f"{canon}.npz"
    if not res.is_file():
        raise ValueError(f"name: no built-in body {name!r}; known: {', '.join(list_bodies())} "
                         f"(aliases: {', '.join(sorted(ALIASES))})")
    return read_body(res, name=canon)


def read_body(path, *, name: str | None = None) -> Body:
    """A body from a file written by :func:`save_body` (a path or package resource)."""
    with path.open("rb") as fh, np.load(io.BytesIO(fh.read())) as z:
        meas = dict(zip(z["measurement_names"].tolist(), z["measurement_values"].tolist()))
        lm = {k[len("landmark_"):]: z[k] for k in z.files if k.startswith("landmark_")}
        meta = json.loads(str(z["meta"]))
        return Body(z["vertices"], z["faces"], name=name or meta.get("name", path.stem),
                    measurements=meas, landmarks=lm, meta=meta)


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
