"""Sweep throughput (variants per second): serial, and on 2 local Dask worker processes.

Runs ``falling-beam-exact`` over N values of ``beams.B.EI`` (t_end = 0.2 s, dt_out = 0.01 s), each
measurement into a fresh directory. Modes: serial (``--workers 1``, no Dask); 2 workers with one
variant per Dask task; 2 workers with batches of variants per task (the default: each task runs
several variants one after the other, sized to about 0.25 s of work; not a vectorised integration);
and the whole of ``--workers 2`` from a cold start (LocalCluster start and model loading included).
Compilation is excluded from the warm modes: a first small sweep fills the on-disk cache and the
workers' in-memory cache before timing. Usage::

    python benchmarks/sweep_throughput.py [--variants N] [--json]

Prints one line per mode; with ``--json`` one JSON object (for benchmarks/run_all.py).
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import tempfile
import time

MODEL = "falling-beam-exact"


def spec(n: int, start: float = 20.0):
    from flexkane.sweep import SweepSpec

    return SweepSpec(vary=(f"beams.B.EI={start}:{start + 60}:{n}",), t_end=0.2, dt_out=0.01)


def timed_sweep(n: int, start: float, **where) -> float:
    """Variants per second of one sweep of ``n`` new variants."""
    from flexkane.sweep import run_sweep

    with tempfile.TemporaryDirectory() as out:
        begin = time.perf_counter()
        outcome = run_sweep(MODEL, spec(n, start), out=out, **where)
        elapsed = time.perf_counter() - begin
    assert outcome.computed == n and outcome.failed == 0, outcome
    return n / elapsed


def main(argv: list[str] | None = None) -> dict:
    """Run the measurements; print them; return them as a dict (see ``--json``)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variants", type=int, default=200, help="variants per measurement [default: 200]")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    args = parser.parse_args(argv)
    from distributed import Client, LocalCluster

    n = args.variants
    timed_sweep(2, 1.0, workers=1)  # compile (or load) the model in this process
    result = {"benchmark": "sweep_throughput", "model": MODEL, "variants": n}
    result["serial_per_s"] = timed_sweep(n, 20.0, workers=1)
    begin = time.perf_counter()
    result["two_workers_cold_per_s"] = timed_sweep(n, 21.0, workers=2)  # starts its own LocalCluster
    result["two_workers_cold_s"] = time.perf_counter() - begin
    begin = time.perf_counter()
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                      silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        result["cluster_start_s"] = time.perf_counter() - begin
        timed_sweep(4, 2.0, client=client, batch_size=1)  # workers load the compiled model
        result["two_workers_per_s"] = timed_sweep(n, 22.0, client=client, batch_size=1)
        result["two_workers_batched_per_s"] = timed_sweep(n, 23.0, client=client)
    result["load_average"] = os.getloadavg()[0]
    if args.json:
        print(json.dumps(result))
    else:
        print(f"sweep throughput, {MODEL}, {n} variants of t_end = 0.2 s "
              f"({os.cpu_count()} cores, load average {result['load_average']:.1f}):")
        print(f"  serial (--workers 1, no Dask)          {result['serial_per_s']:8.1f} variants/s")
        print(f"  2 local workers, 1 variant per task    {result['two_workers_per_s']:8.1f} variants/s")
        print(f"  2 local workers, batched (default)     {result['two_workers_batched_per_s']:8.1f} variants/s "
              f"(warm cluster; its start took {result['cluster_start_s']:.1f} s)")
        print(f"  --workers 2 from a cold start          {result['two_workers_cold_per_s']:8.1f} variants/s "
              f"({result['two_workers_cold_s']:.1f} s in all)")
    return result


if __name__ == "__main__":  # the guard is required: Dask starts its workers by spawning this script
    main()
