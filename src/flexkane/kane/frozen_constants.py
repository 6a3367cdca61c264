"""Which constants of the equations a user may change without deriving them again, which are frozen.

The equations hold every number of a model as a symbol (:mod:`flexkane.model.values`), but not every
symbol is free: the modal constants of a beam (``E_1 = int rho Phi_1 dx``, ``H_11 = int EI Phi_1''^2
dx``, ``Phi_1(L/2)``, eqs. 8.22-8.32) are integrals of the shape functions computed by quadrature
from the beam's length, mass per length, rigidities, the roots of its shape family, the stations and
the load profiles (:meth:`flexkane.kane.beam_constants.BeamConstants.values`). A program that holds
the equations without that quadrature (the exported C, :mod:`flexkane.c_export`) can only take them
as numbers frozen at export; changing ``L`` beside them would give a model that is none.

:func:`constant_roles` sorts the constants of a model's equations, and the parameters and field
values they are computed from, into

* **frozen**: every modal constant, and every parameter or field value that one of them is
  computed from, directly or through the expressions of other parameters (``L = "2*a"`` freezes
  ``L`` and ``a``); their values are those of the model;
* **editable**: a parameter whose value is a number (or an expression of no parameter), or a field
  whose value is such a number (``bodies.RB.mass = 2.5``, symbol ``m_RB``), that no frozen constant
  is computed from; a change of it is a change of ``--set`` of its key path;
* **derived**: a parameter or field value that is an expression of other parameters
  (``Iz = "mR*(c**2 + d**2)/12"``) and is not frozen, recomputed from the editable and frozen
  entries, as the model's evaluator does after ``--set`` of one of them;
* **inputs**: the control inputs of a model derived with ``control_inputs`` (editable, zero).

By construction no editable entry influences a frozen one.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import sympy as sp

from ..expressions import parse_expression
from ..model.values import symbol_order
from .inputs import input_symbols

__all__ = ["MODAL_CONSTANT_FIELDS", "ConstantRoles", "constant_roles"]

#: The fields of a beam (planar or spatial) that its modal constants are computed from.
MODAL_CONSTANT_FIELDS = ("L", "EI", "rho", "EA", "rotary_inertia", "shape", "axial_shape", "EI_y", "EI_z",
                         "shape_y", "shape_z", "GJ", "rho_Ip", "torsion_shape", "rho_Iy", "rho_Iz")


@dataclass
class ConstantRoles:
    """The constants of a model's equations and the values they come from, by role.

    Attributes
    ----------
    editable : list of sympy.Symbol
        The entries a user may change, in natural order of their names: parameters (their
        symbols), field symbols of a number and control inputs.
    frozen : list of sympy.Symbol
        Modal constants and the parameters and field symbols they are computed from, in natural
        order of their names (some need not be constants of the equations, e.g. ``rho``).
    derived : list of (sympy.Symbol, sympy.Expr)
        Each derived parameter or field symbol that the equations need, with its expression in
        the editable, frozen and earlier derived symbols, in evaluation order.
    paths : dict of sympy.Symbol to str
        The key path that sets each editable or frozen parameter or field value
        (``parameters.mR``, ``bodies.RB.mass``); control inputs and modal constants have none.
    modal : set of sympy.Symbol
        The modal constants (a subset of ``frozen``).
    """

    editable: list
    frozen: list
    derived: list
    paths: dict
    modal: set


def _strings(value) -> list[str]:
    """Every text inside a field (a dataclass, table or list of them, recursively)."""
    if isinstance(value, str):
        return [value]
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return [s for f in dataclasses.fields(value) for s in _strings(getattr(value, f.name))]
    if isinstance(value, dict):
        return [s for v in value.values() for s in _strings(v)]
    if isinstance(value, (list, tuple)):
        return [s for v in value for s in _strings(v)]
    return []


def constant_roles(eom, model=None) -> ConstantRoles:
    """Sort the constants of ``eom`` and the values they come from into editable, frozen and derived.

    Parameters
    ----------
    eom : EquationsOfMotion
    model : Model, optional
        A model of the structure of ``eom`` (default: the derived one); its parameter
        expressions decide which parameters are derived.

    Returns
    -------
    ConstantRoles
        See the module docstring.
    """
    model = model or eom.model
    symbols = eom.chain.symbols
    params = dict(symbols.parameters)                         # name -> Symbol, every parameter
    definitions = dict(symbols.definitions)                   # Symbol -> (path, value)
    by_path = {path: s for s, (path, _) in definitions.items()}
    # the expression of every parameter and field symbol, in the parameters' symbols
    texts = {params[name]: (f"parameters.{name}", value) for name, value in model.parameters.items()}
    texts.update(definitions)
    expressions = {s: parse_expression(value, params, path=path) for s, (path, value) in texts.items()}
    depends = {s: expr.free_symbols & set(params.values()) for s, expr in expressions.items()}

    modal = set(eom.beam_constant_symbols())
    # the parameters and field symbols the modal constants are computed from
    sources: set = set()
    for name, consts in eom.kinematics.constants.items():
        if not consts.used:
            continue
        beam = model.beams[name]
        for key in MODAL_CONSTANT_FIELDS:
            path = f"beams.{name}.{key}"
            if path in by_path:
                sources.add(by_path[path])
            for text in _strings(getattr(beam, key, None)):
                sources |= {params[n] for n in _names(text, params)}
        for spec in consts.used.values():
            if spec[0] == "station":
                sources |= sp.sympify(spec[3]).free_symbols
            elif spec[0] == "load":
                sources |= sp.sympify(spec[2]).free_symbols
    frozen_values: set = set()
    stack = [s for s in sources if s in expressions]
    while stack:
        s = stack.pop()
        if s not in frozen_values:
            frozen_values.add(s)
            stack += list(depends[s])

    inputs = list(input_symbols(eom.chain).values())
    editable, derived_needed = set(inputs), []
    seen: set = set()

    def need(s):   # a value the C code computes: editable, frozen or derived (after what it uses)
        if s in seen or s in frozen_values or s not in expressions:
            return
        seen.add(s)
        if not depends[s]:
            editable.add(s)
            return
        for d in sorted(depends[s], key=symbol_order):
            need(d)
        derived_needed.append((s, expressions[s]))

    for s in eom.constants:
        if s in modal or s in frozen_values:
            continue
        if s in expressions:
            need(s)
        else:
            editable.add(s)    # a control input, or a constant of a hand-made equation set
    paths = {s: texts[s][0] for s in (*editable, *frozen_values) if s in texts}
    return ConstantRoles(editable=sorted(editable, key=symbol_order),
                         frozen=sorted(modal | frozen_values, key=symbol_order),
                         derived=derived_needed, paths=paths, modal=modal)


def _names(text: str, params: dict) -> set[str]:
    """The parameters an expression names (none for a text that is not an expression, e.g. a family)."""
    from ..expression_syntax import NeedsSymbolic, expression_names

    try:
        return expression_names(text) & set(params)
    except (NeedsSymbolic, ValueError, SyntaxError):
        return set(params) & {text.strip()}
