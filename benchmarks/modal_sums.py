"""Build stages and one evaluation against the number of modes per plane (issue 26, item 2).

The 3D flexible arm of ``benchmarks/spatial_chains.py`` with one flexible link (``flexible_arm(1, n)``:
waist, shoulder, an aluminium link bending in two planes with ``n`` modes each and twisting with 1
mode, a 2 kg payload at its tip) for n = 2, 4, 8, 16, each in a fresh process with an empty model
cache: ``derive`` (:func:`flexkane.derive` without its cache), ``codegen`` (the module's source),
``compile`` (the model's functions), CPU seconds; ``rhs``: one evaluation of the compiled right-hand
side at the initial state [ns], the median of 9 timings of a compiled loop of calls; ``ops``: the
operation count of the generated right-hand side (the measurement of ``benchmarks/engine_stages.py``); ``sums``: the modal sums printed as loops.
``--model NAME`` measures a built-in model with every beam at n modes per plane and of torsion
(``Model.with_modes``; e.g. ``rotor-blade``, with geometric stiffening), the caps on mode counts
lifted.

Run it with a checkout's sources first on the path to compare two versions:
``PYTHONPATH=<checkout>/src python benchmarks/modal_sums.py --json FILE [n ...]``, and
``--compare BEFORE.json AFTER.json`` for the table with the ratios.
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
from engine_stages import _CHILD as _STAGES  # noqa: E402

# The child of benchmarks/engine_stages.py (derive, source, compile, timed evaluations), its model
# made here, and the modal sums of the source counted.
_MODEL = r"""
import sys
sys.path.insert(0, {here!r})
from spatial_chains import flexible_arm
from flexkane.model import loads_model
import flexkane.model.validate as _validate   # the caps of mode counts lifted: measuring them is the point
_validate.MAX_MODES = _validate.MAX_ELASTIC_COORDINATES = _validate.MAX_STIFFENED_MODES = 1000
model = loads_model(flexible_arm(1, {n})) if {model!r} == "arm" else builtin_model({model!r}).with_modes({n})
"""
_CHILD = _STAGES.replace("model = builtin_model({name!r})", _MODEL).replace(
    '"dimensions": int(getattr(model, "dimensions", 2))',
    '"sums": source.count("modal_sum1(") + source.count("modal_sum2(")')

MODES = (2, 4, 8, 16)


def measure(n: int, model: str = "arm") -> dict:
    """The figures of the arm (or of a built-in model's ``with_modes(n)``) with ``n`` modes per plane,
    in a fresh process (module docstring)."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, FLEXKANE_CACHE_DIR=cache, FLEXKANE_COMPILE_OPERATIONS=str(10 ** 7))
        child = subprocess.run([sys.executable, "-c", _CHILD.format(n=n, cache=cache, here=str(HERE), model=model)],
                               capture_output=True, text=True, env=env, check=False)
    if child.returncode != 0:
        return {"error": (child.stderr.strip().splitlines() or ["failed"])[-1]}
    return json.loads(child.stdout.strip().splitlines()[-1])


def table(rows: dict, before: dict | None = None) -> str:
    """Markdown table of the figures (and the ratios after / before)."""
    head = "| modes per plane | speeds | ops | sums | derive [s] | codegen [s] | compile [s] | rhs [ns] |"
    rule = "|---|---|---|---|---|---|---|---|"
    if before:
        head += " derive | codegen | compile | rhs |"
        rule += "---|---|---|---|"
    lines = [head, rule]
    for n, r in rows.items():
        if "error" in r:
            lines.append(f"| {n} | {r['error']} |")
            continue
        line = (f"| {n} | {r['speeds']} | {r['ops']:,} | {r.get('sums', 0)} | {r['derive']:.2f} | "
                f"{r['codegen']:.2f} | {r['compile']:.2f} | {r['rhs_ns']:.0f} |")
        if before and n in before and "error" not in before[n]:
            b = before[n]
            line += "".join(f" {r[k] / b[k]:.2f} |" for k in ("derive", "codegen", "compile", "rhs_ns"))
        lines.append(line)
    return "\n".join(lines)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("modes", nargs="*", type=int, help=f"modes per plane (default {MODES})")
    parser.add_argument("--json", type=Path, help="also write the figures to this JSON file")
    parser.add_argument("--model", default="arm",
                        help="a built-in model with every beam at n modes per plane (and of torsion) "
                             "instead of the arm (e.g. rotor-blade: geometric stiffening)")
    parser.add_argument("--compare", nargs=2, type=Path, metavar=("BEFORE", "AFTER"))
    args = parser.parse_args(argv)
    if args.compare:
        before, after = (json.loads(path.read_text()) for path in args.compare)
        print(table(after, before))
        return
    rows = {}
    measure(2)   # the integrators are compiled once per installation: a first, discarded case
    for n in args.modes or MODES:
        rows[str(n)] = measure(n, args.model)
        print(n, rows[str(n)], flush=True)
    print(table(rows))
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main()
