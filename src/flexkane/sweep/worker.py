"""Run one variant, on the sweep's own process or on a Dask worker.

Each process keeps the compiled models it has loaded, by structure key, so a worker builds (or
loads from the on-disk Numba cache) one module per structure and then only integrates. The
equations arrive derived: workers never call :func:`flexkane.derive`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from ..errors import ModelError
from ..model import Model
from .metrics import summary_metrics
from .variants import RunSettings, apply_assignments

__all__ = ["Structure", "Task", "run_variant", "run_batch", "compiled_model"]

#: Compiled models loaded by this process, by structure key.
_COMPILED: dict = {}


@dataclass(frozen=True)
class Structure:
    """What the variants of one structure share; sent to each worker once.

    Attributes
    ----------
    eom : EquationsOfMotion
        The equations, derived once.
    key : str
        Cache key of their compiled module.
    base : Model
        The sweep's base model, to which each variant's assignments are applied.
    """

    eom: object
    key: str
    base: Model


@dataclass(frozen=True)
class Task:
    """One variant: its id, its assignments and the run settings.

    Attributes
    ----------
    variant_id : str
    assignments : tuple of (str, object)
        Values of the varied keys, applied to :attr:`Structure.base`.
    settings : RunSettings
    keep_results : bool
        Return the whole :class:`~flexkane.results.Results` (``--save-trajectories``).
    """

    variant_id: str
    assignments: tuple
    settings: RunSettings
    keep_results: bool = False


def compiled_model(eom, structure_key: str):
    """The compiled model of ``eom``, built or loaded once per process."""
    from ..simulation import compile_model

    compiled = _COMPILED.get(structure_key)
    if compiled is None:
        compiled = compile_model(eom)
        _COMPILED[structure_key] = compiled
    return compiled


def _message(exc: Exception) -> str:
    if isinstance(exc, ModelError):
        return str(exc)
    return f"{type(exc).__name__}: {exc}"


def run_variant(structure: Structure, task: Task) -> dict:
    """Validate, integrate and summarise one variant.

    Parameters
    ----------
    structure : Structure
        Equations and base model of the variant's structure.
    task : Task

    Returns
    -------
    dict
        ``variant`` (id), ``status`` (``ok``, ``failed`` or ``interrupted``), ``error`` (message,
        empty when ok), ``metrics`` (:func:`~flexkane.sweep.metrics.summary_metrics` and
        ``run_time`` [s]) and ``results`` (the Results when ``task.keep_results``, else None).
        Errors of the variant (invalid numbers, solver failure) are returned, not raised.
    """
    from ..simulation import simulate

    start = time.perf_counter()
    record = {"variant": task.variant_id, "status": "failed", "error": "", "metrics": {}, "results": None}
    s = task.settings
    try:
        model = apply_assignments(structure.base, task.assignments).validate()
        compiled = compiled_model(structure.eom, structure.key)
        results = simulate(compiled, t_end=s.t_end, dt_out=s.dt_out, rtol=s.rtol, atol=s.atol,
                           method=s.method, model=model, max_steps=s.max_steps)
        metrics = summary_metrics(results)
    except Exception as exc:  # the variant fails, the sweep goes on
        record["error"] = _message(exc)
        record["metrics"]["run_time"] = time.perf_counter() - start
        return record
    metrics["run_time"] = time.perf_counter() - start
    record["metrics"] = metrics
    if results.solver.get("status") == "interrupted":
        record["status"] = "interrupted"
        return record
    if results.partial:
        record["error"] = str(results.solver.get("message") or "the integration stopped early")
    else:
        record["status"] = "ok"
    if task.keep_results:
        record["results"] = results
    return record


def run_batch(structure: Structure, tasks: list) -> list[dict]:
    """Run several variants of one structure one after the other (one Dask task); their records.

    A batch amortises the latency of a task round trip over its variants. It stops at the first
    interrupted variant (Ctrl-C), whose record is the last one returned.
    """
    records = []
    for task in tasks:
        records.append(run_variant(structure, task))
        if records[-1]["status"] == "interrupted":
            break
    return records
