"""Generalized active forces of distributed loads on beams, without integrating over x symbolically.

A force per unit length ``f(x, t)`` [N/m] on a beam contributes, like eq. 8.28 does for the internal
forces, the generalized active forces

    F_r = int_0^L v_P,r(x) . f(x, t) dx,

with ``v_P,r`` the partial velocities of the beam point at x (eq. 8.18). The partial velocities are
sums ``sum_a c_a,r(q, t) a(x)`` over the atoms of :mod:`flexkane.kane.modal_field` (1, x, Phi_i, Psi_k,
d_ij), so

    F_r = sum_a c_a,r(q, t) int_0^L a(x) f(x, t) dx.

The load is expanded into terms. A term that separates into ``g(t) h(x)`` (``g`` and ``h`` may both
contain parameters) gives ``g(t) K_a`` with the *load constant* ``K_a = int_0^L a(x) h(x) dx``,
computed numerically for each parameter set by the Gauss-Legendre rule of the modal constants
(:class:`~flexkane.kane.beam_quadrature.AtomEvaluator`, twice its verified order): exact, to the
accuracy of the modal constants, for every load that is a sum of such products (uniform, linearly
varying, ``q0 sin(w t) exp(-x/a)``, ...). The terms that do not separate (``sin(k x - w t)``) are
integrated by an ``N``-node Gauss-Legendre rule on ``[0, L]`` with the load's time dependence kept
symbolic at the nodes,

    int_0^L a(x) f(x, t) dx ~ sum_k w_k L a(x_k) f(x_k, t),    x_k = xi_k L,

whose atom values ``a(x_k)`` are station constants (``Phi_1(0.5*L)``); ``N`` is the load's
``quadrature_nodes`` (the rule integrates ``a f`` exactly when it is a polynomial of degree below
``2N`` in x, and converges quickly for smooth loads).

Components given in the ``ground`` frame are turned into the beam frame with the angle of the beam's
root frame (``f_B = R(-theta) f_N``); the rotation does not depend on x. On a spatial beam
(:func:`spatial_distributed_load_forces`) the load has three components and the point at x the
three partial-velocity fields of :mod:`flexkane.kane.spatial_beam`; ground components are turned by
the transpose of the beam frame's direction cosines.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..model.values import TIME
from .modal_field import Field

__all__ = ["POSITION", "separate", "distributed_load_forces", "spatial_distributed_load_forces", "load_profile"]

#: Position along a beam, from its root [m], in the expressions of distributed loads.
POSITION = sp.Symbol("x", real=True)


def separate(expr: sp.Expr) -> tuple[dict, sp.Expr]:
    """Split a load ``f(x, t)`` into separable terms and a remainder.

    Parameters
    ----------
    expr : sympy.Expr
        Expression of :data:`POSITION`, t and parameter symbols.

    Returns
    -------
    profiles : dict of sympy.Expr to sympy.Expr
        ``h(x) -> g(t)`` with ``f = sum g h + rest``; ``h`` contains no t, ``g`` no x.
    rest : sympy.Expr
        The terms in which x and t do not separate (0 if none).
    """
    profiles: dict = {}
    rest = []
    for term in sp.Add.make_args(sp.expand(expr)):
        in_x, others = [], []
        for factor in sp.Mul.make_args(term):
            (in_x if factor.has(POSITION) else others).append(factor)
        h, g = sp.Mul(*in_x), sp.Mul(*others)
        if h.has(TIME):
            rest.append(term)
        else:
            profiles[h] = profiles.get(h, sp.Integer(0)) + g
    return profiles, sp.Add(*rest)


def load_profile(profile: sp.Expr, values: dict):
    """The x-profile ``h(x)`` of a load as a NumPy function of x [m], parameters substituted.

    Parameters
    ----------
    profile : sympy.Expr
        Expression of :data:`POSITION` and parameter symbols.
    values : dict of sympy.Symbol to float
        Values of the parameters.
    """
    numeric = profile.xreplace({s: sp.Float(values[s]) for s in profile.free_symbols if s in values})
    return sp.lambdify(POSITION, numeric, modules="numpy")


def _partial(kin, field: Field, u) -> Field:
    return field.map(lambda c: kin.chain.partial(c, u))


class _LoadIntegrals:
    """``int_0^L V(x) f_c(x, t) dx`` for the components ``f_c`` of one distributed load and fields V
    of partial-velocity components (module docstring): separable terms through load constants, the
    others at Gauss-Legendre nodes.

    Parameters
    ----------
    kin : Kinematics or SpatialKinematics
    load : DistributedLoad
    keys : tuple of str
        The load's component fields (``fx``, ``fy`` and, in 3D, ``fz``).
    """

    def __init__(self, kin, load, keys):
        from ..expressions import parse_expression

        path = f"distributed_loads.{load.name}"
        bm = kin.beams[load.beam]
        self.name = load.name
        self.consts = bm.constants
        names = {**kin.symbols.parameters, "t": TIME, "x": POSITION}
        components = [parse_expression(getattr(load, key), names, path=f"{path}.{key}") for key in keys]
        self.L = L = kin.value(f"beams.{load.beam}.L", bm.beam.L, f"L_{load.beam}")
        self.L_text = bm.beam.L.strip() if isinstance(bm.beam.L, str) else repr(bm.beam.L)
        xi, w = np.polynomial.legendre.leggauss(int(load.quadrature_nodes))
        nodes = [((float(a) + 1.0) / 2.0, float(b) / 2.0) for a, b in zip(xi, w)]
        # per component: separable profiles (h -> g(t)) and the remainder evaluated at the nodes
        self.parts = []
        for f in components:
            profiles, rest = separate(f)
            labels = {h: k + 1 for k, h in enumerate(profiles)}
            at_nodes = [] if rest == 0 else [(xi_k, w_k, rest.xreplace({POSITION: L * sp.Float(xi_k)}))
                                             for xi_k, w_k in nodes]
            self.parts.append((profiles, labels, at_nodes))

    def loaded(self, k: int) -> bool:
        """Whether component k has any term."""
        profiles, _, at_nodes = self.parts[k]
        return bool(profiles or at_nodes)

    def integral(self, V: Field, k: int, component: str) -> sp.Expr:
        """int_0^L V(x) f_k(x, t) dx for a field V of partial velocity components."""
        profiles, labels, at_nodes = self.parts[k]
        consts, L = self.consts, self.L
        terms = []
        for h, g in profiles.items():
            for atom, coeff in V.items():
                label = f"{self.name}_{component}{labels[h]}"
                terms.append(g * coeff * consts.load_integral(atom, h, label))
        for xi_k, w_k, f_k in at_nodes:
            x_k = L * sp.Float(xi_k)
            text = f"{xi_k:.15g}*{self.L_text}"
            value = V.evaluate(lambda a: consts.station(a, x_k, text))
            terms.append(sp.Float(w_k) * L * f_k * value)
        return sp.Add(*terms)


def distributed_load_forces(kin, load, speeds) -> list:
    """``F_r`` of one distributed load, one expression per speed.

    Parameters
    ----------
    kin : Kinematics
    load : DistributedLoad
    speeds : list of sympy.Symbol

    Returns
    -------
    list of sympy.Expr
        Shape (len(speeds),).
    """
    bm = kin.beams[load.beam]
    loads = _LoadIntegrals(kin, load, ("fx", "fy"))
    if load.frame == "ground":
        c, s = sp.cos(bm.frame.theta), sp.sin(bm.frame.theta)
        # beam-frame components of the unit vectors i0 and j0
        directions = [(c, -s), (s, c)]
    else:
        directions = [(sp.Integer(1), sp.Integer(0)), (sp.Integer(0), sp.Integer(1))]
    return _load_forces(kin, loads, directions, bm.v, speeds)


def spatial_distributed_load_forces(kin, load, speeds) -> list:
    """``F_r`` of one distributed load on a spatial beam, one expression per speed.

    The load ``(fx, fy, fz)`` [N/m] has components along the beam frame's axes (``frame = "beam"``)
    or N's (``ground``: turned into the beam frame by ``R_B^T``, whose row k holds the beam-frame
    components of N's k-th axis); the point at x moves with the three fields of partial velocities
    of :mod:`flexkane.kane.spatial_beam`.

    Parameters
    ----------
    kin : SpatialKinematics
    load : DistributedLoad
    speeds : list of sympy.Symbol

    Returns
    -------
    list of sympy.Expr
        Shape (len(speeds),).
    """
    bm = kin.beams[load.beam]
    keys = ("fx", "fy", "fz") if kin.chain.dimensions == 3 else ("fx", "fy")    # a planar chain's: in the plane
    loads = _LoadIntegrals(kin, load, keys)
    if load.frame == "ground":
        R = bm.frame.rotation.matrix
        directions = [tuple(R[k, j] for j in range(3)) for k in range(len(keys))]
    else:
        directions = [tuple(sp.Integer(1 if j == k else 0) for j in range(3)) for k in range(len(keys))]
    return _load_forces(kin, loads, directions, bm.v, speeds)


def _load_forces(kin, loads, directions, velocity, speeds) -> list:
    """``F_r = sum_k int f_k (e_k . v_P,r) dx`` for each speed: ``directions[k]`` holds the beam-frame
    components of the load's k-th direction, ``velocity`` the beam-frame components of the velocity
    field of the point at x (2 or 3 fields)."""
    out = []
    for u in speeds:
        V = [_partial(kin, c, u) for c in velocity]
        total = sp.Integer(0)
        for k, component in enumerate("xyz"[:len(directions)]):
            if not loads.loaded(k):
                continue
            for e, Vj in zip(directions[k], V):
                if e != 0 and not Vj.is_zero():
                    total += e * loads.integral(Vj, k, component)
        out.append(total)
    return out
