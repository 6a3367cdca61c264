"""Loops that evaluate modal sums in generated modules (template source).

A modal sum of the equations (:class:`flexkane.kane.modal_sums.ModalSum`) is printed in generated
Numba code as a call of one of these functions with tuples of floats: the array's entries
(row-major) and one vector per axis. The text between the template markers is copied into every
generated module (:mod:`flexkane.numerics.jit_module`), as the linear algebra is; Numba compiles a
specialisation per length of the tuples, inlined into the caller, so the generated code does not
grow with the number of terms of a sum.

Functions
---------
modal_sum1(A, a) -> float
    ``sum_i A[i] a[i]``.
modal_sum2(A, a, b) -> float
    ``sum_ij A[i m + j] a[i] b[j]`` with ``m = len(b)``.
"""

# >>> flexkane template >>>
from numba import njit


@njit(cache=True, error_model="numpy")
def modal_sum1(A, a):
    s = 0.0
    for i in range(len(a)):
        s += A[i] * a[i]
    return s


@njit(cache=True, error_model="numpy")
def modal_sum2(A, a, b):
    m = len(b)
    s = 0.0
    for i in range(len(a)):
        r = 0.0
        for j in range(m):
            r += A[i * m + j] * b[j]
        s += a[i] * r
    return s
# <<< flexkane template <<<


from flexkane.numerics.checked_numba_cache import guard_namespace  # noqa: E402

guard_namespace(globals())   # their files in Numba's cache are checked before loading
