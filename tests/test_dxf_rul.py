"""Grade rule tables (``.rul``, ASTM D6673 / ANSI-AAMA) beside a DXF drawn in its sample size
only, written here the way Gerber AccuMark, Lectra and Optitex export them: the DXF's cut
line a closed POLYLINE on layer 1 with every turn point repeated, each grade point a POINT on
layer 2 followed by a TEXT ``# N`` (its rule), notches on layer 4 with their own ``# N``,
``Grade Rule Table:`` and ``Sample Size:`` in the style text; the ``.rul`` in CRLF lines, a
header (``ANSI/AAMA VERSION``, ``UNITS``, ``GRADE RULE TABLE``, ``NUMBER OF SIZES``, ``SIZE
LIST``, ``SAMPLE SIZE``), then ``RULE: DELTA n`` and its (dx, dy) pairs, four to a line, each
``%10.2f,%9.2f`` (Optitex packs several pairs on a line, others one)."""

from __future__ import annotations

import ezdxf
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from patternfit import api
from patternfit.pattern import PatternError
from patternfit.pattern.dxf import load_dxf
from patternfit.pattern.dxf_rules import parse_rules

MM = 0.001
#: a skirt panel [mm]: hem corners, side (with a point half-way up), waist corners
CORNERS = np.array([(0.0, 0.0), (300.0, 0.0), (290.0, 300.0), (280.0, 600.0), (20.0, 600.0)])
#: the rule of each point; rule 1 holds still (the centre front hem)
RULES = [1, 2, 3, 4, 5]
SIZES = ["S", "M", "L", "XL"]
#: per rule, the offsets (dx, dy) [mm] of each size from the sample M
DELTAS = {1: [(0, 0)] * 4,
          2: [(-10, 0), (0, 0), (10, 0), (20, 0)],
          3: [(-8, -5), (0, 0), (8, 5), (16, 10)],
          4: [(-6, -10), (0, 0), (6, 10), (12, 20)],
          5: [(0, -10), (0, 0), (0, 10), (0, 20)],
          # the notch half-way up the side: half of the side's two ends' moves
          6: [(-9, -2.5), (0, 0), (9, 2.5), (18, 5)]}


def rul_text(deltas=DELTAS, sizes=SIZES, sample="M", per_line=4, units="METRIC",
             count=None) -> str:
    lines = ["ANSI/AAMA VERSION: 1.0.0", "AUTHOR: ACCUMARK", "CREATION DATE: 2-12-2026",
             "CREATION TIME: 3:10", f"UNITS: {units}", "GRADE RULE TABLE: SKIRTS",
             f"NUMBER OF SIZES: {count if count is not None else len(sizes):>2d}",
             "SIZE LIST: " + " ".join(sizes) + " ", f"SAMPLE SIZE: {sample}"]
    for rid in sorted(deltas):
        lines.append(f"RULE: DELTA {rid:>2d}")
        pairs = [f"{dx:>10.2f},{dy:>9.2f}" for dx, dy in deltas[rid]]
        lines += ["".join(pairs[i:i + per_line]) for i in range(0, len(pairs), per_line)]
    return "\r\n".join(lines + ["END"]) + "\r\n"


def sample_dxf(path, *, notch=True):
    """The skirt panel in size M alone, its grade points numbered."""
    doc = ezdxf.new("R12")
    blk = doc.blocks.new("SKIRT-M")
    pts = []
    for p in CORNERS:  # every turn point twice, as AccuMark writes them
        pts += [p, p]
    blk.add_polyline2d([tuple(p) for p in pts] + [tuple(CORNERS[0])],
                       dxfattribs={"layer": "1"})
    for p, rule in zip(CORNERS, RULES):
        blk.add_point(tuple(p), dxfattribs={"layer": "2"})
        blk.add_text(f"# {rule}", dxfattribs={"layer": "2", "insert": tuple(p + 3)})
    if notch:  # a notch on the side seam, graded by its own rule
        at = (295.0, 150.0)
        blk.add_line(at, (285.0, 150.0), dxfattribs={"layer": "4"})
        blk.add_text("# 6", dxfattribs={"layer": "4", "insert": (298.0, 153.0)})
    blk.add_line((150, 100), (150, 500), dxfattribs={"layer": "7"})
    for j, t in enumerate(["Piece Name: SKIRT", "Size: M", "Quantity: 1"]):
        blk.add_text(t, dxfattribs={"layer": "1", "insert": (5, 5 + 5 * j)})
    msp = doc.modelspace()
    msp.add_blockref("SKIRT-M", (0, 0))
    for j, t in enumerate(["Style Name: SKIRT1", "Units: METRIC", "Sample Size: M",
                           "Grade Rule Table: SKIRTS"]):
        msp.add_text(t, dxfattribs={"layer": "1", "insert": (0, -10 - 5 * j)})
    doc.saveas(path)
    return path


@pytest.fixture
def graded(tmp_path):
    dxf = sample_dxf(tmp_path / "skirt.dxf")
    (tmp_path / "skirt.rul").write_bytes(rul_text().encode("latin-1"))
    return dxf


def off_outline(pattern, point) -> float:
    """How far [mm] ``point`` [mm] lies from the panel's outline (its sampled segments)."""
    poly = pattern.panels[0].outline.polygon(64) / MM
    a, b = poly, np.roll(poly, -1, axis=0)
    d = b - a
    t = np.clip(np.einsum("ij,ij->i", point - a, d) / np.einsum("ij,ij->i", d, d), 0, 1)
    return float(np.min(np.linalg.norm(a + t[:, None] * d - point, axis=1)))


def test_the_table_is_read_as_written():
    table = parse_rules(rul_text(per_line=1))
    assert table.sizes == tuple(SIZES) and table.sample == "M" and table.name == "SKIRTS"
    assert sorted(table.rules) == sorted(DELTAS)
    assert table.rules[3][3] == pytest.approx(np.array([16, 10]) * MM)
    # pairs packed four to a line or one to a line read alike
    packed = parse_rules(rul_text(per_line=4))
    assert all(np.array_equal(packed.rules[k], table.rules[k]) for k in table.rules)


def test_inches_in_an_english_table():
    table = parse_rules(rul_text(units="ENGLISH"))
    assert table.rules[2][3] == pytest.approx([20 * 0.0254, 0.0])


def test_the_sample_size_is_the_dxf_as_drawn(graded):
    p = load_dxf(graded)
    assert p.meta["size"] == "M" and p.meta["sizes"] == SIZES
    assert p.meta["grade_rule_table"] == "SKIRTS"
    for c in CORNERS:
        assert off_outline(p, c) < 0.05


@pytest.mark.parametrize("size", ["S", "L", "XL"])
def test_each_grade_point_moves_by_its_rule(graded, size):
    k = SIZES.index(size)
    p = load_dxf(graded, size=size)
    for c, rule in zip(CORNERS, RULES):
        assert off_outline(p, c + np.array(DELTAS[rule][k])) < 0.05, (size, rule)
    # the hem's corners are turn points: edges start there
    starts = np.array([e.start for e in p.panels[0].outline.edges]) / MM
    for c, rule in list(zip(CORNERS, RULES))[:2]:
        want = c + np.array(DELTAS[rule][k])
        assert np.min(np.linalg.norm(starts - want, axis=1)) < 0.01


def test_points_between_grade_points_and_marks_follow(graded):
    # the notch on the side seam moves by its own rule; the grain line keeps its direction
    m, xl = load_dxf(graded, size="M"), load_dxf(graded, size="XL")
    (n_m,), (n_xl,) = m.panels[0].notches, xl.panels[0].notches
    assert n_m.edge == n_xl.edge
    at = xl.panels[0].edge(n_xl.edge).point_at([n_xl.t])[0] / MM
    assert at == pytest.approx(np.array([295.0, 150.0]) + DELTAS[6][3], abs=0.5)
    # the area grows size by size
    areas = [load_dxf(graded, size=s).panels[0].area() for s in SIZES]
    assert all(a < b for a, b in zip(areas, areas[1:]))
    assert xl.panels[0].grainline == pytest.approx(m.panels[0].grainline)


def test_a_size_the_table_lacks_is_refused_naming_its_sizes(graded):
    with pytest.raises(PatternError, match="S, M, L, XL"):
        load_dxf(graded, size="XXL")


def test_the_api_reads_the_table_beside_the_dxf(graded):
    p = api.read_pattern(graded, size="L")
    assert p.meta["size"] == "L" and p.meta["sizes"] == SIZES


@pytest.mark.parametrize("text, message", [
    (rul_text(count=5), "NUMBER OF SIZES"),
    (rul_text(sample="XXL"), "SAMPLE SIZE"),
    (rul_text().replace("      0.00,     0.00\r\n", "\r\n", 1), "pairs"),
    (rul_text().replace("SIZE LIST", "SIZES"), "SIZE LIST"),
    (rul_text(units="FURLONGS"), "UNITS"),
    (rul_text().replace("RULE: DELTA  2", "RULE: DELTA  1"), "twice"),
    (rul_text().replace("RULE: DELTA  3", "RULES 3"), "RULE: DELTA"),
])
def test_malformed_tables_are_refused_saying_where(tmp_path, text, message):
    dxf = sample_dxf(tmp_path / "skirt.dxf")
    (tmp_path / "skirt.rul").write_bytes(text.encode("latin-1"))
    with pytest.raises(PatternError, match=message) as err:
        load_dxf(dxf, size="L")
    assert "skirt.rul" in str(err.value)


def test_a_grade_point_whose_rule_is_missing_is_refused(tmp_path):
    dxf = sample_dxf(tmp_path / "skirt.dxf")
    (tmp_path / "skirt.rul").write_bytes(
        rul_text({k: v for k, v in DELTAS.items() if k != 4}).encode("latin-1"))
    with pytest.raises(PatternError, match="rule 4"):
        load_dxf(dxf)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.integers(-15, 15), st.integers(-15, 15)), min_size=5,
                max_size=5))
def test_any_rule_offsets_move_the_grade_points_exactly(tmp_path_factory, offsets):
    # each corner's rule moves it to size L by an arbitrary offset: the corners land there
    tmp = tmp_path_factory.mktemp("rul")
    deltas = {r: [(0, 0), (0, 0), off, off] for r, off in zip(RULES, offsets)}
    deltas[6] = [(0, 0)] * 4
    dxf = sample_dxf(tmp / "skirt.dxf")
    (tmp / "skirt.rul").write_bytes(rul_text(deltas).encode("latin-1"))
    try:
        p = load_dxf(dxf, size="L")
    except PatternError:
        return  # an offset that folds the outline over itself is refused, not read wrong
    for c, off in zip(CORNERS, offsets):
        assert off_outline(p, c + off) < 0.05


def test_a_rule_that_moves_the_sample_size_is_refused(tmp_path):
    """A table of size-to-size steps (or misaligned columns) moves the sample: refused."""
    steps = dict(DELTAS)
    steps[2] = [(-10, 0), (10, 0), (10, 0), (10, 0)]
    dxf = sample_dxf(tmp_path / "skirt.dxf")
    (tmp_path / "skirt.rul").write_bytes(rul_text(steps).encode("latin-1"))
    with pytest.raises(PatternError, match="rule 2 moves the sample size M") as err:
        load_dxf(dxf)
    assert "skirt.rul" in str(err.value)


#: one rule over six sizes, the sample third, in inches, as an Optitex table lays it out:
#: a blank first line, two pairs to a line, six decimals (offsets from the sample, growing
#: away from it: the shape of the real tables quoted in docs/interchange.md)
OPTITEX = """
ANSI/AAMA VERSION: 1.0.0
AUTHOR: Optitex
UNITS: ENGLISH
GRADE RULE TABLE: TOPS
NUMBER OF SIZES: 6
SIZE LIST: XXS XS S M L XL
SAMPLE SIZE: S
RULE: DELTA 1
       0.000000,      0.000000       0.000000,      0.000000
       0.000000,      0.000000       0.000000,      0.000000
       0.000000,      0.000000       0.000000,      0.000000
RULE: DELTA 2
       0.500006,      0.000404       0.250003,      0.000193
       0.000000,      0.000000      -0.250010,     -0.000560
      -0.625012,     -0.001611      -1.000014,     -0.000776
END
"""

#: the same shape as AccuMark writes an ASTM table: one pair to a line
ACCUMARK = """ASTM/D13Proposal 1 Version: D 6673-04
UNITS: ENGLISH
NUMBER OF SIZES: 4
SIZE LIST:  XS S M L
SAMPLE SIZE: M
RULE: DELTA 1
      0.1800,   0.0120
      0.0900,   0.0030
      0.0000,   0.0000
     -0.1800,  -0.0070
END
"""


def test_real_table_layouts_are_offsets_from_the_sample():
    t = parse_rules(OPTITEX)
    assert t.sizes == ("XXS", "XS", "S", "M", "L", "XL") and t.sample == "S"
    inch = 0.0254
    # XL is one inch in from the sample, not the sum of the steps (1.875 inches)
    assert t.rules[2][5] == pytest.approx([-1.000014 * inch, -0.000776 * inch])
    assert t.rules[2][0] == pytest.approx([0.500006 * inch, 0.000404 * inch])
    a = parse_rules(ACCUMARK.replace("\n", "\r\n"))
    assert a.sample == "M" and a.rules[1][0] == pytest.approx([0.18 * inch, 0.012 * inch])
    assert not a.rules[1][2].any()


def test_the_optitex_layout_grades_a_point_by_its_offset(tmp_path):
    dxf = sample_dxf(tmp_path / "skirt.dxf", notch=False)
    inch = 25.4
    table = OPTITEX.replace("SIZE LIST: XXS XS S M L XL", "SIZE LIST: XXS XS M L XL XXL") \
        .replace("SAMPLE SIZE: S", "SAMPLE SIZE: M")
    rules = table.split("RULE: DELTA 1")[0]
    zero = "RULE: DELTA {}\n" + ("       0.000000,      0.000000       0.000000,      0.000000\n"
                                 * 3)
    body = "".join(zero.format(r) for r in (1, 3, 4, 5))
    body += table[table.index("RULE: DELTA 2"):table.index("END")]
    (tmp_path / "skirt.rul").write_text(rules + body + "END\n")
    p = load_dxf(dxf, size="XXL")
    # rule 2 (the side's hem corner) in the sixth size: 1.000014 inches in, not 1.875
    starts = np.array([e.start for e in p.panels[0].outline.edges]) / MM
    near = np.min(np.linalg.norm(starts - (CORNERS[1] + np.array([-1.000014, -0.000776]) * inch),
                                 axis=1))
    as_steps = np.min(np.linalg.norm(starts - (CORNERS[1] + np.array([-1.875, -0.003]) * inch),
                                     axis=1))
    assert near < 0.01 and as_steps > 20
