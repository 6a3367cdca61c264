"""How derivation, code generation and compilation grow with the length of a chain (issue 16).

``chain_model(k)`` (benchmarks/scaling.py: k flexible links on hubs, 2 modes each) for k = 1, 2, 4,
8, 12, 20. Each k runs in a fresh Python process with an empty model cache, so nothing is shared:

* ``derive``: :func:`flexkane.derive` without its cache (kinematics, F*_r, F_r, the equations);
* ``codegen``: the module's source (common subexpressions, printing);
* ``compile``: Numba, the model's own functions (what :func:`flexkane.compile_model` does after code
  generation), of which ``rhs`` (the right-hand side) and ``outputs`` separately;
* ``operations``: floating-point operations of one right-hand-side evaluation, counted in the
  generated source (``RHS_OPERATIONS``).

Times are CPU seconds of the child process (user + sys), which a loaded machine inflates less than
wall time. The child lifts the code-size budget of untrusted models (``FLEXKANE_COMPILE_OPERATIONS``);
with the mass matrix summed by the loop of :mod:`flexkane.numerics.mass_assembly`, 20 links need
about 7,900 operations outside term tables, under the default 20,000 (with M written out, 38,000;
``compiled operations``: :func:`flexkane.numerics.code_budget.compiled_operations` of the right-hand
side and ``system_rhs``). The ratio of consecutive rows, divided by the ratio of their link counts, shows the growth
per link: 1 for linear growth.

Usage: ``python benchmarks/chain_scaling.py [--quick] [--write] [--compare]`` (``--quick``: k <= 8;
``--write``: replace this section of benchmarks/RESULTS.md; ``--compare``: k = 8 and 20 with the
symbolic mass matrix formed by the derivation and formed when read, alternately). ``make bench`` runs it through ``run_all.py``.
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
LINKS = (1, 2, 4, 8, 12, 20)
QUICK_LINKS = (1, 2, 4, 8)
SECTION = "## Chain length: derivation, code generation, compilation (issue 16)"

_CHILD = r"""
import json, resource, sys, time
sys.path.insert(0, {here!r})
from scaling import chain_model
import numpy as np
import flexkane
from flexkane._version import __version__
from flexkane.derivation_cache import model_source
from flexkane.numerics.code_budget import compiled_operations
from flexkane.numerics.integrate import compile_integrators
from flexkane.numerics.jit_module import build_module, structure_key

def cpu():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime

model = chain_model({k})
t0 = cpu()
if {lazy_mass!r}:
    eom = flexkane.derive(model, cache=False)
else:   # every entry of the symbolic M formed by the derivation (the form before the lazy one)
    from flexkane.kane.equations import derive as derive_afresh
    eom = derive_afresh(model, lazy_mass=False)
if not {mass_loop!r}:
    eom.compact.mass_assembly = None   # M written out entry by entry (the form before the loop)
t1 = cpu()
source = model_source(eom)
t2 = cpu()
# what compile_model does after code generation, function by function
module = build_module(source, structure_key(__version__, source), {cache!r})
n, p = module.NQ + module.NU, eom.parameter_vector()
t3 = cpu()
module.rhs(0.0, np.zeros(n), p, np.empty(n))
t4 = cpu()
module.outputs(np.zeros(0), np.zeros((0, n)), p)
t5 = cpu()
compile_integrators(module)        # system_rhs, spin rates; the integrators load from their cache
t6 = cpu()
rhs_source = source.split("# ---- generated outputs")[0]   # rhs and system_rhs
print(json.dumps({{"derive": t1 - t0, "codegen": t2 - t1, "compile_rhs": t4 - t3, "compile_outputs": t5 - t4,
                  "compile": t6 - t2, "operations": module.RHS_OPERATIONS,
                  "compiled_operations": compiled_operations(rhs_source.splitlines()),
                  "speeds": len(eom.u), "intermediates": len(eom.intermediates)}}))
"""


def measure(k: int, timeout: float = 1800.0, mass_loop: bool = True, lazy_mass: bool = True) -> dict:
    """Times of one chain length in a fresh process with an empty cache (module docstring);
    ``mass_loop=False``: the mass matrix written out entry by entry, as before the compiled loop
    of :mod:`flexkane.numerics.mass_assembly`; ``lazy_mass=False``: every entry of the symbolic
    mass matrix formed by the derivation, as before they were formed when read (both for
    comparisons in the same period)."""
    with tempfile.TemporaryDirectory(prefix="flexkane-chain-") as cache:
        # the code-size budget that protects a run from untrusted model files (20,000 operations
        # outside term tables) is lifted: measuring what long chains cost is the point here
        env = dict(os.environ, FLEXKANE_CACHE_DIR=cache, FLEXKANE_COMPILE_OPERATIONS=str(10 ** 7))
        code = _CHILD.format(here=str(HERE), k=k, cache=cache, mass_loop=mass_loop, lazy_mass=lazy_mass)
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                              timeout=timeout)
    if done.returncode != 0:
        return {"links": k, "error": done.stderr.strip().splitlines()[-1] if done.stderr else "failed"}
    row = json.loads(done.stdout.strip().splitlines()[-1])
    row["links"] = k
    row["total"] = row["derive"] + row["codegen"] + row["compile"]
    return row


def run(links=LINKS) -> dict:
    """Rows of :func:`measure` for each chain length, printed as they come."""
    print("chain length: chain_model(k), derive + code generation + compilation from an empty cache "
          "(CPU seconds of a fresh process)")
    rows = []
    for k in links:
        row = measure(k)
        rows.append(row)
        if "error" in row:
            print(f"  k = {k:2d}: {row['error']}", flush=True)
            continue
        print(f"  k = {k:2d} ({row['speeds']} speeds, {row['intermediates']} intermediates): derive "
              f"{row['derive']:.2f} s, codegen {row['codegen']:.2f} s, compile {row['compile']:.2f} s, "
              f"(rhs {row['compile_rhs']:.2f} s, outputs {row['compile_outputs']:.2f} s), total {row['total']:.2f} s, "
              f"{row['operations']} operations per evaluation, {row['compiled_operations']} compiled",
              flush=True)
    return {"rows": rows, "load_average_end": os.getloadavg()[0], "date": time.strftime("%Y-%m-%d")}


def compare(links=(8, 20)) -> list:
    """The symbolic mass matrix formed when read against formed by the derivation, alternately in
    the same period: rows ``(k, written-out row, lazy row)`` of :func:`measure`."""
    rows = []
    for k in links:
        before, after = measure(k, lazy_mass=False), measure(k)
        rows.append((k, before, after))
        for label, r in (("formed by derive", before), ("formed when read", after)):
            print(f"  k = {k:2d}, M {label}: derive {r['derive']:.2f} s, codegen {r['codegen']:.2f} s, "
                  f"compile {r['compile']:.2f} s, total {r['total']:.2f} s", flush=True)
    print(f"  load average {os.getloadavg()[0]:.1f}")
    return rows


def markdown(result: dict, machine: dict) -> list[str]:
    """The RESULTS.md section of :func:`run`'s result."""
    md = [SECTION, "",
          "`benchmarks/chain_scaling.py`: `chain_model(k)` (k flexible links on hubs, 2 modes each), each "
          "k in a fresh process with an empty cache; CPU seconds (user + sys) of that process. *derive*: "
          "`flexkane.derive(model, cache=False)`; *codegen*: the module source; *compile*: Numba, the "
          "model's functions (what `compile_model` does after code generation), of which the right-hand "
          "side (*rhs*, with the linear-algebra helpers it calls) and *outputs*; *per link*: the total's "
          "ratio to the previous row divided by the ratio of the link counts (1 = linear growth); "
          "*compiled operations*: the straight-line operations of the right-hand side and `system_rhs`, "
          "the measure of the code-size budget (20,000 by default; the child lifts it). From 9 speeds "
          "on, the mass matrix is summed by the loop of `numerics.mass_assembly` (compiled once per "
          "installation) from the twists and composites the generated code evaluates, instead of "
          "being written out entry by entry, and the derivation forms none of the symbolic mass "
          "matrix's entries (`kane.compact.LazyMassMatrix`: each is formed when read; code "
          "generation reads the diagonal).", "",
          f"Measured on {result['date']}: {machine.get('Model name', '?')}, {machine.get('CPU(s)', '?')} "
          f"CPUs, load average {machine.get('load_average', float('nan')):.1f} at the start, "
          f"{result.get('load_average_end', float('nan')):.1f} at the end (the machine is shared).", "",
          "| links | speeds | intermediates | derive [s] | codegen [s] | compile [s] | of which rhs [s] "
          "| of which outputs [s] | total [s] | per link | operations per evaluation | compiled operations |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    previous = None
    for r in result["rows"]:
        if "error" in r:
            md.append(f"| {r['links']} | - | - | - | - | - | - | - | failed: {r['error']} | - | - | - |")
            continue
        per_link = "-" if previous is None else \
            f"{(r['total'] / previous['total']) / (r['links'] / previous['links']):.2f}"
        md.append(f"| {r['links']} | {r['speeds']} | {r['intermediates']} | {r['derive']:.2f} | "
                  f"{r['codegen']:.2f} | {r['compile']:.2f} | {r['compile_rhs']:.2f} | {r['compile_outputs']:.2f} | "
                  f"{r['total']:.2f} | {per_link} | {r['operations']} | {r['compiled_operations']} |")
        previous = r
    return md + [""]


def main() -> dict:
    sys.path.insert(0, str(HERE))
    import _common

    if "--compare" in sys.argv:
        return {"compare": compare()}
    return _common.section_main(lambda: run(QUICK_LINKS if "--quick" in sys.argv else LINKS), markdown,
                                SECTION)


if __name__ == "__main__":
    main()
