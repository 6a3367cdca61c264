"""Generalized inertia forces F*_r (eq. 8.22), by composite bodies.

    F*_r = w_r . (-I alpha) + v_r . (-m a)        for every rigid body,
         + int_0^L v_P,r . (-a_P) rho dx          for every beam,

with ``a = sum_s v_s u_s' + a_rem``. Split accordingly, ``F*_r = -sum_s M_rs u_s' - Fhat_r`` where
``M_rs = sum m v_r . v_s + I w_r w_s + int rho v_P,r . v_P,s dx`` is the (symmetric) mass matrix.

Summed body by body, each entry of M has a term for every link beyond both speeds: the cost grows
with the cube of the chain's length. But a speed moves every link beyond the joint (or beam) it
belongs to as a rigid body: at the frame F of a link, its partial velocity field is a *twist*
``(A_r, W_r)`` (the partial velocity of F's origin and the partial angular velocity, eq. 8.20), and
at any point P of a link beyond F, ``v_P,r = A_r + W_r k x r_FP``. So the links beyond F enter
M_rs only through their *composite* rigid-body properties about F (mass m, first moment S, moment
of inertia J, all in F's axes) and Fhat_r only through the composite resultant R and moment K of
their ``rho a_rem``:

    M_rs = m A_r . A_s + W_s (k x S) . A_r + W_r (k x S) . A_s + J W_r W_s,
    Fhat_r = A_r . R + W_r K,

at the frame F of the deeper of the two speeds. The composite properties of a link's frame are
its own plus those of the links attached to it, moved to its frame: named intermediates computed
from the tips of the chain inwards. Each entry of M then costs a few operations whatever the
length of the chain. The terms of a beam's own modal speeds (which deform it rather than move it
rigidly) are integrated over that beam alone, with its modal constants (eq. 8.22).

A Rayleigh beam's sections also turn, at ``w_s(x) = w_B + sum_i Phi_i'(x) q_i'``, with the mass
moment of inertia ``rho_I`` per unit length: F*_r gains ``-int rho_I w_s,r alpha_s dx``. A speed
that moves the beam rigidly turns every section by ``W_r``, so the beam's composite moment of
inertia gains ``int rho_I dx`` and its moment ``K`` gains ``int rho_I alpha_s,rem dx``; the rows of
its own modal speeds gain ``int rho_I w_s,r w_s,s dx`` and ``int rho_I w_s,r alpha_s,rem dx``.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..model.coordinates import BEAM_ROLES
from .kinematics import Kinematics, rigid_vec
from .modal_field import ONE, vec_map

__all__ = ["LAZY_MASS_MIN_SPEEDS", "SPATIAL_LAZY_MASS_MIN_SPEEDS", "InertiaForces", "MassAssembly",
           "generalized_inertia_forces", "lazy_mass_min_speeds"]

#: Fewest speeds for which :func:`flexkane.kane.equations.derive` forms the mass matrix's entries
#: only when read: generated code then sums ``M`` from the :class:`MassAssembly`
#: (``flexkane.numerics.codegen.MASS_LOOP_MIN_SPEEDS`` is this number: one more than the 8 speeds up to
#: which generated code unrolls the L D L^T factorization, ``codegen.UNROLL_LDL_MAX``).
LAZY_MASS_MIN_SPEEDS = 9

#: The same for spatial chains (``codegen.SPATIAL_MASS_LOOP_MIN_SPEEDS``), chosen by measurement
#: (benchmarks/RESULTS.md, "Spatial chains: the mass matrix summed by the loop"): a spatial chain's
#: twists of every speed at every deeper frame are formed anyway for the generalized active forces,
#: so its written-out ``M`` costs only their products (sparse where joint axes are), while the loop
#: carries dense twists at run time. Up to 18 speeds (rigid chains of 3, 6, 12 revolute and 6
#: spherical joints, the flexible arms of 1 and 2 links, the built-in models of 13 and 16 speeds)
#: the written-out form built and evaluated faster; at 19 (a flexible arm of 3 links) the loop
#: compiled 3 times faster (its right-hand side stays one function where the written-out one is
#: split into parts) and evaluated 6 % faster.
SPATIAL_LAZY_MASS_MIN_SPEEDS = 19


def lazy_mass_min_speeds(dimensions: int) -> int:
    """:data:`LAZY_MASS_MIN_SPEEDS` of a planar chain, :data:`SPATIAL_LAZY_MASS_MIN_SPEEDS` of a
    spatial one."""
    return SPATIAL_LAZY_MASS_MIN_SPEEDS if dimensions == 3 else LAZY_MASS_MIN_SPEEDS


def shared_frames(roots_r, roots_s, beyond):
    """The link frames whose composite bodies both speeds move rigidly: for each pair of the links
    where the two speeds start to move links (``roots_r``, ``roots_s``), the outer of the two when one
    lies beyond the other (``beyond[a]``: the links outboard of ``a``, ``a`` included)."""
    for root_r in roots_r:
        for root_s in roots_s:
            if root_s in beyond[root_r]:
                yield root_s
            elif root_r in beyond[root_s]:
                yield root_r


class InertiaForces:
    """The pieces of F*_r.

    Attributes
    ----------
    mass_matrix : sympy.Matrix, shape (n, n)
        ``M_rs`` for all speeds (driven ones included).
    remainder : list of sympy.Expr, length n
        ``Fhat_r``, so that ``F*_r = -sum_s M_rs u_s' - Fhat_r``.
    speeds : list of sympy.Symbol
        The speeds r, in order.
    lazy : bool
        Whether ``mass_matrix`` is formed on first use, entry by entry (:meth:`entry`).
    assembly : MassAssembly or None
        The same mass matrix as data for a compiled sum over twists (generated code of long
        chains); None where a link's offset in its parent is not known.
    """

    def __init__(self, mass_matrix: sp.Matrix | None, remainder: list, speeds: list,
                 assembly: "MassAssembly | None" = None, terms: "_MassTerms | None" = None):
        self._mass_matrix = mass_matrix
        self.remainder = remainder
        self.speeds = speeds
        self.assembly = assembly
        self.terms = terms

    @property
    def lazy(self) -> bool:
        """Whether the entries of the mass matrix are formed only when read (:meth:`entry`)."""
        return self._mass_matrix is None

    @property
    def mass_matrix(self) -> sp.Matrix:
        if self._mass_matrix is None:
            self._mass_matrix = self.terms.matrix()
        return self._mass_matrix

    def entry(self, r: int, s: int) -> sp.Expr:
        """``M_rs`` (formed on demand when :attr:`lazy`)."""
        return self.terms.entry(r, s) if self._mass_matrix is None else self._mass_matrix[r, s]

    def F_r_star(self, ud: dict) -> list[sp.Expr]:
        """F*_r with the symbols of u' (eq. 8.22, term by term as eq. 8.23)."""
        n = len(self.speeds)
        return [-sp.Add(*[self.entry(r, s) * ud[self.speeds[s]] for s in range(n)])
                - self.remainder[r] for r in range(n)]


@dataclass
class MassAssembly:
    """The mass matrix of a chain as data: twists and composite bodies (module docstring; a
    spatial chain's: ``dimensions`` below).

    ``M_rs`` is the sum of three kinds of terms, which a compiled loop
    (:mod:`flexkane.numerics.mass_assembly`) adds up from the arrays below, so that the generated
    code evaluates only quantities whose number grows with the links, not with pairs of speeds:

    * for two *sources* (a speed and a link frame where it starts to move links rigidly) of which
      one's link is beyond (or is) the other's, at the deeper link F: ``T_r(F) . I_F T_s(F)``
      with ``T(F) = (A_x, A_y, W)`` the twist carried out to F link by link
      (``A_child = R(-angle) (A + W k x d)``, ``W`` unchanged) and ``I_F`` the composite
      rigid-body properties ``(m, S_x, S_y, J)`` about F;
    * for a beam's own modal speed r (a *wrench* ``c_r`` at the beam's frame B) and a source s
      that moves B rigidly: ``T_s(B) . c_r`` with ``c_r = (int rho v_r,x, int rho v_r,y,
      int rho (X v_r,y - Y v_r,x) [+ int rho_I w_s,r])``;
    * *explicit* entries: the products of a beam's own modal speeds (its modal mass).

    Attributes
    ----------
    parent : list of int
        Per link (tree order), the index of its parent link, -1 for a link on the ground.
    offsets : list of tuple
        Per link, ``(cos, sin, d_x, d_y)`` of its frame in its parent's (angle and origin [m]);
        for a link on the ground, in N.
    inertia : list of tuple
        Per link, the composite ``(m, S_x, S_y, J)`` about its frame [kg, kg m, kg m, kg m^2].
    sources : list of (int, int, tuple)
        ``(speed index, link index, (A_x, A_y, W))``.
    wrenches : list of (int, int, tuple)
        ``(speed index, beam's link index, (c_x, c_y, c_w))``.
    explicit : dict of (int, int) to sympy.Expr
        Entries ``(r, s)``, ``r <= s``, added as expressions.
    dimensions : int
        2 (the planar data above) or 3: a spatial chain's (:mod:`flexkane.kane.spatial_inertia`),
        whose ``offsets`` are each link frame's orientation in its parent's (direction cosines row
        by row) and origin there [m] (12; zeros for a link on the ground),
        ``inertia`` the composite ``(m, S_x, S_y, S_z, J_xx, J_xy, J_xz, J_yy, J_yz, J_zz)`` (10),
        twists ``(A, W)`` and wrenches ``(c_v, c_w)`` 6 components each.
    """

    parent: list
    offsets: list
    inertia: list
    sources: list
    wrenches: list
    explicit: dict
    dimensions: int = 2

    def reduced(self, free: list, sub) -> "MassAssembly":
        """The assembly of the rows and columns ``free`` (indices of speeds), numbered 0, 1, ...
        in that order, with ``sub`` (the drivers' laws) applied to every expression."""
        row = {r: i for i, r in enumerate(free)}
        tup = lambda v: tuple(sub(sp.sympify(e)) for e in v)  # noqa: E731
        return MassAssembly(list(self.parent), [tup(o) for o in self.offsets],
                            [tup(i) for i in self.inertia],
                            [(row[r], b, tup(t)) for r, b, t in self.sources if r in row],
                            [(row[r], b, tup(c)) for r, b, c in self.wrenches if r in row],
                            {(row[r], row[s]): sub(e) for (r, s), e in self.explicit.items()
                             if r in row and s in row}, self.dimensions)

    def expressions(self) -> list:
        """Every expression of the assembly (offsets, composites, twists, wrenches, entries)."""
        return [*(e for o in self.offsets for e in o),
                *(e for i in self.inertia for e in i), *(e for _, _, t in self.sources for e in t),
                *(e for _, _, c in self.wrenches for e in c), *self.explicit.values()]


@dataclass
class RigidProperties:
    """Rigid-body properties of a link (or of everything beyond a frame) about a frame's origin.

    Components along the frame's axes. ``m`` mass [kg], ``S`` first moment (m times the position
    of the mass centre) [kg m], ``J`` moment of inertia about the origin [kg m^2], ``R`` resultant
    of ``rho a_rem`` [N], ``K`` its moment about the origin [N m].
    """

    m: sp.Expr
    S: tuple
    J: sp.Expr
    R: tuple
    K: sp.Expr

    def __add__(self, other: "RigidProperties") -> "RigidProperties":
        return RigidProperties(self.m + other.m, (self.S[0] + other.S[0], self.S[1] + other.S[1]),
                               self.J + other.J, (self.R[0] + other.R[0], self.R[1] + other.R[1]),
                               self.K + other.K)

    def moved(self, d: tuple, angle) -> "RigidProperties":
        """The same properties about a frame in which this one's origin is at ``d`` and whose
        axes are turned by ``-angle`` relative to this one's."""
        c, s = sp.cos(angle), sp.sin(angle)
        S = (c * self.S[0] - s * self.S[1], s * self.S[0] + c * self.S[1])
        R = (c * self.R[0] - s * self.R[1], s * self.R[0] + c * self.R[1])
        return RigidProperties(
            self.m, (self.m * d[0] + S[0], self.m * d[1] + S[1]),
            self.J + 2 * (d[0] * S[0] + d[1] * S[1]) + self.m * (d[0] ** 2 + d[1] ** 2),
            R, self.K + d[0] * R[1] - d[1] * R[0])

    def named(self, chain, label: str) -> "RigidProperties":
        return RigidProperties(self.m, (chain.name(self.S[0], f"Sx_{label}"), chain.name(self.S[1], f"Sy_{label}")),
                               chain.name(self.J, f"J_{label}"),
                               (chain.name(self.R[0], f"Rx_{label}"), chain.name(self.R[1], f"Ry_{label}")),
                               chain.name(self.K, f"K_{label}"))


def _own_properties(kin: Kinematics, link: str, joint, beam_a_rem: dict,
                    beam_alpha_rem: dict) -> RigidProperties:
    """Properties of one link about its own frame (the child frame of the joint that carries it);
    ``beam_a_rem``: the acceleration remainder field of every beam, by name; ``beam_alpha_rem``:
    the angular acceleration remainder of the sections of every Rayleigh beam, by name."""
    chain = kin.chain
    model = chain.model
    if link in model.bodies:
        body = model.bodies[link]
        m = kin.value(f"bodies.{link}.mass", body.mass, f"m_{link}")
        inertia = kin.value(f"bodies.{link}.inertia", body.inertia, f"I_{link}")
        cp = kin.body_point(link, joint.child_point)
        c = (-cp[0], -cp[1])                         # mass centre in the link's frame
        frame = kin.bodies[link]                     # at the mass centre, same axes
        a = kin.acceleration_remainder(rigid_vec(frame.v), frame.omega)
        ax, ay = a[0].coefficient(ONE), a[1].coefficient(ONE)
        alpha = chain.dt(frame.omega)
        return RigidProperties(m, (m * c[0], m * c[1]), inertia + m * (c[0] ** 2 + c[1] ** 2),
                               (m * ax, m * ay), m * (c[0] * ay - c[1] * ax) + inertia * alpha)
    bm = kin.beams[link]
    consts = bm.constants
    a = beam_a_rem[link]
    own = RigidProperties(consts.pair(ONE, ONE), (consts.integrate1(bm.X), consts.integrate1(bm.Y)),
                          consts.integrate(bm.X, bm.X) + consts.integrate(bm.Y, bm.Y),
                          (consts.integrate1(a[0]), consts.integrate1(a[1])),
                          consts.integrate(bm.X, a[1]) - consts.integrate(bm.Y, a[0]))
    if link in beam_alpha_rem:    # the sections' rotation (Rayleigh beam)
        zero = sp.Integer(0)
        own = own + RigidProperties(zero, (zero, zero), consts.rotary(ONE, ONE), (zero, zero),
                                    consts.rotary_integrate1(beam_alpha_rem[link]))
    return own


def generalized_inertia_forces(kin: Kinematics, lazy: bool = False) -> InertiaForces:
    """Mass matrix and remainder of F*_r of the chain, by composite bodies (module docstring).

    Parameters
    ----------
    kin : Kinematics
    lazy : bool
        Form the entries of the mass matrix only when they are read (:attr:`InertiaForces.lazy`):
        where generated code sums ``M`` from its :class:`MassAssembly`, nothing else may need them.

    Returns
    -------
    InertiaForces
    """
    chain = kin.chain
    speeds = chain.u
    n = len(speeds)
    joints = chain.joints                             # tree order: a parent before its children
    frame = {j.child: kin.joint_frames[j.name][1] for j in joints}
    joint_of = {j.child: j.name for j in joints}
    children: dict[str, list] = {}
    for j in joints:
        children.setdefault(j.parent, []).append(j.child)
    # links beyond each link's frame (itself included)
    beyond: dict[str, set] = {}
    for j in reversed(joints):
        beyond[j.child] = {j.child}.union(*(beyond[c] for c in children.get(j.child, [])))
    beam_a_rem = {name: kin.acceleration_remainder(bm.v, bm.frame.omega) for name, bm in kin.beams.items()}
    beam_alpha_rem = {name: bm.rotation.map(chain.dt) for name, bm in kin.beams.items()
                      if bm.rotation is not None}
    # composite properties, from the tips inwards, named at each link
    composite: dict[str, RigidProperties] = {}
    for j in reversed(joints):
        link = j.child
        total = _own_properties(kin, link, j, beam_a_rem, beam_alpha_rem)
        for child in children.get(link, []):
            d, angle = kin.link_offsets[joint_of[child]]    # the child's frame in this link's frame
            total = total + composite[child].moved(d, angle)
        composite[link] = total.named(chain, f"{link}_composite") if children.get(link) else total.named(chain, link)
    # where each speed starts to move links rigidly: the frame of its joint's link, or the frames of
    # the links attached to its beam
    roots = {}
    for c in chain.coordinates:
        if c.role in BEAM_ROLES:
            roots[c.u] = [j.child for j in joints if j.parent == c.owner]
        else:
            roots[c.u] = [j.child for j in joints if j.name == c.owner]
    terms = _MassTerms(kin, speeds, roots, beyond, composite, frame)
    twist_at = terms.twist_at
    M = None if lazy else [[sp.Integer(0)] * n for _ in range(n)]
    rem = [sp.Integer(0)] * n
    for r in range(n):
        for root in roots[speeds[r]]:
            Ax, Ay, W = twist_at(speeds[r], root)
            P = composite[root]
            rem[r] += Ax * P.R[0] + Ay * P.R[1] + W * P.K
        if not lazy:
            for s in range(r, n):
                M[r][s] = terms.rigid_part(r, s)
    # a beam's own modal speeds deform it: their terms are integrated over that beam
    explicit: dict = {}
    wrenches: list = []
    for name, bm in kin.beams.items():
        consts = bm.constants
        own = terms.own[name]
        if not own:
            continue
        # every speed's field (written-out M), or only the beam's own speeds' (lazy M)
        moving = range(n) if not lazy else [r for r in range(n) if speeds[r] in own]
        V = {r: terms.field(name, r) for r in moving}
        a_rem = beam_a_rem[name]
        active = [r for r in moving if not (V[r][0].is_zero() and V[r][1].is_zero())]
        for i, r in enumerate(active):
            for s in active[i:]:
                if speeds[r] in own or speeds[s] in own:
                    term = consts.integrate(V[r][0], V[s][0]) + consts.integrate(V[r][1], V[s][1])
                    if not lazy:
                        M[r][s] += term
                    if speeds[r] in own and speeds[s] in own:
                        explicit[(r, s)] = explicit.get((r, s), sp.Integer(0)) + term
            if speeds[r] in own:
                rem[r] += consts.integrate(V[r][0], a_rem[0]) + consts.integrate(V[r][1], a_rem[1])
        W = None
        if bm.rotation is not None:   # the sections' rotation (Rayleigh beam)
            W = {r: terms.turning(name, r) for r in moving}
            turning = [r for r in moving if not W[r].is_zero()]
            for i, r in enumerate(turning):
                for s in turning[i:]:
                    if speeds[r] in own or speeds[s] in own:
                        term = consts.rotary_integrate(W[r], W[s])
                        if not lazy:
                            M[r][s] += term
                        if speeds[r] in own and speeds[s] in own:
                            explicit[(r, s)] = explicit.get((r, s), sp.Integer(0)) + term
                if speeds[r] in own:
                    rem[r] += consts.rotary_integrate(W[r], beam_alpha_rem[name])
        # the same products with a speed that moves the beam rigidly (twist T_s at its frame):
        # int rho v_r . (A_s + W_s k x r) dx = T_s . c_r
        for r in range(n):
            if speeds[r] in own:
                c_w = consts.integrate(bm.X, V[r][1]) - consts.integrate(bm.Y, V[r][0])
                if W is not None:
                    c_w += consts.rotary_integrate1(W[r])
                wrenches.append((r, name, (consts.integrate1(V[r][0]), consts.integrate1(V[r][1]), c_w)))
    if not lazy:
        for r in range(n):
            for s in range(r):
                M[r][s] = M[s][r]
        M = sp.Matrix(M)
    return InertiaForces(M, rem, speeds,
                         _assembly(kin, joints, composite, roots, twist_at, speeds, wrenches, explicit),
                         terms=terms if lazy else None)


class _MassTerms:
    """The entries of the written-out mass matrix, each formed on demand (module docstring):
    twists of the speeds at link frames and the beams' partial velocity fields, created once."""

    def __init__(self, kin: Kinematics, speeds: list, roots: dict, beyond: dict, composite: dict,
                 frame: dict):
        self.kin, self.speeds, self.roots, self.beyond = kin, speeds, roots, beyond
        self.composite, self.frame = composite, frame
        chain = kin.chain
        self.own = {name: {c.u for c in chain.of(name) if c.role in BEAM_ROLES}
                    for name in kin.beams}
        self._twist: dict = {}
        self._field: dict = {}
        self._turning: dict = {}
        self._entry: dict = {}

    def twist_at(self, u, link) -> tuple:
        """``(A_x, A_y, W)`` of speed ``u`` at the frame of ``link`` (eq. 8.20)."""
        key = (u, link)
        if key not in self._twist:
            chain, F = self.kin.chain, self.frame[link]
            self._twist[key] = (chain.partial(F.v[0], u), chain.partial(F.v[1], u), chain.partial(F.omega, u))
        return self._twist[key]

    def field(self, name: str, r: int):
        """The partial velocity field of beam ``name`` for speed ``r``."""
        if (name, r) not in self._field:
            chain, u = self.kin.chain, self.speeds[r]
            self._field[(name, r)] = vec_map(self.kin.beams[name].v, lambda c: chain.partial(c, u))
        return self._field[(name, r)]

    def turning(self, name: str, r: int):
        """The partial angular velocity field of the sections of Rayleigh beam ``name``."""
        if (name, r) not in self._turning:
            chain, u = self.kin.chain, self.speeds[r]
            self._turning[(name, r)] = self.kin.beams[name].rotation.map(lambda c: chain.partial(c, u))
        return self._turning[(name, r)]

    def rigid_part(self, r: int, s: int) -> sp.Expr:
        """The terms of ``M_rs`` (``r <= s``) of the links the two speeds move rigidly."""
        speeds, beyond = self.speeds, self.beyond
        total = sp.Integer(0)
        for F in shared_frames(self.roots[speeds[r]], self.roots[speeds[s]], beyond):
            Ar0, Ar1, Wr = self.twist_at(speeds[r], F)
            As0, As1, Ws = self.twist_at(speeds[s], F)
            P = self.composite[F]
            total += (P.m * (Ar0 * As0 + Ar1 * As1) + Ws * (-Ar0 * P.S[1] + Ar1 * P.S[0])
                      + Wr * (-As0 * P.S[1] + As1 * P.S[0]) + P.J * Wr * Ws)
        return total

    def entry(self, r: int, s: int) -> sp.Expr:
        """``M_rs``: the same sum, term by term in the same order, as the written-out matrix."""
        r, s = min(r, s), max(r, s)
        if (r, s) in self._entry:
            return self._entry[(r, s)]
        speeds = self.speeds
        total = self.rigid_part(r, s)
        for name, bm in self.kin.beams.items():
            own = self.own[name]
            if not own or not (speeds[r] in own or speeds[s] in own):
                continue
            consts = bm.constants
            Vr, Vs = self.field(name, r), self.field(name, s)
            if not (Vr[0].is_zero() and Vr[1].is_zero()) and not (Vs[0].is_zero() and Vs[1].is_zero()):
                total += consts.integrate(Vr[0], Vs[0]) + consts.integrate(Vr[1], Vs[1])
            if bm.rotation is not None:
                Wr, Ws = self.turning(name, r), self.turning(name, s)
                if not Wr.is_zero() and not Ws.is_zero():
                    total += consts.rotary_integrate(Wr, Ws)
        self._entry[(r, s)] = total
        return total

    def matrix(self) -> sp.Matrix:
        """The whole (symmetric) mass matrix."""
        n = len(self.speeds)
        return sp.Matrix(n, n, lambda r, s: self.entry(r, s))


def _assembly(kin: Kinematics, joints: list, composite: dict, roots: dict, twist_at, speeds: list,
              wrenches: list, explicit: dict) -> MassAssembly | None:
    """The mass matrix as twists and composite bodies (:class:`MassAssembly`); None if a link's
    offset in its parent is not known."""
    index = {j.child: b for b, j in enumerate(joints)}
    parent = [index.get(j.parent, -1) for j in joints]
    offsets = []
    for j, pa in zip(joints, parent):
        if pa < 0:   # a link on the ground: its frame's pose in N
            F = kin.joint_frames[j.name][1]
            offsets.append((sp.cos(F.theta), sp.sin(F.theta), F.r[0], F.r[1]))
            continue
        if j.name not in kin.link_offsets:
            return None
        d, angle = kin.link_offsets[j.name]
        offsets.append((sp.cos(angle), sp.sin(angle), d[0], d[1]))
    inertia = [(P.m, P.S[0], P.S[1], P.J) for P in (composite[j.child] for j in joints)]
    sources = [(r, index[root], twist_at(u, root)) for r, u in enumerate(speeds) for root in roots[u]]
    return MassAssembly(parent, offsets, inertia, sources,
                        [(r, index[link], c) for r, link, c in wrenches], explicit)
