"""Numba's typing of arithmetic on scalars, resolved once per operation and argument types.

A generated right-hand side is thousands of scalar operations (chain_model(8): 7,100; chain_model(20):
34,000), and Numba types each one anew: for ``a * b`` on two float64 it tries every template
registered for ``operator.mul`` (NumPy's ufunc rules first, which look up the ufunc's loops) until
one accepts, about 0.7 ms of CPU time per operation, a third of the compile time. The answer depends
only on the typing context, the function and the argument types, so :func:`install` memoizes it for
arguments that are all plain (non-literal) numbers or booleans: the first ``float64 * float64``
of a process is typed as before, the others are a dictionary look-up. The signature is the same
object Numba computed, so the compiled code is unchanged (bit for bit); a failure to type is never
memoized (the next call tries again and raises as before).

Measured on chain_model(8) (benchmarks/RESULTS.md, chain length): the right-hand side compiles in
11.1 s of CPU time instead of 15.7 s, the outputs in 3.7 s instead of 5.2 s.

This reaches into Numba's type classes (``numba.core.types.functions.BaseFunction.get_call_type``):
:func:`install` checks that the method is there with the expected arguments and otherwise leaves
Numba as it is.
"""

from __future__ import annotations

import inspect

__all__ = ["install", "installed"]

_state: dict = {"installed": False, "original": None}


def _is_plain_scalar(t, types) -> bool:
    return isinstance(t, (types.Float, types.Integer, types.Boolean)) and not isinstance(t, types.Literal)


def install() -> bool:
    """Memoize Numba's typing of functions of plain scalars in this process (idempotent).

    Returns
    -------
    bool
        Whether the memoization is active (False when this Numba's internals differ from those
        it was written for: then nothing is changed).
    """
    if _state["installed"]:
        return True
    try:
        from numba.core import types
        from numba.core.types.functions import BaseFunction
    except ImportError:
        return False
    original = getattr(BaseFunction, "get_call_type", None)
    if original is None or list(inspect.signature(original).parameters) != ["self", "context", "args", "kws"]:
        return False
    memo: dict = {}

    def get_call_type(self, context, args, kws):
        if kws or not all(_is_plain_scalar(a, types) for a in args):
            return original(self, context, args, kws)
        key = (context, self, tuple(args))
        signature = memo.get(key)
        if signature is None:
            signature = original(self, context, args, kws)
            if signature is not None:
                memo[key] = signature
        return signature

    get_call_type.__doc__ = original.__doc__
    get_call_type.__wrapped__ = original
    BaseFunction.get_call_type = get_call_type
    _state.update(installed=True, original=original)
    return True


def installed() -> bool:
    """Whether :func:`install` is active in this process."""
    return _state["installed"]
