"""Start-up and interaction times of the ``flexkane`` command, measured as whole processes.

Measured, each the median of several runs (a new Python process every time, as a user types it):

* ``flexkane --help``, ``flexkane --version`` and ``flexkane check falling-beam`` (target: < 0.3 s);
* ``flexkane derive falling-beam-exact --n-modes 40`` (target: a few seconds);
* a cached ``flexkane run falling-beam --out DIR --force`` (the second run of ``make run``), with and
  without ``--no-plots`` (target: < 2 s);
* one run of ``falling-beam`` into an empty cache: its wall time and the compile time it prints in
  its summary (``compile X s``);
* ``flexkane run falling-beam --out DIR`` with its plots, each run into a new empty model cache
  (``FLEXKANE_CACHE_DIR``) with the integrators compiled (a new model structure; target: < 3 s);
* which heavy libraries a cached run imports, and their import times (``python -X importtime``):
  a cached run loads its numbers and its compiled module only, so SymPy must not be among them.

Besides the wall time, the CPU time of each process (user + system, from ``getrusage``) is given:
on a shared machine it is the steadier figure.

Usage: ``python benchmarks/startup.py [--quick] [--write]``; ``--write`` puts the section into
benchmarks/RESULTS.md (replacing an earlier one); ``make bench`` runs it through ``run_all.py``.
"""

from __future__ import annotations

import datetime
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SECTION = "## Start-up and interaction times (issue 14, items 3 and 4)"
#: Targets [s] of the median wall time, by case.
TARGETS = {"--help": 0.3, "--version": 0.3, "check falling-beam": 0.3, "run falling-beam (cached)": 2.0,
           "run falling-beam (new structure)": 3.0}


def _command() -> list[str]:
    """The flexkane command of this interpreter (sources of this checkout first on the path)."""
    return [sys.executable, "-m", "flexkane"]


def _environment(cache: str) -> dict:
    env = dict(os.environ, FLEXKANE_CACHE_DIR=cache)
    src = str(HERE.parent / "src")
    env["PYTHONPATH"] = src + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    return env


def _timed(arguments: list[str], env: dict, cwd: str) -> tuple[float, float, str]:
    """(wall time [s], CPU time [s], stdout) of one process; raises on a non-zero exit code."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    tic = time.perf_counter()
    out = subprocess.run(_command() + arguments, capture_output=True, text=True, env=env, cwd=cwd, timeout=900)
    wall = time.perf_counter() - tic
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode != 0:
        raise RuntimeError(f"flexkane {' '.join(arguments)} exited with {out.returncode}: "
                           f"{out.stderr.strip()[-500:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, out.stdout


#: Heavy libraries whose import a cached run is checked for.
HEAVY = ("sympy", "numba", "scipy.linalg", "matplotlib")


def _imports(arguments: list[str], env: dict, cwd: str) -> dict:
    """Heavy top-level packages imported by one process, with their cumulative import times [s]."""
    out = subprocess.run([sys.executable, "-X", "importtime"] + _command()[1:] + arguments, capture_output=True,
                         text=True, env=env, cwd=cwd, timeout=900)
    if out.returncode != 0:
        raise RuntimeError(f"flexkane {' '.join(arguments)} exited with {out.returncode}")
    found = {}
    for line in out.stderr.splitlines():
        match = re.match(r"import time:\s+\d+\s+\|\s+(\d+)\s+\|\s+(\S+)\s*$", line)
        if match and match.group(2) in HEAVY:   # the package itself: its cumulative time, first import
            found.setdefault(match.group(2), int(match.group(1)) * 1e-6)
    return found


def _median_case(name: str, arguments: list[str], env: dict, cwd: str, repeat: int, shown: str | None = None,
                 empty_cache: bool = False) -> dict:
    """Median wall and CPU time of ``repeat`` runs; ``empty_cache``: each into a new empty model cache."""
    walls, cpus = [], []
    for k in range(repeat):
        if empty_cache:
            env = dict(env, FLEXKANE_CACHE_DIR=tempfile.mkdtemp(prefix=f"cache-{k}-", dir=cwd))
        wall, cpu, _ = _timed(arguments, env, cwd)
        walls.append(wall)
        cpus.append(cpu)
    row = {"case": name, "command": "flexkane " + (shown or " ".join(arguments)), "runs": repeat,
           "wall": statistics.median(walls), "cpu": statistics.median(cpus), "wall_min": min(walls)}
    print(f"  {name}: median {row['wall']:.3f} s wall, {row['cpu']:.3f} s CPU ({repeat} runs)", flush=True)
    return row


def run(quick: bool = False) -> dict:
    """Measure every case; return ``{"rows": [...], "fresh": {...}, "load_average": ...}``."""
    repeat = 3 if quick else 7
    work = tempfile.mkdtemp(prefix="flexkane-startup-")
    cache = os.path.join(work, "cache")
    env = _environment(cache)
    print("start-up and interaction times (issue 14), whole processes, median of several runs", flush=True)
    load_start = os.getloadavg()[0]
    try:
        out_dir = os.path.join(work, "out", "falling-beam")
        run_args = ["run", "falling-beam", "--out", out_dir, "--force"]
        # a fresh cache: the first run derives and compiles; its summary says how long the compile took
        wall, cpu, stdout = _timed(run_args, env, work)
        found = re.search(r"compil\w*\s+(\d+(?:\.\d+)?)\s*s", stdout)
        fresh = {"wall": wall, "cpu": cpu, "compile": float(found.group(1)) if found else None,
                 "summary": next((line for line in stdout.splitlines() if "compil" in line), "").strip()}
        print(f"  fresh cache: run {wall:.2f} s wall, compile {fresh['compile']} s (from the summary)", flush=True)
        rows = [
            _median_case("--help", ["--help"], env, work, repeat),
            _median_case("--version", ["--version"], env, work, repeat),
            _median_case("check falling-beam", ["check", "falling-beam"], env, work, repeat),
            _median_case("derive falling-beam-exact --n-modes 40",
                         ["derive", "falling-beam-exact", "--n-modes", "40"], env, work, 1 if quick else 3),
            _median_case("run falling-beam (cached)", run_args, env, work, 3 if quick else 5,
                         "run falling-beam --out out/falling-beam --force"),
            _median_case("run falling-beam (cached) --no-plots", run_args + ["--no-plots"], env, work,
                         3 if quick else 5, "run falling-beam --out out/falling-beam --force --no-plots"),
            _median_case("run falling-beam (new structure)", run_args, env, work, 3 if quick else 5,
                         "run falling-beam --out out/falling-beam --force (an empty model cache each)",
                         empty_cache=True),
        ]
        imports = _imports(run_args, env, work)
        print("  a cached run imports: " + ", ".join(f"{k} {v:.3f} s" for k, v in imports.items()), flush=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return {"rows": rows, "fresh": fresh, "imports": imports, "load_average": load_start, "load_average_end": os.getloadavg()[0],
            "date": datetime.date.today().isoformat(), "repeat": repeat}


def markdown(result: dict, machine: dict | None = None) -> list[str]:
    """The RESULTS.md section of :func:`run`'s result."""
    from _common import machine_sentence

    md = [SECTION, ""]
    text = (f"Measured by `benchmarks/startup.py` on {result['date']}: every case is a new process "
            f"(`python -m flexkane ...`), median of the runs given; CPU = user + system time of the "
            f"process. Load average {result['load_average']:.2f} at the start, "
            f"{result['load_average_end']:.2f} at the end (a shared machine: the wall times of a loaded "
            "machine are longer than the CPU times).")
    text += machine_sentence(machine)
    md += [text, "", "| case | runs | median wall | median CPU | target | met (wall) | met (CPU) |",
           "|---|---|---|---|---|---|---|"]
    for row in result["rows"]:
        target = TARGETS.get(row["case"])
        met = ["" if target is None else ("yes" if row[key] < target else "**no**") for key in ("wall", "cpu")]
        md.append(f"| `{row['command']}` | {row['runs']} | "
                  f"{row['wall']:.3f} s | {row['cpu']:.3f} s | {'' if target is None else f'< {target:g} s'} | "
                  f"{met[0]} | {met[1]} |")
    fresh = result["fresh"]
    compile_text = f"{fresh['compile']:g} s" if fresh["compile"] is not None else "not printed"
    md += ["", f"A run of `falling-beam` into an empty cache took {fresh['wall']:.2f} s wall "
               f"({fresh['cpu']:.2f} s CPU); its summary reports a compile time of {compile_text}"
               + (f" (`{fresh['summary']}`)." if fresh["summary"] else "."), ""]
    imports = result.get("imports")
    if imports is not None:
        heavy = ", ".join(f"{name} ({seconds:.2f} s)" for name, seconds in imports.items())
        missing = [name for name in HEAVY if name not in imports]
        md += [f"A cached `run falling-beam` imports {heavy or 'none of them'} (cumulative import times from "
               f"`python -X importtime`, first import of each package); it does not import "
               f"{', '.join(missing) or '-'}: its numbers, outputs and equations come from the cache and the "
               "compiled module.", ""]
    return md


def main() -> dict:
    sys.path.insert(0, str(HERE))
    import _common

    return _common.section_main(lambda: run(quick="--quick" in sys.argv), markdown, SECTION)


if __name__ == "__main__":
    main()
