"""Recompute the state-feedback gains of the built-in model ``flexible-arm-lqr`` (not needed to run it).

Usage: ``python examples/flexible_arm_lqr_gains.py``; needs python-control (``pip install
'flexkane[control]'``). Prints the gain lines of the model's ``[parameters]`` table.

The design, as in ``examples/flexible-arm-lqr.ipynb``: the plant is ``flexible-arm`` with its torque
profile switched off (``T0 = 0``), linearized about rest by :func:`flexkane.analysis.linearize`
(state ``x = [q_shoulder, q_link_1..3, u_shoulder, u_link_1..3]``, input ``input_effort_shoulder`` [N m]).
python-control's ``lqr`` minimises the integral of ``x' Q x + u' R u`` with

* ``Q = diag(400 on q_shoulder, 1 on u_shoulder) + 1e4 c' c``, ``c`` the row of the output
  ``tip_link`` in ``C`` (the tip deflection, 2 (q_link_1 - q_link_2 + q_link_3) [m]);
* ``R = 1``.

The law ``effort_shoulder = -K (x - x_ref)``, ``x_ref`` the hub at ``theta_ref`` and everything
else 0, is the model's torque, with the gain on state ``s`` named ``k_<s>``.
"""

from __future__ import annotations

import sys

import numpy as np

#: Weights of the design (see the module docstring), on the states and the torque in SI units.
HUB_ANGLE_WEIGHT = 400.0        # on q_shoulder
HUB_RATE_WEIGHT = 1.0           # on u_shoulder
TIP_WEIGHT = 1e4                # on tip_link
TORQUE_WEIGHT = 1.0             # R, on input_effort_shoulder


def lqr_gains() -> dict[str, float]:
    """The gains by parameter name, ``k_<state>``, in the order of the linear model's state.

    Returns
    -------
    dict of str to float
        Gain on each state [N m per unit of the state: rad, m, rad/s, m/s].
    """
    import control

    import flexkane
    from flexkane.analysis import linearize

    plant = flexkane.builtin_model("flexible-arm").with_values({"T0": 0})
    plant.beams["link"].static_corrections = False   # the three clamped-free modes of flexible-arm-lqr
    linear = linearize(plant, about="rest")
    A, B = linear.state_space()
    C, _ = linear.output_matrices()
    names = linear.state_names
    tip = C[linear.output_names.index("tip_link")]
    weights = np.zeros(len(names))
    weights[names.index("q_shoulder")] = HUB_ANGLE_WEIGHT
    weights[names.index("u_shoulder")] = HUB_RATE_WEIGHT
    Q = np.diag(weights) + TIP_WEIGHT * np.outer(tip, tip)
    K, _, _ = control.lqr(A, B, Q, TORQUE_WEIGHT * np.eye(1))
    return {f"k_{name}": float(k) for name, k in zip(names, np.asarray(K)[0])}


def main() -> int:
    try:
        gains = lqr_gains()
    except ImportError as exc:
        print(f"flexible_arm_lqr_gains: {exc.name} is not installed: pip install 'flexkane[control]'",
              file=sys.stderr)
        return 2
    for name, value in gains.items():
        print(f"{name} = {value:.10g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
