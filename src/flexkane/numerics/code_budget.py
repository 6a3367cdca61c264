"""Size budget of the compiled right-hand side: refuse a model whose code Numba cannot compile in bounded time.

The cost of compiling a generated right-hand side grows with the straight-line code Numba and LLVM
translate, not with the number of shape functions: long sums of modal constants (``falling-beam-exact``
with 40 modes) become term tables that one compiled loop adds (see
:mod:`flexkane.numerics.large_rhs`), while a payload at a beam station makes the slope
``sum_i Phi_i'(L) q_i`` enter the rotations of the bodies beyond it, whose products stay straight-line
code (``flexible-arm`` with 40 modes). The measure is therefore the number of floating-point
operations of the generated statements outside the term tables (:func:`compiled_operations`),
counted after common-subexpression elimination, which code generation does anyway. It is computed
in seconds, is the same on every machine, and is checked before the compile starts
(:func:`check_compiled_operations`): beyond :data:`DEFAULT_COMPILED_OPERATIONS`, or the value of the
environment variable ``FLEXKANE_COMPILE_OPERATIONS``, the model is refused with a
:class:`~flexkane.errors.ModelError` (exit code 2) naming its size, the budget and what to do.
benchmarks/RESULTS.md gives the measurements the default rests on.
"""

from __future__ import annotations

import re

from ..errors import ModelError
from ..kane.budget import _setting

__all__ = ["DEFAULT_COMPILED_OPERATIONS", "check_compiled_operations", "compiled_operations"]

#: Default largest number of straight-line operations of a generated right-hand side (outside term
#: tables). Measured (benchmarks/RESULTS.md): generation and compile take about 20 s plus 7 ms of
#: CPU time per operation up to flexible-arm with 40 modes (7,908 operations, 77 s, 0.67 GB);
#: spin-up (geometric stiffening) with 10 modes, 27,544 operations, exhausts Python's compiler
#: (RecursionError) before Numba starts.
DEFAULT_COMPILED_OPERATIONS = 20_000

# Lines of data, not code: the term tables and copy tables of large_rhs (module-level arrays).
_DATA_LINE = re.compile(r"^\w+_(TABLE_COEF|TABLE_INDEX|COPY_DY|COPY_M) = ")


def compiled_operations(lines) -> int:
    """Floating-point operations of generated source lines, without the term and copy tables.

    Parameters
    ----------
    lines : iterable of str
        Lines of generated Python source.

    Returns
    -------
    int
        Operators ``+ - * /`` and 20 per ``math`` call, counted in the code lines.
    """
    total = 0
    for line in lines:
        if _DATA_LINE.match(line) or line.lstrip().startswith(("#", '"""')):
            continue
        total += sum(line.count(op) for op in "+-*/") + 20 * line.count("math.")
    return total


def check_compiled_operations(operations: int) -> None:
    """Raise ModelError when a right-hand side has more straight-line operations than the budget.

    Parameters
    ----------
    operations : int
        :func:`compiled_operations` of the generated right-hand side.
    """
    limit = int(_setting("FLEXKANE_COMPILE_OPERATIONS", DEFAULT_COMPILED_OPERATIONS))
    if operations > limit:
        raise ModelError("model size", f"a right-hand side of at most {limit} operations outside "
                         "term tables (the size budget of code generation, beyond which compiling "
                         "takes unbounded time)",
                         f"{operations} operations",
                         "use fewer shape functions (n_modes of the beams), fewer links "
                         "or shorter expressions, or raise the budget with the environment variable "
                         "FLEXKANE_COMPILE_OPERATIONS (see benchmarks/RESULTS.md for what large "
                         "models cost)")
