"""Spatial chains with the mass matrix summed by the compiled loop, against M written out.

For each model, in a fresh Python process with an empty model cache (the integrators compiled once
beforehand), the build stages and one right-hand-side evaluation of :mod:`engine_stages` (derive,
code generation, compile [CPU s], rhs [ns] at the initial state): rigid spatial chains of k bodies on
revolute joints (axes x, y, z in turn; issue 27's case), the flexible arms of
:func:`spatial_chains.flexible_arm` and the spatial built-in models of 9 speeds and more. Each case
runs with a checkout's source first on the path (``--checkout DIR``, e.g. the main checkout before the
change), alternating between the checkouts run by run; with ``--loop-from N`` the checkout named
``loop`` derives and generates with the threshold of the loop lowered to N speeds (so that shorter
chains take it too: how the threshold is chosen).

Usage: ``python benchmarks/spatial_mass_loop.py --checkout before=/path/src --checkout loop=/path/src
[--loop-from 2] [--runs 2] [--json FILE] [CASE ...]`` with cases ``revolute-<k>``,
``spherical-<k>`` (:func:`spatial_chains.pendulum_chain`), ``arm-<links>x<modes>`` or built-in model
names.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import engine_stages  # noqa: E402

DEFAULT_CASES = ("revolute-3", "revolute-6", "revolute-12", "arm-1x2", "arm-2x2", "robot-arm-3d-flexible",
                 "spacecraft-flexible-slew")

# the loop's threshold lowered in the child (before anything is derived)
_LOWER = """
import flexkane.kane.equations as _equations, flexkane.numerics.codegen as _codegen
import flexkane.kane.inertia as _inertia
_equations.LAZY_MASS_MIN_SPEEDS = _inertia.LAZY_MASS_MIN_SPEEDS = _codegen.MASS_LOOP_MIN_SPEEDS = {speeds}
_inertia.SPATIAL_LAZY_MASS_MIN_SPEEDS = _codegen.SPATIAL_MASS_LOOP_MIN_SPEEDS = {speeds}
"""


def revolute_chain(k: int) -> str:
    """A model file: k bodies hanging from each other on revolute joints about x, y, z in turn, full
    inertia tensors, offset points (issue 27's rigid spatial chain)."""
    lines = ['name = "revolute-chain"', "dimensions = 3", "[gravity]", "g = 9.81", "direction = [0, 0, -1]"]
    axes = ("[1, 0, 0]", "[0, 1, 0]", "[0, 0, 1]")
    for i in range(k):
        parent = "ground" if i == 0 else f"b{i - 1}"
        lines += [f"[bodies.b{i}]", "mass = 1.0", "inertia = [[0.1, 0.01, 0], [0.01, 0.2, 0], [0, 0, 0.15]]",
                  "points = { top = [0, 0, 0.25], bottom = [0.02, 0, -0.25] }",
                  f"[joints.j{i}]", 'type = "revolute"', f'parent = "{parent}"', f'child = "b{i}"',
                  'child_point = "top"', f"axis = {axes[i % 3]}"] + (['parent_point = "bottom"'] if i else [])
    lines += ["[initial]", "q_j0 = 0.5"]
    return "\n".join(lines) + "\n"


def model_text(case: str) -> str | None:
    """The model file of a case; None for a built-in model's name."""
    if case.startswith("revolute-"):
        return revolute_chain(int(case.split("-")[1]))
    if case.startswith("spherical-"):
        from spatial_chains import pendulum_chain

        return pendulum_chain(int(case.split("-")[1]))
    if case.startswith("arm-"):
        from spatial_chains import flexible_arm

        links, modes = case.split("-")[1].split("x")
        return flexible_arm(int(links), int(modes))
    return None


def measure(case: str, src: str, lower: int | None = None) -> dict:
    """Figures of one case with the source ``src`` first on the path (module docstring)."""
    text = model_text(case)
    child = engine_stages._CHILD.replace("model = builtin_model({name!r})",
                                         "model = builtin_model({name!r}) if {text!r} is None "
                                         "else flexkane.loads_model({text!r})")
    if lower is not None:
        child = child.replace("import sympy, flexkane.kane", _LOWER.format(speeds=lower) + "import sympy, flexkane.kane")
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, FLEXKANE_CACHE_DIR=cache, PYTHONPATH=src, FLEXKANE_COMPILE_OPERATIONS=str(10 ** 7))
        done = subprocess.run([sys.executable, "-c", child.format(name=case, text=text, cache=cache)],
                              capture_output=True, text=True, env=env, check=False)
    if done.returncode != 0:
        raise RuntimeError(f"{case}: {done.stderr.strip().splitlines()[-1:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", default=list(DEFAULT_CASES))
    parser.add_argument("--checkout", action="append", required=True, metavar="LABEL=SRC")
    parser.add_argument("--loop-from", type=int, help="threshold of the loop in the checkout labelled loop")
    parser.add_argument("--runs", type=int, default=2)
    parser.add_argument("--json", type=Path)
    args = parser.parse_args(argv)
    checkouts = dict(item.split("=", 1) for item in args.checkout)
    measure("revolute-3", next(iter(checkouts.values())))     # the integrators compiled once
    rows: dict = {}
    for run in range(args.runs):
        for case in args.cases:
            for label, src in checkouts.items():
                lower = args.loop_from if label == "loop" else None
                r = measure(case, src, lower)
                rows.setdefault(case, {}).setdefault(label, []).append(r)
                print(f"run {run} {case:26s} {label:8s} speeds {r['speeds']:3d} ops {r['ops']:6d} derive "
                      f"{r['derive']:6.2f} codegen {r['codegen']:6.2f} compile {r['compile']:7.2f} rhs "
                      f"{r['rhs_ns']:8.0f} ns  load {os.getloadavg()[0]:.2f}", flush=True)
    best = {case: {label: {k: min(r[k] for r in runs) for k in ("derive", "codegen", "compile", "rhs_ns")}
                   | {"speeds": runs[0]["speeds"], "ops": runs[0]["ops"]}
                   for label, runs in by_label.items()} for case, by_label in rows.items()}
    print(json.dumps(best, indent=1))
    if args.json:
        args.json.write_text(json.dumps({"best": best, "runs": rows}, indent=1, sort_keys=True) + "\n")
    return best


if __name__ == "__main__":
    main()
