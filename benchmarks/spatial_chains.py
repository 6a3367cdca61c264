"""Rigid spatial chains: derivation, code generation, compilation and simulation (issue 17).

Two measurements, each case in a fresh Python process with an empty model cache:

* a rigid three-joint arm (waist about the vertical, shoulder and elbow about horizontal axes, full
  inertia tensors, actuator torques that are functions of time, joint dampers, gravity), with 5 s of
  its motion;
* chains of k bodies on spherical joints (a spatial k-pendulum, 3k speeds, 4k coordinates) for
  k = 1, 2, 4, 8: how the costs grow with the length of a spatial chain.

For each:

* ``derive``: :func:`flexkane.derive` without its cache;
* ``codegen``: the module's source;
* ``compile``: Numba, the model's own functions (:func:`flexkane.compile_model` minus the code
  generation; the integrators are compiled once per installation and are warmed up first);
* ``simulate``: :func:`flexkane.simulate` of 5 s at rtol 1e-8 (the best of three runs).

Times are CPU seconds of the child process (user + sys), the simulation's the wall time reported by
the integrator.

Usage: ``python benchmarks/spatial_chains.py [--quick] [--write]`` (``--quick``: k <= 4; ``--write``:
replace this section of benchmarks/RESULTS.md).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SECTION = "## Spatial chains: a rigid arm and chain length (issue 17)"
LINKS = (1, 2, 4, 8)
QUICK_LINKS = (1, 2, 4)

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
model = loads_model({model!r})
t0 = cpu()
eom = flexkane.derive(model, cache=False)
t1 = cpu()
source = model_source(eom)
t2 = cpu()
compiled = compile_model(eom, cache_dir={cache!r})
t3 = cpu()
w3 = time.perf_counter()
runs = [flexkane.simulate(compiled, t_end=5.0, dt_out=0.01, rtol=1e-8, atol=1e-10) for _ in range({runs})]
best = min(r.solver["wall_time"] for r in runs)
print(json.dumps({{"derive": t1 - t0, "codegen": t2 - t1, "compile": (t3 - t2) - (t2 - t1), "simulate": best,
                  "nfev": runs[0].solver["nfev"], "method": runs[0].solver["method"],
                  "energy_balance": float(abs(runs[0].outputs["energy_balance"]).max()),
                  "operations": int(source.split("RHS_OPERATIONS = ")[1].split()[0]),
                  "intermediates": len(eom.intermediates), "wall": w3 - w0, "speeds": len(eom.u)}}))
"""


def pendulum_chain(k: int) -> str:
    """A model file: k bodies hanging from each other on spherical joints, full inertia tensors."""
    lines = ["name = \"spherical-chain\"", "dimensions = 3", "[gravity]", "g = 9.81", "direction = [0, 0, -1]"]
    for i in range(k):
        parent = "ground" if i == 0 else f"b{i - 1}"
        lines += [f"[bodies.b{i}]", "mass = 1.0", "inertia = [[0.1, 0.01, 0], [0.01, 0.2, 0], [0, 0, 0.15]]",
                  "points = { top = [0, 0, 0.5], bottom = [0.05, 0, -0.5] }",
                  f"[joints.j{i}]", "type = \"spherical\"", f"parent = \"{parent}\"", f"child = \"b{i}\"",
                  "child_point = \"top\""] + (["parent_point = \"bottom\""] if i else [])
    lines += ["[initial]", "u_j0_wx = 1.0"]
    return "\n".join(lines) + "\n"


def measure(model: str, runs: int = 3) -> dict:
    """Times of one model in a fresh process with an empty model cache (module docstring)."""
    with tempfile.TemporaryDirectory(prefix="flexkane-spatial-") as cache:
        # the code-size budget of untrusted model files is lifted: measuring long chains is the point
        env = dict(os.environ, FLEXKANE_CACHE_DIR=cache, FLEXKANE_COMPILE_OPERATIONS=str(10 ** 7))
        done = subprocess.run([sys.executable, "-c", _CHILD.format(model=model, cache=cache, runs=runs)],
                              capture_output=True, text=True, env=env, timeout=1800)
    if done.returncode != 0:
        return {"error": done.stderr.strip().splitlines()[-1] if done.stderr else "failed"}
    row = json.loads(done.stdout.strip().splitlines()[-1])
    row["total"] = row["derive"] + row["codegen"] + row["compile"]
    return row


def _line(name: str, r: dict) -> str:
    if "error" in r:
        return f"  {name}: {r['error']}"
    return (f"  {name} ({r['speeds']} speeds, {r['intermediates']} intermediates, {r['operations']} operations per "
            f"evaluation): derive {r['derive']:.2f} s, codegen {r['codegen']:.2f} s, compile {r['compile']:.2f} s, "
            f"total {r['total']:.2f} s CPU ({r['wall']:.2f} s wall); 5 s of motion at rtol 1e-8 in "
            f"{r['simulate'] * 1e3:.1f} ms ({r['method']}, {r['nfev']} evaluations)")


def run(links=LINKS) -> dict:
    """The arm, then the spherical chains, printed as they come."""
    print("rigid spatial chains: derive + code generation + compilation from an empty cache (CPU seconds of a "
          "fresh process), 5 s of motion")
    arm = measure(ARM)
    print(_line("three-joint arm", arm), flush=True)
    rows = []
    for k in links:
        row = measure(pendulum_chain(k))
        row["links"] = k
        rows.append(row)
        print(_line(f"spherical chain k = {k}", row), flush=True)
    return {"arm": arm, "rows": rows, "load_average_end": os.getloadavg()[0], "date": time.strftime("%Y-%m-%d")}


def markdown(result: dict, machine: dict) -> list[str]:
    """The RESULTS.md section of :func:`run`'s result."""
    md = [SECTION, "",
          "`benchmarks/spatial_chains.py`: each case in a fresh process with an empty cache; CPU seconds (user + "
          "sys) of that process. *derive*: `flexkane.derive(model, cache=False)`; *codegen*: the module source; "
          "*compile*: Numba, the model's functions; *5 s*: `flexkane.simulate` of 5 s at rtol 1e-8 (wall time of "
          "the integration, best of three runs).", "",
          f"Measured on {result['date']}: {machine.get('Model name', '?')}, {machine.get('CPU(s)', '?')} CPUs, "
          f"load average {machine.get('load_average', float('nan')):.1f} at the start, "
          f"{result.get('load_average_end', float('nan')):.1f} at the end (the machine is shared).", "",
          "| model | speeds | intermediates | derive [s] | codegen [s] | compile [s] | total [s] | operations per "
          "evaluation | 5 s of motion [ms] |", "|---|---|---|---|---|---|---|---|---|"]
    cases = [("rigid three-joint arm", result["arm"])] + [(f"spherical chain, k = {r['links']}", r)
                                                          for r in result["rows"]]
    for name, r in cases:
        if "error" in r:
            md.append(f"| {name} | - | - | - | - | - | failed: {r['error']} | - | - |")
            continue
        md.append(f"| {name} | {r['speeds']} | {r['intermediates']} | {r['derive']:.2f} | {r['codegen']:.2f} | "
                  f"{r['compile']:.2f} | {r['total']:.2f} | {r['operations']} | {r['simulate'] * 1e3:.1f} |")
    md += ["", "The mass matrix of a chain of k spherical joints has (3k)(3k + 1)/2 entries, each a bounded number "
           "of operations (composite bodies): the operations per evaluation and the derivation grow with its "
           "size, about as k^2, not geometrically.", ""]
    return md


def main() -> dict:
    sys.path.insert(0, str(HERE))
    import _common

    return _common.section_main(lambda: run(QUICK_LINKS if "--quick" in sys.argv else LINKS), markdown, SECTION)


if __name__ == "__main__":
    main()
