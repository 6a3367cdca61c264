"""Plots drawn by two processes (``write_plots(workers=2)``, as ``flexkane run`` draws them): the same
files, byte for byte, as one process draws, run after run; a figure that fails in the second process
is reported with its error, and the files already written stay."""

from __future__ import annotations

import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

from flexkane import plots
from flexkane.forking import fork_allowed
from flexkane.plot_workers import PlotWorkerError
from flexkane.model.columns import Output
from flexkane.plots import write_plots
from flexkane.results import Results

#: Set in the fresh interpreter that :func:`test_in_a_fresh_interpreter` starts.
INNER = "FLEXKANE_TEST_PLOT_FORK"


@pytest.fixture
def single_thread():
    """Skip where this process may not fork (not Linux, or other threads left by earlier tests, e.g. a
    notebook's kernel client): :func:`test_in_a_fresh_interpreter` then runs these tests in one."""
    if not fork_allowed():
        pytest.skip("this process may not fork now: the tests run in a fresh interpreter instead")


def test_in_a_fresh_interpreter():
    """The fork's tests below, run in a new interpreter (one thread) when they cannot run here."""
    if fork_allowed() or os.environ.get(INNER) == "1":
        pytest.skip("the tests run in this process")
    if not (sys.platform.startswith("linux") and hasattr(os, "fork")):
        pytest.skip("a plotting fork needs Linux")
    done = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", __file__],
                          env={**os.environ, INNER: "1"}, capture_output=True, text=True,
                          cwd=pathlib.Path(__file__).resolve().parents[1])
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
    assert "3 passed" in done.stdout.splitlines()[-1], done.stdout[-3000:]

UNITS = {"q1": "rad", "q2": "m", "u1": "rad/s"}


def made_up_run(rows: int = 120) -> Results:
    """Results of no model: three state variables, a tip deflection and energies (five figures)."""
    t = np.linspace(0.0, 2.0, rows)
    names = ["q1", "q2", "u1"]
    state = np.column_stack([np.sin((k + 1) * t) * 10.0 ** -k for k in range(len(names))])
    kinetic = 0.5 * state[:, 2] ** 2
    outputs = {"tip_b": 1e-4 * np.sin(7 * t), "kinetic": kinetic, "energy": kinetic + 1e-9 * t}
    declared = {"tip_b": Output("tip_b", None, "m", "tip"), "kinetic": Output("kinetic", None, "J", "energy"),
                "energy": Output("energy", None, "J", "energy")}
    return Results(t=t, state=state, state_names=names, outputs=outputs, declared=declared)


def files(directory) -> dict:
    return {p.name: p.read_bytes() for p in sorted(directory.iterdir())}


def test_two_processes_write_the_same_bytes_as_one(tmp_path, single_thread):
    res = made_up_run()
    written = {}
    for label, workers in (("one", 1), ("two", 2)):
        (tmp_path / label).mkdir()
        paths = write_plots(res, UNITS, tmp_path / label, "made-up", workers=workers)
        assert [p.name for p in paths] == ["q1.png", "q2.png", "u1.png", "tip_deflection.png", "energy.png"]
        assert all(p.parent == tmp_path / label for p in paths)
        written[label] = files(tmp_path / label)
    assert sorted(written["one"]) == sorted(p.name for p in paths)   # no temporary file left
    assert written["two"] == written["one"]


def test_a_figure_failing_in_the_second_process_is_reported_and_the_written_files_stay(tmp_path, monkeypatch,
                                                                                      single_thread):
    res = made_up_run(rows=30)
    draw = plots._SeriesFigure.draw

    def draw_or_fail(self, results, name, *args):
        if name == "q2":   # the second figure: the fork draws the second and the fourth
            raise ValueError("made-up failure drawing q2")
        return draw(self, results, name, *args)
    monkeypatch.setattr(plots._SeriesFigure, "draw", draw_or_fail)
    with pytest.raises(PlotWorkerError) as failure:
        write_plots(res, UNITS, tmp_path, "made-up", workers=2)
    text = str(failure.value)
    assert "ValueError: made-up failure drawing q2" in text and "3 of 5 figures" in text
    assert "draw_or_fail" in text   # the fork's traceback
    # this process's figures (the first, third and fifth) stay; no temporary file is left
    assert sorted(p.name for p in tmp_path.iterdir()) == ["energy.png", "q1.png", "u1.png"]


def test_one_process_when_forking_is_not_allowed(tmp_path, monkeypatch):
    """With another thread running (a fork could inherit a held lock), this process draws them all."""
    import flexkane.forking

    monkeypatch.setattr(flexkane.forking, "fork_allowed", lambda: False)
    monkeypatch.setattr("flexkane.plot_workers.draw_in_two", lambda *a: pytest.fail("forked"))
    res = made_up_run(rows=20)
    res.outputs = {}
    paths = write_plots(res, UNITS, tmp_path, "made-up", workers=2)
    assert [p.name for p in paths] == ["q1.png", "q2.png", "u1.png"]
    assert sorted(p.name for p in paths) == sorted(p.name for p in tmp_path.iterdir())
