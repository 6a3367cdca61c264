"""Whether a distributed load can be integrated along its beam.

A force per unit length ``f(x, t)`` [N/m] enters the equations through ``int_0^L a(x) f(x, t) dx``
(:mod:`flexkane.kane.distributed_loads`), computed by Gauss-Legendre rules, whose nodes lie inside
``(0, L)``: a load whose integral diverges (``0.001/(x - 0.35)**2``) still gives finite numbers there,
arbitrary ones. :func:`check_integrable` refuses such a load before any derivation:

1. **from the expression**: every denominator of the load (a base raised to a negative power
   ``b(x)**(-p)``, ``tan`` as ``sin/cos``) and every argument of a ``log`` is sampled along ``[0, L]``
   at the start and end of the run; a zero of order ``m`` of ``b`` at ``x0`` makes
   ``|f| ~ |x - x0|^(-m p)``, not integrable when ``m p >= 1``; the message names the position of the
   pole and its order;
2. **else by quadrature**: SciPy's adaptive :func:`scipy.integrate.quad` of ``|f(x, 0)|`` over
   ``[0, L]`` must converge without a warning to a finite, non-negative value (a steep load the
   adaptive rule cannot resolve is not integrated by the fixed rules of the derivation either).

Integrable singularities are refused too: ``1/sqrt(|x - a|)`` has a finite integral, but the
derivation's Gauss-Legendre rules reach it with errors of 3 to 10 % in the generalized forces of the
first three clamped-free modes (measured for ``a = 0.35 L``), a silent wrong answer; so the load must
be bounded on ``[0, L]``: every zero of a denominator (any order ``m p > 0``) and of the argument
of a ``log`` is refused, the message saying whether the integral diverges or is only out of reach of
the rules. (Singularities at the beam's ends are already refused by the validation's evaluation of the
load at ``0``, ``L/2`` and ``L``.)

Both checks run only for a load that may be unbounded by its syntax
(:func:`flexkane.expression_syntax.may_be_unbounded`: a division by, a negative or non-numeric power
of, a ``tan`` or a ``log`` of something that depends on ``x``); any other load is bounded on
``[0, L]`` and is accepted without SymPy or SciPy, so that ``flexkane check`` loads neither.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import ModelError
from ..expression_syntax import may_be_unbounded

__all__ = ["check_integrable"]

#: Samples of a denominator along the beam.
_SAMPLES = 2001
#: Functions written as a quotient for the search of poles: the function -> its denominator.
_QUOTIENTS = {"tan": "cos"}


def check_integrable(path: str, text, parameters: dict, length: float, times) -> None:
    """Refuse a distributed load's component that is not integrable along its beam (module docstring).

    Parameters
    ----------
    path : str
        Key path of the component (``distributed_loads.w.fy``).
    text : int, float or str
        The component as given [N/m], an expression of ``x`` [m], ``t`` [s] and the parameters.
    parameters : dict of str to float
        Values of the parameters.
    length : float
        Length of the beam [m].
    times : sequence of float
        Times [s] at which the poles are searched (the start and end of the run).

    Raises
    ------
    ModelError
        Naming the component, a pole of the load on ``[0, L]`` (its position and order) or the
        quadrature's report.
    """
    if not isinstance(text, str) or not may_be_unbounded(text, "x"):
        return    # sums, products, non-negative powers and bounded functions of x: bounded on [0, L]
    import sympy as sp

    from ..expressions import parse_expression

    x, t = sp.Symbol("x", real=True), sp.Symbol("t", real=True)
    names = {name: sp.Float(value) for name, value in parameters.items()}
    expr = parse_expression(text, {**names, "x": x, "t": t}, path=path)
    if not expr.has(x):
        return
    expected = "a force per unit length [N/m] bounded and integrable along the beam (0 <= x <= L)"
    for base, power in _denominators(expr):
        if not base.has(x):   # a function of t alone: the run's own evaluation of the load decides
            continue
        for time in times:
            for x0, order in _zeros(base.xreplace({t: sp.Float(time)}), x, length):
                where = f"{sp.sstr(base)} is zero at x = {x0:.6g} m"
                if power == 0:
                    kind = "a logarithmic singularity"
                else:
                    kind = f"a pole of order {order * power:g}"
                why = "its integral diverges" if order * power >= 1 else \
                    "integrable, but unbounded: the Gauss-Legendre rules of the derivation miss its integral by " \
                    "percents"
                raise ModelError(path, expected, text, f"{where}, {kind} of the load at t = {time:g} s: {why}")
    _check_quadrature(path, text, expected, sp.lambdify(x, expr.xreplace({t: sp.Float(0)}), modules="numpy"),
                      length)


def _denominators(expr, power=1):
    """(base, p) of every factor ``base**(-p)`` reached through sums, products and positive powers
    (``p = 0`` for the argument of a ``log``)."""
    import sympy as sp

    if isinstance(expr, (sp.Add, sp.Mul)):
        for arg in expr.args:
            yield from _denominators(arg, power)
    elif isinstance(expr, sp.Pow) and expr.exp.is_number and expr.exp.is_real:
        exponent = float(expr.exp)
        if exponent < 0:
            yield expr.base, -exponent * power
        else:
            yield from _denominators(expr.base, exponent * power)
    elif isinstance(expr, sp.Function) and expr.func.__name__ in _QUOTIENTS:
        yield getattr(sp, _QUOTIENTS[expr.func.__name__])(*expr.args), power
    elif isinstance(expr, sp.log):
        yield expr.args[0], 0.0


def _zeros(base, x, length: float):
    """(x0, order) of the zeros of ``base(x)`` on ``[0, L]``: sign changes on a grid, and minima of
    ``|base|`` that reach zero (double roots), each with its order (:func:`_order`)."""
    import sympy as sp
    from scipy.optimize import brentq, minimize_scalar

    grid = np.linspace(0.0, length, _SAMPLES)
    f = sp.lambdify(x, base, modules="numpy")
    with np.errstate(all="ignore"):
        values = np.broadcast_to(np.asarray(f(grid), dtype=complex), grid.shape)
    if np.any(np.abs(values.imag) > 0) or not np.all(np.isfinite(values.real)):
        return []   # complex or not finite somewhere: the validation's own checks at sample points decide
    values = values.real
    scale = float(np.max(np.abs(values))) or 1.0
    found = []
    zero = np.flatnonzero(values == 0.0)
    found += [float(grid[k]) for k in zero]
    change = np.flatnonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0)
    found += [brentq(lambda s: float(np.real(f(s))), grid[k], grid[k + 1], xtol=1e-14) for k in change]
    magnitude = np.abs(values)
    minima = np.flatnonzero((magnitude[1:-1] <= magnitude[:-2]) & (magnitude[1:-1] <= magnitude[2:])
                            & (magnitude[1:-1] < 1e-3 * scale)) + 1
    for k in minima:
        best = minimize_scalar(lambda s: abs(complex(f(s))), bounds=(grid[k - 1], grid[k + 1]), method="bounded",
                               options={"xatol": 1e-14})
        if abs(complex(f(best.x))) <= 1e-12 * scale:
            found.append(float(best.x))
    return [(x0, _order(f, x0, length)) for x0 in sorted({round(v, 12) for v in found})]


def _order(f, x0: float, length: float) -> float:
    """Order m of a zero of ``f`` at ``x0``, from ``|f(x0 + h)| ~ h^m`` at two distances (on the side
    inside the beam), rounded to a hundredth."""
    side = 1.0 if x0 + 1e-3 * length <= length else -1.0
    h1, h2 = 1e-5 * length, 1e-4 * length
    with np.errstate(all="ignore"):
        f1, f2 = abs(complex(f(x0 + side * h1))), abs(complex(f(x0 + side * h2)))
    if not (f1 > 0 and f2 > 0 and np.isfinite(f1) and np.isfinite(f2)):
        return 1.0
    return round(float(np.log(f2 / f1) / np.log(h2 / h1)), 2)


def _check_quadrature(path: str, text, expected: str, f, length: float) -> None:
    """Refuse a load whose ``int_0^L |f(x, 0)| dx`` the adaptive quadrature does not bring to convergence."""
    from scipy.integrate import IntegrationWarning, quad

    def magnitude(s):
        with np.errstate(all="ignore"):
            value = complex(f(s))
        return abs(value) if np.isfinite(value) else np.inf

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IntegrationWarning)
        result = quad(magnitude, 0.0, length, limit=100, full_output=True)
    value = result[0]
    report = result[3] if len(result) > 3 else None
    if report or not np.isfinite(value) or value < 0:
        reason = str(report).split("\n")[0].strip() if report else f"the integral of |f| came out as {value:g}"
        raise ModelError(path, expected, text,
                         f"the adaptive quadrature of |f| over [0, {length:g}] m at t = 0 does not converge: "
                         f"{reason} (a pole, or a variation too steep to integrate)")
