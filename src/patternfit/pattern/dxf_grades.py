"""Graded DXF files: one block per piece and size, read as one pattern in one size.

The file's ``Sample Size:`` is the base size; every block's ``Size:`` text says which size it
draws (a block without one belongs to every size). The chosen size becomes the pattern's
panels; the other sizes are kept as the file drew them, in ``meta["grade"]`` (size -> the
pieces, :meth:`~.dxf_format.RawPiece.to_json`, metres), so the writer gives every size back
and another size can be picked later. ``meta["sizes"]`` lists the sizes in file order,
``meta["size"]`` the one shown, ``meta["sample_size"]`` the base.
"""

from __future__ import annotations

from typing import Any

from .dxf_format import RawPiece
from .errors import PatternError

__all__ = ["graded_meta", "graded_pieces", "pick_size", "pieces_in_size", "share_quantities",
           "sizes_of"]


def sizes_of(pieces: list[RawPiece]) -> list[str]:
    """The sizes the pieces are drawn in, in file order (empty when none says)."""
    out: list[str] = []
    for p in pieces:
        if p.size and p.size not in out:
            out.append(p.size)
    return out


def share_quantities(pieces: list[RawPiece]) -> None:
    """Give every block without a ``Quantity:`` text (quantity None) the quantity another
    block of the same piece states, else 1, in place: Gerber AccuMark writes it in the
    sample size's block only, so a pair read in another size would lose its second panel."""
    stated: dict[str | None, int] = {}
    for p in pieces:
        if p.quantity is not None:
            stated.setdefault(p.name or p.block, p.quantity)
    for p in pieces:
        if p.quantity is None:
            p.quantity = stated.get(p.name or p.block, 1)


def pick_size(sizes: list[str], requested: str | None, sample: str | None) -> str | None:
    """The size to read: ``requested`` (matched ignoring case), else the sample size, else
    the first. A :class:`PatternError` naming the file's sizes for a size it does not have."""
    if requested is not None:
        for s in sizes:
            if s.strip().upper() == str(requested).strip().upper():
                return s
        have = ", ".join(sizes) if sizes else "none: the file is in one size"
        raise PatternError(f"no size '{requested}' in the file (sizes: {have})")
    if sample is not None:
        for s in sizes:
            if s.strip().upper() == sample.strip().upper():
                return s
    return sizes[0] if sizes else None


def pieces_in_size(pieces: list[RawPiece], size: str | None) -> list[RawPiece]:
    """The pieces drawn in ``size`` and those drawn for every size (no ``Size:`` text)."""
    return [p for p in pieces if size is None or not p.size or p.size == size]


def graded_meta(pieces: list[RawPiece], size: str | None, sample: str | None
                ) -> dict[str, Any]:
    """What a pattern read in ``size`` keeps of the file's grading: ``size``, ``sizes``,
    ``sample_size`` and, for a file with more than one size, ``grade`` (every other size's
    pieces as JSON)."""
    sizes = sizes_of(pieces)
    meta: dict[str, Any] = {}
    if size is not None:
        meta["size"] = size
    elif sample:
        meta["size"] = sample
    if sample:
        meta["sample_size"] = sample
    if len(sizes) > 1:
        meta["sizes"] = sizes
        meta["grade"] = {s: [p.to_json() for p in pieces if p.size == s]
                         for s in sizes if s != size}
    return meta


def graded_pieces(meta: dict) -> dict[str, list[RawPiece]]:
    """The other sizes' pieces kept in ``meta["grade"]`` (none when it has no grade); a
    :class:`PatternError` when they are malformed."""
    grade = meta.get("grade") if isinstance(meta, dict) else None
    if not isinstance(grade, dict):
        return {}
    out = {}
    for size, pieces in grade.items():
        if not isinstance(pieces, list) or not all(isinstance(p, dict) for p in pieces):
            raise PatternError(f"meta 'grade': size '{size}' must be a list of pieces")
        out[str(size)] = [RawPiece.from_json(p) for p in pieces]
    return out
