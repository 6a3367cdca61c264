"""Spatial chains, rigid and flexible: derivation, code generation, compilation and simulation (issue 17).

Four measurements, each case in a fresh Python process with an empty model cache:

* a rigid three-joint arm (waist about the vertical, shoulder and elbow about horizontal axes, full
  inertia tensors, actuator torques that are functions of time, joint dampers, gravity), with 5 s of
  its motion;
* chains of k bodies on spherical joints (a spatial k-pendulum, 3k speeds, 4k coordinates) for
  k = 1, 2, 4, 8: how the costs grow with the length of a spatial chain;
* the built-in ``robot-arm-3d-flexible`` (waist, shoulder and elbow; two aluminium links bending in
  two planes with 2 modes each and twisting with 1 mode; a payload), with 5 s of its motion: the
  target of issue 17 (build under 20 s from an empty cache, 5 s of motion at rtol 1e-8 under 1 s);
* how that arm's costs grow with its flexible links (1, 2, 3 links of 2 modes per plane) and with
  the modes (1, 2, 4 per plane on both links), each link with 1 torsion mode (:func:`flexible_arm`).

For each:

* ``derive``: :func:`flexkane.derive` without its cache;
* ``codegen``: the module's source;
* ``compile``: Numba, the model's own functions (:func:`flexkane.compile_model` minus the code
  generation; the integrators are compiled once per installation and are warmed up first);
* ``simulate``: :func:`flexkane.simulate` of 5 s at rtol 1e-8 (the best of three runs), from the
  model's initial state (``method = "auto"``).

Times are CPU seconds of the child process (user + sys); the simulation's are the CPU seconds and
the wall time of the integration (:func:`flexkane.simulate`'s own ``wall_time``), best of three.

Usage: ``python benchmarks/spatial_chains.py [--quick] [--write]`` (``--quick``: k <= 4, flexible
arms of 1 and 2 links and 1 and 2 modes; ``--write``: replace this section of benchmarks/RESULTS.md).
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
SECTION = "## Spatial chains: rigid and flexible arms, chain length, links and modes (issue 17)"
LINKS = (1, 2, 4, 8)
QUICK_LINKS = (1, 2, 4)
#: The flexible arm's growth: (flexible links, modes per plane), each link with 1 torsion mode.
FLEXIBLE_CASES = ((1, 2), (3, 2), (2, 1), (2, 4))
QUICK_FLEXIBLE_CASES = ((1, 2), (2, 1))
#: Targets of issue 17 for the built-in flexible arm: build [s of CPU], 5 s of motion [s].
BUILD_TARGET = 20.0
MOTION_TARGET = 1.0

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
from flexkane.derivation_cache import model_source
from flexkane.simulation import compile_model

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
runs, cpus = [], []
for _ in range({runs}):
    c0 = cpu()
    runs.append(flexkane.simulate(compiled, t_end=5.0, dt_out=0.01, rtol=1e-8, atol=1e-10))
    cpus.append(cpu() - c0)
best = min(r.solver["wall_time"] for r in runs)
print(json.dumps({{"derive": t1 - t0, "codegen": t2 - t1, "compile": (t3 - t2) - (t2 - t1), "simulate": best,
                  "simulate_cpu": min(cpus),
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


def flexible_arm(links: int, modes: int) -> str:
    """A model file: the built-in flexible arm's column, shoulder hub and links with ``links`` flexible
    links in series (the first the upper arm's 40 x 3 mm tube, 0.7 m; the others the forearm's 30 x 2 mm
    tube, 0.6 m, each on an elbow motor at the previous link's tip), ``modes`` shape functions per
    bending plane and 1 torsion mode on each link, the 2 kg payload at the last tip; the same torques,
    servo springs and dampers at the waist, shoulder and every elbow. It starts undeformed, with the
    shoulder at 0.3 rad and every elbow at -0.6 / (links - 1) rad (the built-in starts at its static
    equilibrium, so its run excites fewer of the stiff modes)."""
    from flexkane.builtin import builtin_text

    text = builtin_text("robot-arm-3d-flexible")
    parameters = text.split("[parameters]")[1].split("\n[")[0]
    lines = ['name = "flexible-arm-3d"', "dimensions = 3", "[parameters]" + parameters.rstrip(),
             "T_load = 1.0", ""]
    lines += ["[bodies.column]", 'mass = "m_col"', "inertia = [0.3, 0.3, 0.5]",
              'points = { bottom = [0, 0, "-h_col/2"], top = [0, 0, "h_col/2"] }',
              "[bodies.shoulder_hub]", 'mass = "m_sh"', 'inertia = ["J_sh/2", "J_sh", "J_sh/2"]',
              'points = { clamp = ["r_sh", 0, 0] }',
              "[bodies.payload]", 'mass = "m_load"', "inertia = [0.004, 0.003, 0.003]", "points = { grip = [-0.05, 0, 0] }",
              "[joints.waist]", 'type = "revolute"', 'parent = "ground"', 'child = "column"',
              "parent_position = [0, 0, 0]", 'child_point = "bottom"', "axis = [0, 0, 1]",
              'torque = "where(t < t1, T_waist*sin(2*pi*t/t1), 0)"', "damping = 2.0",
              "[joints.shoulder]", 'type = "revolute"', 'parent = "column"', 'parent_point = "top"',
              'child = "shoulder_hub"', "axis = [0, -1, 0]", 'stiffness = "k_sh"', "rest = 0.3",
              'damping = "c_sh"', 'torque = "T_sh + dT_sh*where(t < t1, sin(pi*t/t1), 0)"',
              "[gravity]", "g = 9.81", "direction = [0, 0, -1]", "[initial]", "q_shoulder = 0.3"]
    elbow = -0.6 / max(links - 1, 1)
    tail = []
    for i in range(links):
        beam, (L, rho, EI, GJ, rIp) = f"link{i + 1}", (("L1", "rho1", "EI1", "GJ1", "rIp1") if i == 0 else
                                                        ("L2", "rho2", "EI2", "GJ2", "rIp2"))
        tail += [f"[beams.{beam}]", f'L = "{L}"', f'rho = "{rho}"', f'EI_y = "{EI}"', f'EI_z = "{EI}"',
                 f'GJ = "{GJ}"', f'rho_Ip = "{rIp}"', f"n_modes_y = {modes}", f"n_modes_z = {modes}", "n_torsion = 1"]
        hub = "shoulder_hub" if i == 0 else f"elbow{i}_motor"
        if i > 0:
            previous = f"link{i}"
            tail += [f"[bodies.{hub}]", 'mass = "m_el"', 'inertia = ["J_el/2", "J_el", "J_el/2"]',
                     'points = { clamp = ["r_el", 0, 0] }',
                     f"[joints.elbow{i}]", 'type = "revolute"', f'parent = "{previous}"',
                     f'station = "{"L1" if i == 1 else "L2"}"', f'child = "{hub}"', "axis = [0, -1, 0]",
                     'stiffness = "k_el"', f"rest = {elbow}", 'damping = "c_el"', 'torque = "T_el"']
        tail += [f"[joints.{beam}_clamp]", 'type = "weld"', f'parent = "{hub}"', 'parent_point = "clamp"',
                 f'child = "{beam}"']
    tail += ["[joints.grip]", 'type = "weld"', f'parent = "link{links}"',
             f'station = "{"L1" if links == 1 else "L2"}"', 'child = "payload"', 'child_point = "grip"']
    initial = [f"q_elbow{i} = {elbow}" for i in range(1, links)]
    return "\n".join(lines + initial + tail) + "\n"


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


def run(links=LINKS, flexible_cases=FLEXIBLE_CASES) -> dict:
    """The rigid arm, the spherical chains, the built-in flexible arm and its variants, printed as they
    come."""
    from flexkane.builtin import builtin_text

    print("spatial chains: derive + code generation + compilation from an empty cache (CPU seconds of a "
          "fresh process), 5 s of motion")
    arm = measure(ARM)
    print(_line("three-joint arm", arm), flush=True)
    rows = []
    for k in links:
        row = measure(pendulum_chain(k))
        row["links"] = k
        rows.append(row)
        print(_line(f"spherical chain k = {k}", row), flush=True)
    flexible = measure(builtin_text("robot-arm-3d-flexible"))
    print(_line("robot-arm-3d-flexible", flexible), flush=True)
    variants = []
    for n_links, modes in flexible_cases:
        row = measure(flexible_arm(n_links, modes))
        row["links"], row["modes"] = n_links, modes
        variants.append(row)
        print(_line(f"flexible arm, {n_links} links, {modes} modes per plane", row), flush=True)
    return {"arm": arm, "rows": rows, "flexible": flexible, "variants": variants,
            "load_average_end": os.getloadavg()[0], "date": time.strftime("%Y-%m-%d")}


def targets(result: dict) -> list[tuple[str, bool | None, str]]:
    """(target, met, measured) of issue 17's Performance for the built-in flexible arm: CPU times (on a
    shared machine the wall time includes waiting for a core)."""
    r = result.get("flexible") or {}
    if "total" not in r:
        return []
    return [(f"robot-arm-3d-flexible derived, generated and compiled in under {BUILD_TARGET:g} s (CPU)",
             r["total"] < BUILD_TARGET, f"{r['total']:.1f} s"),
            (f"robot-arm-3d-flexible: 5 s of motion at rtol 1e-8 in under {MOTION_TARGET:g} s (CPU: the machine "
             "is shared)", r["simulate_cpu"] < MOTION_TARGET,
             f"{r['simulate_cpu']:.2f} s CPU ({r['simulate']:.2f} s wall)")]


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
    if "flexible" not in result:
        return md
    md += ["### The flexible three-joint arm", "",
           "`robot-arm-3d-flexible` (built in): waist, shoulder and elbow, two aluminium links bending in two "
           "planes (2 modes each) and twisting (1 mode), a 2 kg payload, from its static equilibrium; then "
           "`flexible_arm(links, modes)` of the script: the same arm with 1 to 3 flexible links and 1 to 4 modes "
           "per plane (1 torsion mode per link), starting undeformed. *5 s of motion*: `flexkane.simulate`, "
           "rtol 1e-8, atol 1e-10, `method = \"auto\"`, the integration's wall time and the CPU time of the "
           "whole call, best of three.", ""]
    rows = targets(result)
    if rows:
        md += ["| target of issue 17 | result | measured |", "|---|---|---|"]
        md += [f"| {name} | {'met' if met else 'not met'} | {value} |" for name, met, value in rows]
        md.append("")
    md += ["| model | links | modes per plane | speeds | derive [s] | codegen [s] | compile [s] | total [s] | "
           "operations per evaluation | 5 s of motion: wall [ms] | CPU [ms] | method, evaluations |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    cases = [("robot-arm-3d-flexible", dict(result["flexible"], links=2, modes=2))]
    cases += [("flexible_arm", r) for r in result.get("variants", [])]
    for name, r in cases:
        if "error" in r:
            md.append(f"| {name} | {r.get('links', '-')} | {r.get('modes', '-')} | - | - | - | - | "
                      f"failed: {r['error']} | - | - | - | - |")
            continue
        md.append(f"| {name} | {r['links']} | {r['modes']} | {r['speeds']} | {r['derive']:.2f} | "
                  f"{r['codegen']:.2f} | {r['compile']:.2f} | {r['total']:.2f} | {r['operations']} | "
                  f"{r['simulate'] * 1e3:.0f} | {r['simulate_cpu'] * 1e3:.0f} | {r['method']}, {r['nfev']} |")
    md.append("")
    return md


def main() -> dict:
    sys.path.insert(0, str(HERE))
    import _common

    quick = "--quick" in sys.argv
    return _common.section_main(lambda: run(QUICK_LINKS if quick else LINKS,
                                            QUICK_FLEXIBLE_CASES if quick else FLEXIBLE_CASES), markdown, SECTION)


if __name__ == "__main__":
    main()
