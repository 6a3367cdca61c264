"""Joints in space: the motion of a joint's child frame J_c relative to its parent frame J_p.

Each joint type gives, from its generalized coordinates q and speeds u (named by
:func:`flexkane.model.coordinates.coordinate_names`):

* ``d``: position of J_c's origin in J_p [m], components along J_p's axes;
* ``rotation``: orientation of J_c in J_p (:class:`~flexkane.kane.rotation.Rotation`);
* ``w_rel``: angular velocity of J_c in J_p, components along J_c's axes [rad/s];
* ``v_rel``: velocity of J_c's origin in J_p, components along J_c's axes [m/s];
* the kinematic equations ``q' = ...`` of its coordinates.

=============  =========================================  ====================================
type           coordinates (speeds)                       kinematic equations
=============  =========================================  ====================================
revolute       angle about ``axis`` (its rate)            q' = u
prismatic      slide along ``axis`` (its rate)            q' = u
cylindrical    angle, slide about / along ``axis``        q' = u
universal      angles about ``axes[0]`` (in J_p) and      q' = u
               ``axes[1]`` (in J_c)
planar         x, y along the plane's axes, angle         q' = u
               about the normal ``axis``
spherical      Euler parameters e0..e3 of J_c in J_p      e' = 1/2 E(e) w
               (w = angular velocity along J_c's axes)
free           x, y, z of J_c's origin in J_p             (x, y, z)' = C(e) v, e' = 1/2 E(e) w
               (v = its velocity along J_c's axes),
               then as spherical
weld           none
=============  =========================================  ====================================

With all coordinates zero (e0 = 1) J_c coincides with J_p. Literal numbers in axis vectors are
structure (integers exact, so that an axis ``[0, 0, 1]`` gives the planar rotation matrix and
``[1, 1, 0]`` the exact ``1/sqrt(2)``; other numbers as the same doubles, normalized at derivation);
expressions of the parameters become symbols of their own and the axis is normalized in the
equations.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..errors import ModelError
from .rotation import IDENTITY, Rotation, about_axis, about_z, body_sequence, euler_parameter_matrix, \
    euler_parameter_rates, unit_vector
from .spatial_frame import ZERO3, cross

__all__ = ["JointMotion", "joint_motion", "kinematic_equations", "orientation", "planar_joint_motion", "plane_axes",
           "vector"]


def _literal(value):
    """A literal number as a SymPy number (integers exact, other floats as the same double), else None."""
    if isinstance(value, bool):
        return None
    if isinstance(value, int) or (isinstance(value, float) and value.is_integer()):
        return sp.Integer(int(value))
    if isinstance(value, float):
        return sp.Float(value)
    return None


def vector(symbols, path: str, values, name: str, exact: bool = False) -> tuple:
    """A 3-vector field as expressions: literal numbers exact when ``exact`` (directions, which
    are structure), otherwise a symbol per non-zero component (``symbols.value``)."""
    if values is None:
        return ZERO3
    out = []
    for k, value in enumerate(values):
        literal = _literal(value) if exact else None
        out.append(literal if literal is not None
                   else symbols.value(f"{path}[{k}]", value, f"{name}_{'xyz'[k]}"))
    return tuple(out)


def direction(symbols, path: str, values, name: str) -> tuple:
    """A unit 3-vector from a direction field (normalized; literal numbers exact)."""
    v = vector(symbols, path, values, name, exact=True)
    if all(c == 0 for c in v):
        raise ModelError(path, "a non-zero 3-component direction", list(values))
    return unit_vector(v)


def _get(spec, key):
    if isinstance(spec, dict):
        return spec.get(key)
    return getattr(spec, key, None)


def orientation(symbols, path: str, spec, name: str) -> Rotation:
    """A constant orientation given as ``{axis, angle}`` or ``{sequence, angles}``; None: identity."""
    if spec is None:
        return IDENTITY
    if _get(spec, "sequence") is not None:
        sequence = _get(spec, "sequence")
        angles = [symbols.value(f"{path}.angles[{k}]", a, f"{name}_{k + 1}")
                  for k, a in enumerate(_get(spec, "angles"))]
        return body_sequence(sequence, angles)
    axis = direction(symbols, f"{path}.axis", _get(spec, "axis"), f"{name}_axis")
    angle = symbols.value(f"{path}.angle", _get(spec, "angle"), f"{name}_angle")
    return about_axis(axis, angle)


def plane_axes(normal: tuple, path: str = "axis") -> tuple[tuple, tuple]:
    """Two unit vectors spanning the plane normal to ``normal`` (a unit vector with literal
    components): the J_p axis least aligned with the normal, made orthogonal to it, then
    ``normal x`` that one. For the normal z: x and y; x: y and z; y: x and -z."""
    if not all(c.is_number for c in normal):
        raise ModelError(path, "a planar joint's normal with numbers as components (not expressions)",
                         [str(c) for c in normal])
    k = min(range(3), key=lambda i: (abs(float(normal[i])), i))
    e = tuple(sp.Integer(1 if i == k else 0) - normal[k] * normal[i] for i in range(3))
    e1 = unit_vector(tuple(sp.expand(c) for c in e))
    e2 = tuple(sp.expand(c) for c in cross(normal, e1))
    return e1, e2


@dataclass
class JointMotion:
    """Motion of J_c relative to J_p (see the module docstring)."""

    d: tuple
    rotation: Rotation
    w_rel: tuple
    v_rel: tuple


def joint_motion(joint, coords, symbols) -> JointMotion:
    """The relative motion of a joint from its coordinates (``coords``: the chain's Coordinates of
    the joint, in order)."""
    path = f"joints.{joint.name}"
    kind = joint.type
    if kind in ("revolute", "prismatic", "cylindrical", "planar"):
        n = direction(symbols, f"{path}.axis", joint.axis, f"n_{joint.name}")
    if kind == "revolute":
        (c,) = coords
        return JointMotion(ZERO3, about_axis(n, c.q), tuple(a * c.u for a in n), ZERO3)
    if kind == "prismatic":
        (c,) = coords
        return JointMotion(tuple(a * c.q for a in n), IDENTITY, ZERO3, tuple(a * c.u for a in n))
    if kind == "cylindrical":
        ca, cs = coords
        return JointMotion(tuple(a * cs.q for a in n), about_axis(n, ca.q), tuple(a * ca.u for a in n),
                           tuple(a * cs.u for a in n))
    if kind == "universal":
        c1, c2 = coords
        a1 = direction(symbols, f"{path}.axes[0]", joint.axes[0], f"a1_{joint.name}")
        a2 = direction(symbols, f"{path}.axes[1]", joint.axes[1], f"a2_{joint.name}")
        second = about_axis(a2, c2.q)
        w = second.inverse_apply(tuple(a * c1.u for a in a1))
        return JointMotion(ZERO3, about_axis(a1, c1.q) * second,
                           tuple(x + a * c2.u for x, a in zip(w, a2)), ZERO3)
    if kind == "planar":
        cx, cy, ca = coords
        e1, e2 = plane_axes(n, f"{path}.axis")
        turn = about_axis(n, ca.q)
        d = tuple(a * cx.q + b * cy.q for a, b in zip(e1, e2))
        return JointMotion(d, turn, tuple(a * ca.u for a in n),
                           turn.inverse_apply(tuple(a * cx.u + b * cy.u for a, b in zip(e1, e2))))
    if kind == "spherical":
        e = tuple(c.q for c in coords)
        w = tuple(c.u for c in coords[1:])
        return JointMotion(ZERO3, Rotation(euler_parameter_matrix(e), e), w, ZERO3)
    if kind == "free":
        e = tuple(c.q for c in coords[3:])
        w = tuple(c.u for c in coords[4:])
        return JointMotion(tuple(c.q for c in coords[:3]), Rotation(euler_parameter_matrix(e), e), w,
                           tuple(c.u for c in coords[:3]))
    if kind == "weld":
        return JointMotion(ZERO3, IDENTITY, ZERO3, ZERO3)
    raise ModelError(f"{path}.type", "revolute, prismatic, cylindrical, universal, planar, spherical, "
                     "free or weld", kind)


def planar_joint_motion(joint, coords, symbols) -> JointMotion:
    """The relative motion of a joint of a planar chain (``dimensions = 2``): turns about z and
    translations in the x-y plane.

    J_c is turned from J_p by the joint's constant ``angle`` (plus the angle coordinate of a
    revolute or free joint); a prismatic joint slides along the direction at ``axis`` [rad] from
    J_p's x axis; a free joint's x, y are J_c's origin in J_p and its speeds the components along
    J_c's axes of that origin's velocity in J_p (eq. 8.10: ``v = u1 i + u2 j``), whose kinematic
    equations the planar chain holds.
    """
    path = f"joints.{joint.name}"
    zero = sp.Integer(0)
    offset = symbols.value(f"{path}.angle", joint.angle, f"theta_{joint.name}")
    if joint.type == "revolute":
        (c,) = coords
        return JointMotion(ZERO3, about_z(c.q + offset), (zero, zero, c.u), ZERO3)
    if joint.type == "prismatic":
        (c,) = coords
        axis = symbols.value(f"{path}.axis", joint.axis, f"alpha_{joint.name}")
        n = (sp.cos(axis), sp.sin(axis), zero)
        turn = about_z(offset)
        return JointMotion(tuple(a * c.q for a in n), turn, ZERO3, turn.inverse_apply(tuple(a * c.u for a in n)))
    if joint.type == "free":
        cx, cy, ca = coords
        return JointMotion((cx.q, cy.q, zero), about_z(ca.q + offset), (zero, zero, ca.u), (cx.u, cy.u, zero))
    if joint.type == "weld":
        return JointMotion(ZERO3, about_z(offset), ZERO3, ZERO3)
    raise ModelError(f"{path}.type", "revolute, prismatic, free or weld (a planar joint)", joint.type)


def kinematic_equations(joint, coords) -> dict:
    """``q' = ...`` of a joint's coordinates (see the module docstring), as {q: expression}."""
    if joint.type == "spherical":
        e = tuple(c.q for c in coords)
        return dict(zip(e, euler_parameter_rates(e, tuple(c.u for c in coords[1:]))))
    if joint.type == "free":
        e = tuple(c.q for c in coords[3:])
        C = euler_parameter_matrix(e)
        v = sp.Matrix([c.u for c in coords[:3]])
        out = {c.q: expr for c, expr in zip(coords[:3], C * v)}
        out.update(zip(e, euler_parameter_rates(e, tuple(c.u for c in coords[4:]))))
        return out
    return {c.q: c.u for c in coords}
