"""The chapter's notebook variant of a spatial beam's forces: the weight at the deformed midpoint and
the elastic forces through the moment and shear at the root (``gravity = "midpoint"``,
``elastic_forces = "shear-moment"``), as :mod:`flexkane.kane.active` gives them for planar beams.

* ``midpoint``: the beam's whole weight ``m_B g`` acts at the deformed midpoint ``r(L/2)`` (the
  point at ``x = L/2`` of :mod:`flexkane.kane.spatial_beam`, its bending in both planes, its
  foreshortening and stretch included): ``F_r = v_C,r . m_B g`` (eqs. 8.19, 8.33, 8.34 in three
  dimensions), and the potential ``-m_B g . r_C``.
* ``shear-moment``: in each bending plane, eq. 8.28 as written. In the plane of the deflection
  ``v(x) = sum_i Phi^y_i q_yi`` along the section's principal axis y_p (bending about z_p, rigidity
  ``EI_z``) the bending moment ``M_0 = EI_z v''(0)`` and the shear ``V_0 = EI_z v'''(0)`` at the root
  act on the beam frame B, and the distributed load ``-EI_z v''''`` along y_p on the beam:

      F_r = (w_B,r . z_p) M_0 - (v_Q,r . y_p) V_0 - int (v_P,r . y_p) EI_z v'''' dx

  (``w_B,r``, ``v_Q,r``: partial angular velocity of B and partial velocity of its origin, the root
  Q). The plane of the deflection ``w(x)`` along z_p (bending about y_p, ``EI_y``) is its image by
  the quarter turn about the beam axis that takes y_p to z_p, and z_p to ``-y_p``: the same terms
  with ``z_p`` for ``y_p`` and ``-y_p`` for ``z_p``. The products ``v_P,r . y_p`` are fields of the
  atoms ``1``, ``x`` and the shape functions of both planes (a turn of B about its axis moves the
  deflection of one plane along the other), so the constants are ``Phi^y_i''(0)``, ``Phi^y_i'''(0)``,
  ``J_yi = int Phi^y_i'''' dx``, ``Jx_yi = int x Phi^y_i'''' dx`` and
  ``JPhi_<a>_yi = int a(x) Phi^y_i'''' dx`` for a shape function ``a`` of either plane. Torsion and
  stretch keep their strain-energy forces; like a planar beam, a shear-moment beam has neither
  geometric stiffening nor axial modes (validation refuses them). For shape functions that satisfy
  the clamped-free boundary conditions the two forms agree (integration by parts); the notebook's
  root ``lambda_1 = 1.875`` does not, which the chapter's example shows.
"""

from __future__ import annotations

import sympy as sp

from .modal_field import ONE, X, vec3_map

__all__ = ["PLANES", "midpoint", "midpoint_gravity_forces", "shear_moment_forces", "midpoint_potential"]

#: Bending plane -> (role of its coordinates, its rigidity's field).
PLANES = {"y": ("mode_y", "EI_z"), "z": ("mode_z", "EI_y")}


def midpoint(kin, name: str) -> tuple:
    """The station ``L/2`` of a beam as an expression and as the text of its symbols' names."""
    beam = kin.beams[name].beam
    L = kin.value(f"beams.{name}.L", beam.L, f"L_{name}")
    return L / 2, f"{beam.L}/2" if isinstance(beam.L, str) else repr(beam.L / 2)


def _principal_axes(kin, beam) -> tuple:
    """The section's principal axes y_p, z_p in B's axes (turned by ``principal_angle`` about x)."""
    from ..model.parts import nonzero_field

    if not nonzero_field(beam.principal_angle):
        return (0, 1, 0), (0, 0, 1)
    beta = kin.value(f"beams.{beam.name}.principal_angle", beam.principal_angle, f"beta_{beam.name}")
    c, s = sp.cos(beta), sp.sin(beta)
    return (0, c, s), (0, -s, c)


def _along(vector, axis) -> sp.Expr:
    return sp.Add(*[a * c for a, c in zip(axis, vector) if a != 0])


def midpoint_gravity_forces(kin, name: str, g_B: tuple) -> list:
    """``v_C,r . m_B g`` for every speed r: the weight at the deformed midpoint C.

    Parameters
    ----------
    kin : SpatialKinematics
    name : str
        A beam with ``gravity = "midpoint"``.
    g_B : tuple of 3 sympy.Expr
        Gravity in the beam frame's axes [m/s^2].

    Returns
    -------
    list of sympy.Expr
        One per speed [N or N m].
    """
    chain = kin.chain
    bm = kin.beams[name]
    k = bm.constants
    x, text = midpoint(kin, name)
    mB = k.pair(ONE, ONE)
    out = []
    for u in chain.u:
        V = vec3_map(bm.v, lambda c: chain.partial(c, u))
        out.append(mB * sp.Add(*[f.evaluate(lambda a: k.station(a, x, text)) * gc for f, gc in zip(V, g_B)]))
    return out


def midpoint_potential(kin, name: str, gravity: tuple) -> sp.Expr:
    """``-m_B g . r_C`` [J]: the potential of the weight at the deformed midpoint (gravity in N)."""
    bm = kin.beams[name]
    k = bm.constants
    x, text = midpoint(kin, name)
    local = tuple(f.evaluate(lambda a: k.station(a, x, text)) for f in bm.r)
    r_C = tuple(a + b for a, b in zip(bm.frame.r, bm.frame.rotation.apply(local)))
    return -k.pair(ONE, ONE) * sp.Add(*[g * c for g, c in zip(gravity, r_C)])


def shear_moment_forces(kin, name: str) -> list:
    """The elastic forces of eq. 8.28 in each bending plane (module docstring), one per speed [N or N m]."""
    chain = kin.chain
    bm = kin.beams[name]
    beam = bm.beam
    k = bm.constants
    y_p, z_p = _principal_axes(kin, beam)
    planes = {"y": (y_p, z_p), "z": (z_p, tuple(-c for c in y_p))}
    out = [sp.Integer(0)] * len(chain.u)
    for label, (deflection, normal) in planes.items():
        role, rigidity = PLANES[label]
        modes = chain.of(name, role)
        if not modes:
            continue
        EI = kin.value(f"beams.{name}.{rigidity}", getattr(beam, rigidity), f"{rigidity}_{name}")
        M0 = EI * sp.Add(*[k.shear_moment("M0", c.index, label) * c.q for c in modes])
        V0 = EI * sp.Add(*[k.shear_moment("V0", c.index, label) * c.q for c in modes])
        for r, u in enumerate(chain.u):
            W = _along([chain.partial(c, u) for c in bm.frame.omega], normal)
            VQ = _along([chain.partial(c, u) for c in bm.frame.v], deflection)
            V = vec3_map(bm.v, lambda c: chain.partial(c, u))
            along = V[0].scale(deflection[0]) + V[1].scale(deflection[1]) + V[2].scale(deflection[2])
            distributed = sp.Add(*[coeff * EI * k.shear_moment(_kind(atom), c.index, label, atom) * c.q
                                   for atom, coeff in along.items() for c in modes])
            out[r] += W * M0 - VQ * V0 - distributed
    return out


def _kind(atom) -> str:
    """The constant of ``int a(x) Phi_i'''' dx`` for an atom a: ``J`` (1), ``Jx`` (x), ``JPhi``."""
    return "J" if atom == ONE else "Jx" if atom == X else "JPhi"
