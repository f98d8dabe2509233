"""True-scale SVG and tiled PDF plots of a pattern."""

import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from patternfit.pattern import Edge, Loop, Panel, Pattern, Seam, SeamSide
from patternfit.pattern.plot import PAPERS, layout, svg_text, write_pdf, write_svg

SVG = "{http://www.w3.org/2000/svg}"


def _pattern():
    a = Panel("front", Loop("outline", (
        Edge.line("hem", (0, 0), (0.3, 0)), Edge.line("side", (0.3, 0), (0.3, 0.2)),
        Edge.arc("top", (0.3, 0.2), (0, 0.2), 0.2, large_arc=False, sweep=True),
        Edge.line("centre", (0, 0.2), (0, 0)))))
    b = Panel("back", Loop("outline", (
        Edge.line("hem", (0, 0), (0.3, 0)), Edge.line("side", (0.3, 0), (0.3, 0.2)),
        Edge.cubic("top", (0.3, 0.2), (0.2, 0.25), (0.1, 0.15), (0, 0.2)),
        Edge.line("centre", (0, 0.2), (0, 0)))), grainline=(1.0, 0.0))
    return Pattern("demo", (a, b), (Seam("side_seam", SeamSide("front", "side"),
                                         SeamSide("back", "centre")),), {"size": "S"})


def _fit(pattern):
    v = np.array([[0.0, 0.0], [0.3, 0.0], [0.3, 0.2], [0.0, 0.2]])
    verts = np.vstack([v, v])
    tris = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    rgb = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0]], dtype=float)
    return verts, tris, rgb, np.array([0, 0, 1, 1])


def test_svg_is_true_scale_with_names_grain_notches_and_seam_labels(tmp_path):
    p = _pattern()
    root = ET.parse(write_svg(p, tmp_path / "p.svg")).getroot()
    sheet = layout(p)
    w, h = (float(x[:-2]) for x in (root.get("width"), root.get("height")))
    assert (w, h) == pytest.approx((sheet.size[0] * 1000, sheet.size[1] * 1000), abs=1e-3)
    assert root.get("viewBox") == f"0 0 {w:.3f} {h:.3f}"
    pieces = root.findall(f".//{SVG}path[@class='piece']")
    assert len(pieces) == 2
    d = pieces[0].get("d")
    assert " A 200.0000 200.0000 0 0 1 " in d  # the arc, its flags unchanged in the y-up group
    xs = [float(x) for x in re.findall(r"-?\d+\.\d+", d.split(" A ")[0])][0::2]
    assert max(xs) - min(xs) == pytest.approx(300.0)  # 0.3 m is 300 mm
    texts = [t.text for t in root.iter(f"{SVG}text")]
    assert "front (S)" in texts and "back (S)" in texts and "side_seam" in texts
    assert len(root.findall(f".//{SVG}line[@class='grain']")) == 2
    assert len(root.findall(f".//{SVG}line[@class='notch']")) == 2


def test_svg_fit_colours_under_outline():
    p = _pattern()
    text = svg_text(layout(p, fit=_fit(p)))
    root = ET.fromstring(text)
    polys = [e for e in root.iter(f"{SVG}polygon") if e.get("stroke") not in (None,)]
    fills = {e.get("fill") for e in polys}
    assert {"#ff0000", "#00ff00", "#0000ff", "#ffff00"} <= fills
    assert text.index("#ff0000") < text.index('class="piece"')  # drawn first: underneath
    # without the panel index the triangles are found by their centroids
    v, t, rgb, _ = _fit(p)
    sheet = layout(p, fit=(v[:4], t[:2], rgb[:2]))
    assert sheet.fit[3].tolist() == [0, 0]


@pytest.mark.parametrize("bad", [
    (np.zeros((3, 3)), np.array([[0, 1, 2]]), np.zeros((1, 3))),
    (np.zeros((3, 2)), np.array([[0, 1, 5]]), np.zeros((1, 3))),
    (np.zeros((3, 2)), np.array([[0, 1, 2]]), np.zeros((2, 3))),
])
def test_bad_fit_arrays_are_refused(bad):
    with pytest.raises(ValueError, match="fit"):
        layout(_pattern(), fit=bad)


@pytest.mark.parametrize("paper", ["a4", "letter"])
def test_pdf_pages_are_paper_sized_tiles(tmp_path, paper):
    p = _pattern()
    pages = write_pdf(p, tmp_path / "p.pdf", paper=paper, fit=_fit(p))
    data = (tmp_path / "p.pdf").read_bytes()
    assert data.startswith(b"%PDF")
    assert len(re.findall(rb"/Type /Page\b(?!s)", data)) == pages
    w, h = (x * 72 / 0.0254 for x in PAPERS[paper])
    boxes = re.findall(rb"/MediaBox \[\s*0 0 ([\d.]+) ([\d.]+)\s*\]", data)
    assert boxes and all(float(a) == pytest.approx(w, abs=0.1) and
                         float(b) == pytest.approx(h, abs=0.1) for a, b in boxes)
    sheet = layout(p)
    tw, th = (s - 0.02 for s in PAPERS[paper])
    grid = int(np.ceil(sheet.size[0] / tw)) * int(np.ceil(sheet.size[1] / th))
    assert 2 <= pages <= 1 + grid


def test_pdf_arguments_checked(tmp_path):
    with pytest.raises(ValueError, match="paper"):
        write_pdf(_pattern(), tmp_path / "x.pdf", paper="a3")
    with pytest.raises(ValueError, match="margin"):
        write_pdf(_pattern(), tmp_path / "x.pdf", margin=0.2)


def test_svg_draws_what_an_accumark_file_draws_on_a_piece(tmp_path):
    """A piece written the way AccuMark writes DXF-AAMA (``test_dxf_aama``: cut line 10 mm
    outside the sew line at the sides and top, 30 mm at the hem; notches at mid side, mid
    hem and a corner; a dart's legs and its drill hole at the tip): the plot draws the cut
    line, the three notches into the fabric, the dashed dart legs and the drill hole where
    they are, in millimetres on the sheet."""
    from test_dxf_aama import accumark, skirt_piece

    from patternfit.pattern.dxf import load_dxf

    p = load_dxf(accumark(tmp_path / "s.dxf", [skirt_piece()], scale=1.0))
    (panel,) = p.panels
    sheet = layout(p)
    off = sheet.offsets[panel.name]
    root = ET.fromstring(svg_text(sheet))

    def pts(e):
        return np.array([[float(c) for c in xy.split(",")] for xy in e.get("points").split()])

    (cut,) = root.findall(f".//{SVG}polygon[@class='cut']")
    np.testing.assert_allclose(pts(cut), (np.array(panel.cut_line) + off) * 1000, atol=2e-3)
    (line,) = root.findall(f".//{SVG}polyline[@class='line']")
    np.testing.assert_allclose(pts(line), (np.array(panel.lines[0].points) + off) * 1000,
                               atol=2e-3)
    (hole,) = root.findall(f".//{SVG}g[@class='drill']/{SVG}circle")
    np.testing.assert_allclose([float(hole.get("cx")), float(hole.get("cy"))],
                               (np.array([0.15, 0.39]) + off) * 1000, atol=2e-3)
    notches = [np.array([[float(e.get(k)) for k in ("x1", "y1")],
                         [float(e.get(k)) for k in ("x2", "y2")]]) / 1000 - off
               for e in root.findall(f".//{SVG}line[@class='notch']")]
    assert len(notches) == 3  # no seams: the piece's own notches only
    starts = sorted(tuple(np.round(n[0], 6)) for n in notches)
    assert starts == [(0.15, 0.0), (0.3, 0.25), (0.3, 0.5)]
    # each slit points into the fabric (the sew line is the rectangle 0.3 x 0.5 m)
    ends = np.array([n[1] for n in notches])
    assert (ends > -1e-9).all() and (ends < np.array([0.3, 0.5]) + 1e-9).all()
    assert np.linalg.norm(ends - [n[0] for n in notches], axis=1) == pytest.approx(0.008)
    # the cut line lies within the sheet (the layout makes room for the allowance)
    assert pts(cut).min() > 0 and (pts(cut) < np.array(sheet.size) * 1000).all()
