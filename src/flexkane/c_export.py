"""Export a model's equations as standalone C: ``flexkane export MODEL --c DIR``.

Writes ``<prefix>.h`` and ``<prefix>.c`` (C99, nothing beyond ``math.h``) to a directory: the
right-hand side ``<prefix>_rhs(t, y, p, dy)`` of the first-order system, the mass matrix, the
forcing, the kinematic equations, the outputs and the ``L D L^T`` solve of ``M u' = f``, with the
order of the state, of the parameters ``p`` (name, unit, what each is) and of the outputs documented
in the header, and the model's parameters and initial state as default arrays, so that a controller
or another integrator can call them without Python.

Every entry of ``p`` is a value a caller may change, a change being that of ``--set`` of it: the
integrals of the beams' shape functions (quadratures) and every parameter they are computed from
are frozen at export, listed apart and held in a read-only array; a modal constant proportional to
a section value that is a parameter (``E_1 = rho * (E_1/rho)``, ``H_11 = EI * (H_11/EI)``) and a
parameter that is an expression of others are computed from ``p`` on every call
(:mod:`flexkane.kane.frozen_constants`). The code is generated from the same compact
equations as the Numba module (:mod:`flexkane.numerics.c_source`); drivers and closed loops are
part of those equations.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

from ._version import __version__
from .errors import ModelError
from .model import Model

__all__ = ["export_c", "c_constants", "constant_descriptions"]


def constant_descriptions(eom, model: Model, symbols=None) -> tuple[list[str], list[str]]:
    """Unit and description of every constant of ``eom``, in the order of ``eom.constants``.

    Parameters
    ----------
    eom : EquationsOfMotion
    model : Model
        A model of the structure of ``eom`` (the units of its fields are those validation checks).
    symbols : sequence of sympy.Symbol, optional
        The constants to describe instead (also parameters and field symbols that are no constant
        of the equations, e.g. those a derived constant is computed from).

    Returns
    -------
    units : list of str
        The unit of a beam's modal constant (as the report gives it), of a field of the model (as
        validation checks it), of a parameter that fields of one unit name; ``""`` where the model
        does not say (a parameter used only in expressions of t).
    notes : list of str
        What the constant is: ``beam B: <definition>``, ``parameter`` (with its expression when it
        has one, and the fields that name it) or the key path of the field it stands for.
    """
    from .expression_syntax import NeedsSymbolic, expression_names
    from .model.parameter_units import field_values, inferred_units
    from .report import _definition

    fields = field_values(model)   # path -> (value, unit)
    field_units = {path: unit for path, (_, unit) in fields.items()}
    named: dict = {}     # parameter -> {path: unit} of the fields that name it
    used_in: dict = {}   # parameter -> {path: unit} of the expressions using it
    for path, (value, unit) in fields.items():
        if isinstance(value, str) and value.strip() in model.parameters:
            named.setdefault(value.strip(), {})[path] = unit
        with contextlib.suppress(NeedsSymbolic):
            for name in expression_names(value) & set(model.parameters):
                used_in.setdefault(name, {})[path] = unit
    # a parameter defined by an expression has the unit of that expression: Jc1 = J1 - m1*(L1/2)**2
    # [kg m^2] gives J1 its unit when no field names J1 (the units the fields fix alone are kept:
    # a number in such an expression, b = a/4 - 0.025, may leave the inference undecided)
    inferred = inferred_units(fields, model.parameters,
                              equal=[(n, v, False) for n, v in model.parameters.items() if isinstance(v, str)])
    inferred.update(inferred_units(fields, model.parameters))
    for other, value in model.parameters.items():   # J1 in Jc1 = J1 - m1*(L1/2)**2: "in parameters.Jc1"
        kinds = set(named.get(other, {}).values())
        unit = kinds.pop() if len(kinds) == 1 else inferred.get(other, "")
        with contextlib.suppress(NeedsSymbolic):
            for name in expression_names(value) & set(model.parameters):
                used_in.setdefault(name, {})[f"parameters.{other}"] = unit
    modal = eom.beam_constant_symbols()
    defined = eom.chain.symbols.definitions
    units, notes = [], []
    for s in (eom.constants if symbols is None else symbols):
        if s in modal:
            beam, consts = modal[s]
            definition, unit = _definition(consts.used[s])
            units.append(unit)
            notes.append(f"beam {beam}: {definition}" if definition else f"beam {beam}")
        elif s.name in model.parameters:
            given = model.parameters[s.name]
            uses = named.get(s.name, {})
            kinds = set(uses.values())
            unit = kinds.pop() if len(kinds) == 1 else "" if kinds else inferred.get(s.name, "")
            units.append(unit)
            laws = sorted(path for path in used_in.get(s.name, ()) if path not in uses)
            notes.append("parameter" + ("" if isinstance(given, (int, float)) else f" = {given}")
                         + (f", the value of {_listed(sorted(uses))}" if uses else "")
                         + (f", in {_listed(laws)}" if laws and not uses else "")
                         + ("" if unit else "; " + _no_unit(s.name, kinds, used_in.get(s.name, {}))))
        elif s in defined:
            path, given = defined[s]
            units.append(field_units.get(path, ""))
            notes.append(f"{path} = {given}")
        else:
            units.append("")
            notes.append("constant")
    return units, notes


def _no_unit(name: str, kinds: set, used_in: dict) -> str:
    """Why a parameter has no unit in the header."""
    if kinds:
        return "no unit: the fields that name it have different units"
    if not used_in:
        return "no unit: no field of the model uses it"
    return ("no unit: its uses do not fix one (" + _listed([f"{p} [{u or '?'}]" for p, u in sorted(used_in.items())])
            + " leave it free or disagree)")


def _listed(paths: list, limit: int = 3) -> str:
    return ", ".join(paths[:limit]) + (f" and {len(paths) - limit} more" if len(paths) > limit else "")


def c_constants(eom, model: Model) -> tuple[list, list, list]:
    """The parameters p, the frozen values and the derived constants of the exported C.

    Parameters
    ----------
    eom : EquationsOfMotion
    model : Model
        A model of the structure of ``eom``: its values and parameter expressions.

    Returns
    -------
    editable, frozen, derived : list of flexkane.numerics.c_source.CConstant
        The entries of ``p`` (what a caller may change; a change is that of ``--set`` of the
        parameter or field), the values frozen at export (the integrals of the shape functions,
        per unit section value where a constant has one, and every value they are computed from)
        and the constants computed from those on every call, in evaluation order
        (:func:`flexkane.kane.frozen_constants.constant_roles`).
    """
    from .kane.frozen_constants import constant_roles
    from .model.parameter_units import field_values
    from .numerics.c_source import CConstant

    roles = constant_roles(eom, model)
    values = eom.constant_values(model)
    per_unit = {u: (s, path) for s, (u, path, _) in roles.per_section.items()}
    values.update({u: value for u, _, value in roles.per_section.values()})
    listed = [*roles.editable, *roles.frozen, *(s for s, _ in roles.derived)]
    units, notes = constant_descriptions(eom, model, [per_unit.get(s, (s,))[0] for s in listed])
    unit, note = dict(zip(listed, units)), dict(zip(listed, notes))
    field_units = {path: u for path, (_, u) in field_values(model).items()}
    for u, (s, path) in per_unit.items():   # E_1/rho [m]: the integral per unit section value
        unit[u] = _quotient(unit[u], field_units.get(path, ""))
        note[u] = f"{note[u]}, per unit {path}"
    for s in roles.frozen:
        if s in roles.paths:
            note[s] += "; the integrals of the shape functions are computed from it"
    given = {s: text for s, (_, text) in eom.chain.symbols.definitions.items()}
    given.update({eom.chain.symbols.parameters[n]: text for n, text in model.parameters.items()})
    for s, (u, _, _) in roles.per_section.items():     # E_1 = ro * (E_1/rho)
        factor = str(roles.factors[s])
        given[s] = f"{factor if roles.factors[s].is_Symbol else f'({factor})'} * ({u.name}): {note[s]}"

    def entry(s, expression=None):
        return CConstant(s, unit[s], str(given[s]) if expression is not None else note[s], float(values[s]),
                         expression)
    return ([entry(s) for s in roles.editable], [entry(s) for s in roles.frozen],
            [entry(s, e) for s, e in roles.derived])


def _quotient(numerator: str, denominator: str) -> str:
    """The unit ``numerator / denominator`` (``"kg"``, ``"kg/m"`` -> ``"m"``); ``""`` if either is unknown."""
    from .model.parameter_units import format_unit, parse_unit

    a, b = (parse_unit(u) if u else None for u in (numerator, denominator))
    if a is None or b is None:
        return ""
    out = dict(a)
    for name, exponent in b.items():
        out[name] = out.get(name, 0) - exponent
    return format_unit({name: e for name, e in out.items() if e}) or "-"


def export_c(model, directory, *, prefix: str | None = None, force: bool = False, cache_dir=None,
             flag: str = "directory") -> list[Path]:
    """Write the model's equations as C99: ``<prefix>.h`` and ``<prefix>.c`` in ``directory``.

    Parameters
    ----------
    model : Model
        A validated model (:func:`flexkane.load_model`, :func:`flexkane.builtin_model`); its
        parameters give the default constants and initial state of the files.
    directory : path-like
        The folder to write to (created if missing); nothing is written outside it.
    prefix : str, optional
        Prefix of every global name and of the file names; default: the model's name made a C
        identifier (``falling-beam`` -> ``falling_beam``).
    force : bool
        Write into a directory that holds files already (files of the same name are replaced,
        others kept); without it such a directory is refused.
    cache_dir : path-like, optional
        Root of the cache of derived equations.
    flag : str
        How messages name the directory (the command line says ``--c``).

    Returns
    -------
    list of pathlib.Path
        The header and the source file written.

    Raises
    ------
    ModelError
        For a model that is not a Model, a prefix that is not a C identifier, a directory that
        holds files (without ``force``) or cannot be created, or equations C cannot express.
    """
    from .atomic import atomic_write_text, directory_syncs_batched, prepare_output_dir
    from .derivation_cache import Derivation
    from .numerics.c_source import C_RESERVED, CModelInfo, c_identifier, c_sources, check_prefix
    from .start_state import start_state

    if not isinstance(model, Model):
        raise ModelError("model", "a flexkane Model (flexkane.load_model, flexkane.builtin_model)",
                         type(model).__name__)
    if prefix is None:
        prefix = c_identifier(model.name)
        prefix = prefix if prefix not in C_RESERVED else f"{prefix}_model"
    else:
        try:
            check_prefix(prefix)
        except ValueError as exc:
            raise ModelError("prefix", str(exc), prefix) from None
    model.validate()
    derivation = Derivation(model, cache_dir)
    eom = derivation.eom
    manifest = derivation.manifest
    y0 = start_state(derivation, model).state   # [initial], or the static equilibrium it asks for
    unit_of = manifest["units"]
    outputs = getattr(eom, "compact", eom).outputs
    editable, frozen, derived = c_constants(eom, model)
    info = CModelInfo(model_name=model.name, editable=editable, frozen=frozen, derived=derived,
                      y0=[float(v) for v in y0],
                      state_units=[unit_of.get(n, "") for n in manifest["state_names"]],
                      output_units=[unit_of.get(n, "") for n in outputs], version=__version__,
                      dimensions=model.dimensions)
    try:
        header, source = c_sources(eom, prefix, info)
    except ValueError as exc:
        raise ModelError("model", "equations that C99 with math.h can express", model.name, str(exc)) from None
    try:
        out = prepare_output_dir(directory, force=force)
    except ModelError as exc:
        raise ModelError(flag, exc.expected, exc.given, exc.hint) from None
    with directory_syncs_batched():
        return [atomic_write_text(out / f"{prefix}.h", header), atomic_write_text(out / f"{prefix}.c", source)]
