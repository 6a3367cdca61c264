"""Item 4 of the timing table: what ``flexkane run`` reports while and after it compiles.

Runs ``flexkane run MODEL`` twice in a fresh cache directory (``python -m flexkane``, a new process
each time): the first run compiles the model structure, the second loads it from Numba's disk cache.
For each: the time until the message "compiling the right-hand side ..." appears on standard error
(if it does), the time to the end, and the compile and integration times of the summary line.

Usage: ``python benchmarks/compile_progress.py [MODEL]`` (default ``falling-beam``).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from flexkane.simulation import COMPILING_MESSAGE


def run_once(model: str, cache: Path, out: Path) -> dict:
    """One ``flexkane run``; times [s] from the start of the process."""
    env = dict(os.environ, FLEXKANE_CACHE_DIR=str(cache))
    start = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "flexkane", "run", model, "--out", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    seen: dict = {}

    def watch_stderr():
        for line in proc.stderr:
            if COMPILING_MESSAGE in line and "message" not in seen:
                seen["message"] = time.perf_counter() - start

    reader = threading.Thread(target=watch_stderr)
    reader.start()
    stdout = proc.stdout.read()
    proc.wait()
    reader.join()
    total = time.perf_counter() - start
    match = re.search(r"compile ([\d.]+) s, integrate ([\d.]+) s", stdout)
    return {"message_at": seen.get("message"), "total": total,
            "compile": float(match.group(1)) if match else None,
            "integrate": float(match.group(2)) if match else None, "code": proc.returncode}


def main(model: str = "falling-beam") -> None:
    with tempfile.TemporaryDirectory(prefix="flexkane-bench-") as tmp:
        tmp = Path(tmp)
        rows = [("fresh cache", run_once(model, tmp / "cache", tmp / "a")),
                ("cached", run_once(model, tmp / "cache", tmp / "b"))]
    print(f"flexkane run {model}: times [s] from the start of the process")
    print("| run | message shown at | reported compile | reported integrate | total |")
    print("|---|---|---|---|---|")
    for label, r in rows:
        shown = f"{r['message_at']:.2f}" if r["message_at"] is not None else "not shown"
        print(f"| {label} | {shown} | {r['compile']} | {r['integrate']} | {r['total']:.2f} |")


if __name__ == "__main__":
    main(*sys.argv[1:2])
