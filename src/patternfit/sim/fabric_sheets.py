"""Fabric measurement sheets in their instruments' own units: KES-F and SiroFAST.

A fabric lab reports a fabric as a KES-F or FAST sheet, not in SI. A fabric file with an
``instrument`` field is read as such a sheet and converted here (the factors and their checks:
docs/fabrics.md, "Conversions used"); without one it is SI (``sim.fabrics``)::

    {"name": "wool tropical", "instrument": "KES-F", "W": 16.29, "T": 0.407,
     "B": [0.071, 0.063], "2HB": 0.033, "G": 0.62, "EMT": [4.1, 6.5], "friction": 0.4}

    {"name": "suiting", "instrument": "FAST", "W": 205, "T2": 0.42, "C": [19.8, 17.1],
     "E100": [2.9, 4.1], "G": 32, "friction": 0.4}

Units (as the instruments report them):

=========  ===============================  =======================================
field      KES-F                            FAST
=========  ===============================  =======================================
W          mass per area [mg/cm^2]          mass per area [g/m^2]
T          thickness at 0.5 gf/cm^2 [mm]    ``T2``: thickness at 2 gf/cm^2 [mm]
B          bending rigidity [gf cm^2/cm]    bending rigidity [uN m]
C          --                               bending length [mm] (instead of B)
2HB        bending hysteresis [gf cm/cm]    --
G          shear rigidity [gf/(cm deg)]     shear rigidity [N/m]
EMT        strain at 500 gf/cm [%]          --
E100       --                               strain at 100 gf/cm [%]
friction   against the body [-]             against the body [-]
=========  ===============================  =======================================

A directional value (B, C, 2HB, G, EMT, E100) is one number for both directions, a pair
``[warp, weft]``, or the sheet's own two fields ``B-1`` / ``B-2`` (KES-F) or ``B1`` / ``B2``
(FAST); 1 is the warp (KES-F's and FAST's own convention). One of these ways only: a
direction given two ways is refused naming both. The model has one shear stiffness
and one 2HB, so those take the mean of a pair. ``friction`` is required: KES-F's MIU is the
surface's friction against a steel contactor, not against skin, and is read but not used.
Other fields of a full sheet (``LT``, ``WT``, ``RT``, ``2HG``, ``MIU``, ``SMD``, ``F``, ...) are
read and not used; any other field is refused, so a misspelt one is not silently dropped.
"""

from __future__ import annotations

import numpy as np

from ..arguments import number
from ..constants import GRAVITY
from ..errors import FabricError

#: KES-F bending rigidity B: gf cm^2/cm = gf cm = 9.80665e-3 N x 0.01 m [N m per gf cm^2/cm]
KES_BENDING = 9.80665e-5
#: KES-F bending hysteresis 2HB: gf cm/cm = gf = 9.80665e-3 N [N per gf cm/cm]
KES_BENDING_HYSTERESIS = 9.80665e-3
#: KES-F shear rigidity G: gf/cm per degree = 0.980665 N/m x 180/pi [N/m per radian per unit]
KES_SHEAR = 0.980665 * 57.29577951308232
#: KES-F mass per area W: mg/cm^2 = 0.01 kg/m^2
KES_MASS = 0.01
#: KES-F EMT is the strain at 500 gf/cm [N/m]; FAST E100 the strain at 100 gf/cm [N/m]
KES_EMT_LOAD = 500 * 0.980665
FAST_E100_LOAD = 100 * 0.980665
#: FAST bending rigidity: uN m [N m per unit]; mass per area g/m^2 [kg/m^2 per unit]
FAST_BENDING = 1e-6
FAST_MASS = 1e-3
#: millimetres [m]
MM = 1e-3
#: a FAST sheet's bending rigidity B and bending length C, both printed by a SiroFAST
#: report to three digits, agree (B = W g C^3) within this share [-]
FAST_B_C_AGREE = 0.05

#: the instruments a sheet may name, by their spellings (case, spaces and hyphens ignored:
#: "KES F" is as common in print as "KES-F")
INSTRUMENTS = {"kesf": "KES-F", "kesfb": "KES-F", "kes": "KES-F", "fast": "FAST",
               "sirofast": "FAST"}
#: fields of a full sheet that the model does not use (tensile linearity, energy and
#: resilience; shear hysteresis; surface friction and roughness; compression; FAST's
#: formability, relaxation and hygral shrinkage, bias extension, thickness under 100 gf/cm^2)
UNUSED = {
    "KES-F": {"LT", "WT", "RT", "2HG", "2HG5", "MIU", "MMD", "SMD", "LC", "WC", "RC", "TM",
              "TO", "Q", "qmax"},
    "FAST": {"T100", "ST", "STR", "EB5", "E5", "E20", "F", "F1", "F2", "RS", "HE", "E100-bias",
             "E100B", "E100-3"},
}
_DIRECTIONAL = {"KES-F": ("B", "2HB", "G", "EMT"), "FAST": ("B", "C", "G", "E100")}
_SINGLE = {"KES-F": ("W", "T", "friction"), "FAST": ("W", "T2", "T", "friction")}


def is_sheet(data: dict) -> bool:
    """Whether the fabric file's object ``data`` is a measurement sheet (has ``instrument``)."""
    return "instrument" in data


def sheet_fields(data: dict, path) -> tuple[dict, dict]:
    """The :class:`~patternfit.sim.fabrics.Fabric` fields (SI, un-checked) of the KES-F or
    FAST sheet ``data`` read from ``path``, and for each the sheet field it came from.

    Returns ``(fields, origin)``: ``fields`` maps every Fabric field but ``name`` to its
    value in SI (density [kg/m^2], stretch and shear [N/m], bending [N m], thickness [m],
    bending_hysteresis [N]); ``origin`` maps it to the sheet's field name (for errors).

    Raises :class:`FabricError` naming ``path`` and the sheet field: an unknown instrument, an
    unknown field, a missing one, a value that is not a finite positive number, a pair that is
    not two numbers, or one direction given both ways.
    """
    kind = _instrument(data.get("instrument"), path)
    known = {"name", "instrument"} | set(_SINGLE[kind])
    # a sheet lists most properties per direction (LT-1, LT-2, MIU-1, ...)
    for key in (*_DIRECTIONAL[kind], *UNUSED[kind]):
        known |= {key, f"{key}-1", f"{key}-2", f"{key}1", f"{key}2"}
    for key in data:
        if key not in known:
            raise FabricError(f"unknown in a {kind} sheet (its fields: "
                              f"{', '.join(_SINGLE[kind] + _DIRECTIONAL[kind])}; see "
                              "docs/fabrics.md)", file=path, place=f"field {key!r:.80}")
    with np.errstate(all="ignore"):  # an extreme value gives 0 or inf, refused later
        return _kes(data, path) if kind == "KES-F" else _fast(data, path)


def _instrument(value, path) -> str:
    key = (value.strip().lower().replace(" ", "").replace("-", "") if isinstance(value, str)
           else None)
    if key not in INSTRUMENTS:
        raise FabricError(f"expected 'KES-F' or 'FAST', got {value!r:.40}", file=path,
                          place="field 'instrument'")
    return INSTRUMENTS[key]


def _positive(value, path, field: str, unit: str, *, zero: bool = False) -> float:
    """``value`` as a number above 0 (``zero``: at least 0), else a :class:`FabricError`.
    A NumPy float: a conversion of an extreme value (a strain that is 1e-320 %, a bending
    length of 1e200 mm) then gives 0 or infinity, which the fabric's range check refuses
    naming the field, where Python's floats raised ZeroDivisionError or OverflowError."""
    try:
        return np.float64(number(value, field, low=0.0, low_open=not zero))
    except ValueError:
        want = "a number >= 0" if zero else "a positive number"
        raise FabricError(f"expected {want} [{unit}], got {value!r:.40}",
                          file=path, place=f"field '{field}'") from None


def _single(data: dict, path, field: str, unit: str) -> float:
    if field not in data:
        raise FabricError(f"missing [{unit}]", file=path, place=f"field '{field}'")
    return _positive(data[field], path, field, unit)


def _pair(data: dict, path, field: str, unit: str, *, optional: bool = False,
          zero: bool = False):
    """``(warp, weft)`` of the directional field ``field`` (above 0; ``zero``: at least 0),
    and the name it came from; None when ``optional`` and absent."""
    dashed = [k for k in (f"{field}-1", f"{field}-2") if k in data]
    plain = [k for k in (f"{field}1", f"{field}2") if k in data]
    split = dashed + plain
    if field in data and split:
        raise FabricError(f"given both as '{field}' and as {split}", file=path,
                          place=f"field '{field}'")
    if dashed and plain:
        # the first spelling found was read and the other dropped without a word
        raise FabricError(f"given both as {dashed} and as {plain}: one direction two ways; "
                          "keep one spelling", file=path, place=f"field '{field}'")
    if field in data:
        v = data[field]
        if isinstance(v, list):
            if len(v) != 2:
                raise FabricError(f"expected one number or [warp, weft], got {len(v)} values",
                                  file=path, place=f"field '{field}'")
            return (_positive(v[0], path, f"{field}[0]", unit, zero=zero),
                    _positive(v[1], path, f"{field}[1]", unit, zero=zero)), field
        x = _positive(v, path, field, unit, zero=zero)
        return (x, x), field
    for warp, weft in ((f"{field}-1", f"{field}-2"), (f"{field}1", f"{field}2")):
        if warp in data or weft in data:
            if warp not in data or weft not in data:
                given, missing = (warp, weft) if warp in data else (weft, warp)
                raise FabricError(f"missing (given '{given}'); give both directions",
                                  file=path, place=f"field '{missing}'")
            return (_positive(data[warp], path, warp, unit, zero=zero),
                    _positive(data[weft], path, weft, unit, zero=zero)), f"{warp}/{weft}"
    if optional:
        return None, field
    raise FabricError(f"missing [{unit}] (one number, [warp, weft], or {field}-1 and "
                      f"{field}-2)", file=path, place=f"field '{field}'")


def _friction(data: dict, path) -> float:
    if "friction" not in data:
        raise FabricError("missing: the cloth's friction coefficient against the body [-] "
                          "(a sheet's MIU is measured against a steel contactor, not skin)",
                          file=path, place="field 'friction'")
    try:
        return number(data["friction"], "friction", low=0.0)
    except ValueError:
        raise FabricError(f"expected a number >= 0 [-], got {data['friction']!r:.40}",
                          file=path, place="field 'friction'") from None


def _floats(fields: dict) -> dict:
    return {k: float(v) for k, v in fields.items()}


def _kes(data: dict, path) -> tuple[dict, dict]:
    w = _single(data, path, "W", "mg/cm^2")
    t = _single(data, path, "T", "mm")
    b, b_from = _pair(data, path, "B", "gf cm^2/cm")
    g, g_from = _pair(data, path, "G", "gf/(cm deg)")
    emt, emt_from = _pair(data, path, "EMT", "%")
    # (2HB 0: a fabric without bending friction, as its SI field allows)
    hb, hb_from = _pair(data, path, "2HB", "gf cm/cm", optional=True, zero=True)
    fields = {"density": w * KES_MASS, "thickness": t * MM,
              "bending_warp": b[0] * KES_BENDING, "bending_weft": b[1] * KES_BENDING,
              "shear": (g[0] + g[1]) / 2 * KES_SHEAR,
              "stretch_warp": KES_EMT_LOAD / (emt[0] / 100),
              "stretch_weft": KES_EMT_LOAD / (emt[1] / 100),
              "bending_hysteresis": 0.0 if hb is None else (hb[0] + hb[1]) / 2
              * KES_BENDING_HYSTERESIS,
              "friction": _friction(data, path)}
    origin = {"density": "W", "thickness": "T", "bending_warp": b_from,
              "bending_weft": b_from, "shear": g_from, "stretch_warp": emt_from,
              "stretch_weft": emt_from, "bending_hysteresis": hb_from, "friction": "friction"}
    return _floats(fields), origin


def _fast(data: dict, path) -> tuple[dict, dict]:
    if "T2" in data and "T" in data:
        raise FabricError("given both as 'T2' and as 'T'", file=path, place="field 'T2'")
    thick = "T" if "T" in data else "T2"
    w = _single(data, path, "W", "g/m^2")
    t = _single(data, path, thick, "mm")
    density = w * FAST_MASS
    b, b_from = _pair(data, path, "B", "uN m", optional=True)
    c, c_from = _pair(data, path, "C", "mm", optional=True)
    from_c = None if c is None else tuple(density * GRAVITY * (x * MM) ** 3 for x in c)
    if b is not None and from_c is not None:
        # a SiroFAST report prints both: they must say the same (B = W g C^3)
        for i, (given, implied) in enumerate(zip(b, from_c)):
            if abs(given * FAST_BENDING / implied - 1.0) > FAST_B_C_AGREE:
                raise FabricError(
                    f"the bending rigidity B{i + 1} {given:g} uN m and the bending length "
                    f"C{i + 1} {c[i]:g} mm disagree: W g C^3 is {implied / FAST_BENDING:.3g} "
                    f"uN m (more than {FAST_B_C_AGREE:.0%} apart; give one of them)",
                    file=path, place="field 'B'")
        c = None
    if b is None and c is None:
        raise FabricError("missing: the bending rigidity B [uN m] or the bending length C "
                          "[mm]", file=path, place="field 'B'")
    if b is not None:
        bending = (b[0] * FAST_BENDING, b[1] * FAST_BENDING)
    else:
        bending, b_from = from_c, c_from
    g, g_from = _pair(data, path, "G", "N/m")
    e, e_from = _pair(data, path, "E100", "%")
    fields = {"density": density, "thickness": t * MM,
              "bending_warp": bending[0], "bending_weft": bending[1],
              "shear": (g[0] + g[1]) / 2, "stretch_warp": FAST_E100_LOAD / (e[0] / 100),
              "stretch_weft": FAST_E100_LOAD / (e[1] / 100), "bending_hysteresis": 0.0,
              "friction": _friction(data, path)}
    origin = {"density": "W", "thickness": thick, "bending_warp": b_from,
              "bending_weft": b_from, "shear": g_from, "stretch_warp": e_from,
              "stretch_weft": e_from, "bending_hysteresis": "bending_hysteresis",
              "friction": "friction"}
    return _floats(fields), origin
