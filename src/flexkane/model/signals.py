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

A speed driver's law (``driver = { speed = ... }``) may read the coordinates, the sensors of
position, the controller states and the outputs built from them, but no speed (its time derivative,
the driven acceleration, would contain u'). A coordinate driver's law
(``driver = { coordinate = ... }``) may read the
coordinates (not its own, nor one driven by another law of the state), the sensors of position
(every kind but velocity, joint rate and acceleration), the controller states whose rates read no
speed, and the controller outputs built from those: it is then a holonomic constraint
(:mod:`flexkane.kane.driver_laws`). It may not read speeds: the driven speed is the law's time
derivative, which for a law of speeds would contain the accelerations u', and the driven
acceleration u''. Planar and spatial models (``dimensions = 3``: the coordinates of every joint type,
Euler parameters included) follow the same rules.

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
        self.coordinates = list(coordinates)
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
        from ..expression_syntax import NeedsSymbolic, expression_names
        from ..expression_values import field_value

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

    def check_driver(self, path: str, value, uses: dict[str, set[str]]) -> set[str]:
        """The signals a driver's law uses; refuses those a prescribed coordinate cannot follow.

        Parameters
        ----------
        path : str
            ``joints.<joint>.driver.coordinate`` or ``...speed``.
        value : int, float or str
            The law.
        uses : dict of str to set of str
            Controller name -> signal names its output uses (:func:`check_controller`).

        Returns
        -------
        set of str
            The signal names the law uses (empty for a law of t and the parameters).
        """
        if not isinstance(value, str):
            return set()
        joint = path.split(".")[1]
        speed_law = path.endswith(".speed")
        what = "speed [m/s or rad/s]" if speed_law else "coordinate [m or rad]"
        found = self.used(path, value, f"a prescribed {what}: a law of t, the parameters, coordinates, position "
                          "sensors and controller states")
        reads = set(found)
        via: dict[str, str] = {}
        pending = [n for n in found if self.kinds[n] == "controller output"]
        while pending:            # through controller outputs, the names they use
            name = pending.pop()
            for other in uses.get(name, ()):
                if other not in reads:
                    reads.add(other)
                    via[other] = via.get(name, name)
                    if self.kinds.get(other) == "controller output":
                        pending.append(other)
        driven = {c.q: c.owner for c in self.coordinates if c.driver is not None}
        sensors = self.model.sensors
        bad = []
        for name in sorted(reads):
            kind = self.kinds[name]
            sensor = sensors.get(name) if kind == "sensor" else None
            if kind == "speed" or (sensor is not None and sensor.type in ("velocity", "joint_rate")):
                bad.append(f"{name} (a speed)" if kind == "speed" else f"{name} (a {sensor.type} sensor)")
            elif speed_law:
                continue        # a speed's law may read every coordinate (it stays in the state)
            elif kind == "coordinate" and name in driven:
                bad.append(f"{name} (its own coordinate)" if driven[name] == joint else
                           f"{name} (a coordinate prescribed by the driver of {driven[name]})")
            elif sensor is not None and sensor.type == "joint_angle" and sensor.joint in driven.values():
                bad.append(f"{name} (the coordinate of the driven joint {sensor.joint})")
            elif sensor is not None and sensor.type == "position" and self._moved_by(sensor.body, driven.values()):
                bad.append(f"{name} (a position on {sensor.body}, which the driven joint "
                           f"{self._moved_by(sensor.body, driven.values())} moves)")
        for ctrl in self.model.controllers.values():
            for state, rate in ctrl.states.items():
                if state in reads and not speed_law:
                    fast = sorted(n for n in self.used(f"controllers.{ctrl.name}.states.{state}", rate, "a rate")
                                  if self.kinds[n] == "speed" or (self.kinds[n] == "sensor" and sensors[n].type in
                                                                  ("velocity", "joint_rate")))
                    if fast:
                        bad.append(f"{state} (a controller state whose rate reads {', '.join(fast)})")
        bad = [f"{entry[:-1]}, through controller output {via[entry.split()[0]]!r})" if entry.split()[0] in via
               else entry for entry in bad]
        if bad and speed_law:
            raise ModelError(path, "a law of t, the parameters, coordinates, position sensors and controller states: "
                             "a driver prescribes its speed, whose rate is the law's time derivative; a law of the "
                             "speeds would need the accelerations u'", value,
                             f"uses {', '.join(bad)}; for feedback of speeds, drive the joint by a torque "
                             "(torque = ...) computed from them")
        if bad:
            raise ModelError(path, "a law of t, the parameters, the other coordinates, position sensors and "
                             "controller states whose rates read no speed: a driver prescribes its coordinate, whose "
                             "speed and acceleration are the law's first and second time derivatives; a law of the "
                             "speeds would need the accelerations u' (and u''), and a law of its own coordinate is "
                             "an equation, not a prescription", value,
                             f"uses {', '.join(bad)}; for feedback of speeds, drive the joint by a torque "
                             "(torque = ...) computed from them")
        return found

    def _moved_by(self, link: str, joints) -> str | None:
        """The first of ``joints`` on the path from the ground to ``link``, or None."""
        carriers = {j.child: j for j in self.model.joints.values()}
        seen = set()
        while link in carriers and link not in seen:
            seen.add(link)
            joint = carriers[link]
            if joint.name in joints:
                return joint.name
            link = joint.parent
        return None


def _listed(names, limit: int = 12) -> str:
    names = list(names)
    return ", ".join(names[:limit]) + (", ..." if len(names) > limit else "")


def _is_function(name: str) -> bool:
    from ..expression_syntax import RESERVED_NAMES

    return name in RESERVED_NAMES


def check_sensor(model, sensor, values, lengths: dict) -> None:
    """Check one sensor's fields and references (see :class:`~flexkane.model.parts.Sensor`)."""
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
            values.station(f"{path}.station", sensor.station, sensor.beam, lengths)
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
            values.station(f"{path}.station", sensor.station, sensor.body, lengths)
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
