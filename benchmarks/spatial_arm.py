"""A rigid spatial three-joint arm: derivation, code generation, compilation and 5 s of motion (issue 17).

The arm (waist about the vertical, shoulder and elbow about horizontal axes, full inertia tensors,
actuator torques that are functions of time, joint dampers, gravity) runs in a fresh Python process
with an empty model cache:

* ``derive``: :func:`flexkane.derive` without its cache;
* ``codegen``: the module's source;
* ``compile``: Numba, the model's own functions (:func:`flexkane.compile_model` minus the code
  generation; the integrators are compiled once per installation and are warmed up first);
* ``simulate``: :func:`flexkane.simulate` of 5 s at rtol 1e-8 (the best of three runs).

Times are CPU seconds of the child process (user + sys), the simulation's the wall time reported by
the integrator.

Usage: ``python benchmarks/spatial_arm.py``.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile

ARM = """
name = "spatial-arm"
dimensions = 3

[bodies.base]
mass = 4.0
inertia = [0.05, 0.05, 0.03]
points = { bottom = [0, 0, -0.1], top = [0, 0, 0.1] }

[bodies.upper]
mass = 2.0
inertia = [[0.06, 0.001, 0.0], [0.001, 0.06, 0.002], [0.0, 0.002, 0.004]]
points = { a = [0, 0, -0.25], b = [0.01, 0, 0.25] }

[bodies.fore]
mass = 1.0
inertia = [0.02, 0.02, 0.002]
points = { a = [0, 0, -0.2] }

[joints.waist]
type = "revolute"
parent = "ground"
child = "base"
parent_position = [0, 0, 0.1]
child_point = "bottom"
axis = [0, 0, 1]
torque = "2*sin(t)"
damping = 0.5

[joints.shoulder]
type = "revolute"
parent = "base"
child = "upper"
parent_point = "top"
child_point = "a"
axis = [0, 1, 0]
torque = "20*cos(t)"
damping = 0.5

[joints.elbow]
type = "revolute"
parent = "upper"
child = "fore"
parent_point = "b"
child_point = "a"
axis = [0, 1, 0]
torque = "5*sin(2*t)"
damping = 0.2

[gravity]
g = 9.81
direction = [0, 0, -1]

[initial]
q_shoulder = 0.3
q_elbow = 0.5
"""

_CHILD = r"""
import json, resource, time
import flexkane
from flexkane.model import loads_model
from flexkane.simulation import compile_model, model_source

def cpu():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime

w0 = time.perf_counter()
model = loads_model({arm!r})
t0 = cpu()
eom = flexkane.derive(model, cache=False)
t1 = cpu()
source = model_source(eom)
t2 = cpu()
compiled = compile_model(eom, cache_dir={cache!r})
t3 = cpu()
w3 = time.perf_counter()
runs = [flexkane.simulate(compiled, t_end=5.0, dt_out=0.01, rtol=1e-8, atol=1e-10) for _ in range(3)]
best = min(r.solver["wall_time"] for r in runs)
print(json.dumps({{"derive": t1 - t0, "codegen": t2 - t1, "compile": (t3 - t2) - (t2 - t1), "simulate": best,
                  "nfev": runs[0].solver["nfev"], "method": runs[0].solver["method"],
                  "energy_balance": float(abs(runs[0].outputs["energy_balance"]).max()),
                  "operations": int(source.split("RHS_OPERATIONS = ")[1].split()[0]),
                  "intermediates": len(eom.intermediates), "wall": w3 - w0}}))
"""


def measure() -> dict:
    """Times of the arm in a fresh process with an empty model cache (module docstring)."""
    with tempfile.TemporaryDirectory(prefix="flexkane-spatial-arm-") as cache:
        env = dict(os.environ, FLEXKANE_CACHE_DIR=cache)
        done = subprocess.run([sys.executable, "-c", _CHILD.format(arm=ARM, cache=cache)], capture_output=True,
                              text=True, env=env, timeout=1800)
    if done.returncode != 0:
        raise RuntimeError(done.stderr)
    row = json.loads(done.stdout.strip().splitlines()[-1])
    row["total"] = row["derive"] + row["codegen"] + row["compile"]
    return row


if __name__ == "__main__":
    r = measure()
    print(f"spatial three-joint arm ({r['intermediates']} intermediates, {r['operations']} operations per "
          f"evaluation): derive {r['derive']:.2f} s, codegen {r['codegen']:.2f} s, compile {r['compile']:.2f} s, "
          f"total {r['total']:.2f} s (CPU), {r['wall']:.2f} s wall; 5 s of motion at rtol 1e-8: {r['simulate'] * 1e3:.1f} ms "
          f"({r['method']}, {r['nfev']} evaluations, energy balance {r['energy_balance']:.2g} J)")
