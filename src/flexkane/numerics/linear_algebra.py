"""Dense linear algebra kernels for generated modules (template source) and the Radau loop.

The text between the two template markers below is copied into every generated module (see
:mod:`flexkane.numerics.jit_module`), where the functions are compiled by Numba together with the
generated right-hand side, so that Numba's on-disk cache covers them. The module is also a module
of the package: :mod:`flexkane.numerics.radau` (compiled once per installation) imports its LU
factorisation from here; tests call the pure-Python originals through ``function.py_func``.

Functions
---------
ldl_factor(M) -> int, ldl_substitute(LD, b) -> None, ldl_solve(M, b) -> int
    Solve ``M x = b`` in place (``b`` becomes ``x``) for a symmetric positive definite
    ``M`` (n, n) by ``M = L D L^T``, reading the upper triangle of ``M`` only.
constant_block_factor(G, out, offset) -> None, schur_solve(M, b, p, offset, block, rest) -> int
    The same solve by block elimination (Schur complement) when a principal block ``G`` of
    ``M`` is constant: ``G`` is factored once per run (see
    :mod:`flexkane.numerics.constant_block`), each solve costs O(n^2) for a small rest.
mass_matrix_failure(dy, pivot) -> int
    Fill ``dy`` with NaN and return the status code of a failed factorisation.
lu_factor(A, piv) -> int
    LU factorisation with partial pivoting, in place, for real or complex ``A`` (n, n).
lu_solve(LU, piv, b) -> None
    Solve ``A x = b`` in place with the factors of :func:`lu_factor`.

Status codes returned: 0 success, 2 non-finite entry, 4 singular (pivot not positive); they are
the integrator's codes, see :mod:`flexkane.numerics.integrate`.
"""

from flexkane.numerics.checked_numba_cache import guard_namespace

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
def ldl_factor(M):
    """Factor ``M = L D L^T`` in place; return -1, or the index of the first pivot that fails.

    Only the upper triangle of ``M`` (n, n) is read; on return its strict lower triangle holds
    the unit lower triangular ``L`` and its diagonal ``D``. Pivot ``j`` fails when
    ``d_j <= PIVOT_RTOL * M_jj`` (not positive definite) or ``d_j`` is not finite; the
    factorisation stops there with ``M[j, j] = d_j``.
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
            M[j, j] = d
            return j
        M[j, j] = d
        for i in range(j + 1, n):
            s = M[j, i]
            for k in range(j):
                s -= M[i, k] * w[k]
            M[i, j] = s / d
    return -1


@njit(cache=True, error_model="numpy")
def ldl_substitute(LD, b):
    """Solve ``L D L^T x = b`` in place with the factors of :func:`ldl_factor`; ``b`` (n,)."""
    n = LD.shape[0]
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= LD[i, k] * b[k]
        b[i] = s
    for i in range(n - 1, -1, -1):
        s = b[i] / LD[i, i]
        for k in range(i + 1, n):
            s -= LD[k, i] * b[k]
        b[i] = s


@njit(cache=True, error_model="numpy")
def ldl_solve(M, b):
    """Solve ``M x = b`` in place by ``M = L D L^T``; ``M`` (n, n) is overwritten by the factors.

    Only the upper triangle of ``M`` is read (M is symmetric); on return its strict lower
    triangle holds ``L`` and its diagonal holds ``D``. ``b`` (n,) is replaced by ``x``.
    Returns 0, or 2 (non-finite pivot) / 4 (pivot ``d_j <= PIVOT_RTOL * M_jj``, M not positive
    definite) after filling ``b`` with NaN.
    """
    j = ldl_factor(M)
    if j >= 0:
        return mass_matrix_failure(b, M[j, j])
    ldl_substitute(M, b)
    return 0


@njit(cache=True, error_model="numpy")
def constant_block_factor(G, out, offset):
    """Factor the constant block ``G`` (c, c) of a mass matrix into ``out[offset:]``, once per run.

    Writes ``out[offset] = 0.0`` and ``out[offset + 1] = 0.0`` on success, or ``1.0`` and the
    failing pivot (see :func:`ldl_factor`); then ``out[offset + 2 + i * c + j]`` holds
    ``L_ij`` for ``i > j``, ``1 / d_i`` for ``i == j`` and ``L_ji`` for ``i < j`` (c * c entries,
    row-major: ``L`` and, in the strict upper part, ``L^T``, whose rows are the columns of ``L``,
    contiguous for :func:`schur_solve`). ``G`` is overwritten; only its upper triangle is read.
    """
    c = G.shape[0]
    j = ldl_factor(G)
    if j >= 0:
        out[offset] = 1.0
        out[offset + 1] = G[j, j]
        for k in range(c * c):
            out[offset + 2 + k] = math.nan
        return
    out[offset] = 0.0
    out[offset + 1] = 0.0
    for i in range(c):
        for k in range(i):
            out[offset + 2 + i * c + k] = G[i, k]
        out[offset + 2 + i * c + i] = 1.0 / G[i, i]
        for k in range(i + 1, c):
            out[offset + 2 + i * c + k] = G[k, i]


@njit(cache=True, error_model="numpy")
def schur_solve(M, b, p, offset, block, rest):
    """Solve ``M x = b`` in place by block elimination of a constant block factored once per run.

    With the speeds split into the constant block ``c = block`` (its entries ``G = M_cc``
    factored by :func:`constant_block_factor` into ``p[offset:]``) and the rest ``r = rest``::

        S = M_rr - M_rc G^-1 M_cr,   S x_r = b_r - M_rc G^-1 b_c,   x_c = G^-1 (b_c - M_cr x_r)

    with ``G^-1`` applied as ``L^-T D^-1 L^-1``: ``Y = L^-1 M_cr`` and ``z = L^-1 b_c`` give
    ``S = M_rr - Y^T D^-1 Y`` (factored by :func:`ldl_factor`) and ``x_c = L^-T D^-1 (z - Y x_r)``;
    O(c^2 r + c r^2 + r^3) operations instead of O((c + r)^3).

    Parameters
    ----------
    M : ndarray (n, n)
        Upper triangle of the mass matrix, except the block ``block x block`` (not read).
    b : ndarray (n,)
        Right-hand side; replaced by ``x``.
    p : ndarray
        Prepared constants: ``p[offset]`` is 0.0 if ``G`` was factored (1.0 if it was not, with the
        failing pivot in ``p[offset + 1]``); the factors follow (see :func:`constant_block_factor`).
    offset : int
        Where the factors of ``G`` start in ``p``.
    block, rest : ndarray (c,), (r,) int
        Indices of the constant block and of the other speeds, increasing, ``c + r = n``.

    Returns
    -------
    int
        0, or 2 / 4 (non-finite / non-positive pivot of ``G`` or of ``S``, as :func:`ldl_solve`)
        after filling ``b`` with NaN.
    """
    if p[offset] != 0.0:
        return mass_matrix_failure(b, p[offset + 1])
    c = block.shape[0]
    r = rest.shape[0]
    f0 = offset + 2
    # z = L^-1 b_c and Y[a] = L^-1 M[c, rest[a]] (forward substitution, L unit lower), column by
    # column of L (rows of L^T, contiguous): each z_i is b_i - L_i0 z_0 - L_i1 z_1 - ... in the
    # order of a row-by-row substitution (the same bits), but the loops over i need no reduction
    # and, with unsigned indices (no wraparound test of negative ones), LLVM vectorizes them
    z = np.empty(c)
    Y = np.empty((r, c))
    for k in range(c):
        z[k] = b[block[k]]
    for a in range(r):
        ra = rest[a]
        for k in range(c):
            bk = block[k]
            Y[a, k] = M[bk, ra] if bk < ra else M[ra, bk]
    uc = np.uint64(c)
    for k in range(c):
        column = np.uint64(f0 + k * c)
        zk = z[k]
        for i in range(np.uint64(k + 1), uc):
            z[i] -= p[column + i] * zk
        for a in range(r):
            yk = Y[a, k]
            for i in range(np.uint64(k + 1), uc):
                Y[a, i] -= p[column + i] * yk
    # S = M_rr - Y D^-1 Y^T (upper triangle), g = b_r - Y D^-1 z
    S = np.empty((r, r))
    g = np.empty(r)
    yd = np.empty(c)
    for a in range(r):
        ra = rest[a]
        for k in range(c):
            yd[k] = Y[a, k] * p[f0 + k * c + k]
        s = b[ra]
        for k in range(c):
            s -= yd[k] * z[k]
        g[a] = s
        for e in range(a, r):
            re = rest[e]
            s = M[ra, re] if ra <= re else M[re, ra]
            for k in range(c):
                s -= yd[k] * Y[e, k]
            S[a, e] = s
    j = ldl_factor(S)
    if j >= 0:
        return mass_matrix_failure(b, S[j, j])
    ldl_substitute(S, g)
    # x_c = L^-T D^-1 (z - Y^T x_r)
    for k in range(c):
        s = z[k]
        for a in range(r):
            s -= Y[a, k] * g[a]
        z[k] = s * p[f0 + k * c + k]
    for k in range(c - 1, -1, -1):
        zk = z[k]
        row = np.uint64(f0 + k * c)
        for j in range(np.uint64(k)):
            z[j] -= p[row + j] * zk
    for k in range(c):
        b[block[k]] = z[k]
    for a in range(r):
        b[rest[a]] = g[a]
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


guard_namespace(globals())   # their files in Numba's cache are checked before loading
