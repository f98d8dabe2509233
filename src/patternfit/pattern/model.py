"""The pattern model: a garment is panels plus seams.

Everything is immutable; an edit returns a new object (``dataclasses.replace`` or the
``with_*`` helpers). Coordinates are metres in each panel's own flat frame, the fabric's
right side facing the viewer (x to the right, y up); outlines are stored as given and
oriented counter-clockwise by the mesher.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, is_dataclass, replace
from typing import Any

import numpy as np

from ..constants import limits, tol
from ..geometry import euler_xyz_matrix, polygon_area
from .edges import Edge
from .errors import PatternError


@dataclass(frozen=True)
class Loop:
    """A closed chain of edges: the outline of a panel, or an inner loop (dart, cut-out).

    Edge ``i`` ends where edge ``i + 1`` starts, and the last edge ends where the first starts.
    """

    name: str
    edges: tuple[Edge, ...]

    def __post_init__(self):
        object.__setattr__(self, "edges", tuple(self.edges))

    def polygon(self, per_curve: int = 32) -> np.ndarray:
        """Closed polyline through the loop, last point not repeated: (k, 2) float [m]."""
        pts = [e.polyline(None if e.kind == "line" else per_curve)[:-1] for e in self.edges]
        return np.concatenate(pts, axis=0)

    def signed_area(self) -> float:
        """Area enclosed [m^2], positive when the loop runs counter-clockwise."""
        return polygon_area(self.polygon(64))

    @property
    def length(self) -> float:
        """Perimeter [m]."""
        return float(sum(e.length for e in self.edges))


#: the body parts a panel may dress, and the sides it may face (docs/pattern-format.md)
PARTS = ("torso", "arm_left", "arm_right", "leg_left", "leg_right")
SIDES = ("front", "back", "outer", "left", "right")
#: the largest Euler angle of an explicit placement [degrees]: a turn and no more (an
#: angle of 1e20 degrees is no rotation anyone drew)
MAX_ROTATION = 360.0


@dataclass(frozen=True)
class Placement:
    """Where a panel goes on the body before sewing.

    ``part`` names the body part it dresses (``"torso"``, ``"arm_left"``, ``"arm_right"``,
    ``"leg_left"``, ``"leg_right"``) and ``side`` the side it faces (``"front"``/``"back"``).
    ``translation`` [m] and ``rotation`` (XYZ Euler angles, degrees) give an explicit 3D
    placement, as imported files carry (body standing at the origin, y up).
    """

    part: str = "torso"
    side: str = "front"
    translation: tuple[float, float, float] | None = None
    rotation: tuple[float, float, float] | None = None

    def __post_init__(self):
        if self.part not in PARTS:
            raise ValueError(f"placement: part must be one of {', '.join(PARTS)}, got "
                             f"{self.part!r:.40}")
        if self.side not in SIDES:
            raise ValueError(f"placement: side must be one of {', '.join(SIDES)}, got "
                             f"{self.side!r:.40}")
        for what, v in (("translation", self.translation), ("rotation", self.rotation)):
            if v is not None and not (len(v) == 3 and all(math.isfinite(c) for c in v)):
                raise ValueError(f"placement: {what} must be 3 finite numbers, got {v!r:.60}")
        if self.translation is not None and \
                max(map(abs, self.translation)) > limits.translation:
            raise ValueError(f"placement: translation must lie within ±{limits.translation:g} "
                             f"m of the body, got {self.translation!r:.60}")
        if self.rotation is not None and max(abs(c) for c in self.rotation) > MAX_ROTATION:
            raise ValueError(f"placement: rotation angles must lie within ±{MAX_ROTATION:g} "
                             f"degrees, got {self.rotation!r:.60}")

    @property
    def explicit(self) -> bool:
        """Whether the placement gives a 3D translation or rotation (an imported file's)."""
        return self.translation is not None or self.rotation is not None

    def rotation_matrix(self) -> np.ndarray:
        """(3, 3) float: the rotation of ``rotation`` (XYZ Euler angles in degrees,
        ``Rz @ Ry @ Rx`` as GarmentCode and Maya read them; the identity when None)."""
        return euler_xyz_matrix(self.rotation or (0.0, 0.0, 0.0))

    def transform(self, points) -> np.ndarray:
        """Panel-frame points placed in 3D by the explicit placement.

        points : (n, 2) float [m]. Returns (n, 3) float [m]: ``R @ (x, y, 0) + translation``.
        Raises ``ValueError`` when the placement has no explicit translation or rotation.
        """
        if not self.explicit:
            raise ValueError("placement: no explicit translation or rotation")
        pts = np.asanyarray(points, dtype=np.float64).reshape(-1, 2)
        shift = np.asarray(self.translation or (0.0, 0.0, 0.0), dtype=np.float64)
        return np.column_stack([pts, np.zeros(len(pts))]) @ self.rotation_matrix().T + shift


@dataclass(frozen=True)
class Notch:
    """A notch: a mark on an edge where pieces are matched when sewing.

    ``edge`` names an edge of the panel (outline or inner loop), ``t`` is the arc-length
    fraction along it in [0, 1] (a notch at a turn point is at ``t = 0`` of the edge that
    starts there), ``kind`` the notch's shape (``"slit"``, the usual cut; others as the file
    names them).
    """

    edge: str
    t: float
    kind: str = "slit"


@dataclass(frozen=True)
class InnerLine:
    """A line drawn on a panel but not cut (a dart leg, a pocket or placement line, a style
    line): an open polyline ``points`` (k, 2) [m], k >= 2, in the panel frame. Kept and
    written back, never meshed."""

    name: str
    points: tuple[tuple[float, float], ...]

    def __post_init__(self):
        object.__setattr__(self, "points", _point_tuple(self.points))


def _point_tuple(points) -> tuple[tuple[float, float], ...]:
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    return tuple((float(x), float(y)) for x, y in pts)


@dataclass(frozen=True)
class Panel:
    """One piece of fabric: an outline, optional inner loops, a grainline and a name.

    ``grainline`` is the warp direction in the panel frame, a unit 2-vector. ``notches``
    mark places on its edges (:class:`Notch`). What a CAD file draws on the piece is kept
    without being meshed: ``lines`` (:class:`InnerLine`), ``drill_holes`` ((k, 2) points
    [m]) and ``cut_line``, the closed cut line ((k, 2) [m], last point not repeated) when
    the outline is the sew line (the seam allowance lies between them; empty when the
    outline is where the fabric is cut).
    """

    name: str
    outline: Loop
    inner: tuple[Loop, ...] = ()
    grainline: tuple[float, float] = (0.0, 1.0)
    placement: Placement = field(default_factory=Placement)
    notches: tuple[Notch, ...] = ()
    lines: tuple[InnerLine, ...] = ()
    drill_holes: tuple[tuple[float, float], ...] = ()
    cut_line: tuple[tuple[float, float], ...] = ()

    def __post_init__(self):
        object.__setattr__(self, "inner", tuple(self.inner))
        object.__setattr__(self, "notches", tuple(self.notches))
        object.__setattr__(self, "lines", tuple(self.lines))
        object.__setattr__(self, "drill_holes", _point_tuple(self.drill_holes))
        object.__setattr__(self, "cut_line", _point_tuple(self.cut_line))
        g = np.asarray(self.grainline, dtype=np.float64)
        with np.errstate(over="ignore"):
            n = float(np.linalg.norm(g))
        big = float(np.max(np.abs(g)))
        if not (n > 0 and np.isfinite(n)) and big > 0 and np.isfinite(big):
            g = g / big  # the norm of (1e300, 1e300) overflows, that of (1e-320, 0) is 0
            n = float(np.linalg.norm(g))
        if n > 0 and np.isfinite(n):
            g = g / n
        object.__setattr__(self, "grainline", (float(g[0]), float(g[1])))

    @property
    def loops(self) -> tuple[Loop, ...]:
        """Outline first, then the inner loops."""
        return (self.outline, *self.inner)

    def edges(self) -> dict[str, Edge]:
        """Every edge of the panel by name, outline first."""
        return {e.name: e for loop in self.loops for e in loop.edges}

    def edge(self, name: str) -> Edge:
        """The edge called ``name``; ``KeyError`` naming the panel when there is none."""
        try:
            return self.edges()[name]
        except KeyError:
            raise KeyError(f"panel '{self.name}' has no edge '{name}' (edges: "
                           f"{', '.join(self.edges())})") from None

    def locate(self, edge: str) -> tuple[int, int]:
        """(loop number, position in that loop) of the edge called ``edge`` (loop 0 is the
        outline); a :class:`PatternError` naming the panel and the edge when there is none."""
        for li, loop in enumerate(self.loops):
            for k, e in enumerate(loop.edges):
                if e.name == edge:
                    return li, k
        raise PatternError(f"no edge '{edge}'", panel=self.name, edge=edge)

    def area(self) -> float:
        """Fabric area [m^2]: the outline's minus the inner loops'."""
        return abs(self.outline.signed_area()) - sum(abs(lp.signed_area()) for lp in self.inner)

    def with_edge(self, edge: Edge) -> "Panel":
        """A copy with the edge of the same name replaced."""
        def swap(loop: Loop) -> Loop:
            return replace(loop, edges=tuple(edge if e.name == edge.name else e
                                             for e in loop.edges))
        return replace(self, outline=swap(self.outline),
                       inner=tuple(swap(lp) for lp in self.inner))


@dataclass(frozen=True)
class SeamSide:
    """One side of a seam: ``edge`` of ``panel``, from arc-length fraction ``start`` to ``end``."""

    panel: str
    edge: str
    start: float = 0.0
    end: float = 1.0


@dataclass(frozen=True)
class Seam:
    """Two edge ranges sewn together.

    With ``reverse`` (the usual case for two panels both laid right side up) the start of side
    ``a`` is sewn to the end of side ``b``; without it, start to start.

    ``ease`` is the most the longer side may exceed the shorter one, as a ratio (longer /
    shorter - 1): 0.08 for a sleeve cap, 0.3 for a 30 % gather. The difference is sewn in as
    ease or gathers: both sides get the same number of vertices spread by arc length, each
    panel keeping its own rest lengths. 0 (the default) asks for sides of equal length.
    At most ``limits.seam_ease`` (:func:`~patternfit.pattern.validate.check_seams`).
    """

    name: str
    a: SeamSide
    b: SeamSide
    reverse: bool = True
    ease: float = 0.0


#: the heights a garment can hang from (:attr:`Pattern.anchor`)
ANCHORS = ("waist", "neck")


@dataclass(frozen=True)
class Pattern:
    """A garment: panels plus seams, with free-form metadata (size, measurements)."""

    name: str
    panels: tuple[Panel, ...]
    seams: tuple[Seam, ...] = ()
    meta: dict[str, Any] = field(default_factory=dict, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "panels", tuple(self.panels))
        object.__setattr__(self, "seams", tuple(self.seams))

    @property
    def anchor(self) -> str:
        """Where the garment hangs from on the body: ``"neck"`` or ``"waist"`` (the one rule
        that placement and the on-body check share; ``docs/pattern-format.md``, "Where a
        garment hangs from").

        ``meta["anchor"]`` when it is one of :data:`ANCHORS` (every built-in garment sets
        it); otherwise read from the panels' roles
        (:func:`patternfit.pattern.roles.garment_anchor`): ``"neck"`` when a panel is a
        sleeve, collar or hood, or two body panels are sewn at their tops across (shoulders,
        or either side of a neck hole; or an edge is named for the neck or shoulders), else
        ``"waist"`` (skirts, trousers). It does not depend on the panels' names being
        kept, so a DXF or GarmentCode round trip keeps it. Placement puts the top of the
        garment at the body's ``neck_base_height`` / ``waist_height``, and a drape whose top
        ends far from that height fails (:mod:`patternfit.sim.onbody`).
        """
        given = self.meta.get("anchor") if isinstance(self.meta, dict) else None
        if given in ANCHORS:
            return given
        from .roles import garment_anchor  # roles reads patterns: imported when first asked
        return garment_anchor(self)

    def same_cut(self, other: "Pattern", *, atol: float = tol.merge) -> bool:
        """Whether ``other`` is this garment up to the rounding of its numbers (``atol``
        [m] on lengths, the same on fractions and angles): the same name, panels and seams;
        ``meta`` is not compared. A pattern written in cm and read back differs in the last
        bit of its coordinates, and a drape of it was refused as of "another version"."""
        return isinstance(other, Pattern) and self.name == other.name \
            and _close(self.panels, other.panels, atol) and _close(self.seams, other.seams, atol)

    def panel(self, name: str) -> Panel:
        """The panel called ``name``; ``KeyError`` listing the panels when there is none."""
        for p in self.panels:
            if p.name == name:
                return p
        raise KeyError(f"pattern '{self.name}' has no panel '{name}' "
                       f"(panels: {', '.join(p.name for p in self.panels)})")

    def panel_index(self, name: str) -> int:
        """Position of panel ``name`` in ``panels``."""
        return [p.name for p in self.panels].index(self.panel(name).name)

    def with_panel(self, panel: Panel) -> "Pattern":
        """A copy with the panel of the same name replaced."""
        return replace(self, panels=tuple(panel if p.name == panel.name else p
                                          for p in self.panels))

    def seam_side_length(self, side: SeamSide) -> float:
        """Arc length of one seam side [m]."""
        return self.panel(side.panel).edge(side.edge).sub_length(side.start, side.end)

    def area(self) -> float:
        """Total fabric area [m^2]."""
        return float(sum(p.area() for p in self.panels))


def _close(a, b, atol: float) -> bool:
    """``a == b`` but numbers within ``atol`` of each other (dataclasses field by compared
    field, sequences item by item, arrays elementwise)."""
    if is_dataclass(a) and not isinstance(a, type):
        return type(a) is type(b) and all(_close(getattr(a, f.name), getattr(b, f.name), atol)
                                          for f in fields(a) if f.compare)
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        if a.dtype.kind in "fi" and b.dtype.kind in "fi":
            return a.shape == b.shape and bool(np.all(np.abs(a - b) <= atol))
        return a.shape == b.shape and bool(np.all(a == b))
    if isinstance(a, (tuple, list)):
        return isinstance(b, (tuple, list)) and len(a) == len(b) \
            and all(_close(x, y, atol) for x, y in zip(a, b))
    if isinstance(a, float) and isinstance(b, (int, float)) and not isinstance(b, bool):
        return abs(a - b) <= atol
    return a == b
