"""The body a garment is draped on: a closed triangle mesh with its measurements."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import trimesh

from ..arguments import array
from .hands import mittens
from .measure import LANDMARKS, MEASUREMENTS, LandmarkError
from .sdf import DistanceField


@dataclass(eq=False)
class Body:
    """A standing human body.

    Attributes
    ----------
    vertices : (n, 3) float
        Surface vertices [m], Y up, feet on y = 0; built-in bodies face +Z (left side +X).
    faces : (m, 3) int
        Triangles, counter-clockwise seen from outside (outward normals).
    name : str
        Short name (``"male_heavy"``, a file's stem, ...).
    measurements : dict of str to float
        Girths, lengths and heights [m] (see :func:`patternfit.body.measure.measure`); every
        name in :data:`~patternfit.body.measure.MEASUREMENTS` is required.
    landmarks : dict of str to array
        Points (3,) and axes (2, 3) [m] used to place panels; every name in
        :data:`~patternfit.body.measure.LANDMARKS` is required.

    Raises
    ------
    ValueError
        Arrays of the wrong shape; :class:`~patternfit.body.measure.LandmarkError` (a
        ``ValueError``) naming a required landmark or measurement that is missing or not
        finite, since placement needs every one of them.
    meta : dict
        Provenance: source, licence, generator parameters.
    """

    vertices: np.ndarray
    faces: np.ndarray
    name: str = "body"
    measurements: dict = field(default_factory=dict)
    landmarks: dict = field(default_factory=dict)
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        self.vertices = array(self.vertices, "vertices", shape=(None, 3))
        self.faces = array(self.faces, "faces", shape=(None, 3), dtype=np.int64)
        self.landmarks = {k: np.asanyarray(p, dtype=np.float64)
                          for k, p in self.landmarks.items()}
        self.measurements = {k: float(x) for k, x in self.measurements.items()}
        for k in LANDMARKS:
            p = self.landmarks.get(k)
            if p is None or p.shape not in ((3,), (2, 3)) or not np.isfinite(p).all():
                raise LandmarkError(k, f"landmarks: '{k}' is missing or not a finite point")
        for k in MEASUREMENTS:
            if not 0.0 < self.measurements.get(k, 0.0) < np.inf:
                raise LandmarkError(k, f"measurements: '{k}' is missing or not a positive "
                                       "length")
        self._fields: dict[tuple, DistanceField] = {}

    @property
    def height(self) -> float:
        """Standing height [m]."""
        return float(np.ptp(self.vertices[:, 1]))

    @property
    def floor(self) -> float:
        """Height of the soles [m], the floor the body stands on (0 in patternfit's frame)."""
        return float(self.vertices[:, 1].min())

    def distance_field(self, spacing: float = 0.005, *, padding: float = 0.1) -> DistanceField:
        """Signed distance field of the body as the cloth meets it, grid step ``spacing``
        [m], ``padding`` [m] around the body: the body joined with its :meth:`mittens`. Kept
        on the body and cached on disk (see :func:`patternfit.body.sdf.cache_dir`)."""
        key = (float(spacing), float(padding))
        if key not in self._fields:
            solids = [(m.vertices, m.faces) for m in self.mittens()]
            self._fields[key] = DistanceField.from_mesh(self.vertices, self.faces,
                                                        spacing=spacing, padding=padding,
                                                        solids=solids)
        return self._fields[key]

    def contact_field(self, spacing: float = 0.005, *, padding: float = 0.1) -> DistanceField:
        """Signed distance field [m] of what the cloth meets in a drape: the body with its
        mittens (:meth:`distance_field`, same ``spacing`` and ``padding`` [m]) standing on
        the floor, the plane y = the soles' height below which everything counts as solid.
        Without the floor a hem longer than the legs hung below the soles (the trousers M on
        female_average: 3 cm, failed as "below the feet"); standing on it, the hem rests
        on it. The floor ends with the grid, ``padding`` beyond the body's bounding box:
        a garment that slips off the body farther out still falls (``sim.stop_rule.fell``).
        The distance to the union is the smaller of the two distances (exact outside
        both). Kept on the body."""
        key = ("floor", float(spacing), float(padding))
        if key not in self._fields:
            body = self.distance_field(spacing, padding=padding)
            y = body.origin[1] + body.spacing * np.arange(body.shape[1])
            above = (y - self.floor).astype(np.float32)
            self._fields[key] = DistanceField(body.origin, body.spacing,
                                              np.minimum(body.values, above[None, :, None]))
        return self._fields[key]

    def mittens(self) -> list[trimesh.Trimesh]:
        """The convex hull of each hand, which the cloth meets instead of the hand (a thumb
        narrower than a sleeve's triangles would pass through them):
        :func:`patternfit.body.hands.mittens`."""
        return mittens(self.vertices, self.faces, self.landmarks)

    def to_trimesh(self):
        """The body as a :class:`trimesh.Trimesh` (no processing)."""
        return trimesh.Trimesh(self.vertices, self.faces, process=False)
