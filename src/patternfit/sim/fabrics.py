"""Fabric constants in SI units, the built-in presets and user fabrics from JSON (SI, a
KES-F / FAST measurement sheet in its own units: ``sim.fabric_sheets``, or an ARCSim material
file such as Wang et al. 2011's measured fabrics: ``sim.fabric_arcsim``).

Every preset value and its published source is listed in ``docs/fabrics.md``. A user fabric
is a JSON object with the same fields and units, e.g.::

    {"name": "my poplin", "density": 0.115, "stretch_warp": 6000, "stretch_weft": 4000,
     "shear": 40, "bending": 6e-6, "friction": 0.4, "thickness": 0.00025}

``bending`` may be one value or ``bending_warp`` and ``bending_weft`` separately;
``bending_hysteresis`` (KES-F 2HB [N]) may be left out (0). Every
value must lie in its plausible range (:data:`RANGES`); errors are :class:`FabricError`
naming the file (``file``) and the field (``place``).
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from functools import lru_cache
from importlib.resources import files
from pathlib import Path

from ..arguments import instance, number
from ..constants import GRAVITY
from ..errors import FabricError
from ..files import read_json_file
from ..text import control_at
from .fabric_arcsim import ARCSIM_BENDING_FACTOR, arcsim_fields, arcsim_notes, is_arcsim
from .fabric_sheets import KES_BENDING, is_sheet, sheet_fields


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
    bending_hysteresis : float
        KES-F 2HB, the width of the bending moment's hysteresis loop [N m/m = N]: the
        frictional couple 2HB / 2 a fold from flat carries on top of ``B kappa``
        (``sim.bending_friction``); 0 (the default) leaves it out.
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
    bending_hysteresis: float = 0.0

    def __post_init__(self):
        _check_values(asdict(self), source=None)

    @property
    def bending_length(self) -> float:
        """Peirce's bending length along the warp, ``(B / (density g))^(1/3)`` [m]."""
        return (self.bending_warp / (self.density * GRAVITY)) ** (1.0 / 3.0)

    @property
    def bending_length_weft(self) -> float:
        """Peirce's bending length along the weft, ``(B_weft / (density g))^(1/3)`` [m]."""
        return (self.bending_weft / (self.density * GRAVITY)) ** (1.0 / 3.0)

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
    "bending_hysteresis": (0.0, 0.1, "N"),
}
#: the densest a cloth may be: its weight over its thickness [kg/m^3]; its fibres are
#: denser (cotton 1,540, polyester 1,380, wool 1,310, nylon 1,140) and it holds air
MAX_BULK_DENSITY = 1600.0
#: fields a fabric file may leave out, with the value they then take
OPTIONAL = {"bending_hysteresis": 0.0}
#: the longest fabric name [characters]
_NAME_LENGTH = 200


def _check_field(key: str, v, source, name: str | None = None) -> None:
    """Refuse the value ``v`` of the field ``key`` when it is not a finite number in its
    plausible range (:data:`RANGES`), with a :class:`FabricError` naming ``source`` (a
    file, or None) and the field as the file named it (``name``, default ``key``)."""
    lo, hi, unit = RANGES[key]
    place = f"field '{name or key}'"
    try:
        number(v, key)
    except ValueError:
        raise FabricError(f"expected a finite number [{unit}], got {v!r:.40}",
                          file=source, place=place) from None
    if not lo <= v <= hi:
        u = "" if unit == "-" else f" {unit}"
        raise FabricError(f"{v!r}{u} is outside the plausible range {lo:g} to {hi:g}{u}",
                          file=source, place=place)


def _check_values(values: dict, source, names: dict | None = None) -> None:
    """Refuse a missing, non-numeric, non-finite or implausible field with a
    :class:`FabricError` naming ``source`` (a file, or None) and the field (as ``names``
    calls it, where given)."""
    names = names or {}
    for key in RANGES:
        _check_field(key, values.get(key), source, name=names.get(key))
    name = values.get("name")
    if not isinstance(name, str) or not name.strip() or len(name) > _NAME_LENGTH:
        raise FabricError(f"expected a non-empty string of at most {_NAME_LENGTH} characters",
                          file=source, place="field 'name'")
    at = control_at(name)
    if at is not None:  # printed in tables and reports (patternfit.text)
        raise FabricError(f"{name!r:.80} holds a control character ({name[at]!r}, at {at})",
                          file=source, place="field 'name'")


def check_bulk(fabric, source=None, names: dict | None = None):
    """``fabric`` (a :class:`Fabric`), refused with a :class:`FabricError` naming ``source``
    and the weight and thickness fields (as ``names`` calls them) when their ratio is denser
    than :data:`MAX_BULK_DENSITY`. Each field in its range is not enough: a KES weight in
    g/m² written where mg/cm² go (ten times too heavy) stays in it, and drapes a wool at ten
    times its weight. Held where fabrics come in (files, the studio's editor), not by
    :class:`Fabric` itself: a design session saved with such a fabric still opens."""
    instance(fabric, Fabric, "fabric", "a Fabric")
    bulk = fabric.density / fabric.thickness
    if bulk > MAX_BULK_DENSITY:
        said = [(names or {}).get(k, k) for k in ("density", "thickness")]
        raise FabricError(f"{fabric.density:g} kg/m² over {fabric.thickness * 1e3:g} mm is "
                          f"{bulk:,.0f} kg/m³ of cloth, denser than the fibres it is made of "
                          f"(at most {MAX_BULK_DENSITY:,.0f} kg/m³; cloth holds air between "
                          "them): a weight or a thickness in another unit?",
                          file=source, place=f"fields '{said[0]}' and '{said[1]}'")
    return fabric


#: Built-in fabrics (sources in docs/fabrics.md). The knits take Wang et al. 2011's
#: zero-curvature bending samples: row 0 (hinges along the weft / course, i.e. curvature
#: along the warp / wale) and row 2 (the other way). The denim's density is the ``density`` of
#: Wang's ``11oz-black-denim`` file; its other values are a KES-measured denim. The shirting
#: bends like a KES-measured cotton broadcloth (Matsudaira et al. 2015, B = 0.118 gf cm^2/cm)
#: and weighs what a measured cotton plain weave of its thickness weighs (Penava et al. 2014);
#: its stretch and shear are Wang's ``royal-target`` cotton/polyester woven.
FABRICS: dict[str, Fabric] = {
    f.name: f for f in (
        Fabric("cotton_shirting", density=0.1503, stretch_warp=4.07e3, stretch_weft=4.03e3,
               shear=52.4, bending_warp=KES_BENDING * 0.118, bending_weft=KES_BENDING * 0.118,
               friction=0.4, thickness=0.318e-3),
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

#: where each preset's numbers come from, in short (the full table and status of every value:
#: docs/fabrics.md, "Values and sources")
PRESET_SOURCES = {
    "cotton_shirting": "bending: KES-F B of a cotton broadcloth (Matsudaira et al. 2015); weight "
                       "and thickness: a cotton plain weave (Penava et al. 2014, Table 1); "
                       "stretch, shear: Wang et al. 2011 royal-target",
    "denim": "KES-F denim (J. Textiles 2016, 4614168, Table 5); density: Wang et al. 2011 "
             "11oz-black-denim",
    "wool_coating": "stretch, shear: SiroFAST wool suiting; density: melton trade range; "
                    "bending and thickness assumed",
    "jersey_knit": "Wang et al. 2011 gray-interlock (stretch, shear, bending, density); "
                   "thickness assumed",
    "stretch_knit": "Wang et al. 2011 ivory-rib-knit (stretch, shear, bending, density); "
                    "thickness assumed",
}

def fabric_names() -> list[str]:
    """Every name a fabric is read by without a file: the presets, their short names
    (``cotton``, ``wool`` ...) and the published test fabrics' ids, lower case."""
    return [*FABRICS, *_ALIASES, *published_drapes()]


_ALIASES = {"cotton": "cotton_shirting", "shirting": "cotton_shirting", "wool": "wool_coating",
            "jersey": "jersey_knit", "elastane": "stretch_knit", "stretch": "stretch_knit"}


def load_fabric(path) -> Fabric:
    """Read a user fabric from a JSON file (SI units, fields as in :class:`Fabric`, each
    within :data:`RANGES`; ``name`` defaults to the file's stem), from a KES-F or FAST
    measurement sheet in its instrument's units (a file with an ``instrument`` field,
    :mod:`patternfit.sim.fabric_sheets`), or from an ARCSim material file (a file with
    ``stretching``, :mod:`patternfit.sim.fabric_arcsim`), converted to SI and held to the same
    ranges (:func:`read_fabric_file` also says what was assumed).

    Raises :class:`FabricError` with ``file`` the path and ``place`` the field (or the line):
    unreadable, not a regular file (``/dev/zero``), too large, not UTF-8 JSON, not an
    object, a field unknown, missing, of the wrong type or outside its plausible range.
    """
    return read_fabric_file(path)[0]


#: mass per volume of cloth [kg/m^3], for a thickness a file does not give: the median of the
#: twelve measured fabrics with weight and thickness in docs/fabrics.md (250-470 kg/m^3)
TYPICAL_BULK_DENSITY = 420.0


def read_fabric_file(path) -> tuple[Fabric, tuple[str, ...]]:
    """:func:`load_fabric`, and what was assumed for values the file does not carry (an
    ARCSim material's friction and thickness) or left out of what it does (an ARCSim
    coupling the file's own table cannot hold, :func:`~.fabric_arcsim.arcsim_notes`), one
    sentence each; empty for the others."""
    path = Path(path)
    # comments allowed: ARCSim's own materials begin with "//" lines
    data = read_json_file(path, error=FabricError, comments=True)
    if not isinstance(data, dict):
        raise FabricError(f"expected a JSON object, got {type(data).__name__}", file=path)
    data = dict(data)
    data.setdefault("name", path.stem)
    if is_sheet(data) or is_arcsim(data):
        fields, origin = (sheet_fields if is_sheet(data) else arcsim_fields)(data, path)
        assumed = _assume_missing(fields, origin) + (() if is_sheet(data)
                                                     else arcsim_notes(data))
        fabric = {**fields, "name": data["name"]}
        names = {key: key if was == key else f"{was} -> {key}" for key, was in origin.items()}
        _check_values(fabric, source=path, names=names)
        fab = check_bulk(Fabric(**fabric), path, names)
        return fab, assumed + unusual(fab)
    for key, value in OPTIONAL.items():
        data.setdefault(key, value)
    if "bending" in data:
        if "bending_warp" in data or "bending_weft" in data:
            raise FabricError("give it or bending_warp/bending_weft, not both", file=path,
                              place="field 'bending'")
        _check_field("bending_warp", data["bending"], path, name="bending")
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
    fab = check_bulk(Fabric(**data), path)
    return fab, unusual(fab)


#: the bending lengths [m] and the mass per volume of cloth [kg/m^3] outside which a file's
#: fabric is noted as unusual, a unit slipped perhaps (the presets and the published wovens:
#: 7.4-19.9 mm, 225-473 kg/m^3; a KES B in uN m read 75 mm, a FAST C in cm 2 mm, a FAST W in
#: mg/cm^2 49 kg/m^3, a thick KES sheet's W in g/m^2 1,358 kg/m^3, all within the ranges)
USUAL_BENDING_LENGTH = (0.003, 0.06)
USUAL_BULK_DENSITY = (80.0, 1000.0)


def unusual(fabric: Fabric) -> tuple[str, ...]:
    """Sentences on values of ``fabric`` that no cloth we know has, though each lies within
    :data:`RANGES` (:data:`USUAL_BENDING_LENGTH`, :data:`USUAL_BULK_DENSITY`): a unit
    slipped perhaps. Empty for a usual fabric."""
    said = []
    lo, hi = USUAL_BENDING_LENGTH
    for side, c in (("warp", fabric.bending_length), ("weft", fabric.bending_length_weft)):
        if not lo <= c <= hi:
            said.append(f"{side} bending length {c * 1e3:.3g} mm, outside the "
                        f"{lo * 1e3:g}-{hi * 1e3:g} mm of cloth: is the bending rigidity (or "
                        "length) in its sheet's unit?")
    bulk = fabric.density / fabric.thickness
    lo, hi = USUAL_BULK_DENSITY
    if not lo <= bulk <= hi:
        said.append(f"{fabric.density:g} kg/m² over {fabric.thickness * 1e3:g} mm is "
                    f"{bulk:,.0f} kg/m³ of cloth, outside the {lo:g}-{hi:,.0f} kg/m³ of "
                    "cloth: is the weight (or thickness) in its sheet's unit?")
    return tuple(said)


def _assume_missing(fields: dict, origin: dict) -> tuple[str, ...]:
    """Fill an ARCSim material's friction and thickness when the file leaves them out (its
    sources do not report them), recording each in ``origin``; the sentences saying so."""
    said = []
    if "friction" not in fields:
        fields["friction"] = _UNREPORTED_FRICTION
        origin["friction"] = "friction"
        said.append(f"friction {_UNREPORTED_FRICTION:g} assumed (not in the file; as for the "
                    "published fabrics without one)")
    if "thickness" not in fields:
        fields["thickness"] = fields["density"] / TYPICAL_BULK_DENSITY
        origin["thickness"] = f"density / {TYPICAL_BULK_DENSITY:g} kg/m^3"
        said.append(f"thickness {fields['thickness'] * 1e3:.2f} mm assumed (not in the file; "
                    f"its weight at a typical {TYPICAL_BULK_DENSITY:g} kg/m^3)")
    return tuple(said)


def get_fabric(name_or_path) -> Fabric:
    """A preset by name (``cotton_shirting``, ``denim``, ...; ``cotton``, ``wool``, ``jersey``,
    ``stretch`` also work), a published test fabric by id (``petrak_m1`` ...,
    :func:`published_drapes`), a :class:`Fabric` as is, or a user fabric from a JSON file."""
    return fabric_with_notes(name_or_path)[0]


def fabric_with_notes(name_or_path) -> tuple[Fabric, tuple[str, ...]]:
    """:func:`get_fabric`, and for a file what was assumed for values it does not carry
    (:func:`read_fabric_file`); empty for a preset, a published fabric or a Fabric."""
    if isinstance(name_or_path, Fabric):
        return name_or_path, ()
    key = str(name_or_path).strip().lower().replace("-", "_").replace(" ", "_")
    key = _ALIASES.get(key, key)
    if key in FABRICS:
        return FABRICS[key], ()
    if key in published_drapes():
        return published_drapes()[key].fabric, ()
    path = Path(str(name_or_path))
    if path.suffix.lower() == ".json" or path.exists():
        return read_fabric_file(path)
    if path.suffix or len(path.parts) > 1:  # a path, not a name
        raise FabricError("no such file (nor a preset of that name)", file=path)
    raise FabricError(f"unknown preset {name_or_path!r} (presets: {', '.join(FABRICS)}; "
                      f"published test fabrics: {', '.join(published_drapes())}; or a .json "
                      "file)", place="fabric")


@dataclass(frozen=True)
class PublishedDrape:
    """A fabric whose drape coefficient was measured and published with its mechanical data.

    Attributes
    ----------
    fabric : Fabric
        Its constants converted to SI (docs/fabrics.md, "Published drape tests").
    drape_coefficient : float
        The measured drape coefficient [-].
    drape_coefficient_reference : float or None
        The source's own simulation of the same test (CLO3D for Petrak et al. 2025) [-].
    description : str
        Weave, fibre content and weight.
    source : str
        The citation, in short.
    provenance : str
        The source in full and how it was read.
    """

    fabric: Fabric
    drape_coefficient: float
    drape_coefficient_reference: float | None
    description: str
    source: str
    provenance: str


#: CLO3D's physical-property units in SI: stretch and shear [g/s^2] -> N/m, bending
#: [g mm^2/s^2] -> N m (dimensional, docs/fabrics.md)
CLO_STRETCH = 1e-3
CLO_BENDING = 1e-9
#: friction of the published fabrics, which their sources do not report; the Cusick test
#: pins the disc and has no body, so it does not enter the drape coefficient [-]
_UNREPORTED_FRICTION = 0.4


@lru_cache(maxsize=1)
def published_drapes() -> dict[str, PublishedDrape]:
    """The fabrics of ``data/fabrics/*.json`` with published drape coefficients, by id
    (``petrak_m1`` ... ``petrak_m6``: Petrak et al. 2025, six wovens, KES-FB converted to
    CLO3D units by the authors, converted here to SI)."""
    out = {}
    for path in sorted((files("patternfit") / "data" / "fabrics").iterdir(),
                       key=lambda p: p.name):
        if not path.name.endswith(".json"):
            continue
        data = json.loads(path.read_text(encoding="utf-8"))
        for row in data["fabrics"]:
            fab = Fabric(row["id"], density=row["mass_g_m2"] / 1000.0,
                         stretch_warp=row["stretch_warp_g_s2"] * CLO_STRETCH,
                         stretch_weft=row["stretch_weft_g_s2"] * CLO_STRETCH,
                         shear=row["shear_g_s2"] * CLO_STRETCH,
                         bending_warp=row["bending_warp_g_mm2_s2"] * CLO_BENDING,
                         bending_weft=row["bending_weft_g_mm2_s2"] * CLO_BENDING,
                         friction=_UNREPORTED_FRICTION, thickness=row["thickness_mm"] / 1000.0)
            out[row["id"]] = PublishedDrape(
                fab, float(row["drape_coefficient"]), row.get("drape_coefficient_clo3d"),
                f"{row['name']} ({row['composition']}, {row['mass_g_m2']} g/m^2)",
                f"{data['citation']}, fabric {row['id'].rsplit('_', 1)[-1].upper()}",
                f"{data['source']}; read from {data['read_from']}")
    return out


@dataclass(frozen=True)
class KitReading:
    """What the virtual fabric-testing kit (``patternfit.sim.fabric_test``) read on a fabric,
    stored from a run (the command is beside each table) and checked against a fresh run by
    tests/test_fabric_test.py.

    Attributes
    ----------
    drape_coefficient : float
        Cusick drape coefficient, mean over the starts [-] (30 cm specimen, 18 cm disc,
        the kit's mesh for the fabric (``fabric_test.cusick_triangles``), starts 0-2, full
        stretch stiffness in compression).
    drape_coefficient_min, drape_coefficient_max : float
        Its range over the starts [-].
    nodes : float
        Mean number of nodes [-].
    bending_length : float or None
        Peirce cantilever bending length along the warp, finest mesh (24 edges per bending
        length) [m]; None where not run.
    """

    drape_coefficient: float
    drape_coefficient_min: float
    drape_coefficient_max: float
    nodes: float
    bending_length: float | None = None

    def to_dict(self) -> dict:
        return asdict(self)


#: The kit's readings of the presets and the published fabrics, stored from runs (a test
#: re-runs the kit on them): Cusick at the kit's defaults (30/18 cm, the kit's mesh for the
#: fabric: 4,000 triangles for the shirting, denim and wool, 6.5K / 4.9K for the jersey and
#: stretch knit, 7.8K-18.7K for the published wovens; the force stop, Newton, compression
#: 1.0), starts 0-2; cantilever along the warp at 12 and 24 edges per bending length (the
#: finest). Presets: ``python benchmarks/physics.py --only presets --seeds 3 --meshes
#: 6,12,24 --fabrics NAME``; published fabrics: ``python benchmarks/physics.py --only
#: published --seeds 3 --compression 1.0``; shirting, denim and wool at commit 2db2939
#: (4K, the curvature-tensor bending and the force stop's L-BFGS-then-Newton solver), the
#: knits and the published wovens at b847d16, where their mesh changed (docs/fabrics.md,
#: "Testing a fabric" and "Published drape tests").
KIT_READINGS: dict[str, KitReading] = {
    "cotton_shirting": KitReading(0.6611, 0.6462, 0.6690, 6.7, 0.019451),
    "denim": KitReading(0.5880, 0.5631, 0.6094, 8.0, 0.017099),
    "wool_coating": KitReading(0.5415, 0.5341, 0.5547, 7.3, 0.018524),
    "jersey_knit": KitReading(0.312, 0.295, 0.336, 8.7, 0.014296),
    "stretch_knit": KitReading(0.394, 0.386, 0.410, 8.7, 0.015826),
    "petrak_m1": KitReading(0.211, 0.204, 0.218, 9.7),
    "petrak_m2": KitReading(0.187, 0.181, 0.196, 10.3),
    "petrak_m3": KitReading(0.236, 0.229, 0.242, 9.0),
    "petrak_m4": KitReading(0.198, 0.194, 0.204, 9.3),
    "petrak_m5": KitReading(0.263, 0.256, 0.274, 9.7),
    "petrak_m6": KitReading(0.335, 0.323, 0.354, 9.3),
}
