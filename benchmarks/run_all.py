"""``make bench``: every comparison of issue 6 side by side, with ratios, into benchmarks/RESULTS.md.

Sections (one script each, also runnable alone):

(a) ``derivation.py``   derivation, n = 1, 2, 4, against the SymPy baseline (``sympy_baseline.py``);
(b) ``simulation.py``   simulation against lambdify + solve_ivp at equal accuracy;
(c) ``exudyn_arm.py``   flexible-arm against Exudyn at matched tip-deflection accuracy;
(d) ``simulation.py``   one evaluation and a whole run against the @njit yardstick (``njit_yardstick.py``);
(e) ``scaling.py``      times against the number of modes (1-40) and of flexible links (1-5);
(f) ``startup.py``      start-up of the command (--help, --version, check), derive n = 40, a cached run;
(g) ``recursive_yardstick.py``  one evaluation of chain_model(k) against a hand-written recursive rhs;
(h) ``constant_block.py``  the constant modal block factored once per run against L D L^T of all of M;
    ``modal_forms.py``  a beam's modal sums evaluated once per call (matrix-vector products) against
    every term in the tables, and DOP853 / Radau / auto at 40 modes;
(i) ``first_class_rhs.py``  integrators compiled once: the cost of calling the right-hand side through a
    first-class function, and the time of a new structure with the integrators cached;
(j) ``chain_scaling.py``  derive, code generation and compilation of chain_model(k), k = 1 ... 20;
(k) ``spatial_chains.py``  spatial chains: a rigid three-joint arm, spherical chains, the flexible
    three-joint arm (issue 17's Performance targets) and its growth with flexible links and modes;
(l) ``iteration.py``  a first run, an unchanged rerun and a value change (``--set``) of falling-beam and
    robot-arm-3d-flexible, whole processes (issue 25, item 1);
(m) ``analysis_cache.py``  first against repeated linearize, campbell and converge (issue 25);
and, when the sweep module and Dask are installed, ``sweep_throughput.py`` (variants per second).

Compiled models go to a fresh cache directory, so compile times are those of a first run.
Exudyn comes with the ``bench`` extra (``pip install -e '.[bench]'``); without it (c) is skipped.

Usage: ``python benchmarks/run_all.py [--quick] [--no-write] [--keep-cache]``; ``--quick`` runs
fewer cases (for a check of the scripts, in a minute or two), ``--no-write`` leaves RESULTS.md.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import traceback
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))


def _section(name, function, results, *args):
    tic = time.perf_counter()
    try:
        results[name] = function(*args)
    except Exception as exc:  # noqa: BLE001 - one failing comparison must not hide the others
        traceback.print_exc()
        results[name] = {"error": f"{type(exc).__name__}: {exc}"}
        print(f"  {name}: FAILED ({type(exc).__name__}: {exc})")
    results.setdefault("section_seconds", {})[name] = time.perf_counter() - tic
    print(flush=True)


def _sweep(quick: bool) -> dict:
    script = HERE / "sweep_throughput.py"
    if not script.exists():
        return {"skipped": "benchmarks/sweep_throughput.py is not there"}
    try:
        import distributed  # noqa: F401
        import flexkane.sweep  # noqa: F401
    except ImportError as exc:
        return {"skipped": f"sweeps need {exc.name}"}
    print("sweep throughput (issue 11), falling-beam-exact, variants per second")
    out = subprocess.run([sys.executable, str(script), "--json", "--variants", "40" if quick else "200"],
                         capture_output=True, text=True, timeout=900, cwd=HERE.parent)
    if out.returncode != 0:
        raise RuntimeError(out.stderr.strip().splitlines()[-1] if out.stderr.strip() else "failed")
    result = json.loads(out.stdout.strip().splitlines()[-1])
    for key in ("serial_per_s", "two_workers_per_s", "two_workers_batched_per_s", "two_workers_cold_per_s"):
        if key in result:
            print(f"  {key.replace('_per_s', '').replace('_', ' ')}: {result[key]:.1f} variants/s")
    return result


def main() -> dict:
    quick = "--quick" in sys.argv
    keep = "--keep-cache" in sys.argv
    cache = None
    if not keep:
        cache = tempfile.mkdtemp(prefix="flexkane-bench-cache-")
        os.environ["FLEXKANE_CACHE_DIR"] = cache
    import _common
    import constant_block
    import derivation
    import recursive_yardstick
    import report
    import scaling
    import simulation

    start = time.perf_counter()
    results: dict = {"machine": _common.machine_info(), "quick": quick}
    info = results["machine"]
    print(f"flexkane benchmarks on {info.get('Model name', '?')}, {info.get('CPU(s)', '?')} CPUs, "
          f"Python {info['python']}, load average {info['load_average']:.2f}\n", flush=True)
    _section("derivation", derivation.run, results, (1, 2) if quick else (1, 2, 4))
    _section("simulation", simulation.run, results)
    try:
        import exudyn  # noqa: F401
        import exudyn_arm
        _section("exudyn", exudyn_arm.run, results)
    except ImportError:
        results["exudyn"] = {"skipped": "Exudyn is not installed (pip install -e '.[bench]')"}
        print("(c) skipped: Exudyn is not installed (pip install -e '.[bench]')\n")
    if quick:
        _section("scaling", scaling.run, results, (1, 4, 10), (1, 2))
    else:
        _section("scaling", scaling.run, results)
    if quick:
        _section("recursive_yardstick", recursive_yardstick.run, results, (1, 2), (8,))
    else:
        _section("recursive_yardstick", recursive_yardstick.run, results)
    _section("constant_block", constant_block.run, results, (10,) if quick else constant_block.MODES)
    import modal_forms
    _section("modal_forms", modal_forms.run, results, modal_forms.QUICK_MODES if quick else modal_forms.MODES)
    import chain_scaling
    _section("chain_scaling", chain_scaling.run, results,
             chain_scaling.QUICK_LINKS if quick else chain_scaling.LINKS)
    import spatial_chains
    _section("spatial_chains", spatial_chains.run, results,
             spatial_chains.QUICK_LINKS if quick else spatial_chains.LINKS,
             spatial_chains.QUICK_FLEXIBLE_CASES if quick else spatial_chains.FLEXIBLE_CASES)
    import first_class_rhs
    _section("integrators", first_class_rhs.run, results, quick)
    _section("sweep", _sweep, results, quick)
    import startup
    _section("startup", startup.run, results, quick)
    import iteration
    _section("iteration", iteration.run, results, quick)
    import analysis_cache
    _section("analysis_cache", analysis_cache.run, results, quick)
    results["machine"]["load_average_end"] = os.getloadavg()[0]
    results["total_seconds"] = time.perf_counter() - start
    summary = report.summary_lines(results)
    print("\n".join(summary))
    print(f"\nmake bench took {results['total_seconds'] / 60:.1f} min")
    if "--no-write" not in sys.argv and not quick:
        (HERE / "RESULTS.md").write_text(report.markdown(results), encoding="utf-8")
        print("written: benchmarks/RESULTS.md")
    if cache is not None:
        shutil.rmtree(cache, ignore_errors=True)
    return results


if __name__ == "__main__":
    main()
