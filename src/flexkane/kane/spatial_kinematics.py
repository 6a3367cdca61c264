"""Kinematics of a spatial chain: every link's frame built from its parent's, as named intermediates.

For a joint whose parent link frame is P (the ground, or the parent body's link frame), attached at
``p`` (P's axes) with the constant orientation ``O_p`` of J_p in P, and whose child frame J_c has the
constant orientation ``O_c`` in the child link's frame L, the joint's relative motion (``d``, ``C``,
``w_rel``, ``v_rel`` of :mod:`flexkane.kane.spatial_joints`) gives

    s = p + O_p d                            (L's origin in P)
    Lambda = O_p C O_c^T                     (L's orientation in P)
    w_L = Lambda^T w_P + O_c w_rel
    v_L = Lambda^T (v_P + w_P x s) + O_c v_rel

and ``R_L = R_P Lambda``, ``r_L = r_P + R_P s``: the spatial form of eq. 8.17. A body's link frame has
the body's axes and its origin at the joint (the body's ``child_point``); its mass-centre frame is the
link frame moved to the mass centre. Each quantity is named (:meth:`SpatialFrame.named`), so a link's
expressions refer to its parent's symbols and never re-expand.

A planar chain (``dimensions = 2``) is the special case of planar motion: its joints turn about z
and translate in the x-y plane (:func:`flexkane.kane.spatial_joints.planar_joint_motion`, the
joint's constant ``angle`` in the joint's turn, so ``O_p``, ``O_c`` are the identity), its points
have a zero z component and its bodies the inertia tensor ``diag(0, 0, I)`` (only the moment of
inertia about the normal enters planar motion). Every rotation is then ``about_z`` of the link's
angle and every zero is an exact zero, so the expressions are those of the planar engine (eq. 8.17),
with the planar engine's names of the symbols; its beams are those of
:mod:`flexkane.kane.spatial_beam` bending in one family, with the planar modal constants
(:class:`~flexkane.kane.beam_constants.BeamConstants`: ``E_i``, ``G_ij``, ``H_ij``).
"""

from __future__ import annotations

import sympy as sp

from .beam_constants import BeamConstants
from .rotation import IDENTITY, Rotation
from .spatial_beam import beam_motion, station_geometry
from .modal_sums import IndexedBeamConstants
from .spatial_frame import GROUND, SpatialFrame, add, cross, ground_frame
from .spatial_joints import joint_motion, orientation, planar_joint_motion, vector

__all__ = ["SpatialKinematics"]


class SpatialKinematics:
    """Frames of every link and body mass centre of a spatial chain.

    Attributes
    ----------
    links : dict of str to SpatialFrame
        Each link's frame (origin at its joint, the link's axes).
    bodies : dict of str to SpatialFrame
        Each body's mass-centre frame (body axes).
    joint_frames : dict of str to (SpatialFrame, SpatialFrame)
        J_p and the child link's frame of each joint.
    link_offsets : dict of str to (tuple, Rotation)
        Per joint with a link as parent: the child link frame's origin ``s`` in the parent link's
        frame [m] and its orientation ``Lambda`` there (local quantities only).
    beams : dict of str to SpatialBeamMotion
        Each beam's frame (origin at the root) and fields (:mod:`flexkane.kane.spatial_beam`).
    constants : dict of str to SpatialBeamConstants
        Each beam's modal constants.
    """

    dimensions = 3

    def __init__(self, chain):
        self.chain = chain
        self.symbols = chain.symbols
        model = chain.model
        self.links: dict[str, SpatialFrame] = {}
        self.bodies: dict[str, SpatialFrame] = {}
        self.beams: dict = {}
        label_beams = len(model.beams) > 1
        constants = BeamConstants if self.planar else IndexedBeamConstants
        self.constants: dict = {name: constants(name, name if label_beams else "") for name in model.beams}
        self.joint_frames: dict[str, tuple[SpatialFrame, SpatialFrame]] = {}
        self.link_offsets: dict[str, tuple[tuple, Rotation]] = {}
        self._stations: dict = {}
        for joint in chain.joints:
            self._add_joint(joint)

    # ------------------------------------------------------------------ values
    @property
    def planar(self) -> bool:
        """Whether the chain is a planar one (motion in the x-y plane, module docstring)."""
        return self.chain.dimensions == 2

    def value(self, path: str, value, name: str) -> sp.Expr:
        return self.symbols.value(path, value, name)

    def _plane_vector(self, path: str, values, name: str) -> tuple:
        """A planar chain's position field (x, y) [m] as a 3-vector with a zero z component; its
        symbols named ``x_<name>``, ``y_<name>`` as the planar engine names them."""
        x, y = values or (0, 0)
        return (self.value(f"{path}[0]", x, f"x_{name}"), self.value(f"{path}[1]", y, f"y_{name}"), sp.Integer(0))

    def body_point(self, body: str, point: str | None) -> tuple:
        """Local position of a named point of a body from its mass centre, body axes [m]."""
        if point is None:
            return (sp.Integer(0),) * 3
        if self.planar:
            return self._plane_vector(f"bodies.{body}.points.{point}", self.chain.model.bodies[body].points[point],
                                      f"{body}_{point}")
        return vector(self.symbols, f"bodies.{body}.points.{point}", self.chain.model.bodies[body].points[point],
                      f"{body}_{point}")

    def link_point(self, body: str, point: str | None) -> tuple:
        """Position of a body's point in the body's link frame [m]."""
        joint = self.chain.joint_of(body)
        origin = self.body_point(body, joint.child_point)
        return tuple(a - b for a, b in zip(self.body_point(body, point), origin))

    def point_frame(self, body: str, point: str | None) -> SpatialFrame:
        """The body's frame moved to one of its points (the mass centre for None)."""
        return self.bodies[body].point(self.body_point(body, point), self.chain)

    def end_frame(self, part, end: str, path: str) -> SpatialFrame:
        """Frame at one end of a two-ended part (``body_<end>``, ``point_<end>``, ``position_<end>``)."""
        body = getattr(part, f"body_{end}")
        if body == "ground":
            pos = getattr(part, f"position_{end}", None)
            if self.planar:
                return ground_frame(self._plane_vector(f"{path}.position_{end}", pos, f"{part.name}_{end}"))
            return ground_frame(vector(self.symbols, f"{path}.position_{end}", pos, f"{part.name}_{end}"))
        if body in self.beams:     # the station named x_<beam>_<part> in a planar chain, as the planar engine does
            return self.beam_station(body, f"{path}.station_{end}", getattr(part, f"station_{end}"),
                                     part.name if self.planar else f"{part.name}_{end}")[0]
        return self.point_frame(body, getattr(part, f"point_{end}", None))

    def load_frame(self, load) -> SpatialFrame:
        """The frame where a load acts: a body point or a beam station."""
        if load.body in self.beams:
            return self.beam_station(load.body, f"loads.{load.name}.station", load.station, load.name)[0]
        return self.point_frame(load.body, load.point)

    def inertia_tensor(self, body: str) -> sp.Matrix:
        """Inertia tensor of a body about its mass centre, body axes (3, 3) [kg m^2]."""
        given = self.chain.model.bodies[body]
        if self.planar:     # the moment of inertia about the normal z
            return sp.diag(0, 0, self.value(f"bodies.{body}.inertia", given.inertia, f"I_{body}"))
        rows = given.inertia_tensor()
        principal = not isinstance(given.inertia[0], (list, tuple))    # [Ixx, Iyy, Izz]
        path = f"bodies.{body}.inertia"
        out = sp.zeros(3, 3)
        for i in range(3):
            for j in range(i, 3):
                if principal and i != j:
                    continue
                where = f"{path}[{i}]" if principal else f"{path}[{i}][{j}]"
                out[i, j] = out[j, i] = self.value(where, rows[i][j], f"I_{body}_{'xyz'[i]}{'xyz'[j]}")
        return out

    def mass(self, body: str) -> sp.Expr:
        return self.value(f"bodies.{body}.mass", self.chain.model.bodies[body].mass, f"m_{body}")

    # ------------------------------------------------------------------ joints
    def _parent(self, joint) -> tuple[SpatialFrame, tuple]:
        """The parent link's frame and the attachment's position in it (for a beam: the frame of
        the station, which follows the deflection, both slopes and the twist there)."""
        if joint.parent == "ground" and self.planar:
            return GROUND, self._plane_vector(f"joints.{joint.name}.parent_position", joint.parent_position,
                                              joint.name)
        if joint.parent == "ground":
            return GROUND, vector(self.symbols, f"joints.{joint.name}.parent_position", joint.parent_position,
                                  f"p_{joint.name}")
        if joint.parent in self.beams:
            return self.station_frame(joint)[0], (sp.Integer(0),) * 3
        return self.links[joint.parent], self.link_point(joint.parent, joint.parent_point)

    def station_frame(self, joint) -> tuple[SpatialFrame, tuple, Rotation]:
        """The frame at a joint's station on its parent beam, with its origin and orientation in
        the beam frame (:func:`flexkane.kane.spatial_beam.station_geometry`)."""
        if joint.name not in self._stations:     # asked for the parent frame, then for the link's offsets
            self._stations[joint.name] = self.beam_station(joint.parent, f"joints.{joint.name}.station",
                                                           joint.station, joint.name)
        return self._stations[joint.name]

    def beam_station(self, beam: str, path: str, value, label: str) -> tuple[SpatialFrame, tuple, Rotation]:
        """The frame of the section at a station (field ``path`` of value ``value`` [m]) of a beam,
        with its origin and orientation in the beam frame."""
        x = self.value(path, value, f"x_{beam}_{label}")
        text = value.strip() if isinstance(value, str) else repr(value)
        p, turn, w_rel = station_geometry(self.beams[beam], x, text, self.chain)
        frame = self.beams[beam].frame.point(p, self.chain).turned(turn, w_rel)
        return frame, p, turn

    def _add_joint(self, joint) -> None:
        chain = self.chain
        path = f"joints.{joint.name}"
        if self.planar:
            motion = planar_joint_motion(joint, chain.joint_coordinates(joint.name), self.symbols)
            Op = Oc = IDENTITY
        else:
            motion = joint_motion(joint, chain.joint_coordinates(joint.name), self.symbols)
            Op = orientation(self.symbols, f"{path}.orientation", getattr(joint, "orientation", None),
                             f"Op_{joint.name}")
            Oc = orientation(self.symbols, f"{path}.child_orientation", getattr(joint, "child_orientation", None),
                             f"Oc_{joint.name}")
        P, p = self._parent(joint)
        s = add(p, Op.apply(motion.d))
        local = Op * motion.rotation * Oc.transpose()
        local = local.map(lambda e: chain.name(e, f"L_{joint.child}"))
        if joint.parent in self.beams:    # in the beam frame: through the station's geometry
            _, ps, turn = self.station_frame(joint)
            self.link_offsets[joint.name] = (add(ps, turn.apply(s)), turn * local)
        elif joint.parent != "ground":
            self.link_offsets[joint.name] = (s, local)
        w = add(local.inverse_apply(P.omega), Oc.apply(motion.w_rel))
        v = add(local.inverse_apply(add(P.v, cross(P.omega, s))), Oc.apply(motion.v_rel))
        r = add(P.r, P.rotation.apply(s))
        link = SpatialFrame(P.rotation * local, w, r, v).named(chain, joint.child)
        self.joint_frames[joint.name] = (P.point(p, chain).turned(Op), link)
        self.links[joint.child] = link
        if joint.child in self.chain.model.beams:
            self.beams[joint.child] = beam_motion(self, self.chain.model.beams[joint.child], link,
                                                  self.constants[joint.child])
            return
        cp = self.body_point(joint.child, joint.child_point)
        self.bodies[joint.child] = link.point(tuple(-c for c in cp), chain).named(chain, f"{joint.child}_cm")
