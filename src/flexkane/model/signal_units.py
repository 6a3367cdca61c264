"""Units of the signals of a model: its sensors and its controllers' states and outputs.

A sensor has the unit of its kind (:data:`flexkane.model.signals.SENSOR_UNITS`; a joint sensor on
a prismatic joint reads m and m/s). A controller's state has the unit of its rate times s, its output
the unit of its expression and of the efforts it feeds, as the rules of dimensions of
:func:`flexkane.model.parameter_units.inferred_units` give them from the units of the coordinates,
speeds and sensors: the integral of an angle error [rad] is in rad s. A state or output whose unit no
expression fixes has none.
"""

from __future__ import annotations

import contextlib

__all__ = ["sensor_unit", "controller_units"]


def sensor_unit(model, name: str) -> str:
    """Unit of the sensor ``name`` of ``model`` (m and m/s for a joint sensor on a prismatic joint)."""
    from .signals import SENSOR_UNITS

    sensor = model.sensors[name]
    if sensor.type in ("joint_angle", "joint_rate") and model.joints[sensor.joint].type == "prismatic":
        return "m" if sensor.type == "joint_angle" else "m/s"
    return SENSOR_UNITS[sensor.type]


def controller_units(model, known: dict) -> dict[str, str]:
    """Units of the controller states and outputs, where the model's expressions fix them.

    Parameters
    ----------
    model : Model
    known : dict of str to str
        Units of the names the expressions read: coordinates, speeds and sensors (by the sensors'
        names).

    Returns
    -------
    dict of str to str
        Each controller state by its name and each controller output as ``controller_<name>``, to
        its unit; those whose unit no expression fixes are left out.
    """
    from ..expression_syntax import NeedsSymbolic, expression_names
    from .parameter_units import field_values, inferred_units
    from .signals import effort_fields

    equal, names = [], set(model.parameters)
    for ctrl in model.controllers.values():
        names.update(ctrl.states)
        equal += [(state, rate, True) for state, rate in ctrl.states.items()]
        if ctrl.output is not None:
            names.add(ctrl.name)
            equal.append((ctrl.name, ctrl.output, False))   # not its bounds: numbers of one model, not structure
    if not equal:
        return {}
    # the efforts that use signals: their texts are structure, as are the controllers' (a manifest
    # serves every model of a structure, so no number of one model may decide a unit)
    efforts = set()
    for path, value in effort_fields(model):
        with contextlib.suppress(NeedsSymbolic):
            if isinstance(value, str) and expression_names(value) - set(model.parameters) - {"t"}:
                efforts.add(path)
    fields = {path: field for path, field in field_values(model).items() if path in efforts}
    found = inferred_units(fields, names, known=known, equal=equal)
    out = {}
    for ctrl in model.controllers.values():
        out.update({state: found[state] for state in ctrl.states if state in found})
        if ctrl.output is not None and ctrl.name in found:
            out[f"controller_{ctrl.name}"] = found[ctrl.name]
    return out
