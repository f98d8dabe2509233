"""The design session: edits with mesh update, undo/redo, atomic save and load."""

import numpy as np
import pytest

from patternfit.loop import DesignSession


@pytest.fixture(scope="module")
def session():
    s = DesignSession.new(garment="skirt", size="M", body="female_thin", triangles=900)
    s.redrape()
    return s


def _same_mesh(a, b):
    return np.array_equal(a.vertices, b.vertices) and np.array_equal(a.triangles, b.triangles)


def test_first_drape_records_fit(session):
    st = session.history[0]
    assert st.positions is not None and st.positions.shape == (session.mesh.n_vertices, 3)
    assert 0.5 < st.fitting_ratio < 1.1
    assert st.checks["inside_vertices"] == 0
    assert session.evaluate().fitting_ratio == pytest.approx(st.fitting_ratio)


def test_edit_undo_redo_restores_exactly(session):
    before = session.state
    session.apply("move_edge", panel="front", edge="hem", offset=(0.0, -0.02), partner=True)
    after = session.state
    assert session.position == 1 and after.label.startswith("move_edge")
    assert np.array_equal(after.mesh.triangles, before.mesh.triangles)  # mesh followed
    assert not _same_mesh(after.mesh, before.mesh)
    assert after.positions is not None  # kept as the warm start of the next drape
    undone = session.undo()
    assert undone is before and session.pattern == before.pattern
    assert _same_mesh(session.mesh, before.mesh)
    assert np.array_equal(session.positions, before.positions)
    session.redo()
    assert session.state is after
    with pytest.raises(IndexError):
        session.redo()


def test_unknown_edit_is_refused(session):
    with pytest.raises(ValueError, match="unknown edit"):
        session.apply("explode")


def test_save_load_round_trip(session, tmp_path):
    session.save(tmp_path / "s")
    back = DesignSession.load(tmp_path / "s")
    assert back.position == session.position and len(back.history) == len(session.history)
    for a, b in zip(session.history, back.history):
        assert a.label == b.label and a.pattern == b.pattern and _same_mesh(a.mesh, b.mesh)
        assert (a.positions is None) == (b.positions is None)
        if a.positions is not None:
            assert np.array_equal(a.positions, b.positions)
        assert a.fitting_ratio == b.fitting_ratio
    assert back.body.name == session.body.name and back.fabric == session.fabric


def test_load_refuses_other_folders(tmp_path):
    from patternfit.errors import SessionError
    with pytest.raises(SessionError, match="not a saved design session"):
        DesignSession.load(tmp_path)


def test_a_hem_edit_is_redraped_from_the_last_drape_moved_with_it():
    s = DesignSession.new(garment="skirt", size="M", body="female_thin", triangles=900)
    s.redrape()
    hem = s.positions[:, 1].min()
    s.apply("move_edge", panel="front", edge="hem", offset=(0.0, -0.03), partner=True)
    again = s.redrape()
    assert again.timing["start"] == "moved" and again.checks.passed, again.checks
    assert 0.02 < hem - s.positions[:, 1].min() < 0.04
    # after an undo the state's positions are an older drape's: re-draped from them as given
    s.undo()
    s.apply("move_edge", panel="front", edge="hem", offset=(0.0, -0.01), partner=True)
    assert s.redrape().timing["start"] == "given"
