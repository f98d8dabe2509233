"""How many threads the solver takes (``patternfit.sim.threads``) and running two halves."""

from __future__ import annotations

import threading

import pytest

from patternfit.sim.threads import ENV, MOST, both, solver_threads


def test_the_variable_sets_the_threads_up_to_two(monkeypatch):
    monkeypatch.setenv(ENV, "1")
    assert solver_threads() == 1
    monkeypatch.setenv(ENV, "16")
    assert solver_threads() == MOST == 2
    monkeypatch.delenv(ENV)
    monkeypatch.setenv("OMP_NUM_THREADS", "1")  # a one-CPU Ray task's
    assert solver_threads() == 1
    monkeypatch.setenv("OMP_NUM_THREADS", "1,4")  # OpenMP's nested levels: the outer one
    assert solver_threads() == 1
    monkeypatch.setenv("OMP_NUM_THREADS", "auto")  # another library's: not ours to refuse
    assert 1 <= solver_threads() <= MOST
    monkeypatch.delenv("OMP_NUM_THREADS")
    assert 1 <= solver_threads() <= MOST


@pytest.mark.parametrize("text", ["two", "0", "-1", "1.5"])
def test_a_bad_setting_is_refused_naming_the_variable(monkeypatch, text):
    monkeypatch.setenv(ENV, text)
    with pytest.raises(ValueError, match=f"{ENV}: expected a whole number.*{text!r}"):
        solver_threads()


def test_both_halves_run_and_the_first_in_another_thread():
    seen = []
    a, b = both(lambda: seen.append(threading.current_thread()) or 1,
                lambda: 2, threads=2)
    assert (a, b) == (1, 2) and seen[0] is not threading.current_thread()
    seen.clear()
    assert both(lambda: seen.append(threading.current_thread()) or 3, lambda: 4,
                threads=1) == (3, 4)
    assert seen[0] is threading.current_thread()


def test_an_error_in_either_half_is_raised_after_both_end():
    done = []

    def fail():
        raise KeyError("first")

    with pytest.raises(KeyError, match="first"):
        both(fail, lambda: done.append(1), threads=2)
    assert done == [1]
    with pytest.raises(ZeroDivisionError):
        both(lambda: done.append(2), lambda: 1 / 0, threads=2)
    assert done == [1, 2]


def test_a_job_split_again_inside_a_half_runs_and_ends():
    """A half that splits its own work (from the worker thread too) does not wait for
    itself (without the guard this hung: the inner job queued behind the outer one)."""
    inner = lambda: both(lambda: 1, lambda: 2, threads=2)  # noqa: E731
    out = []
    runner = threading.Thread(target=lambda: out.append(both(inner, inner, threads=2)),
                              daemon=True)
    runner.start()
    runner.join(timeout=20)
    assert out == [((1, 2), (1, 2))]
