"""Drivers whose law reads the state: ``q_d = L(t, q, z)`` as a holonomic constraint, ``u_d = L(t, q, z)``
as a velocity servo.

A coordinate driver prescribes its joint's coordinate. With a law of t and the parameters, the
coordinate, its speed and its acceleration are the law and its time derivatives
(:class:`~flexkane.kane.equations.EquationsOfMotion` substitutes them). A law may also read the
other coordinates (a gear or a cam: ``q_b = 0.5*q_a``), position-level sensors (functions of q) and
controller states z (a driver following a filtered reference); it is then a rheonomic holonomic
constraint ``q_d - L(t, q, z) = 0`` between the driven coordinate and those it reads, and:

* ``u_d = dL/dt = sum_i C_i u_i + L_z z' + L_t``, with ``C_i = dL/dq . dq'/du_i``, is linear in the
  free speeds as long as L reads no speed and the rates z' of the controller states it reads read no
  speed either (validation refuses such laws: a law of the speeds would make ``u_d`` depend on u' and
  ``u_d'`` on u'', a prescription of higher order, not a motion of the chain);
* ``u_d' = sum_i C_i u_i' + e_d``, with ``e_d`` free of u' (the chain rule through the named
  intermediates, :meth:`flexkane.kane.intermediates.Intermediates.rate`, with the controller states'
  rates added: ``d/dt = (d/dt at fixed z) + sum_z (d/dz) z'``).

The constraint is enforced by ideal forces, as a gear or a cam enforces it: the driver's effort
``lambda`` acts on the driven joint, and ``-C_i lambda`` on each speed the law reads, so Kane's
equations are formed with the partial velocities of the dependent-speed reduction
(:func:`flexkane.kane.speed_reduction.dependent_speed_reduction`, the one closed loops use):
``P^T M P u_f' = P^T (f - M e)`` with ``P = [I; C]``, and the mass matrix stays symmetric positive
definite. The power of the constraint forces is ``lambda (u_d - sum_i C_i u_i) = lambda (L_z z' + L_t)``:
a gear does no work, a law that moves with time or with a controller state does.

A speed driver's law ``u_d = L(t, q, z)`` (``driver = { speed = ... }``) may read the same signals,
its own coordinate and the other driven ones included, and controller states whatever their rates:
``q_d`` stays in the state with ``q_d' = L``, and ``u_d' = dL/dt`` is free of u' (L reads no speed), so
the driver's effort acts on its joint alone, as a law of time's does, and the mass matrix is the free
speeds' (a velocity servo: ``u_d - L = 0`` is a constraint on the speeds whose only partial velocity is
the driven one's). A law of speeds would put u' in ``u_d'`` and is refused.

A law that reads its own coordinate (directly, or through a sensor on a link its joint moves) is an
equation for q_d, not a prescription, and is refused, as are laws that read a coordinate prescribed by
another driver (whose effort would have to include this constraint's reaction), and such drivers in
models with closed loops.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import sympy as sp

from ..errors import ModelError
from ..expression_syntax import NeedsSymbolic, expression_names
from .speed_reduction import dependent_speed_reduction

__all__ = ["reads_state", "parse_state_laws", "state_driver_substitutions", "speed_coupling", "DriverReduction",
           "reduce_by_drivers"]


def reads_state(text, parameters) -> bool:
    """Whether a driver's law names anything but t and the parameters (a law of the state)."""
    if not isinstance(text, str):
        return False
    try:
        return bool(expression_names(text) - {*parameters, "t"})
    except NeedsSymbolic:
        return False


def _path(coord) -> str:
    return f"joints.{coord.owner}.driver.{coord.driver}"


def parse_state_laws(chain) -> None:
    """Parse the laws of the state once the signals are known (:func:`.controllers.control_signals`).

    Sets ``law`` on every coordinate whose driver reads the state (``state_law``).
    """
    for coord in chain.coordinates:
        if coord.state_law:
            joint = chain.model.joints[coord.owner]
            coord.law = chain.symbols.effort(_path(coord), getattr(joint.driver, coord.driver))


def _refuse(chain, coord, expected: str, detail: str):
    law = getattr(chain.model.joints[coord.owner].driver, coord.driver)
    raise ModelError(_path(coord), expected, law, detail)


def state_driver_substitutions(chain, subs: dict) -> dict:
    """``q_d -> L``, ``u_d -> L'``, ``u_d' -> L''`` of every driver whose law reads the state.

    Parameters
    ----------
    chain : Chain
        With its controller states and rates.
    subs : dict
        The substitutions of the drivers' laws of time (extended and returned, every value free of
        the substituted symbols).
    """
    state = [c for c in chain.coordinates if c.state_law]
    if not state:
        return subs
    if chain.model.constraints:
        _refuse(chain, state[0], "a law of t and the parameters in a model with closed loops (a driver that reads the "
                "state is a constraint of its own, not combined with loop constraints)",
                f"the model has constraints {', '.join(chain.model.constraints)}")
    deps = chain.intermediates.dependencies
    speeds = set(chain.u)
    driven_q = {c.q: c for c in chain.coordinates if c.driver is not None}
    rates = chain.controller_rates
    for coord in state:
        law = coord.law
        used = deps(law)
        if coord.driver == "speed":
            read = sorted(u.name for u in used & speeds)
            if read:
                _refuse(chain, coord, "a law of t, the parameters, coordinates, position sensors and controller "
                        "states: the driven acceleration is the law's time derivative, which for a law of speeds "
                        "would need u'", f"reads {', '.join(read)}")
            continue
        if coord.q in used:
            _refuse(chain, coord, "a law that does not read the coordinate it drives (q = L(q) is an equation, not a "
                    "prescription)", f"reads {coord.q.name} (directly or through a sensor on a link the joint moves)")
        others = sorted(q.name for q in used & set(driven_q))
        if others:      # its driver would have to supply the reaction of this one as well
            _refuse(chain, coord, "a law that does not read a coordinate prescribed by another driver",
                    f"reads {', '.join(others)} (directly or through a sensor on a link that joint moves); write "
                    "that driver's law into this one")
        read = sorted(u.name for u in used & speeds)
        if read:
            _refuse(chain, coord, "a law of t, the parameters, coordinates, position sensors and controller states: "
                    "the driven speed is the law's time derivative, which for a law of speeds would need u'",
                    f"reads {', '.join(read)}")
        for z in sorted(used & set(rates), key=lambda s: s.name):
            fast = sorted(u.name for u in deps(rates[z]) & speeds)
            if fast:
                _refuse(chain, coord, "a law of controller states whose rates read no speed (the driven speed would "
                        "not be linear in the speeds: not a holonomic prescription)",
                        f"the rate of {z.name} reads {', '.join(fast)}")
    for coord in state:
        if coord.driver == "speed":     # q_d stays in the state, q_d' = u_d = L
            subs[coord.u] = coord.law
            subs[chain.ud[coord.u]] = _rate(chain, coord.law, with_ud=True)
            continue
        first = _rate(chain, coord.law)
        subs[coord.q] = coord.law
        subs[coord.u] = first
        subs[chain.ud[coord.u]] = _rate(chain, first, with_ud=True)
    # the coordinates' laws read no driven symbol; the speeds' laws and the derivatives may (the
    # coordinates of other drivers, the controllers' rates): substituted until none is left
    keys = set(subs)
    for _ in range(len(subs) + 1):
        stale = [k for k, v in subs.items() if v.free_symbols & keys]
        if not stale:
            break
        for k in stale:
            subs[k] = subs[k].xreplace(subs)
    for coord in state:
        if chain.intermediates.expand(subs[chain.ud[coord.u]]).has(sp.Heaviside, sp.DiracDelta, sp.sign,
                                                                   sp.Derivative):
            _refuse(chain, coord, "a law that can be differentiated with respect to time (twice for a coordinate)",
                    "its derivative has steps or impulses (min, max, abs or a saturated controller output in the law)")
    return subs


def _rate(chain, expr, with_ud: bool = False):
    """Total time derivative of ``expr`` (q, u, z, t and intermediates), u' terms when ``with_ud``."""
    out = chain.dt(expr, with_ud=with_ud)
    for z, rate in chain.controller_rates.items():
        dz = chain.partial(expr, z)
        if dz != 0:
            out = out + dz * rate
    return out


def speed_coupling(chain, subs: dict, free: list) -> dict:
    """Each driven acceleration of a law of the state in the free ones: ``u_d' = sum_i C_i u_i' + e_d``.

    ``C_i = du_d/du_i`` are also the driven speed's coefficients in the free speeds (the law reads no
    speed), the rows of ``P`` in ``u = P u_f + p``.

    Parameters
    ----------
    chain : Chain
    subs : dict
        Every driver's substitutions (:func:`state_driver_substitutions`).
    free : list of sympy.Symbol
        The free speeds.

    Returns
    -------
    dict of Symbol to (list of sympy.Expr, sympy.Expr)
        Driven speed of a law of the state -> (C, one per free speed; e_d). Time laws are absent.
    """
    out = {}
    rates = [chain.ud[u] for u in free]
    for c in chain.coordinates:
        if c.state_law and c.driver == "coordinate":
            accel = subs[chain.ud[c.u]]
            out[c.u] = ([sp.diff(accel, a) for a in rates], accel.xreplace({a: 0 for a in rates}))
    return out


@dataclass(frozen=True)
class DriverReduction:
    """Kane's equations over the free speeds of a chain with drivers of the state.

    Attributes
    ----------
    mass_matrix : sympy.Matrix, shape (nf, nf)
        ``P^T M P`` over the nf free speeds (symmetric positive definite).
    forcing : sympy.Matrix, shape (nf, 1)
        ``P^T (f - M e)``.
    """

    mass_matrix: sp.Matrix
    forcing: sp.Matrix


def reduce_by_drivers(chain, mass_matrix, forcing: list, remainder: list, free: list, driven: list,
                      ud_driven: list, coupling: dict, sub: Callable) -> DriverReduction:
    """Kane's equations with the speeds of drivers of the state dependent: ``P^T M P u_f' = P^T (f - M e)``
    over the free speeds and those driven speeds, ``P = [I; C]``, ``e = [0; e_d]``
    (:func:`speed_coupling`; :func:`flexkane.kane.speed_reduction.dependent_speed_reduction`).

    The inputs are not modified.

    Parameters
    ----------
    chain : Chain
    mass_matrix : sympy.Matrix, shape (n, n)
        M of every speed of the chain (rows and columns numbered as ``chain.speed_coordinates``),
        drivers not substituted.
    forcing : list of sympy.Expr, length n
        The generalized active forces ``F_r`` summed over their sources.
    remainder : list of sympy.Expr, length n
        The part of ``-F*_r`` free of u' (:class:`~flexkane.kane.inertia.InertiaForces`).
    free : list of int
        Indices of the free speeds.
    driven : list of int
        Indices of the driven speeds.
    ud_driven : list of sympy.Expr
        The driven accelerations (their laws' derivatives), one per ``driven``.
    coupling : dict
        :func:`speed_coupling`: driven speed of a law of the state -> (C, e_d).
    sub : callable
        Substitution of the drivers' laws (expression -> expression).

    Returns
    -------
    DriverReduction
    """

    speed_coords = chain.speed_coordinates
    state = [d for d in driven if speed_coords[d].u in coupling]
    keep = free + state
    time_laws = [(d, a) for d, a in zip(driven, ud_driven) if d not in state]
    M = sp.Matrix(len(keep), len(keep), lambda i, j: sub(mass_matrix[keep[i], keep[j]]))
    f = sp.Matrix([sub(forcing[r] - remainder[r] - sp.Add(*[mass_matrix[r, d] * a for d, a in time_laws]))
                   for r in keep])
    P = sp.zeros(len(keep), len(free))
    e = sp.zeros(len(keep), 1)
    for k in range(len(free)):
        P[k, k] = 1
    for k, d in enumerate(state):
        C, e_d = coupling[speed_coords[d].u]
        P[len(free) + k, :] = sp.Matrix([C])
        e[len(free) + k] = e_d
    return DriverReduction(*dependent_speed_reduction(M, f, P, e))
