"""Generalized active forces F_r (eqs. 8.24-8.35), by source.

* ``elastic``: internal forces of the beams. ``strain-energy`` beams give eq. 8.31,
  ``(F_{3+j})_I = -sum_i H_ij q_{3+i}`` (with H of eq. 8.32), plus ``-sum HA_kl s_l`` for axial modes;
  ``shear-moment`` beams give eq. 8.28 as written, with the bending moment and shear at x = 0 acting
  on the parent and the distributed load ``-(EI y'')''`` on the beam (the chapter's notebook).
* ``gravity``: eq. 8.34 with the weight of each beam distributed (``int v_P,r . g rho dx``) or at the
  deformed midpoint (eq. 8.19, the notebook).
* ``damping``: modal damping of the beams, ``-2 zeta_i sqrt(H_ii G_ii) u_i``.
* ``joints``: springs and dampers on joint coordinates.
* ``loads``: applied forces and torques, actuator torques of joints, joint springs whose rest
  position moves (an expression of t or of the state: the spring is then an actuator), and
  distributed loads on beams (``int v_P,r . f dx``, :mod:`flexkane.kane.distributed_loads`).
  Torques, forces and rest positions are expressions of t, the parameters and the signals of
  :mod:`flexkane.kane.controllers` (coordinates, speeds, sensors, controller states and outputs,
  by name): state feedback enters ``F_r = sum v_r . F + w_r T`` with the partial velocities of the
  point where it acts (``chain.partial``), and stays symbolic (named) in the equations.
  A model derived with its control inputs (:mod:`flexkane.kane.inputs`) adds them here too.
* ``springs``: linear springs and dampers between points.

Each source is a list of n expressions (one per speed).
"""

from __future__ import annotations

import sympy as sp

from .distributed_loads import distributed_load_forces
from .inputs import input_forces
from .kinematics import Kinematics, rot
from .modal_field import ONE, X, phi

__all__ = ["generalized_active_forces", "gravity_vector", "moving_rest"]


def gravity_vector(kin: Kinematics):
    """Gravity acceleration in N, components (g_x, g_y) [m/s^2]; None without gravity."""
    grav = kin.chain.model.gravity
    if grav is None:
        return None
    g = kin.value("gravity.g", grav.g, "g")
    if any(isinstance(c, str) for c in grav.direction):
        # expressions of the parameters: symbols of their own, normalised in the equations
        dx, dy = (kin.value(f"gravity.direction[{k}]", c, f"g_direction_{'xy'[k]}")
                  for k, c in enumerate(grav.direction))
    else:
        # literal numbers are part of the model's structure, normalised exactly
        dx, dy = (sp.Integer(c) if isinstance(c, int) else sp.nsimplify(c, rational=True) for c in grav.direction)
    norm = sp.sqrt(dx ** 2 + dy ** 2)
    return (g * dx / norm, g * dy / norm)


def moving_rest(kin: Kinematics, joint):
    """The rest position of a joint spring that moves (an expression of t or of the state), else None."""
    if joint.stiffness is None or not isinstance(joint.rest, str):
        return None
    rest = kin.symbols.effort(f"joints.{joint.name}.rest", joint.rest)
    constant = set(kin.symbols.parameters.values())
    return rest if rest.free_symbols - constant else None


def _local(theta, v):
    """Components along a frame turned by theta of a vector given in N."""
    return rot(-theta, v)


def generalized_active_forces(kin: Kinematics) -> dict[str, list]:
    """F_r by source (see the module docstring).

    Parameters
    ----------
    kin : Kinematics

    Returns
    -------
    dict of str to list of sympy.Expr
    """
    chain = kin.chain
    model = chain.model
    speeds = chain.u
    n = len(speeds)
    zero = lambda: [sp.Integer(0)] * n  # noqa: E731
    parts = {"elastic": zero(), "gravity": zero(), "damping": zero(), "joints": zero(),
             "loads": zero(), "springs": zero()}

    def add(kind, frame_or_v, vector, omega=None, torque=None):
        for r, u in enumerate(speeds):
            term = 0
            if vector is not None:
                term += chain.partial(frame_or_v[0], u) * vector[0] + chain.partial(frame_or_v[1], u) * vector[1]
            if torque is not None:
                term += chain.partial(omega, u) * torque
            if term != 0:
                parts[kind][r] += term

    # ---------------------------------------------------------------- gravity (8.33, 8.34)
    gvec = gravity_vector(kin)
    if gvec is not None:
        for name, frame in kin.bodies.items():
            m = kin.value(f"bodies.{name}.mass", model.bodies[name].mass, f"m_{name}")
            gl = _local(frame.theta, gvec)
            add("gravity", frame.v, (m * gl[0], m * gl[1]))
        for name, bm in kin.beams.items():
            gl = _local(bm.frame.theta, gvec)
            if bm.beam.gravity == "midpoint":
                L = kin.value(f"beams.{name}.L", bm.beam.L, f"L_{name}")
                mid = kin.beam_station_velocity(name, L / 2, _half(bm.beam.L))
                mB = bm.constants.pair(ONE, ONE)
                add("gravity", mid, (mB * gl[0], mB * gl[1]))
            else:
                for r, u in enumerate(speeds):
                    Vx = bm.v[0].map(lambda c: chain.partial(c, u))
                    Vy = bm.v[1].map(lambda c: chain.partial(c, u))
                    parts["gravity"][r] += bm.constants.integrate1(Vx) * gl[0] + bm.constants.integrate1(Vy) * gl[1]

    # ---------------------------------------------------------------- elastic (8.28, 8.31)
    for name, bm in kin.beams.items():
        beam = bm.beam
        consts = bm.constants
        modes = chain.beam_modes(name)
        mode_speeds = [c.u for c in chain.of(name, "mode")]
        index = {u: r for r, u in enumerate(speeds)}
        if beam.elastic_forces == "strain-energy":
            for j, uj in enumerate(mode_speeds):
                parts["elastic"][index[uj]] += -sp.Add(*[consts.stiffness(i + 1, j + 1) * qi
                                                         for i, qi in enumerate(modes)])
        else:
            EI = kin.value(f"beams.{name}.EI", beam.EI, f"EI_{name}")
            M0 = EI * sp.Add(*[consts.shear_moment("M0", i + 1) * qi for i, qi in enumerate(modes)])
            V0 = EI * sp.Add(*[consts.shear_moment("V0", i + 1) * qi for i, qi in enumerate(modes)])
            for r, u in enumerate(speeds):
                W = chain.partial(bm.frame.omega, u)
                VQy = chain.partial(bm.frame.v[1], u)
                Vy = bm.v[1].map(lambda c: chain.partial(c, u))
                distributed = 0
                for atom, coeff in Vy.items():
                    for i, qi in enumerate(modes):
                        if atom == ONE:
                            k = consts.shear_moment("J", i + 1)
                        elif atom == X:
                            k = consts.shear_moment("Jx", i + 1)
                        else:  # a transverse shape function
                            k = consts.shear_moment("JPhi", i + 1, atom[1])
                        distributed += coeff * EI * k * qi
                parts["elastic"][r] += W * M0 - VQy * V0 - distributed
        axial = chain.beam_axial(name)
        axial_speeds = [c.u for c in chain.of(name, "axial")]
        for l, ul in enumerate(axial_speeds):
            parts["elastic"][index[ul]] += -sp.Add(*[consts.axial_stiffness(k + 1, l + 1) * sk
                                                     for k, sk in enumerate(axial)])
        # ------------------------------------------------------------ modal damping
        for j, uj in enumerate(mode_speeds):
            if beam.damping:
                zeta_text = beam.damping[j] if len(beam.damping) > 1 else beam.damping[0]
                zeta = kin.value(f"beams.{name}.damping[{j if len(beam.damping) > 1 else 0}]",
                                 zeta_text, f"zeta_{name}_{j + 1}")
                if zeta != 0:
                    c = 2 * zeta * sp.sqrt(consts.stiffness(j + 1, j + 1) * consts.pair(phi(j + 1), phi(j + 1)))
                    parts["damping"][index[uj]] += -c * uj

    # ---------------------------------------------------------------- joint springs and dampers
    for joint in chain.joints:
        if joint.torque is not None:
            coord = chain.of(joint.name)[0]
            torque = kin.symbols.effort(f"joints.{joint.name}.torque", joint.torque)
            parts["loads"][speeds.index(coord.u)] += torque
        if joint.stiffness is None and joint.damping is None:
            continue
        coord = chain.of(joint.name)[0]
        r = speeds.index(coord.u)
        if joint.stiffness is not None:
            k = kin.value(f"joints.{joint.name}.stiffness", joint.stiffness, f"k_{joint.name}")
            rest = moving_rest(kin, joint)
            if rest is not None:   # an actuator: its power is counted in the work W
                parts["loads"][r] += -k * (coord.q - rest)
            else:
                rest = kin.value(f"joints.{joint.name}.rest", joint.rest, f"{coord.q.name}_rest")
                parts["joints"][r] += -k * (coord.q - rest)
        if joint.damping is not None:
            c = kin.value(f"joints.{joint.name}.damping", joint.damping, f"c_{joint.name}")
            parts["joints"][r] += -c * coord.u

    # ---------------------------------------------------------------- applied loads
    for load in model.loads.values():
        path = f"loads.{load.name}"
        frame = kin.load_frame(load)
        force = None
        if load.force is not None:
            fx = kin.symbols.effort(f"{path}.force[0]", load.force[0])
            fy = kin.symbols.effort(f"{path}.force[1]", load.force[1])
            force = (fx, fy) if load.frame == "local" else _local(frame.theta, (fx, fy))
        torque = None
        if load.torque is not None:
            torque = kin.symbols.effort(f"{path}.torque", load.torque)
        add("loads", frame.v, force, frame.omega, torque)

    # ---------------------------------------------------------------- distributed loads on beams
    for load in model.distributed_loads.values():
        for r, term in enumerate(distributed_load_forces(kin, load, speeds)):
            parts["loads"][r] += term

    # ---------------------------------------------------------------- springs between points
    for spring in model.springs.values():
        path = f"springs.{spring.name}"
        a, b = kin.end_frame(spring, "a", path), kin.end_frame(spring, "b", path)
        d = (b.r[0] - a.r[0], b.r[1] - a.r[1])
        length = sp.sqrt(d[0] ** 2 + d[1] ** 2)
        e = (d[0] / length, d[1] / length)
        va, vb = rot(a.theta, a.v), rot(b.theta, b.v)
        rate = e[0] * (vb[0] - va[0]) + e[1] * (vb[1] - va[1])
        k = kin.value(f"{path}.stiffness", spring.stiffness, f"k_{spring.name}")
        c = kin.value(f"{path}.damping", spring.damping, f"c_{spring.name}")
        l0 = kin.value(f"{path}.rest_length", spring.rest_length, f"l0_{spring.name}")
        tension = k * (length - l0) + c * rate
        fb = (-tension * e[0], -tension * e[1])            # on b, in N
        add("springs", vb, fb)
        add("springs", va, (-fb[0], -fb[1]))

    # ---------------------------------------------------------------- control inputs (kane/inputs.py)
    for r, term in enumerate(input_forces(kin)):
        if term != 0:
            parts["loads"][r] += term
    return parts


def _half(text) -> str:
    return f"{text}/2" if isinstance(text, str) else repr(text / 2)
