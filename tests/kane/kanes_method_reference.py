"""Independent derivations of rigid spatial chains with ``sympy.physics.mechanics.KanesMethod``.

A chain is described in plain Python (the same description builds the flexkane model in the tests):

* ``bodies``: name -> (mass [kg], inertia tensor about the mass centre, body axes, 3 x 3 [kg m^2],
  points: name -> (x, y, z) from the mass centre [m]);
* ``joints``: list of dicts with ``name``, ``type`` (``revolute`` or ``spherical``), ``parent``
  (``ground`` or a body), ``child``, ``parent_point`` (a point of the parent, or a position on the
  ground), ``child_point``, ``axis`` (revolute), ``orientation`` (optional: (axis, angle), the
  orientation of the joint's parent frame in the parent body's frame), ``torque`` (optional
  constant actuator torque [N m] about a revolute joint's axis);
* ``gravity``: (gx, gy, gz) [m/s^2].

Coordinates and speeds follow flexkane's definitions (revolute: angle and its rate; spherical:
Euler parameters of the child frame in the parent frame and the child's angular velocity relative
to the parent along the child's axes), in tree order.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from sympy.physics.mechanics import KanesMethod, Point, ReferenceFrame, RigidBody, dynamicsymbols, inertia


def kanes_method_rhs(bodies: dict, joints: list, gravity=(0.0, 0.0, 0.0), applied=()):
    """``f(q, u) -> u'`` of the chain by KanesMethod, and the names of q and u (flexkane's order)."""
    N = ReferenceFrame("N")
    O = Point("O")
    O.set_vel(N, 0)
    frames, centres = {"ground": N}, {"ground": O}
    q, u, kd, q_names, u_names = [], [], [], [], []
    system, loads = [], []
    for joint in joints:
        name = joint["name"]
        parent = joint["parent"]
        P = frames[parent]
        if parent == "ground":
            attach = O.locatenew(f"J_{name}", sum((c * v for c, v in zip(joint["parent_point"], N)), 0 * N.x))
            attach.set_vel(N, 0)
        else:
            p = bodies[parent][2][joint["parent_point"]]
            attach = centres[parent].locatenew(f"J_{name}", sum((c * v for c, v in zip(p, P)), 0 * P.x))
            attach.v2pt_theory(centres[parent], N, P)
        if joint.get("orientation") is not None:
            axis, angle = joint["orientation"]
            Jp = ReferenceFrame(f"Jp_{name}")
            Jp.orient_axis(P, sum((c * v for c, v in zip(axis, P)), 0 * P.x), angle)
            Jp.set_ang_vel(P, 0)
        else:
            Jp = P
        C = ReferenceFrame(f"C_{name}")
        kind = joint["type"]
        at = attach                             # J_c's origin
        if kind in ("revolute", "prismatic", "cylindrical", "planar"):
            axis = np.array(joint["axis"], dtype=float)
            axis = axis / np.linalg.norm(axis)
            n = sum((c * v for c, v in zip(axis, Jp)), 0 * Jp.x)
        if kind == "revolute":
            qj, uj = dynamicsymbols(f"q_{name} u_{name}")
            C.orient_axis(Jp, n, qj)
            C.set_ang_vel(Jp, uj * n)
            coordinates = [(qj, uj, f"q_{name}", f"u_{name}")]
        elif kind == "prismatic":
            qj, uj = dynamicsymbols(f"q_{name} u_{name}")
            C.orient_axis(Jp, Jp.z, 0)
            at = attach.locatenew(f"Jc_{name}", qj * n)
            at.set_vel(Jp, uj * n)
            at.v1pt_theory(attach, N, Jp)
            coordinates = [(qj, uj, f"q_{name}", f"u_{name}")]
        elif kind == "cylindrical":
            qa, qs, ua, us = dynamicsymbols(f"qa_{name} qs_{name} ua_{name} us_{name}")
            C.orient_axis(Jp, n, qa)
            C.set_ang_vel(Jp, ua * n)
            at = attach.locatenew(f"Jc_{name}", qs * n)
            at.set_vel(Jp, us * n)
            at.v1pt_theory(attach, N, Jp)
            coordinates = [(qa, ua, f"q_{name}_angle", f"u_{name}_angle"),
                           (qs, us, f"q_{name}_slide", f"u_{name}_slide")]
        elif kind == "universal":
            q1, q2, u1, u2 = dynamicsymbols(f"q1_{name} q2_{name} u1_{name} u2_{name}")
            a1, a2 = (np.array(a, dtype=float) / np.linalg.norm(a) for a in joint["axes"])
            middle = ReferenceFrame(f"U_{name}")
            middle.orient_axis(Jp, sum((c * v for c, v in zip(a1, Jp)), 0 * Jp.x), q1)
            C.orient_axis(middle, sum((c * v for c, v in zip(a2, middle)), 0 * Jp.x), q2)
            coordinates = [(q1, u1, f"q_{name}_1", f"u_{name}_1"), (q2, u2, f"q_{name}_2", f"u_{name}_2")]
        elif kind == "planar":      # normal z: in-plane axes x and y of J_p
            qx, qy, qa, ux, uy, ua = dynamicsymbols(f"qx_{name} qy_{name} qa_{name} ux_{name} uy_{name} ua_{name}")
            C.orient_axis(Jp, Jp.z, qa)
            C.set_ang_vel(Jp, ua * Jp.z)
            at = attach.locatenew(f"Jc_{name}", qx * Jp.x + qy * Jp.y)
            at.set_vel(Jp, ux * Jp.x + uy * Jp.y)
            at.v1pt_theory(attach, N, Jp)
            coordinates = [(qx, ux, f"q_{name}_x", f"u_{name}_x"), (qy, uy, f"q_{name}_y", f"u_{name}_y"),
                           (qa, ua, f"q_{name}_angle", f"u_{name}_angle")]
        else:                       # spherical, free: Euler parameters, body-frame angular velocity
            e = dynamicsymbols(f"e0_{name} e1_{name} e2_{name} e3_{name}")
            w = dynamicsymbols(f"wx_{name} wy_{name} wz_{name}")
            C.orient_quaternion(Jp, e)
            C.set_ang_vel(Jp, w[0] * C.x + w[1] * C.y + w[2] * C.z)
            e0, e1, e2, e3 = e
            wx, wy, wz = w
            rates = [-(e1 * wx + e2 * wy + e3 * wz) / 2, (e0 * wx - e3 * wy + e2 * wz) / 2,
                     (e3 * wx + e0 * wy - e1 * wz) / 2, (-e2 * wx + e1 * wy + e0 * wz) / 2]
            if kind == "free":
                x = dynamicsymbols(f"x_{name} y_{name} z_{name}")
                v = dynamicsymbols(f"vx_{name} vy_{name} vz_{name}")
                at = attach.locatenew(f"Jc_{name}", x[0] * Jp.x + x[1] * Jp.y + x[2] * Jp.z)
                v_rel = v[0] * C.x + v[1] * C.y + v[2] * C.z
                at.set_vel(Jp, v_rel)
                at.v1pt_theory(attach, N, Jp)
                q += list(x)
                u += list(v)
                kd += [xk.diff() - v_rel.dot(a) for xk, a in zip(x, Jp)]
                q_names += [f"q_{name}_{a}" for a in "xyz"]
                u_names += [f"u_{name}_v{a}" for a in "xyz"]
            q += list(e)
            u += list(w)
            kd += [ek.diff() - r for ek, r in zip(e, rates)]
            q_names += [f"q_{name}_e{k}" for k in range(4)]
            u_names += [f"u_{name}_w{a}" for a in "xyz"]
            coordinates = []
        for qj, uj, qn, un in coordinates:
            q.append(qj)
            u.append(uj)
            kd.append(qj.diff() - uj)
            q_names.append(qn)
            u_names.append(un)
        if joint.get("child_orientation") is not None:   # J_c in the child's frame: the child turned back
            axis, angle = joint["child_orientation"]
            B = ReferenceFrame(f"B_{name}")
            B.orient_axis(C, sum((c * v for c, v in zip(axis, C)), 0 * C.x), -angle)
            B.set_ang_vel(C, 0)
        else:
            B = C
        if joint.get("stiffness") is not None and kind == "revolute":
            spring = -joint["stiffness"] * (qj - joint.get("rest", 0.0)) - joint.get("damping", 0.0) * uj
            loads.append((B, spring * n))
            if P is not N:
                loads.append((P, -spring * n))
        child = joint["child"]
        m, I, points = bodies[child]
        cp = points[joint["child_point"]]
        cm = at.locatenew(f"cm_{child}", sum((-c * v for c, v in zip(cp, B)), 0 * B.x))
        cm.v2pt_theory(at, N, B)
        frames[child], centres[child] = B, cm
        dyadic = inertia(B, I[0][0], I[1][1], I[2][2], I[0][1], I[1][2], I[0][2])
        system.append(RigidBody(child, cm, B, m, (dyadic, cm)))
        loads.append((cm, m * sum((g * v for g, v in zip(gravity, N)), 0 * N.x)))
        if joint.get("torque") is not None and joint["type"] == "revolute":
            loads.append((B, joint["torque"] * n))
            if P is not N:
                loads.append((P, -joint["torque"] * n))
    for load in applied:
        frame = frames[load["body"]]
        axes = N if load["frame"] == "ground" else frame
        point = centres[load["body"]].locatenew(f"F_{load['body']}", sum(
            (c * v for c, v in zip(bodies[load["body"]][2][load["point"]], frame)), 0 * frame.x))
        point.v2pt_theory(centres[load["body"]], N, frame)
        loads.append((point, sum((c * v for c, v in zip(load["force"], axes)), 0 * N.x)))
        loads.append((frame, sum((c * v for c, v in zip(load["torque"], axes)), 0 * N.x)))
    kane = KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kd)
    kane.kanes_equations(system, loads)
    qs = sp.symbols(f"q0:{len(q)}")
    us = sp.symbols(f"u0:{len(u)}")
    plain = dict(zip(q, qs)) | dict(zip(u, us))
    M = sp.lambdify([qs, us], kane.mass_matrix.xreplace(plain), "numpy", cse=True)
    f = sp.lambdify([qs, us], kane.forcing.xreplace(plain), "numpy", cse=True)

    def rhs(qv, uv):
        return np.linalg.solve(np.array(M(qv, uv), dtype=float), np.array(f(qv, uv), dtype=float).ravel())

    return rhs, q_names, u_names


def random_state(q_names, u_names, rng):
    """A random state: joint angles in (-pi, pi), unit Euler parameters per spherical joint, speeds
    in (-2, 2)."""
    q = rng.uniform(-np.pi, np.pi, len(q_names))
    for k, name in enumerate(q_names):
        if name.endswith("_e0"):
            e = rng.normal(size=4)
            q[k:k + 4] = e / np.linalg.norm(e)
    return q, rng.uniform(-2, 2, len(u_names))
