"""Kane's dynamical equations ``F*_r + F_r = 0`` (eq. 8.36) as ``M(q, t) u' = f(q, u, t)``.

:func:`derive` composes the stages: chain (coordinates, kinematic equations) -> kinematics ->
generalized inertia forces (eq. 8.22) -> generalized active forces (eqs. 8.28-8.35) -> equations.
Prescribed joint coordinates (drivers) are substituted at the end; the generalized force each driver
must supply is kept as an output.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import sympy as sp

from ..expressions import bounded_expand, time_derivative
from ..model import Model
from ..model.values import symbol_order
from . import loop_closure, numeric
from .active import generalized_active_forces
from .budget import DerivationBudget
from .chain import BEAM_ROLES, Chain, build_chain
from .compact import CompactEquations, LazyMassMatrix
from .controllers import control_signals
from .driver_laws import parse_state_laws, speed_coupling, state_driver_substitutions
from .inertia import LAZY_MASS_MIN_SPEEDS, InertiaForces, generalized_inertia_forces
from .kinematics import Kinematics
from .outputs import output_expressions
from .spatial_active import spatial_active_forces
from .spatial_inertia import spatial_inertia_forces
from .spatial_kinematics import SpatialKinematics
from .spatial_outputs import spatial_output_expressions

__all__ = ["EquationsOfMotion", "derive"]


class _Expanded:
    """An attribute of :class:`EquationsOfMotion` read from the expanded equations.

    While the equations are built, the attribute holds the compact form in the instance's
    ``__dict__``; once built, reading it gives the attribute of the same name of the expanded form
    (intermediates substituted) that the instance's method ``form`` returns.
    """

    def __init__(self, name: str, doc: str, form: str = "_expanded_form"):
        self.name = name
        self.form = form
        self.__doc__ = doc + " Intermediates substituted (formed on first use)."

    def __get__(self, instance, owner=None):
        if instance is None:
            return self
        if self.name in instance.__dict__:
            return instance.__dict__[self.name]
        return getattr(getattr(instance, self.form)(), self.name)

    def __set__(self, instance, value):
        instance.__dict__[self.name] = value

    def __delete__(self, instance):
        del instance.__dict__[self.name]


class LazyForces:
    """F*_r of every speed, formed on first use from :class:`InertiaForces` whose mass matrix is
    formed entry by entry (a sequence: ``len``, indexing, iteration)."""

    def __init__(self, inertia: InertiaForces, ud: dict):
        self.inertia = inertia
        self.ud = ud
        self._formed = None

    def _list(self) -> list:
        if self._formed is None:
            self._formed = self.inertia.F_r_star(self.ud)
        return self._formed

    def __len__(self) -> int:
        return len(self.inertia.speeds)

    def __getitem__(self, r):
        return self._list()[r]

    def __iter__(self):
        return iter(self._list())


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
    z : list of sympy.Symbol
        Controller states (:mod:`flexkane.kane.controllers`); the state is ``y = [q, u, z]``.
    zdot : sympy.Matrix, shape (len(z), 1)
        Their rates, expressions of q, u, z, t and the constants.
    constants : list of sympy.Symbol
        Every symbol of the equations and outputs other than t, q, u, u' and the intermediates; the
        parameter vector p.
    compact : CompactEquations
        The same equations in terms of named intermediate quantities (evaluated in tree order):
        what generated code and long reports use. ``mass_matrix``, ``forcing``, ``qdot`` and
        ``outputs`` above are these with every intermediate substituted (formed on first use; for a
        chain without intermediates, the same objects).
    intermediates : list of (sympy.Symbol, sympy.Expr)
        ``compact.intermediates``: definitions in evaluation order.
    """

    def __init__(self, chain: Chain, kin: Kinematics, inertia: InertiaForces, active: dict):
        self.model = chain.model
        self.chain = chain
        self.kinematics = kin
        self.t = chain.t
        self.all_speeds = list(chain.u)
        self.F_r = active
        self._inertia = inertia
        coords = chain.coordinates
        speed_coords = chain.speed_coordinates     # rows and columns of M (a 3D chain's e0 has none)
        subs = {}
        for c in coords:   # drivers' laws are differentiated branch by branch (no impulses)
            path = f"joints.{c.owner}.driver.{c.driver}"
            if c.state_law:
                continue       # laws of the state: below
            if c.driver == "coordinate":
                subs[c.q] = c.law
                subs[c.u] = time_derivative(c.law, chain.t, path=path)
                subs[chain.ud[c.u]] = time_derivative(c.law, chain.t, path=path, order=2)
            elif c.driver == "speed":
                subs[c.u] = c.law
                subs[chain.ud[c.u]] = time_derivative(c.law, chain.t, path=path)
        subs = state_driver_substitutions(chain, subs)     # laws of the state (kane.driver_laws)
        self.substitutions = subs
        sub = (lambda e: e.xreplace(subs)) if subs else (lambda e: e)
        free = [r for r, c in enumerate(speed_coords) if c.driver is None]
        driven = [r for r, c in enumerate(speed_coords) if c.driver is not None]
        self.q = [c.q for c in coords if c.driver != "coordinate"]
        self.u = [speed_coords[r].u for r in free]
        self.ud = [chain.ud[u] for u in self.u]
        self.qdot = sp.Matrix([sub(chain.qdot[q]) for q in self.q])
        self.z = list(chain.controller_states)
        self.zdot = sp.Matrix(len(self.z), 1, [sub(chain.controller_rates[z]) for z in self.z])
        # M's entries formed when read where nothing here needs them (no drivers, no closed loops)
        lazy = getattr(inertia, "lazy", False) and inertia.assembly is not None and not subs \
            and not driven and not chain.model.constraints
        Mfull = None if lazy else inertia.mass_matrix
        self.F_r_star = LazyForces(inertia, chain.ud) if lazy else inertia.F_r_star(chain.ud)
        F_total = [sp.Add(*[part[r] for part in active.values()]) for r in range(len(speed_coords))]
        ud_driven = [sub(chain.ud[speed_coords[d].u]) for d in driven]
        coupling = speed_coupling(chain, subs, self.u)
        if lazy:
            self.mass_matrix = LazyMassMatrix(inertia, free, chain.intermediates)
        if not coupling:
            if not lazy:
                self.mass_matrix = sp.Matrix(len(free), len(free),
                                             lambda i, j: sub(Mfull[free[i], free[j]]))
            self.forcing = sp.Matrix([sub(F_total[r] - inertia.remainder[r]
                                          - sp.Add(*[Mfull[r, d] * a for d, a in zip(driven, ud_driven)]))
                                      for r in free])
        else:
            self._reduce_by_drivers(Mfull, F_total, free, driven, ud_driven, coupling, sub)
        #: generalized force each driver supplies [N m or N], as expressions of q, u, u', t
        self.driver_efforts = {}
        for d, a_d in zip(driven, ud_driven):
            expr = (sp.Add(*[Mfull[d, s] * chain.ud[speed_coords[s].u] for s in free]) + Mfull[d, d] * a_d
                    + sum((Mfull[d, e] * a for e, a in zip(driven, ud_driven) if e != d), sp.Integer(0))
                    + inertia.remainder[d] - F_total[d])
            self.driver_efforts[speed_coords[d].owner] = sub(expr)
        #: dependent speeds and their expressions in the state (loop constraints)
        self.dependent_speeds: dict = {}
        self.constraint_set = None
        outputs = spatial_output_expressions if chain.dimensions == 3 else output_expressions
        self.outputs = {k: sub(v) for k, v in outputs(self).items()}
        for u_d, (C, _) in coupling.items():    # the driver's force on the speeds its law reads
            effort = self.driver_efforts[next(c.owner for c in speed_coords if c.u == u_d)]
            self.outputs["power_nonconservative"] -= effort * sp.Add(*[c * u for c, u in zip(C, self.u)])
        dependent_subs: dict = {}
        if chain.model.constraints:
            dependent_subs = self._reduce_by_constraints(sub)
        assembly = getattr(inertia, "assembly", None)
        assembly = assembly.reduced(free, sub) if assembly is not None else None
        self.compact = CompactEquations.collect(self, chain.intermediates, sub, dependent_subs, assembly)
        self._expanded = None
        known = set(self.q) | set(self.u) | set(self.ud) | set(self.z) | {self.t}
        symbols = set()
        for expr in self.compact.expressions():
            symbols |= expr.free_symbols
        symbols -= {s for s, _ in self.compact.intermediates}
        self.constants = sorted(symbols - known, key=symbol_order)   # E_1, E_2, ..., E_10
        #: F*_r and F_r by source in terms of the kinematic intermediates (drivers not substituted)
        self.compact_forces = {"F_r_star": self.F_r_star, "F_r": self.F_r}
        self._forces_expanded = None
        # the public attributes are the expanded equations, formed on first use
        del self.mass_matrix, self.forcing, self.qdot, self.outputs, self.F_r_star, self.F_r, self.zdot

    # ------------------------------------------------------------------ compact and expanded forms
    @property
    def intermediates(self) -> list:
        return self.compact.intermediates

    @property
    def output_names(self) -> list[str]:
        """Names of the outputs (columns of the results files), without forming their expressions."""
        return list(self.compact.outputs)

    def expand(self, expr):
        """``expr`` (an expression or a Matrix) with every intermediate replaced by its definition."""
        return self.compact.expand(expr)

    def _expanded_forces(self) -> SimpleNamespace:
        if self._forces_expanded is None:
            expand = self.chain.intermediates.expand
            forces = self.compact_forces
            self._forces_expanded = SimpleNamespace(
                F_r_star=[expand(e) for e in forces["F_r_star"]],
                F_r={k: [expand(e) for e in v] for k, v in forces["F_r"].items()})
        return self._forces_expanded

    def _expanded_form(self) -> "CompactEquations":
        if self._expanded is None:
            self._expanded = self.compact.expanded()
        return self._expanded

    F_r_star = _Expanded("F_r_star", "list of sympy.Expr: F*_r of every speed (eq. 8.22).", "_expanded_forces")
    F_r = _Expanded("F_r", "dict of str to list of sympy.Expr: F_r by source (eq. 8.35).", "_expanded_forces")
    mass_matrix = _Expanded("mass_matrix", "sympy.Matrix (len(u), len(u)): M of ``M u' = f``.")
    forcing = _Expanded("forcing", "sympy.Matrix (len(u), 1): f of ``M u' = f``.")
    qdot = _Expanded("qdot", "sympy.Matrix (len(q), 1): the kinematic equations q'.")
    outputs = _Expanded("outputs", "dict of str to sympy.Expr: output expressions.")
    zdot = _Expanded("zdot", "sympy.Matrix (len(z), 1): the rates of the controller states.")

    def __getstate__(self):
        state = dict(self.__dict__)
        state["_expanded"] = None
        state["_forces_expanded"] = None
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)

    # ------------------------------------------------------------------ drivers of the state
    def _reduce_by_drivers(self, Mfull, F_total, free, driven, ud_driven, coupling, sub) -> None:
        """Kane's equations with the speeds of drivers of the state dependent (see
        :mod:`flexkane.kane.driver_laws`): ``P^T M P u_f' = P^T (f - M e)`` over the free speeds and
        those driven speeds, ``P = [I; C]``."""
        from .constraints import dependent_speed_reduction

        speed_coords = self.chain.speed_coordinates
        state = [d for d in driven if speed_coords[d].u in coupling]
        keep = free + state
        time_laws = [(d, a) for d, a in zip(driven, ud_driven) if d not in state]
        M = sp.Matrix(len(keep), len(keep), lambda i, j: sub(Mfull[keep[i], keep[j]]))
        f = sp.Matrix([sub(F_total[r] - self._inertia.remainder[r] - sp.Add(*[Mfull[r, d] * a for d, a in time_laws]))
                       for r in keep])
        P = sp.zeros(len(keep), len(free))
        e = sp.zeros(len(keep), 1)
        for k in range(len(free)):
            P[k, k] = 1
        for k, d in enumerate(state):
            C, e_d = coupling[speed_coords[d].u]
            P[len(free) + k, :] = sp.Matrix([C])
            e[len(free) + k] = e_d
        self.mass_matrix, self.forcing = dependent_speed_reduction(M, f, P, e)

    # ------------------------------------------------------------------ loop constraints
    def _reduce_by_constraints(self, sub) -> None:
        """Kane's equations with dependent speeds (see :mod:`flexkane.kane.constraints`)."""
        from .constraints import choose_dependent, dependent_speed_reduction, loop_constraints

        chain = self.chain
        cons = loop_constraints(self.kinematics)
        self.constraint_set = cons
        u_free = list(self.u)
        ud_free = [chain.ud[u] for u in u_free]
        phi = [sub(e) for e in cons.phi]
        g_raw = [chain.dt(e) for e in cons.phi]
        # Phi' = A u + a: g_raw is linear and homogeneous in all the speeds (drivers not yet
        # substituted), so A is its partial derivatives with respect to the free speeds and a the part
        # of the driven ones, whose speeds become the drivers' laws
        driven = [c_.u for c_ in chain.coordinates if c_.driver is not None]
        simplified = lambda e: (expanded if (expanded := bounded_expand(e, [*u_free, *self.q], self.t))  # noqa: E731
                                is not None else e)
        A = sp.Matrix([[simplified(sub(chain.partial(gi, u))) for u in u_free] for gi in g_raw])
        a = sp.Matrix([simplified(sub(sp.Add(*[chain.partial(gi, u) * u for u in driven]))) + rate * ph
                       for gi, ph, rate in zip(g_raw, phi, cons.rates)])
        gd = [sub(chain.dt(e, with_ud=True)) for e in g_raw]
        c = sp.Matrix([e.xreplace({ud: 0 for ud in ud_free}) for e in gd])
        # choose the dependent speeds at the initial configuration
        values = self.constant_values()
        guess = self._initial_guess(self.model, values)
        numeric = {**values, **guess, self.t: 0.0}
        A_full = sub(chain.intermediates.expand(A))
        A0 = np.array(A_full.xreplace({k: sp.Float(v) for k, v in numeric.items()}).evalf(), dtype=float)
        roles = {c_.u: c_.role for c_ in chain.coordinates}
        preferred = [roles[u] not in BEAM_ROLES for u in u_free]
        dep = choose_dependent(A0, u_free, preferred, cons.dependent)
        ind = [j for j in range(len(u_free)) if j not in dep]
        Ad = A[:, dep]
        Ai = A[:, ind]
        # A_d^-1 as adjugate / determinant: no symbolic pivot that could vanish at some configuration
        spatial = chain.dimensions == 3    # the loops' solution, named: it enters every equation
        named = (lambda m, label: m.applyfunc(lambda x: chain.name(x, label))) if spatial \
            else (lambda m, label: m)  # noqa: E731
        if spatial:
            from .spatial_constraints import named_det_adjugate

            det, adj = named_det_adjugate(Ad, chain)
        else:
            det = sp.factor_terms(Ad.det(method="berkowitz"))
            adj = Ad.adjugate(method="berkowitz")
        solve = lambda rhs: (adj * rhs) / det  # noqa: E731
        X = named(solve(Ai), "C_loops")
        y = solve(a)
        ui = sp.Matrix([u_free[j] for j in ind])
        u_dep = named(-X * ui - y, "u_loops")
        dep_subs = {u_free[j]: u_dep[k] for k, j in enumerate(dep)}
        e_dep = named(-solve(c.xreplace(dep_subs)), "ud_loops")
        n, ni = len(u_free), len(ind)
        P = sp.zeros(n, ni)
        e = sp.zeros(n, 1)
        for k, j in enumerate(ind):
            P[j, k] = 1
        for k, j in enumerate(dep):
            P[j, :] = -X[k, :]
            e[j] = e_dep[k]
        M = self.mass_matrix
        # u' of the dependent speeds in terms of the independent ones (for outputs)
        udi = sp.Matrix([ud_free[j] for j in ind])
        ud_dep = -X * udi + e_dep
        ud_subs = {ud_free[j]: ud_dep[k] for k, j in enumerate(dep)}
        # constraint forces: the dependent rows of M u' - f are A_d^T lambda; drivers also work against
        # them, through their own columns of the constraint matrix
        residual = (M * sp.Matrix(ud_free) - self.forcing)
        lam = (adj.T * sp.Matrix([residual[j] for j in dep])) / det
        for owner, effort in list(self.driver_efforts.items()):
            coord = chain.of(owner)[0]
            column = sp.Matrix([sub(chain.partial(e, coord.u)) for e in g_raw])
            self.driver_efforts[owner] = effort - (column.T * lam)[0]
        M_reduced, f_reduced = dependent_speed_reduction(M, self.forcing, P, e)
        self.mass_matrix = M_reduced.applyfunc(lambda x: x.xreplace(dep_subs))
        self.forcing = f_reduced.applyfunc(lambda x: x.xreplace(dep_subs))
        self.qdot = self.qdot.applyfunc(lambda x: x.xreplace(dep_subs))
        self.zdot = self.zdot.applyfunc(lambda x: x.xreplace(dep_subs))
        self.dependent_speeds = dep_subs
        self.u = [u_free[j] for j in ind]
        self.ud = [chain.ud[u] for u in self.u]
        for owner, effort in self.driver_efforts.items():
            self.outputs[f"effort_{owner}"] = effort
        self.outputs["power_nonconservative"] = self._power_with_efforts(sub)
        self.driver_efforts = {k: v.xreplace(ud_subs).xreplace(dep_subs) for k, v in self.driver_efforts.items()}
        self.outputs = {k: v.xreplace(ud_subs).xreplace(dep_subs) for k, v in self.outputs.items()}
        for name, ph in zip(cons.names, phi):
            self.outputs[f"constraint_{name}"] = ph
        for u, expr in dep_subs.items():
            self.outputs[u.name] = expr
        # the constraints decide the dependent coordinates of the initial state
        self.dependent_coordinates = [c_.q for c_ in chain.coordinates if c_.u in dep_subs]
        self._phi = [sub(chain.intermediates.expand(e)) for e in phi]
        return dep_subs

    def _power_with_efforts(self, sub) -> sp.Expr:
        """Power of non-conservative forces with the drivers' efforts corrected for constraint forces."""
        from .outputs import output_expressions

        outputs = spatial_output_expressions if self.chain.dimensions == 3 else output_expressions
        return sub(outputs(self)["power_nonconservative"])

    def _initial_guess(self, model, values) -> dict:
        """Coordinates and speeds from the model's [initial] table (others 0), as numbers
        (:func:`flexkane.kane.numeric.initial_guess`; ``values`` is not needed)."""
        return numeric.initial_guess(self, model)

    def project_coordinates(self, q: np.ndarray, p_values: dict, t: float = 0.0) -> np.ndarray:
        """Solve the loop constraints for the dependent coordinates, the others kept
        (:func:`.loop_closure.project_coordinates`)."""
        return loop_closure.project_coordinates(self, q, p_values, t)

    # ------------------------------------------------------------------ structure
    @property
    def state_names(self) -> list[str]:
        """Names of the state variables: coordinates, speeds, then controller states."""
        return [q.name for q in self.q] + [u.name for u in self.u] + [z.name for z in getattr(self, "z", ())]

    def beam_constant_symbols(self) -> dict:
        """symbol -> (beam name, BeamConstants) for every modal constant."""
        out = {}
        for name, consts in self.kinematics.constants.items():
            for symbol in consts.used:
                out[symbol] = (name, consts)
        return out

    # ------------------------------------------------------------------ numbers
    def constant_values(self, model: Model | None = None) -> dict:
        """Numeric value of every constant for ``model`` (:func:`flexkane.kane.numeric.constant_values`)."""
        return numeric.constant_values(self, model)

    def parameter_vector(self, model: Model | None = None) -> np.ndarray:
        """The constants vector p in the order of :attr:`constants` (:func:`flexkane.kane.numeric.parameter_vector`)."""
        return numeric.parameter_vector(self, model)

    def initial_state(self, model: Model | None = None) -> np.ndarray:
        """Initial state [q, u] from the model's ``[initial]`` table (:func:`flexkane.kane.numeric.initial_state`)."""
        return numeric.initial_state(self, model)


def derive(model: Model, *, lazy_mass: bool | None = None) -> EquationsOfMotion:
    """Derive Kane's equations of motion of a model.

    Parameters
    ----------
    model : Model
        A model (validated here).
    lazy_mass : bool, optional
        Whether the entries of the symbolic mass matrix are formed only when read. By default,
        by the structure: a planar chain without drivers or closed loops with at least
        ``LAZY_MASS_MIN_SPEEDS`` speeds, whose generated code sums ``M`` from its
        :class:`~flexkane.kane.inertia.MassAssembly`; the entries are the same either way.

    Returns
    -------
    EquationsOfMotion
    """
    from ..errors import ModelError

    if not isinstance(model, Model):
        raise ModelError("model", "a flexkane Model (flexkane.load_model, flexkane.builtin_model)",
                         type(model).__name__)
    model.validate()
    budget = DerivationBudget()   # bounded time and size (see flexkane.kane.budget)
    chain = build_chain(model)
    spatial = chain.dimensions == 3
    kin = SpatialKinematics(chain) if spatial else Kinematics(chain)
    budget.check_time("the kinematics")
    if lazy_mass is None:
        lazy_mass = not model.constraints and len(chain.u) >= LAZY_MASS_MIN_SPEEDS \
            and all(c.driver is None for c in chain.coordinates)
    inertia = spatial_inertia_forces(kin) if spatial else generalized_inertia_forces(kin, lazy=lazy_mass)
    mass = inertia.assembly.expressions() if getattr(inertia, "lazy", False) and inertia.assembly is not None \
        else list(inertia.mass_matrix)
    budget.check_size(mass + list(inertia.remainder), "the inertia forces")
    control_signals(kin)   # sensors, controller states and outputs: the names efforts may use
    if not spatial:
        parse_state_laws(chain)   # drivers' laws that read them (planar chains)
    active = spatial_active_forces(kin) if spatial else generalized_active_forces(kin)
    budget.check_time("the active forces")
    eom = EquationsOfMotion(chain, kin, inertia, active)
    budget.check_size(eom.compact.expressions(), "the equations")
    return eom
