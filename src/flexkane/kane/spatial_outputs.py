"""Quantities computed along the trajectory of a spatial chain.

Names of the outputs (columns of results files):

* ``kinetic``, ``potential_gravity``, ``strain``, ``potential_springs``, ``energy`` [J]:
  ``1/2 sum (m v.v + w.I w)`` (and the beams' ``1/2 int rho v.v + rho_Ip w_sx^2 dx``),
  ``-sum m g.r`` (beams integrated), the beams' ``1/2 q^T K q``, joint and point springs;
* ``power_nonconservative`` [W]: power of drivers, loads, actuators, dampers and the beams' modal
  damping (integrated into
  ``work`` and ``energy_balance`` by :func:`flexkane.simulate`, as for planar chains);
* per body: ``x_<b>, y_<b>, z_<b>`` [m] of the mass centre in N, the Euler parameters
  ``e0_<b> .. e3_<b>`` [-] of the body frame in N (the product of the joints' quaternions along the
  chain: continuous, no branches) and its 3-2-1 angles ``yaw_<b>, pitch_<b>, roll_<b>`` [rad];
* ``x_cm, y_cm, z_cm`` [m], ``p_x, p_y, p_z`` [kg m/s]: centre of mass and linear momentum of the
  system; ``H_x, H_y, H_z`` [kg m^2/s]: angular momentum about the centre of mass, components in N;
* per beam: ``tip_<b>_y``, ``tip_<b>_z`` [m], the tip's deflections along the section's principal
  axes, ``slope_<b>_y``, ``slope_<b>_z`` [rad] their slopes, ``twist_<b>`` [rad] the tip section's
  twist (:func:`flexkane.kane.spatial_beam.tip_outputs`);
* per beam: ``x_<b>, y_<b>, z_<b>`` [m] of the root (the beam frame's origin) in N and the Euler
  parameters ``e0_<b> .. e3_<b>`` of the beam frame;
* ``quaternion_norm_<j>`` [-]: ``e0^2 + ... + e3^2 - 1`` of each spherical and free joint;
* ``effort_<joint>`` [N m or N]: generalized force supplied by each driver.
"""

from __future__ import annotations

import sympy as sp

from ..model.columns import Outputs
from .active import moving_rest
from .rotation import yaw_pitch_roll
from .spatial_active import joint_coordinate_values, spatial_gravity_vector
from .spatial_beam import beam_outputs, tip_outputs
from .spatial_frame import add, cross, dot
from .system_outputs import energy_outputs, power_and_efforts

__all__ = ["spatial_output_expressions"]


def spatial_output_expressions(eom) -> Outputs:
    """Output expressions of spatial :class:`~flexkane.kane.equations.EquationsOfMotion`, each declared
    with its unit and group (:class:`~flexkane.model.columns.Outputs`)."""
    kin = eom.kinematics
    chain = eom.chain
    model = chain.model
    out = Outputs()    # each name once (flexkane.model.columns)
    kinetic, masses = [], []
    first = (sp.Integer(0),) * 3
    momentum = (sp.Integer(0),) * 3
    h_origin = (sp.Integer(0),) * 3
    for name, frame in kin.bodies.items():
        m = kin.mass(name)
        I = kin.inertia_tensor(name)
        Iw = tuple(I * sp.Matrix(frame.omega))
        kinetic.append((m * dot(frame.v, frame.v) + dot(frame.omega, Iw)) / 2)
        masses.append(m)
        vN = frame.rotation.apply(frame.v)
        first = add(first, tuple(m * c for c in frame.r))
        momentum = add(momentum, tuple(m * c for c in vN))
        h_origin = add(h_origin, add(cross(frame.r, tuple(m * c for c in vN)), frame.rotation.apply(Iw)))
        _frame_outputs(out, name, frame, f"body {name!r}'s mass centre")
        for angle, c in zip(("yaw", "pitch", "roll"), yaw_pitch_roll(frame.R)):
            out.add(f"{angle}_{name}", c, "rad", "attitude", f"the {angle} of body {name!r} (3-2-1 angles in N)")
    beam_parts = {name: beam_outputs(kin, name, spatial_gravity_vector(kin)) for name in kin.beams}
    for name in kin.beams:
        for output in tip_outputs(kin, name):
            out.put(output)
        root = kin.beams[name].frame          # the beam frame at the root: drawn by the 3D animation
        _frame_outputs(out, name, root, f"beam {name!r}'s root")
    for part in beam_parts.values():
        kinetic.append(part["kinetic"])
        masses.append(part["mass"])
        first = add(first, part["first"])
        momentum = add(momentum, part["p"])
        h_origin = add(h_origin, part["h"])
    M = sp.Add(*masses)
    cm = tuple(c / M for c in first)
    for axis, c, p in zip("xyz", cm, momentum):
        out.add(f"{axis}_cm", c, "m", "position", f"{axis} of the system's mass centre")
        out.add(f"p_{axis}", p, "kg m/s", "momentum", f"the system's momentum along {axis}")
    for axis, c in zip("xyz", tuple(h - x for h, x in zip(h_origin, cross(cm, momentum)))):
        out.add(f"H_{axis}", c, "kg m^2/s", "angular_momentum",
                f"the system's angular momentum about its mass centre along {axis}")
    for joint in chain.joints:
        if joint.type in ("spherical", "free"):
            e = [c.q for c in chain.joint_coordinates(joint.name)][-4:]
            out.add(f"quaternion_norm_{joint.name}", sp.Add(*[x ** 2 for x in e]) - 1, "-", "quaternion_norm",
                    f"the norm of joint {joint.name!r}'s Euler parameters minus 1")
    # ---------------------------------------------------------------- potential energy
    gravity = []
    g = spatial_gravity_vector(kin)
    if g is not None:
        for name, frame in kin.bodies.items():
            gravity.append(-kin.mass(name) * dot(g, frame.r))
    gravity += [part["potential_gravity"] for part in beam_parts.values()]
    springs = []
    power = []
    for joint in chain.joints:
        coords = chain.joint_coordinates(joint.name)
        stiffness = joint_coordinate_values(kin, joint, "stiffness", "k")
        moving = moving_rest(kin, joint) is not None   # an actuator (its power is in the work): no spring energy
        rest = joint_coordinate_values(kin, joint, "rest", "rest") if joint.stiffness is not None and \
            not moving else []
        stiffness = [None] * len(coords) if moving else stiffness
        damping = joint_coordinate_values(kin, joint, "damping", "c")
        for k, c in enumerate(coords):
            if stiffness[k] is not None:
                springs.append(stiffness[k] * (c.q - (rest[k] if rest and rest[k] is not None else 0)) ** 2 / 2)
            if damping[k] is not None and c.u is not None:
                power.append(-damping[k] * c.u ** 2)
    point_springs = []
    for spring in model.springs.values():
        path = f"springs.{spring.name}"
        a, b = (kin.end_frame(spring, end, path).r for end in ("a", "b"))
        d = tuple(y - x for x, y in zip(a, b))
        k = kin.value(f"{path}.stiffness", spring.stiffness, f"k_{spring.name}")
        l0 = kin.value(f"{path}.rest_length", spring.rest_length, f"l0_{spring.name}")
        point_springs.append(k * (sp.sqrt(dot(d, d)) - l0) ** 2 / 2)
    energy_outputs(out, kinetic=sp.Add(*kinetic), potential_gravity=sp.Add(*gravity),
                   strain=sp.Add(*[part["strain"] for part in beam_parts.values()]),
                   potential_springs=sp.Add(*springs, *point_springs))
    # ---------------------------------------------------------------- power of non-conservative forces
    speeds = chain.u
    for kind in ("damping", "loads"):
        power += [u * f for u, f in zip(speeds, eom.F_r[kind]) if f != 0]
    if model.springs:   # the spring forces' power minus the rate of their energy: the dampers'
        power.append(sp.Add(*[u * f for u, f in zip(speeds, eom.F_r["springs"]) if f != 0])
                     + chain.dt(sp.Add(*point_springs)))
    for owner, effort in eom.driver_efforts.items():
        power.append(effort * chain.joint_coordinates(owner)[0].u)
    power_and_efforts(out, eom, sp.Add(*power))
    return out


def _frame_outputs(out: Outputs, name: str, frame, where: str) -> None:
    """``x_, y_, z_<name>`` [m] of ``where`` in N and the Euler parameters ``e0_ .. e3_<name>`` [-] of
    the frame in N."""
    for axis, c in zip("xyz", frame.r):
        out.add(f"{axis}_{name}", c, "m", "position", f"{axis} of {where}")
    for k, c in enumerate(frame.rotation.quaternion):
        out.add(f"e{k}_{name}", c, "-", "orientation", f"Euler parameter e{k} of {name!r}'s frame in N")
