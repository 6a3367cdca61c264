"""Reading and writing model files (TOML).

The file has one table per kind of part, keyed by name::

    dimensions = 3          # a spatial model (2, the default, is planar)
    [parameters]            # name = number or "expression of other parameters"
    [bodies.NAME]           # mass, inertia, points = { P = [x, y] }, outline = [[x, y], ...]
    [beams.NAME]            # L, EI, rho, n_modes, shape = { family, roots, ... }, damping, ...
    [joints.NAME]           # type, parent, child, parent_point | parent_position | station, ...
    [gravity]               # g, direction
    [loads.NAME]            # body, point | station, force, torque, frame
    [distributed_loads.NAME]  # beam, fx, fy, fz (3D) (expressions of x, t), frame, quadrature_nodes
    [springs.NAME]          # body_a, point_a | station_a | position_a, body_b, ..., stiffness, damping, rest_length
    [constraints.NAME]      # loop-closure joints: type, body_a, point_a | station_a | position_a, ...
    [sensors.NAME]          # type, beam | body, point | station, joint, distance, frame, component
    [controllers.NAME]      # states = { z = "rate" }, initial = { z = value }, output, min, max
    [initial]               # coordinate or speed name = value
    [simulation]            # t_end, dt_out, rtol, atol, method, max_steps, deflection_warning, spin_warning
    [sweep]                 # read by flexkane.sweep, ignored here

In a spatial model vectors have three components, a body's ``inertia`` is three principal values or
a 3 x 3 tensor, a joint has ``axis = [ax, ay, az]`` (or ``axes`` for a universal joint) and
``orientation`` / ``child_orientation`` tables (:func:`flexkane.model.file_layout.orientation_from_table`),
a load's ``torque`` is a vector.

Reading checks the layout of the file: tables where tables belong, no unknown key (a typo is
reported with the nearest valid key), every required key present. Values are kept as given (a
number or the text of an expression); :func:`flexkane.model.validate.validate_model` then checks
their types and ranges with the unit of each field, and every reference, so that a model built in
Python gets the same checks.
"""

from __future__ import annotations

import dataclasses
import difflib
import numbers
import tomllib
from pathlib import Path

import tomli_w

from ..errors import ModelError
from .file_layout import (BEAM_KEYS, BODY_KEYS, CONSTRAINT_KEYS, CONTROLLER_KEYS, DISTRIBUTED_KEYS, DRIVER_KEYS,
                          GRAVITY_KEYS, JOINT_KEYS, LOAD_KEYS, SENSOR_KEYS, SHAPE_KEYS, SIM_KEYS, SPATIAL_BEAM_KEYS,
                          SPRING_KEYS, TOP_KEYS, orientation_from_table)
from .model import Model
from .parts import (SENSOR_TYPES, Beam, Controller, DistributedLoad, Driver, Gravity, Joint, Load, LoopConstraint,
                    PointSpring, RigidBody, Sensor, ShapeSpec, Simulation)

__all__ = ["load_model", "loads_model", "dumps_model", "save_model", "model_to_dict", "MAX_FILE_BYTES"]

#: Largest model file accepted [bytes].
MAX_FILE_BYTES = 1_000_000

_MISSING = object()


def _join(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key


def _check_keys(table: dict, valid, path: str) -> None:
    for key in table:
        if key not in valid:
            close = difflib.get_close_matches(key, list(valid), n=1, cutoff=0.5)
            hint = f"did you mean {close[0]!r}?" if close else f"valid keys: {', '.join(valid)}"
            raise ModelError(_join(path, key), "a known key", key, hint)


def _table(parent: dict, key: str, path: str, what: str = "a table") -> dict:
    """A sub-table (empty when absent)."""
    value = parent.get(key, {})
    if not isinstance(value, dict):
        raise ModelError(_join(path, key), what, value)
    return value


def _parts(data: dict, kind: str, keys) -> dict[str, dict]:
    """The tables of one kind of part, ``[kind.NAME]``, each checked for unknown keys."""
    out = {}
    for name, table in _table(data, kind, "", f"a table of parts [{kind}.NAME]").items():
        if not isinstance(table, dict):
            raise ModelError(f"{kind}.{name}", f"a table [{kind}.{name}] of keys {', '.join(keys)}", table)
        _check_keys(table, keys, f"{kind}.{name}")
        out[name] = table
    return out


def _get(table: dict, key: str, path: str, expected: str | None = None, default=None):
    """A field as given; ``expected`` (what to write, with the unit) makes it required."""
    if key in table:
        return table[key]
    if expected is not None:
        raise ModelError(_join(path, key), expected, None, "missing", show_given=False)
    return default


def _pair(table: dict, key: str, path: str, expected: str | None = None):
    """A pair [x, y] as a tuple (other values are kept as given, for the validation to report)."""
    value = _get(table, key, path, expected)
    return tuple(value) if isinstance(value, list) else value


def _shape(table: dict, key: str, path: str, default_family: str | None):
    if key not in table:
        return ShapeSpec(default_family) if default_family else None
    spec = table[key]
    shape_path = f"{path}.{key}"
    if isinstance(spec, str):
        return ShapeSpec(spec)
    if not isinstance(spec, dict):
        raise ModelError(shape_path, "a family name or a table { family = ..., options }", spec)
    family = _get(spec, "family", shape_path, "the name of a shape-function family")
    roots = spec.get("roots")
    if isinstance(roots, list) and all(isinstance(r, numbers.Real) and not isinstance(r, bool) for r in roots):
        roots = [float(r) for r in roots]
    options = {k: v for k, v in spec.items() if k not in SHAPE_KEYS}
    return ShapeSpec(family, roots, options)


def _spatial_beam(name: str, beam: dict, path: str) -> Beam:
    """A beam of a spatial model: bending in two principal planes, torsion, axial stretch."""
    damping = beam.get("damping", [])
    n_y, n_z = beam.get("n_modes_y", 0), beam.get("n_modes_z", 0)
    n_torsion, n_axial = beam.get("n_torsion", 0), beam.get("n_axial", 0)
    return Beam(
        name, _get(beam, "L", path, "the length [m]"), None, _get(beam, "rho", path, "the mass per unit length [kg/m]"),
        0, damping=damping if isinstance(damping, list) else [damping],
        gravity=beam.get("gravity", "distributed"), geometric_stiffening=beam.get("geometric_stiffening", False),
        EA=beam.get("EA"), n_axial=n_axial,
        axial_shape=_shape(beam, "axial_shape", path, "axial-fixed-free" if n_axial else None),
        rotary_inertia=beam.get("rotary_inertia"),
        EI_y=_get(beam, "EI_y", path, "the flexural rigidity about the section's y axis [N m^2]"),
        EI_z=_get(beam, "EI_z", path, "the flexural rigidity about the section's z axis [N m^2]"),
        n_modes_y=n_y, n_modes_z=n_z, shape_y=_shape(beam, "shape_y", path, "clamped-free"),
        shape_z=_shape(beam, "shape_z", path, "clamped-free"), GJ=beam.get("GJ"), rho_Ip=beam.get("rho_Ip"),
        n_torsion=n_torsion,
        torsion_shape=_shape(beam, "torsion_shape", path, "torsion-clamped-free" if n_torsion else None),
        principal_angle=beam.get("principal_angle"), rho_Iy=beam.get("rho_Iy"), rho_Iz=beam.get("rho_Iz"),
        static_corrections=beam.get("static_corrections", True),
        **{key: _ratios(beam.get(key, [])) for key in ("damping_y", "damping_z", "torsion_damping", "axial_damping")})


def _ratios(value):
    """A list of modal damping ratios as given (one value: a list of it)."""
    return value if isinstance(value, list) else [value]


def _vectors(value):
    """Lists (of lists) as tuples, to any depth (other values are kept for the validation)."""
    if isinstance(value, list):
        return tuple(_vectors(v) for v in value)
    return value


def _float(table: dict, key: str, default=None):
    value = table.get(key, default)
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return float(value)
    return value


def _model_from_dict(data: dict) -> Model:
    _check_keys(data, TOP_KEYS, "")
    model = Model(name=_get(data, "name", "", default="model"),
                  description=_get(data, "description", "", default=""),
                  naming=_get(data, "naming", "", default="joint"),
                  dimensions=_get(data, "dimensions", "", default=2))
    spatial = model.dimensions == 3
    model.parameters.update(_table(data, "parameters", "", "a table of parameters { name = value }"))
    for name, body in _parts(data, "bodies", BODY_KEYS).items():
        path = f"bodies.{name}"
        points = {pname: _pair(body["points"], pname, f"{path}.points")
                  for pname in _table(body, "points", path, "a table of named points { P = [x, y] } [m]")}
        outline = body.get("outline", [])
        if isinstance(outline, list):
            outline = [tuple(v) if isinstance(v, list) else v for v in outline]
        inertia = _get(body, "inertia", path, "the inertia tensor about the mass centre, [Ixx, Iyy, Izz] or "
                       "[[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]] [kg m^2]" if spatial else
                       "the moment of inertia about the mass centre [kg m^2]")
        model.bodies[name] = RigidBody(name, _get(body, "mass", path, "the mass [kg]"), _vectors(inertia),
                                       points, outline)
    for name, beam in _parts(data, "beams", SPATIAL_BEAM_KEYS if spatial else BEAM_KEYS).items():
        path = f"beams.{name}"
        if spatial:
            model.beams[name] = _spatial_beam(name, beam, path)
            continue
        damping = beam.get("damping", [])
        n_axial = beam.get("n_axial", 0)
        model.beams[name] = Beam(
            name, _get(beam, "L", path, "the length [m]"), _get(beam, "EI", path, "the flexural rigidity [N m^2]"),
            _get(beam, "rho", path, "the mass per unit length [kg/m]"),
            _get(beam, "n_modes", path, "the number of shape functions, a positive integer"),
            shape=_shape(beam, "shape", path, "clamped-free"),
            damping=damping if isinstance(damping, list) else [damping],
            gravity=beam.get("gravity", "distributed"), elastic_forces=beam.get("elastic_forces", "strain-energy"),
            geometric_stiffening=beam.get("geometric_stiffening", False), EA=beam.get("EA"), n_axial=n_axial,
            axial_shape=_shape(beam, "axial_shape", path, "axial-fixed-free" if n_axial else None),
            rotary_inertia=beam.get("rotary_inertia"), static_corrections=beam.get("static_corrections", True))
    for name, joint in _parts(data, "joints", JOINT_KEYS).items():
        path = f"joints.{name}"
        driver = None
        if "driver" in joint:
            table = _table(joint, "driver", path, "a table { coordinate = ... } or { speed = ... }")
            _check_keys(table, DRIVER_KEYS, f"{path}.driver")
            driver = Driver(table.get("coordinate"), table.get("speed"))
        axes = joint.get("axes")
        orientations = {key: orientation_from_table(joint[key], f"{path}.{key}") if key in joint else None
                        for key in ("orientation", "child_orientation")}
        model.joints[name] = Joint(
            name, _get(joint, "type", path, "the joint type (free, revolute, prismatic or weld)"),
            _get(joint, "parent", path, "the parent: 'ground', a body or a beam"),
            _get(joint, "child", path, "the child: a body or a beam"),
            parent_point=joint.get("parent_point"), parent_position=_pair(joint, "parent_position", path),
            station=joint.get("station"), child_point=joint.get("child_point"),
            angle=joint.get("angle", 0), axis=_vectors(joint.get("axis", 0)),
            coordinates=joint.get("coordinates"), speeds=joint.get("speeds"),
            stiffness=joint.get("stiffness"), damping=joint.get("damping"), rest=joint.get("rest", 0),
            torque=joint.get("torque"), driver=driver,
            axes=[_vectors(a) for a in axes] if isinstance(axes, list) else axes, **orientations)
    if "gravity" in data:
        grav = _table(data, "gravity", "", "a table { g = ..., direction = [x, y] }")
        _check_keys(grav, GRAVITY_KEYS, "gravity")
        model.gravity = Gravity(_get(grav, "g", "gravity", "the gravitational acceleration [m/s^2]"),
                                _pair(grav, "direction", "gravity", "a direction [x, y] in the ground frame"))
    for name, load in _parts(data, "loads", LOAD_KEYS).items():
        path = f"loads.{name}"
        model.loads[name] = Load(name, _get(load, "body", path, "the name of a body or a beam"),
                                 point=load.get("point"), station=load.get("station"),
                                 force=_pair(load, "force", path), torque=_vectors(load.get("torque")),
                                 frame=load.get("frame", "ground"))
    for name, table in _parts(data, "distributed_loads", DISTRIBUTED_KEYS + (("fz",) if spatial else ())).items():
        path = f"distributed_loads.{name}"
        model.distributed_loads[name] = DistributedLoad(
            name, _get(table, "beam", path, "the name of the loaded beam"), fx=table.get("fx", 0),
            fy=table.get("fy", 0), fz=table.get("fz", 0), frame=table.get("frame", "beam"),
            quadrature_nodes=table.get("quadrature_nodes", DistributedLoad.quadrature_nodes))
    for name, spring in _parts(data, "springs", SPRING_KEYS).items():
        path = f"springs.{name}"
        model.springs[name] = PointSpring(
            name, _get(spring, "body_a", path, "'ground', a body or a beam"),
            _get(spring, "body_b", path, "'ground', a body or a beam"),
            point_a=spring.get("point_a"), point_b=spring.get("point_b"),
            position_a=_pair(spring, "position_a", path), position_b=_pair(spring, "position_b", path),
            stiffness=spring.get("stiffness", 0), damping=spring.get("damping", 0),
            rest_length=spring.get("rest_length", 0),
            station_a=spring.get("station_a"), station_b=spring.get("station_b"))
    for name, con in _parts(data, "constraints", CONSTRAINT_KEYS).items():
        path = f"constraints.{name}"
        model.constraints[name] = LoopConstraint(
            name, _get(con, "type", path, "the loop joint type (revolute or prismatic)"),
            _get(con, "body_a", path, "'ground', a body or a beam"), _get(con, "body_b", path, "'ground', a body or a beam"),
            point_a=con.get("point_a"), point_b=con.get("point_b"),
            station_a=con.get("station_a"), station_b=con.get("station_b"),
            position_a=_pair(con, "position_a", path), position_b=_pair(con, "position_b", path),
            axis=_vectors(con.get("axis", 0)), angle=con.get("angle", 0), dependent=con.get("dependent"),
            stabilization=_float(con, "stabilization", 0.0),
            orientation=(orientation_from_table(con["orientation"], f"{path}.orientation")
                         if "orientation" in con else None))
    for name, table in _parts(data, "sensors", SENSOR_KEYS).items():
        model.sensors[name] = Sensor(
            name, _get(table, "type", f"sensors.{name}", "the kind of sensor (" + ", ".join(SENSOR_TYPES) + ")"),
            **{key: table.get(key) for key in SENSOR_KEYS if key not in ("type", "frame")},
            frame=table.get("frame", "ground"))
    for name, table in _parts(data, "controllers", CONTROLLER_KEYS).items():
        path = f"controllers.{name}"
        model.controllers[name] = Controller(
            name, states=_table(table, "states", path, "a table of state rates { z = \"expression\" }"),
            initial=_table(table, "initial", path, "a table of initial values { z = value }"),
            output=table.get("output"), min=table.get("min"), max=table.get("max"))
    model.initial.update(_table(data, "initial", "", "a table of initial values { q_name = value }"))
    sim = _table(data, "simulation", "", "a table of run settings")
    _check_keys(sim, SIM_KEYS, "simulation")
    model.simulation = Simulation(_float(sim, "t_end"), _float(sim, "dt_out"), _float(sim, "rtol", 1e-8),
                                  _float(sim, "atol", 1e-10), sim.get("method", "auto"), sim.get("max_steps"),
                                  _float(sim, "deflection_warning", Simulation.deflection_warning),
                                  _float(sim, "spin_warning", Simulation.spin_warning))
    return model


def loads_model(text: str, *, source: str = "<string>") -> Model:
    """Parse and validate a model from TOML text.

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
    if not isinstance(text, str):
        raise ModelError(source if isinstance(source, str) else "text", "the text of a model file (str)",
                         type(text).__name__)
    if len(text.encode("utf-8", "replace")) > MAX_FILE_BYTES:
        raise ModelError(source, f"a model file of at most {MAX_FILE_BYTES} bytes", f"{len(text)} characters")
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
    if not isinstance(path, (str, Path)):
        raise ModelError("MODEL", "the path of a model file", type(path).__name__)
    path = Path(path)
    try:
        if path.stat().st_size > MAX_FILE_BYTES:
            raise ModelError(str(path), f"a model file of at most {MAX_FILE_BYTES} bytes",
                             f"{path.stat().st_size} bytes")
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


def _spatial_beam_out(b: Beam) -> dict:
    """A spatial beam in the model-file layout."""
    t = _drop_none({"L": b.L, "rho": b.rho, "EI_y": b.EI_y, "EI_z": b.EI_z, "GJ": b.GJ, "rho_Ip": b.rho_Ip,
                    "EA": b.EA, "principal_angle": b.principal_angle, "rotary_inertia": b.rotary_inertia,
                    "rho_Iy": b.rho_Iy, "rho_Iz": b.rho_Iz})
    for key, count, shape in (("y", b.n_modes_y, b.shape_y), ("z", b.n_modes_z, b.shape_z)):
        if count:
            t[f"n_modes_{key}"] = count
            t[f"shape_{key}"] = _shape_out(shape)
    for key, count, shape in (("torsion", b.n_torsion, b.torsion_shape), ("axial", b.n_axial, b.axial_shape)):
        if count:
            t[f"n_{key}"] = count
            t[f"{key}_shape"] = _shape_out(shape)
    if b.damping:
        t["damping"] = list(b.damping)
    for key in ("damping_y", "damping_z", "torsion_damping", "axial_damping"):
        if getattr(b, key):
            t[key] = list(getattr(b, key))
    if b.gravity != "distributed":
        t["gravity"] = b.gravity
    if b.geometric_stiffening:
        t["geometric_stiffening"] = True
    if b.static_corrections is not True:
        t["static_corrections"] = b.static_corrections
    return t


def _drop_none(table: dict) -> dict:
    return {k: (list(v) if isinstance(v, tuple) else v) for k, v in table.items() if v is not None}


def model_to_dict(model: Model) -> dict:
    """The model as nested dictionaries in the model-file layout."""
    out: dict = {"name": model.name}
    if model.dimensions != 2:
        out["dimensions"] = model.dimensions
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
        if model.dimensions == 3:
            beams[b.name] = _spatial_beam_out(b)
            continue
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
        if b.rotary_inertia is not None:
            t["rotary_inertia"] = b.rotary_inertia
        if b.static_corrections is not True:
            t["static_corrections"] = b.static_corrections
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
        if j.axes is not None:
            t["axes"] = j.axes
        for key in ("orientation", "child_orientation"):
            spec = getattr(j, key)
            if spec is not None:
                t[key] = _drop_none(dataclasses.asdict(spec)) if dataclasses.is_dataclass(spec) else spec
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
    if model.distributed_loads:
        loads = {}
        for d in model.distributed_loads.values():
            t = {"beam": d.beam, "fx": d.fx, "fy": d.fy, "fz": d.fz, "frame": d.frame,
                 "quadrature_nodes": d.quadrature_nodes}
            for key in ("fx", "fy", "fz", "quadrature_nodes"):
                if t[key] == getattr(DistributedLoad, key):
                    del t[key]
            loads[d.name] = t
        out["distributed_loads"] = loads
    if model.springs:
        out["springs"] = {s.name: _drop_none({
            "body_a": s.body_a, "point_a": s.point_a, "station_a": s.station_a, "position_a": s.position_a,
            "body_b": s.body_b, "point_b": s.point_b, "station_b": s.station_b, "position_b": s.position_b,
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
            if c.orientation is not None:
                t["orientation"] = _drop_none(dataclasses.asdict(c.orientation))
            cons[c.name] = t
        out["constraints"] = cons
    if model.sensors:
        out["sensors"] = {s.name: _drop_none({"type": s.type, "beam": s.beam, "body": s.body, "point": s.point,
                                              "joint": s.joint, "station": s.station, "distance": s.distance,
                                              "frame": None if s.frame == "ground" else s.frame,
                                              "component": s.component})
                          for s in model.sensors.values()}
    if model.controllers:
        out["controllers"] = {c.name: _drop_none({"states": dict(c.states) if c.states else None,
                                                  "initial": dict(c.initial) if c.initial else None,
                                                  "output": c.output, "min": c.min, "max": c.max})
                              for c in model.controllers.values()}
    if model.initial:
        out["initial"] = dict(model.initial)
    sim = _drop_none({"t_end": model.simulation.t_end, "dt_out": model.simulation.dt_out,
                      "rtol": model.simulation.rtol, "atol": model.simulation.atol,
                      "method": model.simulation.method, "max_steps": model.simulation.max_steps})
    for key in ("deflection_warning", "spin_warning"):
        if getattr(model.simulation, key) != getattr(Simulation, key):
            sim[key] = getattr(model.simulation, key)
    out["simulation"] = sim
    return out


def _plain(value):
    """Tables, lists and numbers as TOML writes them (NumPy scalars and tuples converted)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, bool) or isinstance(value, str):
        return value
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    return value


def dumps_model(model: Model) -> str:
    """The model as TOML text; :func:`loads_model` of it gives an equivalent model."""
    return tomli_w.dumps(_plain(model_to_dict(model)))


def save_model(model: Model, path: str | Path) -> None:
    """Write the model file atomically."""
    from ..atomic import atomic_write_text

    if not isinstance(path, (str, Path)):
        raise ModelError("path", "the path of the model file to write", type(path).__name__)
    text = dumps_model(model)
    try:
        atomic_write_text(Path(path), text)
    except OSError as exc:
        raise ModelError("path", "a writable model file path", str(path), exc.strerror or str(exc)) from None
