"""Iteration times of ``flexkane run``: a first run, an unchanged rerun and a value change (issue 25, item 1).

For each model, three cases, each the median of several runs of a new process
(``python -m flexkane run MODEL --out DIR --force --no-plots``, as a user types it):

* **first run**: into a new empty model cache (``FLEXKANE_CACHE_DIR``) each time, the integrator loops
  compiled already (they are cached once per installation): derive, generate, compile, integrate;
* **rerun**: the same command again, everything cached;
* **value change**: ``--set NAME=VALUE`` of a parameter, a new value each time (a value run before
  would be a rerun): the equations and their compiled code are cached, the constants vector p of the
  new values is computed, and ``equations.md`` / ``.tex`` are assembled from the stored text of the
  structure.

The figure of merit is the ratio value change / rerun (issue 25: "a value change costs what a rerun
costs"). Besides the wall time, the CPU time of each process and its children (user + system, from
``getrusage``) is given: on a shared machine it is the steadier figure.

``--before SRC`` also measures the rerun and the value change with the sources ``SRC`` of another
checkout (the ``src`` directory of one from before a change), sharing the warmed cache: the derived
equations and the compiled module are found there when only the run's stages differ.

Usage: ``python benchmarks/iteration.py [--quick] [--write] [--before SRC]``; ``--write`` puts the
section into benchmarks/RESULTS.md (replacing an earlier one); ``make bench`` runs it through
``run_all.py``.
"""

from __future__ import annotations

import datetime
import os
import shutil
import statistics
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from startup import _timed  # noqa: E402 - the benchmarks' directory is put on the path first

SECTION = "## Iteration: first run, rerun and value change (issue 25, item 1)"
#: Model, the parameter changed, and its new values (one per run of the value change, none repeated).
MODELS = (("falling-beam", "EI", (40.0, 41.0, 42.0, 43.0, 44.0, 45.0)),
          ("robot-arm-3d-flexible", "m_load", (3.0, 3.1, 3.2, 3.3, 3.4, 3.5)))
QUICK_MODELS = MODELS[:1]
CASES = ("first run", "rerun", "value change")


def _environment(cache: str, src: Path) -> dict:
    env = dict(os.environ, FLEXKANE_CACHE_DIR=cache)
    env["PYTHONPATH"] = str(src) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    return env


def _median(name: str, runs: list[tuple[float, float, str]]) -> dict:
    walls, cpus = [r[0] for r in runs], [r[1] for r in runs]
    row = {"case": name, "runs": len(runs), "wall": statistics.median(walls), "cpu": statistics.median(cpus),
           "walls": walls, "cpus": cpus}
    print(f"    {name}: median {row['wall']:.2f} s wall, {row['cpu']:.2f} s CPU "
          f"(walls {', '.join(f'{w:.2f}' for w in walls)} s)", flush=True)
    return row


def _iterations(model: str, parameter: str, values, work: str, cache: str, src: Path, repeat: int,
                first: bool) -> dict:
    """The cases of one model with the sources ``src``; ``first``: measure the first run (each into a
    new empty cache, the last of which is kept as ``cache``), else warm ``cache`` with one run."""
    out = os.path.join(work, "out", model)
    arguments = ["run", model, "--out", out, "--force", "--no-plots"]
    rows = {}
    if first:
        runs = []
        for k in range(repeat):
            shutil.rmtree(cache, ignore_errors=True)
            runs.append(_timed(arguments, _environment(cache, src), work))
        rows["first run"] = _median("first run", runs)
    else:
        _timed(arguments, _environment(cache, src), work)   # this source's manifest, numbers, module
    env = _environment(cache, src)
    rows["rerun"] = _median("rerun", [_timed(arguments, env, work) for _ in range(repeat)])
    rows["value change"] = _median("value change", [_timed(arguments + ["--set", f"{parameter}={value:g}"], env, work)
                                                    for value in values[:repeat]])
    rows["ratio"] = {key: rows["value change"][key] / rows["rerun"][key] for key in ("wall", "cpu")}
    print(f"    value change / rerun: {rows['ratio']['wall']:.2f} (wall), {rows['ratio']['cpu']:.2f} (CPU)",
          flush=True)
    return rows


def run(quick: bool = False, before: str | None = None) -> dict:
    """Measure every case; return ``{"models": {...}, "before": {...}, "load_average": ...}``."""
    repeat = 1 if quick else 3
    work = tempfile.mkdtemp(prefix="flexkane-iteration-")
    src = HERE.parent / "src"
    load_start = os.getloadavg()
    print("iteration times (issue 25 item 1): first run, rerun, value change; whole processes, "
          f"median of {repeat}", flush=True)
    found: dict = {}
    earlier: dict = {}
    try:
        # the integrator loops compiled (once per installation) before anything is measured
        _timed(["run", "falling-beam", "--t-end", "0.01", "--out", os.path.join(work, "warm"), "--force",
                "--no-plots"], _environment(os.path.join(work, "warm-cache"), src), work)
        for model, parameter, values in (QUICK_MODELS if quick else MODELS):
            cache = os.path.join(work, f"cache-{model}")
            print(f"  {model} (--set {parameter}=...)", flush=True)
            found[model] = _iterations(model, parameter, values, work, cache, src, repeat, first=True)
            if before:
                print(f"  {model}, sources {before}", flush=True)
                earlier[model] = _iterations(model, parameter, values[repeat:], work, cache, Path(before),
                                             repeat, first=False)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return {"models": found, "before": earlier, "before_src": before, "repeat": repeat,
            "load_average": load_start, "load_average_end": os.getloadavg(),
            "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")}


def _load(loads) -> str:
    return " / ".join(f"{x:.2f}" for x in loads)


def markdown(result: dict, machine: dict | None = None) -> list[str]:
    """The RESULTS.md section of :func:`run`'s result."""
    from _common import machine_sentence

    md = [SECTION, ""]
    text = (f"Measured by `benchmarks/iteration.py` on {result['date']}: every case is a new process "
            "(`python -m flexkane run MODEL --out DIR --force --no-plots`), median of "
            f"{result['repeat']} runs; a first run goes into an empty model cache with the integrator "
            "loops compiled, a value change sets a parameter to a value not run before. CPU = user + system "
            "time of the process and its children (the compiling child included). Load average "
            f"(1 / 5 / 15 min, as `uptime` gives it) {_load(result['load_average'])} at the start, "
            f"{_load(result['load_average_end'])} at the end: a shared machine, whose wall times under load "
            "are longer than the CPU times.")
    text += machine_sentence(machine)
    md += [text, "", "| model | first run | rerun | value change (`--set`) | value change / rerun |",
           "|---|---|---|---|---|"]

    def cell(row):
        return f"{row['wall']:.2f} s ({row['cpu']:.2f} s CPU)" if row else "-"

    for model, rows in result["models"].items():
        ratio = rows["ratio"]
        md.append(f"| {model} | {cell(rows.get('first run'))} | {cell(rows['rerun'])} | "
                  f"{cell(rows['value change'])} | {ratio['wall']:.2f} wall, {ratio['cpu']:.2f} CPU |")
    md += ["", "What a value change adds to a rerun: SymPy and the pickled equations of the structure are loaded "
               "to compute the constants vector p of the new values (`EquationsOfMotion.constant_values`); the "
               "printed equations are not rendered again (`equations.md` and `.tex` are the stored text of the "
               "structure with the new values, `flexkane.equations_document`)."]
    if result.get("before"):
        md += ["", f"The same with the sources before the change (`{result['before_src']}`), in the same "
                   "warmed cache:", "",
               "| model | rerun | value change (`--set`) | value change / rerun |", "|---|---|---|---|"]
        for model, rows in result["before"].items():
            ratio = rows["ratio"]
            md.append(f"| {model} | {cell(rows['rerun'])} | {cell(rows['value change'])} | "
                      f"{ratio['wall']:.2f} wall, {ratio['cpu']:.2f} CPU |")
    return md + [""]


def main() -> dict:
    import _common

    before = sys.argv[sys.argv.index("--before") + 1] if "--before" in sys.argv else None
    return _common.section_main(lambda: run(quick="--quick" in sys.argv, before=before), markdown, SECTION)


if __name__ == "__main__":
    main()
