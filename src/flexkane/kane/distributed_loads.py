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
root frame (``f_B = R(-theta) f_N``); the rotation does not depend on x.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..model.values import TIME
from .modal_field import Field

__all__ = ["POSITION", "separate", "distributed_load_forces", "load_profile"]

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
    from ..expressions import parse_expression

    path = f"distributed_loads.{load.name}"
    bm = kin.beams[load.beam]
    consts = bm.constants
    names = {**kin.symbols.parameters, "t": TIME, "x": POSITION}
    components = [parse_expression(getattr(load, key), names, path=f"{path}.{key}") for key in ("fx", "fy")]
    if load.frame == "ground":
        c, s = sp.cos(bm.frame.theta), sp.sin(bm.frame.theta)
        # beam-frame components of the unit vectors i0 and j0
        directions = [(c, -s), (s, c)]
    else:
        directions = [(sp.Integer(1), sp.Integer(0)), (sp.Integer(0), sp.Integer(1))]
    L = kin.value(f"beams.{load.beam}.L", bm.beam.L, f"L_{load.beam}")
    L_text = bm.beam.L.strip() if isinstance(bm.beam.L, str) else repr(bm.beam.L)
    xi, w = np.polynomial.legendre.leggauss(int(load.quadrature_nodes))
    nodes = [((float(a) + 1.0) / 2.0, float(b) / 2.0) for a, b in zip(xi, w)]

    # per component: separable profiles (h -> g(t)) and the remainder evaluated at the nodes
    parts = []
    for f in components:
        profiles, rest = separate(f)
        labels = {h: k + 1 for k, h in enumerate(profiles)}
        at_nodes = [] if rest == 0 else [(xi_k, w_k, rest.xreplace({POSITION: L * sp.Float(xi_k)}))
                                         for xi_k, w_k in nodes]
        parts.append((profiles, labels, at_nodes))

    def integral(V: Field, profiles, labels, at_nodes, component: str) -> sp.Expr:
        """int_0^L V(x) f(x, t) dx for a field V of partial velocity components."""
        terms = []
        for h, g in profiles.items():
            for atom, coeff in V.items():
                label = f"{load.name}_{component}{labels[h]}"
                terms.append(g * coeff * consts.load_integral(atom, h, label))
        for xi_k, w_k, f_k in at_nodes:
            x_k = L * sp.Float(xi_k)
            text = f"{xi_k:.15g}*{L_text}"
            value = V.evaluate(lambda a: consts.station(a, x_k, text))
            terms.append(sp.Float(w_k) * L * f_k * value)
        return sp.Add(*terms)

    out = []
    for u in speeds:
        Vx, Vy = _partial(kin, bm.v[0], u), _partial(kin, bm.v[1], u)
        total = sp.Integer(0)
        for (profiles, labels, at_nodes), (ex, ey), component in zip(parts, directions, ("x", "y")):
            if not profiles and not at_nodes:
                continue
            if ex != 0 and not Vx.is_zero():
                total += ex * integral(Vx, profiles, labels, at_nodes, component)
            if ey != 0 and not Vy.is_zero():
                total += ey * integral(Vy, profiles, labels, at_nodes, component)
        out.append(total)
    return out
