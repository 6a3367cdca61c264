"""Every built-in model's build stages and one right-hand-side evaluation (issue 26).

For each built-in model, in a fresh Python process with an empty model cache (the integrators
compiled once beforehand):

* ``derive``: :func:`flexkane.derive` without its cache [CPU s];
* ``codegen``: the module's source [CPU s];
* ``compile``: the model's own functions (right-hand side and outputs) [CPU s];
* ``rhs``: one evaluation of the compiled right-hand side at the model's initial state [ns]: the
  median of 9 timings of a compiled loop of many calls (no Python dispatch inside), CPU time;
* ``ops``: the operation count of the right-hand side's generated code.

These are the figures that the one-engine issue compares before and after: no planar model may
derive, generate or compile more slowly, and no evaluation may be more than 10 % slower.

Usage: ``python benchmarks/engine_stages.py [--label LABEL] [--json FILE] [MODEL ...]``; with
``--json`` the figures are also written as JSON (to compare two commits' figures, run the script in
each checkout and give both files to ``--compare BEFORE.json AFTER.json``).
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

_CHILD = r"""
import json, resource, time
import numpy as np
import flexkane
from flexkane.builtin import builtin_model
from flexkane.derivation_cache import model_source
from flexkane.simulation import compile_model

def cpu():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime

model = builtin_model({name!r})
import sympy, flexkane.kane, flexkane.numerics.codegen   # imports are not a stage's cost
t0 = cpu()
eom = flexkane.derive(model, cache=False)
t1 = cpu()
source = model_source(eom)
t2 = cpu()
compiled = compile_model(eom, cache_dir={cache!r})
t3 = cpu()
p, y = eom.parameter_vector(), eom.initial_state()
from numba import njit
from flexkane.numerics.constant_block import prepared_parameters

@njit(error_model="numpy")
def many(f, t, y, p, dy, calls):
    acc = 0.0
    for i in range(calls):
        f(t + 1e-9 * i, y, p, dy)
        acc += dy[dy.shape[0] - 1]
    return acc

prepared, dy = prepared_parameters(compiled.module, p), np.empty(len(y))
many(compiled.module.rhs, 0.0, y, prepared, dy, 1)
calls = 100
while True:
    tic = time.process_time()
    many(compiled.module.rhs, 0.0, y, prepared, dy, calls)
    if time.process_time() - tic > 0.02:
        break
    calls *= 4
times = []
for _ in range(9):
    tic = time.process_time()
    many(compiled.module.rhs, 0.0, y, prepared, dy, calls)
    times.append((time.process_time() - tic) / calls)
best = sorted(times)[len(times) // 2]
print(json.dumps({{"derive": t1 - t0, "codegen": t2 - t1, "compile": (t3 - t2) - (t2 - t1),
                  "rhs_ns": best * 1e9, "speeds": len(eom.u),
                  "ops": int(source.split("RHS_OPERATIONS = ")[1].split()[0]),
                  "dimensions": int(getattr(model, "dimensions", 2))}}))
"""


def builtin_names() -> list[str]:
    """Names of the built-in models, in alphabetical order."""
    from flexkane.builtin import builtin_names as names

    return sorted(names())


def measure(name: str) -> dict:
    """The stage figures of one built-in model, in a fresh process with an empty model cache."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, FLEXKANE_CACHE_DIR=cache)
        child = subprocess.run([sys.executable, "-c", _CHILD.format(name=name, cache=cache)],
                               capture_output=True, text=True, env=env, check=False)
    if child.returncode != 0:
        raise RuntimeError(f"{name}: {child.stderr.strip().splitlines()[-1:]}")
    return json.loads(child.stdout.strip().splitlines()[-1])


def table(rows: dict[str, dict], before: dict[str, dict] | None = None) -> str:
    """Markdown table of the figures (with the ratios after/before when ``before`` is given)."""
    head = "| model | dim | speeds | ops | derive [s] | codegen [s] | compile [s] | rhs [ns] |"
    rule = "|---|---|---|---|---|---|---|---|"
    if before:
        head += " derive | codegen | compile | rhs |"
        rule += "---|---|---|---|"
    lines = [head, rule]
    for name, r in rows.items():
        line = (f"| {name} | {r['dimensions']} | {r['speeds']} | {r['ops']:,} | {r['derive']:.2f} | "
                f"{r['codegen']:.2f} | {r['compile']:.2f} | {r['rhs_ns']:.0f} |")
        if before and name in before:
            b = before[name]
            line += "".join(f" {r[k] / b[k]:.2f} |" for k in ("derive", "codegen", "compile", "rhs_ns"))
        lines.append(line)
    return "\n".join(lines)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("models", nargs="*", help="built-in models (default: all)")
    parser.add_argument("--json", type=Path, help="also write the figures to this JSON file")
    parser.add_argument("--compare", nargs=2, type=Path, metavar=("BEFORE", "AFTER"),
                        help="print the table of AFTER with its ratios to BEFORE and exit")
    parser.add_argument("--table", type=Path, metavar="FIGURES",
                        help="print the table of figures written by --json and exit")
    args = parser.parse_args(argv)
    if args.compare:
        before, after = (json.loads(path.read_text()) for path in args.compare)
        print(table(after, before))
        return
    if args.table:
        print(table(json.loads(args.table.read_text())))
        return
    sys.path.insert(0, str(HERE))
    from _common import machine_info, machine_sentence

    names = args.models or builtin_names()
    # the integrators are compiled once per installation: a first, discarded case compiles them
    measure(names[0])
    rows = {}
    for name in names:
        rows[name] = measure(name)
        r = rows[name]
        print(f"{name:28s} derive {r['derive']:6.2f}  codegen {r['codegen']:6.2f}  "
              f"compile {r['compile']:7.2f}  rhs {r['rhs_ns']:9.0f} ns  ops {r['ops']}", flush=True)
    machine = machine_info()
    print()
    print(f"load average {machine['load_average']:.2f};" + machine_sentence(machine))
    print(table(rows))
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main()
