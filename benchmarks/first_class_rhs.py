"""Integrators compiled once (issue 16, item 5): the price of the indirection, the time of a new structure.

The DOP853 and Radau loops are functions of the package, compiled once per installation, that call
the model's right-hand side through a Numba first-class function
(:mod:`flexkane.numerics.system_function`). Two measurements:

1. **Indirection.** The same run (the chapter's example, ``falling-beam-exact`` with n = 4 modes,
   t in [0, 1] s, rtol = 1e-8, atol = 1e-10, no output grid) through the first-class function and
   with the right-hand side called directly (the same loop compiled once more with the model's
   dispatcher bound, which lets LLVM inline it): best of several runs each, their ratio, the extra
   time per evaluation, and whether the numbers are the same bits. Also one evaluation in a
   compiled loop, directly and through the first-class function.
2. **A new structure.** ``flexkane run falling-beam --out DIR --no-plots --quiet`` in a new process
   with an empty model cache (``FLEXKANE_CACHE_DIR``) and the integrators already in their cache:
   wall time and CPU time (user + system of the process and of its compiling child); for comparison
   the same run with the cache filled, and (not with ``--quick``) a first run of an installation,
   with Numba's cache of the package empty too (``NUMBA_CACHE_DIR``). The same two cases with the
   plots (``flexkane run falling-beam --quiet``, the whole command: the target of under 3 s).
   The processes run as in an installation, with Python's bytecode cache (``PYTHONDONTWRITEBYTECODE``
   unset).

Usage: ``python benchmarks/first_class_rhs.py [--quick]``.
"""

from __future__ import annotations

import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from numba import njit

import flexkane
from flexkane.numerics.dop853 import dop853_chunk
from flexkane.numerics.integrate import load_integrators
from flexkane.numerics.radau import radau5_chunk
from flexkane.numerics.system_function import direct_chunk, system_function

from _common import best_time, build, fmt_time

RTOL, ATOL = 1e-8, 1e-10
CHUNKS = {"dop853": dop853_chunk, "radau": radau5_chunk}
TARGET_SHARE = 0.10      # the indirection: below 10 % of a run
TARGET_NEW_STRUCTURE = 3.0  # [s] a new structure of the chapter's example, integrators cached


def _calls(function_argument):
    """Compiled loops calling a right-hand side ``count`` times (bound, or passed as an argument)."""
    @njit
    def through_argument(f, count, y, p, dy):
        for _ in range(count):
            f(0.0, y, p, dy)

    def bound(dispatcher):
        @njit
        def direct(count, y, p, dy):
            for _ in range(count):
                dispatcher(0.0, y, p, dy)
        return direct

    return through_argument if function_argument else bound


def indirection(methods=("dop853", "radau")) -> dict:
    """Time of the same run through the first-class function and with direct calls."""
    model = flexkane.builtin_model("falling-beam-exact").with_modes(4)
    built = build(model, methods)
    module, p, y0 = built.module, built.p, built.y0
    n = y0.shape[0]
    system = system_function(module)
    t_out = np.array([0.0, 1.0])
    rows = []
    for method in methods:
        direct = direct_chunk(method, module.system_rhs)
        outputs = {}

        def run(kind):
            Y = np.empty((2, n))
            args = (0.0, y0, 0.0, t_out, p, RTOL, np.full(n, ATOL), 1_000_000, Y, -np.inf)
            out = CHUNKS[method](system, *args) if kind == "indirect" else direct(*args)
            outputs[kind] = (out[3:], Y.tobytes())
            return out

        run("direct")  # compiles the direct specialisation (seconds)
        nfev = run("indirect")[4]
        t_direct = best_time(lambda: run("direct"), repeat=15, min_total=1.0)
        t_indirect = best_time(lambda: run("indirect"), repeat=15, min_total=1.0)
        row = {"method": method, "nfev": int(nfev), "direct_s": t_direct, "indirect_s": t_indirect,
               "ratio": t_indirect / t_direct, "per_evaluation_s": (t_indirect - t_direct) / nfev,
               "same_bits": outputs["direct"] == outputs["indirect"]}
        rows.append(row)
        print(f"  {method}: direct {fmt_time(t_direct)}, first-class function {fmt_time(t_indirect)} "
              f"({nfev} evaluations): ratio {row['ratio']:.3f} "
              f"({(row['ratio'] - 1) * 100:+.1f} %, {row['per_evaluation_s'] * 1e9:+.1f} ns per evaluation), "
              f"same bits: {row['same_bits']}", flush=True)
    dy = np.empty(n)
    y = y0 + 0.01
    count = 200_000
    through, bound = _calls(True), _calls(False)(module.system_rhs)
    through(system, 10, y, p, dy)
    bound(10, y, p, dy)
    one_direct = best_time(lambda: bound(count, y, p, dy), repeat=5) / count
    one_indirect = best_time(lambda: through(system, count, y, p, dy), repeat=5) / count
    print(f"  one evaluation in a compiled loop: direct {fmt_time(one_direct)}, first-class function "
          f"{fmt_time(one_indirect)}", flush=True)
    return {"model": "falling-beam-exact (n = 4)", "rows": rows, "evaluation_direct_s": one_direct,
            "evaluation_indirect_s": one_indirect}


def _timed_process(argv: list[str], env: dict) -> tuple[float, float, str]:
    """Wall and CPU time [s] (user + system, children included) of a command, and its standard error."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    tic = time.perf_counter()
    out = subprocess.run(argv, env=env, capture_output=True, text=True, timeout=900)
    wall = time.perf_counter() - tic
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode != 0:
        raise RuntimeError(f"{' '.join(argv)} failed: {out.stderr.strip()[-500:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, out.stderr


def new_structure(runs: int = 3, first_run: bool = True) -> dict:
    """``flexkane run falling-beam`` from an empty model cache, the integrators cached."""
    load_integrators()  # compiled (or loaded) once here: the runs below find them in the cache
    plotting = [sys.executable, "-m", "flexkane", "run", "falling-beam", "--quiet"]
    command = plotting[:-1] + ["--no-plots", "--quiet"]
    result: dict = {"command": "flexkane run falling-beam --no-plots --quiet", "runs": runs,
                    "plots_command": "flexkane run falling-beam --quiet"}
    base = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    fresh, cached, fresh_plots, cached_plots = [], [], [], []
    with tempfile.TemporaryDirectory(prefix="flexkane-bench-new-structure-") as tmp:
        for k in range(runs):
            for argv, new, old, name in ((command, fresh, cached, "np"), (plotting, fresh_plots, cached_plots, "p")):
                env = dict(base, FLEXKANE_CACHE_DIR=str(Path(tmp) / f"cache{k}{name}"))
                out = str(Path(tmp) / f"out{k}{name}")
                new.append(_timed_process(argv + ["--out", out], env)[:2])
                old.append(_timed_process(argv + ["--out", out, "--force"], env)[:2])
        if first_run:
            env = dict(base, FLEXKANE_CACHE_DIR=str(Path(tmp) / "first"),
                       NUMBA_CACHE_DIR=str(Path(tmp) / "numba"))
            wall, cpu, _ = _timed_process(command + ["--out", str(Path(tmp) / "first-out")], env)
            result["first_run_wall_s"], result["first_run_cpu_s"] = wall, cpu
    for name, values in (("fresh", fresh), ("cached", cached), ("fresh_plots", fresh_plots),
                         ("cached_plots", cached_plots)):
        walls, cpus = zip(*values)
        result[f"{name}_wall_s"] = statistics.median(walls)
        result[f"{name}_wall_min_s"] = min(walls)
        result[f"{name}_cpu_s"] = statistics.median(cpus)
        result[f"{name}_cpu_min_s"] = min(cpus)
    result["load_average"] = os.getloadavg()[0]
    print(f"  new structure (empty model cache, integrators cached): wall {fmt_time(result['fresh_wall_s'])} "
          f"(min {fmt_time(result['fresh_wall_min_s'])}), CPU {fmt_time(result['fresh_cpu_s'])} "
          f"(min {fmt_time(result['fresh_cpu_min_s'])}); cached: wall {fmt_time(result['cached_wall_s'])}, "
          f"CPU {fmt_time(result['cached_cpu_s'])}; median of {runs}, load average "
          f"{result['load_average']:.2f}", flush=True)
    print(f"  with the plots: empty model cache wall {fmt_time(result['fresh_plots_wall_s'])}, CPU "
          f"{fmt_time(result['fresh_plots_cpu_s'])}; cached wall {fmt_time(result['cached_plots_wall_s'])}, "
          f"CPU {fmt_time(result['cached_plots_cpu_s'])}", flush=True)
    if first_run:
        print(f"  first run of an installation (integrators compiled too): wall "
              f"{fmt_time(result['first_run_wall_s'])}, CPU {fmt_time(result['first_run_cpu_s'])}", flush=True)
    return result


def run(quick: bool = False) -> dict:
    print("Integrators compiled once (issue 16, item 5): the first-class function's cost, a new structure")
    return {"indirection": indirection(("dop853",) if quick else ("dop853", "radau")),
            "new_structure": new_structure(2 if quick else 5, first_run=not quick)}


def targets(result: dict) -> list[tuple[str, bool | None, str]]:
    """(target, met, measured) of item 5."""
    out = []
    for row in result.get("indirection", {}).get("rows", []):
        out.append((f"indirection of the right-hand side below {TARGET_SHARE:.0%} of a run ({row['method']})",
                    row["ratio"] - 1.0 < TARGET_SHARE, f"{(row['ratio'] - 1) * 100:+.1f} %"))
    new = result.get("new_structure")
    if new:
        total = "fresh_plots" if "fresh_plots_wall_s" in new else "fresh"
        out.append((f"new structure of the chapter's example under {TARGET_NEW_STRUCTURE:g} s in total, plots "
                    "included (integrators cached)",
                    new[f"{total}_wall_s"] < TARGET_NEW_STRUCTURE,
                    f"wall {fmt_time(new[f'{total}_wall_s'])}, CPU {fmt_time(new[f'{total}_cpu_s'])} "
                    f"(load average {new['load_average']:.1f})"))
    return out


def markdown(result: dict) -> list[str]:
    """The section of RESULTS.md."""
    md = ["## (h) Integrators compiled once (issue 16, item 5)", "",
          "`benchmarks/first_class_rhs.py`. The DOP853 and Radau IIA loops are functions of the package "
          "(`@njit(cache=True)`), compiled once per installation; they call the model's `system_rhs` "
          "through a Numba first-class function (`flexkane.numerics.system_function`), whose type is the "
          "same for every model, so a new structure compiles only its own functions.", ""]
    ind = result.get("indirection")
    if ind:
        md += [f"The price of the indirection: one run of {ind['model']}, t in [0, 1] s, rtol = {RTOL:g}, "
               f"atol = {ATOL:g}, no output grid, with the right-hand side called directly (the loop "
               "compiled again with the model's dispatcher bound, so LLVM may inline it) and through the "
               "first-class function; best of at least 15 runs each:", "",
               "| method | evaluations | direct | first-class function | ratio | per evaluation | same bits |",
               "|---|---|---|---|---|---|---|"]
        md += [f"| {r['method']} | {r['nfev']} | {fmt_time(r['direct_s'])} | {fmt_time(r['indirect_s'])} | "
               f"{r['ratio']:.3f} ({(r['ratio'] - 1) * 100:+.1f} %) | {r['per_evaluation_s'] * 1e9:+.1f} ns | "
               f"{'yes' if r['same_bits'] else '**no**'} |" for r in ind["rows"]]
        md += ["", f"One evaluation in a compiled loop: {fmt_time(ind['evaluation_direct_s'])} called directly, "
               f"{fmt_time(ind['evaluation_indirect_s'])} through the first-class function.", ""]
    new = result.get("new_structure")
    if new:
        md += [f"A new structure: `{new['command']} --out DIR` in a new process, an empty model cache "
               f"(`FLEXKANE_CACHE_DIR`), the integrators in their cache; median (min) of {new['runs']} runs, "
               f"CPU = user + system of the process and its compiling child, load average "
               f"{new['load_average']:.2f} (a shared 2-core machine: wall times under load exceed the CPU "
               "times):", "",
               "| case | wall | CPU |", "|---|---|---|",
               f"| empty model cache | {fmt_time(new['fresh_wall_s'])} ({fmt_time(new['fresh_wall_min_s'])}) | "
               f"{fmt_time(new['fresh_cpu_s'])} ({fmt_time(new['fresh_cpu_min_s'])}) |",
               f"| model cached | {fmt_time(new['cached_wall_s'])} ({fmt_time(new['cached_wall_min_s'])}) | "
               f"{fmt_time(new['cached_cpu_s'])} ({fmt_time(new['cached_cpu_min_s'])}) |"]
        if "fresh_plots_wall_s" in new:
            md += [f"| empty model cache, with the plots (`{new['plots_command']}`) | "
                   f"{fmt_time(new['fresh_plots_wall_s'])} ({fmt_time(new['fresh_plots_wall_min_s'])}) | "
                   f"{fmt_time(new['fresh_plots_cpu_s'])} ({fmt_time(new['fresh_plots_cpu_min_s'])}) |",
                   f"| model cached, with the plots | "
                   f"{fmt_time(new['cached_plots_wall_s'])} ({fmt_time(new['cached_plots_wall_min_s'])}) | "
                   f"{fmt_time(new['cached_plots_cpu_s'])} ({fmt_time(new['cached_plots_cpu_min_s'])}) |"]
        if "first_run_wall_s" in new:
            md.append(f"| first run of an installation (Numba's cache of the package empty too, "
                      f"`NUMBA_CACHE_DIR`) | {fmt_time(new['first_run_wall_s'])} | "
                      f"{fmt_time(new['first_run_cpu_s'])} |")
        md.append("")
    return md


if __name__ == "__main__":
    print("\n".join(markdown(run("--quick" in sys.argv))))
