"""Reading and writing model files (TOML).

The file has one table per kind of part, keyed by name::

    [parameters]            # name = number or "expression of other parameters"
    [bodies.NAME]           # mass, inertia, points = { P = [x, y] }, outline = [[x, y], ...]
    [beams.NAME]            # L, EI, rho, n_modes, shape = { family, roots, ... }, damping, ...
    [joints.NAME]           # type, parent, child, parent_point | parent_position | station, ...
    [gravity]               # g, direction
    [loads.NAME]            # body, point | station, force, torque, frame
    [springs.NAME]          # body_a, point_a | position_a, body_b, ..., stiffness, damping, rest_length
    [initial]               # coordinate or speed name = value
    [simulation]            # t_end, dt_out, rtol, atol, method

Reading checks the shape of the file (tables, keys, types) with messages that name the key path;
:func:`flexkane.model.validate.validate_model` then checks values and references.
"""

from __future__ import annotations

import difflib
import math
import tomllib
from pathlib import Path

import tomli_w

from ..errors import ModelError
from .model import Model
from .parts import (Beam, Driver, Gravity, Joint, Load, LoopConstraint, PointSpring, RigidBody,
                    ShapeSpec, Simulation)

__all__ = ["load_model", "loads_model", "dumps_model", "save_model", "MAX_FILE_BYTES"]

#: Largest model file accepted [bytes].
MAX_FILE_BYTES = 1_000_000

_TOP_KEYS = ("name", "description", "naming", "parameters", "bodies", "beams", "joints", "gravity",
             "loads", "springs", "constraints", "initial", "simulation", "sweep")


def _unknown(path: str, key: str, valid) -> ModelError:
    close = difflib.get_close_matches(key, list(valid), n=1, cutoff=0.5)
    hint = f"did you mean {close[0]!r}?" if close else f"valid keys: {', '.join(valid)}"
    return ModelError(f"{path}.{key}" if path else key, "a known key", key, hint)


def _check_keys(table: dict, valid, path: str) -> None:
    for key in table:
        if key not in valid:
            raise _unknown(path, key, valid)


def _table(parent: dict, key: str, path: str, required: bool = False) -> dict:
    value = parent.get(key, {} if not required else None)
    if value is None:
        raise ModelError(f"{path}.{key}" if path else key, "a table", None, show_given=False)
    if not isinstance(value, dict):
        raise ModelError(f"{path}.{key}" if path else key, "a table", value)
    return value


def _value(table: dict, key: str, path: str, required: bool = True, default=None):
    """A scalar field value: number or expression text."""
    if key not in table:
        if required:
            raise ModelError(f"{path}.{key}", "a value (number or expression)", None,
                             "missing", show_given=False)
        return default
    value = table[key]
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ModelError(f"{path}.{key}", "a number or an expression string", value)
    if isinstance(value, float) and not math.isfinite(value):
        raise ModelError(f"{path}.{key}", "a finite number", value)
    return value


def _pair(table: dict, key: str, path: str, required: bool = True):
    if key not in table:
        if required:
            raise ModelError(f"{path}.{key}", "a pair [x, y]", None, "missing", show_given=False)
        return None
    value = table[key]
    if not isinstance(value, list) or len(value) != 2:
        raise ModelError(f"{path}.{key}", "a pair [x, y]", value)
    for i, item in enumerate(value):
        _value({str(i): item}, str(i), f"{path}.{key}")
    return (value[0], value[1])


def _int(table: dict, key: str, path: str, default=None, required=False):
    if key not in table:
        if required:
            raise ModelError(f"{path}.{key}", "an integer", None, "missing", show_given=False)
        return default
    value = table[key]
    if isinstance(value, bool) or not isinstance(value, int):
        raise ModelError(f"{path}.{key}", "an integer", value)
    return value


def _str(table: dict, key: str, path: str, default=None, required=False, choices=None):
    if key not in table:
        if required:
            raise ModelError(f"{path}.{key}", "a string" + (f" (one of {', '.join(choices)})" if choices else ""),
                             None, "missing", show_given=False)
        return default
    value = table[key]
    if not isinstance(value, str):
        raise ModelError(f"{path}.{key}", "a string", value)
    if choices is not None and value not in choices:
        close = difflib.get_close_matches(value, list(choices), n=1, cutoff=0.5)
        raise ModelError(f"{path}.{key}", f"one of {', '.join(choices)}", value,
                         f"did you mean {close[0]!r}?" if close else None)
    return value


def _float(table: dict, key: str, path: str, default=None):
    if key not in table:
        return default
    value = table[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ModelError(f"{path}.{key}", "a finite number", value)
    return float(value)


def _names(table: dict, key: str, path: str):
    if key not in table:
        return None
    value = table[key]
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ModelError(f"{path}.{key}", "a list of names", value)
    return list(value)


def _shape(table: dict, key: str, path: str, default_family: str | None):
    if key not in table:
        return ShapeSpec(default_family) if default_family else None
    spec = table[key]
    sp = f"{path}.{key}"
    if isinstance(spec, str):
        return ShapeSpec(spec)
    if not isinstance(spec, dict):
        raise ModelError(sp, "a family name or a table { family = ... }", spec)
    family = _str(spec, "family", sp, required=True)
    roots = None
    if "roots" in spec:
        roots = spec["roots"]
        if not isinstance(roots, list) or not roots or not all(
                isinstance(r, (int, float)) and not isinstance(r, bool) for r in roots):
            raise ModelError(f"{sp}.roots", "a non-empty list of numbers", roots)
        roots = [float(r) for r in roots]
    options = {k: v for k, v in spec.items() if k not in ("family", "roots")}
    return ShapeSpec(family, roots, options)


_BODY_KEYS = ("mass", "inertia", "points", "outline")
_BEAM_KEYS = ("L", "EI", "rho", "n_modes", "shape", "damping", "gravity", "elastic_forces",
              "geometric_stiffening", "EA", "n_axial", "axial_shape")
_JOINT_KEYS = ("type", "parent", "child", "parent_point", "parent_position", "station", "child_point",
               "angle", "axis", "coordinates", "speeds", "stiffness", "damping", "rest", "torque", "driver")
_LOAD_KEYS = ("body", "point", "station", "force", "torque", "frame")
_SPRING_KEYS = ("body_a", "point_a", "position_a", "body_b", "point_b", "position_b", "stiffness",
                "damping", "rest_length")
_SIM_KEYS = ("t_end", "dt_out", "rtol", "atol", "method")
_CONSTRAINT_KEYS = ("type", "body_a", "point_a", "station_a", "position_a", "body_b", "point_b", "station_b",
                    "position_b", "axis", "angle", "dependent", "stabilization")


def _model_from_dict(data: dict) -> Model:
    from .model import NAMING_STYLES
    from .parts import ELASTIC_MODELS, FRAMES, GRAVITY_MODELS, JOINT_TYPES

    _check_keys(data, _TOP_KEYS, "")
    model = Model(name=_str(data, "name", "", default="model"),
                  description=_str(data, "description", "", default=""),
                  naming=_str(data, "naming", "", default="joint", choices=NAMING_STYLES))
    params = _table(data, "parameters", "")
    for key in params:
        model.parameters[key] = _value(params, key, "parameters")
    for name, body in _table(data, "bodies", "").items():
        path = f"bodies.{name}"
        if not isinstance(body, dict):
            raise ModelError(path, "a table", body)
        _check_keys(body, _BODY_KEYS, path)
        points = {}
        for pname in _table(body, "points", path):
            points[pname] = _pair(body["points"], pname, f"{path}.points")
        outline = []
        if "outline" in body:
            if not isinstance(body["outline"], list):
                raise ModelError(f"{path}.outline", "a list of [x, y] pairs", body["outline"])
            for i, _ in enumerate(body["outline"]):
                outline.append(_pair({str(i): body["outline"][i]}, str(i), f"{path}.outline"))
        model.bodies[name] = RigidBody(name, _value(body, "mass", path), _value(body, "inertia", path),
                                       points, outline)
    for name, beam in _table(data, "beams", "").items():
        path = f"beams.{name}"
        if not isinstance(beam, dict):
            raise ModelError(path, "a table", beam)
        _check_keys(beam, _BEAM_KEYS, path)
        damping = beam.get("damping", [])
        if not isinstance(damping, list):
            damping = [damping]
        for i, item in enumerate(damping):
            _value({str(i): item}, str(i), f"{path}.damping")
        stiff = beam.get("geometric_stiffening", False)
        if not isinstance(stiff, bool):
            raise ModelError(f"{path}.geometric_stiffening", "true or false", stiff)
        n_axial = _int(beam, "n_axial", path, default=0)
        model.beams[name] = Beam(
            name, _value(beam, "L", path), _value(beam, "EI", path), _value(beam, "rho", path),
            _int(beam, "n_modes", path, required=True),
            shape=_shape(beam, "shape", path, "clamped-free"), damping=damping,
            gravity=_str(beam, "gravity", path, default="distributed", choices=GRAVITY_MODELS),
            elastic_forces=_str(beam, "elastic_forces", path, default="strain-energy",
                                choices=ELASTIC_MODELS),
            geometric_stiffening=stiff, EA=_value(beam, "EA", path, required=False),
            n_axial=n_axial,
            axial_shape=_shape(beam, "axial_shape", path, "axial-fixed-free" if n_axial else None))
    for name, joint in _table(data, "joints", "").items():
        path = f"joints.{name}"
        if not isinstance(joint, dict):
            raise ModelError(path, "a table", joint)
        _check_keys(joint, _JOINT_KEYS, path)
        driver = None
        if "driver" in joint:
            dt = _table(joint, "driver", path)
            _check_keys(dt, ("coordinate", "speed"), f"{path}.driver")
            driver = Driver(_value(dt, "coordinate", f"{path}.driver", required=False),
                            _value(dt, "speed", f"{path}.driver", required=False))
        model.joints[name] = Joint(
            name, _str(joint, "type", path, required=True, choices=JOINT_TYPES),
            _str(joint, "parent", path, required=True), _str(joint, "child", path, required=True),
            parent_point=_str(joint, "parent_point", path),
            parent_position=_pair(joint, "parent_position", path, required=False),
            station=_value(joint, "station", path, required=False),
            child_point=_str(joint, "child_point", path),
            angle=_value(joint, "angle", path, required=False, default=0),
            axis=_value(joint, "axis", path, required=False, default=0),
            coordinates=_names(joint, "coordinates", path), speeds=_names(joint, "speeds", path),
            stiffness=_value(joint, "stiffness", path, required=False),
            damping=_value(joint, "damping", path, required=False),
            rest=_value(joint, "rest", path, required=False, default=0),
            torque=_value(joint, "torque", path, required=False), driver=driver)
    if "gravity" in data:
        grav = _table(data, "gravity", "")
        _check_keys(grav, ("g", "direction"), "gravity")
        direction = _pair(grav, "direction", "gravity")
        if any(isinstance(c, str) for c in direction):
            raise ModelError("gravity.direction", "two numbers [x, y] (the direction is structural)",
                             list(direction))
        model.gravity = Gravity(_value(grav, "g", "gravity"), direction)
    for name, load in _table(data, "loads", "").items():
        path = f"loads.{name}"
        if not isinstance(load, dict):
            raise ModelError(path, "a table", load)
        _check_keys(load, _LOAD_KEYS, path)
        model.loads[name] = Load(name, _str(load, "body", path, required=True),
                                 point=_str(load, "point", path),
                                 station=_value(load, "station", path, required=False),
                                 force=_pair(load, "force", path, required=False),
                                 torque=_value(load, "torque", path, required=False),
                                 frame=_str(load, "frame", path, default="ground", choices=FRAMES))
    for name, spring in _table(data, "springs", "").items():
        path = f"springs.{name}"
        if not isinstance(spring, dict):
            raise ModelError(path, "a table", spring)
        _check_keys(spring, _SPRING_KEYS, path)
        model.springs[name] = PointSpring(
            name, _str(spring, "body_a", path, required=True), _str(spring, "body_b", path, required=True),
            point_a=_str(spring, "point_a", path), point_b=_str(spring, "point_b", path),
            position_a=_pair(spring, "position_a", path, required=False),
            position_b=_pair(spring, "position_b", path, required=False),
            stiffness=_value(spring, "stiffness", path, required=False, default=0),
            damping=_value(spring, "damping", path, required=False, default=0),
            rest_length=_value(spring, "rest_length", path, required=False, default=0))
    for name, con in _table(data, "constraints", "").items():
        path = f"constraints.{name}"
        if not isinstance(con, dict):
            raise ModelError(path, "a table", con)
        _check_keys(con, _CONSTRAINT_KEYS, path)
        stab = _float(con, "stabilization", path, 0.0)
        if stab < 0:
            raise ModelError(f"{path}.stabilization", "a non-negative rate [1/s]", stab)
        model.constraints[name] = LoopConstraint(
            name, _str(con, "type", path, required=True, choices=("revolute", "prismatic")),
            _str(con, "body_a", path, required=True), _str(con, "body_b", path, required=True),
            point_a=_str(con, "point_a", path), point_b=_str(con, "point_b", path),
            station_a=_value(con, "station_a", path, required=False),
            station_b=_value(con, "station_b", path, required=False),
            position_a=_pair(con, "position_a", path, required=False),
            position_b=_pair(con, "position_b", path, required=False),
            axis=_value(con, "axis", path, required=False, default=0),
            angle=_value(con, "angle", path, required=False, default=0),
            dependent=_names(con, "dependent", path), stabilization=stab)
    initial = _table(data, "initial", "")
    for key in initial:
        model.initial[key] = _value(initial, key, "initial")
    sim = _table(data, "simulation", "")
    _check_keys(sim, _SIM_KEYS, "simulation")
    model.simulation = Simulation(_float(sim, "t_end", "simulation"), _float(sim, "dt_out", "simulation"),
                                  _float(sim, "rtol", "simulation", 1e-8),
                                  _float(sim, "atol", "simulation", 1e-10),
                                  _str(sim, "method", "simulation", default="auto"))
    return model


def loads_model(text: str, *, source: str = "<string>") -> Model:
    """Parse a model from TOML text.

    Parameters
    ----------
    text : str
        The file's content.
    source : str
        Where it came from, for messages.

    Returns
    -------
    Model
        The model, validated.
    """
    if len(text.encode("utf-8", "replace")) > MAX_FILE_BYTES:
        raise ModelError(source, f"a model file of at most {MAX_FILE_BYTES} bytes",
                         f"{len(text)} characters")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ModelError(source, "valid TOML", str(exc)) from None
    return _model_from_dict(data).validate()


def load_model(path: str | Path) -> Model:
    """Read and validate a model file.

    Parameters
    ----------
    path : str or Path
        Path of a TOML model file.
    """
    path = Path(path)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise ModelError("MODEL", "a readable model file", str(path), exc.strerror) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise ModelError(str(path), "a UTF-8 text file", "undecodable bytes") from None
    return loads_model(text, source=str(path))


def _shape_out(spec: ShapeSpec):
    if spec.roots is None and not spec.options:
        return spec.family
    out = {"family": spec.family}
    if spec.roots is not None:
        out["roots"] = list(spec.roots)
    out.update(spec.options)
    return out


def _drop_none(table: dict) -> dict:
    return {k: (list(v) if isinstance(v, tuple) else v) for k, v in table.items() if v is not None}


def model_to_dict(model: Model) -> dict:
    """The model as nested dictionaries in the model-file layout."""
    out: dict = {"name": model.name}
    if model.description:
        out["description"] = model.description
    if model.naming != "joint":
        out["naming"] = model.naming
    if model.parameters:
        out["parameters"] = dict(model.parameters)
    out["bodies"] = {b.name: _drop_none({"mass": b.mass, "inertia": b.inertia,
                                         "points": {k: list(v) for k, v in b.points.items()} or None,
                                         "outline": [list(p) for p in b.outline] or None})
                     for b in model.bodies.values()}
    beams = {}
    for b in model.beams.values():
        t = {"L": b.L, "EI": b.EI, "rho": b.rho, "n_modes": b.n_modes, "shape": _shape_out(b.shape)}
        if b.damping:
            t["damping"] = list(b.damping)
        if b.gravity != "distributed":
            t["gravity"] = b.gravity
        if b.elastic_forces != "strain-energy":
            t["elastic_forces"] = b.elastic_forces
        if b.geometric_stiffening:
            t["geometric_stiffening"] = True
        if b.EA is not None:
            t["EA"] = b.EA
        if b.n_axial:
            t["n_axial"] = b.n_axial
            t["axial_shape"] = _shape_out(b.axial_shape)
        beams[b.name] = t
    if beams:
        out["beams"] = beams
    joints = {}
    for j in model.joints.values():
        t = _drop_none({"type": j.type, "parent": j.parent, "child": j.child,
                        "parent_point": j.parent_point, "parent_position": j.parent_position,
                        "station": j.station, "child_point": j.child_point,
                        "coordinates": j.coordinates, "speeds": j.speeds,
                        "stiffness": j.stiffness, "damping": j.damping, "torque": j.torque})
        if j.angle != 0:
            t["angle"] = j.angle
        if j.axis != 0:
            t["axis"] = j.axis
        if j.rest != 0:
            t["rest"] = j.rest
        if j.driver is not None:
            t["driver"] = _drop_none({"coordinate": j.driver.coordinate, "speed": j.driver.speed})
        joints[j.name] = t
    out["joints"] = joints
    if model.gravity is not None:
        out["gravity"] = {"g": model.gravity.g, "direction": list(model.gravity.direction)}
    if model.loads:
        out["loads"] = {ld.name: _drop_none({"body": ld.body, "point": ld.point, "station": ld.station,
                                             "force": ld.force, "torque": ld.torque,
                                             "frame": ld.frame}) for ld in model.loads.values()}
    if model.springs:
        out["springs"] = {s.name: _drop_none({
            "body_a": s.body_a, "point_a": s.point_a, "position_a": s.position_a,
            "body_b": s.body_b, "point_b": s.point_b, "position_b": s.position_b,
            "stiffness": s.stiffness, "damping": s.damping, "rest_length": s.rest_length})
            for s in model.springs.values()}
    if model.constraints:
        cons = {}
        for c in model.constraints.values():
            t = _drop_none({"type": c.type, "body_a": c.body_a, "point_a": c.point_a, "station_a": c.station_a,
                            "position_a": c.position_a, "body_b": c.body_b, "point_b": c.point_b,
                            "station_b": c.station_b, "position_b": c.position_b, "dependent": c.dependent})
            if c.axis != 0:
                t["axis"] = c.axis
            if c.angle != 0:
                t["angle"] = c.angle
            if c.stabilization:
                t["stabilization"] = c.stabilization
            cons[c.name] = t
        out["constraints"] = cons
    if model.initial:
        out["initial"] = dict(model.initial)
    sim = _drop_none({"t_end": model.simulation.t_end, "dt_out": model.simulation.dt_out,
                      "rtol": model.simulation.rtol, "atol": model.simulation.atol,
                      "method": model.simulation.method})
    out["simulation"] = sim
    return out


def dumps_model(model: Model) -> str:
    """The model as TOML text; :func:`loads_model` of it gives an equivalent model."""
    return tomli_w.dumps(model_to_dict(model))


def save_model(model: Model, path: str | Path) -> None:
    """Write the model file atomically."""
    from ..atomic import atomic_write_text

    atomic_write_text(Path(path), dumps_model(model))
