"""(e) How derivation, compilation and simulation times grow with the modes and with the links.

* Modes: ``falling-beam-exact`` with n = 1 ... 40 modes, t in [0, 1] s, at rtol = 1e-8 (accuracy
  limited, DOP853) and rtol = 1e-4 (where the automatic choice moves to Radau IIA).
* Links: a planar chain of k = 1 ... 5 flexible links (2 modes each), each link clamped to a hub
  that turns on a revolute joint at the tip of the previous link, every joint driven by a torque
  pulse, a payload at the end; t in [0, 1.5] s at rtol = 1e-8. Built programmatically.

Times: ``derive`` (first derivation, SymPy cache cleared), ``codegen`` (common subexpressions and
source text), ``compile`` (Numba, right-hand side and both integrator loops, from an empty cache),
``run`` (the integration, compiled, best of several).

Usage: ``python benchmarks/scaling.py [--quick]``.
"""

from __future__ import annotations

import os
import sys
import tempfile

import numpy as np
from sympy.core.cache import clear_cache

import flexkane
from flexkane.model.validate import MAX_MODES
from flexkane.numerics import integrate

from _common import best_time, build, fmt_time

MODES = tuple(n for n in (1, 2, 4, 8, 10, 16, 20, 30, 40) if n <= MAX_MODES)  # 30, 40 measured before the limit
LINKS = (1, 2, 3, 4, 5)


def chain_model(links: int, modes: int = 2):
    """A chain of ``links`` flexible links on hubs, every joint driven by a torque pulse; each link
    bends in its first clamped-free modes (``static_corrections = false``: the basis of the
    hand-written yardsticks, and of the earlier figures of RESULTS.md).

    ::

        ground -o- hub_1 ===== link_1 =====o- hub_2 ===== link_2 ... ===== link_k [payload]
    """
    lines = ['name = "flexible-chain"', "[parameters]", "J = 0.02", "m = 0.5", "r = 0.04",
             "L = 0.6", "EI = 8.0", "rho = 0.5", "m_tip = 0.1", "J_tip = 1e-4", "T = 1.0",
             "t1 = 0.5", "[bodies.payload]", 'mass = "m_tip"', 'inertia = "J_tip"']
    for k in range(1, links + 1):
        lines += [f"[bodies.hub_{k}]", 'mass = "m"', 'inertia = "J"', 'points = { clamp = ["r", 0] }',
                  f"[beams.link_{k}]", 'L = "L"', 'EI = "EI"', 'rho = "rho"', f"n_modes = {modes}",
                  "static_corrections = false",
                  f"[joints.joint_{k}]", 'type = "revolute"',
                  'parent = "ground"' if k == 1 else f'parent = "link_{k - 1}"',
                  *([] if k == 1 else ['station = "L"']), f'child = "hub_{k}"',
                  f'torque = "where(t < t1, T*sin(2*pi*t/t1)/{k}, 0)"',
                  f"[joints.clamp_{k}]", 'type = "weld"', f'parent = "hub_{k}"',
                  'parent_point = "clamp"', f'child = "link_{k}"']
    lines += ["[joints.tip]", 'type = "weld"', f'parent = "link_{links}"', 'station = "L"',
              'child = "payload"', "[simulation]", "t_end = 1.5", "dt_out = 0.005"]
    return flexkane.loads_model("\n".join(lines) + "\n", source=f"chain of {links} links")


def _measure(model, t_end: float, tolerances, rows: list, label: str, value: int) -> None:
    clear_cache()
    built = build(model, ("dop853", "radau"))
    grid = np.linspace(0.0, t_end, 101)
    row = {label: value, "states": len(built.y0), "derive_s": built.derive_time,
           "codegen_s": built.codegen_time, "compile_s": built.compile_time,
           "rhs_compile_s": built.rhs_compile_time}
    text = []
    for rtol in tolerances:
        result = integrate(built.module, built.y0, grid, built.p, rtol=rtol, atol=rtol * 1e-2)
        wall = best_time(lambda: integrate(built.module, built.y0, grid, built.p, rtol=rtol,
                                           atol=rtol * 1e-2), repeat=3, min_total=0.0)
        row[f"run_s@{rtol:g}"] = wall
        row[f"method@{rtol:g}"] = result.method
        row[f"nfev@{rtol:g}"] = result.nfev
        text.append(f"run {fmt_time(wall)} at rtol {rtol:g} ({result.method}, {result.nfev} evaluations)")
    rows.append(row)
    print(f"  {label} = {value:2d} ({row['states']} states): derive {fmt_time(built.derive_time)}, "
          f"codegen {fmt_time(built.codegen_time)}, compile {fmt_time(built.compile_time)} "
          f"(right-hand side {fmt_time(built.rhs_compile_time)}); "
          + "; ".join(text), flush=True)


def run(modes=MODES, links=LINKS) -> dict:
    """Measure every case, compiling into a cache directory of its own (compile times are cold)."""
    previous = os.environ.get("FLEXKANE_CACHE_DIR")
    with tempfile.TemporaryDirectory(prefix="flexkane-scaling-") as cache:
        os.environ["FLEXKANE_CACHE_DIR"] = cache
        try:
            print("(e) growth with the number of modes (falling-beam-exact, t in [0, 1] s)")
            mode_rows: list = []
            for n in modes:
                model = flexkane.builtin_model("falling-beam-exact").with_modes(n)
                _measure(model, 1.0, (1e-8, 1e-4), mode_rows, "modes", n)
            print("(e) growth with the number of flexible links (2 modes each, t in [0, 1.5] s)")
            link_rows: list = []
            for k in links:
                _measure(chain_model(k), 1.5, (1e-8,), link_rows, "links", k)
        finally:
            if previous is None:
                os.environ.pop("FLEXKANE_CACHE_DIR", None)
            else:
                os.environ["FLEXKANE_CACHE_DIR"] = previous
    return {"modes": mode_rows, "links": link_rows}


if __name__ == "__main__":
    if "--quick" in sys.argv:
        run((1, 4, 10), (1, 2))
    else:
        run()
