"""The correction keeps a sleeve's length: the Table 2 coat (1.5K triangles), let out
until every region fits, ends with each sleeve's end within the length tolerance of where
its first drape had it (a let-out that turned a sleeve up is answered by lengthening it at
the cuff), and reports every drape's sleeve ends. (Without the lengthening, the same run
ends with both sleeves 6 cm higher up the arm than its first drape had them.) It takes
seven drapes since the body is kept out between the cloth's vertices too: five reached only
"tight" (98.1 %), where the sleeves had cut into the arms before."""

from patternfit.fit.verdict_rules import VerdictRules
from patternfit.loop.correct import CorrectionSettings
from patternfit.loop.table2 import ROWS, run_row


def test_the_let_out_coat_keeps_its_sleeves_length():
    rules = VerdictRules()
    row = {r.garment: r for r in ROWS}["coat"]
    out = run_row(row, triangles=1500, settings=CorrectionSettings(
        goal="fits", max_iterations=8, rules=rules))
    first, last = out["lengths_cm"][0], out["lengths_cm"][-1]
    assert {"sleeve_left", "sleeve_right"} <= set(first)
    assert len(out["lengths_cm"]) == len(out["ratios"])
    assert out["reached"]
    for limb in ("sleeve_left", "sleeve_right"):
        assert last[limb] - first[limb] <= rules.length_tolerance_cm
