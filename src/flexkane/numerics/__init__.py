"""Numerics: generated right-hand sides compiled by Numba, and their integrators.

Pipeline: :func:`generate_rhs_source` (SymPy equations -> source text; large models through
:mod:`~flexkane.numerics.large_rhs`, term tables and parts), :func:`build_module` (source ->
compiled, disk-cached module), :func:`integrate` (module -> :class:`IntegrationResult` on a grid
of output times; ``method="auto"`` switches between DOP853 and Radau IIA by counted work, never
by time, see :mod:`~flexkane.numerics.switching`).

The code generators (:mod:`~flexkane.numerics.codegen`, which needs SymPy) are imported on first
use (PEP 562): the child process that compiles a new model structure imports this package without
them.
"""

import importlib

from flexkane.numerics.integrate import (
    METHODS,
    IntegrationResult,
    Status,
    StiffnessEstimate,
    choose_method,
    compile_integrators,
    estimate_stiffness,
    evaluate_outputs,
    integrate,
)
from flexkane.numerics.jit_module import build_module, default_cache_dir, structure_key

__all__ = [
    "METHODS",
    "IntegrationResult",
    "Status",
    "StiffnessEstimate",
    "build_module",
    "choose_method",
    "compile_integrators",
    "default_cache_dir",
    "estimate_stiffness",
    "evaluate_outputs",
    "generate_outputs_source",
    "generate_rhs_source",
    "integrate",
    "structure_key",
]

_LAZY = {"generate_outputs_source": ".codegen", "generate_rhs_source": ".codegen"}


def __getattr__(name: str):
    """Import a code generator's module on first access and keep the name here."""
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(module, __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
