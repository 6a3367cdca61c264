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

from ..expressions import time_derivative
from ..model import Model
from ..model.values import symbol_order
from . import loop_closure, numeric
from .active import generalized_active_forces
from .budget import DerivationBudget
from .chain import Chain, build_chain
from .compact import CompactEquations, LazyMassMatrix
from .constraints import loop_constraints
from .controllers import control_signals
from .driver_laws import parse_state_laws, reduce_by_drivers, speed_coupling, state_driver_substitutions
from .inertia import InertiaForces, generalized_inertia_forces, lazy_mass_min_speeds
from .kinematics import Kinematics
from .loop_reduction import reduce_by_loops
from .outputs import output_expressions
from .spatial_active import spatial_active_forces
from .spatial_inertia import spatial_inertia_forces
from .spatial_kinematics import SpatialKinematics
from .spatial_outputs import spatial_output_expressions

__all__ = ["EquationsOfMotion", "PLANAR_ENGINE", "derive", "planar_engine_reason"]

#: The engine that derives planar chains by default: ``"spatial"`` (planar motion in the spatial
#: engine, :class:`~flexkane.kane.spatial_kinematics.SpatialKinematics`) or ``"planar"`` (the planar
#: engine, :class:`~flexkane.kane.kinematics.Kinematics`), for the models the spatial one takes
#: (:func:`planar_engine_reason`); :func:`derive`'s ``engine`` chooses per call.
PLANAR_ENGINE = "spatial"


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
        Independent generalized speeds (neither prescribed by a driver nor dependent by a loop).
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
    driver_efforts : dict of str to sympy.Expr
        Joint -> the generalized force its driver supplies [N m or N] (q, u, u', t).
    dependent_speeds : dict of sympy.Symbol to sympy.Expr
        Speeds made dependent by loop constraints -> their expressions (empty without loops;
        :func:`flexkane.kane.loop_reduction.reduce_by_loops` decides these, the reduced equations
        and the two attributes below).
    dependent_coordinates : list of sympy.Symbol
        Their coordinates, which the constraints decide in the initial state.
    constraint_set : ConstraintSet or None
        The loop joints' constraints.
    """

    def __init__(self, chain: Chain, kin: Kinematics, inertia: InertiaForces, active: dict):
        self.model = chain.model
        self.chain = chain
        self.kinematics = kin
        self.t = chain.t
        self.all_speeds = list(chain.u)
        self.F_r = active
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
        u_free = [speed_coords[r].u for r in free]
        qdot = sp.Matrix(len(self.q), 1, [sub(chain.qdot[q]) for q in self.q])   # (0, 1) when every q is driven
        self.z = list(chain.controller_states)
        zdot = sp.Matrix(len(self.z), 1, [sub(chain.controller_rates[z]) for z in self.z])
        # M's entries formed when read where nothing here needs them (no drivers, no closed loops)
        lazy = getattr(inertia, "lazy", False) and inertia.assembly is not None and not subs \
            and not driven and not chain.model.constraints
        Mfull = None if lazy else inertia.mass_matrix
        self.F_r_star = LazyForces(inertia, chain.ud) if lazy else inertia.F_r_star(chain.ud)
        F_total = [sp.Add(*[part[r] for part in active.values()]) for r in range(len(speed_coords))]
        ud_driven = [sub(chain.ud[speed_coords[d].u]) for d in driven]
        coupling = speed_coupling(chain, subs, u_free)
        if coupling:    # drivers of the state: their speeds dependent (kane.driver_laws)
            drivers = reduce_by_drivers(chain, Mfull, F_total, inertia.remainder, free, driven, ud_driven,
                                        coupling, sub)
            M, forcing = drivers.mass_matrix, drivers.forcing
        else:
            M = LazyMassMatrix(inertia, free, chain.intermediates) if lazy else \
                sp.Matrix(len(free), len(free), lambda i, j: sub(Mfull[free[i], free[j]]))
            forcing = sp.Matrix(len(free), 1, [sub(F_total[r] - inertia.remainder[r]
                                     - sp.Add(*[Mfull[r, d] * a for d, a in zip(driven, ud_driven)]))
                                 for r in free])
        efforts = {}    # generalized force each driver supplies
        for d, a_d in zip(driven, ud_driven):
            expr = (sp.Add(*[Mfull[d, s] * chain.ud[speed_coords[s].u] for s in free]) + Mfull[d, d] * a_d
                    + sum((Mfull[d, e] * a for e, a in zip(driven, ud_driven) if e != d), sp.Integer(0))
                    + inertia.remainder[d] - F_total[d])
            efforts[speed_coords[d].owner] = sub(expr)
        outputs = self._output_expressions(efforts).map(sub)    # declared outputs (model.columns)
        for u_d, (C, _) in coupling.items():    # the driver's force on the speeds its law reads
            effort = efforts[next(c.owner for c in speed_coords if c.u == u_d)]
            outputs.replace("power_nonconservative",
                            outputs["power_nonconservative"] - effort * sp.Add(*[c * u for c, u in zip(C, u_free)]))
        loops = None
        if chain.model.constraints:     # closed loops: dependent speeds (kane.loop_reduction)
            cons = loop_constraints(kin)    # before the numbers: it names the constants of its ends
            at = {**numeric.constant_values(self), **numeric.initial_guess(self), self.t: 0.0}
            loops = reduce_by_loops(
                chain, cons, M, forcing, qdot, zdot, u_free, self.q, efforts, outputs, sub, at,
                power=lambda e: sub(self._output_expressions(e)["power_nonconservative"]))
            M, forcing, qdot, zdot = loops.mass_matrix, loops.forcing, loops.qdot, loops.zdot
            efforts, outputs = loops.driver_efforts, loops.outputs
        # each attribute set once, from the equations over the free speeds or the loops' reduction
        self.mass_matrix, self.forcing, self.qdot, self.zdot, self.outputs = M, forcing, qdot, zdot, outputs
        #: every output's name, unit, group and description, in order (:class:`~flexkane.model.columns.Output`)
        self.output_declarations = outputs.declarations()
        self.u = list(loops.u) if loops else u_free
        self.ud = [chain.ud[u] for u in self.u]
        #: generalized force each driver supplies [N m or N], as expressions of q, u, u', t
        self.driver_efforts = efforts
        #: dependent speeds and their expressions in the state (loop constraints)
        self.dependent_speeds = loops.dependent_speeds if loops else {}
        #: the coordinates of the dependent speeds, which the constraints decide in the initial state
        self.dependent_coordinates = list(loops.dependent_coordinates) if loops else []
        self._phi = list(loops.phi) if loops else []     # Phi(q, t), intermediates written out
        self.constraint_set = loops.constraint_set if loops else None
        assembly = getattr(inertia, "assembly", None)
        assembly = assembly.reduced(free, sub) if assembly is not None else None
        self.compact = CompactEquations.collect(self, chain.intermediates, sub, self.dependent_speeds, assembly)
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

    # ------------------------------------------------------------------ outputs
    def _output_expressions(self, efforts: dict) -> dict:
        """Output expressions (drivers not substituted) with the drivers' efforts ``efforts``
        (:func:`.outputs.output_expressions`, :func:`.spatial_outputs.spatial_output_expressions`)."""
        outputs = spatial_output_expressions if self.chain.dimensions == 3 else output_expressions
        return outputs(SimpleNamespace(chain=self.chain, kinematics=self.kinematics, F_r=self.F_r,
                                       driver_efforts=efforts))

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


def derive(model: Model, *, lazy_mass: bool | None = None, engine: str | None = None) -> EquationsOfMotion:
    """Derive Kane's equations of motion of a model.

    Parameters
    ----------
    model : Model
        A model (validated here).
    lazy_mass : bool, optional
        Whether the entries of the symbolic mass matrix are formed only when read. By default,
        by the structure: a chain without drivers or closed loops with at least
        ``LAZY_MASS_MIN_SPEEDS`` speeds (``SPATIAL_LAZY_MASS_MIN_SPEEDS`` of a spatial chain;
        :mod:`flexkane.kane.inertia`), whose generated code sums ``M`` from its
        :class:`~flexkane.kane.inertia.MassAssembly`; the entries are the same either way. A planar
        chain for which it is given (or which has that many speeds) is derived by the planar engine.
    engine : {"spatial", "planar"}, optional
        The engine of a planar model (default :data:`PLANAR_ENGINE`): the spatial one for the
        models it takes (:func:`planar_engine_reason` says why one stays on the planar engine),
        the planar one otherwise; the equations are the same (names, printed form, numbers).

    Returns
    -------
    EquationsOfMotion
    """
    from ..errors import ModelError

    if not isinstance(model, Model):
        raise ModelError("model", "a flexkane Model (flexkane.load_model, flexkane.builtin_model)",
                         type(model).__name__)
    model.validate()
    engine = PLANAR_ENGINE if engine is None else engine
    if engine not in ("spatial", "planar"):
        raise ModelError("engine", "'spatial' or 'planar'", engine)
    from ..progress import activity

    with activity(f"deriving the equations of motion of {model.name}", delay=0):   # on stderr (flexkane.progress)
        return _derive(model, lazy_mass, engine)


def planar_engine_reason(model: Model, chain: Chain, lazy_mass: bool) -> str | None:
    """Why a planar model stays on the planar engine (a feature the spatial engine lacks for it
    today), or None when the spatial engine derives it.

    ``lazy_mass``: whether the chain has the mass matrix assembled from data,
    :class:`~flexkane.kane.inertia.MassAssembly` (at least ``LAZY_MASS_MIN_SPEEDS`` speeds, no
    drivers, no closed loops), or :func:`derive` was asked for one form of it (``lazy_mass`` given),
    which spatial chains do not have yet: such a chain stays on the planar engine whichever form
    of its mass matrix is asked, so that both are the same expressions.
    """
    for beam in model.beams.values():
        if beam.gravity == "midpoint":
            return f"beams.{beam.name}.gravity = 'midpoint'"
        if beam.elastic_forces != "strain-energy":
            return f"beams.{beam.name}.elastic_forces = {beam.elastic_forces!r}"
    if lazy_mass:
        return f"the mass matrix assembled from data ({len(chain.u)} speeds)"
    return None


def _derive(model: Model, lazy_mass: bool | None, engine: str = "spatial") -> EquationsOfMotion:
    """:func:`derive` of a validated model."""
    budget = DerivationBudget()   # bounded time and size (see flexkane.kane.budget)
    chain = build_chain(model)
    threshold = lazy_mass_min_speeds(chain.dimensions)
    long_chain = not model.constraints and len(chain.u) >= threshold \
        and all(c.driver is None for c in chain.coordinates)
    assembly = long_chain or lazy_mass is not None      # the mass assembly asked for, either form of M
    if lazy_mass is None:
        lazy_mass = long_chain
    spatial = chain.dimensions == 3 or (engine == "spatial" and planar_engine_reason(model, chain, assembly) is None)
    if spatial:
        kin = SpatialKinematics(chain)
        # a planar chain's frames in the planar terms of its outputs, sensors, constraints, reports
        view = kin if chain.dimensions == 3 else Kinematics.of_spatial(kin)
    else:
        kin = view = Kinematics(chain)
    budget.check_time("the kinematics")
    inertia = spatial_inertia_forces(kin, lazy=lazy_mass) if spatial else generalized_inertia_forces(kin, lazy=lazy_mass)
    mass = inertia.assembly.expressions() if getattr(inertia, "lazy", False) and inertia.assembly is not None \
        else list(inertia.mass_matrix)
    budget.check_size(mass + list(inertia.remainder), "the inertia forces")
    control_signals(view)   # sensors, controller states and outputs: the names efforts may use
    parse_state_laws(chain)   # drivers' laws that read them (kane.driver_laws)
    active = spatial_active_forces(kin) if spatial else generalized_active_forces(kin)
    budget.check_time("the active forces")
    eom = EquationsOfMotion(chain, view, inertia, active)
    budget.check_size(eom.compact.expressions(), "the equations")
    return eom
