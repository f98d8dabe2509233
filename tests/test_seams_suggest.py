"""Seam suggestion for unsewn patterns (issue 20 item 3): the built-ins with their seams
removed, with and without edge names, a DXF round trip without the side file (written by
the ``convert`` command), left and right legs, notches, sleeve-cap ease, openings."""

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from patternfit.cli.main import app
from patternfit.pattern import Edge, Loop, Panel, Pattern, check_pattern, load_pattern
from patternfit.pattern.library import GARMENTS, build
from patternfit.pattern.seam_suggest import openings, suggest_seams

runner = CliRunner()


def key(seam):
    return frozenset([(seam.a.panel, seam.a.edge), (seam.b.panel, seam.b.edge)])


def generic_names(pattern):
    """The pattern with every outline edge called ``e<k>`` (as a DXF without a side file
    names them), seams renamed alike."""
    rename, panels = {}, []
    for p in pattern.panels:
        edges = tuple(replace(e, name=f"e{k}") for k, e in enumerate(p.outline.edges))
        rename.update({(p.name, e.name): f"e{k}" for k, e in enumerate(p.outline.edges)})
        panels.append(replace(p, outline=replace(p.outline, edges=edges)))
    seams = tuple(replace(s, a=replace(s.a, edge=rename[(s.a.panel, s.a.edge)]),
                          b=replace(s.b, edge=rename[(s.b.panel, s.b.edge)]))
                  for s in pattern.seams)
    return replace(pattern, panels=tuple(panels), seams=seams)


def precision_recall(truth, suggestions):
    real = {key(s): s for s in truth.seams}
    got = {key(s.seam): s.seam for s in suggestions}
    hits = set(real) & set(got)
    reverse_ok = all(real[k].reverse == got[k].reverse for k in hits)
    return len(hits) / max(len(got), 1), len(hits) / len(real), reverse_ok


@pytest.mark.parametrize("garment, names", [
    (g, n) for g in GARMENTS for n in ("named", "generic")])
def test_built_ins_without_seams_get_their_seams_back(garment, names):
    truth = build(garment, "M")
    if names == "generic":
        truth = generic_names(truth)
    found = suggest_seams(replace(truth, seams=()))
    precision, recall, reverse_ok = precision_recall(truth, found)
    print(f"{garment} ({names} edges): precision {precision:.2f}, recall {recall:.2f}")
    assert precision == 1.0 and recall == 1.0
    assert reverse_ok
    for s in found:
        assert 0.0 <= s.score <= 1.0 and s.reasons
    check_pattern(replace(truth, seams=tuple(s.seam for s in found)))


@pytest.mark.parametrize("garment", [g for g in GARMENTS if build(g, "M").anchor == "neck"])
def test_a_bodice_without_its_anchor_keeps_its_armholes_open(garment):
    """A DXF without notches or side file says nothing of where the garment hangs from, and
    unsewn a bodice has no shoulder seams: it read as hung from the waist, needing two
    openings, and each front armhole was sewn to the back one (a tank top and the dress from
    Gerber DXFs drape with 6 edges through the body). The openings are counted on the
    pattern sewn as suggested."""
    truth = generic_names(build(garment, "M"))
    truth = replace(truth, meta={})
    found = suggest_seams(replace(truth, seams=()))
    precision, recall, _ = precision_recall(truth, found)
    assert precision == 1.0 and recall == 1.0, garment


@pytest.mark.parametrize("names", ["named", "generic"])
def test_the_left_leg_is_never_sewn_to_the_right_leg(names):
    trousers = build("trousers", "M")
    if names == "generic":
        trousers = generic_names(trousers)
    # whatever order the pieces come in
    for panels in (trousers.panels, trousers.panels[::-1],
                   trousers.panels[1::2] + trousers.panels[0::2]):
        found = suggest_seams(replace(trousers, panels=panels, seams=()))
        for s in found:
            a, b = s.seam.a, s.seam.b
            if a.panel[-1] != b.panel[-1]:
                # left to right only along the centre front or back (the crotch)
                assert {a.panel, b.panel} in ({"front_r", "front_l"}, {"back_r", "back_l"})
                # the crotch edges (named, or by position when the names are generic)
                assert key(s.seam) in {key(t) for t in trousers.seams}
                if names == "named":
                    assert a.edge == b.edge == "crotch"


def test_suggestions_leave_sewn_edges_alone_and_sew_each_edge_once():
    skirt = build("skirt", "M")
    some = replace(skirt, seams=skirt.seams[:2])
    found = suggest_seams(some)
    assert {key(s.seam) for s in found} == {key(s) for s in skirt.seams[2:]}
    sides = [(x.panel, x.edge) for s in suggest_seams(replace(skirt, seams=()))
             for x in (s.seam.a, s.seam.b)]
    assert len(sides) == len(set(sides))


def test_openings_of_the_built_ins():
    assert {g: openings(build(g, "M")) for g in GARMENTS} == \
        {"coat": 4, "skirt": 2, "trousers": 3, "dress": 4, "shirt": 4, "gathered_skirt": 2}
    skirt = build("skirt", "M")
    assert openings(replace(skirt, seams=())) == 2   # each panel's own outline
    closed = replace(skirt, seams=skirt.seams + (
        replace(skirt.seams[0], name="x", a=replace(skirt.seams[0].a, edge="hem"),
                b=replace(skirt.seams[0].b, edge="hem")),))
    assert openings(closed) == 1


def _notched(pattern, notches):
    """``pattern`` with ``Panel.notches`` {panel: {edge: [t]}} as a reader gives them."""
    from patternfit.pattern.model import Notch

    return replace(pattern, panels=tuple(
        replace(p, notches=tuple(Notch(e, t) for e, ts in notches.get(p.name, {}).items()
                                 for t in ts)) for p in pattern.panels))


def test_notches_decide_between_edges_of_equal_length():
    """Generic names: the skirt's side seams notched at 0.3 on the front and mirrored
    (0.7) on the back are found; notched where they do not match, they are not; corner
    notches (t = 0) say nothing about the match."""
    skirt = generic_names(build("skirt", "M"))
    bare = replace(skirt, seams=())
    truth = {key(s) for s in skirt.seams}
    front = {s.a.edge: [0.3] for s in skirt.seams}
    back = {s.b.edge: [0.7] for s in skirt.seams}
    found = suggest_seams(_notched(bare, {"front": front, "back": back}))
    assert {key(s.seam) for s in found} == truth
    assert all(any("notches match" in r for r in s.reasons) for s in found)
    wrong = {s.b.edge: [0.3] for s in skirt.seams}  # not mirrored: they do not meet
    assert suggest_seams(_notched(bare, {"front": front, "back": wrong})) == []
    corners = {s.b.edge: [0.0, 0.7] for s in skirt.seams}
    assert {key(s.seam) for s in suggest_seams(
        _notched(bare, {"front": front, "back": corners}))} == truth


def _rect(name, w, h, names=("bottom", "right", "top", "left")):
    pts = [(0, 0), (w, 0), (w, h), (0, h)]
    return Panel(name, Loop("outline", tuple(
        Edge.line(n, pts[k], pts[(k + 1) % 4]) for k, n in enumerate(names))))


def test_a_sleeve_cap_eases_into_its_armhole_but_two_bodies_do_not():
    """A sleeve's top edge 3 cm longer than a front's side edge: suggested as cap ease
    with the ease measured; the same lengths between two unnamed pieces: a small ease at
    most, scored lower."""
    from patternfit.pattern import Seam, SeamSide

    front = _rect("FRONT", 0.30, 0.40)
    sleeve = _rect("SLEEVE", 0.43, 0.30, names=("cuff", "under_r", "cap", "under_l"))
    tube = Seam("under", SeamSide("SLEEVE", "under_r"), SeamSide("SLEEVE", "under_l"))
    # one sleeve and a front: no garment with two arm openings, though a sleeve makes
    # Pattern.anchor infer one hung from the neck (which needs four openings)
    found = suggest_seams(Pattern("t", (front, sleeve), (tube,), {"anchor": "waist"}))
    cap = [s for s in found if {s.seam.a.edge, s.seam.b.edge} == {"cap", "left"}
           or {s.seam.a.edge, s.seam.b.edge} == {"cap", "right"}]
    assert cap and any("sleeve cap easing 3.0 cm" in r for r in cap[0].reasons)
    assert cap[0].seam.ease == pytest.approx(0.43 / 0.40 - 1, abs=1e-4)
    tube = replace(tube, a=SeamSide("p2", "right"), b=SeamSide("p2", "left"))
    plain = suggest_seams(Pattern("t", (_rect("p1", 0.30, 0.40), _rect("p2", 0.43, 0.30)),
                                  (tube,)))
    assert all(s.score < cap[0].score for s in plain)


def _midpoints(pattern):
    return {(p.name, e.name): e.point_at(0.5) for p in pattern.panels
            for e in p.outline.edges}


@pytest.mark.parametrize("garment", ["skirt", "trousers", "coat"])
def test_a_dxf_round_trip_without_the_side_file_gets_its_seams_back(garment, tmp_path):
    src, dxf = tmp_path / f"{garment}.json", tmp_path / f"{garment}.dxf"
    truth = build(garment, "M")
    from patternfit.pattern import save_pattern
    save_pattern(truth, src)
    result = runner.invoke(app, ["convert", str(src), str(dxf)])
    assert result.exit_code == 0, result.output
    (tmp_path / f"{garment}.seams.json").unlink()
    from patternfit.api import read_pattern
    read = read_pattern(dxf)
    assert read.seams == ()
    # the DXF names edges e0, e1...: match them to ours by their midpoints
    ours, theirs = _midpoints(load_pattern(src)), _midpoints(read)
    named = {}
    for k, q in theirs.items():
        near = min(ours, key=lambda o: np.linalg.norm(ours[o] - q) if o[0] == k[0] else 1e9)
        assert np.linalg.norm(ours[near] - q) < 1e-3
        named[k] = near
    found = suggest_seams(read)
    got = {frozenset([named[(s.seam.a.panel, s.seam.a.edge)],
                      named[(s.seam.b.panel, s.seam.b.edge)]]) for s in found}
    real = {key(s) for s in truth.seams}
    print(f"{garment} DXF: {len(got & real)} of {len(real)} seams, {len(got)} suggested")
    assert got == real


def _moved_panel(panel, angle, shift, roll, backwards):
    """``panel`` turned by ``angle`` [rad] with its grainline, moved by ``shift`` [m], its
    outline started ``roll`` edges later and, with ``backwards``, traversed the other way
    round: the same piece, as another tool might write it."""
    c, s = np.cos(angle), np.sin(angle)
    m = np.array([[c, -s], [s, c]])
    edges = [e.transformed(m, np.asarray(shift)) for e in panel.outline.edges]
    edges = edges[roll % len(edges):] + edges[:roll % len(edges)]
    if backwards:
        edges = [e.reversed() for e in edges[::-1]]
    g = m @ np.asarray(panel.grainline)
    return replace(panel, outline=replace(panel.outline, edges=tuple(edges)),
                   grainline=(float(g[0]), float(g[1])))


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(garment=st.sampled_from(["skirt", "trousers", "coat"]), data=st.data())
def test_suggestions_do_not_depend_on_how_a_file_lays_out_its_pieces(garment, data):
    """Each piece turned (with its grain), moved, its outline started elsewhere and maybe
    run the other way: the same seams come back, ``reverse`` telling whether the two
    outlines now run the same way round."""
    truth = generic_names(build(garment, "M"))
    flipped = {}
    panels = []
    for p in truth.panels:
        backwards = data.draw(st.booleans())
        flipped[p.name] = backwards
        panels.append(_moved_panel(
            p, data.draw(st.floats(-np.pi, np.pi)),
            (data.draw(st.floats(-2, 2)), data.draw(st.floats(-2, 2))),
            data.draw(st.integers(0, 11)), backwards))
    found = suggest_seams(replace(truth, panels=tuple(panels), seams=()))
    real = {key(s): s for s in truth.seams}
    assert {key(s.seam) for s in found} == set(real)
    for s in found:
        want = real[key(s.seam)].reverse != (flipped[s.seam.a.panel] != flipped[s.seam.b.panel])
        assert s.seam.reverse == want


def _shirt():
    """A set-in-sleeve shirt as a CAD file would give it: front and back bodices, a left and
    a right sleeve whose cap is 3 cm longer than the two armholes together, no seams.
    Returns (pattern, the seams a pattern maker sews, each side with its span)."""
    from patternfit.pattern import Seam, SeamSide

    def piece(name, pts, names):
        pts = np.asarray(pts, dtype=float) / 100
        return Panel(name, Loop("outline", tuple(
            Edge.line(n, pts[k], pts[(k + 1) % len(pts)]) for k, n in enumerate(names))))

    body = [(-20, 0), (20, 0), (20, 40), (14, 55), (6, 58), (-6, 58), (-14, 55), (-20, 40)]
    front = piece("FRONT", body, ["hem", "side_l", "armhole_l", "shoulder_l", "neck",
                                  "shoulder_r", "armhole_r", "side_r"])
    back = piece("BACK", body, ["hem", "side_r", "armhole_r", "shoulder_r", "neck",
                                "shoulder_l", "armhole_l", "side_l"])
    half = (2 * np.hypot(6, 15) + 3) / 2
    sleeve = [(-12, 0), (12, 0), (half, 50), (-half, 50)]
    names = ["cuff", "under_l", "cap", "under_r"]
    pattern = Pattern("shirt", (front, back, piece("SLEEVE_L", sleeve, names),
                                piece("SLEEVE_R", sleeve, names)), meta={"anchor": "neck"})
    sewn = [Seam(n, SeamSide("FRONT", n), SeamSide("BACK", n))
            for n in ("side_l", "side_r", "shoulder_l", "shoulder_r")]
    for s in ("L", "R"):
        sl = f"SLEEVE_{s}"
        first, second = ("BACK", "FRONT") if s == "L" else ("FRONT", "BACK")
        sewn += [Seam("u" + s, SeamSide(sl, "under_l"), SeamSide(sl, "under_r")),
                 Seam("c1" + s, SeamSide(sl, "cap", 0.0, 0.5),
                      SeamSide(first, f"armhole_{s.lower()}")),
                 Seam("c2" + s, SeamSide(sl, "cap", 0.5, 1.0),
                      SeamSide(second, f"armhole_{s.lower()}"))]
    return pattern, replace(pattern, seams=tuple(sewn))


def span_key(seam):
    return frozenset([(x.panel, x.edge, x.start, x.end) for x in (seam.a, seam.b)])


@pytest.mark.parametrize("names", ["named", "generic"])
def test_a_set_in_sleeve_cap_is_sewn_to_both_armholes_with_its_ease(names):
    """Each sleeve's cap is split between the front and the back armhole of its own side,
    meeting at the shoulder seam, its 3 cm of ease spread over both halves; the sleeve is
    sewn into a tube; the cuffs, neck and hem stay open."""
    from patternfit.mesh.triangulate import mesh_pattern

    bare, truth = _shirt()
    if names == "generic":
        truth = generic_names(truth)
        bare = replace(truth, seams=())
    found = suggest_seams(bare)
    assert {span_key(s.seam) for s in found} == {span_key(s) for s in truth.seams}
    caps = [s for s in found if (s.seam.a.start, s.seam.a.end) != (0.0, 1.0)]
    assert len(caps) == 4
    for s in caps:
        assert s.seam.ease == pytest.approx((np.hypot(6, 15) + 1.5) / np.hypot(6, 15) - 1,
                                            abs=1e-4)
        assert any("meet at a corner" in r for r in s.reasons)
    sewn = replace(bare, seams=tuple(s.seam for s in found))
    check_pattern(sewn)
    assert openings(sewn) == 4
    mesh = mesh_pattern(sewn, triangles=800)
    assert len(mesh.seam_names) == 10 and len(mesh.seam_pairs) > 0


def test_the_api_suggests_seams_for_a_file_in_its_own_size(tmp_path):
    # api.suggest_seams read every file in size M: "no size 'M' in the file (sizes: L)"
    from patternfit import api
    from patternfit.pattern import save_pattern
    truth = build("skirt", "L")
    save_pattern(replace(truth, seams=()), tmp_path / "skirt.json")
    found = api.suggest_seams(tmp_path / "skirt.json")
    assert {key(s.seam) for s in found} == {key(s) for s in truth.seams}
