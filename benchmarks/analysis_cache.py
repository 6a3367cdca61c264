"""Analyses answered from the cache of results: first against repeated ``linearize``, ``campbell``, ``converge``.

Each case is a new process (``python -m flexkane ...``, as a user types it), into one cache directory
that starts empty: the first command derives the equations, forms and evaluates the Jacobians; the
same command again is answered from the cache of analysis results
(:mod:`flexkane.result_cache`); a changed value (``--set``) computes again, with the
equations from the cache of derived equations. Cases:

* ``linearize robot-arm-3d-flexible``: first, repeated, with ``--set m_load=3``;
* ``campbell rotor-blade --spin 0:20:4``: first, repeated;
* ``converge rotor-blade --n-modes 2..3``: first, repeated.

Wall and CPU time (user + system of the process, from ``getrusage``: on a shared machine the steadier
figure) of each. ``--src DIR`` measures another checkout's sources; ``--before DIR`` also measures the
sources in DIR (a checkout before a change), side by side; ``--quick`` only the linearization.

Usage: ``python benchmarks/analysis_cache.py [--quick] [--src DIR] [--before DIR] [--write]``; ``--write`` puts the
section into benchmarks/RESULTS.md (replacing an earlier one); ``make bench`` runs it through
``run_all.py``.
"""

from __future__ import annotations

import datetime
import os
import shutil
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
SECTION = "## Analyses answered from the cache of results (issue 25, item 1)"
#: (name, arguments) of each analysis; each is run first, then again unchanged (and the arm with a new value).
CASES = [
    ("linearize robot-arm-3d-flexible", ["linearize", "robot-arm-3d-flexible"]),
    ("campbell rotor-blade --spin 0:20:4", ["campbell", "rotor-blade", "--spin", "0:20:4"]),
    ("converge rotor-blade --n-modes 2..3", ["converge", "rotor-blade", "--n-modes", "2..3"]),
]
VALUE_CHANGE = ["--set", "m_load=3"]


def _option(flag: str, default: Path | None = None) -> Path | None:
    """The directory given after ``flag`` on the command line, else ``default``."""
    if flag in sys.argv:
        return Path(sys.argv[sys.argv.index(flag) + 1]).resolve()
    return default


def run(quick: bool = False, source: Path | None = None) -> dict:
    """Measure every case; return ``{"rows": [...], "load_average": ..., ...}``."""
    sys.path.insert(0, str(HERE))
    from startup import _timed

    source = source or _option("--src", HERE.parent / "src")
    work = tempfile.mkdtemp(prefix="flexkane-analysis-cache-")
    env = dict(os.environ, FLEXKANE_CACHE_DIR=os.path.join(work, "cache"), PYTHONPATH=str(source))
    load_start = os.getloadavg()[0]
    print(f"analyses first and repeated (issue 25), whole processes, sources {source}", flush=True)
    rows = []
    try:
        for k, (name, arguments) in enumerate(CASES[:1] if quick else CASES):
            steps = [("first", []), ("repeated", [])]
            if k == 0:
                steps.append(("value changed", VALUE_CHANGE))
            for step, extra in steps:
                out = os.path.join(work, "out", f"{k}-{step.replace(' ', '-')}")
                wall, cpu, _ = _timed([*arguments, *extra, "--out", out, "--quiet"], env, work)
                rows.append({"case": name, "step": step, "command": "flexkane " + " ".join([*arguments, *extra]),
                             "wall": wall, "cpu": cpu})
                print(f"  {name} ({step}): {wall:.2f} s wall, {cpu:.2f} s CPU", flush=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return {"rows": rows, "source": str(source), "load_average": load_start, "load_average_end": os.getloadavg()[0],
            "date": datetime.date.today().isoformat()}


def run_before_and_after(quick: bool = False) -> dict:
    """:func:`run` of the sources measured, and with ``--before DIR`` of those too (first), as ``before``."""
    before = _option("--before")
    earlier = run(quick, before) if before is not None else None
    result = run(quick)
    if earlier is not None:
        result["before"] = earlier
    return result


def markdown(result: dict, machine: dict | None = None) -> list[str]:
    """The RESULTS.md section of :func:`run`'s result."""
    text = (f"Measured by `benchmarks/analysis_cache.py` on {result['date']}: every case is a new process "
            "(`python -m flexkane ... --quiet`) into one cache directory that starts empty; `first` derives and "
            "computes, `repeated` is the same command again (answered from the cache of analysis results), "
            "`value changed` a new value (computed, the equations from the cache of derived equations). "
            f"CPU = user + system time of the process. Load average {result['load_average']:.2f} at the start, "
            f"{result['load_average_end']:.2f} at the end.")
    if machine:
        text += (f" Machine: {machine.get('Model name', '?')}, {machine.get('CPU(s)', '?')} CPUs, "
                 f"Python {machine.get('python', '?')}.")
    before = result.get("before")
    if before is None:
        md = [SECTION, "", text, "", "| command | step | wall | CPU |", "|---|---|---|---|"]
        for row in result["rows"]:
            md.append(f"| `{row['command']}` | {row['step']} | {row['wall']:.2f} s | {row['cpu']:.2f} s |")
        return md + [""]
    text += (f" Before: the sources in `{before['source']}` measured just before (load average "
             f"{before['load_average']:.2f} to {before['load_average_end']:.2f}).")
    md = [SECTION, "", text, "", "| command | step | wall before | CPU before | wall | CPU | CPU ratio |",
          "|---|---|---|---|---|---|---|"]
    for old, row in zip(before["rows"], result["rows"]):
        md.append(f"| `{row['command']}` | {row['step']} | {old['wall']:.2f} s | {old['cpu']:.2f} s | "
                  f"{row['wall']:.2f} s | {row['cpu']:.2f} s | {old['cpu'] / row['cpu']:.1f} |")
    return md + [""]


def main() -> dict:
    sys.path.insert(0, str(HERE))
    import _common

    return _common.section_main(lambda: run_before_and_after(quick="--quick" in sys.argv), markdown, SECTION)


if __name__ == "__main__":
    main()
