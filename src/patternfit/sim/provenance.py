"""What a saved drape is a state of, and how near rest it ended: the digests of its
positions, mesh, body and fabric and the fabric itself, kept in its contact state
(``contact.npz``), so that a state read back moved, edited, on another body or in another
fabric is not taken for a rest there (a skirt at rest on one body read "equilibrium: true"
on another, 92 of its vertices inside it) and is judged in the fabric it was draped in;
and its residual's rms and p99."""

from __future__ import annotations

import json
from dataclasses import asdict

import numpy as np

from ..errors import FabricError, GarmentFileError
from ..mesh.store import (MESH_DIGEST, POSITIONS_DIGEST, digest, mesh_digest,
                          positions_digest, saved_for_other)
from .fabrics import Fabric

#: the arrays of ``contact.npz`` that hold the body's and the fabric's digests ...
BODY_DIGEST, FABRIC_DIGEST = "body_sha256", "fabric_sha256"
#: ... and the fabric itself, as JSON in SI units
FABRIC_JSON = "fabric_json"
#: ... and why the drape failed its checks, as a JSON list of sentences (empty: it passed)
DRAPE_REASONS = "drape_reasons"
#: the longest fabric JSON or list of reasons read back [characters]
_FABRIC_CHARS = 4096


def body_digest(body) -> str:
    """SHA-256 (hex) of a :class:`patternfit.body.Body`'s surface (vertices [m], faces)."""
    return digest(np.asarray(body.vertices, np.float64), np.asarray(body.faces, np.int64))


def fabric_digest(fabric: Fabric) -> str:
    """SHA-256 (hex) of a fabric's constants (its name left out)."""
    values = asdict(fabric)
    del values["name"]
    return digest(np.array([float(values[k]) for k in sorted(values)]))


def saved_failure(contact: dict[str, np.ndarray] | None, *, file=None) -> list[str] | None:
    """Why the drape that saved ``contact`` (read from ``file``) failed its checks (on the
    body it was draped on: fell, slid, not at rest ...), an empty list when it passed, None
    when it does not say; one that is not a list of sentences is a
    :class:`~patternfit.errors.GarmentFileError` naming ``file`` and the array."""
    if contact is None or DRAPE_REASONS not in contact:
        return None
    a = np.asarray(contact[DRAPE_REASONS])
    try:
        if a.dtype.kind != "U" or a.size != 1 or len(str(a.item())) > _FABRIC_CHARS:
            raise ValueError
        reasons = json.loads(str(a.item()))
        if not isinstance(reasons, list) or not all(isinstance(r, str) for r in reasons):
            raise ValueError
    except ValueError:
        raise GarmentFileError(f"expected a JSON list of sentences of at most {_FABRIC_CHARS} "
                               "characters", file=file, place=f"array '{DRAPE_REASONS}'") \
            from None
    return reasons


def saved_provenance(positions, mesh, body, fabric: Fabric) -> dict[str, np.ndarray]:
    """The arrays a drape ending at ``positions`` (n, 3) [m] of ``mesh`` on ``body`` in
    ``fabric`` adds to its saved contact state: their digests (``mesh`` and ``body`` None:
    not known, left out) and the fabric. Only a drape writes them: a contact state read back
    and written again keeps its own (stamped anew, one without them passed as a rest of an
    edited pattern)."""
    out = {POSITIONS_DIGEST: np.array(positions_digest(positions)),
           FABRIC_DIGEST: np.array(fabric_digest(fabric)),
           FABRIC_JSON: np.array(json.dumps(fabric.to_dict()))}
    if mesh is not None:
        out[MESH_DIGEST] = np.array(mesh_digest(mesh))
    if body is not None:
        out[BODY_DIGEST] = np.array(body_digest(body))
    return out


def draped_for(body=None, fabric: Fabric | None = None) -> dict[str, tuple[str, str]]:
    """The digests a saved contact state must hold to be a rest on ``body`` in ``fabric``
    (each None: not compared), for :func:`patternfit.mesh.store.saved_rest`."""
    out = {}
    if body is not None:
        out[BODY_DIGEST] = (body_digest(body), f"another body than {body.name}")
    if fabric is not None:
        out[FABRIC_DIGEST] = (fabric_digest(fabric), f"another fabric than {fabric.name}")
    return out


def not_draped_for(contact: dict[str, np.ndarray] | None, body=None,
                   fabric: Fabric | None = None) -> list[str]:
    """What a saved contact state was not draped on or in, of ``body`` and ``fabric``, in
    words ("another body than female_heavy"); empty when it does not say."""
    return [] if contact is None else saved_for_other(contact, draped_for(body, fabric))


def saved_fabric(contact: dict[str, np.ndarray] | None, *, file=None) -> Fabric | None:
    """The fabric a saved contact state (read from ``file``) was draped in, or None when it
    does not say; one that is not a valid fabric is a
    :class:`~patternfit.errors.GarmentFileError` naming ``file`` and the array."""
    if contact is None or FABRIC_JSON not in contact:
        return None
    place = f"array '{FABRIC_JSON}'"
    a = np.asarray(contact[FABRIC_JSON])
    if a.dtype.kind != "U" or a.size != 1 or len(str(a.item())) > _FABRIC_CHARS:
        raise GarmentFileError(f"expected one text of at most {_FABRIC_CHARS} characters, "
                               f"got {a.dtype} {a.shape}", file=file, place=place)
    try:
        values = json.loads(str(a.item()))
        if not isinstance(values, dict):
            raise ValueError("not an object")
        fabric = Fabric(**values)
    except FabricError as exc:
        raise GarmentFileError(f"not a valid fabric: {exc}", file=file, place=place) from None
    except (ValueError, TypeError) as exc:
        raise GarmentFileError(f"not a fabric in JSON: {exc}", file=file, place=place) \
            from None
    if FABRIC_DIGEST in contact and str(np.asarray(contact[FABRIC_DIGEST])) \
            != fabric_digest(fabric):
        # one edited by hand (3 times heavier) was used while the report named the old one
        raise GarmentFileError(f"not the fabric of the digest '{FABRIC_DIGEST}' beside it "
                               "(edited since it was saved?)", file=file, place=place)
    return fabric


def saved_residual(contact: dict[str, np.ndarray] | None, *,
                   file=None) -> tuple[float, float] | None:
    """The residual (rms, p99) of |F_i| / (m_i g) [-] the drape that saved ``contact``
    (read from ``file``) ended at, or None when it does not say; a value that is not one
    finite number >= 0 is a :class:`~patternfit.errors.GarmentFileError` naming ``file``
    and the array."""
    if contact is None or "residual_rms" not in contact or "residual_p99" not in contact:
        return None
    out = []
    for name in ("residual_rms", "residual_p99"):
        a = np.asarray(contact[name])
        if a.dtype.kind not in "fiu" or a.size != 1 or not np.isfinite(a).all() \
                or float(a.item()) < 0:
            raise GarmentFileError(f"expected one finite number >= 0, got {a.dtype} {a.shape}",
                                   file=file, place=f"array '{name}'")
        out.append(float(a.item()))
    return out[0], out[1]
