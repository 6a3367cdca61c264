"""Same model and options, same bytes: a run does not depend on the machine or its load.

The model is one where ``method = "auto"`` switches between DOP853 and Radau during the run (a
soft shoulder spring and a stiff elbow spring), so the method choice shapes the numbers. It runs
twice through the command line, the second time beside a process that keeps a core busy; the files
must be equal apart from the timing fields, which results.npz keeps in its own array ``timing``.
The first run, in a fresh cache directory, also says that it compiles.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from child_env import child_env
from flexkane.simulation import COMPILING_MESSAGE


STIFF_ELBOW = """
name = "stiff-elbow"
description = "Two links on a soft shoulder spring, joined by a stiff elbow spring"

[bodies.arm]
mass = 1.0
inertia = 0.1
points = { elbow = [0.5, 0] }

[bodies.hand]
mass = 0.5
inertia = 0.02
points = { pin = [-0.3, 0] }

[joints.shoulder]
type = "revolute"
parent = "ground"
child = "arm"
stiffness = 1.0
damping = 0.05

[joints.elbow]
type = "revolute"
parent = "arm"
parent_point = "elbow"
child = "hand"
child_point = "pin"
stiffness = 2e4
damping = 0.01

[initial]
q_shoulder = 0.5

[simulation]
t_end = 20.0
dt_out = 0.05
rtol = 1e-4
atol = 1e-6
"""


def _run(model: Path, out: Path, cache: Path) -> subprocess.CompletedProcess:
    env = child_env(FLEXKANE_CACHE_DIR=str(cache))
    return subprocess.run([sys.executable, "-m", "flexkane", "run", str(model), "--out", str(out), "--no-plots"],
                          capture_output=True, text=True, env=env, timeout=900)


def test_run_beside_a_busy_loop_gives_the_same_files(tmp_path):
    model = tmp_path / "stiff-elbow.toml"
    model.write_text(STIFF_ELBOW)
    cache = tmp_path / "cache"
    first = _run(model, tmp_path / "quiet", cache)
    assert first.returncode == 0, first.stderr
    assert COMPILING_MESSAGE in first.stderr  # a fresh cache: it compiles, and says so
    busy = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        second = _run(model, tmp_path / "loaded", cache)
    finally:
        busy.kill()
        busy.wait()
    assert second.returncode == 0, second.stderr
    assert COMPILING_MESSAGE not in second.stderr  # cached now
    a, b = tmp_path / "quiet", tmp_path / "loaded"
    assert (a / "results.csv").read_bytes() == (b / "results.csv").read_bytes()
    with np.load(a / "results.npz") as x, np.load(b / "results.npz") as y:
        assert sorted(x.files) == sorted(y.files)
        for name in x.files:
            if name != "timing":
                assert x[name].tobytes() == y[name].tobytes(), name
        solver = json.loads(str(x["solver"]))
        assert solver["method_spans"]["dop853"] > 0 and solver["method_spans"]["radau"] > 0
        assert "wall_time" in json.loads(str(x["timing"])) and "wall_time" not in solver
