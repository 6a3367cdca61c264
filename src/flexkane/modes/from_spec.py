"""The shape family of a beam's shape specification (a model file's ``shape`` or ``axial_shape``).

Needs no SymPy, except for the family ``expression`` whose functions are SymPy expressions of xi.
"""

from __future__ import annotations

import functools

from ..errors import ModelError
from ..expression_values import field_value
from . import get_family, numeric_option_names

__all__ = ["shape_family", "beam_shape_family", "tip_attachments", "COUNT_KEYS"]

#: The key of a beam's count of functions for each of its shape keys.
COUNT_KEYS = {"shape": "n_modes", "shape_y": "n_modes_y", "shape_z": "n_modes_z",
              "torsion_shape": "n_torsion", "axial_shape": "n_axial"}


def shape_family(spec, path: str, parameters=None):
    """The :class:`~flexkane.modes.ShapeFamily` of a beam's shape specification.

    Numeric options (typed ``roots``, the family's :attr:`~flexkane.modes.ShapeFamily.numeric_options`
    such as ``mass_ratio``) are numbers or expressions of the model's parameters, evaluated here
    with ``parameters``; they give numbers only, never structure, so one derivation serves every
    value (a sweep over a tip mass updates the modes through the modal constants). Expressions of
    ``xi`` given in a model file (family ``expression``) are parsed with the safe expression
    language and may use parameters too. Errors name the key path.

    Parameters
    ----------
    spec : ShapeSpec
        The beam's ``shape`` or ``axial_shape``.
    path : str
        Its key path (``beams.B.shape``).
    parameters : dict of str to float, optional
        Values of the model's parameters by name; without them only literal numbers are accepted.
    """
    parameters = {name: float(value) for name, value in (parameters or {}).items()}

    def number(value, where):
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            return value   # the family reports what it expected
        if not isinstance(value, str):
            return value
        return field_value(value, parameters, path=where)

    options = dict(spec.options)
    if spec.roots is not None:
        roots = spec.roots
        options["roots"] = ([number(r, f"{path}.roots[{i}]") for i, r in enumerate(roots)]
                            if isinstance(roots, (list, tuple)) else roots)
    for option in numeric_option_names(spec.family):
        if option in options and option != "roots":
            options[option] = number(options[option], f"{path}.{option}")
    if spec.family == "expression" and "expressions" in options:
        texts = options["expressions"]
        if not isinstance(texts, list) or not texts:
            raise ModelError(f"{path}.expressions", "a non-empty list of expressions of xi", texts)
        import sympy as sp

        from ..expressions import parse_expression

        from . import XI

        symbols = {name: sp.Symbol(name, real=True) for name in parameters}
        numbers = {symbols[name]: value for name, value in parameters.items()}
        exprs = []
        for i, text in enumerate(texts):
            where = f"{path}.expressions[{i}]"
            expr = parse_expression(text, {**symbols, "xi": XI}, path=where)
            exprs.append(expr.xreplace({s: sp.Float(numbers[s]) for s in expr.free_symbols if s in numbers}))
        options["expressions"] = exprs
    try:
        return get_family(spec.family, **options)
    except ModelError as exc:
        raise ModelError(f"{path}.{exc.path}" if exc.path != "family" else f"{path}.family",
                         exc.expected, exc.given, exc.hint) from None


def tip_attachments(model, beam, parameters=None) -> tuple[str, ...]:
    """Key paths of what ``beam`` carries at its tip: joints with ``station`` on it (a body or a
    beam hangs there), loads, springs and loop joints at a station of it equal to its length.

    Parameters
    ----------
    model : Model
        The model.
    beam : Beam
        One of its beams.
    parameters : dict of str to float, optional
        Values of the model's parameters (stations and lengths may be expressions of them).

    Returns
    -------
    tuple of str
        E.g. ``("joints.elbow.station",)``; empty when nothing is attached at the tip. A station
        short of the tip is not listed: correction shapes are made for the tip only.
    """
    parameters = {name: float(value) for name, value in (parameters or {}).items()}
    path = f"beams.{beam.name}"
    length = field_value(beam.L, parameters, path=f"{path}.L")
    found = []
    attached = [(f"joints.{j.name}.station", j.parent, j.station) for j in model.joints.values()]
    attached += [(f"loads.{a.name}.station", a.body, a.station) for a in model.loads.values()]
    for kind, parts in (("springs", model.springs), ("constraints", model.constraints)):
        for part in parts.values():
            attached += [(f"{kind}.{part.name}.station_{end}", getattr(part, f"body_{end}"),
                          getattr(part, f"station_{end}")) for end in ("a", "b")]
    for where, owner, station in attached:
        if owner != beam.name or station is None:
            continue
        if abs(field_value(station, parameters, path=where) - length) <= 1e-9 * abs(length):
            found.append(where)
    return tuple(found)


#: The use of each of a beam's shape keys.
_KINDS = {"shape": "transverse", "shape_y": "transverse", "shape_z": "transverse", "torsion_shape": "torsion",
          "axial_shape": "axial"}


@functools.lru_cache(maxsize=256)
def _corrected(family, n: int, where: str, kind: str):
    from .static_correction import StaticCorrection

    return StaticCorrection(family, n, where, kind)


def beam_shape_family(model, beam, key: str, parameters=None):
    """The shape family of one of a beam's bases, with the static correction shapes where it
    carries something at its tip (:mod:`flexkane.modes.static_correction`).

    The corrections are added when the beam's ``static_corrections`` is true (the default), the
    beam carries a joint, a load, a spring or a loop joint at its tip (:func:`tip_attachments`)
    and the family has a clamped (bending) or fixed (torsion, axial) root and a free tip; otherwise
    this is :func:`shape_family` of the key.

    Parameters
    ----------
    model : Model
        The model the beam belongs to.
    beam : Beam
        The beam.
    key : str
        ``shape`` or ``axial_shape`` (planar), ``shape_y``, ``shape_z``, ``torsion_shape`` or
        ``axial_shape`` (spatial).
    parameters : dict of str to float, optional
        Values of the model's parameters.
    """
    path = f"beams.{beam.name}.{key}"
    family = shape_family(getattr(beam, key), path, parameters)
    count = getattr(beam, COUNT_KEYS[key])
    if not count or not getattr(beam, "static_corrections", True):
        return family
    from .static_correction import accepts_corrections

    if not accepts_corrections(family, _KINDS[key]) or not tip_attachments(model, beam, parameters):
        return family
    corrected = _corrected(family, int(count), path, _KINDS[key])
    return corrected if corrected.corrections() else family   # every shape spanned already
