"""Radau IIA of order 5, the stiff integrator loop, compiled once per installation.

The three-stage Radau IIA collocation method (order 5 at the step points, L-stable) solved by
simplified Newton iterations in the transformed form of

    E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II*, 2nd ed., Springer 1996,
    Sec. IV.8 (code RADAU5): eqs. (8.15)-(8.18) for the transformed Newton iteration,
    (8.19)-(8.20) for the error estimate, the collocation polynomial for dense output.

Why Radau IIA rather than a Rosenbrock method (Rodas4): the Jacobian is formed by finite
differences (n + 1 right-hand-side evaluations, see :func:`fd_jacobian`); Radau's simplified
Newton iteration keeps one Jacobian over many steps, whereas a Rosenbrock method needs a fresh one
every step for its order. Radau is also order 5 against 4 and stiffly accurate.

All method constants (the 3 x 3 matrix A, the eigen-decomposition of A^-1 into one real
eigenvalue and a complex pair, the embedded error weights, the dense-output matrix) are derived
here at import from the nodes ``c = ((4 - sqrt 6)/10, (4 + sqrt 6)/10, 1)``.

The contract of :func:`radau5_chunk` is that of ``dop853_chunk`` (see
:mod:`flexkane.numerics.dop853`): its first argument is the model's integrated right-hand side as a
Numba first-class function, so that this module, like :mod:`~flexkane.numerics.dop853`, is compiled
once for all models and cached by Numba with the package; ``nfev`` includes the evaluations spent on
Jacobians.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from flexkane.numerics.checked_numba_cache import guard_namespace
from flexkane.numerics.dop853 import all_finite, fill_rows_at, rms_norm, starting_step
from flexkane.numerics.linear_algebra import lu_factor, lu_solve

__all__ = ["RADAU_ALPHA", "RADAU_BETA", "RADAU_C", "RADAU_E", "RADAU_GAMMA", "RADAU_P", "RADAU_T",
           "RADAU_TI", "fd_jacobian", "radau5_chunk", "radau_factor"]


def _radau_constants():
    """Return ``(c, T, TI, gamma, alpha, beta, E, P)`` of the 3-stage Radau IIA method.

    ``A^-1 = T [[gamma, 0, 0], [0, alpha, beta], [0, -beta, alpha]] T^-1``; ``E`` (3,) gives the
    error estimate ``(gamma/h - J)^-1 (f0 + sum_i E_i Z_i / h)``; ``P`` (3, 3) maps stage
    increments Z (3, n) to the coefficients of ``u(s) = y0 + sum_k (P Z)_k s^(k+1)``.
    """
    sqrt6 = math.sqrt(6.0)
    c = np.array([(4.0 - sqrt6) / 10.0, (4.0 + sqrt6) / 10.0, 1.0])
    a = np.empty((3, 3))
    for j in range(3):  # A_ij = integral from 0 to c_i of the Lagrange polynomial l_j
        others = np.array([c[k] for k in range(3) if k != j])
        lagrange = np.poly1d(np.poly(others)) / np.prod(c[j] - others)
        primitive = np.polyint(lagrange)
        a[:, j] = primitive(c) - primitive(0.0)
    a_inv = np.linalg.inv(a)
    lam, vec = np.linalg.eig(a_inv)
    i_real = int(np.argmin(np.abs(lam.imag)))
    i_cplx = [k for k in range(3) if k != i_real and lam[k].imag > 0][0]
    gamma = lam[i_real].real
    alpha = lam[i_cplx].real
    beta = lam[i_cplx].imag
    t = np.column_stack([vec[:, i_real].real, vec[:, i_cplx].real, vec[:, i_cplx].imag])
    ti = np.linalg.inv(t)
    # Embedded order-3 formula with weight 1/gamma on f(t0, y0) (Hairer & Wanner, eq. 8.19).
    b_hat = np.linalg.solve(np.vstack([c ** 0, c, c ** 2]), np.array([1.0 - 1.0 / gamma, 0.5, 1.0 / 3.0]))
    e = gamma * ((b_hat - a[2]) @ a_inv)
    p = np.linalg.inv(np.column_stack([c, c ** 2, c ** 3]))
    return (c, np.ascontiguousarray(t), np.ascontiguousarray(ti), gamma, alpha, beta, e,
            np.ascontiguousarray(p))


(RADAU_C, RADAU_T, RADAU_TI, RADAU_GAMMA, RADAU_ALPHA, RADAU_BETA, RADAU_E,
 RADAU_P) = _radau_constants()
RADAU_NEWTON_MAXITER = 7
# Jacobian reuse (Hairer & Wanner's THET): keep J after a step whose Newton contraction rate
# was below this; keep also h (and the LU factors) when the proposed ratio is in [1, 1.2].
# RADAU5's default 0.001 suits cheap Jacobians; a finite-difference one costs n evaluations, for
# which Hairer & Wanner advise about 0.1.
RADAU_JAC_REUSE_RATE = 0.1
RADAU_KEEP_H_MAX = 1.2
RADAU_UNIT_ROUNDOFF = 2.220446049250313e-16


@njit(cache=True, error_model="numpy")
def fd_jacobian(system_rhs, t, y, f0, p, J, work_y, work_f):
    """Forward-difference Jacobian ``J[i, j] = d f_i / d y_j`` (n, n) of ``system_rhs`` at ``(t, y)``.

    ``f0`` (n,) is ``system_rhs(t, y)``; increments ``sqrt(eps * max(1e-5, |y_j|))`` (RADAU5's choice).
    Returns ``(code, nfev)`` with the right-hand side's status code.

    Cost note (measured, planar pendulum chains from KanesMethod with n = 4, 8, 12 states):
    this costs 0.22, 0.77, 2.5 us against 49, 84, 186 ns for one ``rhs``. A symbolic Jacobian
    needs ``df/dy`` and every ``dM/dq_k`` (1.6 to 2.2 times the operations of ``rhs`` after
    CSE) plus ``nu`` solves with the factors of M, and 3 to 10 times the SymPy time of ``rhs``
    (0.03, 0.16, 0.55 s against 0.01, 0.02, 0.06 s), growing faster with the model. Radau
    keeps one Jacobian over many steps, so the microseconds matter less than generation and
    compilation time: finite differences win.
    """
    n = y.shape[0]
    for i in range(n):
        work_y[i] = y[i]
    for j in range(n):
        delta = math.sqrt(RADAU_UNIT_ROUNDOFF * max(1e-5, abs(y[j])))
        work_y[j] = y[j] + delta
        delta = work_y[j] - y[j]
        code = system_rhs(t, work_y, p, work_f)
        work_y[j] = y[j]
        if code != 0:
            return code, j + 1
        for i in range(n):
            J[i, j] = (work_f[i] - f0[i]) / delta
    return 0, n


@njit(cache=True, error_model="numpy")
def radau_factor(J, h, LUr, pivr, LUc, pivc):
    """Factor ``gamma/h I - J`` into ``LUr`` and ``(alpha - i beta)/h I - J`` into ``LUc``."""
    n = J.shape[0]
    shift_r = RADAU_GAMMA / h
    shift_c = complex(RADAU_ALPHA / h, -RADAU_BETA / h)
    for i in range(n):
        for j in range(n):
            LUr[i, j] = -J[i, j]
            LUc[i, j] = -J[i, j]
        LUr[i, i] += shift_r
        LUc[i, i] += shift_c
    code = lu_factor(LUr, pivr)
    if code == 0:
        code = lu_factor(LUc, pivc)
    return code


@njit(cache=True, error_model="numpy")
def radau5_chunk(system_rhs, t, y, h, t_out, p, rtol, atol, max_steps, Y_out, t_stop=-math.inf):
    """Integrate with Radau IIA (order 5) from ``t`` to ``t_out[-1]``, filling ``Y_out``.

    Same arguments and returns as ``dop853_chunk``, except the last count: the number of LU
    decompositions of the iteration matrices (each a real and a complex one). Rows between step points come from the
    collocation polynomial (order 3 there, order 5 at the step points).
    """
    t_start = t
    n = y.shape[0]
    y = y.copy()
    f0 = np.empty(n)
    ynew = np.empty(n)
    ytmp = np.empty(n)
    ftmp = np.empty(n)
    scale = np.empty(n)
    err = np.empty(n)
    rr = np.empty(n)
    rcx = np.empty(n, dtype=np.complex128)
    J = np.empty((n, n))
    LUr = np.empty((n, n))
    LUc = np.empty((n, n), dtype=np.complex128)
    pivr = np.empty(n, dtype=np.int64)
    pivc = np.empty(n, dtype=np.int64)
    Z = np.zeros((3, n))
    W = np.zeros((3, n))
    F = np.empty((3, n))
    Q = np.zeros((3, n))
    nfev = 0
    naccept = 0
    nreject = 0
    nlu = 0  # LU decompositions (of the real and the complex matrix)
    t_end = t_out[-1]
    i_out = fill_rows_at(t, y, t_out, 0, Y_out)
    code = system_rhs(t, y, p, f0)
    nfev += 1
    if code != 0:
        return t, y, h, code, nfev, naccept, nreject, nlu
    if not all_finite(f0):
        return t, y, h, 2, nfev, naccept, nreject, nlu
    if t >= t_end:
        return t, y, h, 0, nfev, naccept, nreject, nlu
    if h <= 0.0:
        h, extra = starting_step(system_rhs, t, y, f0, p, rtol, atol, 5, t_end, ytmp, ftmp)
        nfev += extra
    newton_tol = max(10.0 * RADAU_UNIT_ROUNDOFF / rtol, min(0.03, math.sqrt(rtol)))
    code, extra = fd_jacobian(system_rhs, t, y, f0, p, J, ytmp, ftmp)
    nfev += extra
    if code != 0:
        return t, y, h, code, nfev, naccept, nreject, nlu
    jac_current = True
    h_lu = -1.0
    eta_prev = 1.0
    have_poly = False
    h_poly = 0.0
    h_acc = 0.0
    err_acc = 0.0
    first = True
    rejected = False
    failure = 0
    while True:
        if naccept + nreject >= max_steps:
            return t, y, h, 3, nfev, naccept, nreject, nlu
        h_min = 16.0 * RADAU_UNIT_ROUNDOFF * max(abs(t), 1e-300)
        if h < h_min:
            return t, y, h, failure if failure != 0 else 1, nfev, naccept, nreject, nlu
        last = False
        h_untruncated = h
        if t + 1.01 * h >= t_end:
            h = t_end - t
            last = True
        if h != h_lu:
            if radau_factor(J, h, LUr, pivr, LUc, pivc) != 0:
                nreject += 1
                h = 0.5 * h
                continue
            h_lu = h
            nlu += 1
        for i in range(n):
            scale[i] = atol[i] + rtol * abs(y[i])
        # Starting guess: the previous step's collocation polynomial, extrapolated.
        if have_poly:
            for k in range(3):
                s = 1.0 + RADAU_C[k] * h / h_poly
                for i in range(n):
                    Z[k, i] = Q[0, i] * (s - 1.0) + Q[1, i] * (s * s - 1.0) + Q[2, i] * (s ** 3 - 1.0)
        else:
            for k in range(3):
                for i in range(n):
                    Z[k, i] = 0.0
        for k in range(3):
            for i in range(n):
                W[k, i] = RADAU_TI[k, 0] * Z[0, i] + RADAU_TI[k, 1] * Z[1, i] + RADAU_TI[k, 2] * Z[2, i]
        converged = False
        bad = 0
        eta = max(eta_prev, RADAU_UNIT_ROUNDOFF) ** 0.8
        rate = 0.0
        norm_old = 0.0
        n_iter = 0
        for it in range(RADAU_NEWTON_MAXITER):
            n_iter = it + 1
            for k in range(3):
                for i in range(n):
                    ytmp[i] = y[i] + Z[k, i]
                code = system_rhs(t + RADAU_C[k] * h, ytmp, p, F[k])
                nfev += 1
                if code != 0:
                    bad = code
                    break
                if not all_finite(F[k]):
                    bad = 2
                    break
            if bad != 0:
                break
            sq = 0.0
            for i in range(n):
                g0 = RADAU_TI[0, 0] * F[0, i] + RADAU_TI[0, 1] * F[1, i] + RADAU_TI[0, 2] * F[2, i]
                g1 = RADAU_TI[1, 0] * F[0, i] + RADAU_TI[1, 1] * F[1, i] + RADAU_TI[1, 2] * F[2, i]
                g2 = RADAU_TI[2, 0] * F[0, i] + RADAU_TI[2, 1] * F[1, i] + RADAU_TI[2, 2] * F[2, i]
                rr[i] = g0 - RADAU_GAMMA / h * W[0, i]
                rcx[i] = complex(g1 - (RADAU_ALPHA * W[1, i] + RADAU_BETA * W[2, i]) / h,
                                 g2 - (RADAU_ALPHA * W[2, i] - RADAU_BETA * W[1, i]) / h)
            lu_solve(LUr, pivr, rr)
            lu_solve(LUc, pivc, rcx)
            for i in range(n):
                W[0, i] += rr[i]
                W[1, i] += rcx[i].real
                W[2, i] += rcx[i].imag
                sq += ((rr[i] / scale[i]) ** 2 + (rcx[i].real / scale[i]) ** 2
                       + (rcx[i].imag / scale[i]) ** 2)
            norm = math.sqrt(sq / (3 * n))
            for k in range(3):
                for i in range(n):
                    Z[k, i] = RADAU_T[k, 0] * W[0, i] + RADAU_T[k, 1] * W[1, i] + RADAU_T[k, 2] * W[2, i]
            if not math.isfinite(norm):
                bad = 2
                break
            if it > 0:
                rate = norm / norm_old
                if rate >= 1.0 or rate ** (RADAU_NEWTON_MAXITER - it) / (1.0 - rate) * norm > newton_tol:
                    break
                eta = rate / (1.0 - rate)
            if eta * norm <= newton_tol or norm == 0.0:
                converged = True
                break
            norm_old = norm
        if not converged:
            nreject += 1
            rejected = True
            if bad != 0:
                failure = bad if failure == 0 or bad == 4 else failure
                h = 0.25 * h
            elif not jac_current:
                code, extra = fd_jacobian(system_rhs, t, y, f0, p, J, ytmp, ftmp)
                nfev += extra
                if code != 0:
                    return t, y, h, code, nfev, naccept, nreject, nlu
                jac_current = True
                h_lu = -1.0
            else:
                h = 0.5 * h
            continue
        eta_prev = eta
        for i in range(n):
            ynew[i] = y[i] + Z[2, i]
            scale[i] = atol[i] + rtol * max(abs(y[i]), abs(ynew[i]))
            ze = (RADAU_E[0] * Z[0, i] + RADAU_E[1] * Z[1, i] + RADAU_E[2] * Z[2, i]) / h
            err[i] = f0[i] + ze
            rr[i] = ze
        lu_solve(LUr, pivr, err)
        err_norm = rms_norm(err, scale)
        if err_norm > 1.0 and (first or rejected):
            for i in range(n):
                ytmp[i] = y[i] + err[i]
            code = system_rhs(t, ytmp, p, ftmp)
            nfev += 1
            if code == 0 and all_finite(ftmp):
                for i in range(n):
                    err[i] = ftmp[i] + rr[i]
                lu_solve(LUr, pivr, err)
                err_norm = rms_norm(err, scale)
        safety = 0.9 * (2 * RADAU_NEWTON_MAXITER + 1) / (2 * RADAU_NEWTON_MAXITER + n_iter)
        if not math.isfinite(err_norm):
            nreject += 1
            rejected = True
            failure = 2
            h = 0.25 * h
            continue
        if err_norm > 1.0:
            nreject += 1
            rejected = True
            failure = 0
            h = h * max(0.2, safety * err_norm ** -0.25)
            continue
        # Accept: derivative at the new point first (it may leave the model's domain).
        t_new = t_end if last else t + h
        code = system_rhs(t_new, ynew, p, ftmp)
        nfev += 1
        if code != 0 or not all_finite(ftmp):
            nreject += 1
            rejected = True
            failure = code if code != 0 else 2
            h = 0.25 * h
            continue
        naccept += 1
        for k in range(3):
            for i in range(n):
                Q[k, i] = RADAU_P[k, 0] * Z[0, i] + RADAU_P[k, 1] * Z[1, i] + RADAU_P[k, 2] * Z[2, i]
        while i_out < t_out.shape[0] and t_out[i_out] <= t_new:
            s = (t_out[i_out] - t) / h
            for i in range(n):
                Y_out[i_out, i] = y[i] + s * (Q[0, i] + s * (Q[1, i] + s * Q[2, i]))
            i_out += 1
        have_poly = True
        h_poly = h
        for i in range(n):
            y[i] = ynew[i]
            f0[i] = ftmp[i]
        t = t_new
        # Step-size proposal: standard controller, limited by Gustafsson's predictive one.
        if err_norm == 0.0:
            factor = 10.0
        else:
            factor = min(10.0, safety * err_norm ** -0.25)
            if h_acc > 0.0 and err_acc > 0.0:
                predictive = safety * (h / h_acc) * (err_acc / err_norm ** 2) ** 0.25
                factor = min(factor, max(0.2, predictive))
        if rejected:
            factor = min(factor, 1.0)
        h_acc = h
        err_acc = max(err_norm, 1e-2)
        first = False
        rejected = False
        failure = 0
        jac_current = False
        if rate > RADAU_JAC_REUSE_RATE:
            code, extra = fd_jacobian(system_rhs, t, y, f0, p, J, ytmp, ftmp)
            nfev += extra
            if code != 0:
                return t, y, h, code, nfev, naccept, nreject, nlu
            jac_current = True
            h_lu = -1.0
        h_new = h * factor
        if not jac_current and 1.0 <= factor <= RADAU_KEEP_H_MAX:
            h_new = h
        if last:
            return t, y, max(h_new, h_untruncated) if h < h_untruncated else h_new, 0, nfev, \
                naccept, nreject, nlu
        if t >= t_stop > t_start:
            return t, y, h_new, 0, nfev, naccept, nreject, nlu
        h = h_new


guard_namespace(globals())   # their files in Numba's cache are checked before loading
