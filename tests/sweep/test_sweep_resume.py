"""Nothing lost: a sweep killed or interrupted part-way resumes without recomputing finished variants."""

import json
import os
import signal
import subprocess
import sys

import pytest

from flexkane.sweep import SweepInterrupted, SweepSpec, read_table, run_sweep
from flexkane.sweep.store import LOG_NAME

MODEL = "falling-beam-exact"
VARY = "beams.B.EI=20:80:30"
SETTINGS = dict(t_end=1.0, dt_out=0.01, rtol=1e-10, atol=1e-12)
CLI = [MODEL, "--vary", VARY, "--t-end", "1", "--dt-out", "0.01", "--rtol", "1e-10", "--atol", "1e-12",
       "--workers", "1", "--quiet"]
VOLATILE = ("wall_time", "run_time")


def spec():
    return SweepSpec(vary=(VARY,), **SETTINGS)


def stable(rows):
    return [{k: v for k, v in row.items() if k not in VOLATILE} for row in rows]


def log_lines(out):
    path = out / LOG_NAME
    return path.read_bytes().split(b"\n")[:-1] if path.exists() else []


@pytest.fixture(scope="module")
def uninterrupted(tmp_path_factory):
    out = tmp_path_factory.mktemp("uninterrupted")
    outcome = run_sweep(MODEL, spec(), out=out, workers=1)
    assert outcome.computed == 30 and outcome.failed == 0
    return stable(read_table(out, as_rows=True))


# The command line in a subprocess that signals itself right after the third variant reaches the log:
# a real process death (or SIGTERM) at a known point, whatever the load of the machine.
STOPPING_CLI = """
import os, sys
from flexkane.cli import main
from flexkane.sweep.store import SweepStore

append = SweepStore.append
count = 0

def append_then_signal(self, record):
    global count
    append(self, record)
    count += 1
    if count == 3:
        os.kill(os.getpid(), int(sys.argv[1]))

SweepStore.append = append_then_signal
sys.exit(main(sys.argv[2:]))
"""


def start_and_stop_part_way(out, sig):
    """Run the CLI in a subprocess that receives ``sig`` once three variants are in the log."""
    process = subprocess.run([sys.executable, "-c", STOPPING_CLI, str(int(sig)), "sweep", *CLI, "--out", str(out)],
                             stderr=subprocess.PIPE, text=True, env=dict(os.environ), timeout=120)
    return process.returncode, process.stderr


def test_sweep_killed_part_way_resumes_to_the_uninterrupted_table(tmp_path, uninterrupted):
    returncode, _ = start_and_stop_part_way(tmp_path, signal.SIGKILL)
    assert returncode == -signal.SIGKILL
    before = log_lines(tmp_path)
    assert len(before) == 3
    outcome = run_sweep(MODEL, spec(), out=tmp_path, workers=1)
    assert (outcome.reused, outcome.computed) == (len(before), 30 - len(before))
    after = log_lines(tmp_path)
    assert after[:len(before)] == before  # finished variants were not run again
    assert len({json.loads(line)["variant"] for line in after}) == len(after) == 30
    assert stable(read_table(tmp_path, as_rows=True)) == uninterrupted


def test_sigterm_leaves_a_consistent_table_and_exit_code_130(tmp_path, uninterrupted):
    returncode, stderr = start_and_stop_part_way(tmp_path, signal.SIGTERM)
    assert returncode == 130 and "interrupted" in stderr
    done = log_lines(tmp_path)
    rows = stable(read_table(tmp_path, as_rows=True))
    assert len(rows) == len(done) == 3
    assert rows == [row for row in uninterrupted if row["variant"] in {r["variant"] for r in rows}]
    csv_lines = (tmp_path / "sweep.csv").read_text().splitlines()
    assert len(csv_lines) == len(rows) + 1


def test_interruption_in_process_keeps_finished_rows_and_resume_completes(tmp_path, uninterrupted):
    seen = []

    def stop_after_three(record):
        seen.append(record["variant"])
        if len(seen) == 3:
            raise KeyboardInterrupt

    with pytest.raises(SweepInterrupted) as exc:
        run_sweep(MODEL, spec(), out=tmp_path, workers=1, on_result=stop_after_three)
    assert exc.value.outcome.interrupted and len(exc.value.outcome.rows) == 3
    assert stable(read_table(tmp_path, as_rows=True)) == uninterrupted[:3]
    outcome = run_sweep(MODEL, spec(), out=tmp_path, workers=1)
    assert (outcome.reused, outcome.computed) == (3, 27)
    assert stable(outcome.rows) == uninterrupted


def test_a_torn_last_log_line_is_dropped_and_its_variant_computed_again(tmp_path, uninterrupted):
    run_sweep(MODEL, spec(), out=tmp_path, workers=1)
    lines = log_lines(tmp_path)
    (tmp_path / LOG_NAME).write_bytes(b"\n".join(lines[:5]) + b"\n" + lines[5][:40])  # crash mid-write
    outcome = run_sweep(MODEL, spec(), out=tmp_path, workers=1)
    assert (outcome.reused, outcome.computed) == (5, 25)
    assert stable(outcome.rows) == uninterrupted


def test_rerunning_a_finished_sweep_computes_nothing(tmp_path):
    small = SweepSpec(vary=("beams.B.EI=20,40",), t_end=0.1)
    run_sweep(MODEL, small, out=tmp_path, workers=1)
    outcome = run_sweep(MODEL, small, out=tmp_path, workers=1)
    assert (outcome.computed, outcome.reused, outcome.structures) == (0, 2, 0)
    extended = SweepSpec(vary=("beams.B.EI=20,40,60",), t_end=0.1)  # one more value: one more run
    outcome = run_sweep(MODEL, extended, out=tmp_path, workers=1)
    assert (outcome.computed, outcome.reused) == (1, 2)
    assert [r["beams.B.EI"] for r in outcome.rows] == [20.0, 40.0, 60.0]
