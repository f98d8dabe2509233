"""Write the malformed-input corpus of ``tests/test_bad_inputs.py`` (dev only)::

    python tools/make_bad_corpus.py

It (re)writes ``tests/data/bad/body/``, ``tests/data/bad/fabric/`` and
``tests/data/bad/garment/`` and touches nothing else under ``tests/data/bad/`` (``pattern/``,
``dxf/`` and ``garmentcode/`` are another corpus). Every file it writes must be refused by
the public loaders (``load_body_mesh``, ``load_fabric``/``get_fabric``, ``load_garment``)
with an ``InputError`` naming the file:

* ``body/``: meshes that are no human (sphere, cube, cylinder, plane), NaN vertices, bad
  face indices, absurd sizes in the guessed unit, garbage and truncated files, and bodies
  saved as ``.npz`` (the layout of ``patternfit.body.builtin.save_body``) with an array
  missing, pickled, of the wrong kind, NaN, out of range, or without landmarks;
* ``fabric/``: JSON fabrics with a field missing, unknown, of the wrong type, outside its
  plausible range, and documents that are no JSON object (NaN, non-UTF-8, deep nesting,
  truncated, ...). A file named ``<field>_...`` is refused at that field;
* ``garment/``: saved garment folders (``pattern.json``, ``mesh.npz``, ``positions.npy``)
  made from one valid garment (a 0.4 m square meshed with 16 triangles, written by
  ``save_garment``) with one file damaged: a ``mesh_<what>`` folder damages ``mesh.npz``, a
  ``positions_<what>`` folder ``positions.npy``, a ``pattern_<what>`` folder
  ``pattern.json``.

The output is byte-for-byte reproducible: no randomness without a fixed seed, and every
zip member (``.npz``) carries a fixed timestamp. Every file stays under 50 kB.
"""

from __future__ import annotations

import io
import json
import shutil
import struct
import sys
import tempfile
import zipfile
from pathlib import Path

import numpy as np
import trimesh

ROOT = Path(__file__).resolve().parents[1]
BAD = ROOT / "tests" / "data" / "bad"
#: the folders this script owns (and only these are cleared)
KINDS = ("body", "fabric", "garment")
#: the largest corpus file [bytes] (``test_corpus_is_there_and_small``)
MAX_BYTES = 50_000

GOOD_FABRIC = {"name": "poplin", "density": 0.2, "stretch_warp": 5e3, "stretch_weft": 3e3,
               "shear": 30, "bending": 5e-6, "friction": 0.3, "thickness": 3e-4}

_EPOCH = (1980, 1, 1, 0, 0, 0)


# ----------------------------------------------------------------------------- writers
def _zip(members: dict[str, bytes], *, compress: bool = True) -> bytes:
    """A zip archive of ``members`` (name -> bytes) with fixed timestamps."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        for name, data in members.items():
            info = zipfile.ZipInfo(name, date_time=_EPOCH)
            info.compress_type = zipfile.ZIP_DEFLATED if compress else zipfile.ZIP_STORED
            info.external_attr = 0o644 << 16
            z.writestr(info, data)
    return buf.getvalue()


def _npy(array) -> bytes:
    buf = io.BytesIO()
    np.save(buf, np.asanyarray(array), allow_pickle=True)
    return buf.getvalue()


def _npz(arrays: dict, *, compress: bool = True) -> bytes:
    """What ``np.savez(_compressed)`` writes, in the given member order, reproducibly."""
    return _zip({f"{k}.npy": v if isinstance(v, bytes) else _npy(v)
                 for k, v in arrays.items()}, compress=compress)


def _npy_with_header(array, *, shape=None, version=(1, 0)) -> bytes:
    """``array`` as ``.npy`` bytes whose header claims ``shape`` (a lie) or whose magic says
    ``version``."""
    a = np.ascontiguousarray(array)
    header = {"descr": np.lib.format.dtype_to_descr(a.dtype), "fortran_order": False,
              "shape": tuple(a.shape if shape is None else shape)}
    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, header)
    head = buf.getvalue()
    if version != (1, 0):
        head = np.lib.format.magic(1, 0)[:6] + bytes(version) + head[8:]
    return head + a.tobytes()


def _obj(v, f, fmt=".6f") -> bytes:
    lines = ["v " + " ".join(format(c, fmt) for c in p) for p in v]
    lines += ["f " + " ".join(str(i + 1) for i in t) for t in f]
    return ("\n".join(lines) + "\n").encode()


def _ply_header(v, f, fmt: str, vtype="float") -> bytes:
    return (f"ply\nformat {fmt} 1.0\nelement vertex {len(v)}\nproperty {vtype} x\n"
            f"property {vtype} y\nproperty {vtype} z\nelement face {len(f)}\n"
            "property list uchar int vertex_indices\nend_header\n").encode()


def _rows(v, f) -> str:
    """Vertex rows ``x y z`` and face rows ``3 i j k`` (PLY and OFF text)."""
    return ("".join(" ".join(f"{c:.6f}" for c in p) + "\n" for p in v)
            + "".join("3 " + " ".join(str(i) for i in t) + "\n" for t in f))


def _ply_ascii(v, f) -> bytes:
    return _ply_header(v, f, "ascii") + _rows(v, f).encode()


def _ply_binary(v, f) -> bytes:
    v = np.asarray(v, dtype="<f4")
    rec = np.zeros(len(f), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    rec["n"], rec["i"] = 3, f
    return _ply_header(v, f, "binary_little_endian") + v.tobytes() + rec.tobytes()


def _stl(v, f) -> bytes:
    v, f = np.asarray(v, dtype=np.float64), np.asarray(f)
    tri = v[f]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
    rec = np.zeros(len(f), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"], rec["v"] = n, tri
    return b"patternfit bad corpus".ljust(80, b" ") + struct.pack("<I", len(f)) + rec.tobytes()


def _off(v, f) -> bytes:
    return (f"OFF\n{len(v)} {len(f)} 0\n" + _rows(v, f)).encode()


# ----------------------------------------------------------------------------- bodies
def _sphere(radius=0.85, centre=(0.0, 0.85, 0.0), subdivisions=2):
    s = trimesh.creation.icosphere(subdivisions=subdivisions, radius=radius)
    return np.asarray(s.vertices) + centre, np.asarray(s.faces)


def _coarse_body(cell=0.06):
    """A built-in body (1.78 m) clustered to ``cell`` [m] (about 630 vertices): a human
    shape small enough for the corpus (not closed, but refused for its size first)."""
    from patternfit.body import load_body

    b = load_body("male_thin")
    q = np.round(b.vertices / cell).astype(np.int64)
    _, inv = np.unique(q, axis=0, return_inverse=True)
    inv = inv.ravel()
    v = np.zeros((inv.max() + 1, 3))
    np.add.at(v, inv, b.vertices)
    v /= np.bincount(inv)[:, None]
    f = inv[b.faces]
    f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])]
    _, first = np.unique(np.sort(f, axis=1), axis=0, return_index=True)
    return v, f[np.sort(first)]


def _body_npz(v, f, *, landmarks=None, **override) -> dict:
    """The arrays of a body ``.npz`` (the layout of ``save_body``), in its order."""
    names = np.array(["height"])
    arrays = {"vertices": np.asarray(v, dtype=np.float32),
              "faces": np.asarray(f, dtype=np.int32),
              "measurement_names": names, "meta": np.array(json.dumps({"name": "sphere"})),
              "measurement_values": np.array([1.7])}
    arrays.update({f"landmark_{k}": np.asarray(p, dtype=np.float32)
                   for k, p in (landmarks or {}).items()})
    for k, a in override.items():
        if a is None:
            arrays.pop(k)
        else:
            arrays[k] = a
    return arrays


def make_bodies(out: Path) -> None:
    sv, sf = _sphere()
    box = trimesh.creation.box(extents=(1.7, 1.7, 1.7))
    bv, bf = np.asarray(box.vertices) + (0, 0.85, 0), np.asarray(box.faces)
    cyl = trimesh.creation.cylinder(radius=0.15, height=1.7, sections=32)
    cv, cf = np.asarray(cyl.vertices), np.asarray(cyl.faces)
    # a flat 0.4 x 1.7 m sheet, 4 x 17 cells: its border (42 edges) is no hole to fill
    gx, gy = np.meshgrid(np.linspace(0, 0.4, 5), np.linspace(0, 1.7, 18))
    pv = np.c_[gx.ravel(), gy.ravel(), np.zeros(gx.size)]
    ids = np.arange(gx.size).reshape(gx.shape)
    a, b, c, d = ids[:-1, :-1].ravel(), ids[:-1, 1:].ravel(), ids[1:, 1:].ravel(), \
        ids[1:, :-1].ravel()
    pf = np.r_[np.c_[a, b, c], np.c_[a, c, d]]
    hv, hf = _coarse_body()
    garbage = np.random.default_rng(20240501).bytes(4000)

    nan_v = sv.copy()
    nan_v[7] = np.nan
    inf_v = sv.copy()
    inf_v[3, 1] = np.inf
    bad_f = sf.copy()
    bad_f[5, 2] = len(sv) + 100
    neg_f = sf.copy()
    neg_f[0, 0] = -1
    two_apart = np.r_[_sphere(0.3, (-0.35, 0.85, 0))[0], _sphere(0.3, (0.35, 0.85, 0))[0]]
    two_apart[:, 1] = (two_apart[:, 1] - 0.55) * 1.7 / 0.6  # two tall eggs side by side
    two_f = np.r_[sf, sf + len(sv)]
    fin = np.array([[0, 0, 0], [0.3, 0, 0], [0, 1.7, 0], [0, 0, 0.3], [0.3, 1.7, 0.3]])
    fin_f = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2], [1, 2, 4], [2, 3, 4],
                      [0, 2, 4]])  # the edge 0-2 is shared by four triangles

    files = {
        # no human: the first landmark the search needs is missing
        "sphere.obj": _obj(sv, sf),
        "cube.ply": _ply_ascii(bv, bf),
        "cylinder.stl": _stl(cv, cf),
        "two_eggs_apart.off": _off(two_apart, two_f),
        "sphere.glb": _glb(sv, sf),
        # not a closed surface
        "plane.stl": _stl(pv, pf),
        "non_manifold_fin.obj": _obj(fin, fin_f),
        # numbers
        "nan_vertex.obj": _obj(nan_v, sf),
        "inf_vertex.ply": _ply_binary(inf_v, sf),
        "face_index_out_of_range.ply": _ply_ascii(sv, bad_f),
        "face_index_negative.obj": _obj(sv, sf).replace(b"\nf 1 ", b"\nf -999 ", 1),
        "all_vertices_one_point.obj": _obj(np.zeros((4, 3)), sf[:4] % 4),
        # sizes: a human 1.78 m tall in the wrong units, spheres of no adult's size
        "body_inches_times_ten.ply": _ply_binary(hv / 0.0254 * 10, hf),
        "body_hundredth_of_inches.obj": _obj(hv / 0.000254, hf, ".1f"),
        "sphere_30_units.obj": _obj(sv * 30 / 1.7, sf),
        "sphere_micrometre.stl": _stl(sv * 1e-6, sf),
        # files that are no mesh
        "empty.obj": b"",
        "garbage.stl": garbage,
        "garbage.ply": b"ply\nformat binary_little_endian 1.0\n" + garbage[:2000],
        "truncated.ply": _ply_binary(sv, sf)[:2500],
        "glb_header_only.glb": b"glTF\x02\x00\x00\x00" + bytes(40),
        "archive.zip": _zip({"sphere.obj": _obj(sv, sf)}),
        "sphere.txt": _obj(sv, sf),
        # bodies saved as .npz
        "sphere_no_landmarks.npz": _npz(_body_npz(sv, sf)),
        "face_index_out_of_range.npz": _npz(_body_npz(sv, bad_f)),
        "face_index_negative.npz": _npz(_body_npz(sv, neg_f)),
        "faces_float.npz": _npz(_body_npz(sv, sf, faces=sf.astype(np.float64))),
        "nan_vertices.npz": _npz(_body_npz(nan_v, sf)),
        "vertices_2d.npz": _npz(_body_npz(sv[:, :2], sf)),
        "not_a_body.npz": _npz({"x": np.arange(10.0), "y": np.arange(10.0)}),
        "pickled_vertices.npz": _npz(_body_npz(sv, sf, vertices=np.array(
            [list(p) for p in sv[:4]] + [None], dtype=object))),
        "meta_not_json.npz": _npz(_body_npz(sv, sf, meta=np.array("{'name': sphere"))),
        "measurements_mismatch.npz": _npz(_body_npz(
            sv, sf, measurement_values=np.array([1.7, 0.9, 0.8]))),
        "landmark_text.npz": _npz(_body_npz(sv, sf, landmarks={"neck_base": [0, 1.5, 0]},
                                            landmark_neck_base=np.array(["neck"]))),
        "truncated.npz": _npz(_body_npz(sv, sf))[:1500],
        "npz_garbage.npz": b"PK\x03\x04" + garbage[:1000],
    }
    for name, data in files.items():
        (out / name).write_bytes(data)


def _glb(v, f) -> bytes:
    """A mesh as binary glTF (trimesh's writer)."""
    return bytes(trimesh.Trimesh(v, f, process=False).export(file_type="glb"))


# ----------------------------------------------------------------------------- fabrics
#: a field to leave out
_DROP = object()


def make_fabrics(out: Path) -> None:
    def fab(**change):
        d = dict(GOOD_FABRIC)
        for k, v in change.items():
            if v is _DROP:
                d.pop(k)
            else:
                d[k] = v
        return (json.dumps(d, indent=1) + "\n").encode()

    good = fab().decode()
    deep = '{"name": "deep", "density": ' + "[" * 100 + "0.2" + "]" * 100 + "}"
    files = {
        # one field wrong (the file's first word names the field)
        "density_missing.json": fab(density=_DROP),
        "density_string.json": fab(density="0.2"),
        "density_null.json": fab(density=None),
        "density_true.json": fab(density=True),
        "density_list.json": fab(density=[0.2]),
        "density_grams.json": fab(density=200.0),
        "density_negative.json": fab(density=-0.2),
        "friction_negative.json": fab(friction=-0.1),
        "friction_too_high.json": fab(friction=3.5),
        "friction_object.json": fab(friction={"static": 0.3}),
        "thickness_millimetres.json": fab(thickness=0.3),
        "thickness_zero.json": fab(thickness=0),
        "shear_missing.json": fab(shear=_DROP),
        "shear_string.json": fab(shear="30 N/m"),
        "shear_huge.json": fab(shear=1e9),
        "name_empty.json": fab(name=""),
        "name_blank.json": fab(name="   "),
        "name_number.json": fab(name=42),
        "name_too_long.json": fab(name="x" * 300),
        "stretch_warp_zero.json": fab(stretch_warp=0),
        "stretch_weft_huge.json": fab(stretch_weft=1e12),
        "bending_and_bending_warp.json": fab(bending_warp=5e-6),
        "bending_warp_negative.json": fab(bending=_DROP, bending_warp=-1e-6,
                                          bending_weft=5e-6),
        "bending_weft_missing.json": fab(bending=_DROP, bending_warp=5e-6),
        "unknown_field.json": fab(colour="red"),
        # documents that are no fabric object
        "not_an_object.json": b'[{"name": "poplin", "density": 0.2}]\n',
        "string_document.json": b'"denim"\n',
        "empty.json": b"",
        "truncated.json": good[: len(good) // 2].encode(),
        "trailing_comma.json": good.replace("\n}", ",\n}").encode(),
        "nan_density.json": good.replace('"density": 0.2', '"density": NaN').encode(),
        "infinity_shear.json": good.replace('"shear": 30', '"shear": Infinity').encode(),
        "overflow_number.json": good.replace('"density": 0.2', '"density": 1e400').encode(),
        "huge_integer.json": good.replace('"shear": 30', '"shear": ' + "9" * 400).encode(),
        "non_utf8.json": fab().replace(b'"poplin"', b'"caf\xe9"'),  # Latin-1
        "utf8_bom.json": b"\xef\xbb\xbf" + good.encode(),
        "deep_nesting.json": deep.encode(),
        "binary_garbage.json": np.random.default_rng(7).bytes(600),
        "fabric.txt": b"density 0.2\nshear 30\n",
    }
    for name, data in files.items():
        (out / name).write_bytes(data)


# ----------------------------------------------------------------------------- garments
def _square_garment(folder: Path):
    """A valid garment folder written by the package: (pattern.json, mesh.npz,
    positions.npy) bytes and the mesh arrays in their file order."""
    sys.path.insert(0, str(ROOT / "tests"))
    from scenes import rectangle_panel

    from patternfit.mesh import mesh_pattern
    from patternfit.mesh.store import MESH, PATTERN, POSITIONS, save_garment
    from patternfit.pattern import Pattern

    pattern = Pattern("square", (rectangle_panel("front", 0.4, 0.4),))
    mesh = mesh_pattern(pattern, triangles=16)
    x = np.c_[mesh.vertices, np.zeros(mesh.n_vertices)]
    save_garment(folder / "square", pattern, mesh, x)
    two = Pattern("two", (rectangle_panel("front", 0.4, 0.4),
                          rectangle_panel("back", 0.4, 0.4, origin=(0.6, 0.0))))
    save_garment(folder / "two", two, mesh_pattern(two, triangles=32))
    p, m, pos = ((folder / "square" / n).read_bytes() for n in (PATTERN, MESH, POSITIONS))
    with zipfile.ZipFile(io.BytesIO(m)) as z:
        members = {i.filename: z.read(i) for i in z.infolist()}
        arrays = {k.removesuffix(".npy"): np.load(io.BytesIO(v)) for k, v in members.items()}
    # the package's bytes, re-zipped with fixed timestamps
    return p, _zip(members), pos, arrays, (folder / "two" / PATTERN).read_bytes()


def make_garments(out: Path) -> None:
    from patternfit.mesh.store import MESH, PATTERN, POSITIONS

    with tempfile.TemporaryDirectory() as tmp:
        P, M, X, A, P_two = _square_garment(Path(tmp))
    x = np.load(io.BytesIO(X))
    n = len(A["vertices"])

    def mesh(compress=True, **change):
        arrays = dict(A)
        for k, v in change.items():
            if v is None:
                arrays.pop(k)
            else:
                arrays[k] = v
        return _npz(arrays, compress=compress)

    def changed(key, fn):
        a = A[key].copy()
        fn(a)
        return a

    # a byte of the stored (uncompressed) vertices flipped: the member's CRC fails
    stored = bytearray(mesh(compress=False))
    at = bytes(stored).index(A["vertices"].tobytes()) + 11
    stored[at] ^= 0x40
    # a member that claims to unpack to 2 GB
    size_lies = bytearray(M)
    cd = bytes(size_lies).index(b"PK\x01\x02")
    size_lies[cd + 24:cd + 28] = struct.pack("<I", 0x7FFFFFFF)
    text_names = np.array(["front bottom", "front right", "front top", "front left"])
    far = x.copy()
    far[2, 0] = 1e3
    nan_x, inf_x = x.copy(), x.copy()
    nan_x[4, 1] = np.nan
    inf_x[0, 2] = -np.inf

    meshes = {
        "mesh_missing": None,
        "mesh_empty": b"",
        "mesh_not_zip": b"not a zip archive\n" * 10,
        "mesh_is_pattern_json": P,
        "mesh_truncated": M[: len(M) // 2],
        "mesh_crc_damaged": bytes(stored),
        "mesh_size_lies": bytes(size_lies),
        "mesh_missing_triangles": mesh(triangles=None),
        "mesh_nan_vertices": mesh(vertices=changed("vertices",
                                                   lambda a: a.__setitem__((3, 0), np.nan))),
        "mesh_vertices_far": mesh(vertices=A["vertices"] * 100),
        "mesh_vertices_int": mesh(vertices=np.round(A["vertices"] * 1000).astype(np.int64)),
        "mesh_vertices_3d": mesh(vertices=np.c_[A["vertices"], np.zeros(n)]),
        "mesh_vertices_scalar": mesh(vertices=np.array(0.4)),
        "mesh_pickled_array": mesh(vertices=np.array([tuple(p) for p in A["vertices"]],
                                                     dtype=object)),
        "mesh_pickled_extra": mesh(extra=np.array([{"os": "system"}], dtype=object)),
        "mesh_header_lies": mesh(vertices=_npy_with_header(A["vertices"], shape=(n + 1, 2))),
        "mesh_npy_version_9": mesh(vertices=_npy_with_header(A["vertices"], version=(9, 0))),
        "mesh_triangles_float": mesh(triangles=A["triangles"].astype(np.float64)),
        "mesh_triangle_index_out_of_range": mesh(triangles=changed(
            "triangles", lambda a: a.__setitem__((2, 1), n + 5))),
        "mesh_triangle_index_negative": mesh(triangles=changed(
            "triangles", lambda a: a.__setitem__((0, 0), -1))),
        "mesh_uint64_huge_index": mesh(triangles=_huge_uint64(A["triangles"])),
        "mesh_triangle_panel_short": mesh(triangle_panel=A["triangle_panel"][:-3]),
        "mesh_vertex_panel_out_of_range": mesh(vertex_panel=A["vertex_panel"] + 3),
        "mesh_boundary_edge_out_of_range": mesh(boundary_edge=changed(
            "boundary_edge", lambda a: a.__setitem__(1, 40))),
        "mesh_grain_zero": mesh(grain=np.zeros((1, 2))),
        "mesh_edge_names_bad": mesh(edge_names=text_names),
        "mesh_panel_names_numbers": mesh(panel_names=np.array([0])),
        "mesh_infinite_param": mesh(boundary_param=changed(
            "boundary_param", lambda a: a.__setitem__(2, np.inf))),
        "mesh_param_above_one": mesh(boundary_param=changed(
            "boundary_param", lambda a: a.__setitem__(2, 1.5))),
        "mesh_other_panel_name": mesh(panel_names=np.array(["back"])),
    }
    for name, m in meshes.items():
        folder = out / name
        folder.mkdir()
        (folder / PATTERN).write_bytes(P)
        if m is not None:
            (folder / MESH).write_bytes(m)

    positions = {
        "positions_empty": b"",
        "positions_garbage": b"\x93NUMPY garbage" + bytes(50),
        "positions_truncated": X[:-20],
        "positions_header_lies": _npy_with_header(x, shape=(n + 4, 3)),
        "positions_is_npz": _npz({"positions": x}),
        "positions_pickled": _npy(np.array([list(p) for p in x], dtype=object)),
        "positions_nan": _npy(nan_x),
        "positions_infinite": _npy(inf_x),
        "positions_far": _npy(far),
        "positions_wrong_shape": _npy(x[:, :2]),
        "positions_other_mesh": _npy(np.r_[x, x]),
        "positions_scalar": _npy(np.array(0.0)),
        "positions_int": _npy(np.round(x * 1000).astype(np.int32)),
        "positions_complex": _npy(x.astype(np.complex128)),
    }
    for name, data in positions.items():
        folder = out / name
        folder.mkdir()
        (folder / PATTERN).write_bytes(P)
        (folder / MESH).write_bytes(M)
        (folder / POSITIONS).write_bytes(data)

    for name, pattern in {"pattern_missing": None, "pattern_truncated": P[: len(P) // 2],
                          "mismatched_pattern_and_mesh": P_two}.items():
        folder = out / name
        folder.mkdir()
        (folder / MESH).write_bytes(M)
        if pattern is not None:
            (folder / PATTERN).write_bytes(pattern)


def _huge_uint64(triangles) -> np.ndarray:
    """The triangles as uint64 with one corner 2**64 - 1 (-1 when read as int64)."""
    t = triangles.astype(np.uint64)
    t[1, 2] = np.iinfo(np.uint64).max
    return t


# ----------------------------------------------------------------------------- main
def main() -> None:
    for kind in KINDS:
        folder = BAD / kind
        if folder.exists():
            shutil.rmtree(folder)
        folder.mkdir(parents=True)
    make_bodies(BAD / "body")
    make_fabrics(BAD / "fabric")
    make_garments(BAD / "garment")
    for kind in KINDS:
        files = [p for p in (BAD / kind).rglob("*") if p.is_file()]
        big = [p for p in files if p.stat().st_size >= MAX_BYTES]
        if big:
            raise SystemExit(f"too large for the corpus: {', '.join(map(str, big))}")
        print(f"{kind:8s} {len(list((BAD / kind).iterdir())):3d} entries, {len(files):3d} files,"
              f" largest {max(p.stat().st_size for p in files)} bytes")


if __name__ == "__main__":
    main()
