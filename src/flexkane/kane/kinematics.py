"""Kinematics of the chain: frames, points and beam fields, with their velocities (eqs. 8.11-8.21).

Every vector is expressed in the frame of the link it belongs to, as the chapter does
(``v_CR = u1 i + u2 j``, eq. 8.11). Going from a parent attachment frame A to the child frame C of a
joint turned by ``phi`` relative to A:

    v_C = R(-phi) (v_A + w_A x d + d'),   w_C = w_A + phi',   (eq. 8.17 for a point of a rigid body)

where d is the joint's translation (free and prismatic joints). A point P of a beam at distance x
from the root (eq. 8.18):

    r_P = r_Q + X(x) b1 + Y(x) b2,   v_P = v_Q + w_B x (X, Y) + (X', Y'),

with ``Y = sum_i Phi_i q_i`` (eq. 8.15), ``X = x + sum_k Psi_k s_k`` for axial modes and
``- 1/2 sum_ij d_ij q_i q_j`` for the foreshortening (geometric stiffening). The section at x of a
Rayleigh beam turns at ``w_B + sum_i Phi_i'(x) q_i'`` (``BeamMotion.rotation``). Accelerations are
``a = sum_r v_r u_r' + a_rem`` with ``a_rem`` = (time derivative of the components without the u'
terms) + ``w x v`` (eq. 8.21).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..model.parts import Beam, Joint
from .beam_constants import BeamConstants
from .chain import Chain
from .intermediates import FRAME_NAME_ABOVE
from .modal_field import (ONE, X, Field, Vec, cross_z, dfs, dphi, phi, psi, rigid, rotate, vec,
                          vec_add, vec_map)

__all__ = ["FrameMotion", "BeamMotion", "Kinematics", "rot"]


def rot(angle, v: tuple) -> tuple:
    """Components in N of a vector with components ``v`` in a frame turned by ``angle``."""
    if angle == 0:
        return v
    c, s = sp.cos(angle), sp.sin(angle)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


@dataclass
class FrameMotion:
    """Motion of a frame fixed in a link (or at a beam station).

    Attributes
    ----------
    theta : sympy.Expr
        Angle of the frame's x axis from i0 [rad].
    omega : sympy.Expr
        Angular velocity about k0 [rad/s].
    r : tuple of Expr
        Position of the origin, components in N [m].
    v : tuple of Expr
        Velocity of the origin in N, components along the frame's own axes [m/s].
    """

    theta: sp.Expr
    omega: sp.Expr
    r: tuple
    v: tuple

    def point(self, p: tuple, chain: Chain) -> "FrameMotion":
        """The frame translated to the point with local position ``p`` (which may depend on q)."""
        pv = vec(*p)
        v = vec_add(vec_add(vec(*self.v), cross_z(self.omega, pv)), vec_map(pv, chain.dt))
        r = tuple(a + b for a, b in zip(self.r, rot(self.theta, p)))
        return FrameMotion(self.theta, self.omega, r, (v[0].coefficient(ONE), v[1].coefficient(ONE)))

    def named(self, chain: Chain, label: str) -> "FrameMotion":
        """The same frame with its large components replaced by intermediates (``theta_<label>``,
        ``omega_<label>``, ``rx_<label>``, ``ry_<label>``, ``vx_<label>``, ``vy_<label>``)."""
        def name(expr, what):
            return chain.name(expr, f"{what}_{label}", FRAME_NAME_ABOVE)

        return FrameMotion(name(self.theta, "theta"), name(self.omega, "omega"),
                           (name(self.r[0], "rx"), name(self.r[1], "ry")),
                           (name(self.v[0], "vx"), name(self.v[1], "vy")))

    def turned(self, angle, chain: Chain) -> "FrameMotion":
        """The frame turned by ``angle`` (an expression of q and t) about its origin."""
        v = rotate(vec(*self.v), angle)
        return FrameMotion(self.theta + angle, self.omega + chain.dt(angle), self.r,
                           (v[0].coefficient(ONE), v[1].coefficient(ONE)))


@dataclass
class BeamMotion:
    """Motion of a beam: its frame (origin at the root Q) and the fields along it.

    Attributes
    ----------
    beam : Beam
    frame : FrameMotion
    constants : BeamConstants
        Modal constants of this beam.
    X, Y : Field
        Position of the point at x, along and across the undeformed axis [m].
    v : Vec
        Velocity of the point at x in N, along the beam frame's axes [m/s] (eq. 8.18).
    rotation : Field or None
        Angular velocity of the section at x about k0, ``omega_B + sum_i Phi_i'(x) q_i'``
        [rad/s], for a Rayleigh beam (``rotary_inertia`` given and not a literal zero); None for
        an Euler-Bernoulli beam, whose sections' rotation carries no kinetic energy.
    """

    beam: Beam
    frame: FrameMotion
    constants: BeamConstants
    X: Field
    Y: Field
    v: Vec
    rotation: Field | None = None


class Kinematics:
    """Positions and velocities of every frame, body mass centre and beam of a chain.

    Parameters
    ----------
    chain : Chain
    """

    def __init__(self, chain: Chain):
        self.chain = chain
        model = chain.model
        self.symbols = chain.symbols
        self.bodies: dict[str, FrameMotion] = {}   # frame at the mass centre
        self.beams: dict[str, BeamMotion] = {}
        self.joint_frames: dict[str, tuple[FrameMotion, FrameMotion]] = {}  # (attachment, child)
        #: joint -> (origin of its child frame in the parent link's frame, angle between the frames)
        self.link_offsets: dict[str, tuple[tuple, sp.Expr]] = {}
        label_beams = len(model.beams) > 1
        self.constants = {name: BeamConstants(name, name if label_beams else "") for name in model.beams}
        for joint in chain.joints:
            self._add_joint(joint)

    @classmethod
    def of_spatial(cls, spatial) -> "Kinematics":
        """The kinematics of a planar chain derived by the spatial engine, in this class's terms.

        Every frame of ``spatial`` (a :class:`~flexkane.kane.spatial_kinematics.SpatialKinematics`
        of a planar chain) turns about z: its angle, angular velocity, position and velocity are
        the rotation's angle, the z component of its angular velocity and the x, y components of
        its position and velocity; a beam's fields are its x and y fields, its sections' rotation
        the turn about z of a Rayleigh beam. Nothing is derived again: the frames are the same
        named quantities, for the outputs, sensors, loop constraints and reports of planar chains.
        """
        kin = cls.__new__(cls)
        kin.chain, kin.symbols, kin.constants = spatial.chain, spatial.symbols, spatial.constants

        def frame(f) -> FrameMotion:
            return FrameMotion(f.rotation.angle, f.omega[2], tuple(f.r[:2]), tuple(f.v[:2]))

        kin.bodies = {name: frame(f) for name, f in spatial.bodies.items()}
        kin.beams = {name: BeamMotion(bm.beam, frame(bm.frame), bm.constants, bm.r[0], bm.r[1], tuple(bm.v[:2]),
                                      bm.turns["y"][1] if "y" in bm.turns else None)
                     for name, bm in spatial.beams.items()}
        kin.joint_frames = {name: (frame(a), frame(c)) for name, (a, c) in spatial.joint_frames.items()}
        kin.link_offsets = {name: (tuple(s[:2]), turn.angle) for name, (s, turn) in spatial.link_offsets.items()}
        return kin

    # ------------------------------------------------------------------ values
    def value(self, path: str, value, name: str) -> sp.Expr:
        return self.symbols.value(path, value, name)

    def body_point(self, body: str, point: str | None) -> tuple:
        """Local position of a named point of a body (the mass centre for ``None``) [m]."""
        if point is None:
            return (sp.Integer(0), sp.Integer(0))
        px, py = self.chain.model.bodies[body].points[point]
        return (self.value(f"bodies.{body}.points.{point}[0]", px, f"x_{body}_{point}"),
                self.value(f"bodies.{body}.points.{point}[1]", py, f"y_{body}_{point}"))

    def station(self, beam: str, path: str, value) -> tuple[sp.Expr, str]:
        """Station expression and its text (for symbol names)."""
        expr = self.value(path, value, f"x_{beam}_{path.split('.')[1]}")
        text = value.strip() if isinstance(value, str) else repr(value)
        return expr, text

    # ------------------------------------------------------------------ beams
    def _beam_fields(self, beam: Beam) -> tuple[Field, Field]:
        chain = self.chain
        modes = chain.beam_modes(beam.name)
        Y = Field({phi(i + 1): q for i, q in enumerate(modes)})
        Xterms: dict = {X: sp.Integer(1)}
        for k, s in enumerate(chain.beam_axial(beam.name)):
            Xterms[psi(k + 1)] = s
        if beam.geometric_stiffening:
            for i, qi in enumerate(modes):
                for j, qj in enumerate(modes):
                    if j < i:
                        continue
                    factor = sp.Rational(-1, 2) if i == j else sp.Integer(-1)
                    Xterms[dfs(i + 1, j + 1)] = factor * qi * qj
        return Field(Xterms), Y

    def beam_station(self, name: str, x: sp.Expr, text: str) -> FrameMotion:
        """Frame at station x of a beam: at the deflected point, turned by the slope y'(x)."""
        bm = self.beams[name]
        consts = bm.constants
        at = lambda f, d=0: f.evaluate(lambda a: consts.station(a, x, text, d))  # noqa: E731
        p = (at(bm.X), at(bm.Y))
        slope = at(bm.Y, 1)
        return bm.frame.point(p, self.chain).turned(slope, self.chain)

    def beam_station_velocity(self, name: str, x: sp.Expr, text: str) -> tuple:
        """Velocity of the beam point at station x, along the beam frame's axes [m/s] (eq. 8.19)."""
        bm = self.beams[name]
        value = lambda a: bm.constants.station(a, x, text)  # noqa: E731
        return (bm.v[0].evaluate(value), bm.v[1].evaluate(value))

    def end_frame(self, part, end: str, path: str) -> FrameMotion:
        """Frame at one end of a two-ended part (spring or loop constraint).

        The part has attributes ``body_<end>`` (``ground``, a body or a beam) and ``point_<end>``,
        ``station_<end>`` or ``position_<end>`` (absent attributes count as not given).
        """
        body = getattr(part, f"body_{end}")
        zero = sp.Integer(0)
        if body == "ground":
            pos = getattr(part, f"position_{end}", None) or (0, 0)
            r = (self.value(f"{path}.position_{end}[0]", pos[0], f"x_{part.name}_{end}"),
                 self.value(f"{path}.position_{end}[1]", pos[1], f"y_{part.name}_{end}"))
            return FrameMotion(zero, zero, r, (zero, zero))
        if body in self.bodies:
            return self.bodies[body].point(self.body_point(body, getattr(part, f"point_{end}", None)), self.chain)
        x, text = self.station(body, f"{path}.station_{end}", getattr(part, f"station_{end}"))
        return self.beam_station(body, x, text)

    def load_frame(self, load) -> FrameMotion:
        """Frame at the point where a load acts: a body point or a beam station."""
        if load.body in self.bodies:
            return self.bodies[load.body].point(self.body_point(load.body, load.point), self.chain)
        x, text = self.station(load.body, f"loads.{load.name}.station", load.station)
        return self.beam_station(load.body, x, text)

    # ------------------------------------------------------------------ joints
    def attachment(self, joint: Joint) -> FrameMotion:
        """Frame of the joint's attachment on its parent."""
        zero = sp.Integer(0)
        if joint.parent == "ground":
            pos = joint.parent_position or (0, 0)
            r = (self.value(f"joints.{joint.name}.parent_position[0]", pos[0], f"x_{joint.name}"),
                 self.value(f"joints.{joint.name}.parent_position[1]", pos[1], f"y_{joint.name}"))
            return FrameMotion(zero, zero, r, (zero, zero))
        if joint.parent in self.bodies:
            return self.bodies[joint.parent].point(self.body_point(joint.parent, joint.parent_point), self.chain)
        x, text = self.station(joint.parent, f"joints.{joint.name}.station", joint.station)
        return self.beam_station(joint.parent, x, text)

    def _local_attachment(self, joint: Joint) -> tuple[tuple, sp.Expr] | None:
        """Position of the joint's attachment in the parent link's frame and the angle of the
        attachment frame relative to it; None for a joint on the ground."""
        if joint.parent == "ground":
            return None
        zero = sp.Integer(0)
        if joint.parent in self.bodies:
            parent_joint = next(j for j in self.chain.joints if j.child == joint.parent)
            cp = self.body_point(joint.parent, parent_joint.child_point)       # the link frame's origin
            p = self.body_point(joint.parent, joint.parent_point)              # from the mass centre
            return (p[0] - cp[0], p[1] - cp[1]), zero
        x, text = self.station(joint.parent, f"joints.{joint.name}.station", joint.station)
        bm = self.beams[joint.parent]
        at = lambda f, d=0: f.evaluate(lambda a: bm.constants.station(a, x, text, d))  # noqa: E731
        return (at(bm.X), at(bm.Y)), at(bm.Y, 1)

    def _add_joint(self, joint: Joint) -> None:
        chain = self.chain
        attach = self.attachment(joint)
        offset = self.value(f"joints.{joint.name}.angle", joint.angle, f"theta_{joint.name}")
        coords = chain.of(joint.name)
        local = self._local_attachment(joint)
        # the child frame relative to the attachment frame: translation t (attachment axes), turn
        if joint.type == "free":
            shift, turn = (coords[0].q, coords[1].q), coords[2].q + offset
        elif joint.type == "revolute":
            shift, turn = (sp.Integer(0), sp.Integer(0)), coords[0].q + offset
        elif joint.type == "prismatic":
            axis = self.value(f"joints.{joint.name}.axis", joint.axis, f"alpha_{joint.name}")
            shift, turn = (coords[0].q * sp.cos(axis), coords[0].q * sp.sin(axis)), offset
        else:
            shift, turn = (sp.Integer(0), sp.Integer(0)), offset
        if local is not None:
            (px, py), slope = local
            t = rot(slope, shift)
            #: child frame's origin in the parent link's frame [m] and its angle from it [rad]
            self.link_offsets[joint.name] = ((px + t[0], py + t[1]), slope + turn)
        if joint.type == "free":
            cx, cy, ca = coords
            phi_ = ca.q + offset
            moved = attach.point((cx.q, cy.q), chain)
            # relative velocity components along the child axes are the speeds u1, u2 (eq. 8.10)
            c, s = sp.cos(phi_), sp.sin(phi_)
            vx, vy = moved.v
            carried = (vx - (cx.u * c - cy.u * s), vy - (cx.u * s + cy.u * c))  # parent-carried part
            child = FrameMotion(attach.theta + phi_, attach.omega + ca.u, moved.r,
                                (c * carried[0] + s * carried[1] + cx.u,
                                 -s * carried[0] + c * carried[1] + cy.u))
        elif joint.type == "revolute":
            child = attach.turned(coords[0].q + offset, chain)
        elif joint.type == "prismatic":
            axis = self.value(f"joints.{joint.name}.axis", joint.axis, f"alpha_{joint.name}")
            d = (coords[0].q * sp.cos(axis), coords[0].q * sp.sin(axis))
            child = attach.point(d, chain).turned(offset, chain)
        else:  # weld
            child = attach.turned(offset, chain)
        child = child.named(chain, joint.child)
        self.joint_frames[joint.name] = (attach, child)
        model = chain.model
        if joint.child in model.bodies:
            cp = self.body_point(joint.child, joint.child_point)
            self.bodies[joint.child] = child.point((-cp[0], -cp[1]), chain).named(chain, f"{joint.child}_cm")
        else:
            beam = model.beams[joint.child]
            Xf, Yf = self._beam_fields(beam)
            pv = (Xf, Yf)
            v = vec_add(vec_add(vec(*child.v), cross_z(child.omega, pv)), vec_map(pv, chain.dt))
            rotation = None
            if beam.rayleigh:
                slope = Field({dphi(i + 1): q for i, q in enumerate(chain.beam_modes(beam.name))})
                rotation = rigid(child.omega) + slope.map(chain.dt)
            self.beams[beam.name] = BeamMotion(beam, child, self.constants[beam.name], Xf, Yf, v, rotation)

    # ------------------------------------------------------------------ accelerations
    def acceleration_remainder(self, v: Vec, omega) -> Vec:
        """The part of the acceleration that does not multiply u' (eq. 8.21 without u' terms)."""
        return vec_add(vec_map(v, self.chain.dt), cross_z(omega, v))


def rigid_vec(v: tuple) -> Vec:
    """A rigid vector as a pair of fields."""
    return (rigid(v[0]), rigid(v[1]))
