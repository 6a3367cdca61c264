"""Kane's dynamical equations ``F*_r + F_r = 0`` (eq. 8.36) as ``M(q, t) u' = f(q, u, t)``.

:func:`derive` composes the stages: chain (coordinates, kinematic equations) -> kinematics ->
generalized inertia forces (eq. 8.22) -> generalized active forces (eqs. 8.28-8.35) -> equations.
Prescribed joint coordinates (drivers) are substituted at the end; the generalized force each driver
must supply is kept as an output.
"""

from __future__ import annotations

import math

import numpy as np
import sympy as sp

from ..model import Model
from ..model.paths import get_value
from .active import generalized_active_forces
from .chain import Chain, build_chain
from .inertia import InertiaForces, generalized_inertia_forces
from .kinematics import Kinematics
from .outputs import output_expressions

__all__ = ["EquationsOfMotion", "derive"]


class EquationsOfMotion:
    """Kane's equations of a chain, ready to be printed, compiled or linearized.

    ``mass_matrix * u' = forcing`` with ``q' = qdot``. Attribute names of the symbolic matrices are
    SymPy's (``mass_matrix``, ``forcing``), so they can be compared with ``KanesMethod``.

    Attributes
    ----------
    model : Model
    chain : Chain
    kinematics : Kinematics
    t : sympy.Symbol
    q : list of sympy.Symbol
        State coordinates (coordinates prescribed by a driver are not among them).
    u : list of sympy.Symbol
        Free generalized speeds.
    ud : list of sympy.Symbol
        Symbols of u'.
    qdot : sympy.Matrix, shape (len(q), 1)
    mass_matrix : sympy.Matrix, shape (len(u), len(u))
    forcing : sympy.Matrix, shape (len(u), 1)
    F_r_star : list of sympy.Expr
        Generalized inertia forces (eq. 8.22) for every speed of the chain, drivers not substituted.
    F_r : dict of str to list of sympy.Expr
        Generalized active forces by source (eq. 8.35).
    all_speeds : list of sympy.Symbol
        The speeds r of ``F_r_star`` and ``F_r``.
    outputs : dict of str to sympy.Expr
        Energy, positions, tip deflections, driver efforts ... (may contain u').
    constants : list of sympy.Symbol
        Every symbol of the equations and outputs other than t, q, u, u'; the parameter vector p.
    """

    def __init__(self, chain: Chain, kin: Kinematics, inertia: InertiaForces, active: dict):
        self.model = chain.model
        self.chain = chain
        self.kinematics = kin
        self.t = chain.t
        self.all_speeds = list(chain.u)
        self.F_r_star = inertia.F_r_star(chain.ud)
        self.F_r = active
        self._inertia = inertia
        coords = chain.coordinates
        subs = {}
        for c in coords:
            if c.driver == "coordinate":
                subs[c.q] = c.law
                subs[c.u] = sp.diff(c.law, chain.t)
                subs[chain.ud[c.u]] = sp.diff(c.law, chain.t, 2)
            elif c.driver == "speed":
                subs[c.u] = c.law
                subs[chain.ud[c.u]] = sp.diff(c.law, chain.t)
        self.substitutions = subs
        sub = (lambda e: e.xreplace(subs)) if subs else (lambda e: e)
        free = [r for r, c in enumerate(coords) if c.driver is None]
        driven = [r for r, c in enumerate(coords) if c.driver is not None]
        self.q = [c.q for c in coords if c.driver != "coordinate"]
        self.u = [coords[r].u for r in free]
        self.ud = [chain.ud[u] for u in self.u]
        self.qdot = sp.Matrix([sub(chain.qdot[q]) for q in self.q])
        Mfull = inertia.mass_matrix
        F_total = [sp.Add(*[part[r] for part in active.values()]) for r in range(len(coords))]
        ud_driven = [sub(chain.ud[coords[d].u]) for d in driven]
        self.mass_matrix = sp.Matrix(len(free), len(free),
                                     lambda i, j: sub(Mfull[free[i], free[j]]))
        self.forcing = sp.Matrix([sub(F_total[r] - inertia.remainder[r]
                                      - sp.Add(*[Mfull[r, d] * a for d, a in zip(driven, ud_driven)]))
                                  for r in free])
        #: generalized force each driver supplies [N m or N], as expressions of q, u, u', t
        self.driver_efforts = {}
        for d, a_d in zip(driven, ud_driven):
            expr = (sp.Add(*[Mfull[d, s] * chain.ud[coords[s].u] for s in free]) + Mfull[d, d] * a_d
                    + sum((Mfull[d, e] * a for e, a in zip(driven, ud_driven) if e != d), sp.Integer(0))
                    + inertia.remainder[d] - F_total[d])
            self.driver_efforts[coords[d].owner] = sub(expr)
        self.outputs = {k: sub(v) for k, v in output_expressions(self).items()}
        known = set(self.q) | set(self.u) | set(self.ud) | {self.t}
        symbols = set()
        for expr in list(self.mass_matrix) + list(self.forcing) + list(self.qdot) + list(self.outputs.values()):
            symbols |= expr.free_symbols
        self.constants = sorted(symbols - known, key=lambda s: s.name)

    # ------------------------------------------------------------------ structure
    @property
    def state_names(self) -> list[str]:
        """Names of the state variables, coordinates then speeds."""
        return [q.name for q in self.q] + [u.name for u in self.u]

    def beam_constant_symbols(self) -> dict:
        """symbol -> (beam name, BeamConstants) for every modal constant."""
        out = {}
        for name, consts in self.kinematics.constants.items():
            for symbol in consts.used:
                out[symbol] = (name, consts)
        return out

    # ------------------------------------------------------------------ numbers
    def constant_values(self, model: Model | None = None) -> dict:
        """Numeric value of every constant for ``model`` (by default the derived one).

        ``model`` may differ from the derived model in its numbers only (parameters, field values,
        typed roots); its structure must be the same.
        """
        from ..expressions import parse_expression, resolve_parameters

        model = model or self.model
        params = resolve_parameters(model.parameters, path_prefix="parameters")
        psyms = self.chain.symbols.parameters
        values: dict = {psyms[k]: float(v) for k, v in params.items() if k in psyms}
        names = dict(psyms)

        def number(path, value):
            expr = parse_expression(value, names, path=path)
            return float(expr.subs(values)) if expr.free_symbols else float(expr)

        for symbol, (path, _) in self.chain.symbols.definitions.items():
            values[symbol] = number(path, get_value(model, path))
        for name, consts in self.kinematics.constants.items():
            if not consts.used:
                continue
            beam = model.beams[name]
            path = f"beams.{name}"
            family = shape_family(beam.shape, f"{path}.shape")
            axial = shape_family(beam.axial_shape, f"{path}.axial_shape") if beam.n_axial else None
            stations = {}
            for spec in consts.used.values():
                if spec[0] == "station":
                    stations[spec[3]] = float(sp.sympify(spec[3]).subs(values))
            values.update(consts.values(
                L=number(f"{path}.L", beam.L), rho=number(f"{path}.rho", beam.rho),
                EI=number(f"{path}.EI", beam.EI), family=family, n=beam.n_modes,
                EA=number(f"{path}.EA", beam.EA) if beam.EA is not None else None,
                axial_family=axial, n_axial=beam.n_axial, station_values=stations))
        for symbol, value in values.items():
            if not math.isfinite(value):
                raise ValueError(f"constant {symbol} is not finite")
        return values

    def parameter_vector(self, model: Model | None = None) -> np.ndarray:
        """The constants vector p, shape (len(constants),), in the order of :attr:`constants`."""
        values = self.constant_values(model)
        return np.array([values[s] for s in self.constants], dtype=float)

    def initial_state(self, model: Model | None = None) -> np.ndarray:
        """Initial state [q, u] from the model's ``[initial]`` table (others 0), shape (n,)."""
        from ..expressions import parse_expression, resolve_parameters

        model = model or self.model
        params = resolve_parameters(model.parameters, path_prefix="parameters")
        psyms = self.chain.symbols.parameters
        values = {psyms[k]: float(v) for k, v in params.items() if k in psyms}
        state = []
        for s in self.q + self.u:
            value = model.initial.get(s.name, 0)
            expr = parse_expression(value, dict(psyms), path=f"initial.{s.name}")
            state.append(float(expr.subs(values)) if expr.free_symbols else float(expr))
        return np.array(state, dtype=float)


def shape_family(spec, path: str):
    """The :class:`~flexkane.modes.ShapeFamily` of a beam's shape specification.

    Expressions of ``xi`` given in a model file (family ``expression``) are parsed with the safe
    expression language; errors name the key path.
    """
    from ..errors import ModelError
    from ..expressions import parse_expression
    from ..modes import XI, get_family

    options = dict(spec.options)
    if spec.roots is not None:
        options["roots"] = list(spec.roots)
    if spec.family == "expression" and "expressions" in options:
        texts = options["expressions"]
        if not isinstance(texts, list) or not texts:
            raise ModelError(f"{path}.expressions", "a non-empty list of expressions of xi", texts)
        options["expressions"] = [parse_expression(text, {"xi": XI}, path=f"{path}.expressions[{i}]")
                                  for i, text in enumerate(texts)]
    try:
        return get_family(spec.family, **options)
    except ModelError as exc:
        raise ModelError(f"{path}.{exc.path}" if exc.path != "family" else f"{path}.family",
                         exc.expected, exc.given, exc.hint) from None


def derive(model: Model) -> EquationsOfMotion:
    """Derive Kane's equations of motion of a model.

    Parameters
    ----------
    model : Model
        A model (validated here).

    Returns
    -------
    EquationsOfMotion
    """
    model.validate()
    chain = build_chain(model)
    kin = Kinematics(chain)
    inertia = generalized_inertia_forces(kin)
    active = generalized_active_forces(kin)
    return EquationsOfMotion(chain, kin, inertia, active)
