"""A generated module's right-hand side as a Numba first-class function, for the compiled-once loops.

The integrator loops (:mod:`~flexkane.numerics.dop853`, :mod:`~flexkane.numerics.radau`) are
``@njit(cache=True)`` functions of this package that take the model's integrated right-hand side
``system_rhs(t, y, p, dy) -> int`` as an argument. Passed as a Numba dispatcher, that argument would
be typed by its identity: a new specialisation of every loop for every model (compiled in seconds,
and written to the package's disk cache where no other process can use it). :class:`SystemFunction` passes it instead as a *first-class function*: its Numba
type is ``FunctionType(SIGNATURE)``, the same for every model, and at a call the loops receive the
address of the generated function's C wrapper (machine code that the generated module's own disk
cache holds). So the loops are compiled once per installation, and a new model structure compiles
only its own functions.

The price is an indirect call per evaluation instead of a direct (inlinable) one;
``benchmarks/first_class_rhs.py`` measures it against :func:`direct_chunk`, the same loop with the
right-hand side bound.
"""

from __future__ import annotations

import atexit
import functools
import importlib.util
import shutil
import sys
import tempfile
from pathlib import Path
from types import ModuleType

import numba.experimental.function_type  # noqa: F401 - registers the Numba type of SystemFunction
from numba import njit, types
from numba.core.types import WrapperAddressProtocol

__all__ = ["FUNCTION_TYPE", "SIGNATURE", "SystemFunction", "direct_chunk", "system_function"]

#: Numba signature of a generated ``system_rhs(t, y, p, dy) -> status``: time [s], state (n,),
#: constants (n_p,) and derivative (n,) written in place, all contiguous float64 arrays.
SIGNATURE = types.int64(types.float64, types.float64[::1], types.float64[::1], types.float64[::1])
#: Numba type of a :class:`SystemFunction` argument: the same for every model.
FUNCTION_TYPE = types.FunctionType(SIGNATURE)


class SystemFunction(WrapperAddressProtocol):
    """The compiled ``system_rhs`` of a generated module, passed to Numba as a first-class function.

    Parameters
    ----------
    dispatcher : numba.core.registry.CPUDispatcher
        The module's ``@njit(cache=True)`` function ``system_rhs(t, y, p, dy) -> int`` (see
        :func:`~flexkane.numerics.codegen.generate_rhs_source`).

    Notes
    -----
    The first call of :meth:`__wrapper_address__` compiles the dispatcher for the arguments of
    :data:`SIGNATURE` (or loads it from the generated module's disk cache, the entry that a call
    from Python with the same arrays uses); the address is kept after that. The
    object keeps the dispatcher, hence the machine code at that address, alive.
    """

    def __init__(self, dispatcher):
        self.dispatcher = dispatcher
        self._address = 0

    def __wrapper_address__(self) -> int:
        """Address of the C-callable wrapper of ``system_rhs`` compiled for :data:`SIGNATURE`."""
        if not self._address:
            # compiled (or loaded from the disk cache) by the argument types, as a call from Python
            # does: one cache entry serves both (a signature with its return type is another key)
            self.dispatcher.compile(SIGNATURE.args)
            result = self.dispatcher.overloads[SIGNATURE.args]
            if result.signature.return_type != SIGNATURE.return_type:  # the loops read an int64
                raise TypeError(f"{self!r} returns {result.signature.return_type}, not "
                                f"{SIGNATURE.return_type}")
            self._address = result.library.get_pointer_to_function(result.fndesc.llvm_cfunc_wrapper_name)
        return self._address

    def signature(self):
        """The Numba signature of the function (:data:`SIGNATURE`)."""
        return SIGNATURE

    def is_compiled(self) -> bool:
        """Whether ``system_rhs`` is compiled for :data:`SIGNATURE` in this process."""
        return SIGNATURE.args in self.dispatcher.overloads

    def __repr__(self) -> str:
        return f"SystemFunction({self.dispatcher.py_func.__module__}.{self.dispatcher.py_func.__name__})"


def system_function(module: ModuleType) -> SystemFunction:
    """Return the integrated right-hand side of a generated module as a :class:`SystemFunction`.

    Parameters
    ----------
    module : module
        Generated module (:func:`~flexkane.numerics.jit_module.build_module`); its ``system_rhs``
        (``rhs`` when the module has no quadrature states and no ``system_rhs``).

    Returns
    -------
    SystemFunction
        One object per module (kept on the module), so that the address is looked up once.
    """
    function = getattr(module, "__flexkane_system_function__", None)
    if function is None:
        function = SystemFunction(getattr(module, "system_rhs", None) or module.rhs)
        module.__flexkane_system_function__ = function
    return function


@functools.cache
def _uncached_loops() -> dict[str, ModuleType]:
    """Copies of the integrator modules whose functions Numba does not cache (``cache=False``).

    A loop called with a Numba dispatcher instead of a :class:`SystemFunction` is specialised on
    that dispatcher; the package's cached functions would add each specialisation (useless to any
    other process) to the package's disk cache. The copies are imported from a temporary directory.
    """
    from flexkane.numerics import dop853, radau

    directory = Path(tempfile.mkdtemp(prefix="flexkane-direct-loops-"))
    atexit.register(shutil.rmtree, directory, ignore_errors=True)
    loops = {}
    for module in (dop853, radau):
        name = f"flexkane_direct_{module.__name__.rsplit('.', 1)[1]}"
        text = Path(module.__file__).read_text(encoding="utf-8").replace("cache=True", "cache=False")
        text = text.replace(f"from {dop853.__name__} import",
                            f"from {loops.get('dop853', dop853).__name__} import")
        path = directory / f"{name}.py"
        path.write_text(text, encoding="utf-8")
        spec = importlib.util.spec_from_file_location(name, path)
        loops[module.__name__.rsplit(".", 1)[1]] = copy = importlib.util.module_from_spec(spec)
        sys.modules[name] = copy
        spec.loader.exec_module(copy)
    return loops


def direct_chunk(method: str, dispatcher):
    """The integrator loop ``method`` calling ``dispatcher`` directly, for measurements and tests.

    Parameters
    ----------
    method : {"dop853", "radau"}
        The loop (``dop853_chunk`` or ``radau5_chunk``, same source, not cached).
    dispatcher : numba.core.registry.CPUDispatcher
        A generated ``system_rhs``; bound at compile time, so LLVM may inline it.

    Returns
    -------
    callable
        ``chunk(t, y, h, t_out, p, rtol, atol, max_steps, Y_out, t_stop)``: the arguments of the
        package's loop after the first-class function. Compiled on its first call (seconds).
    """
    loops = _uncached_loops()
    chunk = loops["dop853"].dop853_chunk if method == "dop853" else loops["radau"].radau5_chunk

    @njit(error_model="numpy")
    def direct(t, y, h, t_out, p, rtol, atol, max_steps, Y_out, t_stop):
        return chunk(dispatcher, t, y, h, t_out, p, rtol, atol, max_steps, Y_out, t_stop)

    return direct
