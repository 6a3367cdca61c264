"""What a long wait shows on standard error (flexkane.progress): an updating line on a terminal, plain
lines elsewhere, nothing with --quiet; no ticker thread outlives its phase, and none runs when the
compilation forks. Time comes from a fake clock: no test depends on the wall clock."""

from __future__ import annotations

import contextlib
import io
import os
import pathlib
import re
import subprocess
import sys
import threading

import pytest

from flexkane import progress
from flexkane.cli import main
from flexkane.forking import fork_allowed
from flexkane.progress import activity, reporting, steps, tick, ticking
from flexkane.simulation import COMPILING_MESSAGE


class FakeClock:
    """Seconds that pass only when a test says so (``clock.now += 2.5``)."""

    def __init__(self):
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


class Stream(io.StringIO):
    """A text stream that is, or is not, a terminal."""

    def __init__(self, terminal: bool):
        super().__init__()
        self.terminal = terminal

    def isatty(self) -> bool:
        return self.terminal


def ticker_threads() -> list:
    return [t for t in threading.enumerate() if t.name == "flexkane-progress"]


def test_the_terminal_line_updates_each_second_and_ends_with_the_elapsed_time():
    clock, stream = FakeClock(), Stream(terminal=True)
    with reporting(stream=stream, clock=clock):
        with activity("compiling the arm", delay=0, thread=False):
            for _ in range(3):
                clock.now += 0.5
                tick()                 # 0.5 s: still "0 s"; 1.0 s: "1 s"; 1.5 s: no change
            clock.now += 29.7
    assert stream.getvalue() == ("\rflexkane: compiling the arm ... 0 s"
                                 "\rflexkane: compiling the arm ... 1 s"
                                 "\rflexkane: compiling the arm ... done in 31.2 s\n")


def test_a_terminal_line_shows_the_progress_of_an_integration_and_is_not_drawn_before_its_delay():
    clock, stream = FakeClock(), Stream(terminal=True)
    with reporting(stream=stream, clock=clock):
        with activity("integrating the arm", delay=1.0, thread=False) as bar:
            clock.now += 0.5
            bar.update(0.25, 5.0, "s")
            assert stream.getvalue() == ""          # quick so far: nothing shown
            clock.now += 1.0
            bar.update(2.5, 5.0, "s")
            clock.now += 1.0
    assert stream.getvalue() == ("\rflexkane: integrating the arm [##########----------] 2.5/5 s ... 1 s"
                                 "\rflexkane: integrating the arm [##########----------] 2.5/5 s ... done in 2.5 s\n")


def test_a_quick_phase_that_was_never_shown_leaves_nothing_on_a_terminal():
    clock, stream = FakeClock(), Stream(terminal=True)
    with reporting(stream=stream, clock=clock):
        with activity("forming the Jacobians", thread=False):
            clock.now += 1.9
            tick()
    assert stream.getvalue() == ""


def test_a_non_terminal_gets_the_start_line_of_an_announced_phase_and_an_end_line_when_it_was_long():
    clock, stream = FakeClock(), Stream(terminal=False)
    with reporting(stream=stream, clock=clock):
        with activity("deriving the equations of motion of a", delay=0):
            clock.now += 0.4
            tick()
        with activity("deriving the equations of motion of b", delay=0):
            clock.now += 31.25
            tick()
    assert stream.getvalue() == ("flexkane: deriving the equations of motion of a ...\n"
                                 "flexkane: deriving the equations of motion of b ...\n"
                                 "flexkane: deriving the equations of motion of b ... done in 31.2 s\n")


def test_a_non_terminal_gets_one_line_for_a_phase_that_may_be_quick_only_when_it_was_long():
    clock, stream = FakeClock(), Stream(terminal=False)
    with reporting(stream=stream, clock=clock):
        with activity("finding the operating point"):
            clock.now += 1.5
        with activity("forming the Jacobians"):
            clock.now += 12.0
            tick()
    assert stream.getvalue() == "flexkane: forming the Jacobians ... done in 12.0 s\n"


@pytest.mark.parametrize("terminal", [True, False])
def test_quiet_or_library_use_shows_nothing(terminal):
    clock, stream = FakeClock(), Stream(terminal=terminal)
    for quiet in (True, None):   # None: no reporting at all (a library call)
        with reporting(quiet=True, stream=stream, clock=clock) if quiet else contextlib.nullcontext():
            with activity("deriving", delay=0) as phase:
                clock.now += 40.0
                phase.update(1, 2)
                tick()
            with steps("Campbell diagram", 2) as loop:
                clock.now += 40.0
                loop.done("Omega = 1 rad/s")
    assert stream.getvalue() == "" and not ticker_threads()


def test_steps_print_one_line_each_once_they_take_long():
    clock, stream = FakeClock(), Stream(terminal=False)
    with reporting(stream=stream, clock=clock):
        with steps("Campbell diagram of spin-up", 4) as loop:
            for seconds, spin in ((0.5, 0.0), (1.0, 1.0), (3.0, 2.0), (0.25, 3.0)):
                clock.now += seconds
                loop.done(f"Omega = {spin:g} rad/s")
    assert stream.getvalue() == (
        "flexkane: Campbell diagram of spin-up: 3/4, Omega = 2 rad/s (3.0 s; 4.5 s so far)\n"
        "flexkane: Campbell diagram of spin-up: 4/4, Omega = 3 rad/s (0.2 s; 4.8 s so far)\n")


def test_the_ticker_thread_lives_only_while_its_activity_is_the_innermost_one():
    stream = Stream(terminal=True)
    before = threading.active_count()
    with reporting(stream=stream, interval=0.001):
        with activity("linearizing", delay=0):
            assert len(ticker_threads()) == 1
            with activity("compiling", delay=0, thread=False):   # where the compilation forks
                assert not ticker_threads()
                with ticking():                                # once the children are forked
                    assert len(ticker_threads()) == 1
                assert not ticker_threads()
            assert len(ticker_threads()) == 1
        assert not ticker_threads()
    assert threading.active_count() == before
    assert re.search(r"\rflexkane: linearizing ... done in \d+\.\d s\n$", stream.getvalue())


def test_a_stop_ends_the_line_and_the_thread_at_once():
    stream = Stream(terminal=True)
    with reporting(stream=stream):
        with pytest.raises(KeyboardInterrupt):
            with activity("deriving", delay=0):
                raise KeyboardInterrupt
        assert progress._active == [] and not ticker_threads()
    assert stream.getvalue().endswith(" s\n") and "done" not in stream.getvalue()


def test_the_compilation_forks_while_no_ticker_thread_runs(tmp_path, monkeypatch):
    """The real forks of jit_module (a module that fails at once in the children) under a terminal
    activity with a ticker thread: the compile's own activity has none when it forks; one is lent to
    the caller's work meanwhile; none remains afterwards."""
    from flexkane.numerics import jit_module

    if not fork_allowed():
        pytest.skip("this process may not fork now (other threads): the test runs in a fresh interpreter instead")
    path = tmp_path / "flexkane_generated_broken.py"
    path.write_text("raise RuntimeError('a module that cannot be imported')\n", encoding="utf-8")
    at_fork, meanwhile = [], []
    real_fork = os.fork

    def fork():
        at_fork.append(len(ticker_threads()))
        return real_fork()

    monkeypatch.setattr(os, "fork", fork)
    with reporting(stream=Stream(terminal=True), interval=0.001):
        with activity("running the arm", delay=0):
            with activity(COMPILING_MESSAGE, delay=0, thread=False):
                ok = jit_module._compile_in_child(path, meanwhile=lambda: meanwhile.append(len(ticker_threads())))
    assert ok is False and at_fork == [0, 0] and meanwhile == [1] and not ticker_threads()


def test_the_compilation_forks_while_no_ticker_thread_runs_in_a_fresh_interpreter():
    """The test above, in a new interpreter (one thread) when earlier tests left threads in this one."""
    if fork_allowed():
        pytest.skip("the test runs in this process")
    if not (sys.platform.startswith("linux") and hasattr(os, "fork")):
        pytest.skip("the compiling fork needs Linux")
    test = f"{__file__}::test_the_compilation_forks_while_no_ticker_thread_runs"
    done = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", test],
                          capture_output=True, text=True, cwd=pathlib.Path(__file__).resolve().parents[1])
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
    assert "1 passed" in done.stdout.splitlines()[-1], done.stdout[-3000:]


PENDULUM = """\
name = "tiny-pendulum"

[parameters]
m = 1.0     # [kg]
a = 0.5     # [m]
J = 0.02    # [kg m^2]
g = 9.81    # [m/s^2]

[bodies.bob]
mass = "m"
inertia = "J"
points = { pin = ["-a", 0] }

[joints.pin]
type = "revolute"
parent = "ground"
child = "bob"
child_point = "pin"

[gravity]
g = "g"
direction = [0, -1]

[initial]
q_pin = 0.5

[simulation]
t_end = 0.1
dt_out = 0.01
"""


class Minutes:
    """A clock on which every reading is a minute after the last: every phase looks long."""

    def __init__(self):
        self.now = 0.0

    def __call__(self) -> float:
        self.now += 60.0
        return self.now


def flexkane_lines(text: str) -> list[str]:
    return [line for line in text.splitlines() if line.startswith("flexkane: ") and "warning" not in line]


def test_run_reports_derivation_code_generation_compilation_and_integration_and_quiet_silences_them(
        tmp_path, monkeypatch, capsys):
    model = tmp_path / "tiny-pendulum.toml"
    model.write_text(PENDULUM, encoding="utf-8")
    monkeypatch.setenv("FLEXKANE_CACHE_DIR", str(tmp_path / "cache"))   # a new structure: all phases
    monkeypatch.setattr(progress, "_clock", Minutes())
    assert main(["run", str(model), "--out", str(tmp_path / "first"), "--no-plots"]) == 0
    lines = flexkane_lines(capsys.readouterr().err)
    announced = ["deriving the equations of motion of tiny-pendulum", "generating the code of tiny-pendulum",
                 COMPILING_MESSAGE]     # known to be long: a start line at once, an end line (a minute)
    integration = "integrating tiny-pendulum to t = 0.1 s [####################] 0.1/0.1 s"   # an end line
    for phase in announced:
        assert [line for line in lines if phase in line and line.endswith(" ...")], lines
    for phase in announced + [integration]:
        assert [line for line in lines if phase in line and re.search(r" \.\.\. done in \d+\.0 s$", line)], lines
    assert lines[-1].startswith(f"flexkane: {integration} ... done in "), lines
    assert main(["run", str(model), "--out", str(tmp_path / "quiet"), "--no-plots", "--quiet"]) == 0
    assert flexkane_lines(capsys.readouterr().err) == []
    assert main(["run", str(model), "--out", str(tmp_path / "again"), "--no-plots"]) == 0
    lines = flexkane_lines(capsys.readouterr().err)   # cached: only the integration is left
    assert len(lines) == 1 and lines[0].startswith(f"flexkane: {integration} ... done in "), lines


def test_campbell_reports_each_spin_rate_and_converge_each_mode_count(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("FLEXKANE_CACHE_DIR", str(tmp_path / "cache"))   # computed, not answered from the cache
    monkeypatch.setattr(progress, "_clock", Minutes())
    assert main(["campbell", "spin-up", "--n-modes", "1", "--spin", "0:2:3", "--out", str(tmp_path / "c")]) == 0
    lines = [line for line in flexkane_lines(capsys.readouterr().err) if "Campbell diagram" in line]
    assert [line.split(" (")[0] for line in lines] == [
        "flexkane: Campbell diagram of spin-up: 1/3, Omega = 0 rad/s",
        "flexkane: Campbell diagram of spin-up: 2/3, Omega = 1 rad/s",
        "flexkane: Campbell diagram of spin-up: 3/3, Omega = 2 rad/s"]
    assert all(re.search(r" \(\d+\.0 s; \d+\.0 s so far\)$", line) for line in lines), lines
    assert main(["converge", "flexible-arm", "--n-modes", "1..2", "--out", str(tmp_path / "v")]) == 0
    lines = [line for line in flexkane_lines(capsys.readouterr().err) if "convergence study" in line]
    assert [line.split(" (")[0] for line in lines] == [
        "flexkane: convergence study of flexible-arm: 1/2, 1 mode per beam",
        "flexkane: convergence study of flexible-arm: 2/2, 2 modes per beam"]
    assert main(["converge", "flexible-arm", "--n-modes", "1..2", "--out", str(tmp_path / "q"), "--quiet"]) == 0
    assert capsys.readouterr().err == ""


def test_linearize_reports_its_stages_in_order(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("FLEXKANE_CACHE_DIR", str(tmp_path / "cache"))   # derived and computed: every stage
    monkeypatch.setattr(progress, "_clock", Minutes())
    assert main(["linearize", "flexible-arm", "--out", str(tmp_path / "l")]) == 0
    ended = [line.split(" ... done in ")[0] for line in flexkane_lines(capsys.readouterr().err) if " ... done in " in line]
    assert ended == [f"flexkane: {stage} of flexible-arm" for stage in (
        "deriving the equations of motion", "forming the matrices",
        "forming the Jacobians and numeric functions of the linearization", "finding the operating point",
        "forming the Jacobians of the outputs", "eigenvalues and mode shapes", "drawing the mode shapes")]


def test_an_activity_of_another_thread_is_silent():
    clock, stream = FakeClock(), Stream(terminal=False)
    with reporting(stream=stream, clock=clock):
        def work():
            with activity("deriving in a worker thread", delay=0):
                clock.now += 10.0

        worker = threading.Thread(target=work)
        worker.start()
        worker.join()
    assert stream.getvalue() == "" and progress._active == []
