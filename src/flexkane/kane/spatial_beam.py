"""Spatial beams: bending in two principal planes, torsion and axial stretch, on the spatial engine.

The beam frame B has its origin at the root and its x axis along the undeformed beam. The section's
principal axes (y_p, z_p) are turned from B's (y, z) by ``principal_angle`` (beta) about x. The point
at distance x from the root is at (B's axes)

    X(x) = x + sum_k Psi_k s_k - 1/2 sum_ij (d^y_ij q_yi q_yj + d^z_ij q_zi q_zj)   (foreshortening,
                                                                                   geometric stiffening)
    Y(x) = cos(beta) v - sin(beta) w,   Z(x) = sin(beta) v + cos(beta) w,
    v(x) = sum_i Phi^y_i q_yi (bends about z_p: EI_z),   w(x) = sum_j Phi^z_j q_zj (about y_p: EI_y),

and moves at ``v_P = v_B + w_B x r + r'`` (derivatives of the components, B's axes): the spatial
form of eq. 8.18. Every component is a :class:`~flexkane.kane.modal_field.Field` of atoms whose
products integrate to modal constants (:mod:`flexkane.kane.spatial_beam_constants`).

The sections twist by ``theta(x) = sum_k Theta_k q_tk`` about x; with ``rho_Ip`` (polar mass moment
of inertia per length) the section at x is a thin disc of inertia ``rho_Ip b1 b1`` turning at
``w_s = w_B + theta' b1``: kinetic energy ``1/2 int rho_Ip (w_Bx + theta')^2 dx`` and inertia torque
``dH/dt = rho_Ip (d(w_sx)/dt, w_Bz w_sx, -w_By w_sx)`` (B's axes), whose power is exactly the rate of
that energy. A Rayleigh beam's sections (``rho_Iz``, ``rho_Iy``: mass moments of inertia per length
about the principal axes z_p, y_p) turn in the same way about z_p with the slope ``v'`` and about
y_p with ``-w'``: each a thin rod along its axis ``a`` (fixed in B) turning at ``w_B.a + v_t'`` and
``w_B.a - w_t'``, so that each carries ``1/2 int rho_J (w_B.a + turn rate)^2 dx`` and its inertia
torque ``rho_J (d(w_a)/dt a + w_B x w_a a)`` has exactly that power (in the plane, the planar
Rayleigh beam's ``1/2 int rho_I (w + y_t')^2 dx``). The strain energy
``1/2 int (EI_z v''^2 + EI_y w''^2 + GJ theta'^2 + EA u'^2) dx`` gives ``F_r = -K q`` with the modal
stiffness constants, and modal damping ``-2 zeta_i sqrt(K_ii M_ii) u_i`` as in the planar beams.

A beam of a planar chain (``dimensions = 2``) is the case of one bending family, y, without twist:
its modes (role ``mode``) are that family's, with the planar atoms and constants (``phi(i)``,
``E_i``, ``G_ij``, ``H_ij``; :func:`family_coordinates`) and its ``rotary_inertia`` the
``rho_Iz`` of its sections turning about z.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..model.columns import Output
from ..model.parts import nonzero_field
from . import modal_sums
from .chain import BEAM_ROLES
from .modal_field import ONE, X, Field, cross3, dfs, dphi, phi, psi, rigid, theta, vec3, vec3_map
from .spatial_beam_constants import SpatialBeamConstants
from .spatial_beam_notebook import midpoint_gravity_forces, midpoint_potential, shear_moment_forces
from .spatial_frame import SpatialFrame, add, cross
from .spatial_rigid_properties import SpatialRigidProperties

__all__ = ["SpatialBeamMotion", "beam_motion", "beam_own_properties", "add_beam_rows", "beam_active_forces",
           "beam_outputs", "tip_outputs"]


@dataclass
class SpatialBeamMotion:
    """Motion of a spatial beam: its frame (origin at the root) and the fields along it.

    Attributes
    ----------
    beam : Beam
    frame : SpatialFrame
    constants : SpatialBeamConstants
    r : tuple of 3 Field
        Position of the point at x from the root, B's axes [m].
    v : tuple of 3 Field
        Its velocity in N, B's axes [m/s].
    turns : dict
        The sections' turns that carry kinetic energy: ``"t" -> (b1, w_B.b1 + theta_t')`` when
        ``rho_Ip`` is given, ``"y" -> (z_p, w_B.z_p + v_t')`` with ``rho_Iz`` and
        ``"z" -> (y_p, w_B.y_p - w_t')`` with ``rho_Iy``: the axis (3 components in B) and the
        angular speed about it [rad/s] (a :class:`Field`).
    """

    beam: object
    frame: SpatialFrame
    constants: SpatialBeamConstants
    r: tuple
    v: tuple
    turns: dict

    def own_speeds(self, chain) -> set:
        """The beam's own modal speeds (which deform it)."""
        return {c.u for c in chain.of(self.beam.name) if c.role in BEAM_ROLES}


def family_coordinates(chain, name: str, role: str) -> list:
    """A beam's coordinates of a role (``mode_y``, ``mode_z``, ``torsion``, ``axial``); a planar
    chain's beam has its modes (role ``mode``) as the family y and no family z, no twist."""
    if chain.dimensions == 2 and role in ("mode_y", "mode_z", "torsion"):
        role = "mode" if role == "mode_y" else None
        if role is None:
            return []
    return chain.of(name, role)


def family_label(chain, label: str):
    """The direction label of a family's atoms: None for a planar chain's beams (planar atoms)."""
    return None if chain.dimensions == 2 else label


def beam_motion(kin, beam, frame: SpatialFrame, constants: SpatialBeamConstants) -> SpatialBeamMotion:
    """The fields of a spatial beam whose frame is ``frame`` (module docstring)."""
    chain = kin.chain
    coords = {role: family_coordinates(chain, beam.name, role) for role in ("mode_y", "mode_z", "torsion", "axial")}
    bend = {}
    for label in ("y", "z"):
        bend[label] = Field({phi(c.index, family_label(chain, label)): c.q for c in coords[f"mode_{label}"]})
    Xterms: dict = {X: sp.Integer(1)}
    for c in coords["axial"]:
        Xterms[psi(c.index)] = c.q
    if beam.geometric_stiffening:
        for label in ("y", "z"):
            modes = coords[f"mode_{label}"]
            for a, ca in enumerate(modes):
                for cb in modes[a:]:
                    factor = sp.Rational(-1, 2) if ca is cb else sp.Integer(-1)
                    Xterms[dfs(ca.index, cb.index, family_label(chain, label))] = factor * ca.q * cb.q
    Y, Z = bend["y"], bend["z"]
    if nonzero_field(beam.principal_angle):
        beta = kin.value(f"beams.{beam.name}.principal_angle", beam.principal_angle, f"beta_{beam.name}")
        c, s = sp.cos(beta), sp.sin(beta)
        Y, Z = bend["y"].scale(c) - bend["z"].scale(s), bend["y"].scale(s) + bend["z"].scale(c)
    r = (Field(Xterms), Y, Z)
    v = tuple(a + b + c for a, b, c in zip(vec3(*frame.v), cross3(frame.omega, r), vec3_map(r, chain.dt)))
    turns = {}
    if nonzero_field(beam.rho_Ip):
        turns["t"] = ((1, 0, 0), rigid(frame.omega[0]) + Field({theta(c.index): c.u for c in coords["torsion"]}))
    c, s = (sp.cos(beta), sp.sin(beta)) if nonzero_field(beam.principal_angle) else (1, 0)
    for label, key, axis, sign in (("y", "rho_Iz", (0, -s, c), 1), ("z", "rho_Iy", (0, c, s), -1)):
        if kin.chain.dimensions == 2:   # a planar beam's sections turn about z with its rotary inertia
            key = "rotary_inertia" if label == "y" else None
        if key is not None and nonzero_field(getattr(beam, key)):
            about = sp.Add(*[a * w for a, w in zip(axis, frame.omega)])
            turns[label] = (axis, rigid(about) + Field({dphi(m.index, family_label(chain, label)): sign * m.u
                                                        for m in coords[f"mode_{label}"]}))
    return SpatialBeamMotion(beam, frame, constants, r, v, turns)


def station_geometry(bm: SpatialBeamMotion, x, text: str, chain) -> tuple:
    """The section at station x: its centre's position in B (3,) [m], its orientation in B and
    its angular velocity relative to B (its own axes) [rad/s].

    The section is turned by the body-fixed sequence z, y, x with the angles ``Y'(x)`` (slope in
    the x-y plane), ``-Z'(x)`` (slope in the x-z plane) and the twist ``theta(x)``: to first order
    the small rotation ``(theta, -Z', Y')``, and exactly the planar turn by ``Y'`` when ``Z'`` and
    ``theta`` vanish.
    """
    from .rotation import body_sequence

    k = bm.constants

    def at(field, deriv=0):
        return modal_sums.evaluate(field, lambda atom: k.station(atom, x, text, deriv))

    p = tuple(at(c) for c in bm.r)
    coords = chain.of(bm.beam.name, "torsion")
    twist = modal_sums.modal_dot([k.station(theta(c.index), x, text) for c in coords], [c.q for c in coords])
    angles = (at(bm.r[1], 1), -at(bm.r[2], 1), twist)
    turn = body_sequence("zyx", angles)
    rates = [chain.dt(a) for a in angles]
    # w_rel = Rx(a3)^T Ry(a2)^T (0, 0, a1') + Rx(a3)^T (0, a2', 0) + (a3', 0, 0)
    from .rotation import about_axis

    rx, ry = about_axis((1, 0, 0), angles[2]), about_axis((0, 1, 0), angles[1])
    w = add(rx.inverse_apply(add(ry.inverse_apply((0, 0, rates[0])), (0, rates[1], 0))), (rates[2], 0, 0))
    return p, turn, tuple(sp.sympify(c) for c in w)


def acceleration_remainder(bm: SpatialBeamMotion, chain) -> tuple:
    """``d(v)/dt + w_B x v`` without u' terms, fields along B's axes [m/s^2]."""
    return tuple(a + b for a, b in zip(vec3_map(bm.v, chain.dt), cross3(bm.frame.omega, bm.v)))


def beam_own_properties(kin, name: str, a_rem: tuple):
    """Mass, first moment, inertia tensor about the root, resultant and moment of the inertia
    forces without u' of a spatial beam, B's axes
    (:class:`~flexkane.kane.spatial_rigid_properties.SpatialRigidProperties`)."""
    bm = kin.beams[name]
    k = bm.constants
    X, Y, Z = bm.r
    integ = k.integrate
    if kin.planar:     # J_zz only (SpatialRigidProperties.planar)
        J = sp.diag(0, 0, integ(X, X) + integ(Y, Y))
    else:
        J = sp.Matrix([[integ(Y, Y) + integ(Z, Z), -integ(X, Y), -integ(X, Z)],
                       [-integ(X, Y), integ(X, X) + integ(Z, Z), -integ(Y, Z)],
                       [-integ(X, Z), -integ(Y, Z), integ(X, X) + integ(Y, Y)]])
    R = tuple(k.integrate1(c) for c in a_rem)
    K = (integ(Y, a_rem[2]) - integ(Z, a_rem[1]), integ(Z, a_rem[0]) - integ(X, a_rem[2]),
         integ(X, a_rem[1]) - integ(Y, a_rem[0]))
    w = bm.frame.omega
    for key, (axis, turn) in bm.turns.items():    # the sections' turns: thin rods rho_J a a per length
        J += k.section(key, ONE, ONE) * sp.Matrix(axis) * sp.Matrix(axis).T
        H = tuple(k.section_integrate1(key, turn) * a for a in axis)
        K = add(K, add(tuple(k.section_integrate1(key, turn.map(kin.chain.dt)) * a for a in axis), cross(w, H)))
    return SpatialRigidProperties(k.pair(ONE, ONE), tuple(k.integrate1(c) for c in bm.r), J, R, K, kin.planar)


def add_beam_rows(kin, M: list | None, rem: list, a_rems: dict) -> None:
    """Add the terms of every beam's own modal speeds to ``M`` (upper triangle) and ``rem``:
    ``int rho v_P,r . v_P,s dx`` (+ the polar terms) for pairs with an own speed, and
    ``int rho v_P,r . a_rem dx`` for own rows (``M`` None: ``rem`` only)."""
    chain = kin.chain
    speeds = chain.u
    n = len(speeds)
    for name, bm in kin.beams.items():
        k = bm.constants
        own = bm.own_speeds(chain)
        if not own:
            continue
        V = [vec3_map(bm.v, lambda c, u=u: chain.partial(c, u)) for u in speeds]
        a_rem = a_rems[name]
        active = [r for r in range(n) if not all(c.is_zero() for c in V[r])]
        for i, r in enumerate(active):
            for s in active[i:] if M is not None else ():
                if speeds[r] in own or speeds[s] in own:
                    M[r][s] += sp.Add(*[k.integrate(a, b) for a, b in zip(V[r], V[s])])
            if speeds[r] in own:
                rem[r] += sp.Add(*[k.integrate(a, b) for a, b in zip(V[r], a_rem)])
        for key, (axis, turn) in bm.turns.items():
            W = [turn.map(lambda c, u=u: chain.partial(c, u)) for u in speeds]
            alpha_rem = turn.map(chain.dt)
            turning = [r for r in range(n) if not W[r].is_zero()]
            for i, r in enumerate(turning):
                for s in turning[i:] if M is not None else ():
                    if speeds[r] in own or speeds[s] in own:
                        M[r][s] += k.section_integrate(key, W[r], W[s])
                if speeds[r] in own:
                    # an own speed turns the sections about the rod's axis only: that component of dH/dt
                    rem[r] += k.section_integrate(key, W[r], alpha_rem)


#: Modal damping of a spatial beam: role of the coordinates -> (field of the ratios, index label).
DAMPING_FIELDS = {"mode_y": ("damping_y", "y"), "mode_z": ("damping_z", "z"), "torsion": ("torsion_damping", "t"),
                  "axial": ("axial_damping", "a")}


def _modal_mass(k, role: str, i: int) -> sp.Expr:
    """The diagonal modal mass of a coordinate of a role: ``G_yii``, ``G_zii``, ``Gt_ii``, ``AA_ii``."""
    if role == "torsion":
        return k.polar(theta(i), theta(i))
    if role == "axial":
        return k.pair(psi(i), psi(i))
    label = role[-1] if role != "mode" else None
    return k.pair(phi(i, label), phi(i, label))


def modal_damping(kin, name: str, role: str, stiffness) -> list:
    """``-2 zeta_i sqrt(K_ii M_ii) u_i`` of each coordinate of one role of a beam (zero where it has
    no damping ratio), as the planar beams' modal damping (:mod:`flexkane.kane.active`)."""
    bm = kin.beams[name]
    key, label = DAMPING_FIELDS[role]
    if kin.chain.dimensions == 2 and role == "mode_y":   # a planar beam's modes: damping, zeta_<b>_<i>
        key, label = "damping", ""
    ratios = getattr(bm.beam, key)
    out = []
    coords = family_coordinates(kin.chain, name, role)
    for j, c in enumerate(coords):
        if not ratios:
            out.append(sp.Integer(0))
            continue
        at = j if len(ratios) > 1 else 0
        zeta = kin.value(f"beams.{name}.{key}[{at}]", ratios[at], f"zeta_{name}_{label}{c.index}")
        if zeta == 0:
            out.append(sp.Integer(0))
            continue
        out.append(-2 * zeta * sp.sqrt(stiffness(c.index, c.index) * _modal_mass(bm.constants, c.role, c.index)) * c.u)
    return out


def beam_active_forces(kin, parts: dict, gravity) -> None:
    """Add the beams' elastic forces ``-K q``, their modal damping and distributed weight
    ``int rho v_P,r . g dx`` (the notebook variant's bending forces through the root's moment and
    shear and weight at the deformed midpoint for beams that choose them:
    :mod:`flexkane.kane.spatial_beam_notebook`)."""
    chain = kin.chain
    speeds = chain.u
    index = {u: r for r, u in enumerate(speeds)}
    for name, bm in kin.beams.items():
        k = bm.constants
        notebook = bm.beam.elastic_forces == "shear-moment"   # bending: spatial_beam_notebook
        for role, stiffness in (("mode_y", lambda i, j: k.bending_stiffness(i, j, "y")),
                                ("mode_z", lambda i, j: k.bending_stiffness(i, j, "z")),
                                ("torsion", lambda i, j: k.torsion_stiffness(i, j)), ("axial", k.axial_stiffness)):
            coords = family_coordinates(chain, name, role)
            for cj in coords if not (notebook and role.startswith("mode")) else ():
                parts["elastic"][index[cj.u]] += -modal_sums.modal_dot([stiffness(ci.index, cj.index) for ci in coords],
                                                                       [ci.q for ci in coords])
            for cj, force in zip(coords, modal_damping(kin, name, role, stiffness)):
                parts["damping"][index[cj.u]] += force
        if notebook:
            for r, force in enumerate(shear_moment_forces(kin, name)):
                parts["elastic"][r] += force
        if gravity is None:
            continue
        g = bm.frame.rotation.inverse_apply(gravity)
        if bm.beam.gravity == "midpoint":
            for r, force in enumerate(midpoint_gravity_forces(kin, name, g)):
                parts["gravity"][r] += force
            continue
        for r, u in enumerate(speeds):
            V = vec3_map(bm.v, lambda c: chain.partial(c, u))
            parts["gravity"][r] += sp.Add(*[k.integrate1(c) * gc for c, gc in zip(V, g)])


def strain_energy(kin, name: str) -> sp.Expr:
    """``1/2 q^T K q`` of a beam's modal stiffness constants [J]."""
    chain = kin.chain
    k = kin.beams[name].constants
    out = []
    for role, stiffness in (("mode_y", lambda i, j: k.bending_stiffness(i, j, "y")),
                            ("mode_z", lambda i, j: k.bending_stiffness(i, j, "z")),
                            ("torsion", lambda i, j: k.torsion_stiffness(i, j)), ("axial", k.axial_stiffness)):
        coords = family_coordinates(chain, name, role)
        for ci in coords:
            for cj in coords:
                out.append(stiffness(ci.index, cj.index) * ci.q * cj.q / 2)
    return sp.Add(*out)


def tip_outputs(kin, name: str) -> list:
    """Deformation of a beam's tip section, as outputs (:class:`~flexkane.model.columns.Output`) [m or rad].

    ``tip_<b>_y = v(L) = sum_i Phi^y_i(L) q_yi`` and ``tip_<b>_z = w(L)`` [m]: the tip's deflections
    along the section's principal axes y_p and z_p (in the beam frame's y and z when
    ``principal_angle`` is 0; ``tip_<b>_y`` is the planar ``tip_<b>``); ``slope_<b>_y = v'(L)``,
    ``slope_<b>_z = w'(L)`` [rad]; ``twist_<b> = theta(L) = sum_k Theta_k(L) q_tk`` [rad]. Each
    appears when the beam has coordinates of its kind.
    """
    chain = kin.chain
    beam = kin.beams[name].beam
    k = kin.beams[name].constants
    L = kin.value(f"beams.{name}.L", beam.L, f"L_{name}")
    text = beam.L.strip() if isinstance(beam.L, str) else repr(beam.L)
    out = []
    for label in ("y", "z"):
        coords = chain.of(name, f"mode_{label}")
        if coords:
            out.append(Output(f"tip_{name}_{label}",
                              sp.Add(*[k.station(phi(c.index, label), L, text) * c.q for c in coords]), "m", "tip",
                              f"deflection of beam {name!r}'s tip along the section's principal axis {label}"))
            out.append(Output(f"slope_{name}_{label}",
                              sp.Add(*[k.station(phi(c.index, label), L, text, 1) * c.q for c in coords]), "rad",
                              "slope", f"slope of beam {name!r}'s tip along the section's principal axis {label}"))
    coords = chain.of(name, "torsion")
    if coords:
        out.append(Output(f"twist_{name}", sp.Add(*[k.station(theta(c.index), L, text) * c.q for c in coords]),
                          "rad", "twist", f"twist of beam {name!r}'s tip section"))
    return out


def beam_outputs(kin, name: str, gravity) -> dict:
    """Energies and momenta of one beam: ``kinetic``, ``strain``, ``potential_gravity`` [J], mass
    [kg], first moment about N's origin (N axes) [kg m], linear momentum [kg m/s] and angular
    momentum about N's origin [kg m^2/s] (N axes)."""
    bm = kin.beams[name]
    k = bm.constants
    frame = bm.frame
    R = frame.rotation
    kinetic = sp.Add(*[k.integrate(c, c) for c in bm.v]) / 2
    for key, (_, turn) in bm.turns.items():
        kinetic += k.section_integrate(key, turn, turn) / 2
    m = k.pair(ONE, ONE)
    S = tuple(k.integrate1(c) for c in bm.r)                       # B's axes, about the root
    p = tuple(k.integrate1(c) for c in bm.v)                       # B's axes
    X, Y, Z = bm.r
    vx, vy, vz = bm.v
    h = (k.integrate(Y, vz) - k.integrate(Z, vy), k.integrate(Z, vx) - k.integrate(X, vz),
         k.integrate(X, vy) - k.integrate(Y, vx))                  # about the root, B's axes
    for key, (axis, turn) in bm.turns.items():
        h = add(h, tuple(k.section_integrate1(key, turn) * a for a in axis))
    pN = R.apply(p)
    first = add(tuple(m * c for c in frame.r), R.apply(S))
    momentum = add(cross(frame.r, pN), R.apply(h))
    potential = sp.Integer(0)
    if gravity is not None and bm.beam.gravity == "midpoint":
        potential = midpoint_potential(kin, name, gravity)
    elif gravity is not None:
        potential = -(m * sum(g * c for g, c in zip(gravity, frame.r)) + sum(g * c for g, c in zip(R.inverse_apply(gravity), S)))
    return {"kinetic": kinetic, "strain": strain_energy(kin, name), "potential_gravity": potential, "mass": m,
            "first": first, "p": pN, "h": momentum}
