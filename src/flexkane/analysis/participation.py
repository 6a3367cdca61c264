"""Modal participation: which motion of the chain a mode is, from its eigenvector.

The speeds of a linear model fall into families, each a kind of motion:

* a beam's bending coordinates: ``bending`` (planar beams; ``lag`` about a steady spin, the plane of
  the chain being the plane of rotation), or, for spatial beams, ``bending y`` and ``bending z``
  (deflection along the section's principal axes y_p and z_p). About a steady spin whose axis
  ``a`` is not along the beam, the two bending planes become **flap** (deflection along the part
  ``a_s`` of the spin axis normal to the beam: out of the plane of rotation) and **lag** (deflection
  normal to both: in the plane of rotation): the pair ``(q_yi, q_zi)`` of the same index is turned
  into ``(flap_i, lag_i)`` by the angle between y_p and ``a_s``, and a coordinate without a partner
  is split by the squared cosines of that angle;
* a beam's torsion (``torsion``) and axial (``axial``) coordinates;
* the coordinates of a joint that floats its child or turns it freely, each a motion of its own
  named after the child link: a free joint's translations along the axes of its child frame J_c
  (``translation along x of bus``; the speeds' axes, :mod:`flexkane.kane.spatial_joints`) and its
  or a spherical joint's turns about them (``rotation about x of bus``; a planar free joint's turn
  is ``rotation of beam``);
* any other joint's coordinates (``joint <name>``).

The participation of a family in a mode is its share of the mode's kinetic energy on the diagonal
of the mass matrix, ``sum_k M_kk |du_k|^2`` over the family's speeds (in the turned flap/lag speeds
for spatial beams), ``du`` the speed part of the eigenvector (its coordinate part ``dq`` for a
mode of zero eigenvalue, which does not move, taken to the speeds that move the chain along it by
:func:`flexkane.analysis.eigen.modal_analysis`). A mode's motion is the kind of motion of the largest
share summed over the beams (``flap``); with several beams the name of the beam that carries at least
3/4 of it follows (``flap blade_a``; a mode shared by two symmetric panels is ``flap``). The spin
axis is the beam frame's angular velocity per unit spin rate at the operating point, in the beam
frame's axes. The **share** of a mode's motion is the participation of its family, or of all
the families of its kind when no beam owns it (``flap`` above: the flap of every beam), as
:meth:`MotionFamilies.share` gives it.
"""

from __future__ import annotations

import weakref

import numpy as np

__all__ = ["MotionFamilies", "motion_families"]

#: The beams' angular velocities as numeric functions, per linearization.
_ANGULAR_VELOCITIES: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()

#: A spin axis closer than this (sine of the angle) to the beam's axis gives no flap and lag.
_ALONG_BEAM = 1e-6
#: Share of a kind of motion one beam must carry for a mode to be named after it.
_OWNS = 0.75
#: Joint types whose coordinates are motions of their own, named after the child link (module docstring).
_FLOATING = ("free", "spherical")
#: The motion of a floating joint's coordinate, by role (``{child}`` the joint's child link).
_FLOATING_MOTIONS = {"x": "translation along x of {child}", "y": "translation along y of {child}",
                     "z": "translation along z of {child}", "e1": "rotation about x of {child}",
                     "e2": "rotation about y of {child}", "e3": "rotation about z of {child}"}


class MotionFamilies:
    """The families of motion of a linear model's speeds (module docstring).

    Attributes
    ----------
    names : list of str
        Family names, in the order of first appearance along the speeds.
    kinds : list of (str, str or None)
        The kind of motion (``flap``, ``torsion``, ``joint hub``) and the beam of each family.
    transform : numpy.ndarray
        Orthogonal map from the speeds to the family speeds (flap/lag pairs turned), shape (n, n).
    weights : numpy.ndarray
        Share of each family speed in each family, shape (n, len(names)); rows sum to 1.
    """

    def __init__(self, names: list, transform: np.ndarray, weights: np.ndarray, kinds: list | None = None):
        self.names = names
        self.kinds = kinds if kinds is not None else [(name, None) for name in names]
        self.transform = transform
        self.weights = weights

    def participation(self, M: np.ndarray, vector: np.ndarray) -> dict:
        """Shares of the families in a mode of speeds (or coordinates) ``vector`` (n,), mass
        matrix M (n, n); family name -> fraction, summing to 1 (empty for a zero vector)."""
        T = self.transform
        moved = T @ np.asarray(vector, dtype=complex)
        energy = np.abs(np.einsum("ij,jk,ik->i", T, M, T)) * np.abs(moved) ** 2
        shares = energy @ self.weights
        total = float(np.sum(shares))
        if not total > 0:
            return {}
        return {name: float(s / total) for name, s in zip(self.names, shares)}

    def dominant(self, participation: dict) -> str:
        """The motion of a mode (module docstring) from its participation ('' when empty)."""
        if not participation:
            return ""
        kinds: dict = {}
        for name, (kind, beam) in zip(self.names, self.kinds):
            kinds.setdefault(kind, {})[name] = participation.get(name, 0.0)
        kind = max(kinds, key=lambda k: (round(sum(kinds[k].values()), 12), k))
        name = max(kinds[kind], key=lambda k: (kinds[kind][k], k))
        beam = self.kinds[self.names.index(name)][1]
        total = sum(kinds[kind].values())
        return name if beam is None or kinds[kind][name] >= _OWNS * total else kind

    def share(self, participation: dict, motion: str) -> float:
        """The share [-] of ``motion`` (a family's name or a kind of motion, :meth:`dominant`) in a
        mode of this ``participation``: the participation of the family, or the sum over the families
        of that kind (0 for a motion no family has)."""
        return float(sum(participation.get(name, 0.0) for name, (kind, _) in zip(self.names, self.kinds)
                         if motion in (name, kind)))


def motion_families(linear) -> MotionFamilies | None:
    """The motion families of a linear model made by
    :class:`~flexkane.analysis.linearization.Linearization` (None without it).

    Parameters
    ----------
    linear : LinearModel

    Returns
    -------
    MotionFamilies or None
    """
    lin = linear.linearization
    if lin is None or linear.n == 0:
        return None
    model = lin.model
    by_speed = {c.u.name: c for c in lin.eom.chain.coordinates if c.u is not None}
    n = linear.n
    spatial = model.dimensions == 3
    axes = _spin_axes(linear) if linear.about == "spin" else {}
    names: list[str] = []
    kinds: list[tuple] = []
    rows: list[dict] = [dict() for _ in range(n)]
    transform = np.eye(n)
    several = len(model.beams) > 1

    def family(kind: str, beam: str | None = None) -> str:
        name = f"{kind} {beam}" if beam is not None and several else kind
        if name not in names:
            names.append(name)
            kinds.append((kind, beam if several else None))
        return name

    bending: dict = {}
    for k, speed in enumerate(linear.speeds):
        c = by_speed.get(speed)
        if c is None:
            rows[k][family("joint")] = 1.0
            continue
        if c.role in ("mode_y", "mode_z"):
            bending.setdefault(c.owner, {}).setdefault(c.index, {})[c.role[-1]] = k
        elif c.role == "mode":
            rows[k][family("lag" if linear.about == "spin" else "bending", c.owner)] = 1.0
        elif c.role in ("torsion", "axial"):
            rows[k][family(c.role, c.owner)] = 1.0
        else:
            rows[k][family(_joint_motion(model.joints[c.owner], c.role, spatial))] = 1.0
    for beam, pairs in bending.items():
        flap = _flap_direction(lin, model.beams[beam], axes.get(beam)) if spatial else None
        for index in sorted(pairs):
            pair = pairs[index]
            if flap is None:
                for key, k in sorted(pair.items()):
                    rows[k][family(f"bending {key}", beam)] = 1.0
                continue
            cosines = {"y": flap[0], "z": flap[1]}    # y_p . a_s and z_p . a_s
            if len(pair) == 2:       # turn (q_y, q_z) into (flap, lag)
                ky, kz = pair["y"], pair["z"]
                transform[np.ix_([ky, kz], [ky, kz])] = [[flap[0], flap[1]], [-flap[1], flap[0]]]
                rows[ky][family("flap", beam)] = 1.0
                rows[kz][family("lag", beam)] = 1.0
            else:
                (key, k), = pair.items()
                share = cosines[key] ** 2
                rows[k][family("flap", beam)] = share
                rows[k][family("lag", beam)] = 1.0 - share
    weights = np.zeros((n, len(names)))
    for k, row in enumerate(rows):
        for name, share in row.items():
            weights[k, names.index(name)] = share
    return MotionFamilies(names, transform, weights, kinds)


def _joint_motion(joint, role: str, spatial: bool) -> str:
    """The family of motion of a joint's coordinate of this role (module docstring)."""
    if joint.type not in _FLOATING:
        return f"joint {joint.name}"
    if role == "angle" and not spatial:       # a planar free joint's turn, about the plane's normal
        return f"rotation of {joint.child}"
    return _FLOATING_MOTIONS[role].format(child=joint.child)


def _flap_direction(lin, beam, axis) -> tuple | None:
    """``(y_p . a_s, z_p . a_s)``: the cosines of the angles of the section's principal axes with the
    unit part ``a_s`` of the spin axis normal to the beam; None without a spin axis or when the
    beam lies along it."""
    if axis is None:
        return None
    section = np.array([axis[1], axis[2]], dtype=float)
    size = float(np.linalg.norm(section))
    if size <= _ALONG_BEAM * max(float(np.linalg.norm(axis)), 1e-300):
        return None
    a_y, a_z = section / size
    beta = 0.0
    if beam.principal_angle is not None:
        from ..model.field_values import FieldValues

        beta = float(FieldValues(lin.model).value(beam.principal_angle, f"beams.{beam.name}.principal_angle"))
    c, s = np.cos(beta), np.sin(beta)
    return (c * a_y + s * a_z, -s * a_y + c * a_z)


def _spin_axes(linear) -> dict:
    """Each spatial beam's angular velocity per unit spin rate at the operating point, in the beam
    frame's axes, shape (3,) per beam name (empty for planar models)."""
    lin = linear.linearization
    if lin.model.dimensions != 3 or not lin.model.beams:
        return {}
    from .jacobian import numeric_function

    beams = sorted(lin.model.beams)
    evaluate = _ANGULAR_VELOCITIES.get(lin)
    if evaluate is None:        # formed once per linearization (a Campbell diagram asks at every spin)
        from ..expressions import time_derivative

        chain = lin.eom.chain
        drivers = {}            # drivers' laws, as Kane's equations substitute them
        for c in chain.coordinates:
            if c.driver == "coordinate":
                drivers[c.q] = c.law
                drivers[c.u] = time_derivative(c.law, chain.t, path=f"joints.{c.owner}.driver.coordinate")
            elif c.driver == "speed":
                drivers[c.u] = c.law
        exprs = [[chain.intermediates.expand(c).xreplace(drivers) for c in lin.eom.kinematics.beams[b].frame.omega]
                 for b in beams]
        evaluate = _ANGULAR_VELOCITIES[lin] = numeric_function(lin._args_symbols, exprs)
    w = np.concatenate([lin.full_operating_point(linear), np.asarray(linear.z0, dtype=float)])
    with np.errstate(all="ignore"):
        per_spin = [np.array(evaluate(*lin._args(w, lin.parameter_values(s), lin.steady_speeds(s))), dtype=float)
                    .reshape(len(beams), 3) for s in (1.0, 0.0)]
    axes = per_spin[0] - per_spin[1]
    return {b: axes[k] for k, b in enumerate(beams)}
