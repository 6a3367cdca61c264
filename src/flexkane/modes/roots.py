"""Roots of the frequency equations of uniform beams, to full double precision.

Each frequency equation is divided by ``cosh lambda`` so that it stays ``O(1)``: eq. 8.6,
``cos l cosh l + 1 = 0``, becomes ``cos l + 1/cosh l = 0``, whose ``i``-th root lies within
``1/cosh`` of ``(2i - 1) pi / 2``. Newton's method from that asymptotic value converges in a few
steps; it is guarded by a bracket that contains exactly one root and falls back to Brent's method
should a step leave it.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

__all__ = ["newton_in_bracket", "cantilever_roots", "clamped_clamped_roots", "tan_tanh_roots",
           "scan_roots"]

_EPS = np.finfo(float).eps


def _sech(x: float) -> float:
    return 0.0 if x > 700.0 else 1.0 / math.cosh(x)


def newton_in_bracket(f: Callable[[float], float], fprime: Callable[[float], float], x0: float,
                      lo: float, hi: float) -> float:
    """Root of ``f`` by Newton's method from ``x0``, kept inside ``[lo, hi]``.

    Parameters
    ----------
    f, fprime : callable
        The function and its derivative.
    x0 : float
        Starting point inside the bracket.
    lo, hi : float
        Bracket with ``f(lo) f(hi) < 0`` and one root inside.

    Returns
    -------
    float
        The root, to a few units in the last place.
    """
    x = x0
    for _ in range(60):
        step = f(x) / fprime(x)
        x_new = x - step
        if not lo <= x_new <= hi or not math.isfinite(x_new):
            break
        if abs(step) <= 2.0 * _EPS * abs(x_new):
            # one more step to land on the nearest representable root
            last = x_new - f(x_new) / fprime(x_new)
            return last if lo <= last <= hi and abs(last - x_new) <= abs(step) else x_new
        x = x_new
    from scipy.optimize import brentq   # here: building a family must not import SciPy

    return brentq(f, lo, hi, xtol=1e-300, rtol=4.0 * _EPS, maxiter=500)


def cantilever_roots(n: int) -> np.ndarray:
    """Roots of ``cos l cosh l + 1 = 0`` (eq. 8.6), the clamped-free beam, shape ``(n,)``."""
    def f(x: float) -> float:
        return math.cos(x) + _sech(x)

    def fprime(x: float) -> float:
        return -math.sin(x) - _sech(x) * math.tanh(x)

    return np.array([newton_in_bracket(f, fprime, (2 * i - 1) * math.pi / 2,
                                       (i - 1) * math.pi, i * math.pi) for i in range(1, n + 1)])


def clamped_clamped_roots(n: int) -> np.ndarray:
    """Positive roots of ``cos l cosh l - 1 = 0`` (clamped-clamped and free-free), shape ``(n,)``."""
    def f(x: float) -> float:
        return math.cos(x) - _sech(x)

    def fprime(x: float) -> float:
        return -math.sin(x) + _sech(x) * math.tanh(x)

    return np.array([newton_in_bracket(f, fprime, (2 * i + 1) * math.pi / 2,
                                       i * math.pi, (i + 1) * math.pi) for i in range(1, n + 1)])


def tan_tanh_roots(n: int) -> np.ndarray:
    """Positive roots of ``tan l = tanh l`` (pinned-free and clamped-pinned), shape ``(n,)``."""
    def f(x: float) -> float:
        return math.sin(x) - math.cos(x) * math.tanh(x)

    def fprime(x: float) -> float:
        t = math.tanh(x)
        return math.cos(x) * t * t + math.sin(x) * t

    return np.array([newton_in_bracket(f, fprime, i * math.pi + math.pi / 4,
                                       i * math.pi, i * math.pi + math.pi / 2)
                     for i in range(1, n + 1)])


def scan_roots(f: Callable[[np.ndarray], np.ndarray], n: int, upper: float) -> np.ndarray:
    """The first ``n`` positive roots of a vectorised ``f`` below ``upper``, by sign changes.

    The grid is geometric on ``[1e-6, 1]`` (small roots, e.g. a heavy tip mass) and has steps of
    ``pi / 64`` above; each bracket is refined by Brent's method to ``4 eps`` relative.

    Parameters
    ----------
    f : callable
        Vectorised function of ``lambda``, ``f(0+) != 0``.
    n : int
        Number of roots wanted.
    upper : float
        A bound known to exceed the ``n``-th root.

    Returns
    -------
    numpy.ndarray
        Shape ``(n,)``.

    Raises
    ------
    RuntimeError
        If fewer than ``n`` sign changes are found (a bug in ``upper``).
    """
    steps = max(1, int(math.ceil((upper - 1.0) * 64 / math.pi)))
    grid = np.concatenate([np.geomspace(1e-6, 1.0, 400, endpoint=False),
                           np.linspace(1.0, upper, steps + 1)])
    values = f(grid)

    def scalar(x: float) -> float:
        return float(f(np.array([x]))[0])

    from scipy.optimize import brentq

    found = []
    for k in range(grid.size - 1):
        if values[k] == 0.0:
            found.append(grid[k])
        elif values[k] * values[k + 1] < 0.0:
            found.append(brentq(scalar, grid[k], grid[k + 1], xtol=1e-300, rtol=4.0 * _EPS,
                                maxiter=500))
        if len(found) == n:
            return np.array(found)
    raise RuntimeError(f"found {len(found)} of {n} roots below {upper}")
