"""The motion of a frame in space: orientation, angular velocity, position and velocity of its origin.

The spatial counterpart of :class:`flexkane.kane.kinematics.FrameMotion`. Vectors are expressed in
the frame they belong to, as the planar engine does, which keeps them short:

* ``rotation``: orientation in the ground frame N (:class:`~flexkane.kane.rotation.Rotation`,
  direction cosines ``R`` with ``v_N = R v_F`` and Euler parameters);
* ``omega``: angular velocity in N, components along the frame's axes [rad/s];
* ``r``: position of the origin, components in N [m];
* ``v``: velocity of the origin in N, components along the frame's axes [m/s].

A point P fixed in (or moving in) the frame at ``p`` (frame axes):
``r_P = r + R p``, ``v_P = v + w x p + p'`` (Kane and Levinson's two-point formulas). A frame C
turned relative to F by ``C_FC`` (constant or a function of q) with relative angular velocity
``w_rel`` (C's axes): ``w_C = C^T w_F + w_rel``, ``v_C = C^T v_F``. Accelerations are
``a = d(v)/dt + w x v`` with ``d/dt`` of the components (:func:`acceleration_remainder`).

A frame of a planar chain turns about z only: its rotation is ``about_z(theta)``
(:func:`~flexkane.kane.rotation.about_z`), its angular velocity ``(0, 0, omega)``, its position and
velocity have a zero z component, and :meth:`SpatialFrame.named` names ``theta``, ``omega``,
``rx``, ``ry``, ``vx``, ``vy`` as the planar engine does.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .intermediates import FRAME_NAME_ABOVE
from .rotation import IDENTITY, Rotation, about_z

__all__ = ["GROUND", "SpatialFrame", "acceleration_remainder", "add", "cross", "dot", "ground_frame"]

ZERO3 = (sp.Integer(0),) * 3


_ZERO = sp.S.Zero


def _product(x, y):
    """``x * y``, exactly 0 without SymPy's work when either is the zero of a planar chain's vectors."""
    return _ZERO if x is _ZERO or y is _ZERO else x * y


def _sum(*terms):
    nonzero = [t for t in terms if t is not _ZERO]
    if len(nonzero) <= 1:
        return nonzero[0] if nonzero else _ZERO
    return sp.Add(*nonzero)


def cross(a, b) -> tuple:
    """``a x b`` of two 3-vectors (same axes)."""
    return (_sum(_product(a[1], b[2]), -_product(a[2], b[1])), _sum(_product(a[2], b[0]), -_product(a[0], b[2])),
            _sum(_product(a[0], b[1]), -_product(a[1], b[0])))


def dot(a, b) -> sp.Expr:
    """``a . b`` of two 3-vectors (same axes)."""
    return _sum(_product(a[0], b[0]), _product(a[1], b[1]), _product(a[2], b[2]))


def add(a, b) -> tuple:
    return tuple(_sum(x, y) for x, y in zip(a, b))


@dataclass
class SpatialFrame:
    """Motion of a frame fixed in a link (see the module docstring for the attributes' axes)."""

    rotation: Rotation
    omega: tuple
    r: tuple
    v: tuple

    @property
    def R(self) -> sp.Matrix:
        """Direction cosines (3, 3): ``v_N = R v_frame``."""
        return self.rotation.matrix

    def point(self, p, chain) -> "SpatialFrame":
        """The frame translated to the point with local position ``p`` (may depend on q) [m]."""
        p = tuple(sp.sympify(c) for c in p)
        if all(c == 0 for c in p):
            return self
        v = add(add(self.v, cross(self.omega, p)), tuple(chain.dt(c) for c in p))
        return SpatialFrame(self.rotation, self.omega, add(self.r, self.rotation.apply(p)), v)

    def turned(self, rotation: Rotation, w_rel=ZERO3) -> "SpatialFrame":
        """The frame turned by ``rotation`` (the new frame in this one) about its origin, with
        relative angular velocity ``w_rel`` (new frame's axes) [rad/s]."""
        if rotation.is_identity():
            return SpatialFrame(self.rotation, add(self.omega, w_rel), self.r, self.v)
        return SpatialFrame(self.rotation * rotation, add(rotation.inverse_apply(self.omega), w_rel),
                            self.r, rotation.inverse_apply(self.v))

    def named(self, chain, label: str) -> "SpatialFrame":
        """The same frame with its large components replaced by intermediates (``R<i><j>_<label>``,
        ``e<k>_<label>``, ``wx_<label>``, ``rx_<label>``, ``vx_<label>`` ...)."""
        def name(expr, what):
            return chain.name(expr, f"{what}_{label}", FRAME_NAME_ABOVE)

        if chain.dimensions == 2:    # a planar chain's frame: its angle about z, named as the planar engine does
            return SpatialFrame(about_z(name(self.rotation.angle, "theta")),
                                (*self.omega[:2], name(self.omega[2], "omega")),
                                tuple(name(c, f"r{a}") for c, a in zip(self.r, "xyz")),
                                tuple(name(c, f"v{a}") for c, a in zip(self.v, "xyz")))
        R = self.rotation.matrix
        rotation = Rotation(sp.Matrix(3, 3, lambda i, j: name(R[i, j], f"R{i + 1}{j + 1}")),
                            tuple(name(c, f"e{k}") for k, c in enumerate(self.rotation.quaternion)))
        return SpatialFrame(rotation, tuple(name(c, f"w{a}") for c, a in zip(self.omega, "xyz")),
                            tuple(name(c, f"r{a}") for c, a in zip(self.r, "xyz")),
                            tuple(name(c, f"v{a}") for c, a in zip(self.v, "xyz")))


def ground_frame(r=ZERO3) -> SpatialFrame:
    """The ground frame N (or a frame fixed in N at ``r``)."""
    return SpatialFrame(IDENTITY, ZERO3, tuple(sp.sympify(c) for c in r), ZERO3)


GROUND = ground_frame()


def acceleration_remainder(frame: SpatialFrame, chain) -> tuple:
    """The part of the acceleration of the frame's origin that does not multiply u' (frame axes):
    ``d(v)/dt + w x v`` without u' terms [m/s^2]."""
    return add(tuple(chain.dt(c) for c in frame.v), cross(frame.omega, frame.v))
