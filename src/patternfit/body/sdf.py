"""Signed distance field of a static body on a regular grid, with a trilinear lookup and a
C1 (quadratic B-spline) reading for contact.

Distances are in metres, negative inside the body. The grid is ``values[i, j, k]`` at the
point ``origin + spacing * (i, j, k)``.

:meth:`DistanceField.from_mesh` computes the field exactly (libigl's signed distance, sign by
the fast winding number, so it stays right on slightly open or self-touching meshes) in a
narrow band around the surface, and fills the far field by trilinear upsampling of an exact
grid four times coarser. Results are cached on disk, keyed by a hash of the mesh and the
grid settings and of the code that built them (see :func:`cache_dir`).

The C1 reading (:func:`smooth_distance_at`): the trilinear interpolant of the grid
(:func:`trilinear_at`) is continuous, but its gradient jumps across every cell face. A
vertex pressed hard against the body (cloth pulled tight over a shoulder) then sits on a
face where the contact force turns by a few percent, and no position balances the
membrane's pull: the 2K coat on the heavy man kept one vertex at 46-225 times its weight of
residual force for thousands of Newton steps while the line search found no descent. The
quadratic B-spline of the same grid values has a continuous gradient, so the contact force
is continuous and the force balance exists.

The B-spline smooths the grid: its value is ``d + h^2/8 lap(d)`` to second order, with ``h``
the grid step and ``lap(d)`` the sum of the body surface's principal curvatures, i.e. about
0.1 mm outward on a 5 cm limb at a 5 mm grid, small against the 3 mm contact margin.
"""

from __future__ import annotations

import functools
import hashlib
import io
import os
from importlib.metadata import PackageNotFoundError
from importlib.metadata import version as _version
from pathlib import Path

import igl
import numba
import numpy as np
import platformdirs

from ..files import atomic_write_bytes

#: ratio of the far-field grid step to the fine step
_COARSE = 4


@functools.cache  # the code and the versions do not change while the process runs
def _build_id() -> bytes:
    """What a cached field is built by: this module's source and the versions of libigl and
    patternfit. Part of the cache key, so that a field cached by other code (an upgrade, a
    local change) is built anew rather than read, without a version number to remember to
    bump."""
    try:
        source = Path(__file__).read_bytes()
    except OSError:  # no readable source (a frozen build): the versions stand in
        source = b""
    versions = []
    for package in ("libigl", "patternfit"):
        try:
            versions.append(_version(package).encode())
        except PackageNotFoundError:  # run from a source tree, or installed under another name
            versions.append(b"")
    return b"\0".join([source, *versions])


def cache_dir() -> Path:
    """Directory for cached distance fields: ``$PATTERNFIT_CACHE`` if set, else the user's
    cache directory (``~/.cache/patternfit`` on Linux)."""
    env = os.environ.get("PATTERNFIT_CACHE")
    if env:
        return Path(env)
    return Path(platformdirs.user_cache_dir("patternfit"))


@numba.njit(cache=True, nogil=True, inline="always")
def _clamp(p, origin, spacing, n):
    """Grid coordinate of ``p`` along one axis, clamped to the grid, and the squared distance
    beyond the grid [m^2] (as ``DistanceField.query`` counts it)."""
    q = (p - origin) / spacing
    out = 0.0
    if q < 0.0:
        out = (q * spacing) ** 2
        q = 0.0
    elif q > n - 1:
        out = ((q - (n - 1)) * spacing) ** 2
        q = float(n - 1)
    return q, out


@numba.njit(cache=True, nogil=True, inline="always")
def _cell(p, origin, spacing, n):
    """Cell index and fraction along one axis, clamped to the grid, and the squared distance
    beyond the grid."""
    q, out = _clamp(p, origin, spacing, n)
    k = min(int(q), n - 2)
    return k, q - k, out


@numba.njit(cache=True, nogil=True, inline="always")
def trilinear_at(values, origin, spacing, p):
    """Distance [m] and gradient (x, y, z) of the trilinear interpolant at point ``p`` (3,);
    compiled, so that simulation kernels call it per vertex."""
    nx, ny, nz = values.shape
    x0, fx, ox = _cell(p[0], origin[0], spacing, nx)
    y0, fy, oy = _cell(p[1], origin[1], spacing, ny)
    z0, fz, oz = _cell(p[2], origin[2], spacing, nz)
    c000 = values[x0, y0, z0]
    c100 = values[x0 + 1, y0, z0]
    c010 = values[x0, y0 + 1, z0]
    c110 = values[x0 + 1, y0 + 1, z0]
    c001 = values[x0, y0, z0 + 1]
    c101 = values[x0 + 1, y0, z0 + 1]
    c011 = values[x0, y0 + 1, z0 + 1]
    c111 = values[x0 + 1, y0 + 1, z0 + 1]
    c00 = c000 * (1 - fx) + c100 * fx
    c10 = c010 * (1 - fx) + c110 * fx
    c01 = c001 * (1 - fx) + c101 * fx
    c11 = c011 * (1 - fx) + c111 * fx
    c0 = c00 * (1 - fy) + c10 * fy
    c1 = c01 * (1 - fy) + c11 * fy
    # beyond the grid the body is at least this much further away
    d = c0 * (1 - fz) + c1 * fz + np.sqrt(ox + oy + oz)
    gx = (((c100 - c000) * (1 - fy) + (c110 - c010) * fy) * (1 - fz)
          + ((c101 - c001) * (1 - fy) + (c111 - c011) * fy) * fz)
    gy = (c10 - c00) * (1 - fz) + (c11 - c01) * fz
    gz = c1 - c0
    return d, gx / spacing, gy / spacing, gz / spacing


@numba.njit(cache=True, nogil=True)
def sdf_query(values, origin, spacing, x):
    """Distances (n,) and gradients (n, 3) of the trilinear field at points ``x`` (n, 3)."""
    n = x.shape[0]
    d = np.empty(n)
    g = np.empty((n, 3))
    for i in range(n):
        d[i], g[i, 0], g[i, 1], g[i, 2] = trilinear_at(values, origin, spacing, x[i])
    return d, g


@numba.njit(cache=True, nogil=True, inline="always")
def _axis(p, origin, spacing, n):
    """Nearest node (its lower neighbour is the stencil's first node, clamped so that the
    three-node stencil lies in the grid), offset ``t`` in [-1/2, 1/2] grid steps from it
    (beyond the clamp: the grid's end), and the squared distance beyond the grid [m^2]."""
    q, out = _clamp(p, origin, spacing, n)
    i = min(max(int(np.floor(q + 0.5)), 1), n - 2)
    t = min(max(q - i, -0.5), 0.5)
    return i - 1, t, out


@numba.njit(cache=True, nogil=True, inline="always")
def _weights(t):
    """Quadratic B-spline weights of the three nodes around offset ``t`` and their
    derivatives [per grid step]: two 3-tuples (tuples, not arrays: this runs per contact
    lookup, tens of millions of times a drape, and an array is a heap allocation)."""
    return ((0.5 * (0.5 - t) ** 2, 0.75 - t * t, 0.5 * (0.5 + t) ** 2),
            (t - 0.5, -2.0 * t, t + 0.5))


@numba.njit(cache=True, nogil=True)
def smooth_distance_at(values, origin, spacing, p):
    """Distance [m] and gradient (x, y, z) of the quadratic B-spline of the grid at ``p``
    (3,); beyond the grid, the distance to the grid is added (as the trilinear lookup)."""
    nx, ny, nz = values.shape
    i0, tx, ox = _axis(p[0], origin[0], spacing, nx)
    j0, ty, oy = _axis(p[1], origin[1], spacing, ny)
    k0, tz, oz = _axis(p[2], origin[2], spacing, nz)
    wx, dx = _weights(tx)
    wy, dy = _weights(ty)
    wz, dz = _weights(tz)
    d = 0.0
    gx = 0.0
    gy = 0.0
    gz = 0.0
    # separably: along z, then y, then x
    for a in range(3):
        s0 = 0.0  # sum over b, c of wy wz v
        sy = 0.0  # ... dy wz v
        sz = 0.0  # ... wy dz v
        for b in range(3):
            r0 = 0.0
            rz = 0.0
            for c in range(3):
                v = values[i0 + a, j0 + b, k0 + c]
                r0 += wz[c] * v
                rz += dz[c] * v
            s0 += wy[b] * r0
            sy += dy[b] * r0
            sz += wy[b] * rz
        d += wx[a] * s0
        gx += dx[a] * s0
        gy += wx[a] * sy
        gz += wx[a] * sz
    d += np.sqrt(ox + oy + oz)
    return d, gx / spacing, gy / spacing, gz / spacing


@numba.njit(cache=True, nogil=True)
def smooth_sdf_query(values, origin, spacing, x):
    """Distances (n,) [m] and gradients (n, 3) of the B-spline field at points ``x`` (n, 3)."""
    n = x.shape[0]
    d = np.empty(n)
    g = np.empty((n, 3))
    for i in range(n):
        d[i], g[i, 0], g[i, 1], g[i, 2] = smooth_distance_at(values, origin, spacing, x[i])
    return d, g


@numba.njit(cache=True, nogil=True)
def _upsample(coarse, factor):
    """Trilinear upsampling of a grid by an integer factor (node i*factor = coarse node i)."""
    cx, cy, cz = coarse.shape
    out = np.empty(((cx - 1) * factor + 1, (cy - 1) * factor + 1, (cz - 1) * factor + 1),
                   dtype=np.float32)
    nx, ny, nz = out.shape
    for i in range(nx):
        i0 = min(i // factor, cx - 2)
        fx = i / factor - i0
        for j in range(ny):
            j0 = min(j // factor, cy - 2)
            fy = j / factor - j0
            for k in range(nz):
                k0 = min(k // factor, cz - 2)
                fz = k / factor - k0
                c00 = coarse[i0, j0, k0] * (1 - fx) + coarse[i0 + 1, j0, k0] * fx
                c01 = coarse[i0, j0, k0 + 1] * (1 - fx) + coarse[i0 + 1, j0, k0 + 1] * fx
                c10 = coarse[i0, j0 + 1, k0] * (1 - fx) + coarse[i0 + 1, j0 + 1, k0] * fx
                c11 = (coarse[i0, j0 + 1, k0 + 1] * (1 - fx)
                       + coarse[i0 + 1, j0 + 1, k0 + 1] * fx)
                c0 = c00 * (1 - fy) + c10 * fy
                c1 = c01 * (1 - fy) + c11 * fy
                out[i, j, k] = c0 * (1 - fz) + c1 * fz
    return out


def signed_distance(points, vertices, faces) -> np.ndarray:
    """Exact signed distance from ``points`` (n, 3) [m] to a triangle mesh, negative inside.

    The sign comes from the fast winding number, so it is right for closed meshes and robust
    to small holes and self-intersections. Returns (n,) float [m].
    """
    p = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 3)
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    f = np.ascontiguousarray(faces, dtype=np.int64)
    if len(p) == 0:
        return np.zeros(0)
    d = igl.signed_distance(p, v, f, igl.SIGNED_DISTANCE_TYPE_FAST_WINDING_NUMBER)[0]
    return np.asarray(d, dtype=np.float64)


def _grid_points(origin, spacing, shape, mask=None) -> np.ndarray:
    if mask is None:
        idx = np.indices(shape).reshape(3, -1).T
    else:
        idx = np.argwhere(mask)
    return origin + spacing * idx


class DistanceField:
    """A signed distance grid with trilinear interpolation and its gradient.

    Parameters
    ----------
    origin : (3,) float
        Position of grid node (0, 0, 0) [m].
    spacing : float
        Grid step [m].
    values : (nx, ny, nz) float
        Signed distance at the nodes [m], negative inside.
    """

    def __init__(self, origin, spacing: float, values):
        self.origin = np.asanyarray(origin, dtype=np.float64).reshape(3)
        self.spacing = float(spacing)
        self.values = np.ascontiguousarray(values, dtype=np.float32)
        if self.values.ndim != 3 or min(self.values.shape) < 2:
            raise ValueError(f"values: expected a 3-D grid at least 2 nodes wide, "
                             f"got shape {self.values.shape}")
        if not self.spacing > 0:
            raise ValueError(f"spacing: must be positive, got {spacing}")

    @property
    def shape(self) -> tuple[int, int, int]:
        return self.values.shape

    @property
    def upper(self) -> np.ndarray:
        """(3,) float: position of the last grid node [m]."""
        return self.origin + self.spacing * (np.array(self.values.shape) - 1)

    def query(self, points) -> tuple[np.ndarray, np.ndarray]:
        """Distance and gradient at ``points``.

        Parameters
        ----------
        points : (n, 3) float
            Query positions [m]. A point outside the grid takes the value at the nearest
            border point plus its distance to the grid box (a lower bound of the truth there).

        Returns
        -------
        distance : (n,) float
            Signed distance [m], negative inside.
        gradient : (n, 3) float
            Gradient of the interpolated distance (approximately the outward unit normal).
        """
        p = np.ascontiguousarray(np.asanyarray(points, dtype=np.float64).reshape(-1, 3))
        return sdf_query(self.values, self.origin, self.spacing, p)

    @classmethod
    def from_mesh(cls, vertices, faces, *, spacing: float = 0.005, padding: float = 0.1,
                  band: float = 0.02, solids=(), cache: bool = True) -> "DistanceField":
        """Signed distance field of a closed triangle mesh, or of its union with ``solids``.

        Parameters
        ----------
        vertices : (n, 3) float
            Mesh vertices [m].
        faces : (m, 3) int
            Triangles, outward (counter-clockwise seen from outside).
        spacing : float
            Grid step [m].
        padding : float
            Margin added around the mesh's bounding box [m].
        band : float
            Nodes at most this far from the surface [m] get the exact distance; further out
            the value is interpolated from an exact grid ``4 * spacing`` wide, whose error is
            at most that grid's half cell diagonal.
        solids : sequence of (vertices (k, 3) float, faces (j, 3) int)
            Closed meshes [m] inside the mesh's bounding box joined to it: the field is the
            smaller of the distances (exact outside the union; inside, the depth below the
            nearer surface). The body's mittens (:mod:`patternfit.body.hands`).
        cache : bool
            Read and write the result in :func:`cache_dir`, keyed by a hash of the inputs.
        """
        v = np.asanyarray(vertices, dtype=np.float64)
        f = np.asanyarray(faces)
        if v.ndim != 2 or v.shape[1] != 3 or len(v) == 0:
            raise ValueError(f"vertices: expected a non-empty (n, 3) array, got {v.shape}")
        if f.ndim != 2 or f.shape[1] != 3 or len(f) == 0:
            raise ValueError(f"faces: expected a non-empty (m, 3) array, got {f.shape}")
        f = f.astype(np.int64)
        if not np.isfinite(v).all():
            raise ValueError("vertices: contain NaN or infinite values")
        if f.min() < 0 or f.max() >= len(v):
            raise ValueError("faces: index a vertex that does not exist")
        if not spacing > 0 or not padding >= 0 or not band > 0:
            raise ValueError("spacing and band must be positive and padding non-negative")
        solids = [(np.ascontiguousarray(sv, dtype=np.float64),
                   np.ascontiguousarray(sf, dtype=np.int64)) for sv, sf in solids]

        key = hashlib.sha256()
        key.update(np.ascontiguousarray(v).tobytes())
        key.update(np.ascontiguousarray(f).tobytes())
        for sv, sf in solids:
            key.update(sv.tobytes())
            key.update(sf.tobytes())
        key.update(np.array([spacing, padding, band], dtype=np.float64).tobytes())
        key.update(_build_id())
        path = cache_dir() / f"sdf-{key.hexdigest()[:24]}.npz"
        if cache and path.exists():
            try:
                with np.load(path, allow_pickle=False) as z:
                    field = cls(z["origin"], float(z["spacing"]), z["values"])
                if field.spacing == spacing and np.isfinite(field.values).all():
                    return field
            except Exception:  # zipfile and numpy raise many kinds for a damaged file
                pass  # a damaged cache file is recomputed and overwritten

        field = cls._build(v, f, spacing, padding, band, solids)
        if cache:
            buf = io.BytesIO()
            np.savez(buf, origin=field.origin, spacing=field.spacing, values=field.values)
            try:
                atomic_write_bytes(path, buf.getvalue())
            except OSError:
                pass  # an unwritable cache only costs time
        return field

    @classmethod
    def _build(cls, v, f, spacing, padding, band, solids) -> "DistanceField":
        lo = v.min(axis=0) - padding
        hi = v.max(axis=0) + padding
        coarse_step = _COARSE * spacing
        coarse_shape = tuple(int(n) for n in np.ceil((hi - lo) / coarse_step).astype(int) + 1)
        points = _grid_points(lo, coarse_step, coarse_shape)
        coarse = _union_distance(points, v, f, solids, np.inf)
        values = _upsample(coarse.reshape(coarse_shape).astype(np.float32), _COARSE)
        # The upsampled value is within a half coarse diagonal of the truth.
        near = np.abs(values) < band + 0.5 * np.sqrt(3.0) * coarse_step
        values[near] = _union_distance(_grid_points(lo, spacing, values.shape, near), v, f,
                                       solids, band + np.sqrt(3.0) * coarse_step)
        return cls(lo, spacing, values)


def _union_distance(points, v, f, solids, reach) -> np.ndarray:
    """Signed distance (n,) [m] from ``points`` (n, 3) [m] to the mesh ``v``, ``f`` joined
    with ``solids``, each looked up only within ``reach`` [m] of its bounding box: beyond,
    it is farther than the mesh (``reach`` at least the mesh's distance there)."""
    d = signed_distance(points, v, f)
    for sv, sf in solids:
        inside = np.all((points > sv.min(axis=0) - reach) & (points < sv.max(axis=0) + reach),
                        axis=1)
        d[inside] = np.minimum(d[inside], signed_distance(points[inside], sv, sf))
    return d
