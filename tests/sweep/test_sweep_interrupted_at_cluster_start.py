"""A sweep interrupted while its Dask cluster starts (or closes) exits 130 with a consistent table and
no traceback (Dask's own errors, such as ``AssertionError: Status.init``, never reach the user).

The signal is sent by the sweep process itself, from a timer started when ``LocalCluster`` begins
to start, after each of several delays: whatever phase of the start (or of the sweep after it) the
signal meets, the outcome is exit 130 (or 0 if the sweep had finished).
"""

import os
import subprocess
import sys

import pytest

from flexkane.sweep import read_table

MODEL = "falling-beam-exact"
CLI = ["sweep", MODEL, "--vary", "beams.B.EI=20:80:6", "--t-end", "0.2", "--dt-out", "0.01", "--workers", "2",
       "--quiet"]

SIGNAL_AT_CLUSTER_START = """
import os, signal, sys, threading
import distributed
from flexkane.cli import main

delay, sig = float(sys.argv[1]), getattr(signal, sys.argv[2])
start = distributed.LocalCluster.__init__

def start_then_signal(self, *args, **kwargs):
    print("FK: cluster starting", file=sys.stderr, flush=True)
    threading.Timer(delay, os.kill, (os.getpid(), sig)).start()
    start(self, *args, **kwargs)

distributed.LocalCluster.__init__ = start_then_signal
sys.exit(main(sys.argv[3:]))
"""


def _sweep_signalled(out, delay, sig):
    process = subprocess.run([sys.executable, "-c", SIGNAL_AT_CLUSTER_START, str(delay), sig, *CLI, "--out", str(out)],
                             stdin=subprocess.DEVNULL, capture_output=True, text=True, env=dict(os.environ),
                             timeout=300)
    return process.returncode, process.stderr


def _check(out, delay, sig):
    code, err = _sweep_signalled(out, delay, sig)
    assert "FK: cluster starting" in err, err
    assert code in (130, 0), (delay, sig, code, err)
    assert "Traceback" not in err and "Status" not in err, (delay, sig, err)
    if code == 130:
        assert "flexkane: sweep interrupted;" in err
    rows = read_table(out, as_rows=True)            # the table is there and readable
    assert all(r["status"] == "ok" for r in rows)
    return code, len(rows)


@pytest.mark.slow
@pytest.mark.parametrize("sig", ["SIGTERM", "SIGINT"])
def test_a_signal_as_the_cluster_starts_exits_130(tmp_path, sig):
    code, _ = _check(tmp_path / "sweep", 0.0, sig)
    assert code == 130


@pytest.mark.slow
@pytest.mark.parametrize("sig", ["SIGTERM", "SIGINT"])
def test_signals_at_many_moments_of_the_cluster_start_exit_130_and_resume(tmp_path, sig):
    for i, delay in enumerate((0.05, 0.2, 0.5, 1.0, 2.0, 4.0)):
        out = tmp_path / f"sweep{i}"
        code, rows = _check(out, delay, sig)
        resumed = subprocess.run([sys.executable, "-m", "flexkane", *CLI, "--out", str(out)], capture_output=True,
                                 text=True, env=dict(os.environ), timeout=300)
        assert resumed.returncode == 0, resumed.stderr
        assert len(read_table(out, as_rows=True)) == 6
