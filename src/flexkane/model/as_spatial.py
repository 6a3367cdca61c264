"""A planar model as the equivalent spatial model (``dimensions = 3``), its motion in the x-y plane.

:func:`as_spatial` rewrites every part of a planar model for the spatial engine, so that both
engines can be compared on the same chain (a planar chain is the special case of a spatial one):

* vectors get a zero z component (points, outlines, ground positions, gravity, forces);
* a body's moment of inertia J about the normal becomes the principal tensor ``diag(J, J, J)``: only
  ``Izz = J`` enters planar motion, and the in-plane values ``J, J`` keep the tensor a valid one
  (non-negative, triangle inequalities) whatever J is;
* a load's torque T becomes ``(0, 0, T)``; a beam sensor reads the bending plane y (``component``);
* a revolute joint turns about ``axis = [0, 0, 1]``; a prismatic one slides along
  ``[cos(axis), sin(axis), 0]``; a planar ``free`` joint becomes a spatial ``planar`` joint with
  normal z (the same coordinates x, y, angle; its speeds are the rates of x and y, so the initial
  speeds of the planar free joint, components along the child's axes (eq. 8.10), are rotated into
  them); a weld stays a weld;
* a joint's constant ``angle`` (the child frame turned from the attachment frame) becomes the
  ``child_orientation`` turn about z by ``-angle`` (J_c relative to the child's frame), which keeps
  the joint's axes, positions and coordinates those of the attachment frame.

* a beam bends in the x-y plane of its frame: its deflection along y (``n_modes_y`` shape
  functions of its ``shape``) bends about z with ``EI_z = EI``; ``EI_y = EI`` too (no z modes, so it
  does not enter); axial modes are kept. Its modal coordinates are named ``q_<beam>_y<i>`` (planar
  ``q_<beam>_<i>``), the only names that differ from the planar model's. Its ``rotary_inertia``
  becomes ``rho_Iz`` (the sections turn about z) and its modal ``damping`` ``damping_y``. The
  notebook variant's options stay as they are: ``gravity = "midpoint"`` (the whole weight at the
  deformed midpoint) and ``elastic_forces = "shear-moment"`` (eq. 8.28 in the bending plane y, the
  only one with modes), which spatial beams have (:mod:`flexkane.kane.spatial_beam_notebook`);
* a driver whose law reads the state (a gear, a cam, a filtered reference) stays one, its law's
  modal names renamed as below (spatial chains have them, :mod:`flexkane.kane.driver_laws`).

* a ``revolute`` loop constraint becomes a spatial ``point_on_line`` constraint along z (point b on
  the normal through point a: the two in-plane equations of the planar one); its dependent speeds
  keep their names (modal ones renamed);
* a distributed load keeps its components fx, fy (fz = 0) and its frame;
* every expression that may read the state (joint torques and rest positions, drivers' laws, load
  components, controllers' rates and outputs) has the planar modal coordinate and speed names replaced by the
  spatial ones (:func:`flexkane.expression_syntax.rename_names`: names only, the text kept).

A ``prismatic`` loop constraint has no spatial counterpart with its two scalar constraints (a
spatial prismatic closure keeps the orientation in three equations, redundant for a planar
motion): it is carried over unchanged and the spatial model refuses it by name.
"""

from __future__ import annotations

import copy

from ..errors import ModelError
from .coordinates import coordinate_names
from .model import Model
from .parts import Orientation, ShapeSpec

__all__ = ["as_spatial"]

_Z = (0, 0, 1)


def _pad(vector):
    """(x, y) -> (x, y, 0); None stays None."""
    return None if vector is None else (*tuple(vector), 0)


def _negated(value):
    """-value, as a number or an expression text."""
    if isinstance(value, str):
        return f"-({value})"
    return -value


def _text(value) -> str:
    return f"({value})"


def _slide_axis(axis) -> tuple:
    """The planar slide direction (an angle [rad] in the attachment frame) as a 3-vector."""
    if isinstance(axis, str):
        return (f"cos({axis})", f"sin({axis})", 0)
    if axis == 0:
        return (1, 0, 0)
    import math

    return (math.cos(axis), math.sin(axis), 0)


def as_spatial(model: Model, *, validate: bool = True) -> Model:
    """The spatial model (``dimensions = 3``) equivalent to a planar one.

    Parameters
    ----------
    model : Model
        A valid planar model (``dimensions = 2``); it is not changed.
    validate : bool
        Validate the result (:meth:`Model.validate`); a model with a part spatial models do not have
        (a prismatic loop constraint) then raises ModelError naming it.

    Returns
    -------
    Model
        The spatial model; its coordinates have the names and the order of the planar model's (a
        free joint's x, y, angle included), and so do its speeds, but for the modal coordinates of
        beams (``q_<b>_y<i>`` for ``q_<b>_<i>``; with ``naming = "sequential"`` all are the same).

    Raises
    ------
    ModelError
        If ``model`` is not a valid planar model (or, with ``validate``, the result does not validate).
    """
    if not isinstance(model, Model):
        raise ModelError("model", "a flexkane Model", type(model).__name__)
    if model.dimensions != 2:
        raise ModelError("dimensions", "a planar model (dimensions = 2) to convert", model.dimensions)
    model.validate()
    out = copy.deepcopy(model)
    out.dimensions = 3
    for body in out.bodies.values():
        body.inertia = (body.inertia, body.inertia, body.inertia)
        body.points = {name: _pad(xy) for name, xy in body.points.items()}
        body.outline = [_pad(xy) for xy in body.outline]
    for joint in out.joints.values():
        if joint.parent == "ground" and joint.parent_position is not None:
            joint.parent_position = _pad(joint.parent_position)
        if joint.type == "revolute":
            joint.axis = _Z
        elif joint.type == "prismatic":
            joint.axis = _slide_axis(joint.axis)
        elif joint.type == "free":
            joint.type, joint.axis = "planar", _Z
        if joint.angle != 0:
            joint.child_orientation = Orientation(axis=_Z, angle=_negated(joint.angle))
        joint.angle = 0
    for beam in out.beams.values():
        beam.EI_z = beam.EI_y = beam.EI
        beam.n_modes_y, beam.shape_y = beam.n_modes, beam.shape
        beam.shape, beam.shape_z = ShapeSpec(), ShapeSpec()
        beam.EI, beam.n_modes = None, 0
        beam.rho_Iz, beam.rotary_inertia = beam.rotary_inertia, None
        beam.damping_y, beam.damping = beam.damping, []
    _beam_mode_names(model, out)
    if out.gravity is not None:
        out.gravity.direction = _pad(out.gravity.direction)
    for load in out.loads.values():
        load.force = _pad(load.force)
        if load.torque is not None:
            load.torque = (0, 0, load.torque)
    for spring in out.springs.values():
        spring.position_a, spring.position_b = _pad(spring.position_a), _pad(spring.position_b)
    for con in out.constraints.values():
        con.position_a, con.position_b = _pad(con.position_a), _pad(con.position_b)
        if con.type == "revolute":
            con.type, con.axis = "point_on_line", _Z
    for sensor in out.sensors.values():   # a planar beam's sensors read its bending in the x-y plane
        if sensor.beam is not None:
            sensor.component = "y"
    _free_joint_speeds(model, out)
    _rename_modal_names(model, out)
    return out.validate() if validate else out


def _rename_modal_names(planar: Model, spatial: Model) -> None:
    """Planar modal coordinate and speed names (``q_<b>_<i>``, ``u_<b>_<i>``) replaced by the spatial
    ones (``q_<b>_y<i>``) in the expressions that may read the state (drivers' laws included) and in
    constraints' dependent speeds."""
    from ..expression_syntax import rename_names
    from .paths import set_value
    from .signals import effort_fields

    if planar.naming == "sequential":
        return
    names = {old: f"{prefix}_{c.owner}_y{c.index}" for c in coordinate_names(planar) if c.role == "mode"
             for old, prefix in ((c.q, "q"), (c.u, "u"))}
    if not names:
        return
    for path, value in effort_fields(spatial):
        renamed = rename_names(value, names)
        if renamed != value:
            set_value(spatial, path, renamed)
    for joint in spatial.joints.values():    # drivers whose law reads the state
        if joint.driver is not None:
            joint.driver.coordinate = rename_names(joint.driver.coordinate, names)
            joint.driver.speed = rename_names(joint.driver.speed, names)
    for ctrl in spatial.controllers.values():
        if isinstance(ctrl.states, dict):
            ctrl.states = {z: rename_names(rate, names) for z, rate in ctrl.states.items()}
        ctrl.output, ctrl.min, ctrl.max = (rename_names(v, names) for v in (ctrl.output, ctrl.min, ctrl.max))
    for con in spatial.constraints.values():
        if isinstance(con.dependent, list):
            con.dependent = [names.get(u, u) if isinstance(u, str) else u for u in con.dependent]


def _beam_mode_names(planar: Model, spatial: Model) -> None:
    """Initial values of planar beam modes (``q_<b>_<i>``, ``u_<b>_<i>``) under the spatial names
    (``q_<b>_y<i>``, ``u_<b>_y<i>``)."""
    if planar.naming == "sequential":    # q1, q2, ...: the same names in both
        return
    for c in coordinate_names(planar):
        if c.role != "mode":
            continue
        for old, new in ((c.q, f"q_{c.owner}_y{c.index}"), (c.u, f"u_{c.owner}_y{c.index}")):
            if old in spatial.initial:
                spatial.initial[new] = spatial.initial.pop(old)


def _free_joint_speeds(planar: Model, spatial: Model) -> None:
    """Initial speeds of planar free joints (components along the child's axes, eq. 8.10) as the
    rates of x and y that the spatial planar joint's speeds are."""
    coordinates = coordinate_names(planar)
    for joint in planar.joints.values():
        if joint.type != "free":
            continue
        cx, cy, ca = (c for c in coordinates if c.owner == joint.name)
        ux, uy = planar.initial.get(cx.u, 0), planar.initial.get(cy.u, 0)
        if ux == 0 and uy == 0:
            continue
        angle = f"{_text(planar.initial.get(ca.q, 0))} + {_text(joint.angle)}"
        if isinstance(ux, (int, float)) and isinstance(uy, (int, float)) and angle == "(0) + (0)":
            continue   # the child's axes are the attachment's: the components are the rates
        c, s = f"cos({angle})", f"sin({angle})"
        spatial.initial[cx.u] = f"{_text(ux)}*{c} - {_text(uy)}*{s}"
        spatial.initial[cy.u] = f"{_text(ux)}*{s} + {_text(uy)}*{c}"
