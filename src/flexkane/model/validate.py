"""Validation of a model's values and references, before anything is derived.

Each problem raises :class:`~flexkane.errors.ModelError` naming the key path, what was expected
(with the unit) and what was given.
"""

from __future__ import annotations

import math

from ..errors import ModelError
from .model import Model
from .parts import JOINT_DOFS

__all__ = ["validate_model", "MAX_MODES"]

MAX_MODES = 200


def _numeric(model: Model, path: str, value, params: dict[str, float], *, allow_t=False) -> float | None:
    """Evaluate a constant field for range checks (None when it depends on t)."""
    from ..expressions import parse_expression

    import sympy as sp

    names = {k: sp.Symbol(k, real=True) for k in model.parameters}
    if allow_t:
        names["t"] = sp.Symbol("t", real=True)
    expr = parse_expression(value, names, path=path)
    if allow_t and expr.has(names["t"]):
        return None
    subs = {names[k]: v for k, v in params.items()}
    number = complex(expr.subs(subs).evalf())
    if number.imag != 0 or not math.isfinite(number.real):
        raise ModelError(path, "a finite real value", value)
    return number.real


def _positive(model, path, value, params, unit):
    number = _numeric(model, path, value, params)
    if not number > 0:
        raise ModelError(path, f"a positive value [{unit}]", value if number == value else f"{value} = {number:g}")
    return number


def _non_negative(model, path, value, params, unit):
    number = _numeric(model, path, value, params)
    if number < 0:
        raise ModelError(path, f"a non-negative value [{unit}]", value if number == value else f"{value} = {number:g}")
    return number


def validate_model(model: Model) -> None:
    """Check a model; raise :class:`ModelError` on the first problem found."""
    from ..expressions import resolve_parameters

    params = resolve_parameters(model.parameters, path_prefix="parameters")
    names = set()
    for kind, table in (("bodies", model.bodies), ("beams", model.beams)):
        for key, part in table.items():
            if key == "ground":
                raise ModelError(f"{kind}.{key}", "a name other than 'ground'", key)
            if key in names:
                raise ModelError(f"{kind}.{key}", "a name unique among bodies and beams", key)
            names.add(key)
    if not names:
        raise ModelError("bodies", "at least one body or beam", None, show_given=False)
    for body in model.bodies.values():
        path = f"bodies.{body.name}"
        _positive(model, f"{path}.mass", body.mass, params, "kg")
        _non_negative(model, f"{path}.inertia", body.inertia, params, "kg m^2")
        for pname, (x, y) in body.points.items():
            _numeric(model, f"{path}.points.{pname}[0]", x, params)
            _numeric(model, f"{path}.points.{pname}[1]", y, params)
    for beam in model.beams.values():
        path = f"beams.{beam.name}"
        length = _positive(model, f"{path}.L", beam.L, params, "m")
        _positive(model, f"{path}.EI", beam.EI, params, "N m^2")
        _positive(model, f"{path}.rho", beam.rho, params, "kg/m")
        if not 1 <= beam.n_modes <= MAX_MODES:
            raise ModelError(f"{path}.n_modes", f"an integer from 1 to {MAX_MODES}", beam.n_modes)
        if beam.shape.roots is not None and len(beam.shape.roots) != beam.n_modes:
            raise ModelError(f"{path}.shape.roots", f"{beam.n_modes} roots (one per mode)", beam.shape.roots)
        if beam.shape.roots is not None and any(not (r > 0 and math.isfinite(r)) for r in beam.shape.roots):
            raise ModelError(f"{path}.shape.roots", "positive finite numbers", beam.shape.roots)
        if beam.damping and len(beam.damping) not in (1, beam.n_modes):
            raise ModelError(f"{path}.damping", f"1 or {beam.n_modes} damping ratios", beam.damping)
        for i, zeta in enumerate(beam.damping):
            _non_negative(model, f"{path}.damping[{i}]", zeta, params, "-")
        if beam.n_axial < 0 or beam.n_axial > MAX_MODES:
            raise ModelError(f"{path}.n_axial", f"an integer from 0 to {MAX_MODES}", beam.n_axial)
        if beam.n_axial and beam.EA is None:
            raise ModelError(f"{path}.EA", "the axial stiffness [N] (required with n_axial > 0)", None,
                             show_given=False)
        if beam.EA is not None:
            _positive(model, f"{path}.EA", beam.EA, params, "N")
        if beam.elastic_forces == "shear-moment" and (beam.geometric_stiffening or beam.n_axial):
            raise ModelError(f"{path}.elastic_forces", "'strain-energy' with geometric_stiffening or axial modes",
                             beam.elastic_forces)
        beam._length = length  # used by station checks below
    _validate_joints(model, params)
    _validate_loads(model, params)
    _validate_constraints(model, params)
    if model.gravity is not None:
        _non_negative(model, "gravity.g", model.gravity.g, params, "m/s^2")
        dx = _numeric(model, "gravity.direction[0]", model.gravity.direction[0], params)
        dy = _numeric(model, "gravity.direction[1]", model.gravity.direction[1], params)
        if dx == 0 and dy == 0:
            raise ModelError("gravity.direction", "a non-zero direction [x, y]", list(model.gravity.direction))
    sim = model.simulation
    for key in ("t_end", "dt_out", "rtol", "atol"):
        value = getattr(sim, key)
        if value is not None and not value > 0:
            raise ModelError(f"simulation.{key}", "a positive number", value)
    for beam in model.beams.values():
        del beam._length


def _station(model, path, value, beam, params):
    x = _numeric(model, path, value, params)
    if not 0 <= x <= beam._length * (1 + 1e-12):
        raise ModelError(path, f"a station 0 <= x <= L = {beam._length:g} [m]", value)


def _validate_joints(model: Model, params) -> None:
    children: dict[str, str] = {}
    for joint in model.joints.values():
        path = f"joints.{joint.name}"
        if joint.child not in model.bodies and joint.child not in model.beams:
            raise ModelError(f"{path}.child", "the name of a body or a beam", joint.child,
                             _suggest(joint.child, model.link_names()))
        if joint.child in children:
            raise ModelError(f"{path}.child", "a link that no other joint has as child "
                             f"(joint {children[joint.child]!r} already does)", joint.child)
        children[joint.child] = joint.name
        if joint.parent == joint.child:
            raise ModelError(f"{path}.parent", "a link other than the child", joint.parent)
        if joint.parent != "ground" and joint.parent not in model.bodies and joint.parent not in model.beams:
            raise ModelError(f"{path}.parent", "'ground' or the name of a body or a beam", joint.parent,
                             _suggest(joint.parent, ["ground"] + model.link_names()))
        if joint.parent in model.bodies:
            body = model.bodies[joint.parent]
            if joint.parent_point is not None and joint.parent_point not in body.points:
                raise ModelError(f"{path}.parent_point", f"a point of body {body.name!r}"
                                 f" ({', '.join(body.points) or 'it has none'})", joint.parent_point)
            if joint.station is not None or joint.parent_position is not None:
                raise ModelError(path, "parent_point (not station or parent_position) on a body parent",
                                 joint.parent)
        elif joint.parent in model.beams:
            if joint.station is None:
                raise ModelError(f"{path}.station", "the station x on the parent beam [m]", None,
                                 show_given=False)
            _station(model, f"{path}.station", joint.station, model.beams[joint.parent], params)
            if joint.parent_point is not None:
                raise ModelError(f"{path}.parent_point", "no point on a beam parent (use station)",
                                 joint.parent_point)
        else:
            if joint.parent_point is not None or joint.station is not None:
                raise ModelError(path, "parent_position (not parent_point or station) on the ground",
                                 joint.parent_point or joint.station)
        if joint.child in model.bodies:
            body = model.bodies[joint.child]
            if joint.child_point is not None and joint.child_point not in body.points:
                raise ModelError(f"{path}.child_point", f"a point of body {body.name!r}"
                                 f" ({', '.join(body.points) or 'it has none'})", joint.child_point)
        elif joint.child_point is not None:
            raise ModelError(f"{path}.child_point", "no child point for a beam (beams hang at their root)",
                             joint.child_point)
        dofs = len(JOINT_DOFS[joint.type])
        for key in ("coordinates", "speeds"):
            names = getattr(joint, key)
            if names is not None and len(names) != dofs:
                raise ModelError(f"{path}.{key}", f"{dofs} names for a {joint.type} joint", names)
        if joint.driver is not None:
            if dofs != 1:
                raise ModelError(f"{path}.driver", "a revolute or prismatic joint (one coordinate)",
                                 joint.type)
            if (joint.driver.coordinate is None) == (joint.driver.speed is None):
                raise ModelError(f"{path}.driver", "exactly one of 'coordinate' and 'speed'",
                                 "both" if joint.driver.coordinate is not None else "neither")
        if joint.torque is not None and dofs != 1:
            raise ModelError(f"{path}.torque", "a revolute or prismatic joint for an actuator torque", joint.type)
        if joint.torque is not None and joint.driver is not None:
            raise ModelError(f"{path}.torque", "no actuator torque on a driven joint (the driver supplies it)",
                             joint.torque)
        if (joint.stiffness is not None or joint.damping is not None) and dofs != 1:
            raise ModelError(f"{path}.stiffness", "a revolute or prismatic joint for joint springs",
                             joint.type)
        for key, unit in (("stiffness", "N m/rad or N/m"), ("damping", "N m s/rad or N s/m")):
            if getattr(joint, key) is not None:
                _non_negative(model, f"{path}.{key}", getattr(joint, key), params, unit)
    for link in model.link_names():
        if link not in children:
            raise ModelError("joints", f"a joint with child {link!r} (every body and beam hangs from one joint)",
                             None, show_given=False)
    # the joints form a tree rooted at the ground
    parent_of = {j.child: j.parent for j in model.joints.values()}
    for link in parent_of:
        seen = [link]
        node = parent_of[link]
        while node != "ground":
            if node in seen:
                raise ModelError("joints", "a tree rooted at the ground (loops need loop constraints)",
                                 " -> ".join(seen + [node]))
            seen.append(node)
            node = parent_of[node]


def _validate_loads(model: Model, params) -> None:
    for load in model.loads.values():
        path = f"loads.{load.name}"
        if load.body in model.bodies:
            body = model.bodies[load.body]
            if load.point is not None and load.point not in body.points:
                raise ModelError(f"{path}.point", f"a point of body {body.name!r}", load.point)
            if load.station is not None:
                raise ModelError(f"{path}.station", "no station on a body (use point)", load.station)
        elif load.body in model.beams:
            if load.station is None:
                raise ModelError(f"{path}.station", "the station x on the beam [m]", None, show_given=False)
            _station(model, f"{path}.station", load.station, model.beams[load.body], params)
        else:
            raise ModelError(f"{path}.body", "the name of a body or a beam", load.body,
                             _suggest(load.body, model.link_names()))
        if load.force is None and load.torque is None:
            raise ModelError(path, "a force, a torque or both", None, show_given=False)
    for spring in model.springs.values():
        path = f"springs.{spring.name}"
        for end in ("a", "b"):
            body = getattr(spring, f"body_{end}")
            point = getattr(spring, f"point_{end}")
            if body == "ground":
                if getattr(spring, f"position_{end}") is None:
                    raise ModelError(f"{path}.position_{end}", "a ground position [x, y] [m]", None,
                                     show_given=False)
            elif body in model.bodies:
                if point is not None and point not in model.bodies[body].points:
                    raise ModelError(f"{path}.point_{end}", f"a point of body {body!r}", point)
            else:
                raise ModelError(f"{path}.body_{end}", "'ground' or a body name", body,
                                 _suggest(body, ["ground"] + list(model.bodies)))
        _non_negative(model, f"{path}.stiffness", spring.stiffness, params, "N/m")
        _non_negative(model, f"{path}.damping", spring.damping, params, "N s/m")
        _non_negative(model, f"{path}.rest_length", spring.rest_length, params, "m")


def _validate_constraints(model: Model, params) -> None:
    names = set(model.joints)
    for con in model.constraints.values():
        path = f"constraints.{con.name}"
        if con.name in names:
            raise ModelError(path, "a name different from every joint's", con.name)
        for end in ("a", "b"):
            body = getattr(con, f"body_{end}")
            point = getattr(con, f"point_{end}")
            station = getattr(con, f"station_{end}")
            position = getattr(con, f"position_{end}")
            if body == "ground":
                if point is not None or station is not None:
                    raise ModelError(f"{path}.body_{end}", f"position_{end} (not a point or station) on the ground", body)
            elif body in model.bodies:
                if point is not None and point not in model.bodies[body].points:
                    raise ModelError(f"{path}.point_{end}", f"a point of body {body!r}", point)
                if station is not None or position is not None:
                    raise ModelError(f"{path}.point_{end}", f"a point (not a station or position) on body {body!r}",
                                     station if station is not None else position)
            elif body in model.beams:
                if station is None:
                    raise ModelError(f"{path}.station_{end}", f"the station x on beam {body!r} [m]", None,
                                     show_given=False)
                _station(model, f"{path}.station_{end}", station, model.beams[body], params)
            else:
                raise ModelError(f"{path}.body_{end}", "'ground', a body or a beam", body,
                                 _suggest(body, ["ground"] + model.link_names()))
        if con.body_a == con.body_b:
            raise ModelError(f"{path}.body_b", "a link other than body_a", con.body_b)


def _suggest(name, options) -> str | None:
    import difflib

    close = difflib.get_close_matches(str(name), list(options), n=1, cutoff=0.5)
    return f"did you mean {close[0]!r}?" if close else None
