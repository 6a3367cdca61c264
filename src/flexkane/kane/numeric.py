"""The numbers of derived equations: constants, parameter vector, initial state, loop closure.

:class:`~flexkane.kane.equations.EquationsOfMotion` holds the symbolic equations; the numbers a run
needs come from a model through the functions here. ``model`` may differ from the derived model in
its numbers only (parameters, field values, typed roots; a sweep's variant), never in its structure,
so that one derivation serves every value. Every field is evaluated by the model's one evaluator,
:class:`~flexkane.model.field_values.FieldValues`.

* :func:`constant_values`: the value of every constant of the equations (parameters, field symbols,
  modal constants of each beam, eqs. 8.23-8.31).
* :func:`parameter_vector`: the same in the order of ``eom.constants`` (the vector p of the
  generated code).
* :func:`initial_state`: ``[q, u]`` from the model's ``[initial]`` table, the dependent coordinates
  of loop constraints solved for (:func:`flexkane.kane.loop_closure.project_coordinates`).
"""

from __future__ import annotations

import math

import numpy as np
import sympy as sp

from ..errors import ModelError
from ..expressions import to_float
from ..model.field_values import FieldValues
from ..model.initial import initial_values
from ..model.paths import get_value
from ..modes.from_spec import beam_shape_family
from .distributed_loads import load_profile
from .inputs import input_symbols
from .loop_closure import project_coordinates

__all__ = ["constant_values", "parameter_vector", "initial_guess", "initial_state"]


def constant_values(eom, model=None) -> dict:
    """Numeric value of every constant of the equations for ``model`` (by default the derived one).

    Parameters
    ----------
    eom : EquationsOfMotion
    model : Model, optional
        The derived model or one that differs from it in its numbers only.

    Returns
    -------
    dict of sympy.Symbol to float
        Parameters, field symbols and modal constants [their units].

    Raises
    ------
    ModelError
        Naming the field whose value cannot be computed, or the beam whose modal constants are not
        finite.
    """
    model = model or eom.model
    fields = FieldValues(model)
    params = fields.parameters
    psyms = eom.chain.symbols.parameters
    values: dict = {psyms[k]: float(v) for k, v in params.items() if k in psyms}
    for symbol, (path, _) in eom.chain.symbols.definitions.items():
        values[symbol] = fields.value(get_value(model, path), path)
    values.update({symbol: 0.0 for symbol in input_symbols(eom.chain).values()})   # control inputs
    for name, consts in eom.kinematics.constants.items():
        if not consts.used:
            continue
        beam = model.beams[name]
        path = f"beams.{name}"
        family = beam_shape_family(model, beam, "shape", params)
        axial = beam_shape_family(model, beam, "axial_shape", params) if beam.n_axial else None
        stations, profiles = {}, {}
        for spec in consts.used.values():
            if spec[0] == "station":   # the station is an expression of the parameters made by the derivation
                stations[spec[3]] = to_float(sp.sympify(spec[3]), values, path=f"{path} station")
            elif spec[0] == "load":
                profiles[spec[2]] = load_profile(spec[2], values)
        if hasattr(consts, "model_values"):   # a spatial beam (flexkane.kane.spatial_beam_constants)
            values.update(consts.model_values(beam, fields, params, stations, profiles, model=model))
            continue
        with np.errstate(over="raise", invalid="raise"):
            try:
                beam_values = consts.values(
                    L=fields.value(beam.L, f"{path}.L"), rho=fields.value(beam.rho, f"{path}.rho"),
                    EI=fields.value(beam.EI, f"{path}.EI"), family=family, n=beam.n_modes,
                    EA=fields.value(beam.EA, f"{path}.EA") if beam.EA is not None else None,
                    axial_family=axial, n_axial=beam.n_axial, station_values=stations, profiles=profiles,
                    rotary_inertia=(fields.value(beam.rotary_inertia, f"{path}.rotary_inertia")
                                    if beam.rotary_inertia is not None else None))
            except (OverflowError, FloatingPointError, ValueError) as exc:
                raise ModelError(path, "values of L, rho, EI (and EA) whose modal constants are finite",
                                 f"{exc}") from None
        values.update(beam_values)
    for symbol, value in values.items():
        if not math.isfinite(value):
            owner = next((f"beams.{name}" for name, consts in eom.kinematics.constants.items()
                          if symbol in consts.used), "parameters")
            raise ModelError(owner, f"values whose modal constants are finite ({symbol.name} is not)", value)
    return values


def parameter_vector(eom, model=None) -> np.ndarray:
    """The constants vector p in the order of ``eom.constants``, shape (len(eom.constants),).

    Parameters
    ----------
    eom : EquationsOfMotion
    model : Model, optional
        The derived model (default) or one that differs from it in its numbers only.
    """
    values = constant_values(eom, model)
    return np.array([values[s] for s in eom.constants], dtype=float)


def initial_guess(eom, model=None) -> dict:
    """Every coordinate and speed of the chain (drivers' included) from the model's ``[initial]``
    table, others 0: ``{symbol: value}`` [m, rad and their rates].

    Parameters
    ----------
    eom : EquationsOfMotion
    model : Model, optional
        The derived model (default) or one that differs from it in its numbers only.
    """
    model = model or eom.model
    values = initial_values(model, FieldValues(model)).values
    return {s: values[s.name] for c in eom.chain.coordinates for s in (c.q, c.u) if s is not None}


def initial_state(eom, model=None) -> np.ndarray:
    """Initial state ``[q, u, z]`` from the model's ``[initial]`` table (others 0, Euler parameters the
    identity; :func:`flexkane.model.initial.initial_values`) and the controllers' ``initial`` tables
    (controller states z, others 0), shape (n,).

    With loop constraints the dependent coordinates are solved for
    (:func:`flexkane.kane.loop_closure.project_coordinates`; the others kept as given)
    and a dependent speed may not be given.

    Parameters
    ----------
    eom : EquationsOfMotion
    model : Model, optional
        The derived model (default) or one that differs from it in its numbers only.

    Raises
    ------
    ModelError
        For an initial value that cannot be computed, a dependent speed given, or coordinates from
        which the loop constraints cannot be closed.
    """
    model = model or eom.model
    fields = FieldValues(model)
    values = initial_values(model, fields).values    # Euler parameters: identity by default
    state = np.array([values[s.name] for s in eom.q + eom.u], dtype=float)
    if eom.dependent_speeds:
        for u in eom.dependent_speeds:
            if u.name in model.initial:
                raise ModelError(f"initial.{u.name}", "no initial value for a dependent speed (it follows "
                                 "from the independent ones through the loop constraints)", model.initial[u.name])
        nq = len(eom.q)
        state[:nq] = project_coordinates(eom, state[:nq], constant_values(eom, model))
    return np.concatenate([state, controller_initial(eom, model, fields)])


def controller_initial(eom, model, fields) -> np.ndarray:
    """Initial values of the controller states ``z`` (their controllers' ``initial``, else 0), shape (nz,)."""
    values = {}
    for ctrl in model.controllers.values():
        for state in ctrl.states:
            values[state] = fields.value_or(ctrl.initial, state, f"controllers.{ctrl.name}.initial")
    return np.array([values[z.name] for z in getattr(eom, "z", ())], dtype=float)
