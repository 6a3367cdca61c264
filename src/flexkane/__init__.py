"""flexkane: dynamics of planar and spatial kinematic chains with continuous flexible links, by Kane's method.

The pipeline, one public function per stage::

    model = flexkane.builtin_model("falling-beam-exact")      # or flexkane.load_model("arm.toml")
    eom = flexkane.derive(model)                               # Kane's equations, M(q,t) u' = f(q,u,t) (cached)
    compiled = flexkane.compile_model(eom)                     # Numba right-hand side, cached on disk
    results = flexkane.simulate(compiled, t_end=1.0, dt_out=0.01)
    results["q4"], results["energy"]

The public names are imported on first use (PEP 562), so that ``import flexkane`` and the command
line's ``--help``, ``--version`` and ``check`` do not load SymPy, SciPy, Numba or matplotlib.
"""

from __future__ import annotations

import importlib

from ._version import __version__

#: Public name -> module (relative to this package) that defines it.
_PUBLIC = {
    "builtin_model": ".builtin", "builtin_names": ".builtin",
    "EquationsOfMotion": ".kane", "derive": ".derivation_cache",
    "Model": ".model", "dumps_model": ".model", "load_model": ".model", "loads_model": ".model",
    "save_model": ".model",
    "Results": ".results", "load_results": ".results",
    "compile_model": ".simulation", "simulate": ".simulation",
    "linearize": ".analysis", "modal_analysis": ".analysis",
    "FlexkaneError": ".errors", "ModelError": ".errors", "SolverFailure": ".errors",
    "MissingExtraError": ".extras",
    "export_c": ".c_export",
}

#: Subpackages reachable as attributes after ``import flexkane`` (imported on first access).
_SUBPACKAGES = {"analysis"}

__all__ = ["__version__", "Model", "load_model", "loads_model", "dumps_model", "save_model",
           "builtin_model", "builtin_names", "derive", "EquationsOfMotion", "compile_model", "simulate",
           "Results", "load_results", "linearize", "modal_analysis",
           "FlexkaneError", "ModelError", "SolverFailure", "MissingExtraError", "export_c"]


def __getattr__(name: str):
    """Import a public name's module on first access and cache the name here."""
    if name in _SUBPACKAGES:
        value = importlib.import_module(f".{name}", __name__)
        globals()[name] = value
        return value
    module = _PUBLIC.get(name)
    if module is None:
        raise AttributeError(f"module 'flexkane' has no attribute {name!r}")
    value = getattr(importlib.import_module(module, __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_PUBLIC) | _SUBPACKAGES)
