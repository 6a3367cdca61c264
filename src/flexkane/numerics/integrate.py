"""Integrate a generated module over a grid of output times, chunk by chunk.

:func:`integrate` calls the compiled loop (``dop853_chunk`` or ``radau5_chunk``, compiled once per
installation, with the model's right-hand side as a first-class function, see
:mod:`flexkane.numerics.system_function`) on successive chunks of the output grid; between chunks
it reports progress, and a ``KeyboardInterrupt`` or a failure ends the run with the rows computed
so far. The stiff/non-stiff choice of ``method="auto"`` is :func:`choose_method` at the start, then
:class:`~flexkane.numerics.switching.MethodSwitch` during the run.

Nothing here depends on the clock: chunks end after a share of the span or a number of steps
fixed by the model's operation count, and the method choice weighs counted work, so a run gives
the same numbers on any machine load (only ``wall_time`` differs).
"""

from __future__ import annotations

import enum
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numba
import numpy as np

from flexkane.errors import ModelError
from flexkane.model.parts import INTEGRATION_METHODS
from flexkane.numerics.constant_block import prepared_parameters
from flexkane.numerics.dop853 import dop853_chunk
from flexkane.numerics.radau import fd_jacobian, radau5_chunk
from flexkane.numerics.switching import MethodSwitch, chunk_work, evaluation_work
from flexkane.numerics.system_function import FUNCTION_TYPE, system_function

__all__ = ["METHODS", "IntegrationResult", "Status", "StiffnessEstimate", "choose_method", "compile_outputs",
           "compile_integrators", "estimate_stiffness", "evaluate_outputs", "integrate", "integrator_signatures",
           "load_integrators"]

# Method name -> name of its compiled chunk function (a function of the package, not of the model).
METHODS = dict(zip(INTEGRATION_METHODS, ("dop853_chunk", "radau5_chunk"), strict=True))
_CHUNKS = dict(zip(INTEGRATION_METHODS, (dop853_chunk, radau5_chunk), strict=True))

# Work per call of a chunk function: about this fraction of the span (its last step is not
# shortened to end there), and at most this many floating-point operations (counted, see
# :func:`~flexkane.numerics.switching.evaluation_work`; about 0.05 s), in steps of
# CHUNK_STEPS_MIN to CHUNK_STEPS_MAX.
CHUNK_SPAN_FRACTION = 0.01
CHUNK_WORK = 5e7
CHUNK_STEPS_MIN, CHUNK_STEPS_MAX = 50, 100_000
# Evaluations per step, by method, for the chunk's step budget.
_EVALUATIONS_PER_STEP = {"dop853": 12, "radau": 10}


class Status(enum.IntEnum):
    """Outcome of an integration; values 0-4 are the chunk functions' status codes."""

    OK = 0
    STEP_TOO_SMALL = 1
    NON_FINITE = 2
    MAX_STEPS = 3
    SINGULAR_MASS_MATRIX = 4
    INTERRUPTED = 5
    CONTROLLER_FAILED = 6   # a controller in the loop failed (flexkane.numerics.controller)


_MESSAGES = {
    Status.OK: "integration reached t = {t:.6g} s",
    Status.STEP_TOO_SMALL: (
        "step size too small at t = {t:.6g} s: the solution probably becomes singular there "
        "(a blow-up, an impact or a discontinuous input); check the model near that time, or "
        "loosen rtol/atol if they are below about 1e-13"),
    Status.NON_FINITE: (
        "non-finite state or derivative (inf or NaN) at t = {t:.6g} s: the motion diverges or "
        "leaves the domain of an expression (sqrt or log of a negative number, a division by "
        "zero); check the parameters, the initial state and the time laws"),
    Status.MAX_STEPS: (
        "maximum number of steps ({max_steps}) reached at t = {t:.6g} s: try increasing "
        "`max_steps`, loosening rtol, or method='radau' if the model is stiff"),
    Status.SINGULAR_MASS_MATRIX: (
        "singular mass matrix at t = {t:.6g} s: the configuration is degenerate (a zero or "
        "negative mass or inertia, a beam of zero density, or coordinates that do not move "
        "anything); check the parameters"),
    Status.INTERRUPTED: "interrupted by the user at t = {t:.6g} s",
    Status.CONTROLLER_FAILED: "the controller failed at t = {t:.6g} s (it raised, or returned efforts "
                              "that are not finite or not one per input channel)",
}


@dataclass
class IntegrationResult:
    """Output of :func:`integrate`; rows beyond ``n_valid`` were not reached.

    Attributes
    ----------
    t : ndarray (n_valid,)
        Output times reached [s].
    y : ndarray (n_valid, nq + nu)
        States ``[q, u]`` at ``t`` (dense output).
    quadratures : ndarray (n_valid, nw)
        Quadrature states ``W`` at ``t`` (``module.QUADRATURE_NAMES``; e.g. the work of the
        non-conservative forces since ``t_out[0]``), integrated with the state to the same
        tolerances.
    status : Status
        ``Status.OK`` when the whole grid was computed.
    message : str
        Human-readable outcome, with the time reached and the likely cause of a failure.
    nfev, nsteps, naccept, nreject : int
        Right-hand-side evaluations (Jacobians included), attempted, accepted, rejected steps.
    wall_time : float
        Elapsed time [s] (compilation included if :func:`compile_integrators` was not called
        first); the only quantity of a run that depends on the machine.
    method : str
        ``"dop853"`` or ``"radau"`` (when ``"auto"`` was asked: the one that covered most of
        the span).
    t_reached : float
        Last time at which the state is known [s] (may exceed ``t[-1]`` on failure).
    n_valid : int
        Number of rows computed.
    method_spans : dict of str to float
        Simulated time covered by each method [s] (``method="auto"`` may switch, see
        :mod:`flexkane.numerics.switching`).
    """

    t: np.ndarray
    y: np.ndarray
    status: Status
    message: str
    nfev: int
    nsteps: int
    naccept: int
    nreject: int
    wall_time: float
    method: str
    t_reached: float
    n_valid: int
    method_spans: dict = field(default_factory=dict)
    quadratures: np.ndarray | None = None

    @property
    def success(self) -> bool:
        """Whether every requested row was computed."""
        return self.status == Status.OK


@dataclass
class StiffnessEstimate:
    """Eigenvalue summary of the Jacobian at the initial state (see :func:`estimate_stiffness`).

    Attributes
    ----------
    spectral_radius : float
        Largest ``|lambda|`` [1/s].
    resolved_rate : float
        Largest ``|lambda|`` among eigenvalues that any method must follow [1/s]: oscillatory
        or growing ones (``-Re lambda < |Im lambda|``); at least ``1/span``.
    explicit_evaluations, implicit_evaluations : float
        Estimated right-hand-side evaluations of DOP853 and Radau IIA over the span.
    """

    spectral_radius: float
    resolved_rate: float
    explicit_evaluations: float
    implicit_evaluations: float

    @property
    def stiff(self) -> bool:
        """Whether the implicit method is expected to be at least 4 times cheaper."""
        return self.explicit_evaluations > 4.0 * self.implicit_evaluations


def estimate_stiffness(module, t0: float, y0: np.ndarray, p: np.ndarray, span: float,
                       rtol: float, system=None) -> StiffnessEstimate:
    """Estimate the cost of explicit and implicit integration from the Jacobian at ``t0``.

    Parameters
    ----------
    module : module
        Generated module (:func:`~flexkane.numerics.jit_module.build_module`).
    t0 : float
        Initial time [s].
    y0 : ndarray (n,)
        Initial state.
    p : ndarray (n_p,)
        Constants.
    span : float
        Length of the time span [s].
    rtol : float
        Relative tolerance.
    system : SystemFunction, optional
        The right-hand side to estimate (a controlled one, :mod:`flexkane.numerics.controller`);
        the module's ``system_rhs`` by default.

    Returns
    -------
    StiffnessEstimate
        With the rule, for eigenvalues ``lambda`` of the finite-difference Jacobian (all of
        them, ``numpy.linalg.eigvals``, cheap for the n <= a few hundred of planar chains):

        * DOP853 is stable for ``|h lambda| <= 6`` (its stability region reaches -6.4 on the
          real axis and 6.0 on the imaginary axis) and needs ``h omega ~ rtol^(1/9)`` for the
          accuracy of a mode of rate ``omega``: ``12 * span * max(rho / 6, omega / rtol^(1/9))``
          evaluations, ``rho`` the spectral radius, ``omega`` the resolved rate;
        * Radau IIA has no stability limit (L-stable) and needs ``h omega ~ rtol^(1/6)``: about
          ``10 * span * omega / rtol^(1/6)`` evaluations (3 stages, 2-4 Newton iterations).

        Fast *decaying* modes (large ``-Re lambda``) make a model stiff; fast lightly damped
        oscillations do not, since both methods must resolve them.
    """
    y0 = _with_quadratures(module, y0)
    n = y0.shape[0]
    f0 = np.empty(n)
    system = system_function(module) if system is None else system
    code = system.dispatcher(t0, y0, p, f0)
    J = np.zeros((n, n))
    if code == 0 and np.all(np.isfinite(f0)):
        fd_jacobian(system, t0, y0, f0, p, J, np.empty(n), np.empty(n))
    J[~np.isfinite(J)] = 0.0
    lam = np.linalg.eigvals(J) if n else np.zeros(0)
    rho = float(np.max(np.abs(lam))) if n else 0.0
    resolved = np.abs(lam[-lam.real < np.abs(lam.imag)]) if n else np.zeros(0)
    omega = max(1.0 / span, float(resolved.max()) if resolved.size else 0.0)
    explicit = 12.0 * span * max(rho / 6.0, omega / rtol ** (1.0 / 9.0))
    implicit = 10.0 * span * omega / rtol ** (1.0 / 6.0) + (n + 1)
    return StiffnessEstimate(rho, omega, explicit, implicit)


def choose_method(module, t0: float, y0: np.ndarray, p: np.ndarray, span: float,
                  rtol: float, system=None) -> str:
    """Return ``"radau"`` if :func:`estimate_stiffness` finds the model stiff, else ``"dop853"``."""
    return "radau" if estimate_stiffness(module, t0, y0, p, span, rtol, system).stiff else "dop853"


def _as_vector(value, name: str, size: int | None, expected: str) -> np.ndarray:
    array = np.ascontiguousarray(np.asarray(value, dtype=np.float64))
    if array.ndim != 1 or (size is not None and array.shape[0] != size):
        raise ModelError(name, expected, f"array of shape {array.shape}", show_given=True)
    return array


def _message(status: Status, t: float, max_steps: int) -> str:
    return _MESSAGES[status].format(t=t, max_steps=max_steps)


def _system(module):
    """The integrated right-hand side of a generated module (``[q', u', W']``)."""
    return getattr(module, "system_rhs", module.rhs)


def _quadrature_count(module) -> int:
    return int(getattr(module, "NW", 0))


def _motion_count(module) -> int:
    """Length of the state ``y = [q, u, z]`` before the quadratures (z: controller states)."""
    return module.NQ + module.NU + int(getattr(module, "NZ", 0))


def _with_quadratures(module, y: np.ndarray) -> np.ndarray:
    """``[q, u]`` with the quadrature states (0) appended; a full state is returned as is."""
    nw = _quadrature_count(module)
    if nw and y.shape[0] == _motion_count(module):
        return np.concatenate([y, np.zeros(nw)])
    return y


def _chunk_budget(name: str, n: int, rhs_operations: int) -> int:
    """Steps per chunk call: about CHUNK_WORK operations (counted, not timed)."""
    per_step = _EVALUATIONS_PER_STEP[name] * evaluation_work(rhs_operations, n)
    return int(min(max(CHUNK_WORK / per_step, CHUNK_STEPS_MIN), CHUNK_STEPS_MAX))


def integrate(module, y0, t_out, p, *, rtol: float, atol, method: str = "auto",
              progress: Callable[[float, float], None] | None = None,
              max_steps: int = 1_000_000, system=None) -> IntegrationResult:
    """Integrate the generated model from ``t_out[0]`` over the output grid ``t_out``.

    Parameters
    ----------
    module : module
        Generated module from :func:`~flexkane.numerics.jit_module.build_module`.
    y0 : array_like (nq + nu,)
        State ``[q, u]`` at ``t_out[0]``, in the order of ``module.STATE_NAMES``; the quadrature
        states of the module (``module.NW``, if any) start at 0.
    t_out : array_like (N,)
        Strictly increasing output times [s]; the integration starts at ``t_out[0]``.
    p : array_like (n_p,)
        Constants, in the order of ``module.CONSTANT_NAMES`` (units of the model).
    rtol : float
        Relative tolerance (1e-13 < rtol < 1).
    atol : float or array_like (nq + nu,) or (nq + nu + nw,)
        Absolute tolerance, in the units of each state (a scalar also applies to the quadrature
        states; an array of nq + nu entries gives them its largest entry).
    method : {"auto", "dop853", "radau"}
        ``"auto"`` starts with :func:`choose_method` at ``t_out[0]`` and may switch methods
        during the run where the other one is found to do less work
        (:mod:`flexkane.numerics.switching`).
    progress : callable, optional
        ``progress(t_reached, t_end)`` called before the first chunk and between chunks.
    max_steps : int
        Maximum number of attempted steps.
    system : SystemFunction, optional
        The right-hand side to integrate, of the module's state: the module's ``system_rhs`` by
        default, a controlled one (:func:`flexkane.numerics.controller.controlled_system`) for a
        controller in the loop.

    Returns
    -------
    IntegrationResult
        Partial (``n_valid < N``) when the status is not ``Status.OK``. A ``KeyboardInterrupt``
        between chunks gives ``Status.INTERRUPTED`` and the rows computed so far. Everything but
        ``wall_time`` is independent of the machine and its load.
    """
    start = time.perf_counter()
    t_out = _as_vector(t_out, "t_out", None, "a 1-D array of output times [s]")
    if t_out.shape[0] < 1 or not np.all(np.isfinite(t_out)) or np.any(np.diff(t_out) <= 0):
        raise ModelError("t_out", "strictly increasing finite output times [s]", "not so",
                         show_given=False)
    n_motion = _motion_count(module)
    nw = _quadrature_count(module)
    n = n_motion + nw
    y0 = _as_vector(y0, "y0", n_motion, f"{n_motion} initial values {module.STATE_NAMES}")
    p = _as_vector(p, "p", len(module.CONSTANT_NAMES),
                   f"{len(module.CONSTANT_NAMES)} constants {module.CONSTANT_NAMES}")
    if not 1e-13 <= rtol < 1.0:
        raise ModelError("rtol", "a relative tolerance between 1e-13 and 1", rtol)
    atol = np.asarray(atol, dtype=np.float64)
    if atol.ndim == 1 and atol.shape[0] == n_motion and nw:
        atol = np.concatenate([atol, np.full(nw, atol.max() if atol.size else 1.0)])
    try:
        atol = np.ascontiguousarray(np.broadcast_to(atol, (n,)))
    except ValueError:
        raise ModelError("atol", f"a scalar or {n_motion} absolute tolerances", atol) from None
    if np.any(atol <= 0) or not np.all(np.isfinite(atol)):
        raise ModelError("atol", "positive absolute tolerances", atol)
    if not (isinstance(max_steps, (int, np.integer)) and max_steps > 0):
        raise ModelError("max_steps", "a positive integer", max_steps)
    y0 = _with_quadratures(module, y0)
    p = prepared_parameters(module, p)  # a constant block of the mass matrix factored once per run
    t0, t_end = float(t_out[0]), float(t_out[-1])
    switch = None
    if method == "auto":
        switch = MethodSwitch(choose_method(module, t0, y0, p, max(t_end - t0, 1e-300), rtol, system),
                              t0, t_end - t0)
        method = switch.current
    if method not in METHODS:
        raise ModelError("method", f"one of 'auto', {', '.join(map(repr, METHODS))}", method)
    operations = int(getattr(module, "RHS_OPERATIONS", 100))
    system = system_function(module) if system is None else system
    Y = np.full((t_out.shape[0], n), np.nan)
    t, y = t0, y0.copy()
    h_of = {name: 0.0 for name in METHODS}  # step size to try next, by method (0: automatic)
    budget = {name: _chunk_budget(name, n, operations) for name in METHODS}
    started = False  # whether row 0 (y0 at t0) has been written by a chunk call
    nfev = naccept = nreject = 0
    status = Status.OK
    span_step = CHUNK_SPAN_FRACTION * (t_end - t0)
    try:
        if progress is not None:
            progress(t0, t_end)
        while not started or t < t_end:
            name, limit = switch.next_chunk() if switch is not None else (method, None)
            chunk = _CHUNKS[name]
            steps = budget[name] if limit is None else limit
            i_row = int(np.searchsorted(t_out, t, side="right")) if started else 0
            result = chunk(system, t, y, h_of[name], t_out[i_row:], p, rtol, atol,
                           min(steps, max_steps - naccept - nreject), Y[i_row:], t + span_step)
            t_new, y, h_of[name], code, fe, na, nr, ns = result
            t_before, t, started = t, float(t_new), True
            nfev, naccept, nreject = nfev + fe, naccept + na, nreject + nr
            if switch is not None:
                nlu = ns if name == "radau" else 0
                switch.record(name, t_before, t, chunk_work(name, n, operations, fe, na + nr, nlu),
                              na, ns if name == "dop853" else 0, h_of[name])
            if code == Status.MAX_STEPS and naccept + nreject < max_steps:
                code = Status.OK  # only this call's share of the steps is used up
            if code != Status.OK:
                status = Status(code)
                break
            if progress is not None:
                progress(t, t_end)
    except KeyboardInterrupt:
        status = Status.INTERRUPTED
    i_row = int(np.searchsorted(t_out, t, side="right")) if started else 0
    rows = Y if i_row == Y.shape[0] else Y[:i_row]
    return IntegrationResult(
        t=t_out[:i_row].copy(), y=np.ascontiguousarray(rows[:, :n_motion]), status=status,
        message=_message(status, t, max_steps), nfev=nfev, nsteps=naccept + nreject,
        naccept=naccept, nreject=nreject, wall_time=time.perf_counter() - start,
        method=switch.main_method if switch is not None else method, t_reached=t, n_valid=i_row,
        method_spans=dict(switch.covered) if switch is not None else {method: t - t0},
        quadratures=np.ascontiguousarray(rows[:, n_motion:]))


def compile_integrators(module, *, loops: bool = True, outputs: bool = True) -> None:
    """Compile (or load from Numba's disk cache) everything :func:`integrate` calls.

    Numba compiles a function at its first call; calling each function once here, on an empty
    span with the argument types of :func:`integrate`, moves that cost out of the first
    integration (so its time is integration only, and a caller can say that it compiles). The
    integrator loops are the package's (compiled once per installation, whatever the model);
    the model's own functions are its ``rhs``, ``system_rhs`` and outputs functions.

    Parameters
    ----------
    module : module
        Generated module (:func:`~flexkane.numerics.jit_module.build_module`).
    loops : bool
        Also the integrator loops (default). False: the module's own functions only, as the child
        process that compiles a new structure does while its parent loads the loops
        (:func:`load_integrators`) from their cache.
    outputs : bool
        Also the outputs functions (default). False: they compile on their first call (a caller
        that evaluates the right-hand side only).
    """
    n_motion = _motion_count(module)
    n = n_motion + _quadrature_count(module)
    p = np.ones(len(module.CONSTANT_NAMES))
    y = np.zeros(n)
    calls = [(_system(module), (0.0, y, p, np.empty(n))),
             (module.rhs, (0.0, np.zeros(n_motion), p, np.empty(n_motion)))]
    if loops:
        calls += _integrator_calls(system_function(module), n, p)
    if outputs:
        calls += _output_calls(module)
    _call_each(calls)


def compile_outputs(module) -> None:
    """Compile (or load from Numba's disk cache) the outputs functions of a generated module, with
    the argument types of :func:`evaluate_outputs` (what :func:`compile_integrators` compiles besides
    the motion)."""
    _call_each(_output_calls(module))


def _output_calls(module) -> list:
    """``(function, arguments)`` of the module's outputs functions, with evaluate_outputs' types."""
    n_motion = _motion_count(module)
    p = np.ones(len(module.CONSTANT_NAMES))
    return [(getattr(module, name), (np.zeros(0), np.zeros((0, n_motion)), p))
            for name in ("outputs", "spin_rates") if hasattr(module, name)]


def _call_each(calls: list) -> None:
    """Call each ``(function, arguments)``, which compiles it; made-up numbers may fail to compute."""
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        for function, args in calls:
            try:
                function(*args)
            except (ArithmeticError, ValueError):
                pass  # compiled already: only the made-up numbers failed (e.g. a division by 0)


def _integrator_calls(system, n: int, p: np.ndarray) -> list:
    """``(function, arguments)`` of each integrator function that :func:`integrate` calls, on an empty
    span, with the argument types it passes (``system`` the model's first-class function)."""
    y = np.zeros(n)
    t_out = np.zeros(3)[1:]  # a slice, as integrate passes
    Y = np.empty((3, n))[1:]
    calls = [(chunk, (system, 0.0, y, 0.0, t_out, p, 1e-6, np.ones(n), 1, Y, 0.0))
             for chunk in _CHUNKS.values()]
    calls.append((fd_jacobian, (system, 0.0, y, np.zeros(n), p, np.zeros((n, n)), np.empty(n), np.empty(n))))
    return calls


def integrator_signatures() -> list:
    """``(dispatcher, argument types)`` of each integrator function as :func:`integrate` calls it.

    The same for every model: the right-hand side is a first-class function of type
    :data:`~flexkane.numerics.system_function.FUNCTION_TYPE`.
    """
    return [(function, tuple(FUNCTION_TYPE if a is None else numba.typeof(a) for a in args))
            for function, args in _integrator_calls(None, 1, np.ones(1))]


def load_integrators() -> None:
    """Load the integrator loops' machine code from the package's Numba cache, without a model.

    The types of every model's calls are the same (:func:`integrator_signatures`), so this needs
    no module; it compiles them if the cache does not hold them (seconds).
    :func:`compile_integrators` then finds them loaded. A process about to fork a child that
    compiles a new structure calls it first.
    """
    for function, types in integrator_signatures():
        function.compile(types)


def evaluate_outputs(module, t: np.ndarray, y: np.ndarray, p: np.ndarray,
                     name: str = "outputs") -> dict[str, np.ndarray]:
    """Evaluate the generated outputs function over samples.

    Parameters
    ----------
    module : module
        Generated module containing ``generate_outputs_source(..., name=name)``.
    t : ndarray (N,)
        Times [s].
    y : ndarray (N, n)
        States.
    p : ndarray (n_p,)
        Constants.
    name : str
        Name given to the generated function.

    Returns
    -------
    dict of str to ndarray (N,)
        One array per output name.
    """
    prefix = "" if name == "outputs" else name.upper() + "_"
    names = getattr(module, prefix + "OUTPUT_NAMES")
    values = getattr(module, name)(np.ascontiguousarray(t, dtype=np.float64),
                                   np.ascontiguousarray(y, dtype=np.float64),
                                   prepared_parameters(module, p))
    return {key: values[:, k] for k, key in enumerate(names)}
