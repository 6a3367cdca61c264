"""Rotations in three dimensions: direction cosines and Euler parameters, kept small.

A :class:`Rotation` of a frame B relative to a frame A holds both descriptions of the same turn:

* the direction-cosine matrix ``C`` (3 x 3), whose columns are B's unit vectors in A's axes, so
  that ``v_A = C v_B`` (Kane and Levinson's ``A C B``);
* the Euler parameters ``e = (e0, e1, e2, e3)`` (a unit quaternion, ``e0 = cos(a/2)``,
  ``(e1, e2, e3) = sin(a/2) n`` for a turn by ``a`` about the unit vector ``n``).

Rotations compose by matrix product (``C_AC = C_AB C_BC``) and quaternion product alike, so the
orientation of every link of a chain is available both ways: direction cosines for the kinematics,
Euler parameters (free of branches and singularities) for the outputs. Entries that are exactly
0 or 1 (rotations about a coordinate axis, identity orientations) stay exact, so a rotation about
``z`` is the planar ``[[c, -s, 0], [s, c, 0], [0, 0, 1]]``.

A turn about the fixed z axis (the planar chains' every rotation) also keeps its angle
(:attr:`Rotation.angle`): such turns compose by adding their angles, so that the orientation of a
link of a planar chain is ``about_z(theta)`` with ``theta`` the sum of the joint angles (eq. 8.17)
and its direction cosines ``cos(theta)``, ``sin(theta)``, exactly the planar engine's.

Euler parameter kinematics (Kane, Likins and Levinson): with ``w`` the angular velocity of B in A,
components along B's axes, ``e' = 1/2 E(e) w`` (:func:`euler_parameter_rates`).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

__all__ = ["IDENTITY", "Rotation", "about_axis", "about_z", "body_sequence", "euler_parameter_matrix",
           "euler_parameter_rates", "unit_vector", "yaw_pitch_roll"]

_AXES = {"x": (1, 0, 0), "y": (0, 1, 0), "z": (0, 0, 1)}


def unit_vector(v) -> tuple:
    """``v / |v|`` for a 3-vector of expressions; exact for a coordinate axis [-]."""
    v = tuple(sp.sympify(c) for c in v)
    nonzero = [c for c in v if c != 0]
    if len(nonzero) == 1 and nonzero[0].is_number:
        return tuple(sp.sign(c) if c != 0 else sp.Integer(0) for c in v)
    norm = sp.sqrt(sum(c ** 2 for c in v))
    return tuple(c / norm for c in v)


def euler_parameter_matrix(e) -> sp.Matrix:
    """Direction cosines of a rotation with Euler parameters ``e = (e0, e1, e2, e3)`` (3 x 3)."""
    e0, e1, e2, e3 = e
    return sp.Matrix([
        [e0 ** 2 + e1 ** 2 - e2 ** 2 - e3 ** 2, 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
        [2 * (e1 * e2 + e0 * e3), e0 ** 2 - e1 ** 2 + e2 ** 2 - e3 ** 2, 2 * (e2 * e3 - e0 * e1)],
        [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), e0 ** 2 - e1 ** 2 - e2 ** 2 + e3 ** 2]])


def euler_parameter_rates(e, w) -> tuple:
    """``e' = 1/2 E(e) w``: rates of the Euler parameters of B in A, ``w`` the angular velocity of
    B in A along B's axes [rad/s]; returns 4 expressions [1/s]."""
    e0, e1, e2, e3 = e
    wx, wy, wz = w
    half = sp.Rational(1, 2)
    return (-half * (e1 * wx + e2 * wy + e3 * wz),
            half * (e0 * wx - e3 * wy + e2 * wz),
            half * (e3 * wx + e0 * wy - e1 * wz),
            half * (-e2 * wx + e1 * wy + e0 * wz))


def _quaternion_product(a, b) -> tuple:
    a0, a1, a2, a3 = a
    b0, b1, b2, b3 = b
    return (a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
            a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
            a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
            a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0)


@dataclass(frozen=True)
class Rotation:
    """The orientation of a frame B relative to a frame A.

    Attributes
    ----------
    matrix : sympy.Matrix, shape (3, 3)
        Direction cosines: ``v_A = matrix * v_B``.
    quaternion : tuple of 4 sympy.Expr
        Euler parameters ``(e0, e1, e2, e3)`` of the same rotation (formed when first read for a
        turn about z, whose ``euler`` is None).
    angle : sympy.Expr or None
        The angle [rad] of a turn about z (A's z axis, which is B's), None for any other rotation.
    """

    matrix: sp.Matrix
    euler: tuple | None
    angle: object = None

    @property
    def quaternion(self) -> tuple:
        if self.euler is None:     # a turn about z
            zero = sp.Integer(0)
            return (sp.cos(self.angle / 2), zero, zero, sp.sin(self.angle / 2))
        return self.euler

    def __mul__(self, other: "Rotation") -> "Rotation":
        """``self`` (B in A) followed by ``other`` (C in B): C in A."""
        if other.is_identity():
            return self
        if self.is_identity():
            return other
        if self.angle is not None and other.angle is not None:   # turns about z: angles add
            return about_z(self.angle + other.angle)
        return Rotation(self.matrix * other.matrix, _quaternion_product(self.quaternion, other.quaternion))

    def transpose(self) -> "Rotation":
        """The inverse rotation (A in B)."""
        e0, e1, e2, e3 = self.quaternion
        return Rotation(self.matrix.T, (e0, -e1, -e2, -e3), None if self.angle is None else -self.angle)

    def is_identity(self) -> bool:
        if self.angle is not None:
            return self.angle == 0
        return self.matrix == sp.eye(3)

    def apply(self, v) -> tuple:
        """Components in A of a vector with components ``v`` in B."""
        M = self.matrix
        return tuple(_row_product((M[i, 0], M[i, 1], M[i, 2]), v) for i in range(3))

    def inverse_apply(self, v) -> tuple:
        """Components in B of a vector with components ``v`` in A."""
        M = self.matrix
        return tuple(_row_product((M[0, i], M[1, i], M[2, i]), v) for i in range(3))

    def map(self, function) -> "Rotation":
        """The same rotation with ``function`` applied to every entry (naming, substitution); a turn
        about z stays one, of angle ``function(angle)``."""
        if self.angle is not None:
            return about_z(function(self.angle))
        return Rotation(self.matrix.applyfunc(function), tuple(function(c) for c in self.quaternion))


IDENTITY = Rotation(sp.eye(3), (sp.Integer(1), sp.Integer(0), sp.Integer(0), sp.Integer(0)), sp.Integer(0))


def about_z(angle) -> Rotation:
    """A turn by ``angle`` [rad] about z: ``[[c, -s, 0], [s, c, 0], [0, 0, 1]]``, the planar rotation."""
    angle = sp.sympify(angle)
    if angle == 0:
        return IDENTITY
    c, s = sp.cos(angle), sp.sin(angle)
    zero, one = sp.Integer(0), sp.Integer(1)
    return Rotation(sp.Matrix([[c, -s, zero], [s, c, zero], [zero, zero, one]]), None, angle)


def _row_product(row, v) -> sp.Expr:
    """``row . v`` with the exact zeros (of rotations about coordinate axes, of planar vectors) left out."""
    terms = [a * b for a, b in zip(row, v) if a != 0 and b != 0]
    return sp.Add(*terms) if terms else sp.Integer(0)


def about_axis(axis, angle) -> Rotation:
    """A turn by ``angle`` [rad] about ``axis`` (a unit 3-vector, components in A and B alike).

    Rodrigues' formula ``C = cos(a) 1 + (1 - cos(a)) n n^T + sin(a) [n x]``.
    """
    angle = sp.sympify(angle)
    if angle == 0:
        return IDENTITY
    n = [sp.sympify(c) for c in axis]
    c, s = sp.cos(angle), sp.sin(angle)
    cross = sp.Matrix([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    matrix = sp.Matrix(3, 3, lambda i, j: (c if i == j else 0) + (1 - c) * n[i] * n[j] + s * cross[i, j])
    matrix = matrix.applyfunc(sp.expand)
    ch, sh = sp.cos(angle / 2), sp.sin(angle / 2)
    return Rotation(matrix, (ch, sh * n[0], sh * n[1], sh * n[2]))


def body_sequence(sequence: str, angles) -> Rotation:
    """Successive body-fixed turns, e.g. ``"zyx"`` with (yaw, pitch, roll) [rad]: about z, then
    about the new y, then about the newest x."""
    out = IDENTITY
    for letter, angle in zip(sequence, angles):
        out = out * (about_z(angle) if letter == "z" else about_axis(_AXES[letter], angle))
    return out


def yaw_pitch_roll(matrix: sp.Matrix) -> tuple:
    """The 3-2-1 (z, y, x body-fixed) angles of a direction-cosine matrix [rad]:
    ``matrix = Rz(yaw) Ry(pitch) Rx(roll)``, pitch in [-pi/2, pi/2]."""
    yaw = sp.atan2(matrix[1, 0], matrix[0, 0])
    pitch = sp.atan2(-matrix[2, 0], sp.sqrt(matrix[2, 1] ** 2 + matrix[2, 2] ** 2))
    roll = sp.atan2(matrix[2, 1], matrix[2, 2])
    return yaw, pitch, roll
