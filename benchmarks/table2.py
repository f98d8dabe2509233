"""The paper's Table 2 on this machine: each garment drafted too small, draped, corrected
automatically (``patternfit.loop.correct``); printed beside the paper's rows.

Run ``python benchmarks/table2.py [--triangles N] [--garments skirt,...]``; same as
``patternfit reproduce table2`` with the colour maps in the repository's
docs/figures/table2_*.png (``--figures DIR`` elsewhere).
"""

from __future__ import annotations

import sys
from pathlib import Path

from patternfit.cli.main import app

FIGURES = Path(__file__).resolve().parents[1] / "docs" / "figures"

if __name__ == "__main__":
    # a --figures given after ours wins
    app(["reproduce", "table2", "--figures", str(FIGURES), *sys.argv[1:]])
