"""Dense linear algebra kernels for generated modules (template source) and the Radau loop.

The text between the two template markers below is copied into every generated module (see
:mod:`flexkane.numerics.jit_module`), where the functions are compiled by Numba together with the
generated right-hand side, so that Numba's on-disk cache covers them. The module is also a module
of the package: :mod:`flexkane.numerics.radau` (compiled once per installation) imports its LU
factorisation from here; tests call the pure-Python originals through ``function.py_func``.

Functions
---------
ldl_solve(M, b) -> int
    Solve ``M x = b`` in place (``b`` becomes ``x``) for a symmetric positive definite
    ``M`` (n, n) by ``M = L D L^T``, reading the upper triangle of ``M`` only.
mass_matrix_failure(dy, pivot) -> int
    Fill ``dy`` with NaN and return the status code of a failed factorisation.
lu_factor(A, piv) -> int
    LU factorisation with partial pivoting, in place, for real or complex ``A`` (n, n).
lu_solve(LU, piv, b) -> None
    Solve ``A x = b`` in place with the factors of :func:`lu_factor`.

Status codes returned: 0 success, 2 non-finite entry, 4 singular (pivot not positive); they are
the integrator's codes, see :mod:`flexkane.numerics.integrate`.
"""

# >>> flexkane template >>>
import math

import numpy as np
from numba import njit

# Relative size below which a pivot of L D L^T counts as zero: d_j <= PIVOT_RTOL * M_jj.
PIVOT_RTOL = 1e-14


@njit(cache=True, error_model="numpy")
def mass_matrix_failure(dy, pivot):
    """Mark a failed mass-matrix factorisation: ``dy`` (n,) -> NaN; return 2 or 4."""
    for i in range(dy.shape[0]):
        dy[i] = math.nan
    if math.isfinite(pivot):
        return 4
    return 2


@njit(cache=True, error_model="numpy")
def ldl_solve(M, b):
    """Solve ``M x = b`` in place by ``M = L D L^T``; ``M`` (n, n) is overwritten by the factors.

    Only the upper triangle of ``M`` is read (M is symmetric); on return its strict lower
    triangle holds ``L`` and its diagonal holds ``D``. ``b`` (n,) is replaced by ``x``.
    Returns 0, or 2 (non-finite pivot) / 4 (pivot ``d_j <= PIVOT_RTOL * M_jj``, M not positive
    definite) after filling ``b`` with NaN.
    """
    n = M.shape[0]
    w = np.empty(n)
    for j in range(n):
        for k in range(j):
            w[k] = M[j, k] * M[k, k]
        d = M[j, j]
        for k in range(j):
            d -= M[j, k] * w[k]
        if not d > PIVOT_RTOL * M[j, j]:
            return mass_matrix_failure(b, d)
        M[j, j] = d
        for i in range(j + 1, n):
            s = M[j, i]
            for k in range(j):
                s -= M[i, k] * w[k]
            M[i, j] = s / d
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= M[i, k] * b[k]
        b[i] = s
    for i in range(n - 1, -1, -1):
        s = b[i] / M[i, i]
        for k in range(i + 1, n):
            s -= M[k, i] * b[k]
        b[i] = s
    return 0


@njit(cache=True, error_model="numpy")
def lu_factor(A, piv):
    """Factor ``P A = L U`` in place (Doolittle, partial pivoting); return 0, or 1 if singular.

    ``A`` (n, n), real or complex, is overwritten by ``L`` (unit diagonal, strict lower part)
    and ``U``; ``piv`` (n,) int receives the row swapped with row k at step k.
    """
    n = A.shape[0]
    for k in range(n):
        p = k
        big = abs(A[k, k])
        for i in range(k + 1, n):
            if abs(A[i, k]) > big:
                big = abs(A[i, k])
                p = i
        piv[k] = p
        if not (big > 0.0 and math.isfinite(big)):
            return 1
        if p != k:
            for j in range(n):
                tmp = A[k, j]
                A[k, j] = A[p, j]
                A[p, j] = tmp
        inv = 1.0 / A[k, k]
        for i in range(k + 1, n):
            A[i, k] *= inv
            lik = A[i, k]
            if lik != 0.0:
                for j in range(k + 1, n):
                    A[i, j] -= lik * A[k, j]
    return 0


@njit(cache=True, error_model="numpy")
def lu_solve(LU, piv, b):
    """Solve ``A x = b`` in place with the factors of :func:`lu_factor`; ``b`` (n,)."""
    n = LU.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= LU[i, k] * b[k]
        b[i] = s
    for i in range(n - 1, -1, -1):
        s = b[i]
        for k in range(i + 1, n):
            s -= LU[i, k] * b[k]
        b[i] = s / LU[i, i]
# <<< flexkane template <<<
