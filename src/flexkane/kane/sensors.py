"""Sensors: named outputs of the motion (``[sensors.NAME]``, :class:`flexkane.model.parts.Sensor`).

Each sensor is an expression of q, u and t (and u' for acceleration sensors), built from the
kinematics:

* beam sensors from the deflection field ``y(x) = sum_i Phi_i(x) q_i`` of eq. 8.15 at a station:
  the tip deflection ``y(L)``, the slope ``y'(L)``, the bending moment ``EI y''(x)`` and the strain
  ``-c y''(x)`` at a distance c from the neutral axis (the station constants ``Phi_i^(k)(x)`` are
  numbers computed per parameter set, like the tip constants);
* point sensors from the frame at a body point or beam station (:class:`~.kinematics.FrameMotion`):
  the position ``r`` (ground components, from the ground origin), the velocity (components along
  the point's frame, as the frames store it) and the acceleration ``dv/dt + w x v`` with its terms
  in u' (eq. 8.21 with the u' terms); ``frame = "ground"`` turns the components by the frame's angle;
* joint sensors: the coordinate and the speed of a joint.

Spatial chains (``dimensions = 3``, :class:`~.spatial_kinematics.SpatialKinematics`) take the same
path with three components: point sensors from the :class:`~.spatial_frame.SpatialFrame` at the
point (``a = dv/dt + w x v`` with u', ground components through the frame's direction cosines), and
beam sensors per bending plane (``component``): the deflection ``v = sum Phi^y_i q_yi`` along the
section's principal axis y_p or ``w = sum Phi^z_j q_zj`` along z_p, their slopes, the bending moments
``EI_z v''`` and ``EI_y w''`` and the strains ``-c v''``, ``-c w''``, and the twist
``theta(x) = sum Theta_k q_tk`` (station constants as for the planar beams).

A sensor that effort expressions may use (every kind but acceleration) becomes a named
intermediate (:mod:`flexkane.kane.intermediates`) called after the sensor, so the printed and
generated equations use it by name and calculus goes through its definition.
"""

from __future__ import annotations

import sympy as sp

from .kinematics import Kinematics, rot
from .modal_field import Field, phi, theta
from .spatial_frame import add, cross

__all__ = ["sensor_expressions"]

#: Per bending plane of a spatial beam: the role of its modal coordinates and the field of its rigidity.
_PLANES = {"y": ("mode_y", "EI_z"), "z": ("mode_z", "EI_y")}


def _acceleration(kin: Kinematics, frame) -> tuple:
    """Acceleration of a frame's origin along its own axes, with the terms in u' [m/s^2]."""
    chain = kin.chain
    vx, vy = frame.v
    w = frame.omega
    return (chain.dt(vx, with_ud=True) - w * vy, chain.dt(vy, with_ud=True) + w * vx)


def _point_frame(kin: Kinematics, sensor):
    if sensor.body in kin.bodies:
        return kin.bodies[sensor.body].point(kin.body_point(sensor.body, sensor.point), kin.chain)
    x, text = kin.station(sensor.body, f"sensors.{sensor.name}.station", sensor.station)
    return kin.beam_station(sensor.body, x, text)


def _spatial_beam_value(kin, sensor) -> sp.Expr:
    """A beam sensor of a spatial beam (module docstring)."""
    path = f"sensors.{sensor.name}"
    chain = kin.chain
    bm = kin.beams[sensor.beam]
    beam = bm.beam
    consts = bm.constants
    if sensor.type in ("tip_deflection", "tip_slope"):
        value = beam.L
        x = kin.value(f"beams.{sensor.beam}.L", beam.L, f"L_{sensor.beam}")
    else:
        value = sensor.station
        x = kin.value(f"{path}.station", value, f"x_{sensor.beam}_{sensor.name}")
    text = value.strip() if isinstance(value, str) else repr(value)
    if sensor.type == "twist":
        field = Field({theta(c.index): c.q for c in chain.of(sensor.beam, "torsion")})
        return field.evaluate(lambda a: consts.station(a, x, text))
    role, rigidity = _PLANES[sensor.component]
    field = Field({phi(c.index, sensor.component): c.q for c in chain.of(sensor.beam, role)})
    deriv = {"tip_deflection": 0, "tip_slope": 1}.get(sensor.type, 2)
    value = field.evaluate(lambda a: consts.station(a, x, text, deriv))
    if sensor.type == "bending_moment":
        stiffness = kin.value(f"beams.{sensor.beam}.{rigidity}", getattr(beam, rigidity), f"{rigidity}_{sensor.beam}")
        return stiffness * value
    if sensor.type == "strain":
        return -kin.value(f"{path}.distance", sensor.distance, f"c_{sensor.name}") * value
    return value


def _spatial_point_value(kin, sensor) -> sp.Expr:
    """A point sensor of a spatial chain: one component of r, v or a (module docstring)."""
    chain = kin.chain
    if sensor.body in kin.beams:
        frame = kin.beam_station(sensor.body, f"sensors.{sensor.name}.station", sensor.station, sensor.name)[0]
    else:
        frame = kin.point_frame(sensor.body, sensor.point)
    if sensor.type == "position":
        vector = frame.rotation.inverse_apply(frame.r) if sensor.frame == "local" else frame.r
    else:
        vector = frame.v
        if sensor.type == "acceleration":
            vector = add(tuple(chain.dt(c, with_ud=True) for c in frame.v), cross(frame.omega, frame.v))
        if sensor.frame == "ground":
            vector = frame.rotation.apply(vector)
    return vector["xyz".index(sensor.component)]


def sensor_value(kin: Kinematics, sensor) -> sp.Expr:
    """The expression of one sensor [its unit] (see the module docstring)."""
    path = f"sensors.{sensor.name}"
    chain = kin.chain
    kind = sensor.type
    if kind in ("joint_angle", "joint_rate"):
        coord = chain.of(sensor.joint)[0]
        return coord.q if kind == "joint_angle" else coord.u
    if chain.dimensions == 3:
        return _spatial_point_value(kin, sensor) if sensor.beam is None else _spatial_beam_value(kin, sensor)
    if kind in ("tip_deflection", "tip_slope", "bending_moment", "strain"):
        bm = kin.beams[sensor.beam]
        consts = bm.constants
        if kind in ("tip_deflection", "tip_slope"):
            x = kin.value(f"beams.{sensor.beam}.L", bm.beam.L, f"L_{sensor.beam}")
            text = bm.beam.L.strip() if isinstance(bm.beam.L, str) else repr(bm.beam.L)
            deriv = 0 if kind == "tip_deflection" else 1
        else:
            x, text = kin.station(sensor.beam, f"{path}.station", sensor.station)
            deriv = 2
        value = bm.Y.evaluate(lambda a: consts.station(a, x, text, deriv))
        if kind == "bending_moment":
            return kin.value(f"beams.{sensor.beam}.EI", bm.beam.EI, f"EI_{sensor.beam}") * value
        if kind == "strain":
            return -kin.value(f"{path}.distance", sensor.distance, f"c_{sensor.name}") * value
        return value
    frame = _point_frame(kin, sensor)
    if kind == "position":
        local = rot(-frame.theta, frame.r) if sensor.frame == "local" else frame.r
        vector = local
    else:
        vector = frame.v if kind == "velocity" else _acceleration(kin, frame)
        if sensor.frame == "ground":
            vector = rot(frame.theta, vector)
    return vector[0 if sensor.component == "x" else 1]


def sensor_expressions(kin: Kinematics) -> dict:
    """Every sensor of the model: name -> expression, named intermediates for those usable in efforts.

    Parameters
    ----------
    kin : Kinematics or SpatialKinematics

    Returns
    -------
    dict of str to sympy.Expr
        In the order of the model's sensors; acceleration sensors contain the symbols u'.
    """
    out = {}
    for sensor in kin.chain.model.sensors.values():
        value = sensor_value(kin, sensor)
        if sensor.type != "acceleration":
            value = kin.chain.name(value, sensor.name, above=0)
        out[sensor.name] = value
    return out
