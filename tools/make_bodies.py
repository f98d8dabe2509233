"""Generate the bodies shipped in ``src/patternfit/data/bodies/`` (dev only).

Needs the ``anny`` body model and torch (``pip install torch anny``; a separate venv keeps
the main one small: append its site-packages to ``sys.path`` after patternfit's own)::

    python tools/make_bodies.py                 # the six built-in bodies
    python tools/make_bodies.py male_heavy      # some of them
    python tools/make_bodies.py --population    # the size-chart set (population/)

Each body is an anny (Apache-2.0, NAVER; MakeHuman CC0 assets) mesh without eyes and
tongue, posed in a relaxed A-pose with straight elbows, turned to Y up / facing +Z, feet on
y = 0, and stored with its measurements and landmarks (see ``patternfit.body.builtin``).

The population bodies each aim at one row of :data:`SIZE_CHART`
(:func:`patternfit.body.anny.anny_body_from_girths`: anny's weight searched until bust +
waist + hip equals the row's at its stature, the body widened where anny's range ends
first). Their measured girths (printed, and in docs/bodies.md) differ from the row's by a
few centimetres: the set spans the chart, it does not reproduce it.
"""

from __future__ import annotations

import sys
from pathlib import Path

from patternfit.body.anny import BUILTIN_PHENOTYPES, anny_body, anny_body_from_girths
from patternfit.body.builtin import save_body

OUT = Path(__file__).resolve().parents[1] / "src" / "patternfit" / "data" / "bodies"

#: the population's targets: name -> (anny gender, stature, bust or chest, waist, hip) [m].
#: Women's XS-XXL and men's XS-XXL: targets we picked to span common ready-to-wear charts
#: (steps of 6-10 cm in bust / chest); no standard's and no brand's chart.
SIZE_CHART = {
    "women_xs": (1.0, 1.60, 0.80, 0.62, 0.86),
    "women_s": (1.0, 1.63, 0.86, 0.68, 0.92),
    "women_m": (1.0, 1.66, 0.92, 0.74, 0.98),
    "women_l": (1.0, 1.68, 1.00, 0.82, 1.06),
    "women_xl": (1.0, 1.70, 1.08, 0.90, 1.14),
    "women_xxl": (1.0, 1.70, 1.18, 1.00, 1.24),
    "men_xs": (0.0, 1.70, 0.86, 0.72, 0.86),
    "men_s": (0.0, 1.74, 0.92, 0.78, 0.92),
    "men_m": (0.0, 1.78, 1.00, 0.86, 0.98),
    "men_l": (0.0, 1.80, 1.08, 0.94, 1.04),
    "men_xl": (0.0, 1.82, 1.16, 1.04, 1.10),
    "men_xxl": (0.0, 1.83, 1.26, 1.14, 1.18),
}


def population_body(name: str):
    """The body of :data:`SIZE_CHART` row ``name`` (:func:`anny_body_from_girths`)."""
    gender, stature, bust, waist, hip = SIZE_CHART[name]
    return anny_body_from_girths(name=name, gender=gender, stature=stature, bust=bust,
                                 waist=waist, hip=hip)


def _save(body, path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    save_body(body, path)
    m = body.measurements
    print(f"{body.name:15s} {len(body.vertices):6d} vertices  height {m['height']:.3f}  "
          f"bust {m['bust']:.3f}  waist {m['waist']:.3f}  hip {m['hip']:.3f}  "
          f"arm {m['arm_length']:.3f}  inseam {m['inseam']:.3f}  "
          f"weight {body.meta['phenotype']['weight']:.3f}  -> {path}", flush=True)


def main(args: list[str]) -> None:
    if args[:1] == ["--population"]:
        for name in args[1:] or SIZE_CHART:
            _save(population_body(name), OUT / "population" / f"{name}.npz")
        return
    for name in args or BUILTIN_PHENOTYPES:
        _save(anny_body(name=name, **BUILTIN_PHENOTYPES[name]), OUT / f"{name}.npz")


if __name__ == "__main__":
    main(sys.argv[1:])
