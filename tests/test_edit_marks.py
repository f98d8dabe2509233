"""Edits carry what a CAD file draws on a piece (cut line, internal lines, drill holes):
a grade maps them with the outline, a lengthening moves those beyond its cut line, a local
edit of the outline drops the cut line (the seam allowance would be wrong) with a warning.
The piece is written the way Gerber AccuMark writes DXF-AAMA (``test_dxf_aama.accumark``)."""

import numpy as np
import pytest
from test_dxf_aama import accumark, skirt_piece

from patternfit.edit import grade, lengthen, move_edge, move_point
from patternfit.pattern import Pattern
from patternfit.pattern.dxf import load_dxf


@pytest.fixture(scope="module")
def skirt(tmp_path_factory):
    path = accumark(tmp_path_factory.mktemp("marks") / "s.dxf", [skirt_piece()], scale=1.0)
    p = load_dxf(path)
    (panel,) = p.panels
    assert panel.cut_line and panel.lines and panel.drill_holes  # what the file draws
    return Pattern(p.name, p.panels, (), {})


def marks(panel):
    return (np.array(panel.cut_line), [np.array(ln.points) for ln in panel.lines],
            np.array(panel.drill_holes))


@pytest.mark.parametrize("sx, sy", [(1.1, 1.05), (0.9, 1.0)])
def test_a_grade_maps_the_marks_with_the_outline(skirt, sx, sy):
    panel = skirt.panels[0]
    c = panel.outline.polygon().mean(axis=0)
    new = grade(skirt, panel.name, sx, sy).panels[0]
    cut, lines, holes = marks(panel)
    cut2, lines2, holes2 = marks(new)
    scale = np.array([sx, sy])
    np.testing.assert_allclose(cut2, c + (cut - c) * scale, atol=1e-12)
    np.testing.assert_allclose(holes2, c + (holes - c) * scale, atol=1e-12)
    for a, b in zip(lines, lines2):
        np.testing.assert_allclose(b, c + (a - c) * scale, atol=1e-12)
    # the allowance scaled alike: the cut line still lies around the sew line
    assert new.outline.polygon().min(axis=0) == pytest.approx(cut2.min(axis=0) + scale * [0.01, 0.03])


def test_a_lengthening_moves_the_marks_beyond_its_cut(skirt):
    panel = skirt.panels[0]
    new = lengthen(skirt, panel.name, (0.15, 0.1), (0.15, 0.4), 0.02).panels[0]
    cut, lines, holes = marks(panel)
    cut2, lines2, holes2 = marks(new)
    up = np.array([0.0, 0.02])
    np.testing.assert_allclose(cut2, cut + np.where(cut[:, 1:] > 0.25, up, 0.0), atol=1e-12)
    np.testing.assert_allclose(holes2, holes + up, atol=1e-12)   # the dart tip at 0.39 m
    np.testing.assert_allclose(lines2[0], lines[0] + up, atol=1e-12)
    assert new.area() == pytest.approx(panel.area() + 0.3 * 0.02, rel=1e-9)


@pytest.mark.parametrize("edit", [
    lambda p, n: move_point(p, n, p.panels[0].outline.edges[1].name, (0.01, 0.0)),
    lambda p, n: move_edge(p, n, p.panels[0].outline.edges[0].name, (0.0, -0.02))])
def test_a_local_edit_drops_the_cut_line_with_a_warning(skirt, edit):
    panel = skirt.panels[0]
    out = edit(skirt, panel.name)
    new = out.panels[0]
    assert new.outline is not panel.outline and new.cut_line == ()
    assert any(panel.name in w and "cut line" in w for w in out.meta["warnings"])
    assert "warnings" not in skirt.meta   # the pattern edited is left alone
    assert new.lines == panel.lines and new.drill_holes == panel.drill_holes
