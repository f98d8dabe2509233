"""Run every benchmark in this folder, one after another; each prints its table.

Run: python benchmarks/run.py [name ...]   (names without .py; default: all)
"""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

here = Path(__file__).parent
names = sys.argv[1:] or sorted(p.stem for p in here.glob("*.py")
                               if p.stem not in ("run",) and not p.stem.startswith("_"))
sys.path.insert(0, str(here))
for name in names:
    runpy.run_path(str(here / f"{name}.py"), run_name="__main__")
