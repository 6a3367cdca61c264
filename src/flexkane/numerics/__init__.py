"""Numerics: generated right-hand sides compiled by Numba, and their integrators.

Pipeline: :func:`generate_rhs_source` (SymPy equations -> source text; large models through
:mod:`~flexkane.numerics.large_rhs`, term tables and parts), :func:`build_module` (source ->
compiled, disk-cached module), :func:`integrate` (module -> :class:`IntegrationResult` on a grid
of output times; ``method="auto"`` switches between DOP853 and Radau IIA by counted work, never
by time, see :mod:`~flexkane.numerics.switching`).
"""

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


def __getattr__(name: str):
    """The code generators, imported on first use: a cached run loads its module without SymPy."""
    if name in ("generate_outputs_source", "generate_rhs_source"):
        from flexkane.numerics import codegen

        return getattr(codegen, name)
    raise AttributeError(f"module 'flexkane.numerics' has no attribute {name!r}")
