"""A saved garment: a folder holding ``pattern.json``, ``mesh.npz`` and, once placed or
draped, ``positions.npy`` (the 3D state, (n, 3) float [m]) and, for a drape, ``contact.npz``
(the solver's contact state there, which a drape started from the folder continues:
``patternfit.sim.state.ContactState.saved_arrays``; this module stores it unread).

The files are written as one step (:func:`patternfit.files.atomic_write_group`): after a
crash a reader sees the old garment or the new one, never a new pattern beside an old mesh.
Reading checks every array; anything damaged is a :class:`~patternfit.errors.GarmentFileError`
naming the file and the array. :func:`read_npz` and :func:`read_npy` are the checked NumPy
readers every saved-array format uses.
"""

from __future__ import annotations

import hashlib
import io
import os
from pathlib import Path

import numpy as np

from ..constants import limits, tol
from ..errors import GarmentFileError, InputError
from ..arguments import array, instance, path
from ..files import atomic_write_group, dumps_finite_json, read_npy, read_npz
from ..pattern.io import load_pattern, pattern_to_dict
from ..pattern.model import Pattern
from ..pattern.validate import check_pattern
from .garment import GarmentMesh

PATTERN, MESH, POSITIONS, CONTACT = "pattern.json", "mesh.npz", "positions.npy", "contact.npz"
#: the array of ``contact.npz`` that holds the digest of the positions it was saved with
POSITIONS_DIGEST = "positions_sha256"
#: ... and of the mesh (flat rest shapes, triangles, grain, seams) its drape solved
MESH_DIGEST = "mesh_sha256"
#: the garment folder inside a drape's or a fit's output folder
GARMENT = "garment"

def _pattern_bytes(pattern: Pattern, units: str) -> bytes:
    check_pattern(pattern)
    return (dumps_finite_json(pattern_to_dict(pattern, units=units), indent=1)
            + "\n").encode("utf-8")


def _positions_bytes(positions, mesh: GarmentMesh) -> bytes:
    x = array(positions, "positions", shape=(mesh.n_vertices, 3))
    buf = io.BytesIO()
    np.save(buf, x)
    return buf.getvalue()


def save_garment(folder, pattern: Pattern, mesh: GarmentMesh, positions=None, *,
                 contact: dict[str, np.ndarray] | None = None) -> Path:
    """Write the pattern, its mesh and optionally a 3D state (n, 3) [m] into ``folder``, as
    one step; ``contact`` (named arrays: a drape's contact state at ``positions``, with the
    digests of what it is a state of, ``Drape.saved_contact(mesh)``) goes with that state,
    as it is. An older ``positions.npy`` or ``contact.npz`` that is not replaced is removed
    (it belongs to the old mesh or state).

    A ``mesh`` that is not a mesh of ``pattern`` (:func:`foreign_mesh`) is refused with a
    ``ValueError``, as reading the folder back would refuse it; ``folder`` naming a file is
    an :class:`~patternfit.errors.InputError`."""
    folder = path(folder, "folder", what="a folder path")
    instance(pattern, Pattern, "pattern", "a Pattern")
    instance(mesh, GarmentMesh, "mesh", "a GarmentMesh")
    why = foreign_mesh(pattern, mesh)
    if why:
        raise ValueError(f"mesh: not a mesh of this pattern: {why}")
    if folder.exists() and not folder.is_dir():
        raise InputError("is a file: expected a folder for the garment", file=folder)
    files = {folder / PATTERN: _pattern_bytes(pattern, "m"), folder / MESH: mesh.to_bytes()}
    if positions is not None:
        files[folder / POSITIONS] = _positions_bytes(positions, mesh)
    if positions is not None and contact is not None:
        files[folder / CONTACT] = contact_bytes(contact)
    # removed first: a crash then leaves the old garment without a state, never the new
    # garment with the old one's
    for name in (POSITIONS, CONTACT):
        if folder / name not in files:
            (folder / name).unlink(missing_ok=True)
    atomic_write_group(files)
    return folder


def contact_bytes(contact: dict[str, np.ndarray]) -> bytes:
    """A drape's contact state (named arrays, ``Drape.saved_contact``) as the bytes of a
    compressed ``.npz`` file, as :func:`load_contact` reads it back."""
    buf = io.BytesIO()
    np.savez_compressed(buf, **{k: np.asarray(v) for k, v in contact.items()})
    return buf.getvalue()


def load_contact(folder) -> dict[str, np.ndarray] | None:
    """The contact state saved with a garment folder's positions (:func:`save_garment`), as
    named arrays, or None when it has none; a damaged or oversized ``contact.npz`` is a
    :class:`~patternfit.errors.GarmentFileError` naming the file and the array. The arrays
    are not checked against a model here (the solver does)."""
    file = Path(folder) / CONTACT
    if not file.exists() or not (Path(folder) / POSITIONS).exists():
        return None
    return read_npz(file, limit=limits.mesh_bytes, error=GarmentFileError)


def digest(*arrays) -> str:
    """SHA-256 (hex) of arrays, each by its dtype, shape and bytes."""
    h = hashlib.sha256()
    for a in arrays:
        a = np.ascontiguousarray(a)
        h.update(f"{a.dtype.str}{a.shape}".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def positions_digest(positions) -> str:
    """SHA-256 (hex) of positions (n, 3) [m] as float64: what ``contact.npz`` was saved
    with (:func:`save_garment`)."""
    return hashlib.sha256(np.ascontiguousarray(positions, dtype=np.float64).tobytes()).hexdigest()


def mesh_digest(mesh: GarmentMesh) -> str:
    """SHA-256 (hex) of what a drape solves of ``mesh``: its flat rest shapes, triangles,
    grain lines and seam pairs."""
    return digest(np.asarray(mesh.vertices, np.float64), np.asarray(mesh.triangles, np.int64),
                  np.asarray(mesh.grain, np.float64), np.asarray(mesh.seam_pairs, np.int64))


def saved_for_other(contact: dict[str, np.ndarray], wanted: dict[str, tuple[str, str]]
                    ) -> list[str]:
    """What ``contact`` says it was saved for other than ``wanted`` (digest name ->
    (digest, what it stands for in words)), in those words; a digest it does not hold says
    nothing."""
    return [what for name, (value, what) in wanted.items()
            if name in contact and str(np.asarray(contact[name])) != value]


def saved_rest(contact: dict[str, np.ndarray] | None, positions, *, mesh=None,
               draped_for: dict[str, tuple[str, str]] | None = None,
               file=None) -> tuple[bool | None, str | None]:
    """Whether the drape that saved ``contact`` (:func:`load_contact`, read from ``file``)
    ended at rest at ``positions`` (n, 3) [m] of ``mesh``: its ``at_rest`` flag, or None
    with the reason in words when that is not known: no contact state or flag, positions
    other than those it was saved with (a state moved since read "at rest" and needed 981
    iterations to get back there), another mesh (a pattern edited in place), or a digest in
    ``draped_for`` (name -> (digest, "another body"), e.g. the body and fabric:
    :func:`patternfit.sim.provenance.draped_for`) other than the saved one; a rest whose
    file does not hold one of those digests (an older file) is not known either, while its
    "not at rest" stands. A flag that is not one true or false (a string "False", NaN,
    several values) is a :class:`~patternfit.errors.GarmentFileError` naming ``file`` and
    the array."""
    if contact is None or "at_rest" not in contact:
        return None, f"no {CONTACT} of these positions"
    wanted = {POSITIONS_DIGEST: (positions_digest(positions), "other positions (moved since)")}
    if mesh is not None:
        wanted[MESH_DIGEST] = (mesh_digest(mesh), "another mesh (the pattern was edited since)")
    wanted.update(draped_for or {})
    other = saved_for_other(contact, wanted)
    if other:
        return None, f"{CONTACT} was saved for {other[0]}"
    flag = np.asarray(contact["at_rest"])
    if flag.dtype.kind != "b" or flag.size != 1:
        raise GarmentFileError(f"expected one true or false, got {flag.dtype} {flag.shape}",
                               file=file, place="array 'at_rest'")
    missing = [name for name in wanted if name not in contact]
    if flag.item() and missing:
        # an older file: an edited pattern's state and another body's read as its rest
        return None, f"{CONTACT} does not say what it is a rest of ({', '.join(missing)})"
    return bool(flag.item()), None


def replace_pattern_and_mesh(pattern_path, pattern: Pattern, mesh_path, mesh: GarmentMesh, *,
                             units: str = "m") -> list[Path]:
    """Write ``pattern`` (lengths in ``units``) to ``pattern_path`` and its ``mesh`` to
    ``mesh_path`` (any two paths) as one step: after a crash at any point the next read of
    either sees both old files or both new ones. The pattern is validated first, so a
    refused pattern changes neither file. Returns the two paths."""
    return atomic_write_group({Path(pattern_path): _pattern_bytes(pattern, units),
                               Path(mesh_path): mesh.to_bytes()})


def garment_folder(folder) -> Path:
    """``folder``, or the ``garment/`` folder in it when it is the output folder of a drape
    or a fit (which holds its garment folder under that name, and no mesh of its own)."""
    folder = Path(folder)
    inner = folder / GARMENT
    return inner if not os.path.lexists(folder / MESH) and inner.is_dir() else folder


def load_garment(folder) -> tuple[Pattern, GarmentMesh, np.ndarray | None]:
    """Read a folder written by :func:`save_garment` (or the output folder holding it:
    :func:`garment_folder`): (pattern, mesh, positions (n, 3) [m] or None).

    Raises :class:`~patternfit.errors.GarmentFileError` naming the file and the array for a
    missing, damaged or inconsistent ``mesh.npz`` or ``positions.npy`` (see
    :meth:`GarmentMesh.load`; positions must be finite and within ``limits.extent`` of the
    origin), and :class:`~patternfit.pattern.errors.PatternError` for the pattern.
    """
    folder = garment_folder(folder)
    if not os.path.lexists(folder):
        raise GarmentFileError("does not exist", file=folder)
    if not folder.is_dir():
        raise GarmentFileError("is a file, not a garment folder", file=folder)
    if not os.path.lexists(folder / MESH):  # one that is there but no file is read, and said
        raise GarmentFileError(f"no {MESH} here: not a saved garment folder", file=folder)
    mesh = GarmentMesh.load(folder / MESH)
    pattern = load_pattern(folder / PATTERN)
    positions = None
    if (folder / POSITIONS).exists():
        file = folder / POSITIONS
        positions = read_npy(file, limit=limits.positions_bytes, error=GarmentFileError)
        if positions.dtype.kind != "f" or positions.shape != (mesh.n_vertices, 3):
            raise GarmentFileError(f"expected ({mesh.n_vertices}, 3) floats for the mesh's "
                                   f"vertices, got {positions.shape} of {positions.dtype}",
                                   file=file)
        positions = positions.astype(np.float64)
        if not np.isfinite(positions).all():
            raise GarmentFileError("holds NaN or infinite positions", file=file)
        if np.abs(positions).max(initial=0.0) > limits.extent:
            raise GarmentFileError(f"positions beyond {limits.extent} m from the origin",
                                   file=file)
    if tuple(p.name for p in pattern.panels) != mesh.panel_names:
        raise GarmentFileError(f"{PATTERN} and {MESH} do not belong together (panels differ)",
                               file=folder)
    why = foreign_mesh(pattern, mesh)
    if why:
        raise GarmentFileError(f"{MESH} is not a mesh of {PATTERN}: {why}", file=folder)
    return pattern, mesh, positions


def foreign_mesh(pattern: Pattern, mesh: GarmentMesh) -> str | None:
    """Why ``mesh`` is not a mesh of ``pattern`` (the same panel names are not enough: a
    skirt's sizes and a dress share them), or None: an edge the pattern lacks, a boundary
    vertex farther than ``tol.mesh_on_edge`` from its edge's point at its arc-length
    fraction, other seams, or a seam pair whose vertex is not on its side's edge."""
    edges = {(p.name, e.name): e for p in pattern.panels for lp in p.loops for e in lp.edges}
    for k, name in enumerate(mesh.edge_names):
        if name not in edges:
            return f"its edge {name[0]}.{name[1]} is not one of the pattern's"
        on = np.flatnonzero(mesh.boundary_edge == k)
        flat = mesh.vertices[mesh.boundary_vertices[on]]
        off = float(np.abs(edges[name].point_at(mesh.boundary_param[on]) - flat).max(initial=0))
        if off > tol.mesh_on_edge:
            return (f"its vertices on {name[0]}.{name[1]} lie up to {off * 1e3:.1f} mm from "
                    "that edge (another size or garment)")
    if mesh.seam_names != tuple(s.name for s in pattern.seams):
        return "its seams are not the pattern's"
    # a seam pair joins a vertex of each side's edge (a corner lies on the edge ending there
    # too: a dart's tip is sewn to itself)
    before = {(p.name, e.name): (p.name, lp.edges[i - 1].name)
              for p in pattern.panels for lp in p.loops for i, e in enumerate(lp.edges)}
    lies_on: dict[int, set] = {}
    for v, k, t in zip(mesh.boundary_vertices, mesh.boundary_edge, mesh.boundary_param):
        lies_on.setdefault(int(v), set()).update(
            [mesh.edge_names[k], *([before[mesh.edge_names[k]]] if t == 0.0 else [])])
    for (a, b), k in zip(mesh.seam_pairs, mesh.seam_index):
        seam = pattern.seams[k]
        for v, side in ((a, seam.a), (b, seam.b)):
            if (side.panel, side.edge) not in lies_on.get(int(v), ()):
                return (f"seam '{seam.name}' joins vertex {int(v)}, which is not on "
                        f"{side.panel}.{side.edge}")
    return None
