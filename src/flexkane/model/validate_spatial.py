"""Validation of the fields that spatial models (``dimensions = 3``) have in their own form.

:func:`flexkane.model.validate.validate_model` checks what planar and spatial models share (names,
references, masses, the joint tree, run settings) and calls these functions for the rest: inertia
tensors, three-component vectors, joint axes and orientations, torque vectors, the kinds of loop
constraints, and the parts that spatial models do not have yet. Each problem is a
:class:`~flexkane.errors.ModelError` naming the key path, what was expected (with the unit) and what
was given. ``values`` is the model's evaluator of field values
(:class:`~flexkane.model.field_values.FieldValues`, with the number checks of validation).
"""

from __future__ import annotations

import numpy as np

from ..errors import ModelError
from .orientation import orientation_matrix, unit_vector, vector3
from .parts import SPATIAL_JOINT_DOFS, Gravity, Joint, Load, RigidBody

__all__ = ["check_body", "check_constraint_kind", "CONSTRAINT_EQUATIONS", "check_joint_geometry", "check_gravity",
           "check_load", "check_position",
           "joint_counts", "PERPENDICULAR_TOLERANCE", "INERTIA_TOLERANCE"]

#: Largest |cos| of the angle between a universal joint's two axes [-].
PERPENDICULAR_TOLERANCE = 1e-9
#: Relative tolerance of the checks of an inertia tensor (symmetry, signs, triangle inequalities) [-].
INERTIA_TOLERANCE = 1e-9
#: Joint types with a single coordinate, which may carry a spring, damper, actuator or driver.
_ONE_COORDINATE = ("revolute", "prismatic")
#: Joint types whose ``axis`` is required, and what it is for each.
_AXIS_MEANING = {"revolute": "rotation axis", "prismatic": "slide direction", "cylindrical": "rotation and slide "
                 "axis", "planar": "normal of the plane"}


#: Loop-constraint types of spatial models and their numbers of scalar constraints.
CONSTRAINT_EQUATIONS = {"spherical": 3, "point_on_line": 2, "weld": 6}


def check_constraint_kind(con, values) -> int:
    """Type, axis and orientation of a spatial loop constraint; returns its number of scalar
    constraints (:data:`CONSTRAINT_EQUATIONS`)."""
    path = f"constraints.{con.name}"
    if con.type not in CONSTRAINT_EQUATIONS:
        raise ModelError(f"{path}.type", "a spatial loop-constraint type: spherical (coincident points), "
                         "point_on_line (point b on the line through point a along axis) or weld "
                         "(coincident frames)", con.type,
                         "revolute and prismatic loop joints are planar" if con.type in ("revolute", "prismatic")
                         else None)
    if con.angle != 0:
        raise ModelError(f"{path}.angle", "no angle in a model with dimensions = 3 (a weld keeps frame b at frame "
                         "a turned by orientation = { axis = [...], angle = ... })", con.angle)
    if con.type == "point_on_line":
        axis = con.axis
        if not isinstance(axis, (list, tuple)) or len(axis) != 3 or not all(
                isinstance(c, (int, float)) and not isinstance(c, bool) and np.isfinite(c) for c in axis):
            raise ModelError(f"{path}.axis", "the line's direction in frame a as three numbers [x, y, z] [-]", axis)
        if not any(c != 0 for c in axis):
            raise ModelError(f"{path}.axis", "a non-zero direction [x, y, z]", list(axis))
    elif con.axis != 0:
        raise ModelError(f"{path}.axis", "no axis on a spatial loop constraint that is not point_on_line", con.axis)
    if con.type == "weld":
        orientation_matrix(con.orientation, f"{path}.orientation", values)
    elif con.orientation is not None:
        raise ModelError(f"{path}.orientation", "no orientation on a spatial loop constraint that is not a weld",
                         con.orientation)
    return CONSTRAINT_EQUATIONS[con.type]


def check_position(path: str, value, values, what: str, unit: str = "m", *, time: bool = False) -> np.ndarray:
    """A three-component vector field [unit] (expressions of t at t = 0 when ``time``)."""
    return vector3(value, path, values, what + (", numbers or expressions of t" if time else ""), unit,
                   **({"t": 0.0} if time else {}))


def _inertia_rows(body: RigidBody) -> tuple:
    path = f"bodies.{body.name}.inertia"
    inertia = body.inertia
    if not isinstance(inertia, (list, tuple)) or len(inertia) != 3:
        raise ModelError(path, "three principal values [Ixx, Iyy, Izz] or a 3x3 symmetric tensor [[Ixx, Ixy, Ixz], "
                         "[Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]] about the mass centre in body axes [kg m^2]", inertia)
    nested = [isinstance(row, (list, tuple)) for row in inertia]
    if any(nested) and not all(isinstance(row, (list, tuple)) and len(row) == 3 for row in inertia):
        bad = next(k for k, row in enumerate(inertia) if not (isinstance(row, (list, tuple)) and len(row) == 3))
        raise ModelError(f"{path}[{bad}]", "a row of three tensor components [kg m^2] (a 3x3 tensor has three "
                         "rows of three)", inertia[bad])
    return body.inertia_tensor()


def check_body(body: RigidBody, values) -> None:
    """Inertia tensor, points and outline of a spatial body (its mass is checked as planar)."""
    path = f"bodies.{body.name}"
    rows = _inertia_rows(body)
    principal = not isinstance(body.inertia[0], (list, tuple))
    tensor = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            if principal and i != j:
                tensor[i, j] = 0.0
                continue
            where = f"{path}.inertia[{i}]" + ("" if principal else f"[{j}]")
            tensor[i, j] = values.number(where, rows[i][j], "inertia tensor component", "kg m^2")
    scale = max(float(np.abs(tensor).max()), np.finfo(float).tiny)
    unit = tensor / scale                      # components up to 1: no overflow whatever the values
    for i, j in ((0, 1), (0, 2), (1, 2)):
        if abs(unit[i, j] - unit[j, i]) > INERTIA_TOLERANCE:
            raise ModelError(f"{path}.inertia[{i}][{j}]", f"a symmetric tensor: inertia[{i}][{j}] equal to "
                             f"inertia[{j}][{i}] = {tensor[j, i]:g} [kg m^2]", f"{tensor[i, j]:g}")
    moments = np.linalg.eigvalsh(0.5 * (unit + unit.T)) * scale
    what = "principal values" if principal else "principal moments (eigenvalues of the tensor)"
    shown = ", ".join(f"{m:.6g}" for m in moments)
    if moments[0] < -INERTIA_TOLERANCE * scale:
        raise ModelError(f"{path}.inertia", f"an inertia tensor with non-negative {what} [kg m^2] (positive "
                         "semi-definite)", shown)
    if moments[0] + moments[1] < moments[2] - INERTIA_TOLERANCE * scale:
        raise ModelError(f"{path}.inertia", f"{what} obeying the triangle inequality I1 + I2 >= I3 [kg m^2], as "
                         "every body's do", shown, f"{moments[0]:.6g} + {moments[1]:.6g} < {moments[2]:.6g}")
    if not isinstance(body.points, dict):
        raise ModelError(f"{path}.points", "a table of named points { P = [x, y, z] } [m]", body.points)
    for pname, xyz in body.points.items():
        check_position(f"{path}.points.{pname}", xyz, values, "coordinates from the mass centre in body axes")
    if not isinstance(body.outline, (list, tuple)):
        raise ModelError(f"{path}.outline", "a list of [x, y, z] vertices [m]", body.outline)
    for k, xyz in enumerate(body.outline):
        check_position(f"{path}.outline[{k}]", xyz, values, "vertex coordinates from the mass centre")


def joint_counts(joint_type: str) -> tuple[int, int]:
    """Numbers of coordinates and of speeds of a spatial joint type (a spherical joint: 4 and 3)."""
    roles = SPATIAL_JOINT_DOFS[joint_type]
    return len(roles), len([r for r in roles if r != "e0"])


def _direction(path: str, value, values, what: str) -> np.ndarray:
    """A direction field as a unit vector (refused if zero)."""
    vector = vector3(value, path, values, what, "-")
    if not np.any(vector != 0):
        raise ModelError(path, f"a non-zero vector [x, y, z] ({what})", list(value))
    return unit_vector(vector)


def check_joint_geometry(joint: Joint, values) -> None:
    """Position on the ground, axis or axes, orientations of a spatial joint (type already valid)."""
    path = f"joints.{joint.name}"
    if joint.parent == "ground" and joint.parent_position is not None:
        check_position(f"{path}.parent_position", joint.parent_position, values, "ground coordinates")
    if joint.angle != 0:
        raise ModelError(f"{path}.angle", "no angle in a model with dimensions = 3 (give the joint frames' "
                         "orientation and child_orientation as tables { axis = [...], angle = ... })", joint.angle)
    if joint.type in _AXIS_MEANING:
        if isinstance(joint.axis, (int, float)) and not isinstance(joint.axis, bool) and joint.axis == 0:
            raise ModelError(f"{path}.axis", f"the {_AXIS_MEANING[joint.type]} of a {joint.type} joint as a vector "
                             "[x, y, z] in the joint frame J_p", None, "missing", show_given=False)
        _direction(f"{path}.axis", joint.axis, values, f"{_AXIS_MEANING[joint.type]} in J_p")
    elif joint.axis != 0:
        raise ModelError(f"{path}.axis", "no axis on a joint that is not revolute, prismatic, cylindrical or planar"
                         + (" (a universal joint has axes = [[...], [...]])" if joint.type == "universal" else ""),
                         joint.axis)
    if joint.type == "universal":
        axes = joint.axes
        if not isinstance(axes, (list, tuple)) or len(axes) != 2:
            raise ModelError(f"{path}.axes", "two axes [[x, y, z], [x, y, z]]: the first fixed in J_p, the second "
                             "in J_c, perpendicular", axes, None if axes is not None else "missing",
                             show_given=axes is not None)
        first = _direction(f"{path}.axes[0]", axes[0], values, "first axis, fixed in J_p")
        second = _direction(f"{path}.axes[1]", axes[1], values, "second axis, fixed in J_c")
        cosine = float(first @ second)
        if abs(cosine) > PERPENDICULAR_TOLERANCE:
            raise ModelError(f"{path}.axes", "two perpendicular axes (in the reference configuration, J_c = J_p)",
                             [list(a) for a in axes], f"the cosine of the angle between them is {cosine:.6g}")
    elif joint.axes is not None:
        raise ModelError(f"{path}.axes", "no axes on a joint that is not universal", joint.axes)
    for key in ("orientation", "child_orientation"):
        orientation_matrix(getattr(joint, key), f"{path}.{key}", values)


def check_gravity(gravity: Gravity, values) -> None:
    """A spatial gravity's direction: three values, not all zero (its g is checked as planar)."""
    direction = check_position("gravity.direction", gravity.direction, values, "direction components in the ground "
                               "frame", "-")
    if not np.any(direction != 0):
        raise ModelError("gravity.direction", "a non-zero direction [x, y, z]", list(gravity.direction))


def check_load(load: Load, values) -> None:
    """A spatial load's force and torque vectors (expressions of t, the parameters and the signals:
    those that name a signal are checked with the sensors and controllers, ``values.law``)."""
    path = f"loads.{load.name}"
    for key, what, unit in (("force", "force components", "N"), ("torque", "torque components", "N m")):
        value = getattr(load, key)
        if value is None:
            continue
        if not isinstance(value, (list, tuple)) or len(value) != 3:
            raise ModelError(f"{path}.{key}", f"three values [x, y, z] ({what} [{unit}], numbers or expressions "
                             "of t and the state)", value)
        for k, component in enumerate(value):
            if isinstance(component, bool) or not isinstance(component, (int, float, str)):
                raise ModelError(f"{path}.{key}[{k}]", f"a number or an expression string ({what[:-1]} [{unit}])",
                                 component)
            values.law(f"{path}.{key}[{k}]", component, what[:-1], unit)
