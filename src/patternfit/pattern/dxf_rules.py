"""ASTM D6673 / ANSI-AAMA grade rule tables (``.rul``): a DXF drawn in its sample size only,
graded by rules.

CAD systems (Gerber AccuMark, Lectra, Optitex) export a graded style either as a block per
piece and size (:mod:`.dxf_grades`) or as the sample size alone with a rule table beside it.
In the DXF, a grade point is a POINT on layer 2 (turn point) or 3 (curve point), or a notch
on layer 4, followed by a TEXT ``# N`` on that layer: rule N moves it. The ``.rul`` file is
plain text::

    ANSI/AAMA VERSION: 1.0.0            (or ASTM/D13Proposal ...)
    AUTHOR: ...
    UNITS: METRIC                       (millimetres; ENGLISH: inches)
    GRADE RULE TABLE: SHIRTS
    NUMBER OF SIZES: 3
    SIZE LIST: S M L
    SAMPLE SIZE: M
    RULE: DELTA 1
         -5.00,    -3.00      0.00,     0.00      5.00,     3.00
    RULE: DELTA 2
    ...
    END

one (dx, dy) pair per size in the size list's order, any number of pairs per line. Each pair
is that size's offset of the point from where the sample size draws it, in the table's units,
added to the sample's coordinates: cumulative from the sample size, not size-to-size steps.
Real tables show it (quoted by public readers of real exports, docs/interchange.md): an
Optitex rule over six sizes with the sample third reads 0.50, 0.25, 0, -0.25, -0.625, -1.0
inch (zero at the sample, growing away from it), an AccuMark one 0.1817, 0.0905, 0, -0.1802
(XS twice S); as steps, the sample's own pair would mean nothing. So the sample size's pair
must be zero: a rule that moves the sample is refused (the columns disagree with ``SAMPLE
SIZE``, or the values are steps).
A point between two grade points of a line moves by the two offsets interpolated along the
line's length; other marks (turn points, notches, drill holes, internal lines, the sew line)
move with the nearest point of the cut line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

from ..constants import limits, tol
from ..files import read_bytes_capped
from .errors import PatternError

__all__ = ["RuleTable", "graded_by_rules", "parse_rules", "read_rules", "rule_points",
           "rules_path"]

_UNIT = {"METRIC": 0.001, "ENGLISH": 0.0254}
_RULE = re.compile(r"RULE\s*:\s*DELTA\s+(\d+)\s*$", re.IGNORECASE)
_PAIR = re.compile(r"([-+]?\d*\.?\d+(?:[eE][-+]?\d+)?)\s*,\s*([-+]?\d*\.?\d+(?:[eE][-+]?\d+)?)")
_RULE_TEXT = re.compile(r"#\s*(\d+)\s*$")
#: sizes one table may list [-]
MAX_SIZES = 100
#: a grade point lies this close [m] to the point of the line it moves
POINT_MATCH = 5e-4


@dataclass(frozen=True)
class RuleTable:
    """A grade rule table: ``name`` (``GRADE RULE TABLE``), ``sizes`` in the file's order,
    ``sample`` (the sample size, one of ``sizes``), and ``rules``: rule number -> offsets
    (len(sizes), 2) [m] of a point in each size from where the sample size draws it."""

    name: str | None
    sizes: tuple[str, ...]
    sample: str
    rules: dict


def rules_path(dxf_path) -> Path | None:
    """The rule table beside a DXF: same name, ending ``.rul`` in any case; None if none."""
    p = Path(dxf_path)
    for suffix in (".rul", ".RUL", ".Rul"):
        q = p.with_suffix(suffix)
        if q.is_file():
            return q
    return None


def _header(lines: list[str], key: str) -> str | None:
    for line in lines:
        k, sep, v = line.partition(":")
        if sep and k.strip().upper() == key:
            return v.strip()
    return None


def parse_rules(text: str) -> RuleTable:
    """The :class:`RuleTable` of a ``.rul`` file's text; a :class:`PatternError` saying
    which header or rule is wrong (no size list, a count that disagrees with it, a sample
    size not in it, a rule without one pair per size, a value that is not finite, a rule
    that moves the sample size)."""
    lines = [ln.strip() for ln in text.replace("\r\n", "\n").replace("\r", "\n").split("\n")]
    first = next((i for i, ln in enumerate(lines) if _RULE.match(ln)), len(lines))
    head = lines[:first]
    sizes = tuple((_header(head, "SIZE LIST") or "").split())
    if not sizes:
        raise PatternError("the rule table has no 'SIZE LIST:'")
    if len(sizes) > MAX_SIZES or len(set(sizes)) != len(sizes):
        raise PatternError(f"'SIZE LIST:' must name at most {MAX_SIZES} different sizes")
    count = _header(head, "NUMBER OF SIZES")
    if count is not None and (not count.isdigit() or int(count) != len(sizes)):
        raise PatternError(f"'NUMBER OF SIZES: {count}' disagrees with the size list's "
                           f"{len(sizes)} sizes")
    sample = _header(head, "SAMPLE SIZE")
    if sample not in sizes:
        raise PatternError(f"'SAMPLE SIZE: {sample}' is not in the size list "
                           f"({', '.join(sizes)})")
    units = (_header(head, "UNITS") or "METRIC").upper()
    if units not in _UNIT:
        raise PatternError(f"'UNITS: {units}' is neither METRIC nor ENGLISH")
    scale = _UNIT[units]
    rules: dict[int, np.ndarray] = {}
    at = first
    while at < len(lines):
        m = _RULE.match(lines[at])
        at += 1
        if m is None:
            if lines[at - 1] and lines[at - 1].upper() != "END":
                raise PatternError(f"line {at}: expected 'RULE: DELTA n', got "
                                   f"{lines[at - 1][:40]!r}")
            continue
        number = int(m.group(1))
        pairs: list[tuple[float, float]] = []
        while at < len(lines) and lines[at] and not _RULE.match(lines[at]) \
                and lines[at].upper() != "END":
            found = _PAIR.findall(lines[at])
            if not found:
                raise PatternError(f"line {at + 1}: expected (dx, dy) pairs or 'RULE: DELTA n', "
                                   f"got {lines[at][:40]!r}")
            pairs += [(float(a), float(b)) for a, b in found]
            at += 1
        if len(pairs) != len(sizes):
            raise PatternError(f"rule {number} has {len(pairs)} (dx, dy) pairs, one per size "
                               f"({len(sizes)}) expected")
        if number in rules:
            raise PatternError(f"rule {number} is given twice")
        if len(rules) >= limits.segments_per_panel:
            raise PatternError(f"the rule table has more than {limits.segments_per_panel} "
                               "rules (the segment limit)")
        values = np.array(pairs) * scale
        if not np.isfinite(values).all() or np.abs(values).max(initial=0.0) > limits.extent:
            raise PatternError(f"rule {number} has a value that is not a length")
        at_sample = values[sizes.index(sample)]
        if np.abs(at_sample).max() > tol.dxf_repeat:
            raise PatternError(
                f"rule {number} moves the sample size {sample} by ({pairs[sizes.index(sample)][0]:g}"
                f", {pairs[sizes.index(sample)][1]:g}) {units.lower()} units: a rule gives each "
                "size's offset from the sample size, zero at the sample (the pairs are not in "
                "the size list's order, or they are size-to-size steps)")
        rules[number] = values
    return RuleTable(_header(head, "GRADE RULE TABLE"), sizes, sample, rules)


def read_rules(path) -> RuleTable:
    """The rule table in file ``path`` (:func:`parse_rules`); errors name the file."""
    path = Path(path)
    data = read_bytes_capped(path, limit=limits.dxf_bytes, error=PatternError)
    try:
        return parse_rules(data.decode("latin-1"))
    except PatternError as exc:
        raise exc.located(path) from None


def rule_points(block, scale: float) -> list[tuple[np.ndarray, int]]:
    """The grade points of a DXF block: (point (2,) [m], rule number), each a POINT (or a
    notch LINE) on layer 2, 3 or 4 followed by a TEXT ``# N`` on the same layer; a TEXT
    ``# N`` with no point before it marks its own insertion point."""
    out, pending = [], None
    for e in block:
        layer = str(e.dxf.get("layer", ""))
        if layer not in ("2", "3", "4"):
            continue
        kind = e.dxftype()
        if kind == "POINT":
            pending = (layer, np.array(tuple(e.dxf.location)[:2], dtype=np.float64) * scale)
        elif kind == "LINE":
            pending = (layer, np.array(tuple(e.dxf.start)[:2], dtype=np.float64) * scale)
        elif kind == "TEXT":
            m = _RULE_TEXT.match(str(e.dxf.get("text", "")).strip())
            if m is None:
                continue
            if pending is not None and pending[0] == layer:
                at = pending[1]
            else:
                at = np.array(tuple(e.dxf.insert)[:2], dtype=np.float64) * scale
            out.append((at, int(m.group(1))))
            pending = None
    return out


def _loop_offsets(loop: np.ndarray, marks, table: RuleTable, k: int) -> np.ndarray | None:
    """Offsets (n, 2) [m] in size ``k`` of a closed loop's points: a point within
    :data:`POINT_MATCH` of a grade point moves by its rule, the others by the offsets of the
    grade points either side interpolated along the loop; None without grade points."""
    n = len(loop)
    ruled = {}
    for at, rule in marks:
        d = np.linalg.norm(loop - at, axis=1)
        i = int(np.argmin(d))
        if d[i] <= POINT_MATCH and rule in table.rules:
            ruled.setdefault(i, table.rules[rule][k])
    if not ruled:
        return None
    seg = np.linalg.norm(np.roll(loop, -1, axis=0) - loop, axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])   # arc length at each point, and round
    total = s[-1]
    keys = sorted(ruled)
    out = np.zeros((n, 2))
    for a, b in zip(keys, keys[1:] + keys[:1]):
        span = (s[b] - s[a]) % total or total
        i = a
        while True:
            t = ((s[i] - s[a]) % total) / span
            out[i] = (1.0 - t) * ruled[a] + t * ruled[b]
            i = (i + 1) % n
            if i == b:
                break
    for i in keys:
        out[i] = ruled[i]
    return out


def graded_by_rules(pieces: list, marks: dict, table: RuleTable) -> list:
    """Every piece of a sample-size DXF in every size of ``table``: the pieces (each
    :class:`~.dxf_format.RawPiece`, ``marks[block]`` its grade points from
    :func:`rule_points`) copied once per size, their ``size`` set and their points moved by
    the rules. A grade point's rule that the table lacks is a :class:`PatternError`."""
    out = []
    for piece in pieces:
        for at, rule in marks.get(piece.block, []):
            if rule not in table.rules:
                raise PatternError(f"grade point at ({at[0] * 1000:.1f}, {at[1] * 1000:.1f}) mm "
                                   f"uses rule {rule}, which the rule table does not have",
                                   panel=piece.block)
    for k, size in enumerate(table.sizes):
        for piece in pieces:
            loop = piece.cut[0] if piece.cut else piece.sew[0]
            own = marks.get(piece.block, [])
            moved = _loop_offsets(loop, own, table, k)
            if moved is None:
                out.append(replace(piece, size=size))
                continue
            shift = _Shift(loop, moved, [(at, table.rules[r][k]) for at, r in own])
            out.append(replace(
                piece, size=size, cut=[shift(q) for q in piece.cut],
                sew=[shift(q) for q in piece.sew], cutouts=[shift(q) for q in piece.cutouts],
                turns=shift(piece.turns), notches=[shift(q, rigid=True) for q in piece.notches],
                lines=[shift(q) for q in piece.lines], drills=shift(piece.drills),
                folds=[shift(q) for q in piece.folds]))
    return out


class _Shift:
    """Moves points (k, 2) [m] of a piece into another size: a point at a grade point by its
    rule, any other by the offset of the nearest point of the piece's cut line (interpolated
    along the segment it falls on)."""

    def __init__(self, loop: np.ndarray, moved: np.ndarray, ruled: list):
        self.loop, self.moved, self.ruled = loop, moved, ruled
        self.tree = cKDTree(loop)

    def _offset(self, p: np.ndarray) -> np.ndarray:
        n = len(self.loop)
        i = self.tree.query(p)[1]
        best, out = np.full(len(p), np.inf), np.zeros((len(p), 2))
        for a in ((i - 1) % n, i):           # the two segments either side of the vertex
            b = (a + 1) % n
            d = self.loop[b] - self.loop[a]
            t = np.clip(np.einsum("ij,ij->i", p - self.loop[a], d)
                        / np.maximum(np.einsum("ij,ij->i", d, d), 1e-18), 0.0, 1.0)
            dist = np.linalg.norm(self.loop[a] + t[:, None] * d - p, axis=1)
            take = dist < best
            best[take] = dist[take]
            out[take] = ((1.0 - t)[:, None] * self.moved[a] + t[:, None] * self.moved[b])[take]
        for at, off in self.ruled:
            out[np.linalg.norm(p - at, axis=1) <= POINT_MATCH] = off
        return out

    def __call__(self, points, *, rigid: bool = False) -> np.ndarray:
        """``points`` moved; ``rigid``: all by the first one's offset (a notch's two ends)."""
        p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        if not len(p):
            return p
        off = self._offset(p[:1] if rigid else p)
        return p + off

