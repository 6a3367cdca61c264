"""Modal integrals of a shape family by Gauss-Legendre quadrature (eqs. 8.22, 8.32).

Integrands are products of shape functions whose fastest member oscillates like
``cos(2 lambda_n xi)``. The quadrature order is first guessed from the family
(:meth:`~flexkane.modes.base.ShapeFamily.quadrature_order`) and then *verified*: it is raised
until two orders agree to ``1e-13`` relative to the Cauchy-Schwarz bound ``||a|| ||b||`` of every
entry. Quadrature is done on ``xi = x / L`` in ``[0, 1]`` and scaled to metres afterwards, so
results for any ``L``, ``rho``, ``EI`` come from one cached dimensionless computation per
``(family, n)``. ``E_i`` and ``F_i`` of eigenfunction families are exact end-value formulas
(``_eigen_moments``) instead, since quadrature leaves rounding of order ``1e-15`` in these
small numbers.
"""
from __future__ import annotations

import functools
from typing import Callable, NamedTuple

import numpy as np
from scipy.linalg import eigvalsh_tridiagonal

from ..errors import ModelError
from .base import ShapeFamily, check_mode_count, check_positive
from .eigen import EigenFamily
from .exponential_form import evaluate

__all__ = ["gauss_legendre", "gram_matrix", "gram", "quadrature_order", "MassIntegrals",
           "mass_integrals", "stiffness_integrals", "foreshortening", "stiffening_integrals"]

#: Agreement between two quadrature orders accepted as converged, relative to ``||a|| ||b||``.
TOLERANCE = 1e-13
#: Largest quadrature order tried before giving up.
MAX_ORDER = 3000


def _legendre_and_derivative(order: int, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``P_N(t)`` and ``P_N'(t)`` by the three-term recurrence (``|t| < 1``)."""
    previous, current = np.ones_like(t), t.copy()
    for k in range(1, order):
        previous, current = current, ((2 * k + 1) * t * current - k * previous) / (k + 1)
    return current, order * (t * current - previous) / (t * t - 1.0)


@functools.lru_cache(maxsize=64)
def _leggauss(order: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes and weights on ``[-1, 1]``: Golub-Welsch nodes (a tridiagonal eigenproblem, so
    ``O(N^2)`` where ``numpy.polynomial.legendre.leggauss`` is ``O(N^3)``), polished by Newton
    steps on ``P_N``; weights ``2 / ((1 - t^2) P_N'(t)^2)``."""
    if order < 2:
        t, w = np.zeros(1), np.full(1, 2.0)
    else:
        k = np.arange(1.0, order)
        t = eigvalsh_tridiagonal(np.zeros(order), k / np.sqrt(4.0 * k * k - 1.0))
        for _ in range(2):
            p, dp = _legendre_and_derivative(order, t)
            t = t - p / dp
        _, dp = _legendre_and_derivative(order, t)
        w = 2.0 / ((1.0 - t * t) * dp * dp)
        t = 0.5 * (t - t[::-1])
        w = 0.5 * (w + w[::-1])
        w *= 2.0 / w.sum()
    t.flags.writeable = False
    w.flags.writeable = False
    return t, w


def gauss_legendre(order: int, a: float = 0.0, b: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on ``[a, b]``.

    Parameters
    ----------
    order : int
        Number of nodes ``N``; exact for polynomials of degree ``2 N - 1``.
    a, b : float
        Interval.

    Returns
    -------
    x, w : numpy.ndarray
        Nodes and weights, shape ``(N,)`` each.
    """
    t, w = _leggauss(int(order))
    half = 0.5 * (b - a)
    return a + half * (t + 1.0), half * w


def gram_matrix(a_values: np.ndarray, b_values: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Quadrature of ``int a_i b_j`` from values at the nodes: ``sum_k w_k a_ik b_jk``.

    Parameters
    ----------
    a_values : numpy.ndarray
        Shape ``(na, N)``.
    b_values : numpy.ndarray
        Shape ``(nb, N)``.
    weights : numpy.ndarray
        Quadrature weights (times any weight function), shape ``(N,)``.

    Returns
    -------
    numpy.ndarray
        Shape ``(na, nb)``.
    """
    return (np.asarray(a_values) * np.asarray(weights)) @ np.asarray(b_values).T


def _bound(a: np.ndarray, b: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Cauchy-Schwarz bounds ``||a_i|| ||b_j||`` (``|w|`` weighted), shape ``(na, nb)``."""
    aw = np.sqrt(np.abs(w) @ (a * a).T)
    bw = np.sqrt(np.abs(w) @ (b * b).T)
    return np.outer(aw, bw) + np.finfo(float).tiny


def _tolerance(family: ShapeFamily) -> float:
    """The agreement asked of a family's integrals: ``TOLERANCE`` times its ``rounding_gain``, the
    factor by which its functions amplify the rounding of the functions they combine (1 for the
    families evaluated directly; :mod:`flexkane.modes.static_correction` combines modes)."""
    return TOLERANCE * max(1.0, float(getattr(family, "rounding_gain", 1.0)))


def _converge(evaluate: Callable[[int], tuple[np.ndarray, np.ndarray]], order: int,
              path: str, tolerance: float = TOLERANCE) -> tuple[np.ndarray, int]:
    """Raise the order from ``order`` until ``evaluate(order) -> (value, bound)`` settles."""
    previous, _ = evaluate(order)
    while order < MAX_ORDER:
        order = min(MAX_ORDER, order + max(16, order // 2))
        value, bound = evaluate(order)
        if np.all(np.abs(value - previous) <= tolerance * bound):
            return value, order
        previous = value
    raise ModelError(path, "functions smooth enough for Gauss-Legendre quadrature to converge",
                     f"no agreement up to order {MAX_ORDER}",
                     hint="check the shape functions (and weight) for singularities on 0 <= xi <= 1")


def gram(funcs_a: Callable[[np.ndarray], np.ndarray], funcs_b: Callable[[np.ndarray], np.ndarray],
         L: float, weight: Callable[[np.ndarray], np.ndarray] | None = None,
         order: int | None = None) -> np.ndarray:
    """Matrix of integrals ``int_0^L w(x) a_i(x) b_j(x) dx``.

    Parameters
    ----------
    funcs_a, funcs_b : callable
        Vectorised: ``funcs_a(x)`` with ``x`` [m] of shape ``(N,)`` returns shape ``(na, N)``.
    L : float
        Length of the interval [m].
    weight : callable, optional
        Vectorised weight ``w(x)`` (e.g. ``rho`` [kg/m]), shape ``(N,)``; unit weight if omitted.
    order : int, optional
        Fixed Gauss-Legendre order. If omitted, the order is raised from 32 until converged.

    Returns
    -------
    numpy.ndarray
        Shape ``(na, nb)``, in the units of ``w a b`` times metres.
    """
    L = check_positive(L, "L", "the length of the beam [m]")

    def evaluate(k: int) -> tuple[np.ndarray, np.ndarray]:
        x, w = gauss_legendre(k, 0.0, L)
        if weight is not None:
            w = w * np.broadcast_to(np.asarray(weight(x), dtype=float), x.shape)
        a = np.atleast_2d(np.asarray(funcs_a(x), dtype=float))
        b = np.atleast_2d(np.asarray(funcs_b(x), dtype=float))
        return gram_matrix(a, b, w), _bound(a, b, w)

    if order is not None:
        return evaluate(int(order))[0]
    return _converge(evaluate, 32, "gram")[0]


def _products(family: ShapeFamily, n: int, x: np.ndarray,
              w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The integrals the modal constants need, ``[Phi 1, Phi xi]`` and ``Phi^(k) Phi^(k)``
    for ``k = 0, 1, 2``, flattened, with their Cauchy-Schwarz bounds."""
    values, bounds = [], []
    phi = family.phi(x, n, 0)
    moments = np.vstack([np.ones_like(x), x])
    values.append(gram_matrix(phi, moments, w).ravel())
    bounds.append(_bound(phi, moments, w).ravel())
    for k in range(3):
        a = phi if k == 0 else family.phi(x, n, k)
        values.append(gram_matrix(a, a, w).ravel())
        bounds.append(_bound(a, a, w).ravel())
    return np.concatenate(values), np.concatenate(bounds)


@functools.lru_cache(maxsize=256)
def quadrature_order(family: ShapeFamily, n: int) -> int:
    """Verified Gauss-Legendre order for the modal integrals of the first ``n`` functions.

    Checked are the products ``Phi_i``, ``xi Phi_i``, ``Phi_i Phi_j``, ``Phi_i' Phi_j'`` and
    ``Phi_i'' Phi_j''``, each to ``1e-13`` relative to its Cauchy-Schwarz bound (module
    docstring).

    Parameters
    ----------
    family : ShapeFamily
        The family.
    n : int
        Number of modes.

    Returns
    -------
    int
        The order; cached per ``(family, n)``.

    Raises
    ------
    ModelError
        If no order up to ``MAX_ORDER`` converges (a singular function or derivative).
    """
    n = check_mode_count(n)

    def evaluate(k: int) -> tuple[np.ndarray, np.ndarray]:
        x, w = gauss_legendre(k)
        return _products(family, n, x, w)

    return _converge(evaluate, family.quadrature_order(n), family.name, _tolerance(family))[1]


class MassIntegrals(NamedTuple):
    """Inertia constants of a uniform beam (definitions after eq. 8.22).

    Attributes
    ----------
    m_B : float
        ``int_0^L rho dx`` [kg].
    e_B : float
        ``int_0^L x rho dx`` [kg m].
    I_B : float
        ``int_0^L x^2 rho dx`` [kg m^2].
    E : numpy.ndarray
        ``E_i = int_0^L Phi_i rho dx`` [kg], shape ``(n,)``.
    F : numpy.ndarray
        ``F_i = int_0^L x Phi_i rho dx`` [kg m], shape ``(n,)``.
    G : numpy.ndarray
        ``G_ij = int_0^L Phi_i Phi_j rho dx`` [kg], shape ``(n, n)``.
    """

    m_B: float
    e_B: float
    I_B: float
    E: np.ndarray
    F: np.ndarray
    G: np.ndarray


def _frozen(*arrays: np.ndarray) -> tuple[np.ndarray, ...]:
    for a in arrays:
        a.flags.writeable = False
    return arrays


def _eigen_moments(family: EigenFamily, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Exact ``int_0^1 Phi_i dxi`` and ``int_0^1 xi Phi_i dxi`` of eigenfunctions.

    Since ``Phi = Phi^(4) / lambda^4``, integration by parts gives
    ``int_0^1 Phi = [Phi^(3)]_0^1 / lambda^4`` and
    ``int_0^1 xi Phi = [xi Phi^(3) - Phi^(2)]_0^1 / lambda^4``: end values only, free of the
    rounding that quadrature of an oscillating integrand leaves in these small numbers
    (``E_i ~ 1 / lambda_i``, ``F_i ~ 1 / lambda_i^2``).
    """
    lam, coeffs = family.coefficients(n)
    ends = np.array([0.0, 1.0])
    d2 = evaluate(lam, coeffs, ends, 2) / lam[:, None] ** 2
    d3 = evaluate(lam, coeffs, ends, 3) / lam[:, None] ** 3
    first = (d3[:, 1] - d3[:, 0]) / lam
    second = d3[:, 1] / lam - (d2[:, 1] - d2[:, 0]) / lam ** 2
    return first, second


@functools.lru_cache(maxsize=256)
def _unit_mass(family: ShapeFamily, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``int_0^1 Phi_i``, ``int_0^1 xi Phi_i``, ``int_0^1 Phi_i Phi_j`` (dimensionless)."""
    x, w = gauss_legendre(quadrature_order(family, n))
    values = family.phi(x, n, 0)
    if isinstance(family, EigenFamily):
        first, second = _eigen_moments(family, n)
    else:
        first, second = values @ w, values @ (w * x)
    return _frozen(first, second, gram_matrix(values, values, w))


@functools.lru_cache(maxsize=256)
def _unit_stiffness(family: ShapeFamily, n: int) -> np.ndarray:
    """``int_0^1 Phi_i^(k) Phi_j^(k) dxi``, ``k = 2`` (bending) or ``1`` (axial, torsion)."""
    x, w = gauss_legendre(quadrature_order(family, n))
    values = family.phi(x, n, 1 if family.kind in ("axial", "torsion") else 2)
    return _frozen(gram_matrix(values, values, w))[0]


def mass_integrals(family: ShapeFamily, n: int, L: float, rho: float) -> MassIntegrals:
    """Inertia constants ``m_B, e_B, I_B, E_i, F_i, G_ij`` of a uniform beam (eq. 8.22).

    Parameters
    ----------
    family : ShapeFamily
        Shape functions ``Phi_i(x / L)``.
    n : int
        Number of modes.
    L : float
        Length of the beam [m].
    rho : float
        Mass per unit length [kg/m].

    Returns
    -------
    MassIntegrals
        New arrays (the caller may modify them); ``G = m I`` for the eigenfunction families
        without tip body (eq. 8.8, ``m = rho L``).
    """
    n = check_mode_count(n)
    L = check_positive(L, "L", "the length of the beam [m]")
    rho = check_positive(rho, "rho", "the mass per unit length [kg/m]")
    e_hat, f_hat, g_hat = _unit_mass(family, n)
    m = rho * L
    return MassIntegrals(m_B=m, e_B=m * L / 2.0, I_B=m * L * L / 3.0,
                         E=m * e_hat, F=m * L * f_hat, G=m * g_hat)


def stiffness_integrals(family: ShapeFamily, n: int, L: float, EI: float) -> np.ndarray:
    """Stiffness constants ``H_ij = int_0^L EI Phi_i'' Phi_j'' dx`` of a uniform beam (eq. 8.32).

    Parameters
    ----------
    family : ShapeFamily
        Shape functions; for an axial family (``family.kind == "axial"``) the result is
        ``int_0^L EA psi_i' psi_j' dx`` and ``EI`` stands for the axial rigidity ``EA`` [N]; for a
        torsion family, ``int_0^L GJ Theta_i' Theta_j' dx`` [N m] with ``EI`` standing for the
        torsional rigidity ``GJ`` [N m^2].
    n : int
        Number of modes.
    L : float
        Length of the beam [m].
    EI : float
        Flexural rigidity [N m^2] (axial rigidity [N] for an axial family).

    Returns
    -------
    numpy.ndarray
        ``H`` [N/m], shape ``(n, n)``; ``H = m p_i^2 delta_ij`` for the eigenfunction families
        without tip body (eq. 8.9).
    """
    n = check_mode_count(n)
    L = check_positive(L, "L", "the length of the beam [m]")
    if family.kind == "axial":
        EA = check_positive(EI, "EA", "the axial rigidity [N]")
        return EA / L * _unit_stiffness(family, n)
    if family.kind == "torsion":
        GJ = check_positive(EI, "GJ", "the torsional rigidity [N m^2]")
        return GJ / L * _unit_stiffness(family, n)
    EI = check_positive(EI, "EI", "the flexural rigidity [N m^2]")
    return EI / L ** 3 * _unit_stiffness(family, n)


def foreshortening(family: ShapeFamily, n: int, L: float, x: np.ndarray) -> np.ndarray:
    """Foreshortening functions ``d_ij(x) = int_0^x Phi_i'(s) Phi_j'(s) ds``.

    Derivatives are with respect to ``s`` [m], so ``-1/2 sum_ij d_ij(x) q_i q_j`` is the axial
    shortening [m] of the point at ``x`` caused by the deflection ``y = sum Phi_i q_i``. Each
    ``x`` gets its own Gauss-Legendre rule on ``[0, x]`` (of the verified order of the family).

    Parameters
    ----------
    family : ShapeFamily
        Shape functions ``Phi_i(x / L)``.
    n : int
        Number of modes.
    L : float
        Length of the beam [m].
    x : float or array_like
        Abscissae [m] in ``[0, L]``, shape ``(P,)``.

    Returns
    -------
    numpy.ndarray
        ``d_ij(x_p)`` [1/m], shape ``(n, n, P)``, symmetric in ``i, j``.
    """
    n = check_mode_count(n)
    L = check_positive(L, "L", "the length of the beam [m]")
    xs = np.atleast_1d(np.asarray(x, dtype=float))
    if xs.ndim != 1 or np.any(xs < 0.0) or np.any(xs > L):
        raise ModelError("x", f"abscissae in [0, L] = [0, {L:g}] m", x)
    t, w = gauss_legendre(quadrature_order(family, n))
    out = np.empty((n, n, xs.size))
    chunk = max(1, 200_000 // (n * t.size))
    for start in range(0, xs.size, chunk):
        xi = xs[start:start + chunk] / L                       # (P,)
        nodes = (xi[:, None] * t[None, :]).ravel()             # (P N,)
        slope = family.phi(nodes, n, 1).reshape(n, xi.size, t.size)
        out[:, :, start:start + chunk] = np.einsum("ipk,jpk,k->ijp", slope, slope, w) * xi / L
    return out


def stiffening_integrals(family: ShapeFamily, n: int, L: float,
                         w: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """Geometric-stiffening integrals ``int_0^L w(x) Phi_i'(x) Phi_j'(x) dx``.

    Parameters
    ----------
    family : ShapeFamily
        Shape functions ``Phi_i(x / L)``.
    n : int
        Number of modes.
    L : float
        Length of the beam [m].
    w : callable
        Vectorised weight of ``x`` [m], e.g. the axial tension [N]; shape ``(N,)`` from ``(N,)``.

    Returns
    -------
    numpy.ndarray
        Shape ``(n, n)``, in the units of ``w`` per metre (derivatives are with respect to x).
    """
    n = check_mode_count(n)
    L = check_positive(L, "L", "the length of the beam [m]")

    def evaluate(k: int) -> tuple[np.ndarray, np.ndarray]:
        xi, weights = gauss_legendre(k)
        ww = weights * np.broadcast_to(np.asarray(w(xi * L), dtype=float), xi.shape)
        slope = family.phi(xi, n, 1)
        return gram_matrix(slope, slope, ww) / L, _bound(slope, slope, ww) / L

    return _converge(evaluate, quadrature_order(family, n), "stiffening weight w", _tolerance(family))[0]
