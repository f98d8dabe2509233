"""One entry point for every pattern file patternfit reads or writes, chosen by file ending
and, for JSON, by content.

Readers: ``.json`` (patternfit's own format or a GarmentCode specification, told apart by
content), ``.dxf`` (DXF-AAMA). Writers: ``.json`` (ours, or GarmentCode when asked or when the
name ends in ``_specification.json``), ``.dxf`` (DXF-AAMA plus its seam side file), ``.svg``
and ``.pdf`` (plots). Lengths are metres inside.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from ..constants import UNITS
from ..files import read_json_file
from .errors import PatternError
from .io import FORMAT, pattern_from_document, save_pattern
from .model import Pattern
from .orientation import TWISTED, twisted_warning
from .validate import check_pattern, check_seams

# .garmentcode, .dxf and .plot are imported inside the functions: a real import cycle (they
# import check_imported from here; .plot through .dxf).

__all__ = ["READ_SUFFIXES", "WRITE_FORMATS", "check_imported", "load_any_pattern",
           "save_any_pattern", "sniff_format"]

READ_SUFFIXES = (".json", ".dxf")
#: writer names and the file ending they go with
WRITE_FORMATS = {"patternfit": ".json", "garmentcode": ".json", "dxf": ".dxf", "svg": ".svg",
                 "pdf": ".pdf"}


def check_imported(pattern: Pattern) -> list[str]:
    """:func:`~patternfit.pattern.check_pattern` for a pattern read from another tool, except
    that seams whose sides differ in length beyond their stated ``ease`` (gathers, ease,
    ruffles the reader did not state) are allowed: they come back as warnings (meshing
    refuses them until their ease is stated). Raises :class:`PatternError` for everything
    else."""
    check_pattern(replace(pattern, seams=()))
    return check_seams(pattern, unequal="warn")


def sniff_format(path) -> str:
    """``"patternfit"``, ``"garmentcode"`` or ``"dxf"`` for a readable pattern file.

    Raises :class:`PatternError` naming the file for an unknown ending or JSON content.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".dxf":
        return "dxf"
    if suffix != ".json":
        raise PatternError(f"cannot read '{suffix or path.name}' files (readable: "
                           f"{', '.join(READ_SUFFIXES)})", file=path)
    return json_kind(read_json_file(path, error=PatternError), path)


def json_kind(data, path) -> str:
    """``"patternfit"`` or ``"garmentcode"`` for the parsed JSON document ``data`` of the
    file ``path``; a :class:`PatternError` naming the file for any other JSON."""
    from .garmentcode import is_garmentcode

    if isinstance(data, dict) and data.get("format") == FORMAT:
        return "patternfit"
    if is_garmentcode(data):
        return "garmentcode"
    raise PatternError("JSON is neither a patternfit pattern (\"format\": "
                       f"\"{FORMAT}\") nor a GarmentCode specification (\"pattern\": "
                       "{\"panels\": ...})", file=path)


def load_any_pattern(path, *, size: str | None = None, units: str | None = None) -> Pattern:
    """Read a pattern from any supported file (see module doc); errors name file, panel, edge.

    size : of a graded DXF, the size to read (default its sample size). A JSON file holds
        one size: a ``size`` other than its ``meta["size"]`` is refused, as is a size a DXF
        does not have, naming the file and the sizes it has.
    units : a DXF's length unit ("mm", "cm", "in", "m"), over what the file says or the
        reader guesses; refused for a JSON file, which states its own.

    ``pattern.meta["source_format"]`` says which reader was used; a patternfit JSON file
    converted from another format keeps that format in ``meta["converted_from"]``.
    """
    kind = sniff_format(path)
    if kind == "dxf":
        from .dxf import load_dxf

        return _said_if_twisted(load_dxf(path, size=size, units=units),
                                "check the side file's seams' 'reverse'")
    if units is not None:
        raise PatternError(f"units: set for a DXF only; this {kind} file states its own "
                           "units", file=path)
    if kind == "garmentcode":
        from .garmentcode import load_garmentcode

        pattern = load_garmentcode(path)
    else:
        document = read_json_file(Path(path), error=PatternError)
        pattern = pattern_from_document(document, path)
        _said_if_implausible(pattern, document)
        # a file converted from a DXF keeps what it came from, apart from the reader used now
        before = pattern.meta.get("source_format")
        if before not in (None, "patternfit"):
            pattern.meta.setdefault("converted_from", before)
        pattern.meta["source_format"] = "patternfit"
        _said_if_twisted(pattern, "check the seams' 'reverse'")
    has = pattern.meta.get("size")
    if size is not None and str(size).strip().upper() != str(has).strip().upper():
        graded = pattern.meta.get("sizes")
        others = [str(g) for g in graded if str(g) != str(has)] \
            if isinstance(graded, list) else []
        hint = (f" (its graded DXF's other sizes, {', '.join(others)}, are kept only to be "
                "written back: read the DXF in that size)" if others else "")
        raise PatternError(f"no size '{size}' in the file: it holds one size"
                           f"{f' ({has})' if has is not None else ''}{hint}; a size is picked "
                           "from a built-in garment's sizes or a graded DXF's", file=path)
    return pattern


def _said_if_implausible(pattern: Pattern, document: dict) -> None:
    """The size warnings the DXF and GarmentCode readers give (a piece implausibly large
    or small in the units read, :func:`~.plausible.size_warnings`), for a patternfit JSON
    read from ``document``, in ``meta["warnings"]`` in place of any the file kept from an
    earlier reading in other units: a skirt in cm stated as "mm", 6.4 cm wide, was read
    without a word and fell in its drape; written again in metres, it kept "read in
    millimetres ... set units cm", which would have made it 100 times too large."""
    from .plausible import is_size_warning, size_warnings

    unit = document.get("units", "m")
    said = size_warnings(pattern.panels, UNITS[unit],
                         f"its 'units': '{unit}'" if "units" in document
                         else "no 'units', so metres",
                         hint=lambda u: f'set "units": "{u}" in the file')
    before = list(pattern.meta.get("warnings", []))
    kept = [w for w in before if not is_size_warning(w)]
    now = kept + [w for w in said if w not in kept]
    if now != before:
        pattern.meta["warnings"] = now


def _said_if_twisted(pattern: Pattern, fix: str) -> Pattern:
    """``pattern`` with the warning of seams that sew it twisted in ``meta["warnings"]``
    (:func:`~.orientation.twisted_warning`), as the GarmentCode reader gives it: a DXF's
    side file or a patternfit JSON so sewn draped with 457 crossed pairs and no word why.
    Once: a JSON written from another reader's pattern keeps that reader's warnings."""
    said = twisted_warning(pattern, fix=fix)
    if said and not any(str(w).startswith(TWISTED) for w in pattern.meta.get("warnings", [])):
        pattern.meta["warnings"] = [*pattern.meta.get("warnings", []), said]
    return pattern


def save_any_pattern(pattern: Pattern, path, *, fmt: str | None = None, units: str = "m",
                     paper: str = "a4", fit=None) -> list[Path]:
    """Write ``pattern`` in the format named by ``fmt`` or by the file ending; returns the
    files written (a DXF brings its seam side file).

    fmt : one of :data:`WRITE_FORMATS`; by default from the ending, ``.json`` meaning ours
        unless the name ends in ``_specification.json`` (GarmentCode's file name).
    units : length unit of a patternfit JSON file (``m``, ``cm``, ``mm``, ``in``); GarmentCode
        files are written in centimetres, DXF in millimetres.
    paper, fit : for PDF (``"a4"`` or ``"letter"``) and SVG/PDF fit colours, see
        :func:`patternfit.pattern.plot.layout`.
    """
    path = Path(path)
    if fmt is None:
        suffix = path.suffix.lower()
        if path.name.lower().endswith("_specification.json"):
            fmt = "garmentcode"
        else:
            fmt = {v: k for k, v in WRITE_FORMATS.items() if k != "garmentcode"}.get(suffix)
        if fmt is None:
            raise ValueError(f"path: cannot tell the format of '{path.name}' (endings: "
                             f"{', '.join(sorted(set(WRITE_FORMATS.values())))})")
    if fmt not in WRITE_FORMATS:
        raise ValueError(f"fmt: expected one of {sorted(WRITE_FORMATS)}, got {fmt!r}")
    if fmt == "patternfit":
        return [save_pattern(pattern, path, units=units)]
    if fmt == "garmentcode":
        from .garmentcode import save_garmentcode

        return [save_garmentcode(pattern, path)]
    if fmt == "dxf":
        from .dxf import save_dxf, sidecar_path

        return [save_dxf(pattern, path), sidecar_path(path)]
    from . import plot

    if fmt == "svg":
        return [plot.write_svg(pattern, path, fit=fit)]
    plot.write_pdf(pattern, path, paper=paper, fit=fit)
    return [path]
