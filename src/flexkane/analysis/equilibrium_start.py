"""A run that starts from the static equilibrium: ``[initial] equilibrium = true``.

The initial state is then ``(q0, u = 0, z0)`` with ``f(q0, 0, t0) = 0`` and ``zdot(q0, 0, z0, t0) = 0``
(Kane's equations ``M u' = f`` at rest, so that ``u' = 0``): the operating point of
``flexkane linearize --about equilibrium`` (:meth:`~flexkane.analysis.linearization.Linearization.operating_point`),
found by Levenberg-Marquardt with the exact stiffness ``K = -df/dq`` as Jacobian
(:func:`~flexkane.analysis.equilibrium.find_equilibrium`). The unknowns are every coordinate not
prescribed by a driver (the elastic coordinates, the joints without drivers, held or not by
springs and feedback torques, the dependent coordinates of closed loops) and the controller states;
their values in ``[initial]`` are where the search starts, so that of several equilibria (a pendulum
hanging or upright) the one nearest to them is found. Coordinates prescribed by drivers keep their
values, and their drivers must be at rest at t0. Every speed is zero: a speed given a value other
than 0 is refused, as is a model without an equilibrium (a body in free fall, a driver moving at
t0), with the reason.

The solution is accepted when the generalized accelerations left are below 1e-9 of the forces'
scale (:data:`~flexkane.analysis.equilibrium.EQUILIBRIUM_RTOL`); the search goes on to the round-off
of f (``xtol = ftol = 1e-15``), and :attr:`EquilibriumStart.relative_residual` says where it ended
(about 1e-16 for the built-in examples). The search may end at an unstable equilibrium when it starts
far from the stable one (a pendulum released at 1.2 rad with its rod bent ends upright):
:attr:`EquilibriumStart.unstable` counts the growing eigenvalues of the motion linearized there, and
a run says so in a warning.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from ..model import Model
from ..model.coordinates import EQUILIBRIUM_KEY
from .equilibrium import EQUILIBRIUM_RTOL, NoEquilibriumError

__all__ = ["EquilibriumStart", "equilibrium_start"]


@dataclass(frozen=True)
class EquilibriumStart:
    """The static equilibrium a run starts from.

    Attributes
    ----------
    state : numpy.ndarray
        The initial state ``[q, u, z]`` in the order of ``state_names``, shape (n,).
    state_names : list of str
        Names of the state entries (``EquationsOfMotion.state_names``).
    unknowns : list of str
        The coordinates and controller states solved for.
    residual : float
        Largest generalized acceleration left, ``max |M^-1 f|`` [m/s^2 or rad/s^2].
    relative_residual : float
        ``residual`` divided by the scale of the accelerations the forces cause [-].
    iterations : int
        Iterations of the search (0 when the initial values were an equilibrium already).
    unstable : int
        Eigenvalues of the motion linearized about it (state matrix of
        :meth:`~flexkane.analysis.linear_model.LinearModel.state_space`) whose real part is positive
        (above 1e-9 of the largest magnitude): 0 for a stable or neutral equilibrium, 1 for a pendulum
        upright.
    """

    state: np.ndarray
    state_names: list
    unknowns: list
    residual: float
    relative_residual: float
    iterations: int
    unstable: int


def equilibrium_start(model: Model, *, t0: float = 0.0) -> EquilibriumStart:
    """The static equilibrium of a model at ``t0``, as the initial state of a run (module docstring).

    Parameters
    ----------
    model : Model
        A valid model; its ``[initial]`` values are where the search starts (the ``equilibrium``
        key itself is not read here).
    t0 : float
        Time [s] at which the loads and drivers are evaluated (the start of the run).

    Returns
    -------
    EquilibriumStart

    Raises
    ------
    ModelError
        Naming ``initial.equilibrium`` when the model has no equilibrium there (a free body under
        gravity, an unbalanced load, a driver moving at t0) or none was found; naming the
        ``initial.<speed>`` given a value other than 0.
    """
    from .linearization import Linearization

    try:
        linearization = Linearization(model, about="equilibrium", t0=t0)
        state_names = [s.name for s in (*linearization.eom.q, *linearization.eom.u, *linearization.z)]
        raw = np.asarray(linearization.eom.initial_state(linearization.model), dtype=float)
        _refuse_moving(linearization.model, state_names, raw, {u.name for u in linearization.eom.u})
        index = {name: k for k, name in enumerate(state_names)}
        # the drivers' coordinates at the run's start, as the run takes them: their [initial] values
        linearization.dropped_values = np.array([raw[index[q.name]] for q in linearization.dropped])
        check = linearization.operating_point()
        A = linearization.at(q_start=check.q[:len(linearization.q_all)], outputs=False).state_space()[0]
    except NoEquilibriumError as exc:
        # the reason, without the advice on linearize's options (--about, --t0) that follows it
        reason = re.split(r"\. Remove the load|; linearize about", exc.args[0])[0]
        raise ModelError(f"initial.{EQUILIBRIUM_KEY}", "a model with a static equilibrium to start from",
                         hint=f"{reason}; start from the values of [initial] instead (initial.{EQUILIBRIUM_KEY} "
                         "= false, or without --from-equilibrium), or take away what moves the model (e.g. "
                         "--set g=0)", show_given=False) from None
    state = raw.copy()
    unknowns = [*(q.name for q in linearization.q_all), *(z.name for z in linearization.z)]
    for name, value in zip(unknowns, check.q):
        state[index[name]] = value
    for u in linearization.eom.u:
        state[index[u.name]] = 0.0
    scale = check.tolerance / EQUILIBRIUM_RTOL
    rates = np.linalg.eigvals(A) if A.size else np.zeros(0)
    growing = rates.real > 1e-9 * max(float(np.max(np.abs(rates), initial=0.0)), 1e-300)
    return EquilibriumStart(state=state, state_names=state_names, unknowns=unknowns, residual=check.residual,
                            relative_residual=check.residual / scale if scale > 0 else 0.0,
                            iterations=check.iterations, unstable=int(np.count_nonzero(growing)))


def _refuse_moving(model: Model, state_names: list, raw: np.ndarray, speeds: set) -> None:
    """A start from the static equilibrium is at rest: no speed may be given a value other than 0."""
    for name, value in zip(state_names, raw):
        if name in speeds and value != 0.0:
            raise ModelError(f"initial.{name}", f"0 or no value (initial.{EQUILIBRIUM_KEY} = true starts at rest "
                             "in the static equilibrium)", model.initial.get(name, value))
