"""Linearized Kane's equations about an equilibrium or a steady spin.

Kane's equations ``M(q, t) u' = f(q, u, t, r)`` with ``q' = qdot(q, u, t)`` (eq. 8.36), perturbed
about an operating point ``(q0, u0 = 0, r0)`` at which ``u' = 0`` and ``q' = 0``, give to first order

    M du' + C du + K dq = B dr,        dq' = W du + V dq,

with, all evaluated at the operating point,

    M = M(q0),  C = -df/du,  K = -df/dq,  B = df/dr,  W = dqdot/du,  V = dqdot/dq.

(The term ``dM/dq . u'`` vanishes because ``u' = 0`` there.) W is the matrix of the kinematic
equations ``q' = W(q) u + k(q, t)``: the identity for revolute, prismatic and modal coordinates, a
rotation for the translation of a free joint (eq. 8.14). The state-space form is
``x = (dq, du)``, ``x' = A x + B_ss dr`` (:class:`~flexkane.analysis.linear_model.LinearModel`).

Controller states z (``[controllers.NAME]`` with ``states``, ``z' = zdot(q, u, z, t, r)``) are part
of the operating point and of the state, ``x = (dq, du, dz)``: the forcing's Jacobian with respect to
z gives ``K_z = -df/dz`` (``M du' + C du + K dq + K_z dz = B dr``) and the rates' Jacobians the rows
``dz' = Z_q dq + Z_u du + Z_z dz + Z_r dr``. An equilibrium solves ``f = 0`` and ``zdot = 0``
together over ``(q, z)`` (an integral state settles where it cancels a constant load: a PID's at
``z0 = tau_d / Ki``); the controllers' outputs and the sensors are outputs with their ``dz`` columns.
Chains with closed loops are linearized in their independent coordinates
(:mod:`flexkane.analysis.reduction`), spatial chains with spherical or free joints in three rotation
coordinates per set of Euler parameters (:mod:`flexkane.analysis.rotation_reduction`); spatial chains
with both in the rotation coordinates of their independent speeds, the loops closing the others
(``dq = T_r T_c dx_i``, :mod:`flexkane.analysis.reduction`), about a state
at rest or about a free steady spin of such a joint (``spin_axis``: a body spinning about a principal
axis, a top spinning upright), with ``u0 = Omega * axis`` for its angular speeds.

Operating points (``about``):

* ``equilibrium``: q0 solves ``f(q0, 0, t0) = 0`` (and the loop constraints), searched from the
  model's initial coordinates (:mod:`flexkane.analysis.equilibrium`);
* ``rest``: q0 is the model's initial configuration with every elastic coordinate (modal, planar or
  along a spatial beam's y and z, torsional and axial: ``model.coordinates.BEAM_ROLES``) set to zero,
  and must be an equilibrium; for free-floating chains;
* ``spin``: a revolute hub turns at the constant rate Omega (its driver is replaced by
  ``speed = Omega``); the other coordinates are in equilibrium in the hub's rotating frame.

Coordinates whose speed is prescribed by a driver are not degrees of freedom of the perturbation
(their perturbation is zero): they are dropped from the linear model. When such a coordinate does
not appear in the equations (it is cyclic, like the angle of a hub without gravity) nothing is lost;
when it does, the linear model freezes it at its value at t0 (and a steady spin is refused).

:class:`Linearization` forms the Jacobians once, symbolically (:mod:`flexkane.analysis.jacobian`),
and evaluates them for any operating point, which serves Campbell diagrams (one derivation, many spin
rates).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import scipy.linalg
import sympy as sp

from ..errors import ModelError
from ..kane.inputs import input_symbols
from ..kane.loop_closure import closure_unknowns
from ..model import Model
from ..model.coordinates import BEAM_ROLES
from ..progress import activity
from .equilibrium import EquilibriumCheck, NoEquilibriumError, check_equilibrium, find_equilibrium
from .jacobian import forward_jacobian, numeric_function
from .linear_model import LinearModel, linear_outputs
from .prepare import ABOUT, prepare_model
from .reduction import closure_map, loop_columns
from .rotation_reduction import RotationReduction

__all__ = ["Linearization", "linearize", "ABOUT"]


def free_symbols(exprs) -> set:
    """The free symbols of ``exprs``, each distinct subexpression visited once.

    The same set as the union of ``e.free_symbols``, which walks a subexpression again wherever it
    occurs: the equations of a closed loop share their minors so often that this takes minutes.

    Parameters
    ----------
    exprs : iterable of sympy.Basic

    Returns
    -------
    set of sympy.Symbol
    """
    out: set = set()
    seen: set = set()
    stack = list(exprs)
    while stack:
        node = stack.pop()
        if node in seen:
            continue
        seen.add(node)
        if not node.args or getattr(node, "bound_symbols", ()):    # a symbol; an integral's variables
            out |= node.free_symbols                                 # are not free
        else:
            stack.extend(node.args)
    return out


class Linearization:
    """Symbolic linearization of a model's equations of motion (module docstring).

    Parameters
    ----------
    model : Model
        A valid model (not modified).
    about : str
        ``equilibrium``, ``rest`` or ``spin``.
    spin : float, optional
        Spin rate Omega of the hub [rad/s] (``about = "spin"``); :meth:`at` may change it.
    hub : str, optional
        Revolute joint spun for ``about = "spin"``; by default the only driven revolute joint, else
        the only revolute joint on the ground.
    t0 : float
        Time of the operating point [s]: loads become the inputs' nominal values at t0, and explicit
        functions of time (drivers) are frozen at t0.
    spin_axis : sequence of 3 float, optional
        3D models: spin freely about this axis of the child frame of a spherical or free joint
        (``hub``) instead of driving a revolute hub (:func:`~flexkane.analysis.prepare.prepare_model`).

    Attributes
    ----------
    eom : EquationsOfMotion
        Of the prepared model (:mod:`flexkane.analysis.prepare`).
    q, u : list of sympy.Symbol
        Coordinates and speeds of the linear model, n of each; in 3D, q holds the Euler parameters,
        which the linear model replaces by rotation coordinates (``reduction``).
    reduction : RotationReduction or None
        The map to the independent coordinates of a spatial chain with spherical or free joints
        (:mod:`flexkane.analysis.rotation_reduction`); None otherwise.
    loop_columns : tuple of (list of int, list of int) or None
        With both Euler parameters and closed loops: the positions of the independent (in the order
        of u) and dependent reduced coordinates (:func:`~flexkane.analysis.reduction.loop_columns`);
        ``q`` is then ``q_all``. None otherwise.
    q_all : list of sympy.Symbol
        The coordinates searched for the operating point: ``q`` and the dependent coordinates of
        closed loops.
    dependent : list of sympy.Symbol
        Dependent coordinates of closed loops (empty for open chains).
    dropped : list of sympy.Symbol
        Coordinates prescribed by drivers, not in the linear model.
    r : list of sympy.Symbol
        Inputs (actuator efforts and load components, :mod:`flexkane.kane.inputs`), m of them.
    z : list of sympy.Symbol
        Controller states (empty without ``[controllers]`` states), nz of them; their rates
        ``zdot`` (list of sympy.Expr, nz).
    M, W, V : sympy.Matrix
        Mass matrix M(q) (n, n) and kinematic Jacobians ``dqdot/du`` (n_all, n), ``dqdot/dq``
        (n_all, n_all) at u = 0; the Jacobians of the forcing are in :meth:`symbolic_matrices`.
    output_names : list of str
        Outputs of the linear model: the model's outputs but its energies and loop constraints
        (:func:`~flexkane.analysis.linear_model.linear_outputs`).
    parameters : list of sympy.Symbol
        Order of the constants vector p of the numeric functions.
    notes : list of str
        What the linear model leaves out or assumes, in words.
    """

    def __init__(self, model: Model, *, about: str = "equilibrium", spin: float | None = None,
                 hub: str | None = None, t0: float = 0.0, spin_axis=None):
        from ..derivation_cache import derive

        if isinstance(t0, bool) or not (isinstance(t0, (int, float)) and np.isfinite(t0)):
            raise ModelError("t0", "a finite time [s]", t0)
        self.about = about
        self.t0 = float(t0)
        self.prepared = prepare_model(model, about=about, spin=spin, hub=hub, t0=t0, spin_axis=spin_axis)
        self.model = self.prepared.model
        self.notes = list(self.prepared.notes)
        eom = derive(self.model)
        self.eom = eom
        self.z = list(getattr(eom, "z", None) or [])      # controller states: x = (dq, du, dz)
        self.zdot = list(eom.zdot) if self.z else []
        self.t = eom.t
        self._coordinate = {c.q: c for c in eom.chain.coordinates}
        self.dropped = [q for q in eom.q if self._coordinate[q].driver == "speed"]
        for q in self.dropped:      # a speed law of the state moves q_d with the state: no frozen value
            if self._coordinate[q].state_law:
                owner = self._coordinate[q].owner
                raise ModelError(f"joints.{owner}.driver.speed", "a law of t and the parameters to linearize (a "
                                 "prescribed speed of the state moves its coordinate with the state, which the linear "
                                 "model has no speed for; prescribe the coordinate instead, driver = { coordinate = "
                                 "... })", self.model.joints[owner].driver.speed)
        self.dependent = list(eom.dependent_coordinates) if eom.dependent_speeds else []
        self.q_all = [q for q in eom.q if q not in self.dropped]
        self.q = [q for q in self.q_all if q not in self.dependent]
        self.u = list(eom.u)
        # spatial orientations: three rotation coordinates per set of Euler parameters; with closed
        # loops over all the coordinates, those of the dependent speeds then closed (reduction.py)
        spinning = self.prepared.hub if self.prepared.spin_axis is not None else None
        self.reduction = RotationReduction.of(eom.chain.coordinates, [q.name for q in self.q_all], spinning)
        self.loop_columns = None
        if self.reduction is not None and self.dependent:
            if spinning is not None:
                raise ModelError("--spin-axis", "a chain without closed loops for a free steady spin (its "
                                 "loops would turn with the spinning joint)", self.prepared.spin_axis)
            self.q = list(self.q_all)
            self.loop_columns = loop_columns(self.reduction.speeds, [u.name for u in self.u],
                                             [u.name for u in eom.dependent_speeds])
        elif self.reduction is not None:
            self.reduction = RotationReduction.of(eom.chain.coordinates, [q.name for q in self.q], spinning)
        n_independent = len(self.u) if self.loop_columns is not None else \
            self.reduction.n if self.reduction is not None else len(self.q)
        if n_independent != len(self.u):  # pragma: no cover - the chain gives one speed per coordinate
            raise ModelError("model", "as many independent speeds as coordinates",
                             f"{n_independent} and {len(self.u)}")
        symbols = input_symbols(eom.chain)
        self.inputs = list(self.prepared.inputs)
        self.r = [symbols[ch.name] for ch in self.inputs]
        self._symbols = None
        with activity(f"forming the matrices of {self.model.name}"):    # on stderr when long (flexkane.progress)
            self._form_matrices()
        self._check_dropped()
        self._check_drivers()
        with activity(f"forming the Jacobians and numeric functions of the linearization of {self.model.name}"):
            self._compile()

    # ------------------------------------------------------------------ symbolic
    def _form_matrices(self) -> None:
        eom = self.eom
        at_rest = {u: sp.Integer(0) for u in self.u}
        rows = [k for k, q in enumerate(eom.q) if q not in self.dropped]
        qdot = sp.Matrix([eom.qdot[k] for k in rows])
        n_all = len(self.q_all)
        self.qdot0 = qdot.xreplace(at_rest)
        self.M = eom.mass_matrix
        self.W = qdot.jacobian(self.u).xreplace(at_rest) if n_all and self.u else sp.zeros(n_all, len(self.u))
        self.V = self.qdot0.jacobian(self.q_all) if n_all else sp.zeros(0, 0)
        names = eom.constraint_set.names if self.dependent else []
        self.phi = sp.Matrix([eom.outputs[f"constraint_{name}"] for name in names])
        self.phi_q = self.phi.jacobian(self.q_all) if names else sp.zeros(0, n_all)
        self.output_names = linear_outputs(eom)
        from ..run_manifest import units

        self._units = units(eom)
        self.ud = [eom.chain.ud[u] for u in self.u]
        # f and zdot and their Jacobian with respect to (q_all, u, z, r), in factored form for the numbers
        # (:meth:`_forcing_jacobian`; the outputs' with respect to (q_all, u, u', z, r) on first use,
        # :meth:`_output_numbers`), formed when their code is not in the cache (:meth:`_compile`)
        self._f_outputs = None
        self._symbolic = None

    def symbolic_matrices(self) -> dict:
        """The symbolic matrices, SymPy Jacobians of ``eom.forcing`` and ``eom.qdot`` at u = 0.

        Returns
        -------
        dict of str to sympy.Matrix
            ``M`` (n, n), ``C = -df/du`` (n, n), ``K = -df/dq`` (n, n_all), ``B = df/dr`` (n, m),
            ``W = dqdot/du`` (n_all, n), ``V = dqdot/dq`` (n_all, n_all) and, for closed loops,
            ``Phi_q`` (constraints, n_all); with controller states also ``K_z = -df/dz`` (n, nz) and
            the Jacobians of zdot ``Z_q`` (nz, n_all), ``Z_u`` (nz, n), ``Z_z`` (nz, nz), ``Z_r``
            (nz, m). Functions of q, z, t, the constants and r. For an open chain
            n_all = n but with Euler parameters (3D: reduced numerically, ``reduction``); a closed one
            is reduced numerically (``K T``, ``V T``, see
            :mod:`flexkane.analysis.reduction`). Formed on first use: for large models (many modes
            with geometric stiffening) this takes long, and the numeric matrices do not need it.
        """
        if self._symbolic is None:
            at_rest = {u: sp.Integer(0) for u in self.u}
            f = self.eom.forcing
            f0 = f.xreplace(at_rest)
            n, m = len(self.u), len(self.r)
            self._symbolic = {
                "M": self.M,
                "C": -f.jacobian(self.u).xreplace(at_rest) if n else sp.zeros(0, 0),
                "K": -f0.jacobian(self.q_all) if n else sp.zeros(0, len(self.q_all)),
                "B": f0.jacobian(self.r) if n and m else sp.zeros(n, m),
                "W": self.W, "V": self.V,
            }
            if self.dependent:
                self._symbolic["Phi_q"] = self.phi_q
            if self.z:
                zdot = sp.Matrix(self.zdot)
                self._symbolic.update({
                    "K_z": -f0.jacobian(self.z) if n else sp.zeros(0, len(self.z)),
                    "Z_q": zdot.jacobian(self.q_all).xreplace(at_rest) if self.q_all else sp.zeros(len(self.z), 0),
                    "Z_u": zdot.jacobian(self.u).xreplace(at_rest) if n else sp.zeros(len(self.z), 0),
                    "Z_z": zdot.jacobian(self.z).xreplace(at_rest),
                    "Z_r": zdot.jacobian(self.r).xreplace(at_rest) if m else sp.zeros(len(self.z), 0)})
        return self._symbolic

    def _equation_symbols(self) -> set:
        """The free symbols of M, the forcing, the rates at rest, the constraints and the
        controller rates (formed once: :func:`free_symbols`)."""
        if self._symbols is None:
            self._symbols = free_symbols(list(self.M) + list(self.eom.forcing) + list(self.qdot0)
                                         + list(self.phi) + self.zdot)
        return self._symbols

    def _appears(self, symbol) -> bool:
        return symbol in self._equation_symbols() or symbol in free_symbols(self.W)

    def _check_dropped(self) -> None:
        for q in self.dropped:
            owner = self._coordinate[q].owner
            if not self._appears(q):
                self.notes.append(f"{q.name} (joint {owner}, prescribed speed) does not appear in the "
                                  "equations (cyclic): dropped from the linear model")
            elif self.about == "spin" and owner == self.prepared.hub:
                hint = " (--set g=0 removes gravity)" if self.model.gravity is not None else ""
                raise NoEquilibriumError(
                    "spin", f"no steady spin of joint {owner}: its angle {q.name} appears in the equations "
                    "(through gravity, a spring, a load or a closed loop), so a constant spin is not a steady "
                    f"motion and the linear model would be periodic in time{hint}")
            else:
                self.notes.append(f"{q.name} (joint {owner}) is prescribed by a driver: dropped from the "
                                  f"linear model, its value frozen at t0 = {self.t0:g} s")
        if self.dependent:
            names = [q.name for q in self.dependent] if self.loop_columns is None else \
                [self.reduction.names[j] for j in self.loop_columns[1]]
            self.notes.append("closed loops: " + ", ".join(names) + " follow the independent coordinates (dq = T dq_i)")
        if self.t in self._equation_symbols():
            self.notes.append(f"the equations depend explicitly on time (drivers, loads): frozen at t0 = {self.t0:g} s")

    def _check_drivers(self) -> None:
        """A driver other than the steady spin must be at rest at t0 for an equilibrium."""
        from ..expressions import time_derivative, to_float

        values = self.eom.constant_values(self.model)
        values[self.t] = self.t0
        for c in self.eom.chain.coordinates:
            if c.driver is None or (self.about == "spin" and c.owner == self.prepared.hub):
                continue
            path = f"joints.{c.owner}.driver"
            if c.state_law:     # a law of the state: at rest with the state, its rate is dL/dt at fixed q, z
                law = self.eom.expand(c.law)
                rate = time_derivative(law, self.t, path=path)
                if rate == 0:
                    continue
                state = dict(zip([*self.eom.q, *self.eom.u, *self.z], self.eom.initial_state(self.model)))
                values = {**values, **state}
                law = law.xreplace(self.eom.substitutions)
            else:
                law = c.law
                rate = c.law if c.driver == "speed" else time_derivative(c.law, self.t, path=path)
            speed = to_float(rate, values, path=path)
            if abs(speed) > 1e-12 * max(1.0, abs(to_float(law, values, path=path))):
                raise NoEquilibriumError(
                    self.about, f"{self.model.name} has no equilibrium at t0 = {self.t0:g} s: joint {c.owner} "
                    f"is driven at {speed:.6g} (rad/s or m/s) there, so the chain is not at rest; linearize "
                    "about a steady spin instead (--about spin --spin OMEGA) or at a time when the driver "
                    "is at rest (--t0)")

    # ------------------------------------------------------------------ numeric
    def _compile(self) -> None:
        eom = self.eom
        extra = [r for r in self.r if r not in eom.constants]
        self.parameters = list(eom.constants) + extra
        self._values = eom.constant_values(self.model)
        self.p = np.array([self._values[s] for s in self.parameters], dtype=float)
        state0 = eom.initial_state(self.model)
        index = {q: k for k, q in enumerate(eom.q)}
        self.q_initial = np.array([state0[index[q]] for q in self.q_all], dtype=float)
        nq, nu = len(eom.q), len(eom.u)
        self.z_initial = np.array(state0[nq + nu:nq + nu + len(self.z)], dtype=float)
        self.dropped_values = np.array([self._dropped_value(q, state0[index[q]]) for q in self.dropped])
        args = [*self.q_all, *self.dropped, *self.u, *self.z, self.t, *self.parameters]
        self._f_forcing = numeric_function(args, *self._forcing_jacobian())
        self._f_mass = numeric_function(args, self.M)
        self._f_kinematic = numeric_function(args, self._kinematic_matrices())
        self._args_symbols = args
        self._cache = (None, None)

    def _forcing_jacobian(self) -> tuple:
        """f and zdot and their Jacobian with respect to (q_all, u, z, r), in factored form
        (:func:`~flexkane.analysis.jacobian.forward_jacobian`): the arguments ``(exprs, jacobian)`` of
        :func:`~flexkane.analysis.jacobian.numeric_function`."""
        fj = forward_jacobian(list(self.eom.forcing) + self.zdot, [*self.q_all, *self.u, *self.z, *self.r])
        return [fj.values, fj.jacobian], fj

    def _kinematic_matrices(self) -> list:
        """qdot at rest, W, V, the loop constraints and their Jacobian; with a free spin, the rates and
        their Jacobian at the spin's speeds u0 (refused with loops: u0 = 0, where they are qdot0 and V)."""
        kinematic = [self.qdot0, self.W, self.V, self.phi, self.phi_q]
        if self.reduction is not None and self.loop_columns is None:
            qdot = sp.Matrix([self.eom.qdot[k] for k, q in enumerate(self.eom.q) if q not in self.dropped])
            kinematic[0], kinematic[2] = qdot, qdot.jacobian(self.q_all)
        return kinematic

    def _dropped_value(self, q, initial: float) -> float:
        """Value of a coordinate with prescribed speed at t0 (its initial value plus the integral)."""
        if self.t0 == 0.0:
            return float(initial)
        from scipy.integrate import quad

        law = self._coordinate[q].law.xreplace({s: v for s, v in self._values.items() if s != self.t})
        rate = sp.lambdify([self.t], law, "numpy")
        return float(initial + quad(lambda s: float(rate(s)), 0.0, self.t0, limit=200)[0])

    def _args(self, w: np.ndarray, p: np.ndarray, u0: np.ndarray | None = None) -> list:
        """Arguments of the numeric functions at ``w = (q_all, z)``, speeds ``u0`` (zero by default), t0."""
        w = np.asarray(w, dtype=float)
        n_all = len(self.q_all)
        u0 = np.zeros(len(self.u)) if u0 is None else u0
        return [*w[:n_all], *self.dropped_values, *u0, *w[n_all:], self.t0, *p]
    def steady_speeds(self, spin: float | None = None) -> np.ndarray:
        """The speeds u0 of the operating point, shape (n,) [rad/s or m/s]: zero, but the angular
        speeds ``Omega * spin_axis`` of a spherical or free joint spinning freely."""
        u0 = np.zeros(len(self.u))
        if self.prepared.spin_axis is not None:
            rate = self.prepared.spin if spin is None else float(spin)
            speeds = {c.u: c.role for c in self.eom.chain.coordinates if c.owner == self.prepared.hub}
            for k, u in enumerate(self.u):
                if speeds.get(u) in ("e1", "e2", "e3"):
                    u0[k] = rate * self.prepared.spin_axis[int(speeds[u][1]) - 1]
        return u0

    def _numbers(self, w: np.ndarray, p: np.ndarray, u0: np.ndarray | None = None) -> dict:
        """Every numeric matrix at ``w = (q_all, z)``, speeds ``u0`` (zero unless a free spin,
        :meth:`steady_speeds`), t0 for constants p (cached for the last point)."""
        key = (np.asarray(w, dtype=float).tobytes(), np.asarray(p, dtype=float).tobytes(),
               None if u0 is None else np.asarray(u0, dtype=float).tobytes())
        if self._cache[0] != key:
            n, n_all, m, nz = len(self.u), len(self.q_all), len(self.r), len(self.z)
            c = self.phi.shape[0]
            args = self._args(w, p, u0)
            as_array = lambda v, shape: np.array(v, dtype=float).reshape(shape)  # noqa: E731
            with np.errstate(all="ignore"):
                values, jacobian = self._f_forcing(*args)
                kin = self._f_kinematic(*args)
                M = self._f_mass(*args)
            J = as_array(jacobian, (n + nz, n_all + n + nz + m))
            values = as_array(values, (n + nz,))
            z_at, r_at = n_all + n, n_all + n + nz
            out = {"f": values[:n], "F_q": J[:n, :n_all], "F_u": J[:n, n_all:z_at], "F_z": J[:n, z_at:r_at],
                   "F_r": J[:n, r_at:], "M": as_array(M, (n, n)), "qdot": as_array(kin[0], (n_all,)),
                   "W": as_array(kin[1], (n_all, n)), "V": as_array(kin[2], (n_all, n_all)),
                   "phi": as_array(kin[3], (c,)), "phi_q": as_array(kin[4], (c, n_all)),
                   "zdot": values[n:], "Z_q": J[n:, :n_all], "Z_u": J[n:, n_all:z_at], "Z_z": J[n:, z_at:r_at],
                   "Z_r": J[n:, r_at:]}
            self._cache = (key, out)
        return self._cache[1]

    def _output_numbers(self, w: np.ndarray, p: np.ndarray, u0: np.ndarray | None = None) -> dict:
        """The outputs and their Jacobians at ``w = (q_all, z)``, speeds u0, u' = 0, t0 for constants p."""
        n, n_all, m, k, nz = len(self.u), len(self.q_all), len(self.r), len(self.output_names), len(self.z)
        if self._f_outputs is None:   # formed once, on first use (campbell diagrams need no outputs)
            with activity(f"forming the Jacobians of the outputs of {self.model.name}"):
                fy = forward_jacobian([self.eom.outputs[name] for name in self.output_names],
                                      [*self.q_all, *self.u, *self.ud, *self.z, *self.r], prefix="_fy")
                self._f_outputs = numeric_function([*self._args_symbols, *self.ud], [fy.values, fy.jacobian], fy)
        with np.errstate(all="ignore"):
            values, jacobian = self._f_outputs(*self._args(w, p, u0), *np.zeros(n))
        J = np.array(jacobian, dtype=float).reshape(k, n_all + 2 * n + nz + m)
        z_at = n_all + 2 * n
        return {"y": np.array(values, dtype=float).reshape(k), "Y_q": J[:, :n_all], "Y_u": J[:, n_all:n_all + n],
                "Y_ud": J[:, n_all + n:z_at], "Y_z": J[:, z_at:z_at + nz], "Y_r": J[:, z_at + nz:]}

    def parameter_values(self, spin: float | None = None) -> np.ndarray:
        """The constants vector p, with the spin rate ``spin`` [rad/s] if given, shape (len(parameters),)."""
        p = self.p.copy()
        if spin is not None:
            if self.about != "spin":
                raise ModelError("--spin", "no spin rate unless --about spin", spin)
            if self.prepared.spin_parameter is None:    # a free spin: in the speeds u0
                return p
            symbol = self.eom.chain.symbols.parameters[self.prepared.spin_parameter]
            if symbol in self.parameters:
                p[self.parameters.index(symbol)] = float(spin)
        return p

    def _load_accelerations(self, q_all: np.ndarray, p: np.ndarray, u0: np.ndarray | None = None) -> float:
        """Size of the accelerations gravity, the nominal inputs and a free spin's velocity forces
        cause [m/s^2 or rad/s^2]."""
        from ..kane.active import gravity_vector

        size = 0.0
        gravity = gravity_vector(self.eom.kinematics) if self.model.dimensions == 2 else \
            (self.model.gravity and (self.eom.kinematics.value("gravity.g", self.model.gravity.g, "g"),))
        if gravity:
            values = dict(zip(self.parameters, p))
            size = float(sp.sqrt(sum(c ** 2 for c in gravity)).xreplace(values))
        if u0 is not None and np.any(u0):   # the velocity forces of the spin, also where they balance
            x = self._numbers(q_all, p, u0)
            try:
                gyroscopic = np.linalg.solve(x["M"], x["F_u"])
                size = max(size, float(np.max(np.abs(gyroscopic @ u0))),
                           float(np.max(np.abs(gyroscopic))) * float(np.max(np.abs(u0))))
            except np.linalg.LinAlgError:
                pass
        if self.r:
            x = self._numbers(q_all, p)
            r0 = np.array(self.prepared.nominal, dtype=float)
            try:
                size = max(size, float(np.max(np.abs(np.linalg.solve(x["M"], x["F_r"] @ r0)))))
            except np.linalg.LinAlgError:
                pass
        return abs(size)

    def _evaluators(self, p: np.ndarray, u0: np.ndarray | None = None) -> dict:
        """The functions of :func:`find_equilibrium` of ``w = (q_all, z)``: with controller states, the
        residual is ``(f, zdot)`` and its Jacobian ``[[F_q, F_z], [Z_q, Z_z]]`` (M extended by the
        identity, so that the controller states' rates are judged as the accelerations)."""
        if not self.z:
            ev = {"forcing": lambda q: self._numbers(q, p, u0)["f"],
                  "stiffness": lambda q: -self._numbers(q, p, u0)["F_q"],
                  "mass": lambda q: self._numbers(q, p, u0)["M"],
                  "rates": lambda q: self._numbers(q, p, u0)["qdot"]}
            if self.dependent:
                ev["constraints"] = lambda q: self._numbers(q, p, u0)["phi"]
                ev["constraint_jacobian"] = lambda q: self._numbers(q, p, u0)["phi_q"]
            return ev
        nz = len(self.z)

        def stiffness(w):
            x = self._numbers(w, p, u0)
            return -np.block([[x["F_q"], x["F_z"]], [x["Z_q"], x["Z_z"]]])

        ev = {"forcing": lambda w: np.concatenate([self._numbers(w, p, u0)["f"], self._numbers(w, p, u0)["zdot"]]),
              "stiffness": stiffness,
              "mass": lambda w: scipy.linalg.block_diag(self._numbers(w, p, u0)["M"], np.eye(nz)),
              "rates": lambda w: self._numbers(w, p, u0)["qdot"]}
        if self.dependent:
            ev["constraints"] = lambda w: self._numbers(w, p, u0)["phi"]
            ev["constraint_jacobian"] = lambda w: np.hstack([self._numbers(w, p, u0)["phi_q"],
                                                             np.zeros((self.phi.shape[0], nz))])
        return ev

    def _project(self, q_all: np.ndarray) -> np.ndarray:
        """Close the loops: the dependent coordinates for the others of ``q_all``."""
        if not self.dependent:
            return np.asarray(q_all, dtype=float)
        index = {q: k for k, q in enumerate(self.eom.q)}
        full = np.zeros(len(self.eom.q))
        for q, v in zip(self.q_all, q_all):
            full[index[q]] = v
        for q, v in zip(self.dropped, self.dropped_values):
            full[index[q]] = v
        full = self.eom.project_coordinates(full, self._values, self.t0)
        return np.array([full[index[q]] for q in self.q_all])

    def operating_point(self, spin: float | None = None, q_start=None) -> EquilibriumCheck:
        """The configuration of the operating point, all coordinates ``q_all``.

        Parameters
        ----------
        spin : float, optional
            Spin rate [rad/s] (``about = "spin"``); the one given at construction by default.
        q_start : array_like, optional
            Starting configuration of the search [m, rad, -]: all coordinates ``q_all``, shape
            (n_all,), or, for a chain with closed loops, planar or spatial, only those the loop
            closure does not solve for (:func:`flexkane.kane.loop_closure.closure_unknowns`: the
            coordinates of the independent speeds, without the Euler parameters of a joint with a
            dependent angular speed), in the order of ``q_all``; the loops are then closed from the
            model's initial guesses. The model's initial coordinates by default. The search finds
            the equilibrium nearest to it, which may be unstable.

        Returns
        -------
        EquilibriumCheck

        Raises
        ------
        NoEquilibriumError
            If no equilibrium is found (``equilibrium``, ``spin``) or the configuration at rest is
            not one (``rest``).
        """
        p = self.parameter_values(spin)
        u0 = self.steady_speeds(spin)
        ev = self._evaluators(p, u0)
        n_all = len(self.q_all)
        start = self.q_initial.copy()
        if q_start is not None:
            given = np.asarray(q_start, dtype=float).ravel()
            solved = set(closure_unknowns(self.eom))
            independent = [k for k, q in enumerate(self.q_all) if q not in solved]
            if given.size == n_all:
                start = given
            elif given.size == len(independent):    # independent coordinates: close the loops from there
                start[independent] = given
                start = self._project(start)
            else:
                raise ModelError("q_start", f"{len(independent)} or {n_all} coordinates [m, rad or -]", given.size)
        loads = self._load_accelerations(np.concatenate([start, self.z_initial]), p, u0)
        elastic = np.array([self._coordinate[q].role in BEAM_ROLES for q in self.q_all], dtype=bool)
        origin = None
        if self.reduction is not None:  # searched in rotation coordinates x about the start (q = origin at x = 0)
            origin = self.reduction.normalize(np.where(elastic, 0.0, start) if self.about == "rest" else start)
            if self.dependent:      # the loops closed along the dependent speeds
                origin = self._project(origin)
            steady = self.reduction.columns(self.prepared.hub) if self.prepared.spin_axis is not None else []
            if self.about != "rest":
                settled = self.reduction.settle(origin, ev, steady)
                if check_equilibrium(np.zeros(self.reduction.n), **self.reduction.wrap(settled, ev, steady),
                                     load_accelerations=loads).ok:
                    origin = settled
            ev = self.reduction.wrap(origin, ev, steady)
            start, elastic = np.zeros(self.reduction.n), np.zeros(self.reduction.n, dtype=bool)
        if self.about == "rest":
            at_rest = start if origin is not None else self._project(np.where(elastic, 0.0, start))
            check = check_equilibrium(np.concatenate([at_rest, self.z_initial]),
                                      **ev, load_accelerations=loads)
            if not check.ok:
                raise NoEquilibriumError(
                    "rest", f"{self.model.name} is not in equilibrium at rest (undeformed, speeds zero): "
                    f"its generalized accelerations are {check.residual:.6g} (m/s^2 or rad/s^2), not 0; "
                    "it moves under gravity or loads (--set g=0 removes gravity; --about equilibrium searches "
                    "for an equilibrium)")
            return self._configuration_of(check, origin)
        check = find_equilibrium(np.concatenate([start, self.z_initial]), **ev, load_accelerations=loads)
        if not check.ok:
            names = ", ".join(f"{q.name} = {v:.6g}" for q, v in zip(self.q_all, start if origin is None else origin)) \
                or "none"
            where = "in the rotating frame of the hub" if self.about == "spin" else "with all speeds zero"
            raise NoEquilibriumError(
                self.about, f"{self.model.name} has no equilibrium {where}: from the initial coordinates "
                f"({names}) the generalized accelerations cannot be brought below {check.residual:.6g} "
                "(m/s^2 or rad/s^2); a chain in free fall under gravity, or pushed by an unbalanced load, has "
                "none. Remove the load (e.g. --set g=0 and --about rest), or start the search elsewhere "
                "(--set on the initial coordinates)")
        return self._configuration_of(check, origin)

    def _configuration_of(self, check: EquilibriumCheck, origin: np.ndarray | None) -> EquilibriumCheck:
        """A check made in rotation coordinates about ``origin``, with its configuration in q_all."""
        if origin is None:
            return check
        return dataclasses.replace(check, q=self.reduction.retract(origin, check.q))

    def at(self, spin: float | None = None, q_start=None, *, outputs: bool = True) -> LinearModel:
        """The numeric linear model at the operating point.

        Parameters
        ----------
        spin : float, optional
            Spin rate [rad/s] (``about = "spin"``); the one given at construction by default.
        q_start : array_like, optional
            Starting configuration of the equilibrium search, all coordinates or the independent
            ones (:meth:`operating_point`).
        outputs : bool
            Form the output matrices (``False``: a model without outputs, for frequencies only; the
            outputs' Jacobians of a large model take as long as the rest).

        Returns
        -------
        LinearModel
        """
        with activity(f"finding the operating point of {self.model.name}"):
            check = self.operating_point(spin, q_start)
        p = self.parameter_values(spin)
        u0 = self.steady_speeds(spin)
        x = self._numbers(check.q, p, u0)
        n, nz = len(self.u), len(self.z)
        names = list(self.output_names) if outputs else []
        y = self._output_numbers(check.q, p, u0) if outputs else \
            {"y": np.zeros(0), "Y_q": np.zeros((0, len(self.q_all))), "Y_u": np.zeros((0, n)),
             "Y_ud": np.zeros((0, n)), "Y_z": np.zeros((0, nz)), "Y_r": np.zeros((0, len(self.r)))}
        independent = [k for k, q in enumerate(self.q_all) if q not in self.dependent]
        dependent = [k for k, q in enumerate(self.q_all) if q in self.dependent]
        T = closure_map(x["phi_q"], independent, dependent) if self.reduction is None else None
        fixed = {q.name: float(v) for q, v in zip(self.dropped, self.dropped_values)}
        fixed.update({self.q_all[k].name: float(check.q[k]) for k in dependent})
        dropped = {q.name: ("cyclic" if not self._appears(q) else "prescribed, frozen") for q in self.dropped}
        dropped.update({q.name: "dependent (closed loop)" for q in self.dependent})
        if self.reduction is None:
            coordinates, q0 = [q.name for q in self.q], check.q[independent].copy()
            W, V = x["W"][independent], (x["V"] @ T)[independent]
            dependent_map = T[dependent]
        else:       # rotation coordinates (rotation_reduction), the loops' dependent ones closed (reduction)
            T_r, back = self.reduction.tangent(check.q)
            n_r = self.reduction.n
            closing, (kept, moved) = np.eye(n_r), (list(range(n_r)), [])
            if self.loop_columns is not None:
                kept, moved = self.loop_columns
                closing = closure_map(x["phi_q"] @ T_r, kept, moved)
                for q in self.dependent:        # Euler parameters: their rotation coordinates instead
                    dropped.pop(q.name, None)
                dropped.update({self.reduction.names[j]: "dependent (closed loop)" for j in moved})
            T = T_r @ closing
            back = back[kept]
            W, V = back @ x["W"], back @ (x["V"] @ T - self.reduction.tangent(check.q, x["qdot"])[0] @ closing)
            held = self.reduction.reference_rows()
            reduced = self.reduction.tangent(check.q)[1] @ np.where(held, 0.0, check.q)
            coordinates, q0 = [self.reduction.names[j] for j in kept], reduced[kept]
            fixed.update({self.q_all[k].name: float(check.q[k]) for k in np.flatnonzero(held)})
            dependent_map = closing[moved]
            self._check_steady(-x["F_q"] @ T, x["F_u"] @ u0, u0)
        spin_value = None
        if self.prepared.spin_axis is not None:
            spin_value = float(self.prepared.spin if spin is None else spin)
        elif self.about == "spin":
            symbol = self.eom.chain.symbols.parameters[self.prepared.spin_parameter]
            spin_value = float(p[self.parameters.index(symbol)]) if symbol in self.parameters \
                else float(self.model.parameters[self.prepared.spin_parameter])
        return LinearModel(
            name=self.model.name, about=self.about, spin=spin_value, hub=self.prepared.hub, t0=self.t0,
            coordinates=coordinates, speeds=[u.name for u in self.u],
            inputs=list(self.inputs), output_names=names,
            q0=q0, r0=np.array(self.prepared.nominal, dtype=float),
            M=x["M"], C=-x["F_u"], K=-x["F_q"] @ T, B=x["F_r"].reshape(n, len(self.r)),
            W=W, V=V,
            C_out=np.hstack([y["Y_q"] @ T, y["Y_u"], y["Y_z"]]), C_acc=y["Y_ud"], D_out=y["Y_r"], y0=y["y"],
            dropped=dropped, fixed=fixed,
            dependent_map=dependent_map, notes=list(self.notes), residual=check.residual, linearization=self,
            output_units={k: self._units.get(k, "") for k in names},
            controller_states=[z.name for z in self.z], z0=check.q[len(self.q_all):].copy(),
            K_z=-x["F_z"], Z_x=np.hstack([x["Z_q"] @ T, x["Z_u"], x["Z_z"]]),
            Z_r=x["Z_r"].reshape(nz, len(self.r)))

    def _check_steady(self, K: np.ndarray, gyroscopic: np.ndarray, u0: np.ndarray) -> None:
        """A free spin is a steady motion only if the forces do not change as the joint turns:
        ``K w0 = 0`` in its rotation coordinates (else the linear model would be periodic in time)."""
        if self.prepared.spin_axis is None:
            return
        cols = self.reduction.columns(self.prepared.hub)
        w0 = np.array([u0[k] for k, u in enumerate(self.u) if u in self._hub_speeds()])
        drift = float(np.max(np.abs(K[:, cols] @ w0), initial=0.0))
        rate = float(np.max(np.abs(w0), initial=0.0))
        scale = rate * max(float(np.max(np.abs(K), initial=0.0)), float(np.max(np.abs(gyroscopic), initial=0.0)))
        if drift > 1e-9 * scale:
            raise NoEquilibriumError(
                "spin", f"no steady spin of joint {self.prepared.hub} about the axis "
                f"({', '.join(f'{c:g}' for c in self.prepared.spin_axis)}): the generalized forces change as "
                f"it turns (at {drift:.6g} per second; gravity, a spring or a load not symmetric about the "
                "spin axis), so the linear model would be periodic in time")

    def _hub_speeds(self) -> list:
        """The angular speeds of a freely spinning joint, in the order wx, wy, wz."""
        by_role = {c.role: c.u for c in self.eom.chain.coordinates if c.owner == self.prepared.hub}
        return [by_role[role] for role in ("e1", "e2", "e3")]

    def to_control(self, spin: float | None = None, q_start=None):
        """The linear model at the operating point (:meth:`at`) as a python-control ``StateSpace``
        with named states, inputs and outputs (:meth:`LinearModel.to_control`)."""
        return self.at(spin, q_start).to_control()

    # ------------------------------------------------------------------ configurations
    def configuration(self, linear: LinearModel, q: np.ndarray) -> dict:
        """Every coordinate of the equations for the linear model's coordinates ``q`` (n,).

        Dependent coordinates of closed loops are first moved along ``dq_d = T_d dq`` and then
        projected back onto the loop constraints; prescribed coordinates keep their values at t0.

        Returns
        -------
        dict of sympy.Symbol to float
        """
        q = np.asarray(q, dtype=float)
        if self.reduction is not None:      # rotation coordinates: orientations turned exactly
            x = q - linear.q0
            if self.loop_columns is not None:   # the loops' dependent rotation coordinates moved along, closed
                kept, moved = self.loop_columns
                x = np.zeros(self.reduction.n)
                x[kept], x[moved] = q - linear.q0, linear.dependent_map @ (q - linear.q0)
            q_all = self._project(self.reduction.retract(self.full_operating_point(linear), x))
            out = {s: float(v) for s, v in zip(self.q_all, q_all)}
            out.update({s: float(v) for s, v in zip(self.dropped, self.dropped_values)})
            return out
        values = dict(zip(self.q, q))
        guess = {name: v for name, v in linear.fixed.items()}
        if self.dependent:
            moved = linear.dependent_map @ (q - linear.q0)
            for k, d in enumerate(self.dependent):
                guess[d.name] = linear.fixed[d.name] + moved[k]
        q_all = np.array([values[s] if s in values else guess[s.name] for s in self.q_all])
        q_all = self._project(q_all)
        out = {s: float(v) for s, v in zip(self.q_all, q_all)}
        out.update({s: float(v) for s, v in zip(self.dropped, self.dropped_values)})
        return out

    def full_operating_point(self, linear: LinearModel) -> np.ndarray:
        """All coordinates ``q_all`` of a linear model's operating point, shape (n_all,)."""
        values = dict(zip(linear.coordinates, linear.q0))   # plain coordinates keep their names
        return np.array([values[s.name] if s.name in values else linear.fixed[s.name] for s in self.q_all])


def linearize(model: Model, *, about: str = "equilibrium", spin: float | None = None,
              hub: str | None = None, t0: float = 0.0, q_start=None, spin_axis=None) -> LinearModel:
    """Linearize a model's equations of motion about an operating point.

    Parameters
    ----------
    model : Model
        A valid model.
    about : str
        ``equilibrium`` (searched from the initial coordinates), ``rest`` (undeformed, at rest) or
        ``spin`` (a hub turning at the constant rate ``spin``).
    spin : float, optional
        Spin rate Omega [rad/s], with ``about = "spin"`` only.
    hub : str, optional
        Revolute joint to spin.
    t0 : float
        Time of the operating point [s].
    q_start : array_like, optional
        Starting configuration of the equilibrium search, all coordinates or the independent ones (see
        :meth:`Linearization.operating_point`).
    spin_axis : sequence of 3 float, optional
        3D models: a free steady spin of the spherical or free joint ``hub`` about this axis of its
        child frame (see :class:`Linearization`).

    Returns
    -------
    LinearModel
        ``M du' + C du + K dq = B dr``, ``dq' = W du + V dq`` and the state-space form.

    Raises
    ------
    NoEquilibriumError
        (a :class:`~flexkane.errors.ModelError`) when the operating point does not exist.
    """
    return Linearization(model, about=about, spin=spin, hub=hub, t0=t0, spin_axis=spin_axis).at(q_start=q_start)
