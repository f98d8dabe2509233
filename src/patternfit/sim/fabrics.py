"""Fabric constants in SI units, the built-in presets and user fabrics from JSON.

Every preset value and its published source is listed in ``docs/fabrics.md``. A user fabric
is a JSON object with the same fields and units, e.g.::

    {"name": "my poplin", "density": 0.115, "stretch_warp": 6000, "stretch_weft": 4000,
     "shear": 40, "bending": 6e-6, "friction": 0.4, "thickness": 0.00025}

``bending`` may be one value or ``bending_warp`` and ``bending_weft`` separately. Every
value must lie in its plausible range (:data:`RANGES`); errors are :class:`FabricError`
naming the file (``file``) and the field (``place``).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path

from ..arguments import number
from ..constants import GRAVITY
from ..errors import InputError
from ..files import read_json_file


class FabricError(InputError):
    """An invalid fabric; the message names the file (if any) and the field."""


@dataclass(frozen=True)
class Fabric:
    """Mechanical constants of a fabric, SI units.

    Attributes
    ----------
    name : str
    density : float
        Mass per area [kg/m^2].
    stretch_warp, stretch_weft : float
        Tensile stiffness along the warp (grain) / weft [N/m]: tension per unit width per unit
        strain.
    shear : float
        In-plane shear stiffness [N/m] (per radian of shear angle).
    bending_warp, bending_weft : float
        Bending rigidity for curvature along the warp / the weft [N m] (moment per unit width
        per unit curvature; 1 uN m = 1e-6 N m).
    friction : float
        Coulomb friction coefficient against the body [-].
    thickness : float
        Fabric thickness [m]; also the contact distance kept from the body.
    """

    name: str
    density: float
    stretch_warp: float
    stretch_weft: float
    shear: float
    bending_warp: float
    bending_weft: float
    friction: float
    thickness: float

    def __post_init__(self):
        _check_values(asdict(self), source=None)

    @property
    def bending_length(self) -> float:
        """Peirce's bending length along the warp, ``(B / (density g))^(1/3)`` [m]."""
        return (self.bending_warp / (self.density * GRAVITY)) ** (1.0 / 3.0)

    def to_dict(self) -> dict:
        """The fabric as a JSON-ready dictionary in SI units."""
        return asdict(self)


#: plausible range of each field, (low, high, unit): from chiffon to leather, from a loose
#: knit to a technical weave, around the presets and the sources in docs/fabrics.md; a value
#: outside is a typo or a wrong unit (grams for kilograms, millimetres for metres)
RANGES = {
    "density": (0.01, 3.0, "kg/m^2"),
    "stretch_warp": (1.0, 1e6, "N/m"), "stretch_weft": (1.0, 1e6, "N/m"),
    "shear": (0.01, 1e5, "N/m"),
    "bending_warp": (1e-9, 1e-2, "N m"), "bending_weft": (1e-9, 1e-2, "N m"),
    "friction": (0.0, 2.0, "-"),
    "thickness": (1e-5, 0.02, "m"),
}
#: the longest fabric name [characters]
_NAME_LENGTH = 200


def _check_values(values: dict, source) -> None:
    """Refuse a missing, non-numeric, non-finite or implausible field with a
    :class:`FabricError` naming ``source`` (a file, or None) and the field."""
    for key, (lo, hi, unit) in RANGES.items():
        v = values.get(key)
        place = f"field '{key}'"
        try:
            number(v, key)
        except ValueError:
            raise FabricError(f"expected a finite number [{unit}], got {v!r:.40}",
                              file=source, place=place) from None
        if not lo <= v <= hi:
            raise FabricError(f"{v!r} {unit} is outside the plausible range {lo:g} to {hi:g} "
                              f"{unit}", file=source, place=place)
    name = values.get("name")
    if not isinstance(name, str) or not name.strip() or len(name) > _NAME_LENGTH:
        raise FabricError(f"expected a non-empty string of at most {_NAME_LENGTH} characters",
                          file=source, place="field 'name'")


#: Continuum bending rigidity B [N m] per unit of ARCSim's hinge stiffness ``ke`` (the
#: ``bending`` samples of Wang et al. 2011's material files). ARCSim stores
#: ``ke l^2 / (2 (A0 + A1)) theta^2 / 4`` per hinge; summed over an equilateral mesh bent on a
#: cylinder of curvature k this is ``ke k^2 / 8`` per area, against ``B k^2 / 2``; derivation and
#: the spread over other meshes in docs/fabrics.md.
ARCSIM_BENDING_FACTOR = 0.25

#: Built-in fabrics (sources in docs/fabrics.md). The knits and the shirting take Wang et al.
#: 2011's zero-curvature bending samples: row 0 (hinges along the weft / course, i.e. curvature
#: along the warp / wale) and row 2 (the other way). The denim's density is the ``density`` of
#: Wang's ``11oz-black-denim`` file; its other values are a KES-measured denim.
FABRICS: dict[str, Fabric] = {
    f.name: f for f in (
        Fabric("cotton_shirting", density=0.115, stretch_warp=4.07e3, stretch_weft=4.03e3,
               shear=52.4, bending_warp=ARCSIM_BENDING_FACTOR * 125.409805e-6,
               bending_weft=ARCSIM_BENDING_FACTOR * 125.409805e-6, friction=0.4,
               thickness=0.318e-3),
        Fabric("denim", density=0.324, stretch_warp=8.9e3, stretch_weft=8.9e3, shear=122.0,
               bending_warp=16.9e-6, bending_weft=16.9e-6, friction=0.4, thickness=1.07e-3),
        Fabric("wool_coating", density=0.45, stretch_warp=2.1e3, stretch_weft=1.7e3,
               shear=26.0, bending_warp=30.0e-6, bending_weft=25.0e-6, friction=0.4,
               thickness=2.0e-3),
        Fabric("jersey_knit", density=0.187, stretch_warp=69.0, stretch_weft=33.2,
               shear=18.4, bending_warp=ARCSIM_BENDING_FACTOR * 23.191698e-6,
               bending_weft=ARCSIM_BENDING_FACTOR * 14.267624e-6, friction=0.4,
               thickness=0.55e-3),
        Fabric("stretch_knit", density=0.276, stretch_warp=130.3, stretch_weft=85.7,
               shear=41.6, bending_warp=ARCSIM_BENDING_FACTOR * 46.237591e-6,
               bending_weft=ARCSIM_BENDING_FACTOR * 32.243889e-6, friction=0.5,
               thickness=0.6e-3),
    )
}

_ALIASES = {"cotton": "cotton_shirting", "shirting": "cotton_shirting", "wool": "wool_coating",
            "jersey": "jersey_knit", "elastane": "stretch_knit", "stretch": "stretch_knit"}


def load_fabric(path) -> Fabric:
    """Read a user fabric from a JSON file (SI units, fields as in :class:`Fabric`, each
    within :data:`RANGES`; ``name`` defaults to the file's stem).

    Raises :class:`FabricError` with ``file`` the path and ``place`` the field (or the line):
    unreadable, not a regular file (``/dev/zero``), too large, not UTF-8 JSON, not an
    object, a field unknown, missing, of the wrong type or outside its plausible range.
    """
    path = Path(path)
    data = read_json_file(path, error=FabricError)
    if not isinstance(data, dict):
        raise FabricError(f"expected a JSON object, got {type(data).__name__}", file=path)
    data = dict(data)
    data.setdefault("name", path.stem)
    if "bending" in data:
        if "bending_warp" in data or "bending_weft" in data:
            raise FabricError("give it or bending_warp/bending_weft, not both", file=path,
                              place="field 'bending'")
        data["bending_warp"] = data["bending_weft"] = data.pop("bending")
    known = set(Fabric.__dataclass_fields__)
    for key in data:
        if key not in known:
            raise FabricError(f"unknown (expected {sorted(known)})", file=path,
                              place=f"field {key!r:.80}")
    for key in sorted(known):
        if key not in data:
            raise FabricError("missing", file=path, place=f"field '{key}'")
    _check_values(data, source=path)
    return Fabric(**data)


def get_fabric(name_or_path) -> Fabric:
    """A preset by name (``cotton_shirting``, ``denim``, ...; ``cotton``, ``wool``, ``jersey``,
    ``stretch`` also work), a :class:`Fabric` as is, or a user fabric from a JSON file."""
    if isinstance(name_or_path, Fabric):
        return name_or_path
    key = str(name_or_path).strip().lower().replace("-", "_").replace(" ", "_")
    key = _ALIASES.get(key, key)
    if key in FABRICS:
        return FABRICS[key]
    path = Path(str(name_or_path))
    if path.suffix.lower() == ".json" or path.exists():
        return load_fabric(path)
    raise FabricError(f"unknown preset {name_or_path!r} (presets: {', '.join(FABRICS)}; or a "
                      ".json file)", place="fabric")
