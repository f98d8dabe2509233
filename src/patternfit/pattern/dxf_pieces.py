"""A DXF piece (:class:`~.dxf_format.RawPiece`) made into panels: a half piece unfolded about
its mirror line, the outline fitted (:mod:`.dxf_curves`) on the sew line when there is one
(the cut line kept beside it), notches placed on the edges, internal lines and drill holes
kept, and a piece cut more than once (``Quantity: 2``) made into a left and a mirrored right
panel. Every length is metres.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy.spatial import cKDTree

from ..constants import tol
from .dxf_curves import corners, dedupe, loop_from_points
from .dxf_format import RawPiece
from .dxf_notches import notches_on
from .errors import PatternError
from .model import InnerLine, Loop, Panel

__all__ = ["MIRROR", "copy_names", "mirrored", "panels_from_piece", "unfolded"]

#: x -> -x: how the second panel of a pair is cut (the piece turned over)
MIRROR = np.diag([-1.0, 1.0])


def _reflect(p: np.ndarray, a: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Points (k, 2) mirrored about the line through ``a`` along the unit vector ``d``."""
    q = np.asarray(p, dtype=np.float64).reshape(-1, 2) - a
    return a + 2.0 * np.outer(q @ d, d) - q


def _unfold_loop(loop: np.ndarray, a: np.ndarray, d: np.ndarray, block: str
                 ) -> tuple[np.ndarray, list[np.ndarray]]:
    """A closed half outline (k, 2) whose side along the fold line (through ``a`` along
    ``d``) is replaced by its mirror image; and the points where the halves join smoothly
    (no corner over 25° there)."""
    off = np.abs((loop - a) @ np.array([-d[1], d[0]]))
    on = off < tol.dxf_fit
    n = len(loop)
    if on.all() or on.sum() < 2:
        raise PatternError("the mirror line (layer 6) does not run along the piece's "
                           "boundary: the half piece cannot be unfolded", panel=block)
    # the longest cyclic run of points on the fold line is the fold side
    start = int(np.flatnonzero(~on)[0])
    best, run = (0, 0), None
    for k in range(n):
        i = (start + k) % n
        if on[i] and run is None:
            run = k
        if run is not None and (not on[i] or k == n - 1):
            end = k if on[i] else k - 1
            if end - run > best[1] - best[0]:
                best = (run, end)
            run = None
    if best[1] == best[0]:
        raise PatternError("the mirror line (layer 6) touches the boundary at one point "
                           "only: the half piece cannot be unfolded", panel=block)
    s, e = (start + best[0]) % n, (start + best[1]) % n
    half = np.roll(loop, -e, axis=0)[: (s - e) % n + 1]  # from the fold's end round to its start
    full = np.vstack([half, _reflect(half, a, d)[::-1][1:-1]])
    sharp = set(corners(full))
    smooth = [i for i in (0, len(half) - 1) if i not in sharp]
    return full, [full[i] for i in smooth]


def unfolded(piece: RawPiece) -> RawPiece:
    """``piece`` with its first mirror line (layer 6) unfolded: cut line, sew line and every
    mark mirrored about it into one symmetric piece; turn points where the halves join are
    dropped unless the outline has a corner there. A piece without a mirror line is returned
    as it is."""
    if not piece.folds:
        return piece
    a, b = piece.folds[0]
    length = float(np.linalg.norm(b - a))
    if length < tol.dxf_fit:
        raise PatternError("the mirror line (layer 6) has no length", panel=piece.block)
    d = (b - a) / length

    def both(p):
        return np.vstack([p, _reflect(p, a, d)]) if len(p) else p

    cut, sew, joins = [], [], []
    for src, dst in ((piece.cut[:1], cut), (piece.sew[:1], sew)):
        for loop in src:
            full, smooth = _unfold_loop(loop, a, d, piece.block)
            joins += smooth
            dst.append(full)
    turns = dedupe_points(both(piece.turns))
    if joins and len(turns):
        near = np.min(np.linalg.norm(turns[:, None] - np.array(joins)[None], axis=2), axis=1)
        turns = turns[near >= tol.dxf_fit]
    notches = piece.notches + [_reflect(q, a, d) for q in piece.notches]
    return replace(piece, cut=cut + piece.cut[1:], sew=sew + piece.sew[1:],
                   cutouts=piece.cutouts + [_reflect(q, a, d)[::-1] for q in piece.cutouts],
                   turns=turns, notches=_distinct(notches),
                   lines=piece.lines + [_reflect(q, a, d) for q in piece.lines],
                   drills=dedupe_points(both(piece.drills)), folds=[])


def _first_of_each(rows: np.ndarray) -> np.ndarray:
    """Indices of the rows (k, d) [m] kept when every row within ``tol.dxf_repeat`` (in
    each coordinate) of an earlier one is dropped."""
    if len(rows) < 2:
        return np.arange(len(rows))
    pairs = cKDTree(rows).query_pairs(tol.dxf_repeat, p=np.inf, output_type="ndarray")
    drop = np.zeros(len(rows), dtype=bool)
    drop[pairs.max(axis=1) if len(pairs) else []] = True
    return np.flatnonzero(~drop)


def dedupe_points(p: np.ndarray) -> np.ndarray:
    """Points (k, 2) [m] without those within ``tol.dxf_repeat`` of an earlier one."""
    p = np.asarray(p, dtype=np.float64).reshape(-1, 2)
    return p[_first_of_each(p)]


def _distinct(marks: list[np.ndarray]) -> list[np.ndarray]:
    """Notch marks ((2, 2) each) without repeats (a mark on the mirror line and its image)."""
    if not marks:
        return []
    rows = np.array([np.asarray(m, dtype=np.float64).reshape(4) for m in marks])
    return [marks[i] for i in _first_of_each(rows)]


def mirrored(panel: Panel, name: str) -> Panel:
    """``panel`` turned over (x -> -x) and called ``name``: the other panel of a pair cut
    from a doubled fabric. Edge names, notches' fractions and the grain line carry over."""
    def flip(p):
        return np.asarray(p, dtype=np.float64).reshape(-1, 2) @ MIRROR

    def loop(lp: Loop) -> Loop:
        return replace(lp, edges=tuple(e.transformed(MIRROR) for e in lp.edges))
    gx, gy = panel.grainline
    return replace(panel, name=name, outline=loop(panel.outline),
                   inner=tuple(loop(lp) for lp in panel.inner), grainline=(-gx, gy),
                   lines=tuple(InnerLine(ln.name, flip(ln.points)) for ln in panel.lines),
                   drill_holes=flip(panel.drill_holes),
                   cut_line=flip(panel.cut_line)[::-1] if panel.cut_line else ())


def copy_names(name: str, quantity: int) -> list[str]:
    """Panel names for a piece cut ``quantity`` times: itself once; a pair ``NAME_L`` and
    ``NAME_R``; more pairs ``NAME_L2``, ``NAME_R2``..."""
    if quantity <= 1:
        return [name]
    return [f"{name}_{'LR'[k % 2]}{k // 2 + 1 if k >= 2 else ''}" for k in range(quantity)]


def panels_from_piece(piece: RawPiece, name: str, *, prefer_sew: bool = True,
                      foreign: bool = True, span: float = tol.dxf_span) -> list[Panel]:
    """The panels of one DXF piece: unfolded, fitted on the sew line (``prefer_sew``, when
    there is one) else the cut line, with notches, internal lines, drill holes, the cut line
    (when the outline is the sew line) and the grain line; ``quantity`` panels, the odd ones
    mirrored (:func:`copy_names`).

    foreign : the file comes from another tool (see :func:`.dxf_curves.loop_from_points`).
    span : how far [m] fitted edges may stray from the file's polyline (the same).
    """
    piece = unfolded(piece)
    on_sew = bool(piece.sew and (prefer_sew or not piece.cut))
    ring = piece.sew[0] if on_sew else piece.cut[0]
    outline = loop_from_points(ring, piece.turns, "outline", "e", foreign=foreign, span=span)
    inner = tuple(loop_from_points(q, piece.turns, f"inner{k}", f"i{k}_e", foreign=foreign,
                                   span=span)
                  for k, q in enumerate(piece.cutouts))
    cut = dedupe(piece.cut[0], closed=True) if on_sew and piece.cut else np.zeros((0, 2))
    lines = [dedupe(q, closed=False) for q in piece.lines]
    panel = Panel(name, outline, inner, piece.grain or (0.0, 1.0),
                  lines=tuple(InnerLine(f"line{k}", q) for k, q in enumerate(lines)
                              if len(q) >= 2),
                  drill_holes=piece.drills, cut_line=cut)
    # marks on the cut line reach the sew line across the allowance
    allowance = 0.0
    if len(cut):
        allowance = float(cKDTree(outline.polygon(64)).query(cut)[0].max())
    panel = replace(panel, notches=notches_on(panel, piece.notches,
                                              tol.notch_reach + allowance))
    return [replace(panel, name=n) if k % 2 == 0 else mirrored(panel, n)
            for k, n in enumerate(copy_names(name, piece.quantity))]
