"""The saved design session: each state written once, ``current`` recovered when missing or
damaged (history never deleted), damaged files refused with a SessionError naming them."""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from patternfit.errors import SessionError
from patternfit.loop import DesignSession
from patternfit.loop.session import STATES, SessionWarning, holds_session

HEM = {"panel": "front", "edge": "hem", "offset": (0.0, -0.004), "partner": True}


@pytest.fixture(scope="module")
def session():
    """Four states, the last two with (made-up) 3D positions: no drape needed here."""
    s = DesignSession.new(garment="skirt", size="M", body="female_thin", triangles=300)
    for _ in range(3):
        s.apply("move_edge", **HEM)
    for st in s.history[2:]:
        st.positions = np.column_stack([st.mesh.vertices, np.full(st.mesh.n_vertices, 0.1)])
    return s


def files_of(folder) -> dict:
    """Every file under ``folder`` with its (inode, mtime): a rewrite changes both."""
    return {str(p.relative_to(folder)): (p.stat().st_ino, p.stat().st_mtime_ns)
            for p in folder.rglob("*") if p.is_file()}


def same_history(a, b) -> bool:
    return a.position == b.position and [s.label for s in a.history] == \
        [s.label for s in b.history] and all(
            np.array_equal(x.mesh.vertices, y.mesh.vertices) for x, y in zip(a.history, b.history))


def snapshot(folder) -> str:
    return (folder / "current").read_text().strip()


def test_saving_after_an_edit_writes_only_the_new_state(session, tmp_path):
    folder = tmp_path / "s"
    session.save(folder)
    before = files_of(folder)
    assert len([f for f in before if f.startswith(STATES)]) == 4 * 2 + 2  # + two drapes
    session.apply("move_edge", **HEM)
    try:
        session.save(folder)
        after = files_of(folder)
        written = {f for f in after if before.get(f) != after[f]}
        new_state = session.state.key
        assert written == {"current", snapshot(folder), f"{STATES}/{new_state}/pattern.json",
                           f"{STATES}/{new_state}/mesh.npz",
                           f"{STATES}/{new_state}/{session.state._stored_positions[1]}"}
        # an unchanged session saved again writes only the small snapshot and ``current``
        session.save(folder)
        again = files_of(folder)
        assert {f for f in again if after.get(f) != again[f]} == {"current", snapshot(folder)}
        # a loaded session saved into its folder writes nothing of its states either
        DesignSession.load(folder).save(folder)
        reloaded = files_of(folder)
        assert {f for f in reloaded if again.get(f) != reloaded[f]} == \
            {"current", snapshot(folder)}
        assert same_history(DesignSession.load(folder), session)
    finally:
        session.undo()
        del session.history[session.position + 1:]


def test_a_redrape_writes_the_new_positions_once_and_drops_the_old(session, tmp_path):
    folder = tmp_path / "s"
    session.save(folder)
    st = session.state
    old = st._stored_positions[1]
    st.positions = st.positions + 0.001  # what a re-drape does: a new array
    session.save(folder)
    names = {p.name for p in (folder / STATES / st.key).iterdir()}
    assert names == {"pattern.json", "mesh.npz", st._stored_positions[1]} and old not in names
    assert np.array_equal(DesignSession.load(folder).positions, st.positions)


@pytest.mark.parametrize("damage", ["missing", "empty", "garbage", "traversal", "dangling"])
def test_a_missing_or_damaged_current_recovers_the_newest_snapshot(session, tmp_path, damage):
    folder = tmp_path / "s"
    session.save(folder)
    current = folder / "current"
    if damage == "missing":
        current.unlink()
    else:
        current.write_bytes({"empty": b"", "garbage": b"\xff\x00 not a name",
                             "traversal": b"../../../etc/passwd",
                             "dangling": b"snapshot-1.json\n"}[damage])
    kept = files_of(folder)
    assert holds_session(folder)
    back = DesignSession.load(folder)
    assert same_history(back, session)
    assert files_of(folder) == kept  # loading deletes (and rewrites) nothing


def test_a_snapshot_written_but_not_yet_named_is_used_only_without_current(session, tmp_path):
    folder = tmp_path / "s"
    session.save(folder)
    named = snapshot(folder)
    # a save killed between its snapshot file and ``current``: a newer, complete snapshot
    meta = json.loads((folder / named).read_text())
    meta["position"] = 0
    newer = f"snapshot-{int(named[9:-5]) + 1}.json"
    (folder / newer).write_text(json.dumps(meta))
    assert DesignSession.load(folder).position == session.position  # current wins
    (folder / "current").unlink()
    assert DesignSession.load(folder).position == 0  # else the newest complete one
    (folder / newer).write_text("{")  # a damaged newest one: the older complete one
    assert DesignSession.load(folder).position == session.position


def test_the_studio_continues_a_session_whose_current_is_lost(session, tmp_path):
    from fastapi.testclient import TestClient

    from patternfit.studio import create_app

    session.save(tmp_path / "studio" / "session")
    (tmp_path / "studio" / "session" / "current").unlink()
    kept = files_of(tmp_path / "studio")
    app = create_app(tmp_path / "studio", allowed_hosts=("testserver",))
    state = TestClient(app).get("/api/state").json()
    assert [h["label"] for h in state["history"]] == [s.label for s in session.history]
    assert files_of(tmp_path / "studio") == kept


def test_the_studio_refuses_a_session_that_does_not_load(session, tmp_path):
    from patternfit.studio import create_app

    folder = tmp_path / "studio" / "session"
    session.save(folder)
    (folder / snapshot(folder)).write_text('{"format": "patternfit-session"')
    kept = files_of(tmp_path / "studio")
    with pytest.raises(SessionError, match=snapshot(folder)):
        create_app(tmp_path / "studio")
    assert files_of(tmp_path / "studio") == kept


def _save_npy(path, array):
    buf = io.BytesIO()
    np.save(buf, array)
    path.write_bytes(buf.getvalue())


def _damage(folder, what: str) -> str:
    """Damage one file of the saved session; the name the error must give."""
    snap = folder / snapshot(folder)
    meta = json.loads(snap.read_text())
    last = folder / STATES / meta["states"][-1]["key"]
    positions = last / meta["states"][-1]["positions"]
    n = len(np.load(positions))
    if what == "nan positions":
        _save_npy(positions, np.full((n, 3), np.nan))
        return positions.name
    if what == "positions shape":
        _save_npy(positions, np.zeros((n - 1, 3)))
        return positions.name
    if what == "positions text":
        positions.write_text("not numpy")
        return positions.name
    if what in ("nan mesh", "mesh triangles", "truncated mesh"):
        with np.load(last / "mesh.npz") as z:
            arrays = dict(z)
        if what == "nan mesh":
            arrays["vertices"][3] = np.nan
        elif what == "mesh triangles":
            arrays["triangles"][0, 0] = 10 ** 6
        buf = io.BytesIO()
        np.savez(buf, **arrays)
        data = buf.getvalue()
        (last / "mesh.npz").write_bytes(data[:100] if what == "truncated mesh" else data)
        return "mesh.npz"
    if what == "pattern":
        (last / "pattern.json").write_text('{"format": "patternfit-pattern", "panels": 3}')
        return "pattern.json"
    if what == "missing state":
        for p in last.iterdir():
            p.unlink()
        last.rmdir()
        return "pattern.json"
    changes = {"position": {"position": 99}, "key": {"states": [{**meta["states"][0],
                                                                   "key": "../../x"}]},
               "fabric": {"fabric": {"name": "x", "density": "heavy"}},
               "body": {"body": "../../elsewhere.npz"}, "version": {"version": 7}}[what]
    snap.write_text(json.dumps({**meta, **changes}))
    return snap.name


@pytest.mark.parametrize("what", ["nan positions", "positions shape", "positions text",
                                  "nan mesh", "mesh triangles", "truncated mesh", "pattern",
                                  "missing state", "position", "key", "fabric", "body",
                                  "version"])
def test_a_damaged_session_is_a_session_error_naming_the_file(session, tmp_path, what):
    folder = tmp_path / "s"
    session.save(folder)
    name = _damage(folder, what)
    kept = files_of(folder)
    with pytest.raises(SessionError) as err:
        DesignSession.load(folder)
    assert name in str(err.value)
    assert files_of(folder) == kept


def test_a_save_killed_while_writing_a_state_leaves_the_previous_one(session, tmp_path):
    folder = tmp_path / "s"
    session.save(folder)
    first = snapshot(folder)
    code = f"""
import os, signal
from patternfit.loop import session as sm
from patternfit.loop import DesignSession
s = DesignSession.load({str(folder)!r})
s.apply("move_edge", panel="front", edge="hem", offset=(0.0, -0.004), partner=True)
real = sm.save_garment
def dying(*a, **k):
    real(*a, **k)
    os.kill(os.getpid(), signal.SIGKILL)
sm.save_garment = dying
s.save({str(folder)!r})
"""
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True)
    assert proc.returncode != 0  # killed
    assert snapshot(folder) == first
    parts = [p for p in (folder / STATES).iterdir() if p.name.startswith(".")]
    assert len(parts) == 1  # the half-written state, in a hidden folder nothing names
    assert same_history(DesignSession.load(folder), session)
    session.save(folder)  # the next save cleans up
    assert not any(p.name.startswith(".") for p in (folder / STATES).iterdir())
    assert len(list(folder.glob("snapshot-*"))) == 1


def test_a_version_1_session_loads_and_is_moved_to_the_new_layout(session, tmp_path):
    from patternfit.pattern.io import save_pattern

    folder = tmp_path / "s"
    snap = folder / "snapshot-1"
    states = []
    for i, s in enumerate(session.history):
        d = snap / f"state-{i:03d}"
        save_pattern(s.pattern, d / "pattern.json")
        s.mesh.save(d / "mesh.npz")
        if s.positions is not None:
            _save_npy(d / "positions.npy", s.positions)
        states.append({"label": s.label, "edit": s.edit, "fitting_ratio": s.fitting_ratio,
                       "checks": s.checks, "draped": s.positions is not None})
    meta = {"format": "patternfit-session", "version": 1, "body": "female_thin",
            "fabric": vars(session.fabric), "triangles": session.triangles,
            "threshold": session.threshold, "position": session.position, "states": states}
    (snap / "session.json").write_text(json.dumps(meta, default=list))
    (folder / "current").write_text("snapshot-1\n")
    back = DesignSession.load(folder)
    assert same_history(back, session) and back.body.name == "female_thin"
    back.save(folder)
    assert not snap.exists() and same_history(DesignSession.load(folder), session)
    assert os.path.isdir(folder / STATES)


def test_a_carried_start_keeps_its_rest_shapes_across_a_save(tmp_path):
    s = DesignSession.new(garment="skirt", size="M", body="female_thin", triangles=300)
    s.apply("move_edge", **HEM)
    st = s.state
    st.positions = np.column_stack([st.mesh.vertices, np.full(st.mesh.n_vertices, 0.1)])
    st.start_rest = st.mesh.vertices + 0.004  # made up: a start carried over an edit
    folder = tmp_path / "s"
    s.save(folder)
    back = DesignSession.load(folder)
    assert np.array_equal(back.state.start_rest, st.start_rest)
    assert back.next_start() == "carried"  # not the placement, as before the save
    written = files_of(folder)
    back.save(folder)
    rest_files = [k for k in files_of(folder) if "start-rest-" in k]
    assert len(rest_files) == 1 and files_of(folder)[rest_files[0]] == written[rest_files[0]]
    # damaged: its shape, then its name in the snapshot
    refused_when_damaged(folder, "start_rest",
                         lambda rest: _save_npy(rest, np.zeros((st.mesh.n_vertices, 3))))


def refused_when_damaged(folder, field: str, damage) -> None:
    """The last state's file that ``field`` of the snapshot names, damaged by
    ``damage(path)``, then that name pointed outside the session: each time the session
    is refused with a SessionError naming the file, then the field."""
    meta = json.loads((folder / snapshot(folder)).read_text())
    row = meta["states"][-1]
    path = folder / STATES / row["key"] / row[field]
    damage(path)
    with pytest.raises(SessionError, match=path.name):
        DesignSession.load(folder)
    row[field] = f"../../{path.name}"
    (folder / snapshot(folder)).write_text(json.dumps(meta))
    with pytest.raises(SessionError, match=field):
        DesignSession.load(folder)


def test_a_drape_read_back_goes_on_from_its_own_rest(tmp_path):
    """A session read back re-drapes a draped state from its own drape and contact state,
    as ``drape --start`` does: at rest, it stops at once and moves nothing (it was draped
    cold, from the placement, and landed elsewhere)."""
    s = DesignSession.new(garment="skirt", size="M", body="female_thin", triangles=300)
    first = s.redrape()
    assert first.checks.equilibrium
    folder = tmp_path / "s"
    s.save(folder)
    back = DesignSession.load(folder)
    assert back.next_start() == "continued"
    again = back.redrape()
    assert again.timing["start"] == "saved" and again.report_extra()["timing"]["iterations"] == 0
    assert np.abs(again.positions - first.positions).max() <= 1e-3
    assert back.state.fitting_ratio == pytest.approx(s.state.fitting_ratio)
    # the contact state is a help, not the state: damaged or lost, the session loads and the
    # drape goes on from the positions, saying so (one lost file made the session
    # unloadable); contents that do not fit the mesh likewise (every drape of the state
    # failed, naming no file)
    meta = json.loads((folder / snapshot(folder)).read_text())
    row = meta["states"][-1]
    contact = folder / STATES / row["key"] / row["contact"]
    kept = contact.read_bytes()
    contact.write_bytes(b"PK\x03\x04 damaged")
    with pytest.warns(SessionWarning, match=contact.name):
        back = DesignSession.load(folder)
    assert back.state.contact is None and back.next_start() == "continued"
    assert np.abs(back.redrape().positions - first.positions).max() <= 1e-3
    contact.write_bytes(kept)
    back = DesignSession.load(folder)
    back.state.contact = {**back.state.contact, "anchor_of": np.zeros(3, np.int64)}
    with pytest.warns(SessionWarning, match="does not fit its mesh"):
        back.redrape()
    # a name that is not its own is refused, as every file the snapshot names
    row["contact"] = "../../contact.npz"
    (folder / snapshot(folder)).write_text(json.dumps(meta))
    with pytest.raises(SessionError, match="contact"):
        DesignSession.load(folder)
