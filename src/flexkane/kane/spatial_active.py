"""Generalized active forces F_r of a spatial chain, by source.

A force ``F`` at a point P and a torque ``T`` on a link contribute ``F_r = v_P,r . F + w_r . T``
(partial velocity and partial angular velocity, eq. 8.24 in three dimensions); both are taken in the
axes of the frame at P, where the velocities are expressed.

* ``gravity``: ``m g`` at each mass centre, ``g`` a 3D vector in N;
* ``joints``: springs ``-k (q - rest)`` and dampers ``-c u`` on the coordinates of revolute,
  prismatic, cylindrical, universal and planar joints (their speeds are the coordinates' rates);
* ``loads``: applied forces and torques (ground or local components), forces per length on beams
  (:func:`flexkane.kane.distributed_loads.spatial_distributed_load_forces`) and actuator torques or
  forces of joints along their coordinates, expressions of t, the parameters and the signals of
  :mod:`flexkane.kane.controllers` (coordinates, speeds, sensors, controller states and outputs:
  state feedback, kept by name in the equations); joint springs whose rest position moves (an
  expression of t or of the state: an actuator); the control inputs of a model derived with them
  (:mod:`flexkane.kane.inputs`);
* ``springs``: linear springs and dampers between points.

* ``elastic``: the beams' strain energy, ``-K q`` with the modal stiffness constants, and
  ``gravity`` on the beams distributed, ``int rho v_P,r . g dx`` (:mod:`flexkane.kane.spatial_beam`),
  or the notebook variant's root moment and shear and weight at the deformed midpoint
  (:mod:`flexkane.kane.spatial_beam_notebook`).

* ``damping``: the beams' modal damping, ``-2 zeta_i sqrt(K_ii M_ii) u_i`` for each bending
  plane, the twist and the stretch (as the planar beams'). Each source is a list of n
expressions (one per speed).

A planar chain (``dimensions = 2``, :class:`~flexkane.kane.spatial_kinematics.SpatialKinematics`
of planar motion) gives its vectors a zero z component: gravity (eq. 8.33), load forces, a load's
torque about z; its symbols are named as the planar engine names them.
"""

from __future__ import annotations

import sympy as sp

from .active import gravity_vector, moving_rest
from .distributed_loads import spatial_distributed_load_forces
from .inputs import input_forces
from .spatial_beam import beam_active_forces
from .spatial_frame import dot
from .spatial_joints import direction

__all__ = ["joint_coordinate_values", "spatial_active_forces", "spatial_gravity_vector"]


def spatial_gravity_vector(kin):
    """Gravity acceleration in N, (g_x, g_y, g_z) [m/s^2]; None without gravity."""
    grav = kin.chain.model.gravity
    if grav is None:
        return None
    if kin.chain.dimensions == 2:
        return (*gravity_vector(kin), sp.Integer(0))
    g = kin.value("gravity.g", grav.g, "g")
    n = direction(kin.symbols, "gravity.direction", grav.direction, "g_direction")
    return tuple(g * c for c in n)


def _per_coordinate(kin, joint, field: str, convert) -> list:
    """Per coordinate of a joint, ``convert(path, value, label)`` of a field given for one coordinate
    (a value, the first coordinate's; label the joint's name) or for each (a list; label the
    coordinate's name); None where not given."""
    coords = kin.chain.joint_coordinates(joint.name)
    value = getattr(joint, field, None)
    path = f"joints.{joint.name}.{field}"
    if value is None:
        return [None] * len(coords)
    if isinstance(value, (list, tuple)):
        return [None if v is None else convert(f"{path}[{k}]", v, c.q.name)
                for k, (v, c) in enumerate(zip(value, coords))]
    return [convert(path, value, joint.name)] + [None] * (len(coords) - 1)


def joint_coordinate_values(kin, joint, field: str, name: str) -> list:
    """Per coordinate of a joint, the expression of a constant field (symbols ``<name>_<label>``)."""
    return _per_coordinate(kin, joint, field, lambda path, v, label: kin.value(path, v, f"{name}_{label}"))


def _joint_efforts(kin, joint, field: str) -> list:
    """Per coordinate of a joint, the expression of a field of t and the signals (actuator efforts)."""
    return _per_coordinate(kin, joint, field, lambda path, v, label: kin.symbols.effort(path, v))


def spatial_active_forces(kin) -> dict[str, list]:
    """F_r by source (module docstring).

    Parameters
    ----------
    kin : SpatialKinematics

    Returns
    -------
    dict of str to list of sympy.Expr
    """
    chain = kin.chain
    model = chain.model
    speeds = chain.u
    n = len(speeds)
    index = {u: r for r, u in enumerate(speeds)}
    parts = {kind: [sp.Integer(0)] * n for kind in ("elastic", "gravity", "damping", "joints", "loads", "springs")}

    def add(kind, frame, force=None, torque=None, velocity=None):
        """Contributions of a force (frame axes; or the axes of ``velocity``, the velocity of the
        frame's origin in other axes) at the frame's origin and a torque on it."""
        velocity = frame.v if velocity is None else velocity
        for r, u in enumerate(speeds):
            term = sp.Integer(0)
            if force is not None:
                term += dot(tuple(chain.partial(c, u) for c in velocity), force)
            if torque is not None:
                term += dot(tuple(chain.partial(c, u) for c in frame.omega), torque)
            if term != 0:
                parts[kind][r] += term

    g = spatial_gravity_vector(kin)
    if g is not None:
        for name, frame in kin.bodies.items():
            m = kin.mass(name)
            add("gravity", frame, tuple(m * c for c in frame.rotation.inverse_apply(g)))
    beam_active_forces(kin, parts, g)
    for load in model.distributed_loads.values():   # int v_P,r . f dx on beams
        for r, term in enumerate(spatial_distributed_load_forces(kin, load, speeds)):
            parts["loads"][r] += term

    for joint in chain.joints:
        coords = chain.joint_coordinates(joint.name)
        stiffness = joint_coordinate_values(kin, joint, "stiffness", "k")
        damping = joint_coordinate_values(kin, joint, "damping", "c")
        moving = moving_rest(kin, joint)    # an actuator: its power is counted in the work W
        rest = []
        if joint.stiffness is not None and moving is None and chain.dimensions == 2 and joint.rest is not None:
            # the planar name of the rest position
            rest = [kin.value(f"joints.{joint.name}.rest", joint.rest, f"{coords[0].q.name}_rest")] \
                + [None] * (len(coords) - 1)
        elif joint.stiffness is not None and moving is None:
            rest = joint_coordinate_values(kin, joint, "rest", "rest")
        torque = _joint_efforts(kin, joint, "torque")
        for k, c in enumerate(coords):
            if c.u is None:
                continue
            r = index[c.u]
            if stiffness[k] is not None and moving is not None:
                parts["loads"][r] += -stiffness[k] * (c.q - moving)
            elif stiffness[k] is not None:
                parts["joints"][r] += -stiffness[k] * (c.q - (rest[k] if rest and rest[k] is not None else 0))
            if damping[k] is not None:
                parts["joints"][r] += -damping[k] * c.u
            if torque[k] is not None:
                parts["loads"][r] += torque[k]

    for load in model.loads.values():
        path = f"loads.{load.name}"
        frame = kin.load_frame(load)

        def components(values, what):
            vec = tuple(kin.symbols.effort(f"{path}.{what}[{k}]", v) for k, v in enumerate(values))
            vec = vec + (sp.Integer(0),) * (3 - len(vec))     # a planar chain's (fx, fy)
            return vec if load.frame == "local" else frame.rotation.inverse_apply(vec)

        if chain.dimensions == 2 and load.torque is not None:     # about z
            torque = (sp.Integer(0), sp.Integer(0), kin.symbols.effort(f"{path}.torque", load.torque))
        else:
            torque = components(load.torque, "torque") if load.torque is not None else None
        add("loads", frame, components(load.force, "force") if load.force is not None else None, torque)

    for spring in model.springs.values():
        path = f"springs.{spring.name}"
        a, b = kin.end_frame(spring, "a", path), kin.end_frame(spring, "b", path)
        d = tuple(y - x for x, y in zip(a.r, b.r))
        length = sp.sqrt(dot(d, d))
        e = tuple(c / length for c in d)
        va, vb = a.rotation.apply(a.v), b.rotation.apply(b.v)
        rate = dot(e, tuple(y - x for x, y in zip(va, vb)))
        k = kin.value(f"{path}.stiffness", spring.stiffness, f"k_{spring.name}")
        c = kin.value(f"{path}.damping", spring.damping, f"c_{spring.name}")
        l0 = kin.value(f"{path}.rest_length", spring.rest_length, f"l0_{spring.name}")
        tension = k * (length - l0) + c * rate
        fb = tuple(-tension * x for x in e)             # on b, in N
        if chain.dimensions == 2:    # in N, on the velocities in N (as the planar engine writes them)
            add("springs", b, fb, velocity=vb)
            add("springs", a, tuple(-x for x in fb), velocity=va)
            continue
        add("springs", b, b.rotation.inverse_apply(fb))
        add("springs", a, a.rotation.inverse_apply(tuple(-x for x in fb)))
    for r, term in enumerate(input_forces(kin)):     # control inputs (kane/inputs.py)
        if term != 0:
            parts["loads"][r] += term
    return parts
