"""Which constants of the equations a user may change without deriving them again, which are frozen.

The equations hold every number of a model as a symbol (:mod:`flexkane.model.values`), but not every
symbol is free: the modal constants of a beam (``E_1 = int rho Phi_1 dx``, ``H_11 = int EI Phi_1''^2
dx``, ``Phi_1(L/2)``, eqs. 8.22-8.32) are integrals of the shape functions computed by quadrature
from the beam's length, the roots and options of its shape family, the stations and the load
profiles (:meth:`flexkane.kane.beam_constants.BeamConstants.values`), times one of the beam's
section values: the mass per length ``rho`` (the integrals of ``rho``), the rigidity ``EI`` (``H``),
``EA``, ``GJ``, the rotary inertias. A program that holds the equations without that quadrature (the
exported C, :mod:`flexkane.c_export`) can take the integral as a number frozen at export and
multiply it by the section value, which therefore stays free; changing ``L`` beside frozen
integrals would give a model that is none.

:func:`constant_roles` sorts the constants of a model's equations, and the parameters and field
values they are computed from, into

* **frozen**: every parameter or field value that the integrals of the shape functions are computed
  from (length, shape roots and options, stations, load profiles), directly or through the
  expressions of other parameters (``L = "2*a"`` freezes ``L`` and ``a``); the integrals of the
  shape functions per unit section value (``E_1/rho = int Phi_1 dx``, named so); and a modal
  constant as a whole when it has no section value (``Phi_1(L)``) or its section value is a number
  of the beam or zero (then the parameters of that value are frozen too); their values are those of
  the model;
* **editable**: a parameter whose value is a number (or an expression of no parameter), or a field
  whose value is such a number (``bodies.RB.mass = 2.5``, symbol ``m_RB``), that no frozen value is
  computed from; a change of it is a change of ``--set`` of its key path;
* **derived**: a parameter or field value that is an expression of other parameters
  (``Iz = "mR*(c**2 + d**2)/12"``) and is not frozen, and a modal constant with a section value
  (``E_1 = rho * (E_1/rho)``), recomputed from the editable and frozen entries, as the model's
  evaluator and quadrature do after ``--set`` of one of them (the integrals are linear in the
  section value);
* **inputs**: the control inputs of a model derived with ``control_inputs`` (editable, zero).

By construction no editable entry influences a frozen one.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import sympy as sp

from ..errors import ModelError
from ..expressions import parse_expression, to_float
from ..model.values import symbol_order
from .inputs import input_symbols

__all__ = ["SHAPE_FIELDS", "ConstantRoles", "constant_roles", "section_field"]

#: The fields of a beam (planar or spatial) that the integrals of its shape functions are computed from.
SHAPE_FIELDS = ("L", "shape", "axial_shape", "shape_y", "shape_z", "torsion_shape")
# The section value a modal constant is proportional to, by kind of its specification
# (BeamConstants.values, SpatialBeamConstants.model_values); kinds not listed have none.
_PLANAR_SECTION = {"pair": "rho", "rotary": "rotary_inertia", "H": "EI", "HA": "EA"}
_SPATIAL_SECTION = {"pair": "rho", "polar": "rho_Ip", "Kt": "GJ", "HA": "EA", ("section", "y"): "rho_Iz",
                    ("section", "z"): "rho_Iy", ("Hs", "y"): "EI_z", ("Hs", "z"): "EI_y"}


@dataclass
class ConstantRoles:
    """The constants of a model's equations and the values they come from, by role.

    Attributes
    ----------
    editable : list of sympy.Symbol
        The entries a user may change, in natural order of their names: parameters (their
        symbols), field symbols of a number and control inputs.
    frozen : list of sympy.Symbol
        The integrals per unit section value (``E_1/rho``, symbols of their own), the modal
        constants frozen whole and the parameters and field symbols the integrals are computed
        from, in natural order of their names (some need not be constants of the equations).
    derived : list of (sympy.Symbol, sympy.Expr)
        Each derived parameter, field symbol or modal constant that the equations need, with its
        expression in the editable, frozen and earlier derived symbols, in evaluation order.
    paths : dict of sympy.Symbol to str
        The key path that sets each editable or frozen parameter or field value
        (``parameters.mR``, ``bodies.RB.mass``); control inputs and modal constants have none.
    modal : set of sympy.Symbol
        The modal constants (each one the equations use is in ``frozen`` or in ``derived``).
    per_section : dict of sympy.Symbol to (sympy.Symbol, str, float)
        For each modal constant in ``derived``: the frozen symbol of its integral per unit section
        value (``E_1/rho``), the key path of the section value (``beams.B.rho``) and the value of
        that integral [the unit of the constant over that of the section value].
    factors : dict of sympy.Symbol to sympy.Expr
        For each modal constant in ``derived``: its section value, an expression of the parameters.
    """

    editable: list
    frozen: list
    derived: list
    paths: dict
    modal: set
    per_section: dict
    factors: dict


def section_field(consts, spec: tuple) -> str | None:
    """The beam field (``rho``, ``EI`` ...) a modal constant of specification ``spec`` is proportional
    to, None for one that has none (a value at a station, a load integral)."""
    table = _SPATIAL_SECTION if hasattr(consts, "model_values") else _PLANAR_SECTION
    return table.get(spec[0]) or (table.get((spec[0], spec[1])) if len(spec) > 1 else None)


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
    values = eom.constant_values(model)
    # the parameters and field symbols the integrals of the shape functions are computed from, and
    # the modal constants proportional to a section value of parameters
    sources: set = set()
    per_section: dict = {}
    factors: dict = {}
    for name, consts in eom.kinematics.constants.items():
        if not consts.used:
            continue
        beam = model.beams[name]
        for key in SHAPE_FIELDS:
            path = f"beams.{name}.{key}"
            if path in by_path:
                sources.add(by_path[path])
            for text in _strings(getattr(beam, key, None)):
                sources |= {params[n] for n in _names(text, params)}
        for symbol, spec in consts.used.items():
            if spec[0] == "station":
                sources |= sp.sympify(spec[3]).free_symbols
            elif spec[0] == "load":
                sources |= sp.sympify(spec[2]).free_symbols
            key = section_field(consts, spec)
            text = getattr(beam, key) if key else None
            if text is None:
                continue
            path = f"beams.{name}.{key}"
            factor = parse_expression(text, params, path=path)
            try:
                value = to_float(factor, values, path=path) if factor.free_symbols else 0.0
            except ModelError:
                value = 0.0
            if value == 0.0:       # a number of the beam, or zero: the whole constant is frozen
                sources |= factor.free_symbols
                continue
            per_section[symbol] = (sp.Symbol(f"{symbol.name}/{key}"), path, float(values[symbol]) / value)
            factors[symbol] = factor
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
        if s in per_section:
            for d in sorted(factors[s].free_symbols, key=symbol_order):
                need(d)
            derived_needed.append((s, factors[s] * per_section[s][0]))
            continue
        if s in modal or s in frozen_values:
            continue
        if s in expressions:
            need(s)
        else:
            editable.add(s)    # a control input, or a constant of a hand-made equation set
    paths = {s: texts[s][0] for s in (*editable, *frozen_values) if s in texts}
    used = set(eom.constants)     # a beam may record constants the equations lost on simplification
    per_section = {s: v for s, v in per_section.items() if s in used}
    factors = {s: f for s, f in factors.items() if s in used}
    frozen = ((modal & used) - set(per_section)) | frozen_values | {u for u, _, _ in per_section.values()}
    return ConstantRoles(editable=sorted(editable, key=symbol_order), frozen=sorted(frozen, key=symbol_order),
                         derived=derived_needed, paths=paths, modal=modal, per_section=per_section,
                         factors=factors)


def _names(text: str, params: dict) -> set[str]:
    """The parameters an expression names (none for a text that is not an expression, e.g. a family)."""
    from ..expression_syntax import NeedsSymbolic, expression_names

    try:
        return expression_names(text) & set(params)
    except (NeedsSymbolic, ValueError, SyntaxError):
        return set(params) & {text.strip()}
