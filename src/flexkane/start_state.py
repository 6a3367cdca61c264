"""The state a run starts from: the model's ``[initial]`` table, or its static equilibrium.

With ``[initial] equilibrium = true`` (or ``flexkane run --from-equilibrium``) a run starts at rest
in the static equilibrium under gravity, loads and drivers at its start time
(:mod:`flexkane.analysis.equilibrium_start`); else from the values of ``[initial]``
(:meth:`~flexkane.kane.EquationsOfMotion.initial_state`). Either is a number of the model kept in
the cache of its equations (:meth:`flexkane.derivation_cache.Derivation.numbers`, keyed by the
model's text, which holds the ``equilibrium`` key), so a run repeated neither searches again nor
loads SymPy.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .model import Model
from .model.coordinates import starts_at_equilibrium

__all__ = ["StartState", "start_state"]


@dataclass(frozen=True)
class StartState:
    """The initial state of a run.

    Attributes
    ----------
    state : numpy.ndarray
        ``[q, u, z]`` in the order of the derivation's state names, shape (n,).
    equilibrium : dict or None
        For a start from the static equilibrium: ``iterations`` of its search, ``residual``, the
        largest generalized acceleration left [m/s^2 or rad/s^2], and ``relative_residual``, that
        divided by the scale of the accelerations the forces cause [-], and ``unstable``, the number
        of growing eigenvalues of the motion linearized there (0: stable or neutral); None otherwise.
    """

    @property
    def warnings(self) -> list[str]:
        """A note when the run starts from an unstable equilibrium."""
        if not self.equilibrium or not self.equilibrium.get("unstable"):
            return []
        return [f"the static equilibrium the run starts from is unstable ({self.equilibrium['unstable']} growing "
                "eigenvalue(s) of the motion linearized there): the search from the values of [initial] ended "
                "there; give [initial] values near the equilibrium meant (a pendulum near hanging)"]

    state: np.ndarray
    equilibrium: dict | None = None


def start_state(derivation, model: Model, *, t0: float = 0.0, remember: bool = False) -> StartState:
    """The state a run of ``model`` starts from at ``t0`` (module docstring).

    Parameters
    ----------
    derivation : flexkane.derivation_cache.Derivation
        The equations of the model's structure.
    model : Model
        A valid model of that structure.
    t0 : float
        Start time of the run [s]: where the loads and drivers are evaluated for the equilibrium.
    remember : bool
        Store the numbers in the cache (as :meth:`~flexkane.derivation_cache.Derivation.numbers`).

    Returns
    -------
    StartState

    Raises
    ------
    ModelError
        Naming ``initial.equilibrium`` when the model has no static equilibrium to start from (a
        free body under gravity, a driver moving at t0), or a speed of ``[initial]`` given a value
        other than 0 with it.
    """
    if not starts_at_equilibrium(model):
        return StartState(np.array(derivation.numbers(model, ("y0",), remember=remember)["y0"], dtype=float))
    field = f"y0_equilibrium_t{float(t0)!r}"

    def solve() -> dict:
        from .analysis.equilibrium_start import equilibrium_start

        found = equilibrium_start(model, t0=t0)
        where = dict(zip(found.state_names, found.state))
        return {"state": [float(where[name]) for name in derivation.manifest["state_names"]],
                "iterations": found.iterations, "residual": found.residual,
                "relative_residual": found.relative_residual, "unstable": found.unstable}

    data = dict(derivation.numbers(model, (field,), remember=remember, extra={field: solve})[field])
    return StartState(np.array(data.pop("state"), dtype=float), data)
