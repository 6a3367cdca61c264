"""A sweep interrupted while its Dask cluster starts (or closes) exits 130 with a consistent table and
no traceback (Dask's own errors, such as ``AssertionError: Status.init``, never reach the user).

The signal is sent by the sweep process itself, from a timer started when ``LocalCluster`` begins
to start, after each of several delays: whatever phase of the start (or of the sweep after it) the
signal meets, the outcome is exit 130 (or 0 if the sweep had finished). The moment the delays met
only by chance, the broadcast of the equations to the workers, is also hit on purpose: the
scheduler's replicate signals the sweep and goes on once the signal was handled.
"""

import asyncio
import gc
import logging
import os
import signal
import subprocess
import sys

import pytest

from flexkane.interruption import StopRequest
from flexkane.sweep import read_table
from flexkane.sweep.execute import _unretrieved_cluster_errors_dropped, run_on_dask

MODEL = "falling-beam-exact"
CLI = ["sweep", MODEL, "--vary", "beams.B.EI=20:80:6", "--t-end", "0.2", "--dt-out", "0.01", "--workers", "2",
       "--quiet"]

SIGNAL_AT_CLUSTER_START = """
import os, signal, sys, threading
import distributed
from flexkane.cli import main

delay, sig = float(sys.argv[1]), getattr(signal, sys.argv[2])
start = distributed.LocalCluster.__init__
timers = []

def start_then_signal(self, *args, **kwargs):
    print("FK: cluster starting", file=sys.stderr, flush=True)
    timers.append(threading.Timer(delay, os.kill, (os.getpid(), sig)))
    timers[-1].start()
    start(self, *args, **kwargs)

distributed.LocalCluster.__init__ = start_then_signal
code = main(sys.argv[3:])
for timer in timers:   # a sweep done before the delay: no signal into the interpreter's exit
    timer.cancel()
sys.exit(code)
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


SIGNAL_DURING_BROADCAST = """
import asyncio, os, signal, sys
from distributed.scheduler import Scheduler
from flexkane import interruption
from flexkane.cli import main

sig = getattr(signal, sys.argv[1])
replicate = Scheduler.replicate

async def signal_then_replicate(self, *args, **kwargs):
    # the broadcast of the equations is under way: signal the sweep, go on once the cluster began to
    # close (the signal cut the broadcast) or the sweep holds the signal (it waits for the broadcast)
    print("FK: broadcasting", file=sys.stderr, flush=True)
    workers = len(self.workers)
    os.kill(os.getpid(), sig)
    while len(self.workers) == workers and self.status.name == "running" \\
            and not (interruption._active and interruption._active[-1].requested):
        await asyncio.sleep(0.01)
    return await replicate(self, *args, **kwargs)

Scheduler.replicate = signal_then_replicate
sys.exit(main(sys.argv[2:]))
"""


@pytest.mark.slow
@pytest.mark.parametrize("sig", ["SIGTERM", "SIGINT"])
def test_a_signal_during_the_broadcast_of_the_equations_exits_130_quietly(tmp_path, sig):
    """Cut, the broadcast went on in the scheduler as the cluster closed and failed: asyncio printed
    "Task exception was never retrieved" and Dask's traceback."""
    out = tmp_path / "sweep"
    process = subprocess.run([sys.executable, "-c", SIGNAL_DURING_BROADCAST, sig, *CLI, "--out", str(out)],
                             stdin=subprocess.DEVNULL, capture_output=True, text=True, env=dict(os.environ),
                             timeout=300)
    err = process.stderr
    assert "FK: broadcasting" in err and process.returncode == 130, err
    assert "Traceback" not in err and "never retrieved" not in err, err
    assert err.splitlines()[-1].startswith("flexkane: sweep interrupted;")
    assert read_table(out, as_rows=True) == []


class _BroadcastSignalled:
    """A client whose broadcast receives a stop signal while it runs (the fact of the slow test above)."""

    def __init__(self):
        self.broadcast_done = False
        self.submitted = []

    def nthreads(self):
        return {"worker": 1}

    def scatter(self, data, broadcast, hash):
        os.kill(os.getpid(), signal.SIGTERM)
        self.broadcast_done = True
        return "scattered"

    def submit(self, *args, **kwargs):   # pragma: no cover - the signal stops the sweep before
        self.submitted.append(args)
        raise AssertionError("submitted after the signal")

    def cancel(self, futures):
        pass


def test_a_signal_during_the_broadcast_acts_once_it_is_done(monkeypatch):
    import distributed

    monkeypatch.setattr(distributed, "as_completed", lambda **kwargs: [])   # no cluster here
    client = _BroadcastSignalled()
    with StopRequest() as stop, pytest.raises(KeyboardInterrupt):
        run_on_dask(client, [(object(), "task")], on_record=None, on_lost=None)
    assert stop.requested and client.broadcast_done and not client.submitted


async def _fails():
    raise KeyError("tcp://127.0.0.1:1")


def _unretrieved_failure() -> None:
    """A task named like Dask's fails and is collected unobserved: asyncio reports it on the logger."""
    loop = asyncio.new_event_loop()
    try:
        task = loop.create_task(_fails(), name="distributed.core._handle_comm")
        loop.run_until_complete(asyncio.sleep(0))
        assert task.done()
        del task
        gc.collect()
    finally:
        loop.close()


def test_reports_of_the_closing_clusters_failed_requests_are_dropped_only_after_an_interruption(caplog):
    with caplog.at_level(logging.ERROR, logger="asyncio"):
        with _unretrieved_cluster_errors_dropped(True):
            _unretrieved_failure()
        assert not [r for r in caplog.records if "never retrieved" in r.getMessage()]
        with _unretrieved_cluster_errors_dropped(False):
            _unretrieved_failure()
        assert [r for r in caplog.records if "never retrieved" in r.getMessage()]
