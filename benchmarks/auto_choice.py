"""Automatic method choice: ``method="auto"`` against DOP853 and Radau IIA alone on the built-in models.

Cases: falling-beam-exact with 4, 10, 20 and 40 modes, flexible-arm, spin-up and
two-link-flexible-arm, each at rtol 1e-6 and 1e-8 (atol = rtol / 100, the model's span and output
rows). Per case and method: the integration's CPU time (``time.process_time`` around
``integrate``, best of REPS, default 2), evaluations, steps, the method that covered most of the
span, the spans covered by each method and a digest of the rows (the same bytes run after run).
One JSON line per case and method on stdout.

Usage: ``python benchmarks/auto_choice.py [case ...]`` (a case as ``falling-beam-exact/40`` or
``spin-up``); ``METHODS=auto,radau`` to run some methods only.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
import time

import numpy as np

import flexkane
import flexkane.numerics.integrate  # noqa: F401  (the module, not the function of flexkane.numerics)
from flexkane.simulation import compile_model, simulate

INTEGRATE = sys.modules["flexkane.numerics.integrate"]
CASES = ([("falling-beam-exact", n, rtol) for n in (4, 10, 20, 40) for rtol in (1e-6, 1e-8)]
         + [(name, None, rtol) for name in ("flexible-arm", "spin-up", "two-link-flexible-arm")
            for rtol in (1e-6, 1e-8)])


def _timed_integrate(captured: dict):
    """``integrate`` that leaves its result and CPU time in ``captured``."""
    integrate = INTEGRATE.integrate

    def timed(*args, **kwargs):
        tic = time.process_time()
        result = integrate(*args, **kwargs)
        captured["cpu"] = time.process_time() - tic
        captured["result"] = result
        return result
    return timed


def main(only=(), methods=("auto", "dop853", "radau"), repeat=2) -> list[dict]:
    captured: dict = {}
    INTEGRATE.integrate = _timed_integrate(captured)
    rows, compiled_of = [], {}
    for name, n, rtol in CASES:
        label = name + (f"/{n}" if n else "")
        if only and label not in only:
            continue
        model = flexkane.builtin_model(name)
        model = model.with_modes(n) if n else model
        if label not in compiled_of:
            compiled_of[label] = compile_model(flexkane.derive(model))
        for method in methods:
            best = float("inf")
            for _ in range(repeat):
                simulate(compiled_of[label], rtol=rtol, atol=rtol / 100, method=method, model=model)
                best = min(best, captured["cpu"])
            r = captured["result"]
            row = dict(case=label, rtol=rtol, method=method, cpu=best, nfev=int(r.nfev),
                       steps=int(r.nsteps), chosen=r.method, ok=bool(r.success),
                       spans={k: round(v, 4) for k, v in r.method_spans.items()},
                       digest=hashlib.sha256(np.ascontiguousarray(r.y).tobytes()).hexdigest()[:12])
            rows.append(row)
            print(json.dumps(row), flush=True)
    print("load", os.getloadavg(), time.strftime("%Y-%m-%d %H:%M"))
    return rows


if __name__ == "__main__":
    main(sys.argv[1:], os.environ.get("METHODS", "auto,dop853,radau").split(","),
         int(os.environ.get("REPS", "2")))
