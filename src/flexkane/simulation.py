"""Simulation: compile the equations of motion once, integrate them, evaluate the outputs.

``compile_model(eom)`` generates the Numba right-hand side of ``M u' = f`` with ``q' = qdot`` and
loads (or builds) it from the on-disk cache; ``simulate(compiled, ...)`` integrates it on an output
grid with dense output and returns :class:`~flexkane.results.Results`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import sympy as sp

from . import __version__
from .errors import ModelError
from .kane import EquationsOfMotion
from .model import Model, dumps_model
from .results import Results

__all__ = ["COMPILING_MESSAGE", "CompiledModel", "compile_model", "simulate", "output_grid", "OutputEvaluator",
           "work_integrands"]


def output_grid(t_end: float, dt_out: float) -> np.ndarray:
    """Output times 0, dt, 2 dt, ..., t_end [s] (t_end included even when not a multiple of dt)."""
    if not (t_end > 0 and np.isfinite(t_end)):
        raise ModelError("--t-end", "a positive end time [s]", t_end)
    if not (dt_out > 0 and np.isfinite(dt_out)):
        raise ModelError("--dt-out", "a positive output interval [s]", dt_out)
    count = int(np.floor(t_end / dt_out + 1e-9))
    if count > 10_000_000:
        raise ModelError("--dt-out", "at most 10 million output rows", f"{count} rows")
    grid = np.arange(count + 1) * dt_out
    if t_end - grid[-1] > 1e-9 * t_end:
        grid = np.append(grid, t_end)
    else:
        grid[-1] = t_end if abs(grid[-1] - t_end) < 1e-9 * t_end else grid[-1]
    return grid


class OutputEvaluator:
    """Vectorised evaluation of the outputs of an equation set over many samples.

    Parameters
    ----------
    eom : EquationsOfMotion
    """

    def __init__(self, eom: EquationsOfMotion):
        self.eom = eom
        self.names = list(eom.outputs)
        args = [eom.t] + list(eom.q) + list(eom.u) + list(eom.ud) + list(eom.constants)
        self._needs_ud = any(e.free_symbols & set(eom.ud) for e in eom.outputs.values())
        self._f = sp.lambdify(args, [eom.outputs[k] for k in self.names], modules="numpy", cse=True)

    def __call__(self, t: np.ndarray, state: np.ndarray, p: np.ndarray, ud: np.ndarray | None) -> dict:
        """Outputs at times ``t`` (N,), states (N, n), constants p, and speed derivatives ud (N, nu)."""
        nq = len(self.eom.q)
        nu = len(self.eom.u)
        cols = [t] + [state[:, k] for k in range(nq + nu)]
        if ud is None:
            ud = np.zeros((len(t), nu))
        cols += [ud[:, k] for k in range(nu)] + list(p)
        with np.errstate(all="ignore"):
            values = self._f(*cols)
        return {k: np.broadcast_to(np.asarray(v, dtype=float), t.shape).copy() for k, v in zip(self.names, values)}


@dataclass
class CompiledModel:
    """Equations of motion with their compiled right-hand side.

    Attributes
    ----------
    eom : EquationsOfMotion
    module : module
        Generated Numba module (``rhs`` and the integrators).
    key : str
        Cache key of the generated module.
    compile_time : float
        Seconds spent generating, loading and compiling the module [s] (timing: the only field
        that depends on the machine).
    """

    eom: EquationsOfMotion
    module: object
    key: str
    compile_time: float
    _outputs: OutputEvaluator | None = None

    @property
    def outputs(self) -> OutputEvaluator:
        if self._outputs is None:
            self._outputs = OutputEvaluator(self.eom)
        return self._outputs

    def rhs(self, t: float, y: np.ndarray, p: np.ndarray) -> np.ndarray:
        """First-order right-hand side dy/dt, shape (n,)."""
        dy = np.empty_like(np.asarray(y, dtype=float))
        self.module.rhs(float(t), np.asarray(y, dtype=float), np.asarray(p, dtype=float), dy)
        return dy


#: Message of :func:`compile_model` while Numba compiles a new model structure.
COMPILING_MESSAGE = "compiling the right-hand side of this model structure (once)"


def work_integrands(eom: EquationsOfMotion) -> dict:
    """Integrands of the quadrature states of a run: ``{"work": power}`` [W], or ``{}``.

    The power of the non-conservative forces (drivers with their efforts, applied loads, actuator
    torques, dampers; :mod:`flexkane.kane.outputs`) is integrated with the motion, so the work
    ``W`` and the balance ``E - E0 - W`` are exact to the solver's tolerance. A model without such
    forces (power identically 0) gets none.
    """
    power = eom.outputs.get("power_nonconservative", sp.Integer(0))
    return {} if power == 0 else {"work": power}


def compile_model(eom: EquationsOfMotion, cache_dir=None, *, announce=None) -> CompiledModel:
    """Generate, build (or load from the cache) and compile the right-hand side of an equation set.

    Parameters
    ----------
    eom : EquationsOfMotion
    cache_dir : path-like, optional
        Root of the compiled-model cache (default: ``$FLEXKANE_CACHE_DIR`` or ``~/.cache/flexkane``).
    announce : callable, optional
        ``announce(text)`` is called with :data:`COMPILING_MESSAGE` before Numba compiles a model
        structure that is not in the cache yet.

    Returns
    -------
    CompiledModel
        Its integrators are compiled (or loaded from the disk cache) already, so that
        ``compile_time`` holds the whole compilation and a simulation's ``wall_time`` none of it.
    """
    from .numerics.codegen import generate_rhs_source

    if not isinstance(eom, EquationsOfMotion):
        raise ModelError("eom", "EquationsOfMotion from flexkane.derive", type(eom).__name__)
    from .numerics.integrate import compile_integrators
    from .numerics.jit_module import build_module, is_compiled, structure_key

    start = time.perf_counter()
    source = generate_rhs_source(eom, quadratures=work_integrands(eom))
    key = structure_key(__version__, source)
    module = build_module(source, key, cache_dir)
    if announce is not None and not is_compiled(module):
        announce(COMPILING_MESSAGE)
    compile_integrators(module)
    return CompiledModel(eom, module, key, time.perf_counter() - start)


def simulate(compiled: CompiledModel, *, t_end: float, dt_out: float, rtol: float = 1e-8,
             atol: float = 1e-10, method: str = "auto", model: Model | None = None,
             progress=None, max_steps: int | None = None) -> Results:
    """Integrate a compiled model from its initial state.

    Parameters
    ----------
    compiled : CompiledModel
    t_end : float
        End time [s].
    dt_out : float
        Output interval [s]; rows at 0, dt, ..., t_end come from dense output.
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
        Step budget.

    Returns
    -------
    Results
        ``partial`` is set when the integration stopped early; ``solver["message"]`` says why.
    """
    from .numerics.integrate import integrate

    from .model.validate import validate_run_arguments

    if not isinstance(compiled, CompiledModel):
        raise ModelError("compiled", "a CompiledModel from flexkane.compile_model", type(compiled).__name__)
    validate_run_arguments(t_end=t_end, dt_out=dt_out, rtol=rtol, atol=atol, method=method,
                           max_steps=max_steps, progress=progress)
    eom = compiled.eom
    if model is None:
        model = eom.model
    elif not isinstance(model, Model):
        raise ModelError("model", "a flexkane Model (or None for the derived one)", type(model).__name__)
    else:
        model.validate()
        from .kane.chain import build_chain

        names = [c.q.name for c in build_chain(model).coordinates]
        if names != [c.q.name for c in eom.chain.coordinates]:
            raise ModelError("model", "a model with the structure of the derived one "
                             f"(coordinates {', '.join(c.q.name for c in eom.chain.coordinates)})", ", ".join(names))
    values = eom.constant_values(model)
    p = np.array([values[s] for s in eom.constants], dtype=float)
    y0 = eom.initial_state(model)
    grid = output_grid(t_end, dt_out)
    kwargs = {"rtol": rtol, "atol": atol, "method": method, "progress": progress}
    if max_steps is not None:
        kwargs["max_steps"] = max_steps
    result = integrate(compiled.module, y0, grid, p, **kwargs)
    quadratures = dict(zip(getattr(compiled.module, "QUADRATURE_NAMES", ()),
                           np.asarray(result.quadratures).T))
    n_valid = result.n_valid
    t = grid[:n_valid]
    state = np.asarray(result.y)[:n_valid]
    ud = None
    if n_valid:
        nq = len(eom.q)
        ud = np.array([compiled.rhs(ti, yi, p)[nq:] for ti, yi in zip(t, state)]).reshape(n_valid, -1)
    outputs = compiled.outputs(t, state, p, ud) if n_valid else {k: np.zeros(0) for k in compiled.outputs.names}
    if "energy" in outputs:
        # work of the non-conservative forces, integrated with the motion (0 for a conservative
        # model), and the balance E - E0 - W, which only the solver's error keeps from 0
        work = quadratures.get("work", np.zeros(n_valid))
        outputs["work"] = np.array(work, dtype=float)
        energy = outputs["energy"]
        outputs["energy_balance"] = energy - energy[:1] - outputs["work"] if n_valid else np.zeros(0)
    # timing fields (wall_time, compile_time) are the only ones that depend on the machine
    solver = {"method": result.method, "rtol": rtol, "atol": atol, "status": result.status.name.lower(),
              "message": result.message, "nfev": int(result.nfev), "nsteps": int(result.nsteps),
              "naccept": int(getattr(result, "naccept", 0)), "nreject": int(getattr(result, "nreject", 0)),
              "wall_time": float(result.wall_time), "t_reached": float(result.t_reached),
              "compile_time": float(compiled.compile_time),
              "method_spans": {k: float(v) for k, v in sorted(result.method_spans.items())}}
    return Results(t=t, state=state, state_names=eom.state_names, outputs=outputs,
                   model_text=dumps_model(model), parameters={s.name: values[s] for s in eom.constants},
                   solver=solver, partial=n_valid < len(grid) or int(result.status) != 0)
