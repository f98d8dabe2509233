"""``patternfit seams`` and the drape-time refusal of unsewn patterns (issue 20 item 3)."""

import json
from dataclasses import replace

import pytest
from typer.testing import CliRunner

import patternfit.api as api
from patternfit.cli.main import app
from patternfit.pattern import PatternError, load_pattern, save_pattern
from patternfit.pattern.library import build

runner = CliRunner()


@pytest.fixture
def bare_skirt(tmp_path):
    path = tmp_path / "skirt.json"
    save_pattern(replace(build("skirt", "M"), seams=()), path, units="cm")
    return path


def run(*args):
    return runner.invoke(app, [str(a) for a in args])


def test_lists_seams_with_lengths_and_ease(tmp_path):
    path = tmp_path / "skirt.json"
    save_pattern(build("skirt", "M"), path)
    r = run("seams", path, "--json")
    assert r.exit_code == 0, r.output
    doc = json.loads(r.output)
    assert [s["name"] for s in doc["seams"]] == ["side_r", "hip_r", "side_l", "hip_l"]
    row = doc["seams"][0]
    assert row["a"]["length_cm"] == pytest.approx(40.45, abs=0.01)
    assert abs(row["difference_mm"]) < 0.1 and row["ease"] == 0.0
    assert doc["written"] == []                      # nothing changed, nothing written
    r = run("seams", path)
    assert r.exit_code == 0 and "front.side_r" in r.output and "40.45" in r.output


def test_suggest_accept_writes_a_new_file_never_the_input(bare_skirt, tmp_path):
    before = bare_skirt.read_bytes()
    r = run("seams", bare_skirt, "--suggest", "--json")
    doc = json.loads(r.output)
    assert r.exit_code == 0 and len(doc["suggestions"]) == 4 and doc["written"] == []
    assert all(0 < s["score"] <= 1 and s["reasons"] for s in doc["suggestions"])
    r = run("seams", bare_skirt, "--accept")
    assert r.exit_code == 0, r.output
    out = tmp_path / "skirt-sewn.json"
    assert out.exists() and bare_skirt.read_bytes() == before
    sewn = load_pattern(out)
    assert {frozenset([(s.a.panel, s.a.edge), (s.b.panel, s.b.edge)]) for s in sewn.seams} \
        == {frozenset([(s.a.panel, s.a.edge), (s.b.panel, s.b.edge)])
            for s in build("skirt", "M").seams}
    r = run("seams", bare_skirt, "--accept", "--out", bare_skirt)
    assert r.exit_code == 2 and "input pattern" in r.output
    assert bare_skirt.read_bytes() == before
    # run again, the default file is not replaced; named, it is
    out.write_text("the user's own notes")
    r = run("seams", bare_skirt, "--accept")
    assert r.exit_code == 2 and "already exists" in r.output and "--out" in r.output
    assert out.read_text() == "the user's own notes"
    r = run("seams", bare_skirt, "--accept", "--out", out)
    assert r.exit_code == 0 and load_pattern(out).seams


def test_set_and_remove_seams(bare_skirt, tmp_path):
    out = tmp_path / "one.json"
    r = run("seams", bare_skirt, "--set", "s1=front.side_r:back.side_r", "--set",
            "s2=front.hip_r:back.hip_r:0.05", "--out", out, "--json")
    assert r.exit_code == 0, r.output
    doc = json.loads(r.output)
    assert [(s["name"], s["ease"]) for s in doc["seams"]] == [("s1", 0.0), ("s2", 0.05)]
    r = run("seams", out, "--remove", "s1", "--out", tmp_path / "two.json", "--json")
    assert [s["name"] for s in json.loads(r.output)["seams"]] == ["s2"]
    r = run("seams", bare_skirt, "--set", "h1=front.hem@0-0.5:back.hem@0.5-1", "--set",
            "h2=front.hem@0.5-1:back.hem@0-0.5", "--out", tmp_path / "h.json", "--json")
    assert r.exit_code == 0, r.output
    rows = json.loads(r.output)["seams"]
    assert [(s["a"]["start"], s["a"]["end"], s["b"]["start"]) for s in rows] == \
        [(0.0, 0.5, 0.5), (0.5, 1.0, 0.0)]
    assert rows[0]["a"]["length_cm"] == pytest.approx(32.0, abs=0.1)
    for bad, words in (("s3=front.hem:back.hip_r", "limit"), ("s3=front:back.hem", "PANEL.EDGE"),
                       ("s3=front.hem@0-x:back.hem", "@START-END"),
                       ("s3=front.hem@0.7-0.2:back.hem", "before end"),
                       ("s3=front.side_r:back.side_r:x", "number"),
                       ("s3=front.nope:back.hem", "nope")):
        r = run("seams", bare_skirt, "--set", bad, "--out", tmp_path / "x.json")
        assert r.exit_code == 2 and words in r.output, (bad, r.output)
    r = run("seams", bare_skirt, "--remove", "zz", "--out", tmp_path / "x.json")
    assert r.exit_code == 2 and "no seam 'zz'" in r.output


def test_unsewn_patterns_are_refused_at_drape_time_naming_the_fix(bare_skirt, tmp_path):
    with pytest.raises(PatternError, match=r"patternfit seams .*skirt.json --suggest --accept"):
        api.drape_and_evaluate(bare_skirt, triangles=300)
    skirt = build("skirt", "M")
    with pytest.raises(PatternError, match="no seams"):
        api.drape_and_evaluate(replace(skirt, seams=()), triangles=300)
    r = run("drape", "--pattern", bare_skirt, "--out", tmp_path / "d", "--triangles", 300)
    assert r.exit_code == 2 and "--suggest --accept" in r.output
    # a piece sewn to nothing while the others are sewn; its own dart does not count
    from patternfit.edit import add_seam
    from patternfit.pattern import Edge, Loop, Panel

    pocket = Panel("pocket", Loop("outline", tuple(
        Edge.line(n, a, b) for n, a, b in (("b", (0, 0), (0.1, 0)), ("r", (0.1, 0), (0.1, 0.1)),
                                           ("t", (0.1, 0.1), (0, 0.1)), ("l", (0, 0.1), (0, 0))))))
    loose = add_seam(replace(skirt, panels=skirt.panels + (pocket,)), {"panel": "pocket",
                     "edge": "r"}, {"panel": "pocket", "edge": "l"})
    with pytest.raises(PatternError, match="'pocket'.*sewn to no other piece"):
        api.drape_and_evaluate(loose, triangles=300)


def test_a_one_piece_wrap_and_a_session_of_an_unsewn_pattern(tmp_path):
    from patternfit.pattern.seam_suggest import check_sewn

    skirt = build("skirt", "M")
    check_sewn(replace(skirt, panels=skirt.panels[:1], seams=()))   # a wrap: allowed
    session = api.design_session(replace(skirt, seams=()), triangles=300)
    with pytest.raises(PatternError, match="--suggest --accept"):
        session.redrape()
    # sewn in the session, it is no longer refused by the check (not draped here)
    for s in skirt.seams:
        session.apply("add_seam", a={"panel": s.a.panel, "edge": s.a.edge},
                      b={"panel": s.b.panel, "edge": s.b.edge}, name=s.name)
    check_sewn(session.pattern)
    assert len(session.mesh.seam_names) == 4


def test_a_seam_edit_the_file_cannot_take_names_the_file_and_the_edges(tmp_path):
    """``seams FILE --set`` of an edge the panel lacks named neither the file nor the
    edges it has."""
    src = tmp_path / "skirt.json"
    assert runner.invoke(app, ["patterns", "skirt", "--out", str(src)]).exit_code == 0
    res = runner.invoke(app, ["seams", str(src), "--set", "side=front.e1:back.e4"])
    assert res.exit_code == 2
    assert f"{src}:" in res.stderr and "edges: hem, side_l" in res.stderr
    res = runner.invoke(app, ["seams", str(src), "--remove", "nosuch"])
    assert res.exit_code == 2 and f"{src}: no seam 'nosuch'" in res.stderr
