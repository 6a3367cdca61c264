"""The names effort expressions may use (state feedback), and the checks of sensors and controllers.

Joint torques and forces, loads, joint-spring rest positions, controller rates and controller
outputs are expressions of ``t``, the parameters and the *signals* of the model:

* the generalized coordinates and speeds, by their names (``q_shoulder``, ``u_shoulder``, see
  :mod:`flexkane.model.coordinates`);
* the sensors ``[sensors.NAME]`` by their names (acceleration sensors excepted: they depend on u',
  and an effort depending on the accelerations it causes is an implicit, algebraic loop; they are
  refused with a message saying so, and stay output columns);
* the controller states (``[controllers.NAME] states = { z = "rate" }``) by their names, and the
  controller outputs by the controllers' names (refused in a cycle: ``a`` uses ``b`` uses ``a``).

Drivers' laws stay functions of ``t`` and the parameters: a prescribed coordinate enters the
equations with its first and second time derivatives, which for a law of the state would need the
accelerations of that state.

Everything here works on names and syntax only (no SymPy unless an expression needs it, as
everywhere in validation); :mod:`flexkane.kane.sensors` and :mod:`flexkane.kane.controllers` build
the symbols.
"""

from __future__ import annotations

import difflib
import keyword

from ..errors import ModelError
from .parts import BEAM_COMPONENTS, COMPONENTS, FRAMES, SENSOR_TYPES, SPATIAL_COMPONENTS

__all__ = ["Signals", "effort_fields", "BEAM_SENSORS", "POINT_SENSORS", "JOINT_SENSORS", "SENSOR_UNITS"]

BEAM_SENSORS = ("tip_deflection", "tip_slope", "bending_moment", "strain", "twist")
POINT_SENSORS = ("position", "velocity", "acceleration")
JOINT_SENSORS = ("joint_angle", "joint_rate")
#: Unit of each kind of sensor (joint sensors: of a revolute joint; m and m/s for a prismatic one).
SENSOR_UNITS = {"tip_deflection": "m", "tip_slope": "rad", "bending_moment": "N m", "strain": "-", "twist": "rad",
                "position": "m", "velocity": "m/s", "acceleration": "m/s^2", "joint_angle": "rad",
                "joint_rate": "rad/s"}
_RESERVED = ("t", "x", "xi", "pi")


def effort_fields(model) -> list[tuple[str, object]]:
    """Every effort field of a model that may use signals: ``(key path, value)``.

    Joint torques and rest positions, load force components and torques.
    """
    fields = []
    for joint in model.joints.values():
        if joint.torque is not None:
            fields.append((f"joints.{joint.name}.torque", joint.torque))
        if isinstance(joint.rest, str):
            fields.append((f"joints.{joint.name}.rest", joint.rest))
    for load in model.loads.values():
        if isinstance(load.force, (list, tuple)) and len(load.force) == model.dimensions:
            fields += [(f"loads.{load.name}.force[{k}]", c) for k, c in enumerate(load.force)]
        if isinstance(load.torque, (list, tuple)):      # a spatial model's torque vector
            fields += [(f"loads.{load.name}.torque[{k}]", c) for k, c in enumerate(load.torque)]
        elif load.torque is not None:
            fields.append((f"loads.{load.name}.torque", load.torque))
    return fields


class Signals:
    """The signal names of a model and what each is.

    Parameters
    ----------
    model : Model
        A model whose parts, references and coordinates are valid.
    coordinates : list of CoordinateName
        Its coordinates (:func:`flexkane.model.coordinates.coordinate_names`).
    fields : FieldValues
        The model's evaluator of field values (:class:`~flexkane.model.field_values.FieldValues`).

    Attributes
    ----------
    kinds : dict of str to str
        Name -> ``coordinate``, ``speed``, ``sensor``, ``acceleration sensor``, ``controller state``
        or ``controller output``, in this order.
    """

    def __init__(self, model, coordinates, fields):
        self.model = model
        self.fields = fields
        self.parameters = list(fields.parameters)
        kinds: dict[str, str] = {}
        for c in coordinates:
            kinds[c.q] = "coordinate"
            if c.u is not None:     # a spatial joint's e0 has no speed
                kinds[c.u] = "speed"
        owners: dict[str, str] = {name: f"coordinate or speed {name!r}" for name in kinds}
        owners.update({name: f"parameter {name!r}" for name in self.parameters})

        def claim(path: str, name, kind: str) -> None:
            if not (isinstance(name, str) and name.isidentifier() and name.isascii()):
                raise ModelError(path, "a name of ASCII letters, digits and underscores, not starting with a "
                                 "digit", name)
            if name in _RESERVED or keyword.iskeyword(name) or _is_function(name):
                raise ModelError(path, "a name other than t, x, xi, pi, the function names and Python keywords",
                                 name)
            if name in owners:
                raise ModelError(path, f"a name not already used (by {owners[name]})", name)
            owners[name] = f"{kind} {name!r}"
            kinds[name] = kind

        for sensor in model.sensors.values():
            claim(f"sensors.{sensor.name}", sensor.name,
                  "acceleration sensor" if sensor.type == "acceleration" else "sensor")
        for ctrl in model.controllers.values():
            if not isinstance(ctrl.states, dict):
                raise ModelError(f"controllers.{ctrl.name}.states", "a table of state rates { z = \"expression\" }",
                                 ctrl.states)
            for state in ctrl.states:
                claim(f"controllers.{ctrl.name}.states.{state}", state, "controller state")
        for ctrl in model.controllers.values():
            if ctrl.output is not None:
                claim(f"controllers.{ctrl.name}", ctrl.name, "controller output")
        self.kinds = kinds

    # ------------------------------------------------------------------ names
    def allowed(self) -> list[str]:
        """Names an effort may use: t, the parameters and the signals but acceleration sensors."""
        return ["t", *self.parameters, *(n for n, k in self.kinds.items() if k != "acceleration sensor")]

    def describe(self) -> str:
        """The allowed names by kind, for messages."""
        groups: dict[str, list[str]] = {}
        for name, kind in self.kinds.items():
            if kind != "acceleration sensor":
                groups.setdefault(kind, []).append(name)
        parts = ["t", "the parameters" + (f" ({_listed(self.parameters)})" if self.parameters else "")]
        plural = {"coordinate": "coordinates", "speed": "speeds", "sensor": "sensors",
                  "controller state": "controller states", "controller output": "controller outputs"}
        parts += [f"{plural[kind]} ({_listed(names)})" for kind, names in groups.items()]
        return ", ".join(parts)

    def used(self, path: str, value, what: str) -> set[str]:
        """The signal names an expression uses; refuses unknown names and acceleration sensors.

        Parameters
        ----------
        path : str
            Key path of the field.
        value : int, float or str
            The field.
        what : str
            What the field is, with its unit (``"actuator torque [N m]"``).
        """
        from ..expression_syntax import NeedsSymbolic, expression_names, field_value

        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            raise ModelError(path, f"a number or an expression ({what})", value)
        known = {*self.allowed(), *self.kinds}
        try:
            found = expression_names(value)
        except NeedsSymbolic:
            found = None
        unknown = sorted(found - known) if found is not None else []
        if unknown:
            close = difflib.get_close_matches(unknown[0], self.allowed(), n=1, cutoff=0.6)
            raise ModelError(path, f"{what}: an expression of {self.describe()}", value,
                             f"unknown name '{unknown[0]}'" + (f"; did you mean '{close[0]}'?" if close else ""))
        typical = {name: 0.31 + 0.0713 * k for k, name in enumerate(self.kinds)}   # distinct: no cancellation
        try:   # in the language: evaluated (without SymPy where it can be) with the signals at typical values
            field_value(value, {**self.fields.parameters, "t": 0.0, **typical}, path=path)
        except ModelError:   # not in the language, or singular at these values: the conversion decides
            import sympy as sp

            from ..expressions import free_names, parse_expression

            found = free_names(parse_expression(value, {n: sp.Symbol(n, real=True) for n in known}, path=path))
        found = found or set()
        accelerations = sorted(n for n in found if self.kinds.get(n) == "acceleration sensor")
        if accelerations:
            raise ModelError(path, f"{what} without acceleration sensors: an effort or controller using one "
                             "would depend on u', the accelerations it causes (an implicit, algebraic loop); "
                             "acceleration sensors are output columns only", value,
                             f"uses {', '.join(accelerations)}; feed back a velocity or position sensor")
        return {n for n in found if n in self.kinds}

    def check_outputs_acyclic(self, uses: dict[str, set[str]]) -> None:
        """Refuse controller outputs that use each other in a cycle.

        Parameters
        ----------
        uses : dict of str to set of str
            Controller name -> signal names its output uses.
        """
        outputs = {name for name, kind in self.kinds.items() if kind == "controller output"}
        state: dict[str, int] = {}

        def visit(name: str, trail: list[str]) -> None:
            state[name] = 1
            for other in sorted(set(uses.get(name, ())) & outputs):
                if state.get(other) == 1:
                    cycle = trail[trail.index(other):] + [other] if other in trail else [name, other]
                    raise ModelError(f"controllers.{name}.output", "controller outputs that do not use each "
                                     "other in a cycle (each is computed from the others once per evaluation)",
                                     self.model.controllers[name].output, " -> ".join(cycle))
                if state.get(other) is None:
                    visit(other, trail + [other])
            state[name] = 2

        for name in sorted(outputs):
            if state.get(name) is None:
                visit(name, [name])

    def refuse_in_driver(self, path: str, value) -> None:
        """A driver's law uses t and the parameters only: say why when it names a signal."""
        if not isinstance(value, str):
            return
        try:
            found = self.used(path, value, "a prescribed motion")
        except ModelError:
            return     # the driver's own check reports it with the message of a law of time
        if found:
            raise ModelError(path, "a law of t and the parameters only: a driver prescribes the motion, and its "
                             "speed and acceleration (first and second time derivatives of the law) would need "
                             "the rates and accelerations of the state it depends on", value,
                             f"uses {', '.join(sorted(found))}; for feedback, drive the joint by a torque "
                             "(torque = ...) computed from them")


def _listed(names, limit: int = 12) -> str:
    names = list(names)
    return ", ".join(names[:limit]) + (", ..." if len(names) > limit else "")


def _is_function(name: str) -> bool:
    from ..expression_syntax import RESERVED_NAMES

    return name in RESERVED_NAMES


def check_sensor(model, sensor, values, lengths: dict) -> None:
    """Check one sensor's fields and references (see :class:`~flexkane.model.parts.Sensor`)."""
    from .validate import _station

    path = f"sensors.{sensor.name}"
    if not isinstance(sensor.type, str) or sensor.type not in SENSOR_TYPES:
        raise ModelError(f"{path}.type", "one of " + ", ".join(repr(t) for t in SENSOR_TYPES), sensor.type)
    kind = sensor.type
    given = {key for key in ("beam", "body", "point", "joint", "station", "distance", "component")
             if getattr(sensor, key) is not None}
    spatial = model.dimensions == 3
    if kind == "twist" and not spatial:
        raise ModelError(f"{path}.type", "a sensor of a planar beam (twist: spatial beams, dimensions = 3)", kind)
    if kind in BEAM_SENSORS:
        needed = {"beam"} | ({"station"} if kind in ("bending_moment", "strain", "twist") else set()) \
            | ({"distance"} if kind == "strain" else set()) \
            | ({"component"} if spatial and kind != "twist" else set())   # the bending plane
    elif kind in POINT_SENSORS:
        needed = {"body", "component"}
    else:
        needed = {"joint"}
    optional = {"point", "station"} if kind in POINT_SENSORS else set()
    extra, missing = sorted(given - needed - optional), sorted(needed - given)
    if extra:
        raise ModelError(f"{path}.{extra[0]}", f"only {', '.join(sorted(needed | optional))} on a {kind!r} sensor",
                         getattr(sensor, extra[0]))
    if missing:
        raise ModelError(f"{path}.{missing[0]}", f"the {missing[0]} of a {kind!r} sensor", None, show_given=False)
    if kind not in POINT_SENSORS and sensor.frame != "ground":
        raise ModelError(f"{path}.frame", f"no frame on a {kind!r} sensor (only point sensors have one)",
                         sensor.frame)
    if kind in BEAM_SENSORS:
        beams = list(model.beams)
        if not isinstance(sensor.beam, str) or sensor.beam not in model.beams:
            raise ModelError(f"{path}.beam", f"the name of a beam ({', '.join(beams) or 'the model has none'})",
                             sensor.beam)
        if sensor.station is not None:
            _station(f"{path}.station", sensor.station, sensor.beam, lengths, values)
        if sensor.distance is not None:
            values.number(f"{path}.distance", sensor.distance, "distance from the neutral axis", "m")
        if spatial and kind != "twist" and sensor.component not in BEAM_COMPONENTS:
            raise ModelError(f"{path}.component", "the bending plane of a spatial beam: 'y' (deflection along "
                             "the principal axis y_p, EI_z) or 'z' (along z_p, EI_y)", sensor.component)
    elif kind in POINT_SENSORS:
        links = model.link_names()
        if not isinstance(sensor.body, str) or sensor.body not in links:
            raise ModelError(f"{path}.body", f"the name of a body or a beam ({', '.join(links)})", sensor.body)
        if sensor.body in model.bodies:
            if sensor.station is not None:
                raise ModelError(f"{path}.station", f"a point (not a station) on body {sensor.body!r}",
                                 sensor.station)
            points = model.bodies[sensor.body].points
            if sensor.point is not None and (not isinstance(sensor.point, str) or sensor.point not in points):
                raise ModelError(f"{path}.point", f"a point of body {sensor.body!r} "
                                 f"({', '.join(points) or 'it has none'})", sensor.point)
        else:
            if sensor.point is not None:
                raise ModelError(f"{path}.point", f"a station (not a point) on beam {sensor.body!r}", sensor.point)
            if sensor.station is None:
                raise ModelError(f"{path}.station", f"the station x on beam {sensor.body!r} [m]", None,
                                 show_given=False)
            _station(f"{path}.station", sensor.station, sensor.body, lengths, values)
        if sensor.frame not in FRAMES:
            raise ModelError(f"{path}.frame", "one of " + ", ".join(repr(f) for f in FRAMES), sensor.frame)
        components = SPATIAL_COMPONENTS if spatial else COMPONENTS
        if sensor.component not in components:
            raise ModelError(f"{path}.component", "one of " + ", ".join(repr(c) for c in components)
                             + " (along the axes of the sensor's frame)", sensor.component)
    else:
        joints = [j.name for j in model.joints.values() if j.type in ("revolute", "prismatic")]
        if not isinstance(sensor.joint, str) or sensor.joint not in joints:
            raise ModelError(f"{path}.joint", f"the name of a revolute or prismatic joint "
                             f"({', '.join(joints) or 'the model has none'})", sensor.joint)


def check_controller(ctrl, signals: Signals, values) -> set[str]:
    """Check one controller; return the signal names its output uses."""
    path = f"controllers.{ctrl.name}"
    if not isinstance(ctrl.initial, dict):
        raise ModelError(f"{path}.initial", "a table of initial values { z = value }", ctrl.initial)
    if not ctrl.states and ctrl.output is None:
        raise ModelError(path, "states, an output or both", None, show_given=False)
    for state, rate in ctrl.states.items():
        signals.used(f"{path}.states.{state}", rate, f"the rate of controller state {state!r} [its unit/s]")
    for state, value in ctrl.initial.items():
        if state not in ctrl.states:
            raise ModelError(f"{path}.initial.{state}", "the name of one of this controller's states "
                             f"({', '.join(ctrl.states) or 'it has none'})", state)
        values.number(f"{path}.initial.{state}", value, f"initial value of {state}", "its unit")
    uses: set[str] = set()
    if ctrl.output is not None:
        uses = signals.used(f"{path}.output", ctrl.output, "the controller's output")
    bounds = {}
    for key in ("min", "max"):
        value = getattr(ctrl, key)
        if value is not None:
            if ctrl.output is None:
                raise ModelError(f"{path}.{key}", "an output to saturate (output = ...)", value)
            bounds[key] = values.number(f"{path}.{key}", value, f"{key}imum of the output", "its unit")
    if len(bounds) == 2 and not bounds["min"] < bounds["max"]:
        raise ModelError(f"{path}.max", f"a maximum above the minimum ({bounds['min']:g})", ctrl.max)
    return uses
