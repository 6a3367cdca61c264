"""(a) Derivation of the chapter's example with n = 1, 2, 4 modes: flexkane against the SymPy baseline.

Both derive ``M(q) u' = f(q, u)`` of ``falling-beam-exact`` (the baseline integrates over x with
``sympy.integrate`` as the notebook does, see ``sympy_baseline.py``); the equations are checked to
agree numerically at random states. SymPy's cache is cleared before each derivation, so every time
is that of a first derivation in a fresh process. Also given: loading the same equations from
flexkane's on-disk derivation cache.

Usage: ``python benchmarks/derivation.py [N ...]``.
"""

from __future__ import annotations

import sys
import tempfile
import time

import numpy as np
import sympy as sp
from sympy.core.cache import clear_cache

import flexkane
from flexkane.derivation_cache import cached_derive

from _common import best_time, fmt_time
from sympy_baseline import derive_baseline


def _flexkane_derive(model):
    clear_cache()
    return flexkane.derive(model)


def _agreement(eom, base, seed=0) -> float:
    """Largest relative difference of M and f between the two derivations at random states."""
    rng = np.random.default_rng(seed)
    p = dict(zip(eom.constants, eom.parameter_vector()))
    worst = 0.0
    for _ in range(3):
        y = rng.normal(scale=0.3, size=len(eom.q) + len(eom.u))
        ours = {**{k: sp.Float(v) for k, v in p.items()}, **dict(zip(eom.q + eom.u, map(sp.Float, y)))}
        theirs = dict(zip(base["q"] + base["u"], map(sp.Float, y)))
        for a, b in ((eom.mass_matrix, base["mass_matrix"]), (eom.forcing, base["forcing"])):
            x = np.array(a.xreplace(ours).evalf(), dtype=float)
            z = np.array(b.xreplace(theirs).evalf(), dtype=float)
            worst = max(worst, float(np.abs(x - z).max() / np.abs(x).max()))
    return worst


def run(modes=(1, 2, 4)) -> list[dict]:
    """Time both derivations for each mode count; print one line each; return the rows."""
    rows = []
    print("(a) derivation of falling-beam-exact, flexkane against a SymPy derivation that "
          "integrates over x")
    with tempfile.TemporaryDirectory() as cache:
        for n in modes:
            model = flexkane.builtin_model("falling-beam-exact").with_modes(n)
            ours = best_time(lambda: _flexkane_derive(model), repeat=3, min_total=0.0)
            eom = flexkane.derive(model)
            clear_cache()
            tic = time.perf_counter()
            base = derive_baseline(n)
            theirs = time.perf_counter() - tic
            cached_derive(model, cache)
            load = best_time(lambda: cached_derive(model, cache), repeat=5)
            row = {"n": n, "flexkane_s": ours, "baseline_s": theirs, "ratio": theirs / ours,
                   "cache_load_s": load, "agreement": _agreement(eom, base)}
            rows.append(row)
            print(f"  n = {n}: flexkane {fmt_time(ours)}, SymPy baseline {fmt_time(theirs)}: "
                  f"{row['ratio']:.0f}x faster; loaded from the derivation cache in {fmt_time(load)}; "
                  f"equations agree to {row['agreement']:.1e}", flush=True)
    return rows


if __name__ == "__main__":
    run(tuple(int(a) for a in sys.argv[1:]) or (1, 2, 4))
