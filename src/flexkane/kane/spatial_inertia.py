"""Generalized inertia forces F*_r of a spatial chain, by composite bodies.

For a rigid body, ``F*_r = v_r . (-m a) + w_r . (-(I alpha + w x I w))`` (Kane and Levinson), with
``a = sum_s v_s u_s' + a_rem`` and ``alpha = sum_s w_s u_s' + alpha_rem``; so
``F*_r = -sum_s M_rs u_s' - Fhat_r``.

A speed moves every link beyond its joint rigidly: at the frame F of the first such link its
partial velocity field is a twist ``(A_r, W_r)`` (partial velocity of F's origin and partial angular
velocity, F's axes), and a point at ``rho`` from F's origin has ``v_P,r = A_r + W_r x rho``. The links
beyond F then enter only through their composite mass ``m``, first moment ``S = sum m rho``, inertia
tensor ``J`` about F's origin, resultant ``R = sum m a_rem`` and moment ``K`` about F's origin of the
inertia forces without u' (``rho x m a_rem`` and each body's ``I alpha_rem + w x I w``):

    M_rs = m A_r . A_s + A_r . (W_s x S) + A_s . (W_r x S) + W_r . J W_s,
    Fhat_r = A_r . R + W_r . K,

at the frame of the deeper of the two speeds. Composites are formed from the tips inwards, each
child's moved to its parent's frame by the parallel-axis theorem with the rotation ``Lambda`` and
offset ``s`` of the child's frame in the parent's (:meth:`~flexkane.kane.spatial_rigid_properties.SpatialRigidProperties.moved`), and named.
"""

from __future__ import annotations

import sympy as sp

from .inertia import InertiaForces, shared_frames
from .spatial_beam import acceleration_remainder as beam_acceleration_remainder
from .chain import BEAM_ROLES
from .spatial_beam import add_beam_rows, beam_own_properties
from .spatial_frame import acceleration_remainder, add, cross, dot
from .spatial_rigid_properties import SpatialRigidProperties, matvec

__all__ = ["spatial_inertia_forces"]


def own_properties(kin, body: str) -> SpatialRigidProperties:
    """Properties of one rigid body about its link frame."""
    chain = kin.chain
    m = kin.mass(body)
    I = kin.inertia_tensor(body)
    c = kin.link_point(body, None)                # mass centre in the link frame
    frame = kin.bodies[body]
    a = acceleration_remainder(frame, chain)
    w = frame.omega
    alpha = tuple(chain.dt(x) for x in w)
    euler = add(matvec(I, alpha), cross(w, matvec(I, w)))
    cc = dot(c, c)
    J = I + sp.Matrix(3, 3, lambda i, j: (m * cc if i == j else 0) - m * c[i] * c[j])
    ma = tuple(m * x for x in a)
    return SpatialRigidProperties(m, tuple(m * x for x in c), J, ma, add(cross(c, ma), euler), kin.planar)


def spatial_inertia_forces(kin) -> InertiaForces:
    """Mass matrix and remainder of F*_r of a spatial chain (module docstring).

    Parameters
    ----------
    kin : SpatialKinematics

    Returns
    -------
    InertiaForces
    """
    chain = kin.chain
    speeds = chain.u
    n = len(speeds)
    joints = chain.joints
    joint_of = {j.child: j.name for j in joints}
    children: dict[str, list] = {}
    for j in joints:
        children.setdefault(j.parent, []).append(j.child)
    beyond: dict[str, set] = {}
    for j in reversed(joints):
        beyond[j.child] = {j.child}.union(*(beyond[c] for c in children.get(j.child, [])))
    a_rems = {name: beam_acceleration_remainder(bm, chain) for name, bm in kin.beams.items()}
    composite: dict[str, SpatialRigidProperties] = {}
    for j in reversed(joints):
        link = j.child
        total = beam_own_properties(kin, link, a_rems[link]) if link in kin.beams else own_properties(kin, link)
        for child in children.get(link, []):
            s, rotation = kin.link_offsets[joint_of[child]]
            total = total + composite[child].moved(s, rotation)
        composite[link] = total.named(chain, f"{link}_composite" if children.get(link) else link)
    # the links whose frames a speed starts to move rigidly: its joint's child link, or for a
    # beam's own speeds (which deform the beam) the links attached to the beam's stations
    roots = {c.u: [j.child for j in joints if (j.parent == c.owner if c.role in BEAM_ROLES else j.name == c.owner)]
             for c in chain.coordinates if c.u is not None}
    twist: dict = {}

    def twist_at(u, link):
        key = (u, link)
        if key not in twist:
            F = kin.links[link]
            twist[key] = (tuple(chain.partial(x, u) for x in F.v), tuple(chain.partial(x, u) for x in F.omega))
        return twist[key]

    M = [[sp.Integer(0)] * n for _ in range(n)]
    rem = [sp.Integer(0)] * n
    for r in range(n):
        for root in roots[speeds[r]]:
            A, W = twist_at(speeds[r], root)
            P = composite[root]
            rem[r] += dot(A, P.R) + dot(W, P.K)
        for s in range(r, n):
            for F in shared_frames(roots[speeds[r]], roots[speeds[s]], beyond):
                Ar, Wr = twist_at(speeds[r], F)
                As, Ws = twist_at(speeds[s], F)
                P = composite[F]
                M[r][s] += (P.m * dot(Ar, As) + dot(Ws, cross(P.S, Ar)) + dot(Wr, cross(P.S, As))
                            + dot(Wr, matvec(P.J, Ws)))
    add_beam_rows(kin, M, rem, a_rems)
    for r in range(n):
        for s in range(r):
            M[r][s] = M[s][r]
    return InertiaForces(sp.Matrix(M), rem, speeds)
