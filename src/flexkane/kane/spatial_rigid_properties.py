"""Rigid-body properties of a spatial chain's links about a frame's origin: mass, first moment, inertia
tensor, and the resultant and moment of the inertia forces without u', moved between frames by the
parallel-axis theorem with a rotation. The composite bodies of :mod:`flexkane.kane.spatial_inertia` are
sums of these, of rigid bodies and of spatial beams (:func:`flexkane.kane.spatial_beam.beam_own_properties`).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .spatial_frame import add, cross, dot

__all__ = ["SpatialRigidProperties", "matvec"]


def matvec(A: sp.Matrix, v) -> tuple:
    """``A v`` for a (3, 3) matrix and a 3-vector given as a tuple."""
    return tuple(dot((A[i, 0], A[i, 1], A[i, 2]), v) for i in range(3))


@dataclass
class SpatialRigidProperties:
    """Rigid-body properties about a frame's origin, components along its axes.

    ``m`` mass [kg], ``S`` first moment (3,) [kg m], ``J`` inertia tensor about the origin (3, 3)
    [kg m^2], ``R`` resultant of ``m a_rem`` (3,) [N], ``K`` moment about the origin of the inertia
    forces without u' (3,) [N m].

    ``planar``: properties of links of a planar chain (frames turning about z, points in the x-y
    plane), whose angular velocities are along z: only ``J_zz`` of the tensor enters their
    equations, the others are dropped (kept 0), and a turn about z leaves ``J_zz`` unchanged, so that
    moving them costs what the planar engine's ``(m, S_x, S_y, J)`` does.
    """

    m: sp.Expr
    S: tuple
    J: sp.Matrix
    R: tuple
    K: tuple
    planar: bool = False

    def __post_init__(self):
        if self.planar:
            self.J = sp.diag(0, 0, self.J[2, 2])

    def __add__(self, other: "SpatialRigidProperties") -> "SpatialRigidProperties":
        return SpatialRigidProperties(self.m + other.m, add(self.S, other.S), self.J + other.J,
                                      add(self.R, other.R), add(self.K, other.K), self.planar and other.planar)

    def moved(self, s: tuple, rotation) -> "SpatialRigidProperties":
        """The same properties about a frame in which this one's origin is at ``s`` and this one's
        orientation is ``rotation`` (parallel-axis theorem with a rotation)."""
        L = rotation.matrix
        S = matvec(L, self.S)
        R = matvec(L, self.R)
        ss, sS = dot(s, s), dot(s, S)
        if self.planar:      # J_zz about the new origin (s, S in the plane), unchanged by the turn about z
            return SpatialRigidProperties(self.m, add(tuple(self.m * c for c in s), S),
                                          sp.diag(0, 0, self.J[2, 2] + self.m * ss + 2 * sS), R,
                                          add(matvec(L, self.K), cross(s, R)), True)
        J = L * self.J * L.T if not rotation.is_identity() else self.J
        J = J + sp.Matrix(3, 3, lambda i, j: (self.m * ss + 2 * sS if i == j else 0)
                          - self.m * s[i] * s[j] - s[i] * S[j] - S[i] * s[j])
        return SpatialRigidProperties(self.m, add(tuple(self.m * c for c in s), S), J, R,
                                      add(matvec(L, self.K), cross(s, R)))

    def named(self, chain, label: str) -> "SpatialRigidProperties":
        """The same properties with their large components replaced by intermediates
        (``Sx_<label>``, ``Jxy_<label>``, ``Rx_<label>``, ``Kx_<label>`` ...; planar ones
        ``J_<label>`` and ``K_<label>`` about z, as the planar engine names them)."""
        S = tuple(chain.name(c, f"S{a}_{label}") for c, a in zip(self.S, "xyz"))     # named in the fields' order
        J = sp.zeros(3, 3)
        for i in range(3):
            for j in range(i, 3):
                stem = "J" if self.planar else f"J{'xyz'[i]}{'xyz'[j]}"
                J[i, j] = J[j, i] = chain.name(self.J[i, j], f"{stem}_{label}")
        about = ("", "", "") if self.planar else "xyz"      # a planar K has its z component only
        return SpatialRigidProperties(self.m, S, J, tuple(chain.name(c, f"R{a}_{label}") for c, a in zip(self.R, "xyz")),
                                      tuple(chain.name(c, f"K{a}_{label}") for c, a in zip(self.K, about)),
                                      self.planar)
