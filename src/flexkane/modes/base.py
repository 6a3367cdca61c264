"""The contract every family of shape functions fulfils.

A *shape family* supplies the functions ``Phi_i(xi)`` of the dimensionless abscissa
``xi = x / L`` in which the deflection of a beam is expanded (eq. 8.3, eq. 8.15)::

    y(x, t) = sum_i Phi_i(x / L) q_i(t)

The contract, numbered as the checks that rely on it:

1. ``phi(xi, n, deriv)`` returns ``d^k Phi_i / d xi^k`` for ``i = 1..n`` and ``k = deriv`` in
   0..4, as an array of shape ``(n, len(xi))``. Derivatives with respect to ``x`` [m] are these
   divided by ``L**k``.
2. ``roots(n)`` returns the dimensionless eigenvalue parameters ``lambda_i`` (shape ``(n,)``), or
   ``None`` for a family that is not made of eigenfunctions.
3. ``frequencies(n, L, EI, rho)`` returns the natural circular frequencies [rad/s] of eq. 8.7
   (shape ``(n,)``), or ``None`` where no eigenvalues exist.
4. Elastic eigenfunctions are mass-normalised, ``int_0^1 Phi_i Phi_j dxi = delta_ij``, which is
   the normalisation of eq. 8.4 (eq. 8.8 then reads ``int_0^L Phi_i Phi_j rho dx = m delta_ij``).
5. Rigid-body modes (zero frequency) are never part of ``phi``; they are listed in
   ``rigid_modes`` and evaluated by ``rigid_phi``.
"""

from __future__ import annotations

import abc
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ModelError

__all__ = ["ShapeFamily", "RigidMode", "END_CONDITIONS", "check_positive", "check_mode_count",
           "as_abscissae", "parse_boundary"]

#: Geometric end conditions and the derivatives they set to zero.
END_CONDITIONS = {
    "clamped": (0, 1),
    "pinned": (0,),
    "fixed": (0,),
    "free": (),
}


def check_positive(value: Any, path: str, what: str) -> float:
    """Return ``value`` as a float after checking that it is finite and positive.

    Parameters
    ----------
    value : object
        The value given.
    path : str
        Name of the argument, used in the error message.
    what : str
        Description with its unit, e.g. ``"a length [m]"``.

    Returns
    -------
    float
        The value.

    Raises
    ------
    ModelError
        If the value is not a finite positive number.
    """
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ModelError(path, f"{what}, a positive number", value) from None
    if not math.isfinite(number) or number <= 0.0:
        raise ModelError(path, f"{what}, a positive number", value)
    return number


def check_mode_count(n: Any, path: str = "n") -> int:
    """Return the number of modes ``n`` as an int after checking that it is at least 1."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ModelError(path, "a positive integer number of modes", n)
    return int(n)


def as_abscissae(xi: Any, path: str = "xi") -> np.ndarray:
    """Return ``xi`` as a 1-D float array of abscissae in ``[0, 1]``.

    Values outside by at most ``1e-12`` (rounding of ``x / L``) are moved onto the ends.

    Parameters
    ----------
    xi : float or array_like
        Dimensionless abscissae ``x / L``.
    path : str
        Name of the argument, used in the error message.

    Returns
    -------
    numpy.ndarray
        Shape ``(m,)``.
    """
    values = np.atleast_1d(np.asarray(xi, dtype=float))
    if values.ndim != 1:
        raise ModelError(path, "a scalar or a 1-D array of abscissae x/L", f"shape {values.shape}")
    if values.size and not (np.all(values >= -1e-12) and np.all(values <= 1.0 + 1e-12)):
        raise ModelError(path, "abscissae x/L in [0, 1]",
                         f"values in [{np.nanmin(values)}, {np.nanmax(values)}]")
    # rounding of x / L may overshoot the ends by an ulp or so
    return np.clip(values, 0.0, 1.0)


@dataclass(frozen=True)
class RigidMode:
    """A rigid-body mode of an unconstrained or partly constrained beam.

    Parameters
    ----------
    name : str
        What the mode is, e.g. ``"translation"``.
    coefficients : tuple of float
        Polynomial coefficients in increasing powers of ``xi``; mass-normalised so that
        ``int_0^1 Phi^2 dxi = 1``.
    """

    name: str
    coefficients: tuple[float, ...]

    def __call__(self, xi: np.ndarray, deriv: int = 0) -> np.ndarray:
        """Evaluate ``d^k Phi / d xi^k`` at ``xi`` (shape ``(m,)``), ``k = deriv``."""
        poly = np.polynomial.Polynomial(self.coefficients).deriv(deriv)
        return poly(np.asarray(xi, dtype=float)) * np.ones_like(xi, dtype=float)


class ShapeFamily(abc.ABC):
    """A family of shape functions ``Phi_i(xi)`` of a beam, ``xi = x / L``.

    Subclasses set ``name``, ``boundary`` (``"<root>-<tip>"``, e.g. ``"clamped-free"``) and
    ``kind`` (``"transverse"`` or ``"axial"``), and implement :meth:`phi`.

    Parameters
    ----------
    options : dict
        The options the family was created with (``get_family(name, **options)``); they identify
        the family together with its name, so two families with equal names and options are
        equal and share cached modal integrals.
    """

    name: str = ""
    boundary: str = ""
    kind: str = "transverse"
    #: Names of the options ``get_family`` accepts for this family.
    option_names: tuple[str, ...] = ()
    #: The options that are numbers (in a model file: numbers or expressions of the parameters,
    #: evaluated per parameter set); the others (names, boundaries) are structure.
    numeric_options: tuple[str, ...] = ()
    #: Rigid-body modes, excluded from :meth:`phi`.
    rigid_modes: tuple[RigidMode, ...] = ()

    def __init__(self, options: dict[str, Any] | None = None):
        self.options = dict(options or {})

    # ------------------------------------------------------------------ identity
    @property
    def key(self) -> tuple:
        """Hashable identity: the name and the options (lists become tuples)."""
        def freeze(value: Any) -> Any:
            if isinstance(value, (list, tuple)):
                return tuple(freeze(v) for v in value)
            if isinstance(value, float):
                return float(value)
            return value
        return (self.name, tuple(sorted((k, freeze(v)) for k, v in self.options.items())))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, ShapeFamily) and self.key == other.key

    def __hash__(self) -> int:
        return hash(self.key)

    def __repr__(self) -> str:
        options = ", ".join(f"{k}={v!r}" for k, v in sorted(self.options.items()))
        return f"get_family({self.name!r}{', ' if options else ''}{options})"

    # ------------------------------------------------------------------ contract
    @property
    def max_modes(self) -> int | None:
        """Largest ``n`` the family supports, ``None`` when unbounded."""
        return None

    def roots(self, n: int) -> np.ndarray | None:
        """Eigenvalue parameters ``lambda_i``, shape ``(n,)``; ``None`` if not eigenfunctions."""
        return None

    @abc.abstractmethod
    def phi(self, xi: Any, n: int, deriv: int = 0) -> np.ndarray:
        """Shape functions or their derivatives.

        Parameters
        ----------
        xi : float or array_like
            Abscissae ``x / L`` in ``[0, 1]``, shape ``(m,)``.
        n : int
            Number of functions.
        deriv : int
            Order ``k`` (0..4) of the derivative with respect to ``xi``.

        Returns
        -------
        numpy.ndarray
            ``d^k Phi_i / d xi^k``, shape ``(n, m)``.
        """

    def frequencies(self, n: int, L: float, EI: float, rho: float) -> np.ndarray | None:
        """Natural circular frequencies ``p_i = (lambda_i / L)^2 (EI / rho)^(1/2)`` (eq. 8.7).

        Parameters
        ----------
        n : int
            Number of modes.
        L : float
            Length of the beam [m].
        EI : float
            Flexural rigidity [N m^2].
        rho : float
            Mass per unit length [kg/m].

        Returns
        -------
        numpy.ndarray or None
            ``p_i`` [rad/s], shape ``(n,)``; ``None`` for a family without eigenvalues.
        """
        lam = self.roots(n)
        if lam is None:
            return None
        L = check_positive(L, "L", "the length of the beam [m]")
        EI = check_positive(EI, "EI", "the flexural rigidity [N m^2]")
        rho = check_positive(rho, "rho", "the mass per unit length [kg/m]")
        return (lam / L) ** 2 * math.sqrt(EI / rho)

    def rigid_phi(self, xi: Any, deriv: int = 0) -> np.ndarray:
        """Rigid-body modes at ``xi``: ``d^k Phi / d xi^k``, shape ``(len(rigid_modes), m)``."""
        x = as_abscissae(xi)
        self._check_deriv(deriv)
        if not self.rigid_modes:
            return np.zeros((0, x.size))
        return np.vstack([mode(x, deriv) for mode in self.rigid_modes])

    def quadrature_order(self, n: int) -> int:
        """A first guess of the Gauss-Legendre order that integrates products of the first ``n``
        functions and their second derivatives; :mod:`flexkane.modes.integrals` verifies it."""
        return 2 * n + 24

    def admissibility(self, boundary: str) -> None:
        """Check that the functions satisfy the geometric conditions of ``boundary``.

        Parameters
        ----------
        boundary : str
            ``"<root>"`` or ``"<root>-<tip>"`` with each end ``clamped`` (``Phi = Phi' = 0``),
            ``pinned`` or ``fixed`` (``Phi = 0``) or ``free`` (no geometric condition).

        Raises
        ------
        ModelError
            Naming the first function and the condition it violates.
        """
        root, tip = parse_boundary(boundary)
        n = self.max_modes or 8
        for end, xi0, label in ((root, 0.0, "0"), (tip, 1.0, "1")):
            for k in END_CONDITIONS[end]:
                values = self.phi(np.array([xi0]), n, k)[:, 0]
                scale = np.max(np.abs(self.phi(np.linspace(0.0, 1.0, 65), n, k)), axis=1)
                for i, (value, s) in enumerate(zip(values, scale)):
                    if abs(value) > 1e-9 * max(s, 1.0):
                        prime = "'" * k
                        raise ModelError(f"Phi_{i + 1} of {self.name}",
                                         f"Phi{prime}({label}) = 0 at a {end} end",
                                         f"Phi{prime}({label}) = {value:.6g}")

    # ------------------------------------------------------------------ helpers
    @staticmethod
    def _check_deriv(deriv: Any) -> int:
        if isinstance(deriv, bool) or not isinstance(deriv, (int, np.integer)) or not 0 <= deriv <= 4:
            raise ModelError("deriv", "an integer order of derivative 0..4", deriv)
        return int(deriv)

    def _check_n(self, n: Any) -> int:
        n = check_mode_count(n)
        if self.max_modes is not None and n > self.max_modes:
            raise ModelError("n", f"at most {self.max_modes} modes for family {self.name!r}", n)
        return n


def parse_boundary(boundary: Any) -> tuple[str, str]:
    """Split ``"<root>-<tip>"`` (or ``"<root>"``, tip free) into its two end conditions."""
    if not isinstance(boundary, str):
        raise ModelError("boundary", "a boundary such as 'clamped-free'", boundary)
    parts = boundary.strip().lower().split("-")
    if len(parts) == 1:
        parts.append("free")
    if len(parts) != 2 or any(p not in END_CONDITIONS for p in parts):
        raise ModelError("boundary", "'<root>-<tip>' with ends among "
                         + ", ".join(sorted(END_CONDITIONS)), boundary)
    return parts[0], parts[1]
