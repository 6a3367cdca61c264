"""(b) Simulation against lambdify + solve_ivp, and (d) against the hand-written @njit yardstick.

(b) ``falling-beam-exact`` (n = 4, t in [0, 1] s, 1001 output rows) and ``flexible-arm`` (3 modes,
t in [0, 1.5] s, 301 rows) at rtol = 1e-8, atol = 1e-10: flexkane's compiled integration
(``method="auto"``) against SciPy's ``solve_ivp`` (DOP853, the same method) on a right-hand side made
by ``sympy.lambdify`` of the same ``M`` and ``f`` (``numpy.linalg.solve`` for ``M u' = f``). The
error of each is measured against a tight reference (flexkane, DOP853, rtol = 1e-12) on the tip
deflection, relative to its largest value.

(d) One evaluation of the right-hand side (in a compiled loop) and a whole run without output grid
(DOP853, t in [0, 1] s, rtol = 1e-8) against ``njit_yardstick.py``.

Usage: ``python benchmarks/simulation.py``.
"""

from __future__ import annotations

import time

import numpy as np
import sympy as sp
from numba import njit
from scipy.integrate import solve_ivp

import flexkane
from flexkane.numerics import integrate

import njit_yardstick
from _common import best_time, build, fmt_time, relative_error, tip_function

RTOL, ATOL = 1e-8, 1e-10
CASES = (("falling-beam-exact", 4, "B"), ("flexible-arm", 3, "link"))


def lambdify_rhs(eom, p):
    """The right-hand side ``fun(t, y)`` for solve_ivp, from ``sympy.lambdify`` of M and f."""
    args = [eom.t, *eom.q, *eom.u, *eom.constants]
    mass = sp.lambdify(args, eom.mass_matrix, "numpy", cse=True)
    forcing = sp.lambdify(args, eom.forcing, "numpy", cse=True)
    qdot = sp.lambdify(args, eom.qdot, "numpy", cse=True)
    nq = len(eom.q)
    p = list(p)

    def fun(t, y):
        values = (t, *y, *p)
        u_dot = np.linalg.solve(np.asarray(mass(*values), dtype=float),
                                np.asarray(forcing(*values), dtype=float).ravel())
        return np.concatenate([np.asarray(qdot(*values), dtype=float).ravel()[:nq], u_dot])

    return fun


def compare_solve_ivp(name: str, n: int, beam: str) -> dict:
    model = flexkane.builtin_model(name).with_modes(n)
    built = build(model, ("dop853", "radau"))
    eom, module, p, y0 = built.eom, built.module, built.p, built.y0
    sim = model.simulation
    grid = np.linspace(0.0, sim.t_end, int(round(sim.t_end / sim.dt_out)) + 1)
    tip = tip_function(eom, beam)
    reference = integrate(module, y0, grid, p, rtol=1e-12, atol=1e-14, method="dop853")
    tip_ref = tip(reference.y, p)
    ours = integrate(module, y0, grid, p, rtol=RTOL, atol=ATOL)
    ours_time = best_time(lambda: integrate(module, y0, grid, p, rtol=RTOL, atol=ATOL))
    fun = lambdify_rhs(eom, p)
    fun(0.0, y0)
    tic = time.perf_counter()
    theirs = solve_ivp(fun, (0.0, sim.t_end), y0, method="DOP853", rtol=RTOL, atol=ATOL, t_eval=grid)
    theirs_time = time.perf_counter() - tic
    row = {"model": f"{name} (n = {n})", "flexkane_s": ours_time, "method": ours.method,
           "flexkane_nfev": ours.nfev, "flexkane_error": relative_error(tip(ours.y, p), tip_ref),
           "solve_ivp_s": theirs_time, "solve_ivp_nfev": int(theirs.nfev),
           "solve_ivp_error": relative_error(tip(theirs.y.T, p), tip_ref),
           "ratio": theirs_time / ours_time}
    print(f"  {row['model']}: flexkane {fmt_time(ours_time)} ({ours.method}, {ours.nfev} "
          f"evaluations, tip error {row['flexkane_error']:.1e}); lambdify + solve_ivp "
          f"{fmt_time(theirs_time)} ({theirs.nfev} evaluations, tip error "
          f"{row['solve_ivp_error']:.1e}): {row['ratio']:.0f}x faster", flush=True)
    return row


def compare_yardstick() -> dict:
    model = flexkane.builtin_model("falling-beam-exact").with_modes(4)
    built = build(model)
    eom, module, p, y0 = built.eom, built.module, built.p, built.y0
    consts = njit_yardstick.constants_from(eom, p, 4)
    rng = np.random.default_rng(0)
    y = y0 + 0.1 * rng.normal(size=y0.shape)
    rhs = module.rhs

    @njit
    def many(count, y, p, dy):
        for _ in range(count):
            rhs(0.0, y, p, dy)

    dy = np.empty_like(y)
    many(10, y, p, dy)
    count = 200_000
    ours_rhs = best_time(lambda: many(count, y, p, dy), repeat=3) / count
    theirs_rhs = min(njit_yardstick.rhs_cost(y, consts, count) for _ in range(3))
    ends = np.array([0.0, 1.0])
    run = integrate(module, y0, ends, p, rtol=RTOL, atol=ATOL, method="dop853")
    ours_run = best_time(lambda: integrate(module, y0, ends, p, rtol=RTOL, atol=ATOL,
                                           method="dop853"))
    grid = np.linspace(0.0, 1.0, 1001)
    ours_grid = best_time(lambda: integrate(module, y0, grid, p, rtol=RTOL, atol=ATOL,
                                            method="dop853"))
    theirs_run, (y_end, nfev, _, _) = njit_yardstick.run_yardstick(y0, 1.0, RTOL, ATOL, consts)
    row = {"rhs_flexkane_s": ours_rhs, "rhs_yardstick_s": theirs_rhs,
           "rhs_ratio": ours_rhs / theirs_rhs, "run_flexkane_s": ours_run,
           "run_flexkane_grid_s": ours_grid, "run_yardstick_s": theirs_run,
           "run_ratio": ours_run / theirs_run, "nfev_flexkane": run.nfev, "nfev_yardstick": nfev,
           "end_difference": float(np.abs(run.y[-1] - y_end).max())}
    print(f"  one rhs evaluation: flexkane {fmt_time(ours_rhs)}, yardstick {fmt_time(theirs_rhs)} "
          f"({row['rhs_ratio']:.2f}x)")
    print(f"  whole run, no output grid: flexkane {fmt_time(ours_run)} ({run.nfev} evaluations), "
          f"yardstick {fmt_time(theirs_run)} ({nfev} evaluations): {row['run_ratio']:.2f}x; "
          f"with 1001 output rows flexkane takes {fmt_time(ours_grid)}", flush=True)
    return row


def run() -> dict:
    print(f"(b) simulation at rtol = {RTOL:g}, atol = {ATOL:g}: flexkane against lambdify + "
          "solve_ivp (DOP853) on the same equations")
    rows = [compare_solve_ivp(*case) for case in CASES]
    print("(d) falling-beam-exact (n = 4) against the hand-written @njit right-hand side in an "
          "@njit DOP853 loop")
    return {"solve_ivp": rows, "yardstick": compare_yardstick()}


if __name__ == "__main__":
    run()
