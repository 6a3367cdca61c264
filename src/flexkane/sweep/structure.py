"""Group the variants of a sweep by the structure of their equations: derive once per group.

What is structure is decided by :func:`flexkane.derivation_cache.structure_signature` (the same
rule as the derivation cache). Computing it for every variant would copy every variant's model, so
variants are first gathered cheaply by what their varied keys can change:

* parameters and initial conditions change numbers only;
* a constant field (:data:`flexkane.derivation_cache.VALUE_FIELDS`: a mass, ``EI``, a stiffness)
  changes the equations only by its class: literal zero, the name of a parameter, or any other
  value;
* any other field (``n_modes``, a beam length given as a number, a station, a time law) is taken
  by value.

Then one signature per gathered set decides, and sets with equal signatures are merged.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

from ..derivation_cache import VALUE_FIELDS, cached_derive, structure_signature
from ..errors import ModelError
from .variants import Variant, key_kind

__all__ = ["StructureGroup", "group_by_structure", "derive_equations"]


@dataclass
class StructureGroup:
    """Variants that share one derivation and one compiled module.

    Attributes
    ----------
    signature : str
        :func:`~flexkane.derivation_cache.structure_signature` of its variants.
    variants : list of Variant
        In sweep order.
    eom : EquationsOfMotion or None
        Set once derived.
    key : str
        Cache key of the compiled module (set once compiled).
    derive_time : float
        Seconds spent deriving (or loading) and compiling [s].
    """

    signature: str
    variants: list = field(default_factory=list)
    eom: object = None
    key: str = ""
    derive_time: float = 0.0


def _value_class(value, parameters) -> str:
    """How the derivation sees a constant field: zero, a parameter's symbol, or a symbol of its own."""
    if isinstance(value, (int, float)) and not isinstance(value, bool) and value == 0:
        return "zero"
    if isinstance(value, str) and value.strip() in parameters:
        return "parameter " + value.strip()
    return "symbol"


def _token(base, key: str, value) -> str:
    """What a varied key's value can change in the equations (see the module docstring)."""
    if key_kind(base, key) in ("parameter", "initial"):
        return "number"
    if any(pattern.fullmatch(key) for pattern in VALUE_FIELDS):
        return _value_class(value, base.parameters)
    return "value " + repr(value)


def group_by_structure(variants: list[Variant]) -> list[StructureGroup]:
    """Split variants into groups of identical equations.

    Parameters
    ----------
    variants : list of Variant
        In sweep order.

    Returns
    -------
    list of StructureGroup
        In order of first appearance, not yet derived.
    """
    gathered: dict[tuple, list] = {}
    for variant in variants:
        token = tuple(_token(variant.base, key, value) for key, value in variant.assignments)
        gathered.setdefault(token, []).append(variant)
    groups: dict[str, StructureGroup] = {}
    for token, members in gathered.items():
        try:
            signature = structure_signature(members[0].model)
        except (ModelError, ValueError, TypeError):  # the derivation will say what is wrong
            signature = "unusable " + repr(token)
        groups.setdefault(signature, StructureGroup(signature)).variants.extend(members)
    for group in groups.values():
        group.variants.sort(key=lambda v: v.index)
    return list(groups.values())


def derive_equations(model):
    """Kane's equations of ``model``, from the on-disk derivation cache when they are there.

    Returns
    -------
    eom : EquationsOfMotion
    seconds : float
        Time taken [s].
    """
    start = time.perf_counter()
    eom = cached_derive(model)
    return eom, time.perf_counter() - start
