"""ARCSim material files: Wang, O'Brien & Ramamoorthi 2011's measured fabrics as distributed.

Wang et al.'s ten measured fabrics ("Data-driven elastic models for cloth", ACM TOG 30(4) 71;
the Berkeley Garment Library's ``Materials/``, ARCSim's ``materials/``) are JSON files read by
ARCSim's ``load_material_data``::

    {"density": 0.187,
     "stretching": [[16.59, -14.70, 34.48, 36.86], ... 6 rows of 4],
     "bending": [[23.19e-6, ... 5 samples], [...], [...]]}

``density`` is the mass per area [kg/m^2]. ``stretching`` row 0 is the sample at zero strain,
``[c0, c1, c2, c3]`` [N/m], of ARCSim's membrane ``A/2 (k0 G00^2 + k2 G11^2 + 2 k1 G00 G11 +
k3 G01^2)`` with ``k = 2 row0`` (``dde.cpp``), axis 0 the weft / course: stretch_warp = 2 c2,
stretch_weft = 2 c0, shear = c3 / 2. ``bending`` holds ARCSim's hinge stiffness ``ke`` [N m]
for hinges along axis 0 (row 0: curvature along the warp), at 45 degrees (row 1) and along
axis 1 (row 2), each at five curvatures (column 0: none); B = ``ARCSIM_BENDING_FACTOR`` x the
zero-curvature sample. Derivations: docs/fabrics.md, "Conversions used". Rows 1-5 of
``stretching`` (the stiffening with strain) and columns 1-4 of ``bending`` are checked and not
used: the model is linear. The coupling c1 of row 0 is not used either (the membrane has no
Poisson coupling); a c1 with which the file's zero-strain table is not positive definite
(c1² ≥ c0 c2, Wang et al.'s navy-sparkle-sweat) is read and noted (:func:`arcsim_notes`), not
refused: ARCSim ships and runs such files, and the linear model takes nothing from c1.

The files carry neither friction nor thickness (an ARCSim scene sets friction). A file may add
``friction`` [-] and ``thickness`` [m] (ARCSim ignores other fields), and ``name``; without
them :func:`patternfit.sim.fabrics.load_fabric` assumes them and says so.
"""

from __future__ import annotations

from ..arguments import number
from ..errors import FabricError

#: Continuum bending rigidity B [N m] per unit of ARCSim's hinge stiffness ``ke`` (the
#: ``bending`` samples of Wang et al. 2011's material files). ARCSim stores
#: ``ke l^2 / (2 (A0 + A1)) theta^2 / 4`` per hinge; summed over an equilateral mesh bent on a
#: cylinder of curvature k this is ``ke k^2 / 8`` per area, against ``B k^2 / 2``; derivation and
#: the spread over other meshes in docs/fabrics.md.
ARCSIM_BENDING_FACTOR = 0.25

#: the fields ARCSim reads, and those a file may add for patternfit
FIELDS = ("density", "stretching", "bending")
EXTRA = ("name", "friction", "thickness")
#: the arrays' shapes (rows, samples per row), as ARCSim's parser reads them
SHAPES = {"stretching": (6, 4), "bending": (3, 5)}


def is_arcsim(data: dict) -> bool:
    """Whether the fabric file's object ``data`` is an ARCSim material (has ``stretching``)."""
    return "stretching" in data


def arcsim_fields(data: dict, path) -> tuple[dict, dict]:
    """The :class:`~patternfit.sim.fabrics.Fabric` fields (SI, un-checked) of the ARCSim
    material ``data`` read from ``path``, and for each the file's entry it came from.

    Returns ``(fields, origin)``: ``fields`` maps density [kg/m^2], stretch_warp,
    stretch_weft, shear [N/m], bending_warp, bending_weft [N m] and bending_hysteresis (0), and
    ``friction`` / ``thickness`` where the file gives them; ``origin`` maps each to the entry
    (``stretching[0][2] x 2``, for errors).

    Raises :class:`FabricError` naming ``path`` and the entry: an unknown or missing field, an
    array not of ARCSim's shape, an entry that is not a finite number.
    """
    for key in data:
        if key not in FIELDS + EXTRA:
            raise FabricError(f"unknown in an ARCSim material (its fields: {', '.join(FIELDS)}; "
                              f"patternfit also reads {', '.join(EXTRA)})", file=path,
                              place=f"field {key!r:.80}")
    for key in FIELDS:
        if key not in data:
            raise FabricError("missing from an ARCSim material", file=path,
                              place=f"field '{key}'")
    density = _number(data["density"], path, "density")
    stretch = _table(data, path, "stretching")
    bend = _table(data, path, "bending")
    fields = {"density": density, "stretch_warp": 2.0 * stretch[0][2],
              "stretch_weft": 2.0 * stretch[0][0], "shear": stretch[0][3] / 2.0,
              "bending_warp": ARCSIM_BENDING_FACTOR * bend[0][0],
              "bending_weft": ARCSIM_BENDING_FACTOR * bend[2][0], "bending_hysteresis": 0.0}
    origin = {"density": "density", "stretch_warp": "stretching[0][2] x 2",
              "stretch_weft": "stretching[0][0] x 2", "shear": "stretching[0][3] / 2",
              "bending_warp": f"bending[0][0] x {ARCSIM_BENDING_FACTOR}",
              "bending_weft": f"bending[2][0] x {ARCSIM_BENDING_FACTOR}",
              "bending_hysteresis": "bending_hysteresis"}
    for key in ("friction", "thickness"):
        if key in data:
            fields[key] = data[key]
            origin[key] = key
    return fields, origin


def arcsim_notes(data: dict) -> tuple[str, ...]:
    """Sentences on what the ARCSim material ``data`` (read by :func:`arcsim_fields`, so of
    ARCSim's shape) gives that the linear model leaves out and a reader should know: a
    coupling c1 [N/m] (``stretching[0][1]``) past what the file's own stretches c0, c2
    [N/m] allow (c1² ≥ c0 c2). Empty otherwise."""
    c0, c1, c2 = (float(v) for v in data["stretching"][0][:3])
    # with negative c0 or c2 the range checks refuse the stretches themselves
    if not (c0 > 0 and c2 > 0 and c1 * c1 >= c0 * c2):
        return ()
    return (f"stretching[0][1]: c1 = {c1:g} N/m not used (the linear membrane has no Poisson "
            f"coupling); with it the file's zero-strain stretching would not be positive "
            f"definite (c1² = {c1 * c1:.4g} ≥ c0 c2 = {c0 * c2:.4g})",)


def _number(value, path, place: str) -> float:
    try:
        return number(value, place)
    except ValueError:
        raise FabricError(f"expected a finite number, got {value!r:.40}", file=path,
                          place=f"field '{place}'") from None


def _table(data: dict, path, key: str) -> list[list[float]]:
    rows, cols = SHAPES[key]
    table = data[key]
    if not isinstance(table, list) or len(table) != rows:
        got = f"{len(table)} rows" if isinstance(table, list) else type(table).__name__
        raise FabricError(f"expected {rows} rows of {cols} numbers, got {got}", file=path,
                          place=f"field '{key}'")
    out = []
    for i, row in enumerate(table):
        if not isinstance(row, list) or len(row) != cols:
            got = f"{len(row)} numbers" if isinstance(row, list) else type(row).__name__
            raise FabricError(f"expected {cols} numbers, got {got}", file=path,
                              place=f"field '{key}', row {i}")
        out.append([_number(v, path, f"{key}[{i}][{j}]") for j, v in enumerate(row)])
    return out
