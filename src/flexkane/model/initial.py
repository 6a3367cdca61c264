"""Initial values of every generalized coordinate and speed of a model, as numbers.

The ``[initial]`` table gives coordinates and speeds by name; the others start at 0, except the
Euler parameters of a spatial spherical or free joint, which start at the identity (``e0 = 1``). Such
a joint's orientation may be given as a table under the key ``q_<joint>``
(:func:`flexkane.model.coordinates.orientation_key`), ``{ axis = [...], angle = ... }`` or
``{ sequence = "zyx", angles = [...] }``, converted to Euler parameters here; or as its four Euler
parameters by name, normalized to unit norm (with a warning when their norm was off by more than
:data:`NORM_TOLERANCE`); four zeros, or some of the four without the others, are refused.

``equilibrium = true`` (:data:`~flexkane.model.coordinates.EQUILIBRIUM_KEY`) asks a run to start
from the static equilibrium instead (:func:`~flexkane.model.coordinates.starts_at_equilibrium`; solved by
:mod:`flexkane.analysis.equilibrium_start`), the values given here being where its search starts.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import ModelError
from .coordinates import coordinate_names, orientation_key
from .field_values import FieldValues
from .file_layout import ORIENTATION_FORMS
from .orientation import normalized, orientation_quaternion

__all__ = ["InitialValues", "initial_values", "NORM_TOLERANCE"]

#: Largest departure of given Euler parameters' norm from 1 that is normalized without a warning [-].
NORM_TOLERANCE = 1e-9


@dataclass
class InitialValues:
    """The initial value of every coordinate and speed of a model.

    Attributes
    ----------
    values : dict of str to float
        By coordinate or speed name, in state order (coordinates, then speeds) [their units].
    warnings : list of str
        Notes on values that were changed (Euler parameters normalized).
    """

    values: dict[str, float] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)


def initial_values(model, fields: FieldValues | None = None) -> InitialValues:
    """Every coordinate and speed's initial value, orientations converted to Euler parameters.

    Parameters
    ----------
    model : Model
        A model whose parts and joint tree are valid.
    fields : FieldValues, optional
        The model's evaluator of field values (made from the model when omitted).

    Returns
    -------
    InitialValues

    Raises
    ------
    ModelError
        Naming the ``initial.<key>``: a value that is not a finite number or expression of the
        parameters, an orientation table that is not valid, an orientation given both as a table
        and by Euler parameters, some Euler parameters of a joint without the others, or four zeros.
    """
    fields = FieldValues(model) if fields is None else fields
    coordinates = coordinate_names(model)
    initial = model.initial
    out = InitialValues()
    euler: dict[str, list] = {}
    names = {c.q for c in coordinates} | {c.u for c in coordinates if c.u is not None}
    for coord in coordinates:
        if coord.role in ("e0", "e1", "e2", "e3"):
            euler.setdefault(coord.owner, []).append(coord)
            continue
        out.values[coord.q] = _number(initial, coord.q, fields)
    for joint, coords in euler.items():
        key = orientation_key(joint)
        given = [c.q for c in coords if c.q in initial]
        table = initial.get(key) if key not in names else None
        if table is not None:
            if given:
                raise ModelError(f"initial.{given[0]}", f"no Euler parameter of joint {joint!r} when its "
                                 f"orientation is given as a table (initial.{key})", initial[given[0]])
            if not isinstance(table, dict) and not hasattr(table, "sequence"):
                raise ModelError(f"initial.{key}", f"the orientation of joint {joint!r} as {ORIENTATION_FORMS}",
                                 table)
            e = orientation_quaternion(table, f"initial.{key}", fields)
        elif given:
            if len(given) != 4:
                missing = [c.q for c in coords if c.q not in initial]
                raise ModelError(f"initial.{missing[0]}", f"all four Euler parameters of joint {joint!r} "
                                 f"({', '.join(c.q for c in coords)}) or none (the identity), or the "
                                 f"orientation as a table initial.{key}", None,
                                 f"missing: {', '.join(missing)}", show_given=False)
            raw = np.array([_number(initial, c.q, fields) for c in coords])
            try:
                e, norm = normalized(raw)
            except ValueError:
                raise ModelError(f"initial.{coords[0].q}", f"Euler parameters of joint {joint!r} with a non-zero "
                                 "norm (they are normalized to 1)", "four zeros") from None
            if abs(norm - 1.0) > NORM_TOLERANCE:
                out.warnings.append(f"initial Euler parameters of joint {joint!r} had norm {norm:.12g}; "
                                    "normalized to 1")
        else:
            e = np.array([1.0, 0.0, 0.0, 0.0])
        for c, value in zip(coords, e):
            out.values[c.q] = float(value)
    out.values = {c.q: out.values[c.q] for c in coordinates}   # state order
    for coord in coordinates:
        if coord.u is not None:
            out.values[coord.u] = _number(initial, coord.u, fields)
    return out


def _number(initial: dict, name: str, fields: FieldValues) -> float:
    if name not in initial:
        return 0.0
    value = initial[name]
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ModelError(f"initial.{name}", "a number or an expression string (initial value)", value)
    return fields.value(value, f"initial.{name}", what="initial value")
