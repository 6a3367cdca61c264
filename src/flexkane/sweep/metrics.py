"""Summary metrics of one run: the numbers a sweep table keeps for each variant.

=======================  =====================================================================
column                   meaning
=======================  =====================================================================
``t_reached``            last time the state is known [s] (``t_end`` unless the run failed)
``nsteps``, ``nfev``     integrator steps and right-hand-side evaluations [-]
``wall_time``            integration wall time [s] (varies from run to run)
``run_time``             wall time of the whole variant on its worker [s] (varies likewise)
``energy_error``         relative energy error: drift ``max |E - E0| / scale`` of a conservative
                         run, or power-balance error ``max |E - E0 - W_nc| / scale`` of a driven or
                         damped one (``W_nc``: work of drivers, loads and dampers, integrated with
                         the motion; output ``work``); ``scale = max(max |E|, max T)`` [-]
``energy_check``         ``drift`` or ``power_balance``: which of the two ``energy_error`` is
``max_abs_tip_<beam>``   maximum over the output times of the tip deflection of each beam [m]
``final_<state>``        each coordinate [m or rad] and speed [m/s or rad/s] at ``t_reached``
=======================  =====================================================================
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["summary_metrics", "energy_error", "METRIC_UNITS"]

#: Units of the fixed metric columns (per-beam and per-state columns follow their quantity).
METRIC_UNITS = {"t_reached": "s", "nsteps": "-", "nfev": "-", "wall_time": "s", "run_time": "s",
                "energy_error": "-", "energy_check": "", "max_abs_tip_<beam>": "m",
                "final_<state>": "m, rad, m/s or rad/s"}


def energy_error(results) -> tuple[float, str]:
    """Relative energy drift, or power-balance error of a run with non-conservative forces.

    Parameters
    ----------
    results : Results
        A run with outputs ``energy`` [J], ``kinetic`` [J] and ``power_nonconservative`` [W].

    Returns
    -------
    error : float
        ``max |E - E0| / scale`` (conservative run) or ``max |E - E0 - W_nc| / scale`` [-];
        NaN when the outputs are missing or there are fewer than two output times.
    kind : str
        ``"drift"`` or ``"power_balance"`` (empty when the error is NaN).
    """
    from scipy.integrate import cumulative_trapezoid

    outputs = results.outputs
    if "energy" not in outputs or len(results.t) < 2:
        return math.nan, ""
    e = np.asarray(outputs["energy"], dtype=float)
    kinetic = np.asarray(outputs.get("kinetic", e), dtype=float)
    scale = max(float(np.abs(e).max()), float(np.abs(kinetic).max()), 1e-300)
    if "energy_balance" in outputs and "work" in outputs:  # work integrated with the motion
        kind = "power_balance" if np.any(np.asarray(outputs["work"])) else "drift"
        return float(np.abs(np.asarray(outputs["energy_balance"], dtype=float)).max() / scale), kind
    power = np.asarray(outputs.get("power_nonconservative", np.zeros_like(e)), dtype=float)
    if not np.any(power):
        return float(np.abs(e - e[0]).max() / scale), "drift"
    work = cumulative_trapezoid(power, results.t, initial=0.0)
    return float(np.abs(e - e[0] - work).max() / scale), "power_balance"


def summary_metrics(results) -> dict:
    """The table columns of one run (see the module docstring).

    Parameters
    ----------
    results : Results
        A complete or partial run.

    Returns
    -------
    dict of str to float, int or str
        Solver statistics, energy error, maximum tip deflections and final state.
    """
    solver = results.solver
    metrics: dict = {"t_reached": float(solver.get("t_reached", results.t[-1] if len(results.t) else 0.0)),
                     "nsteps": int(solver.get("nsteps", 0)), "nfev": int(solver.get("nfev", 0)),
                     "wall_time": float(solver.get("wall_time", math.nan))}
    with np.errstate(all="ignore"):
        metrics["energy_error"], metrics["energy_check"] = energy_error(results)
        for name in results.outputs_of("tip"):    # the tip deflections (flexkane.model.columns.GROUPS)
            values = np.asarray(results.outputs[name], dtype=float)
            metrics[f"max_abs_{name}"] = float(np.abs(values).max()) if values.size else math.nan
    final = results.state[-1] if len(results.t) else np.full(len(results.state_names), math.nan)
    for name, value in zip(results.state_names, final):
        metrics[f"final_{name}"] = float(value)
    return metrics
