"""SIGTERM during ``flexkane run`` leaves complete, readable files for what was computed, marked
partial, and exit code 130; an existing output directory is never overwritten without --force.

The run is a long one (the torque pendulum with its singularity moved far away, 10^6 s of motion);
its standard error is a terminal so that the progress bar shows when the integration is under way;
the signal is sent once the bar has shown progress past 2 s of simulated time.
"""

import csv
import os
import pty
import select
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import flexkane
from flexkane.cli import main

T_END = 1e6



def _read_until(fd: int, proc: subprocess.Popen, marker: bytes | None, timeout: float) -> bytes:
    """Read the terminal until ``marker`` appears (or, with None, until the process closes it)."""
    seen = b""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        ready, _, _ = select.select([fd], [], [], 0.2)
        if ready:
            try:
                chunk = os.read(fd, 4096)
            except OSError:   # the other end is closed: the process has exited
                chunk = b""
            if not chunk and marker is None:
                return seen
            seen += chunk
            if marker is not None and marker in seen:
                return seen
        elif proc.poll() is not None and marker is not None:
            break
    raise AssertionError(f"no {marker!r} within {timeout} s; the run printed: {seen.decode(errors='replace')}")


def _last_time(shown: bytes) -> float:
    """The simulated time last drawn by the progress bar [s]."""
    last = shown.rsplit(b"/1e+06 s", 1)[0].rsplit(b"]", 1)[-1]
    return float(last)


@pytest.fixture(scope="module")
def interrupted_run(torque_pendulum, torque_pendulum_file, tmp_path_factory):
    """Start a long run, send SIGTERM once it integrates, and return (exit code, stderr, out)."""
    out = tmp_path_factory.mktemp("interrupted") / "run"
    master, slave = pty.openpty()
    proc = subprocess.Popen(
        [sys.executable, "-m", "flexkane", "run", str(torque_pendulum_file), "--set", "t1=1e9",
         "--t-end", str(T_END), "--dt-out", "1", "--rtol", "1e-12", "--atol", "1e-12", "--method", "dop853",
         "--out", str(out)],
        stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=slave, env=dict(os.environ))
    os.close(slave)
    try:
        shown = _read_until(master, proc, b"/1e+06 s", timeout=300)   # the progress bar: t/t_end s
        while _last_time(shown) < 2.0:
            shown += _read_until(master, proc, b"/1e+06 s", timeout=300)
        proc.send_signal(signal.SIGTERM)
        shown += _read_until(master, proc, None, timeout=300)
        code = proc.wait(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
        os.close(master)
    return code, shown.decode(errors="replace"), out


def test_sigterm_exits_130_and_says_where_it_stopped(interrupted_run):
    code, err, out = interrupted_run
    assert code == 130, err
    assert "Traceback" not in err
    assert "interrupted at t = " in err and "the files hold the results up to there (marked partial)" in err


def test_results_csv_is_complete_for_the_rows_computed(interrupted_run):
    _, _, out = interrupted_run
    lines = (out / "results.csv").read_text().splitlines()
    assert lines[-1].startswith("# partial: interrupted by the user at t = ")
    rows = list(csv.reader(line for line in lines if not line.startswith("#")))
    header, body = rows[0], rows[1:]
    assert header[:3] == ["t", "q_pin", "u_pin"] and len(body) >= 2
    table = np.array(body, dtype=float)              # every row complete and numeric
    assert table.shape[1] == len(header) and np.all(np.isfinite(table))
    np.testing.assert_allclose(np.diff(table[:, 0]), 1.0)
    assert 0 < table[-1, 0] < T_END


def test_results_npz_loads_and_is_marked_partial(interrupted_run):
    _, _, out = interrupted_run
    saved = flexkane.load_results(out)
    assert saved.partial and saved.solver["status"] == "interrupted"
    assert saved.t[-1] <= saved.solver["t_reached"] < T_END
    rows = [line for line in (out / "results.csv").read_text().splitlines()[1:] if not line.startswith("#")]
    assert len(saved.t) == len(rows)
    assert (out / "model.toml").exists()   # the equations and plots are skipped: the stop is honoured at once
    assert not [p.name for p in out.iterdir() if p.name.startswith(".") or ".tmp" in p.name]


def test_an_existing_output_directory_is_not_overwritten_without_force(torque_pendulum_file, tmp_path, capsys):
    out = tmp_path / "earlier"
    out.mkdir()
    (out / "results.csv").write_text("t,q_pin\n0.0,0.5\n")   # a previous run's results
    (out / "notes.txt").write_text("keep")
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    assert main(["run", str(torque_pendulum_file), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and f"--out: expected a new or empty directory (or --force" in err and str(out) in err
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
