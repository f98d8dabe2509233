"""Generate the built-in bodies shipped in ``src/patternfit/data/bodies/`` (dev only).

Needs the ``anny`` body model and the CPU build of torch::

    pip install torch==2.13.0 && pip install anny
    python tools/make_bodies.py            # all bodies
    python tools/make_bodies.py male_heavy # some

Each body is an anny (Apache-2.0, NAVER; MakeHuman CC0 assets) mesh without eyes and
tongue, posed in a relaxed A-pose with straight elbows, turned to Y up / facing +Z, feet on
y = 0, and stored with its measurements and landmarks (see ``patternfit.body.builtin``).
"""

from __future__ import annotations

import sys
from pathlib import Path

from patternfit.body.anny import BUILTIN_PHENOTYPES, anny_body
from patternfit.body.builtin import save_body

OUT = Path(__file__).resolve().parents[1] / "src" / "patternfit" / "data" / "bodies"


def main(names: list[str]) -> None:
    for name in names or BUILTIN_PHENOTYPES:
        body = anny_body(name=name, **BUILTIN_PHENOTYPES[name])
        path = save_body(body, OUT / f"{name}.npz")
        m = body.measurements
        print(f"{name:15s} {len(body.vertices):6d} vertices  height {m['height']:.3f}  "
              f"bust {m['bust']:.3f}  waist {m['waist']:.3f}  hip {m['hip']:.3f}  "
              f"arm {m['arm_length']:.3f}  inseam {m['inseam']:.3f}  -> {path}")


if __name__ == "__main__":
    main(sys.argv[1:])
