"""A controller in the loop: the control inputs set from the state before every right-hand-side evaluation.

A model derived with its control inputs (:mod:`flexkane.kane.inputs`) has one constant of the
constants vector p per input channel (``input_effort_<joint>``, ``input_load_<name>_fx`` ...). With a controller
``f(t, y) -> efforts`` the integrated right-hand side becomes::

    controlled(t, y, p, dy):  p[inputs] = f(t, [q, u]);  return system_rhs(t, y, p, dy)

so the efforts are those of the state at which the integrator evaluates the equations (a continuous
controller, not a sampled one), and a stage, a Jacobian column of Radau IIA and dense output all see
the feedback. ``controlled`` is a Numba function of :data:`~flexkane.numerics.system_function.SIGNATURE`
passed to the compiled-once loops as a first-class function, like the model's own ``system_rhs``.

* **Python controllers** (any callable): ``controlled`` leaves compiled code for the call
  (``numba.objmode``), reads the active controller of the thread (:func:`active_controller`) and
  checks its output: about 20 microseconds per evaluation plus the controller's own time (measured
  on the hub-beam model of the tests, whose right-hand side takes 1.3 microseconds). One wrapper
  per generated module and process (compiled in about a second on first use), whatever the
  controller.
* **Numba controllers** (an ``@njit`` function ``f(t, y)`` returning a float64 array): called
  directly from compiled code, no Python in the loop (about 0.4 microseconds per evaluation
  besides the law); one wrapper per module and controller and process.

A controller's output is checked: an array (or sequence) of one finite value per input channel,
in the order of the channels, or (Python controllers) a dict by channel name (channels it does not
name get 0). A wrong output stops the integration with :data:`CONTROLLER_FAILED`; the caller
(:func:`flexkane.simulate`) then raises a :class:`~flexkane.errors.ModelError` naming what was wrong,
or the controller's own exception.
"""

from __future__ import annotations

import contextlib
import math
import threading

import numpy as np
from numba import njit, objmode

from ..errors import ModelError
from .system_function import SystemFunction

__all__ = ["CONTROLLER_FAILED", "ControlLoop", "Controller", "active_controller", "controlled_system"]

#: Status a controlled right-hand side returns when the controller failed (see :class:`Controller`).
CONTROLLER_FAILED = 6

_ACTIVE = threading.local()


class Controller:
    """A user's control law ``f(t, y) -> efforts`` checked against the model's input channels.

    Parameters
    ----------
    function : callable
        ``f(t, y)`` with t [s] and y the state ``[q, u, z]`` (z: the controller states of the
        model, none in most; shape (nq + nu + nz,), in the order of ``Results.state_names``; a
        spatial model's q holds every Euler parameter, so nq may exceed nu), returning the efforts
        [N m or N]: an array of shape (m,) in the
        order of ``channels``, or a dict by channel name. A Numba ``@njit`` function takes the
        compiled path and must return a float64 array of shape (m,).
    channels : list of str
        Names of the input channels, m of them.

    Attributes
    ----------
    error : BaseException or None
        What went wrong in the last run (the controller's exception, or a :class:`ModelError`
        describing a bad output), None if nothing.
    """

    def __init__(self, function, channels: list[str]):
        if not callable(function):
            raise ModelError("controller", "a function f(t, y) returning the efforts", type(function).__name__)
        if not channels:
            raise ModelError("controller", "a model with control inputs (a revolute or prismatic joint not "
                             "driven, or a load)", "a model without any", show_given=False)
        self.function = function
        self.channels = list(channels)
        self.compiled = _is_numba(function)
        self.error = None

    def efforts(self, t: float, y: np.ndarray) -> np.ndarray:
        """The checked efforts at (t, y), shape (m,).

        Raises
        ------
        ModelError
            For an output that is not m finite numbers (or a dict of channel names to numbers).
        """
        value = self.function(t, y)
        m = len(self.channels)
        if isinstance(value, dict):
            return self._from_dict(value, t)
        try:
            out = np.asarray(value, dtype=np.float64)
        except (TypeError, ValueError):
            out = None
        if out is not None and out.shape == () and m == 1:
            out = out.reshape(1)
        if out is None or out.shape != (m,):
            shape = np.shape(value) if out is not None else "(not numbers)"
            raise ModelError("controller", f"{m} efforts ({', '.join(self.channels)}) as an array or a dict "
                             "by channel name", f"{type(value).__name__} of shape {shape} at t = {t:.6g} s")
        if not math.isfinite(out.dot(out)) and not np.all(np.isfinite(out)):   # one test if all is well
            bad = [name for name, v in zip(self.channels, out) if not np.isfinite(v)]
            raise ModelError("controller", "finite efforts", f"{', '.join(bad)} = "
                             f"{', '.join(repr(float(v)) for v in out[~np.isfinite(out)])} at t = {t:.6g} s")
        return out

    def _from_dict(self, value: dict, t: float) -> np.ndarray:
        unknown = [k for k in value if k not in self.channels]
        if unknown:
            raise ModelError("controller", f"a dict whose keys are input channels ({', '.join(self.channels)})",
                             ", ".join(map(str, unknown)))
        out = np.zeros(len(self.channels))
        for k, name in enumerate(self.channels):
            if name in value:
                out[k] = _number(value[name], name, t)
        return out


def _number(value, name: str, t: float) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ModelError("controller", f"a number for {name}", f"{value!r} at t = {t:.6g} s") from None
    if not np.isfinite(number):
        raise ModelError("controller", "finite efforts", f"{name} = {number!r} at t = {t:.6g} s")
    return number


def _is_numba(function) -> bool:
    from numba.core.registry import CPUDispatcher

    return isinstance(function, CPUDispatcher)


@contextlib.contextmanager
def active_controller(controller: Controller):
    """Make ``controller`` the one the Python wrappers of this thread call, for the ``with`` block."""
    previous = getattr(_ACTIVE, "controller", None)
    _ACTIVE.controller = controller
    controller.error = None
    try:
        yield controller
    finally:
        _ACTIVE.controller = previous


def _python_efforts(t: float, y: np.ndarray, out: np.ndarray) -> int:
    """Evaluate the active controller (object mode); 0, or :data:`CONTROLLER_FAILED` after a failure."""
    controller = _ACTIVE.controller
    if controller.error is not None:
        return CONTROLLER_FAILED
    try:
        out[:] = controller.efforts(t, y)
    except BaseException as exc:  # noqa: BLE001 - handed back to the caller after the integration
        controller.error = exc
        return CONTROLLER_FAILED
    return 0


def _python_wrapper(system_rhs, index: np.ndarray, n_state: int):
    m = index.shape[0]

    @njit(error_model="numpy")
    def controlled(t, y, p, dy):
        out = np.empty(m)
        state = y[:n_state].copy()
        with objmode(status="int64"):
            status = _python_efforts(t, state, out)
        if status != 0:
            return status
        for k in range(m):
            p[index[k]] = out[k]
        return system_rhs(t, y, p, dy)

    return controlled


def _numba_wrapper(system_rhs, function, index: np.ndarray, n_state: int):
    m = index.shape[0]

    @njit(error_model="numpy")
    def controlled(t, y, p, dy):
        out = function(t, y[:n_state].copy())
        if out.shape[0] != m:
            return CONTROLLER_FAILED
        for k in range(m):
            if not np.isfinite(out[k]):
                return CONTROLLER_FAILED
            p[index[k]] = out[k]
        return system_rhs(t, y, p, dy)

    return controlled


def controlled_system(module, controller: Controller, index) -> SystemFunction:
    """The integrated right-hand side of ``module`` with ``controller`` setting the inputs (module docstring).

    Parameters
    ----------
    module : module
        Generated module of a model derived with its control inputs.
    controller : Controller
    index : array_like of int, shape (m,)
        Positions of the input channels in the constants vector p.

    Returns
    -------
    SystemFunction
        Kept on the module (per controller for Numba controllers), so that the wrapper is compiled
        once per process.
    """
    index = np.asarray(index, dtype=np.int64)
    cache = module.__dict__.setdefault("__flexkane_controlled__", {})
    key = (tuple(index), id(controller.function) if controller.compiled else None)
    entry = cache.get(key)
    if entry is None or (controller.compiled and entry[1] is not controller.function):
        system_rhs = getattr(module, "system_rhs", None) or module.rhs
        n_state = module.NQ + module.NU + getattr(module, "NZ", 0)    # [q, u, z], not the work W
        wrapper = (_numba_wrapper(system_rhs, controller.function, index, n_state) if controller.compiled
                   else _python_wrapper(system_rhs, index, n_state))
        entry = (SystemFunction(wrapper), controller.function if controller.compiled else None)
        cache[key] = entry
    return entry[0]


class ControlLoop:
    """A run's controller in the loop: the controlled right-hand side, its checks and its outputs.

    Parameters
    ----------
    module : module
        Generated module of a model derived with its control inputs.
    function : callable
        The control law (:class:`Controller`).
    channels : list of str
        Names of the model's input channels, m of them.
    constant_names : list of str
        Names of the constants vector p (the module's ``CONSTANT_NAMES``).
    t0 : float
        Initial time [s].
    y0 : numpy.ndarray
        Initial state ``[q, u, z]``, shape (nq + nu + nz,).

    Raises
    ------
    ModelError
        If the module's right-hand side folds constants into term tables once per run (a very large
        model, :mod:`flexkane.numerics.large_rhs`), where the inputs could not change during the run,
        or if the controller's output at ``(t0, y0)`` is not one finite effort per channel.
    """

    def __init__(self, module, function, channels: list[str], constant_names: list[str], t0: float,
                 y0: np.ndarray):
        if any(name.endswith("_table_coefficients") for name in vars(module)):
            raise ModelError("controller", "a model whose right-hand side is not tabulated (the inputs of a "
                             "very large right-hand side are folded into its term tables once per run)",
                             "a tabulated right-hand side", show_given=False)
        self.module = module
        self.controller = Controller(function, channels)
        self.index = np.array([list(constant_names).index(name) for name in channels], dtype=np.int64)
        self.n_state = module.NQ + module.NU + getattr(module, "NZ", 0)
        self.controller.efforts(float(t0), np.array(y0[:self.n_state], dtype=float))  # checked once here
        self.system = controlled_system(module, self.controller, self.index)

    def active(self):
        """Context manager: this loop's controller is the thread's active one (Python controllers)."""
        return active_controller(self.controller)

    def check(self, result) -> None:
        """Raise what made the controller fail during ``result`` (an :class:`IntegrationResult`).

        Raises
        ------
        BaseException
            The controller's own exception, or a :class:`ModelError` for a bad output.
        """
        error = self.controller.error
        if error is not None:
            raise error
        if int(result.status) == CONTROLLER_FAILED:   # a compiled controller: find what it returned
            t = float(result.t_reached)
            raise ModelError("controller", f"{len(self.index)} finite efforts ({', '.join(self.controller.channels)})",
                             f"another output near t = {t:.6g} s (the integration stopped there)", show_given=True)

    def efforts(self, t: np.ndarray, state: np.ndarray) -> np.ndarray:
        """The controller's efforts at the output rows, shape (N, m)."""
        return np.array([self.controller.efforts(float(ti), np.array(row[:self.n_state], dtype=float))
                         for ti, row in zip(t, state)]).reshape(len(t), len(self.index))

    def outputs(self, t: np.ndarray, state: np.ndarray, p: np.ndarray) -> dict:
        """The module's outputs at the output rows with each row's efforts, and the efforts by channel name.

        Parameters
        ----------
        t : numpy.ndarray, shape (N,)
        state : numpy.ndarray, shape (N, nq + nu + nz)
        p : numpy.ndarray, shape (n_p,)
            Constants (the inputs' entries are set row by row).

        Returns
        -------
        dict of str to numpy.ndarray, shape (N,)
        """
        from .constant_block import prepared_parameters

        efforts = self.efforts(t, state)
        prepared = prepared_parameters(self.module, np.array(p, dtype=float))
        names = self.module.OUTPUT_NAMES
        values = np.empty((len(t), len(names)))
        for i in range(len(t)):
            prepared[self.index] = efforts[i]
            values[i] = self.module.outputs(np.ascontiguousarray(t[i:i + 1], dtype=np.float64),
                                            np.ascontiguousarray(state[i:i + 1], dtype=np.float64), prepared)[0]
        out = {name: values[:, k].copy() for k, name in enumerate(names)}
        out.update({name: efforts[:, k].copy() for k, name in enumerate(self.controller.channels)})
        return out
