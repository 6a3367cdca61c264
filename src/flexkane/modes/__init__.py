"""Shape functions of flexible links and their modal integrals.

``get_family(name, **options)`` returns a :class:`ShapeFamily` (contract in
:mod:`flexkane.modes.base`); :mod:`flexkane.modes.integrals` turns a family into the modal
constants of eqs. 8.22 and 8.32, and :mod:`flexkane.modes.free_vibration` solves eqs. 8.3 and 8.5
for a beam on a fixed base.

Families (``get_family`` names and options):

===========================  ==========================================================
``clamped-free``             the chapter's cantilever, eqs. 8.4 and 8.6; option ``roots``
                             (``lambda_i`` as typed, e.g. ``[1.875]``)
``pinned-free``              elastic modes; rigid rotation about the pin in ``rigid_modes``
``pinned-pinned``            ``sqrt(2) sin(i pi xi)``
``clamped-pinned``           ``tan l = tanh l``
``clamped-clamped``          ``cos l cosh l = 1``
``free-free``                elastic modes; two rigid modes in ``rigid_modes``
``clamped-free-tip-mass``    options ``mass_ratio = M/(rho L)``, ``inertia_ratio = J/(rho L^3)``
``polynomial``               Rayleigh-Ritz ``xi^(k+1)``, ``k = 1..n``
``torsion-polynomial``       Rayleigh-Ritz ``xi^k``, ``k = 1..n``, torsion (fixed root)
``axial-polynomial``         Rayleigh-Ritz ``xi^k``, ``k = 1..n``, axial deformation
``expression``               options ``expressions`` (SymPy, in ``xi``), ``boundary``
``axial-fixed-free``         ``sqrt(2) sin((2k-1) pi xi / 2)``, axial deformation
``axial-fixed-fixed``        ``sqrt(2) sin(k pi xi)``, axial deformation
``torsion-clamped-free``     ``sqrt(2) sin((2k-1) pi xi / 2)``, torsion
``torsion-clamped-clamped``  ``sqrt(2) sin(k pi xi)``, torsion
``torsion-free-free``        ``sqrt(2) cos(k pi xi)``, torsion; rigid rotation in ``rigid_modes``
===========================  ==========================================================
"""

from __future__ import annotations

from typing import Any

from ..errors import ModelError
from .axial import AxialFixedFixed, AxialFixedFree
from .base import RigidMode, ShapeFamily
from .expression import Expression
from .polynomial import AxialPolynomial, Polynomial, TorsionPolynomial
from .tip_mass import ClampedFreeTipMass
from .torsion import TorsionClampedClamped, TorsionClampedFree, TorsionFreeFree
from .transverse import (ClampedClamped, ClampedFree, ClampedPinned, FreeFree, PinnedFree,
                         PinnedPinned)

__all__ = ["get_family", "family_names", "numeric_option_names", "ShapeFamily", "RigidMode", "XI"]

_FAMILIES: dict[str, type[ShapeFamily]] = {
    cls.name: cls for cls in (ClampedFree, PinnedFree, PinnedPinned, ClampedPinned, ClampedClamped,
                              FreeFree, ClampedFreeTipMass, Polynomial, Expression,
                              AxialFixedFree, AxialFixedFixed, TorsionClampedFree, TorsionClampedClamped,
                              TorsionFreeFree, TorsionPolynomial, AxialPolynomial)
}


def family_names() -> tuple[str, ...]:
    """Names accepted by :func:`get_family`, in the order of the table above."""
    return tuple(_FAMILIES)


def numeric_option_names(name: str) -> tuple[str, ...]:
    """The numeric options of family ``name`` (empty for an unknown name).

    In a model file these are numbers or expressions of the parameters; they change the modal
    constants, never the structure of the equations.
    """
    cls = _FAMILIES.get(name) if isinstance(name, str) else None
    return cls.numeric_options if cls is not None else ()


def get_family(name: str, **options: Any) -> ShapeFamily:
    """Return the family of shape functions called ``name``.

    Parameters
    ----------
    name : str
        One of :func:`family_names`.
    **options
        Options of that family (module docstring); any other option is an error.

    Returns
    -------
    ShapeFamily
        A new family object; equal names and options give equal (and equally hashed) families.

    Raises
    ------
    ModelError
        For an unknown name, an unknown option or an invalid option value.
    """
    cls = _FAMILIES.get(name) if isinstance(name, str) else None
    if cls is None:
        raise ModelError("family", "one of " + ", ".join(_FAMILIES), name)
    accepted = cls.option_names
    for option in options:
        if option not in accepted:
            expected = ("options among " + ", ".join(accepted)) if accepted else "no options"
            raise ModelError(option, f"{expected} for family {name!r}", options[option])
    return cls(**options)


def __getattr__(name: str):
    """``XI``, the SymPy symbol of the abscissa x / L, is made on first use (SymPy is not loaded before)."""
    if name == "XI":
        from .expression import _xi

        return _xi()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
