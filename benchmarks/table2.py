"""The paper's Table 2 on this machine: each garment drafted too small, draped, corrected
automatically (``patternfit.loop.correct``); printed beside the paper's rows.

Run ``python benchmarks/table2.py [--triangles N] [--garments skirt,...]``; same as
``patternfit reproduce table2``. Colour maps go to docs/figures/table2_*.png.
"""

from __future__ import annotations

import sys

from patternfit.cli.main import app

if __name__ == "__main__":
    app(["reproduce", "table2", *sys.argv[1:]])
