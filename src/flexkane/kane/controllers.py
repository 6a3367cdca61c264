"""Controller states and outputs (``[controllers.NAME]``, :class:`flexkane.model.parts.Controller`).

A controller state z is a first-order state integrated with the motion, ``z' = rate(...)``; a
controller output is an expression (saturated to ``[min, max]`` when they are given: ``Min(Max(e,
min), max)``) usable by name in efforts and in other controllers. Both may use t, the parameters,
the coordinates and speeds, the sensors (:mod:`flexkane.kane.sensors`), the controller states and
the other outputs (validation refuses cycles among outputs and acceleration sensors).

State vector: ``y = [q, u, z]`` (then the work W of the integrated system): the controller states
come after the speeds, in the order of the controllers (as listed in the model), each controller's
states as listed.

:func:`control_signals` makes the symbols and registers every name an effort may use on the
chain's field symbols (:attr:`flexkane.model.values.FieldSymbols.signals`), so that
``symbols.effort(path, text)`` parses a state-feedback law.
"""

from __future__ import annotations

import sympy as sp

from ..model.values import GeneratedSymbol
from .kinematics import Kinematics
from .sensors import sensor_expressions

__all__ = ["control_signals", "signal_outputs"]


def _ordered_outputs(model) -> list:
    """Controllers with an output, each after the outputs it uses (validation refused cycles)."""
    names = [c.name for c in model.controllers.values() if c.output is not None]
    order, done = [], set()

    def visit(name, trail=()):
        if name in done:
            return
        text = model.controllers[name].output
        for other in names:
            if other != name and other not in trail and isinstance(text, str) and _mentions(text, other):
                visit(other, (*trail, name))
        done.add(name)
        order.append(name)

    for name in names:
        visit(name)
    return order


def _mentions(text: str, name: str) -> bool:
    import re

    return re.search(rf"(?<![A-Za-z0-9_]){re.escape(name)}(?![A-Za-z0-9_])", text) is not None


def control_signals(kin: Kinematics) -> dict:
    """Build the sensors and controllers of a chain; register the names efforts may use.

    Sets on the chain ``controller_states`` (list of symbols, state order) and ``controller_rates``
    (symbol -> rate expression), and on ``chain.symbols.signals`` every name an effort may use
    (coordinates, speeds, sensors, controller states and outputs) with its expression.

    Parameters
    ----------
    kin : Kinematics or SpatialKinematics

    Returns
    -------
    dict of str to sympy.Expr
        The sensors by name (acceleration sensors with u').
    """
    chain = kin.chain
    model = chain.model
    symbols = chain.symbols
    signals: dict = {}
    for c in chain.coordinates:
        signals[c.q.name] = c.q
        if c.u is not None:     # a spatial joint's e0 has no speed
            signals[c.u.name] = c.u
    sensors = sensor_expressions(kin)
    signals.update({name: e for name, e in sensors.items() if model.sensors[name].type != "acceleration"})
    states = []
    for ctrl in model.controllers.values():
        for state in ctrl.states:
            z = GeneratedSymbol(state, real=True)
            states.append(z)
            signals[state] = z
    symbols.signals = signals
    for name in _ordered_outputs(model):
        ctrl = model.controllers[name]
        path = f"controllers.{name}"
        value = symbols.effort(f"{path}.output", ctrl.output)
        if ctrl.max is not None:
            value = sp.Min(value, kin.value(f"{path}.max", ctrl.max, f"max_{name}"))
        if ctrl.min is not None:
            value = sp.Max(value, kin.value(f"{path}.min", ctrl.min, f"min_{name}"))
        signals[name] = chain.name(value, name, above=0)
    chain.controller_states = states
    chain.sensors = sensors
    chain.controller_rates = {}
    k = 0
    for ctrl in model.controllers.values():
        for state, rate in ctrl.states.items():
            chain.controller_rates[states[k]] = symbols.effort(f"controllers.{ctrl.name}.states.{state}", rate)
            k += 1
    return sensors


def effort_unit(chain, owner: str) -> str:
    """Unit of the generalized force on the first coordinate of joint ``owner``: N m on an angle, else N."""
    return "N m" if chain.of(owner)[0].role == "angle" else "N"


def signal_outputs(eom) -> list:
    """The output columns of the efforts, sensors and controllers of derived equations.

    ``effort_<joint>`` [N m or N]: the actuator torque or force of each joint that has one (planar,
    and revolute or prismatic joints in 3D); ``load_<name>_fx``, ``_fy`` [N] (and ``_fz`` in 3D):
    the force components as given, in the load's frame; ``load_<name>_torque`` [N m] (planar) or
    ``load_<name>_tx``, ``_ty``, ``_tz`` (3D): the torque; ``sensor_<name>`` [its unit]: each sensor;
    ``controller_<name>`` [its unit]: each controller output, saturated. Efforts that use the state
    are functions of q, u, the controller states and t, evaluated along the trajectory.

    Parameters
    ----------
    eom : EquationsOfMotion
        Being built (its chain's sensors and signals made by :func:`control_signals`).

    Returns
    -------
    list of Output
        Each declared with its unit and group (:class:`~flexkane.model.columns.Output`).
    """
    from ..model.columns import Output
    from ..model.coordinates import coordinate_unit, speed_unit
    from ..model.signal_units import controller_units, sensor_unit

    chain = eom.chain
    model = chain.model
    symbols = chain.symbols
    out = []
    for joint in chain.joints:
        if joint.torque is not None:
            out.append(Output(f"effort_{joint.name}", symbols.effort(f"joints.{joint.name}.torque", joint.torque),
                              effort_unit(chain, joint.name), "actuator",
                              f"the actuator's torque or force on joint {joint.name!r}"))
    axes = "xyz"[:chain.dimensions]
    for load in model.loads.values():
        path = f"loads.{load.name}"
        if load.force is not None:
            for k, axis in enumerate(axes):
                out.append(Output(f"load_{load.name}_f{axis}", symbols.effort(f"{path}.force[{k}]", load.force[k]),
                                  "N", "load", f"the force of load {load.name!r} along its frame's {axis}"))
        if load.torque is not None and chain.dimensions == 3:
            for k, axis in enumerate(axes):
                out.append(Output(f"load_{load.name}_t{axis}",
                                  symbols.effort(f"{path}.torque[{k}]", load.torque[k]), "N m", "load",
                                  f"the torque of load {load.name!r} about its frame's {axis}"))
        elif load.torque is not None:
            out.append(Output(f"load_{load.name}_torque", symbols.effort(f"{path}.torque", load.torque), "N m",
                              "load", f"the torque of load {load.name!r}"))
    for name, value in getattr(chain, "sensors", {}).items():
        out.append(Output(f"sensor_{name}", value, sensor_unit(model, name), "sensor", f"sensor {name!r}"))
    if any(ctrl.output is not None for ctrl in model.controllers.values()):
        known = {name: sensor_unit(model, name) for name in getattr(chain, "sensors", {})}
        for c in chain.coordinates:
            known[c.q.name] = coordinate_unit(c.role)
            if c.u is not None:
                known[c.u.name] = speed_unit(c.role)
        units = controller_units(model, known)
        for ctrl in model.controllers.values():
            if ctrl.output is not None:
                name = f"controller_{ctrl.name}"
                out.append(Output(name, symbols.signals[ctrl.name], units.get(name), "controller",
                                  f"the output of controller {ctrl.name!r}, saturated"))
    return out
