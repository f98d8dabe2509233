"""Reading multi-size DXF-AAMA files written the way Gerber AccuMark writes them.

Run ``python benchmarks/dxf.py``; prints a table: file size, pieces x sizes, the read time
(``load_dxf``, base size; wall seconds, median of 3 reads after a warm-up that also compiles
the kernels) and the part of it spent fitting curves to the outlines (mean of the 3 reads).

The files: every piece in 14 sizes (one block per piece and size, graded outward from the
base), the cut line a closed POLYLINE in inches with every turn point repeated, as real
AccuMark exports draw them (docs/interchange.md): curves as points 1.5 mm apart ("dense"), or
as points about 25 mm apart on half pieces with a mirror line, as annotation.DXF's back piece
("sparse, halves").
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

import _path  # noqa: F401  (tests/ on sys.path: the tests' AccuMark writer)
from _table import median_time, print_table
from test_dxf_aama import accumark

from patternfit.pattern import dxf_pieces
from patternfit.pattern.dxf import load_dxf

SIZES = [str(s) for s in range(32, 60, 2)]  # 14 sizes
BASE = "44"
REPEAT = 3  # reads timed per file
#: distance between a curve's points in the file [mm] and whether pieces are halves
STYLES = {"dense": (1.5, False), "sparse, halves": (25.0, True)}


def _curve(c, step: float) -> np.ndarray:
    """A cubic Bézier c (4, 2) [mm] as points about ``step`` apart."""
    c = np.asarray(c, dtype=float)
    t = np.linspace(0, 1, 400)[:, None]
    dense = ((1 - t) ** 3 * c[0] + 3 * (1 - t) ** 2 * t * c[1] + 3 * (1 - t) * t * t * c[2]
             + t ** 3 * c[3])
    n = max(4, int(np.sum(np.linalg.norm(np.diff(dense, axis=0), axis=1)) // step) + 1)
    t = np.linspace(0, 1, n)[:, None]
    return ((1 - t) ** 3 * c[0] + 3 * (1 - t) ** 2 * t * c[1] + 3 * (1 - t) * t * t * c[2]
            + t ** 3 * c[3])


def _piece(k: int, grade: float, step: float) -> list[np.ndarray]:
    """Piece ``k``'s cut line [mm] as runs between turn points, graded by ``grade`` [-],
    curves as points ``step`` [mm] apart: a bodice-like outline (centre line on x = 0) whose
    proportions change with ``k``."""
    w, h = (220 + 7 * (k % 9)) * grade, (380 + 11 * (k % 7)) * (1 + 0.5 * (grade - 1))
    a = 0.15 + 0.02 * (k % 5)
    return [np.array([(0, 0), (w, 0)]),                                             # hem
            np.array([(w, 0), (w, 0.7 * h)]),                                       # side
            _curve([(w, 0.7 * h), (w * (1 - a), 0.72 * h), (w * 0.75, 0.85 * h),
                    (w * 0.78, h)], step),                                                # armhole
            np.array([(w * 0.78, h), (w * 0.45, 1.06 * h)]),                        # shoulder
            _curve([(w * 0.45, 1.06 * h), (w * 0.4, 0.95 * h), (w * 0.15, 0.9 * h),
                    (0, 0.9 * h)], step),                                                 # neck
            np.array([(0, 0.9 * h), (0, 0)])]                                       # centre


def write_file(path: Path, pieces: int, style: str) -> Path:
    """An AccuMark-style AAMA file of ``pieces`` pieces in every one of ``SIZES``, drawn in
    ``style`` (one of ``STYLES``)."""
    step, halves = STYLES[style]
    blocks = []
    for k in range(pieces):
        for j, s in enumerate(SIZES):
            runs = _piece(k, 1 + 0.03 * (j - SIZES.index(BASE)), step)
            fold = {"fold": (runs[-1][0], runs[-1][-1])} if halves else {}
            blocks.append({"name": f"P{k:02d}", "size": s, "quantity": 1, "runs": runs,
                           **fold})
    return accumark(path, blocks, sample=BASE)


class _FitClock:
    """Sums the wall time [s] spent in the outline curve fitting while installed."""

    def __init__(self):
        self.total = 0.0
        self._fit = dxf_pieces.loop_from_points

    def __enter__(self):
        def timed(*args, **kwargs):
            t0 = time.perf_counter()
            try:
                return self._fit(*args, **kwargs)
            finally:
                self.total += time.perf_counter() - t0
        dxf_pieces.loop_from_points = timed
        return self

    def __exit__(self, *exc):
        dxf_pieces.loop_from_points = self._fit


def main():
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for style, pieces in (("dense", 4), ("dense", 8), ("sparse, halves", 40)):
            path = write_file(Path(tmp) / f"accumark-{pieces}.dxf", pieces, style)
            pattern = load_dxf(path)  # warm-up: compiles or loads the kernels
            with _FitClock() as clock:
                read = median_time(lambda: load_dxf(path), repeat=REPEAT, warmup=0)
            fit = clock.total / REPEAT
            size = f"{path.stat().st_size / 1e6:.2f} MB"
            rows.append((style, size, f"{pieces} x {len(SIZES)}", len(pattern.panels),
                         f"{read:.2f}", f"{fit:.2f}", f"{fit / len(pattern.panels):.3f}"))
    print_table("Reading AccuMark-style multi-size DXF-AAMA files (base size)", rows,
                ("curves", "file", "pieces x sizes", "panels", "read [s]", "curve fitting [s]",
                 "per piece [s]"))


if __name__ == "__main__":
    main()
