"""flexkane: dynamics of planar kinematic chains with continuous flexible links, by Kane's method.

The pipeline, one public function per stage::

    model = flexkane.builtin_model("falling-beam-exact")      # or flexkane.load_model("arm.toml")
    eom = flexkane.derive(model)                               # Kane's equations, M(q,t) u' = f(q,u,t)
    compiled = flexkane.compile_model(eom)                     # Numba right-hand side, cached on disk
    results = flexkane.simulate(compiled, t_end=1.0, dt_out=0.01)
    results["q4"], results["energy"]
"""

__version__ = "0.1.0"

from .builtin import builtin_model, builtin_names  # noqa: E402
from .kane import EquationsOfMotion, derive  # noqa: E402
from .model import Model, dumps_model, load_model, loads_model, save_model  # noqa: E402
from .results import Results, load_results  # noqa: E402
from .simulation import compile_model, simulate  # noqa: E402
from .linearize import linearize, modal_analysis  # noqa: E402
from .errors import FlexkaneError, ModelError, SolverFailure  # noqa: E402
from .extras import MissingExtraError  # noqa: E402

__all__ = ["__version__", "Model", "load_model", "loads_model", "dumps_model", "save_model",
           "builtin_model", "builtin_names", "derive", "EquationsOfMotion", "compile_model", "simulate",
           "Results", "load_results", "linearize", "modal_analysis",
           "FlexkaneError", "ModelError", "SolverFailure", "MissingExtraError"]
