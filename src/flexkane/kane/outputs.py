"""Quantities computed along a trajectory: energy, momentum, positions, tip deflections, efforts.

Names of the outputs (columns of results files):

* ``kinetic``, ``potential_gravity``, ``strain``, ``potential_springs``, ``energy`` [J]:
  kinetic energy ``1/2 sum m v.v + 1/2 I w^2 + 1/2 int rho v_P.v_P dx`` (``+ 1/2 int rho_I w_s^2 dx``
  for the turning sections of a Rayleigh beam), gravity potential
  ``-sum m g.r - int rho g.r_P dx`` (or the whole weight at the deformed midpoint for ``midpoint``
  beams), strain energy ``1/2 q^T H q`` (eq. 8.32) plus axial, spring energy, and their sum;
* ``power_nonconservative`` [W]: power of drivers (their efforts, constraint forces of closed loops
  included), applied loads, actuator torques and dampers; :func:`flexkane.simulate` integrates it
  with the motion as a quadrature state and adds the outputs ``work`` [J] and ``energy_balance``
  ``= energy - energy[0] - work`` [J];
* ``x_<link>``, ``y_<link>``, ``theta_<link>`` [m, m, rad]: mass centre of each body, root of each
  beam, and the frame angle;
* ``tip_<beam>`` [m]: deflection of the beam's tip in the beam frame, ``sum_i Phi_i(L) q_i``;
* ``x_cm``, ``y_cm`` [m], ``p_x``, ``p_y`` [kg m/s]: centre of mass of the whole system and its
  linear momentum; ``h_cm`` and ``h_o`` [kg m^2/s]: angular momentum about the centre of mass and
  about the ground origin;
* ``effort_<joint>`` [N m or N]: generalized force supplied by each driver, and the actuator torque
  (or force) of each joint that has one;
* ``load_<name>_fx``, ``load_<name>_fy`` [N], ``load_<name>_torque`` [N m]: the force components (as
  given, in the load's frame) and the torque of each load;
* ``sensor_<name>`` [its unit]: each sensor (:mod:`flexkane.kane.sensors`);
  ``controller_<name>`` [its unit]: each controller output, saturated.

Efforts may depend on the state (feedback): their values are then functions of q, u, the
controller states and t, evaluated along the trajectory like every output.
"""

from __future__ import annotations

import sympy as sp

from ..model.columns import Outputs
from .active import gravity_vector, moving_rest
from .kinematics import rot
from .modal_field import ONE
from .system_outputs import energy_outputs, power_and_efforts

__all__ = ["output_expressions"]


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def output_expressions(eom) -> Outputs:
    """Output expressions of an :class:`~flexkane.kane.equations.EquationsOfMotion` (unsubstituted),
    each declared with its unit and group (:class:`~flexkane.model.columns.Outputs`)."""
    kin = eom.kinematics
    chain = eom.chain
    model = chain.model
    out = Outputs()    # each name once (flexkane.model.columns)
    kinetic = []
    mass_total = []
    first_moment = [[], []]
    momentum = [[], []]
    h_origin = []
    for name, frame in kin.bodies.items():
        body = model.bodies[name]
        m = kin.value(f"bodies.{name}.mass", body.mass, f"m_{name}")
        inertia = kin.value(f"bodies.{name}.inertia", body.inertia, f"I_{name}")
        vx, vy = frame.v
        kinetic.append(m * (vx ** 2 + vy ** 2) / 2 + inertia * frame.omega ** 2 / 2)
        vN = rot(frame.theta, frame.v)
        mass_total.append(m)
        for k in range(2):
            first_moment[k].append(m * frame.r[k])
            momentum[k].append(m * vN[k])
        h_origin.append(inertia * frame.omega + m * _cross(frame.r, vN))
        _frame_outputs(out, name, frame, f"body {name!r}'s mass centre")
    strain = []
    for name, bm in kin.beams.items():
        c = bm.constants
        v = bm.v
        kinetic.append((c.integrate(v[0], v[0]) + c.integrate(v[1], v[1])) / 2)
        mB = c.pair(ONE, ONE)
        mass_total.append(mB)
        fr = bm.frame
        mom_local = (c.integrate1(v[0]), c.integrate1(v[1]))
        first_local = (c.integrate1(bm.X), c.integrate1(bm.Y))
        first_N = rot(fr.theta, first_local)
        mom_N = rot(fr.theta, mom_local)
        for k in range(2):
            first_moment[k].append(mB * fr.r[k] + first_N[k])
            momentum[k].append(mom_N[k])
        # r_P x v_P is invariant under rotation: use beam-frame components
        r_local = rot(-fr.theta, fr.r)
        h_origin.append(_cross(r_local, mom_local)
                        + c.integrate(bm.X, v[1]) - c.integrate(bm.Y, v[0]))
        if bm.rotation is not None:   # the sections' own rotation (Rayleigh beam)
            kinetic.append(c.rotary_integrate(bm.rotation, bm.rotation) / 2)
            h_origin.append(c.rotary_integrate1(bm.rotation))
        _frame_outputs(out, name, fr, f"beam {name!r}'s root")
        L = kin.value(f"beams.{name}.L", bm.beam.L, f"L_{name}")
        text = bm.beam.L.strip() if isinstance(bm.beam.L, str) else repr(bm.beam.L)
        out.add(f"tip_{name}", bm.Y.evaluate(lambda a: c.station(a, L, text)), "m", "tip",
                f"deflection of beam {name!r}'s tip in the beam frame")
        modes = chain.beam_modes(name)
        strain.append(sp.Add(*[c.stiffness(i + 1, j + 1) * qi * qj * (1 if i == j else 2)
                               for i, qi in enumerate(modes) for j, qj in enumerate(modes) if j >= i]) / 2)
        axial = chain.beam_axial(name)
        strain.append(sp.Add(*[c.axial_stiffness(k + 1, l + 1) * sk * sl * (1 if k == l else 2)
                               for k, sk in enumerate(axial) for l, sl in enumerate(axial) if l >= k]) / 2)
    M = sp.Add(*mass_total)
    cm = [out.add(f"{a}_cm", sp.Add(*first_moment[k]) / M, "m", "position", f"{a} of the system's mass centre")
          for k, a in enumerate("xy")]
    p = [out.add(f"p_{a}", sp.Add(*momentum[k]), "kg m/s", "momentum", f"the system's momentum along {a}")
         for k, a in enumerate("xy")]
    out.add("h_o", sp.Add(*h_origin), "kg m^2/s", "momentum", "the system's angular momentum about the origin")
    out.add("h_cm", sp.Add(*h_origin) - _cross(cm, p), "kg m^2/s", "momentum",
            "the system's angular momentum about its mass centre")
    # ---------------------------------------------------------------- potential energy
    gravity = []
    gvec = gravity_vector(kin)
    if gvec is not None:
        for name, frame in kin.bodies.items():
            m = kin.value(f"bodies.{name}.mass", model.bodies[name].mass, f"m_{name}")
            gravity.append(-m * (gvec[0] * frame.r[0] + gvec[1] * frame.r[1]))
        for name, bm in kin.beams.items():
            c = bm.constants
            fr = bm.frame
            mB = c.pair(ONE, ONE)
            if bm.beam.gravity == "midpoint":
                L = kin.value(f"beams.{name}.L", bm.beam.L, f"L_{name}")
                text = bm.beam.L.strip() if isinstance(bm.beam.L, str) else repr(bm.beam.L)
                half = f"{text}/2" if isinstance(bm.beam.L, str) else repr(bm.beam.L / 2)
                p = (bm.X.evaluate(lambda a: c.station(a, L / 2, half)),
                     bm.Y.evaluate(lambda a: c.station(a, L / 2, half)))
                pN = rot(fr.theta, p)
                gravity.append(-mB * (gvec[0] * (fr.r[0] + pN[0]) + gvec[1] * (fr.r[1] + pN[1])))
            else:
                firstN = rot(fr.theta, (c.integrate1(bm.X), c.integrate1(bm.Y)))
                gravity.append(-(gvec[0] * (mB * fr.r[0] + firstN[0]) + gvec[1] * (mB * fr.r[1] + firstN[1])))
    springs = []
    for joint in chain.joints:
        if joint.stiffness is not None and moving_rest(kin, joint) is None:
            coord = chain.of(joint.name)[0]
            k = kin.value(f"joints.{joint.name}.stiffness", joint.stiffness, f"k_{joint.name}")
            rest = kin.value(f"joints.{joint.name}.rest", joint.rest, f"{coord.q.name}_rest")
            springs.append(k * (coord.q - rest) ** 2 / 2)
    for spring in model.springs.values():
        path = f"springs.{spring.name}"
        ends = [kin.end_frame(spring, end, path).r for end in ("a", "b")]
        length = sp.sqrt((ends[1][0] - ends[0][0]) ** 2 + (ends[1][1] - ends[0][1]) ** 2)
        k = kin.value(f"{path}.stiffness", spring.stiffness, f"k_{spring.name}")
        l0 = kin.value(f"{path}.rest_length", spring.rest_length, f"l0_{spring.name}")
        springs.append(k * (length - l0) ** 2 / 2)
    energy_outputs(out, kinetic=sp.Add(*kinetic), potential_gravity=sp.Add(*gravity), strain=sp.Add(*strain),
                   potential_springs=sp.Add(*springs))
    # ---------------------------------------------------------------- power of non-conservative forces
    speeds = chain.u
    power = []
    for kind in ("damping", "loads"):
        power += [u * f for u, f in zip(speeds, eom.F_r[kind]) if f != 0]
    for joint in chain.joints:
        if joint.damping is not None:
            coord = chain.of(joint.name)[0]
            c = kin.value(f"joints.{joint.name}.damping", joint.damping, f"c_{joint.name}")
            power.append(-c * coord.u ** 2)
    # springs between points: total power of the spring forces minus the rate of their energy
    spring_power = sp.Add(*[u * f for u, f in zip(speeds, eom.F_r["springs"]) if f != 0])
    if model.springs:
        springs_energy = sp.Add(*springs[len(springs) - len(model.springs):])
        power.append(spring_power + chain.dt(springs_energy))
    for owner, effort in eom.driver_efforts.items():
        coord = chain.of(owner)[0]
        power.append(effort * coord.u)
    power_and_efforts(out, eom, sp.Add(*power))
    return out


def _frame_outputs(out: Outputs, name: str, frame, where: str) -> None:
    """``x_<name>``, ``y_<name>`` [m] of ``where`` and ``theta_<name>`` [rad], the frame's angle."""
    for k, axis in enumerate("xy"):
        out.add(f"{axis}_{name}", frame.r[k], "m", "position", f"{axis} of {where}")
    out.add(f"theta_{name}", frame.theta, "rad", "frame_angle", f"angle of {name!r}'s frame")

