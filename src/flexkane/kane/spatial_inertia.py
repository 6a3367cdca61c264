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

A long chain's mass matrix is also given as data (:class:`~flexkane.kane.inertia.MassAssembly`,
``dimensions = 3``) for the compiled loop of :mod:`flexkane.numerics.mass_assembly`: each link
frame's rotation ``Lambda`` and offset ``s`` in its parent's, its composite ``(m, S, J)``, each
speed's twist ``(A, W)`` where it starts to move links rigidly, and, for a beam's own modal speed r,
the wrench of its partial velocity field over the beam (B's axes)

    c_r = (int rho v_r dx,  int rho r x v_r dx + sum_turns a int rho_J w_r dx),

so that ``M_rs = A_s . c_v + W_s . c_w`` for a speed s that moves the beam rigidly; the products of
a beam's own speeds (its modal mass) are explicit entries. Where the generated code sums ``M`` so,
:func:`spatial_inertia_forces` forms the entries of the symbolic ``M`` only when they are read.
"""

from __future__ import annotations

import sympy as sp

from .inertia import InertiaForces, MassAssembly, shared_frames
from .spatial_beam import acceleration_remainder as beam_acceleration_remainder
from .chain import BEAM_ROLES
from .spatial_beam import add_beam_rows, beam_own_properties
from .spatial_frame import acceleration_remainder, add, cross, dot
from .modal_field import vec3_map
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


def spatial_inertia_forces(kin, lazy: bool = False) -> InertiaForces:
    """Mass matrix and remainder of F*_r of a spatial chain (module docstring).

    Parameters
    ----------
    kin : SpatialKinematics
    lazy : bool
        Form the entries of the mass matrix only when they are read
        (:attr:`~flexkane.kane.inertia.InertiaForces.lazy`): where generated code sums ``M``
        from its :class:`~flexkane.kane.inertia.MassAssembly`, nothing else may need them.

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
    terms = _SpatialMassTerms(kin, speeds, roots, beyond, composite)
    M = None if lazy else [[sp.Integer(0)] * n for _ in range(n)]
    rem = [sp.Integer(0)] * n
    for r in range(n):
        for root in roots[speeds[r]]:
            A, W = terms.twist_at(speeds[r], root)
            P = composite[root]
            rem[r] += dot(A, P.R) + dot(W, P.K)
        if not lazy:
            for s in range(r, n):
                M[r][s] = terms.rigid_part(r, s)
    add_beam_rows(kin, M, rem, a_rems)
    assembly = _assembly(kin, joints, composite, roots, terms)
    if lazy:
        return InertiaForces(None, rem, speeds, assembly, terms=terms)
    for r in range(n):
        for s in range(r):
            M[r][s] = M[s][r]
    return InertiaForces(sp.Matrix(M), rem, speeds, assembly)


class _SpatialMassTerms:
    """The entries of the written-out mass matrix of a spatial chain, each formed on demand: the
    twists of the speeds at link frames and the beams' partial velocity fields, created once."""

    def __init__(self, kin, speeds: list, roots: dict, beyond: dict, composite: dict):
        self.kin, self.speeds, self.roots, self.beyond, self.composite = kin, speeds, roots, beyond, composite
        self.own = {name: bm.own_speeds(kin.chain) for name, bm in kin.beams.items()}
        self._twist: dict = {}
        self._field: dict = {}
        self._entry: dict = {}

    def twist_at(self, u, link) -> tuple:
        """``(A, W)`` of speed ``u`` at the frame of ``link``, its axes."""
        key = (u, link)
        if key not in self._twist:
            chain, F = self.kin.chain, self.kin.links[link]
            self._twist[key] = (tuple(chain.partial(x, u) for x in F.v), tuple(chain.partial(x, u) for x in F.omega))
        return self._twist[key]

    def field(self, name: str, r: int) -> tuple:
        """The partial velocity field of beam ``name`` for speed ``r`` and the partial angular
        speeds of its sections' turns (``key -> Field``)."""
        if (name, r) not in self._field:
            chain, u, bm = self.kin.chain, self.speeds[r], self.kin.beams[name]
            self._field[(name, r)] = (vec3_map(bm.v, lambda c: chain.partial(c, u)),
                                      {key: turn.map(lambda c: chain.partial(c, u))
                                       for key, (_, turn) in bm.turns.items()})
        return self._field[(name, r)]

    def rigid_part(self, r: int, s: int) -> sp.Expr:
        """The terms of ``M_rs`` (``r <= s``) of the links the two speeds move rigidly."""
        speeds = self.speeds
        total = sp.Integer(0)
        for F in shared_frames(self.roots[speeds[r]], self.roots[speeds[s]], self.beyond):
            Ar, Wr = self.twist_at(speeds[r], F)
            As, Ws = self.twist_at(speeds[s], F)
            P = self.composite[F]
            total += (P.m * dot(Ar, As) + dot(Ws, cross(P.S, Ar)) + dot(Wr, cross(P.S, As))
                      + dot(Wr, matvec(P.J, Ws)))
        return total

    def beam_part(self, name: str, r: int, s: int) -> sp.Expr:
        """``int rho v_P,r . v_P,s dx`` over beam ``name`` with its sections' turns (``r <= s``),
        the terms :func:`~flexkane.kane.spatial_beam.add_beam_rows` adds."""
        bm = self.kin.beams[name]
        k = bm.constants
        (Vr, Wr), (Vs, Ws) = self.field(name, r), self.field(name, s)
        total = sp.Integer(0)
        if not all(c.is_zero() for c in Vr) and not all(c.is_zero() for c in Vs):
            total += sp.Add(*[k.integrate(a, b) for a, b in zip(Vr, Vs)])
        for key in bm.turns:
            if not Wr[key].is_zero() and not Ws[key].is_zero():
                total += k.section_integrate(key, Wr[key], Ws[key])
        return total

    def wrench(self, name: str, r: int) -> tuple:
        """``(c_v, c_w)`` of an own speed r of beam ``name`` at its frame (module docstring)."""
        bm = self.kin.beams[name]
        k = bm.constants
        V, W = self.field(name, r)
        X, Y, Z = bm.r
        c_w = (k.integrate(Y, V[2]) - k.integrate(Z, V[1]), k.integrate(Z, V[0]) - k.integrate(X, V[2]),
               k.integrate(X, V[1]) - k.integrate(Y, V[0]))
        for key, (axis, _) in bm.turns.items():
            c_w = add(c_w, tuple(a * k.section_integrate1(key, W[key]) for a in axis))
        return (*(k.integrate1(c) for c in V), *c_w)

    def entry(self, r: int, s: int) -> sp.Expr:
        """``M_rs``: the same terms as the written-out matrix's."""
        r, s = min(r, s), max(r, s)
        if (r, s) not in self._entry:
            total = self.rigid_part(r, s)
            for name, own in self.own.items():
                if self.speeds[r] in own or self.speeds[s] in own:
                    total += self.beam_part(name, r, s)
            self._entry[(r, s)] = total
        return self._entry[(r, s)]

    def matrix(self) -> sp.Matrix:
        """The whole (symmetric) mass matrix."""
        n = len(self.speeds)
        return sp.Matrix(n, n, lambda r, s: self.entry(r, s))


def _assembly(kin, joints: list, composite: dict, roots: dict, terms: _SpatialMassTerms) -> MassAssembly:
    """The mass matrix as link offsets, composite bodies, twists and beam-mode wrenches (module
    docstring)."""
    index = {j.child: b for b, j in enumerate(joints)}
    parent = [index.get(j.parent, -1) for j in joints]
    zero = (sp.Integer(0),) * 12
    offsets = []
    for j in joints:     # the link frame in its parent's: direction cosines row by row, origin
        s, rotation = kin.link_offsets.get(j.name, (None, None))
        offsets.append(zero if s is None else (*rotation.matrix, *s))
    inertia = []
    for P in (composite[j.child] for j in joints):
        inertia.append((P.m, *P.S, P.J[0, 0], P.J[0, 1], P.J[0, 2], P.J[1, 1], P.J[1, 2], P.J[2, 2]))
    speeds = terms.speeds
    sources = [(r, index[root], (*A, *W)) for r, u in enumerate(speeds) for root in roots[u]
               for A, W in [terms.twist_at(u, root)]]
    wrenches, explicit = [], {}
    for name, own in terms.own.items():
        rows = [r for r, u in enumerate(speeds) if u in own]
        for i, r in enumerate(rows):
            wrenches.append((r, index[name], terms.wrench(name, r)))
            for s in rows[i:]:
                explicit[(r, s)] = terms.beam_part(name, r, s)
    return MassAssembly(parent, offsets, inertia, sources, wrenches, explicit, dimensions=3)
