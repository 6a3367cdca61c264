"""Simulation: compile the equations of motion once, integrate them, evaluate the outputs.

``compile_model(eom)`` generates the Numba module of the equations
(:func:`~flexkane.derivation_cache.model_source`: the
right-hand side of ``M u' = f`` with ``q' = qdot``, the quadratures of the work, and the outputs)
and loads (or builds) it from the on-disk cache; ``simulate(compiled, ...)`` integrates it on an
output grid with dense output, evaluates the outputs with the module's compiled ``outputs``
function and returns :class:`~flexkane.results.Results`.

A run needs the symbolic equations only to generate that module and to compute its numbers
(:mod:`flexkane.run_manifest`); :class:`~flexkane.derivation_cache.Derivation` reads both from the
cache when they are there, so that a repeated run imports no SymPy.
"""

from __future__ import annotations

import contextlib
import time
import dataclasses
from dataclasses import dataclass

import numpy as np

from ._version import __version__
from .errors import ModelError
from .model import Model, dumps_model
from .model.columns import Output, Outputs
from .model.validate import MAX_OUTPUT_ROWS, check_output_grid
from .results import Results
from .run_manifest import RUN_OUTPUTS

__all__ = ["COMPILING_MESSAGE", "CompiledModel", "compile_model", "simulate", "output_grid", "output_times",
           "INTEGRATORS_MESSAGE", "initial_state_vector"]


def output_grid(t_end: float, dt_out: float) -> np.ndarray:
    """Output times 0, dt, 2 dt, ..., t_end [s] (t_end included even when not a multiple of dt)."""
    check_output_grid(t_end, dt_out)
    count = int(np.floor(t_end / dt_out + 1e-9))
    if count > MAX_OUTPUT_ROWS:
        raise ModelError("dt_out", "at most 10 million output rows", f"{count} rows")
    grid = np.arange(count + 1) * dt_out
    if t_end - grid[-1] > 1e-9 * t_end:
        grid = np.append(grid, t_end)
    else:
        grid[-1] = t_end if abs(grid[-1] - t_end) < 1e-9 * t_end else grid[-1]
    return grid


def _time(value, name: str) -> float:
    """A finite time [s] given as an argument."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) \
            or not np.isfinite(value):
        raise ModelError(name, "a finite time [s]", value)
    return float(value)


def output_times(*, t_end=None, dt_out=None, t_span=None, t_eval=None, simulation=None):
    """The integration grid of a run and which of its rows are outputs.

    Parameters
    ----------
    t_end, dt_out, t_span, t_eval :
        As :func:`simulate` takes them (``t_end`` or ``t_span``; ``dt_out`` or ``t_eval``).
    simulation : Simulation, optional
        The model's run settings: its ``t_end`` and ``dt_out`` serve when none are given.

    Returns
    -------
    grid : ndarray, shape (M,)
        Strictly increasing times [s] from t0 to t1 the integrator reports at.
    keep : ndarray of bool, shape (M,), or None
        With ``t_eval``: the rows of ``grid`` that are output times (t0 and t1 may be added to
        ``t_eval`` to start and end there); None when every row is an output.

    Raises
    ------
    ModelError
        Naming the argument for a missing, invalid or conflicting time.
    """
    if t_span is not None and t_end is not None:
        raise ModelError("t_span", "either t_span=(t0, t1) or t_end, not both", t_span)
    if t_eval is not None and dt_out is not None:
        raise ModelError("t_eval", "either t_eval (output times) or dt_out (an output interval), not both",
                         None, show_given=False)
    evaluated = None
    if t_eval is not None:
        try:
            evaluated = np.array(t_eval, dtype=float).reshape(-1) if np.ndim(t_eval) <= 1 else None
        except (TypeError, ValueError):
            evaluated = None
        if evaluated is None or evaluated.size == 0 or not np.all(np.isfinite(evaluated)):
            raise ModelError("t_eval", "a 1-D array of finite output times [s]", t_eval)
        if np.any(np.diff(evaluated) <= 0):
            raise ModelError("t_eval", "strictly increasing output times [s]", t_eval)
    if t_span is not None:
        if isinstance(t_span, (str, bytes)) or np.ndim(t_span) != 1 or len(t_span) != 2:
            raise ModelError("t_span", "a pair (t0, t1) of times [s]", t_span)
        t0, t1 = _time(t_span[0], "t_span[0]"), _time(t_span[1], "t_span[1]")
        if not t1 > t0:
            raise ModelError("t_span", "(t0, t1) with t1 > t0 [s]", t_span)
    elif evaluated is not None and t_end is None:
        t0, t1 = float(evaluated[0]), float(evaluated[-1])
        if not t1 > t0:
            raise ModelError("t_eval", "at least two output times (or a t_span that holds them)", t_eval)
    else:
        if t_end is None:
            t_end = getattr(simulation, "t_end", None)
        if t_end is None:
            raise ModelError("t_end", "an end time [s] (or t_span=(t0, t1)); the model has no simulation.t_end",
                             None, show_given=False)
        t0, t1 = 0.0, _time(t_end, "t_end")
    if evaluated is not None:
        if evaluated[0] < t0 or evaluated[-1] > t1:
            raise ModelError("t_eval", f"output times within t_span = ({t0:g}, {t1:g}) [s]",
                             f"times from {evaluated[0]:g} to {evaluated[-1]:g}")
        grid = np.unique(np.concatenate([[t0], evaluated, [t1]]))
        keep = np.isin(grid, evaluated)
        return grid, (None if keep.all() else keep)
    if dt_out is None:
        dt_out = getattr(simulation, "dt_out", None) or (t1 - t0) / 100
    grid = output_grid(t1 - t0, dt_out)
    if t0 != 0.0:
        grid = t0 + grid
        grid[-1] = t1
    return grid, None


def initial_state_vector(y0, state_names: list) -> np.ndarray:
    """An initial state given as an array, checked against the state's names.

    Parameters
    ----------
    y0 : array_like, shape (n,)
        Coordinates then speeds, in the order of ``state_names``.
    state_names : list of str, length n

    Returns
    -------
    ndarray, shape (n,)
    """
    n = len(state_names)
    try:
        state = np.array(y0, dtype=float)
    except (TypeError, ValueError):
        raise ModelError("y0", f"{n} numbers ({', '.join(state_names)})", y0) from None
    if state.shape != (n,):
        raise ModelError("y0", f"{n} numbers ({', '.join(state_names)})", f"an array of shape {state.shape}")
    if not np.all(np.isfinite(state)):
        raise ModelError("y0", "finite numbers", y0)
    return state


@dataclass
class CompiledModel:
    """Equations of motion with their compiled module.

    Attributes
    ----------
    derivation : Derivation
        The equations as a run uses them (:class:`flexkane.derivation_cache.Derivation`).
    module : module
        Generated Numba module (``rhs``, ``outputs`` and the integrators).
    key : str
        Cache key of the generated module.
    compile_time : float
        Seconds spent generating, loading and compiling the module [s] (timing: the only field
        that depends on the machine).
    """

    derivation: object
    module: object
    key: str
    compile_time: float

    @property
    def eom(self):
        """The symbolic equations (:class:`~flexkane.kane.EquationsOfMotion`; loaded on first use)."""
        return self.derivation.eom

    def rhs(self, t: float, y: np.ndarray, p: np.ndarray) -> np.ndarray:
        """First-order right-hand side dy/dt, shape (n,)."""
        from .numerics.constant_block import prepared_parameters

        dy = np.empty_like(np.asarray(y, dtype=float))
        self.module.rhs(float(t), np.asarray(y, dtype=float), prepared_parameters(self.module, p), dy)
        return dy


#: Message of :func:`compile_model` while Numba compiles a new model structure.
COMPILING_MESSAGE = "compiling the right-hand side of this model structure (once)"
#: Message of :func:`compile_model` while Numba compiles the integrators (once per installation).
INTEGRATORS_MESSAGE = "compiling the integrators DOP853 and Radau IIA (once per installation)"


def compile_model(eom, cache_dir=None, *, announce=None, outputs: bool = True) -> CompiledModel:
    """Generate, build (or load from the cache) and compile the module of an equation set.

    Parameters
    ----------
    eom : EquationsOfMotion or Derivation
        Equations from :func:`flexkane.derive` (or a
        :class:`~flexkane.derivation_cache.Derivation`, which finds them in the cache).
    cache_dir : path-like, optional
        Root of the compiled-model cache (default: ``$FLEXKANE_CACHE_DIR`` or ``~/.cache/flexkane``).
    announce : callable, optional
        ``announce(text)`` is called with :data:`COMPILING_MESSAGE` before Numba compiles a model
        structure that is not in the cache yet, and with :data:`INTEGRATORS_MESSAGE` before it
        compiles the integrators (the first run of an installation).
    outputs : bool
        Compile the outputs functions now (default), so that ``compile_time`` holds the whole
        compilation; False: on their first call (:func:`simulate` calls them), for a caller that
        evaluates the right-hand side only (:meth:`CompiledModel.rhs`).

    Returns
    -------
    CompiledModel
        Its integrators are compiled (or loaded from the disk cache) already, so that
        ``compile_time`` holds the whole compilation and a simulation's ``wall_time`` none of it.
    """
    from .derivation_cache import Derivation

    if isinstance(eom, Derivation):
        derivation = eom
    else:
        from .kane import EquationsOfMotion

        if not isinstance(eom, EquationsOfMotion):
            raise ModelError("eom", "EquationsOfMotion from flexkane.derive", type(eom).__name__)
        derivation = Derivation(eom=eom, cache_dir=cache_dir)
    if not isinstance(outputs, bool):
        raise ModelError("outputs", "True or False (compile the outputs functions now)", outputs)
    from .numerics.integrate import compile_integrators
    from .numerics.jit_module import build_module, integrators_compiled, is_compiled, structure_key
    from .progress import activity, enabled

    start = time.perf_counter()
    if not derivation.manifest["state_names"]:   # derive serves inverse dynamics; a run needs a state
        raise ModelError("joints", "at least one coordinate that no coordinate driver prescribes, or a controller "
                         "state, to integrate (derive gives the drivers' efforts of a fully prescribed motion)",
                         "a chain whose every coordinate a driver prescribes")
    source = derivation.source()
    key = structure_key(__version__, source)
    module = build_module(source, key, cache_dir)
    shown = []   # what Numba compiles here (a first use outside the command line's child process)
    if (announce is not None or enabled()) and not integrators_compiled():
        shown.append(INTEGRATORS_MESSAGE)
    if (announce is not None or enabled()) and not is_compiled(module):
        shown.append(COMPILING_MESSAGE)
    for text in shown if announce is not None else ():
        announce(text)
    with activity("; ".join(shown), delay=0) if shown else contextlib.nullcontext():   # on stderr
        compile_integrators(module, outputs=outputs)
    return CompiledModel(derivation, module, key, time.perf_counter() - start)


def _with_inputs(compiled: CompiledModel) -> CompiledModel:
    """The compiled model of the same structure derived with its control inputs (:mod:`flexkane.kane.inputs`),
    derived and compiled on first use (cached on disk by structure, and on ``compiled``)."""
    from .derivation_cache import Derivation
    from .kane.inputs import with_control_inputs

    model = compiled.derivation.model
    if getattr(model, "control_inputs", False) is True:
        return compiled
    cached = compiled.__dict__.get("_with_inputs")
    if cached is None:
        derivation = Derivation(with_control_inputs(model), compiled.derivation._cache_dir,
                                cache=compiled.derivation._cache)
        cached = compiled.__dict__["_with_inputs"] = compile_model(derivation)
    return cached


def _in_the_loop(compiled: CompiledModel, controller, model: Model, constant_names, t0: float, y0):
    """The :class:`~flexkane.numerics.controller.ControlLoop` of a run."""
    from .kane.inputs import input_channels
    from .numerics.controller import ControlLoop

    channels = [channel.name for channel in input_channels(model)]
    return ControlLoop(compiled.module, controller, channels, constant_names, t0, y0)


def simulate(compiled: CompiledModel, *, t_end: float | None = None, dt_out: float | None = None,
             rtol: float = 1e-8, atol: float = 1e-10, method: str = "auto", model: Model | None = None,
             progress=None, max_steps: int | None = None, t_span=None, t_eval=None, y0=None,
             remember: bool = False, controller=None) -> Results:
    """Integrate a compiled model from its initial state.

    The times are given either as ``t_end`` and ``dt_out`` (rows at 0, dt_out, ..., t_end) or, as
    :func:`scipy.integrate.solve_ivp` takes them, as ``t_span=(t0, t1)`` with ``t_eval`` (the output
    times) or ``dt_out`` (rows at t0, t0 + dt_out, ..., t1).

    Parameters
    ----------
    compiled : CompiledModel
    t_end : float, optional
        End time [s] of a run from t = 0; the model's ``simulation.t_end`` when neither ``t_end``,
        ``t_span`` nor ``t_eval`` is given.
    dt_out : float, optional
        Output interval [s]; rows come from dense output. The model's ``simulation.dt_out``, else
        a hundredth of the time span, when neither ``dt_out`` nor ``t_eval`` is given.
    rtol, atol : float
        Integrator tolerances.
    method : str
        ``auto``, ``dop853`` or ``radau``.
    model : Model, optional
        Model giving the numbers (parameters, initial conditions); the derived one by default.
        Its structure must be that of the derived model.
    progress : callable, optional
        ``progress(t_reached, t_end)`` called between chunks.
    max_steps : int, optional
        Step budget; the model's ``simulation.max_steps``, else 1,000,000.
    t_span : (float, float), optional
        Start and end time ``(t0, t1)`` [s], ``t0 < t1`` (instead of ``t_end``).
    t_eval : array_like, shape (N,), optional
        Output times [s], strictly increasing, within ``t_span`` (instead of ``dt_out``); without
        ``t_span`` the run goes from ``t_eval[0]`` to ``t_eval[-1]``.
    y0 : array_like, shape (n,), optional
        State ``[q, u]`` at ``t0`` in the order of ``Results.state_names`` (instead of the model's
        ``[initial]`` table, or its static equilibrium with ``equilibrium = true``:
        :mod:`flexkane.start_state`); used as given (in a model with loop constraints it must satisfy
        them).
    remember : bool
        Store the model's numbers (constants, initial state) in the cache of its equations, so
        that a run of the same model again needs no SymPy (the command line's runs do).
    controller : callable, optional
        A control law ``f(t, y) -> efforts`` in the loop (:mod:`flexkane.numerics.controller`):
        y is the state ``[q, u, z]`` in the order of ``Results.state_names``; the efforts [N m or N]
        are an array in the order of the model's input channels (:mod:`flexkane.kane.inputs`:
        ``input_effort_<joint>`` of every revolute or prismatic joint not driven, in the order of
        the model, then ``input_load_<name>_fx``, ``_fy``, ``_torque`` of its loads; in 3D ``_fx``,
        ``_fy``, ``_fz``, ``_tx``, ``_ty``, ``_tz``) or a dict by
        channel name (others 0), added to the model's own torques and loads. Evaluated at every
        evaluation of the right-hand side; an ``@njit`` function (returning a float64 array) runs in
        compiled code. The equations with the inputs are derived and compiled on first use (cached
        like any structure). The efforts at the output times are the outputs named by the channels.

    Returns
    -------
    Results
        ``partial`` is set (``success`` false) when the integration stopped early;
        ``message`` says why; ``warnings`` lists where the run left the validity of its model
        (:mod:`flexkane.validity`).

    Raises
    ------
    ModelError
        For invalid or conflicting arguments (``t_end`` with ``t_span``, ``dt_out`` with ``t_eval``,
        output times outside ``t_span``, a ``y0`` of the wrong size ...), before any integration;
        for a controller whose output is not one finite effort per input channel.
    """
    from .model.coordinates import coordinate_names
    from .model.validate import validate_run_arguments
    from .numerics.integrate import evaluate_outputs, integrate

    if not isinstance(compiled, CompiledModel):
        raise ModelError("compiled", "a CompiledModel from flexkane.compile_model", type(compiled).__name__)
    if controller is not None:
        from .kane.inputs import with_control_inputs

        compiled = _with_inputs(compiled)
        model = with_control_inputs(model) if isinstance(model, Model) else model
    derivation = compiled.derivation
    sim = (model if isinstance(model, Model) else derivation.model).simulation
    grid, keep = output_times(t_end=t_end, dt_out=dt_out, t_span=t_span, t_eval=t_eval, simulation=sim)
    if max_steps is None:
        max_steps = getattr(sim, "max_steps", None)
    span = float(grid[-1] - grid[0])   # t_end and dt_out were checked by output_times
    validate_run_arguments(t_end=span, dt_out=span if dt_out is None else dt_out, rtol=rtol, atol=atol,
                           method=method, max_steps=max_steps, progress=progress)
    manifest = derivation.manifest
    if model is None:
        model = derivation.model
    elif not isinstance(model, Model):
        raise ModelError("model", "a flexkane Model (or None for the derived one)", type(model).__name__)
    else:
        model.validate()
        names = [c.q for c in coordinate_names(model)]
        if names != manifest["coordinates"]:
            raise ModelError("model", "a model with the structure of the derived one "
                             f"(coordinates {', '.join(manifest['coordinates'])})", ", ".join(names))
    state_names = manifest["state_names"]
    start = None
    if y0 is None:      # [initial], or the static equilibrium (initial.equilibrium = true)
        from .start_state import start_state

        start = start_state(derivation, model, t0=float(grid[0]), remember=remember)
    numbers = derivation.numbers(model, ("p", "checks"), remember=remember)
    p = np.array(numbers["p"], dtype=float)
    y0 = start.state if start is not None else initial_state_vector(y0, state_names)
    kwargs = {"rtol": rtol, "atol": atol, "method": method, "progress": progress}
    if max_steps is not None:
        kwargs["max_steps"] = max_steps
    control = None
    if controller is not None:
        control = _in_the_loop(compiled, controller, model, manifest["constant_names"], float(grid[0]), y0)
        kwargs["system"] = control.system
        with control.active():
            result = integrate(compiled.module, y0, grid, p, **kwargs)
        control.check(result)
    else:
        result = integrate(compiled.module, y0, grid, p, **kwargs)
    quadratures = dict(zip(getattr(compiled.module, "QUADRATURE_NAMES", ()),
                           np.asarray(result.quadratures).T))
    n_valid = result.n_valid
    partial = n_valid < len(grid) or int(result.status) != 0
    t = grid[:n_valid]
    state = np.asarray(result.y)[:n_valid]
    if keep is not None:   # t_eval: drop the rows added at t0 and t1
        t, state = t[keep[:n_valid]], state[keep[:n_valid]]
        n_valid = len(t)
    # the compiled outputs (u' of the outputs that need it from the compiled rhs, row by row)
    declared = [Output.from_json(d) for d in manifest["outputs"]]
    if control is not None:   # the efforts of the controller by channel (input_effort_<joint> ...)
        from .kane.inputs import input_channels

        declared += [Output(c.name, None, c.unit, "input", f"the controller's input to {c.path}")
                     for c in input_channels(model)]
    with np.errstate(all="ignore"):
        values = evaluate_outputs(compiled.module, t, state, p) if control is None else control.outputs(t, state, p)
        outputs = Outputs.of(declared, {k: np.array(v, dtype=float) for k, v in values.items()})

        spins = evaluate_outputs(compiled.module, t, state, p, name="spin_rates") \
            if hasattr(compiled.module, "spin_rates") else {}
    if "energy" in outputs:
        # work of the non-conservative forces, integrated with the motion (0 for a conservative
        # model), and the balance E - E0 - W, which only the solver's error keeps from 0
        work = np.array(quadratures.get("work", np.zeros(n_valid)), dtype=float)
        energy = outputs["energy"]
        with np.errstate(invalid="ignore"):   # a diverged run: inf - inf is NaN, as it should be
            balance = energy - energy[:1] - work if n_valid else np.zeros(0)
        for declaration, value in zip(RUN_OUTPUTS, (work, balance)):   # work: a name of its own
            outputs.put(dataclasses.replace(declaration, value=value))
    # timing fields (wall_time, compile_time) are the only ones that depend on the machine
    solver = {"method": result.method, "rtol": rtol, "atol": atol, "status": result.status.name.lower(),
              "message": result.message, "nfev": int(result.nfev), "nsteps": int(result.nsteps),
              "naccept": int(getattr(result, "naccept", 0)), "nreject": int(getattr(result, "nreject", 0)),
              "wall_time": float(result.wall_time), "t_reached": float(result.t_reached),
              "compile_time": float(compiled.compile_time),
              "method_spans": {k: float(v) for k, v in sorted(result.method_spans.items())}}
    if start is not None and start.equilibrium is not None:
        solver["equilibrium"] = dict(start.equilibrium)   # the search of the start (start_state)
    from .validity import run_warnings

    warnings = run_warnings(numbers["checks"], model.simulation, t, state, spins)
    if start is not None:
        warnings = start.warnings + warnings
    if model.dimensions == 3:   # given Euler parameters normalized (flexkane.model.initial)
        from .model.initial import initial_values

        warnings = initial_values(model).warnings + warnings
    return Results(t=t, state=state, state_names=list(state_names), outputs=dict(outputs),
                   declared={o.name: o for o in outputs.declarations()},
                   state_units={n: manifest["units"][n] for n in state_names if n in manifest["units"]},
                   model_text=dumps_model(model),
                   parameters=dict(zip(manifest["constant_names"], numbers["p"])),
                   solver=solver, partial=partial, warnings=warnings)
