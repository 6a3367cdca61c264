"""Dormand-Prince 8(5,3) integrator loop, compiled once per installation.

The explicit Runge-Kutta method of Dormand and Prince of order 8 with embedded error estimators of
orders 5 and 3 and a dense output of order 7, with the step-size control of

    E. Hairer, S. P. Norsett, G. Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.,
    Springer 1993, Sec. II.10 (code DOP853) and Sec. II.4 (starting step size).

The tableau numbers are SciPy's (``scipy.integrate._ivp.dop853_coefficients``), read at import.

The loop takes the model's integrated right-hand side ``system_rhs(t, y, p, dy) -> int`` (0 ok,
2 non-finite, 4 singular mass matrix; the right-hand side ``rhs`` with the quadrature states
appended, see :mod:`flexkane.numerics.codegen`) as its first argument, a Numba first-class function
(:class:`~flexkane.numerics.system_function.SystemFunction`). Its functions are ``@njit(cache=True)``
in this package module, so Numba compiles them once for every model (the first-class function type
is the same for all of them) and stores the machine code in the package's ``__pycache__``; a new
model structure compiles only its own functions.

Contract of :func:`dop853_chunk` (also followed by ``radau5_chunk``)
------------------------------------------------------------------
0. ``system_rhs`` is the model's integrated right-hand side (a
   :class:`~flexkane.numerics.system_function.SystemFunction`); the other arguments follow.
1. It integrates from ``t`` with state ``y`` (n,) to exactly ``t_out[-1]``, forward in time;
   ``t_out`` (m,) is increasing with ``t_out[0] >= t``. With ``t_stop > t`` it returns earlier,
   at the first step point at or after ``t_stop``: that step is not shortened (only the last one,
   at ``t_out[-1]``, is), so a run cut into chunks takes the steps of an uncut one.
2. Row ``Y_out[i]`` (m, n) is filled with the dense output at ``t_out[i]`` once a step passes it
   (a row with ``t_out[i] == t`` receives ``y``); rows are filled in order, so the rows filled are
   exactly those with ``t_out[i] <= t_returned``.
3. It returns ``(t, y, h, status, nfev, naccept, nreject, nstiff)``: the time reached, the state
   there (a new array), the step size to try next, the status (0 ok, 1 step size too small, 2
   non-finite state or derivative, 3 ``max_steps`` attempted steps used, 4 singular mass matrix)
   and counts; ``nstiff`` counts the accepted steps whose size was limited by stability rather
   than accuracy (Hairer's test ``h |lambda| > 6.1`` of DOP853, Sec. IV.2 of Hairer & Wanner's
   volume II); for Radau the last count is the number of LU decompositions instead.
4. ``h <= 0`` on entry asks for an automatic starting step.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from flexkane.numerics.checked_numba_cache import guard_namespace

__all__ = ["DOP853_A", "DOP853_B", "DOP853_C", "DOP853_D", "DOP853_E3", "DOP853_E5", "all_finite",
           "dop853_chunk", "dop853_dense_fill", "fill_rows_at", "rms_norm", "starting_step"]


def _dop853_tableau():
    """SciPy's DOP853 tableau (``scipy/integrate/_ivp/dop853_coefficients.py``, which needs only NumPy).

    The file is loaded by itself: importing it as ``scipy.integrate._ivp.dop853_coefficients``
    would first run ``scipy.integrate``'s ``__init__`` (its solvers, quadrature and ODE wrappers:
    about 0.8 s, most of the start-up of a cached run), none of which the compiled loop uses.
    """
    import importlib.util
    import pathlib
    import sys

    name = "scipy.integrate._ivp.dop853_coefficients"
    if name in sys.modules:
        return sys.modules[name]
    import scipy

    path = pathlib.Path(scipy.__file__).parent / "integrate" / "_ivp" / "dop853_coefficients.py"
    spec = importlib.util.spec_from_file_location("flexkane_dop853_coefficients", path)
    if spec is None or not path.is_file():  # a SciPy laid out otherwise: the ordinary import
        from scipy.integrate._ivp import dop853_coefficients

        return dop853_coefficients
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


_dop853_coefficients = _dop853_tableau()
DOP853_A = np.ascontiguousarray(_dop853_coefficients.A, dtype=np.float64)    # (16, 16)
DOP853_B = np.ascontiguousarray(_dop853_coefficients.B, dtype=np.float64)    # (12,)
DOP853_C = np.ascontiguousarray(_dop853_coefficients.C, dtype=np.float64)    # (16,)
DOP853_E3 = np.ascontiguousarray(_dop853_coefficients.E3, dtype=np.float64)  # (13,)
DOP853_E5 = np.ascontiguousarray(_dop853_coefficients.E5, dtype=np.float64)  # (13,)
DOP853_D = np.ascontiguousarray(_dop853_coefficients.D, dtype=np.float64)    # (4, 16)

UNIT_ROUNDOFF = 2.220446049250313e-16
# Step-size controller of DOP853 (Hairer et al. 1993, Sec. II.4 and IV.2): safety factor, bounds
# of the ratio h_new / h, and the exponent of the stabilised (PI) part.
DOP853_SAFETY = 0.9
DOP853_MIN_FACTOR = 0.333
DOP853_MAX_FACTOR = 6.0
DOP853_BETA = 0.0
# Stiffness test of DOP853: ``h |lambda|`` estimated from the last two stages (both at t + h). The
# stability region reaches 6.5 on the negative real axis but only 5.9 on the imaginary axis, where
# the fast modes of beams lie; a step with ``h |lambda|`` above 4 resolves that mode poorly (phase
# error of whole radians), so it was not chosen for accuracy: stability held it back. (Hairer's
# DOP853 uses 6.1, which oscillatory modes never reach.)
DOP853_STIFF_HLAMBDA = 4.0


@njit(cache=True, error_model="numpy")
def rms_norm(x, scale):
    """Root mean square of ``x / scale``; both (n,)."""
    s = 0.0
    for i in range(x.shape[0]):
        r = x[i] / scale[i]
        s += r * r
    return math.sqrt(s / x.shape[0])


@njit(cache=True, error_model="numpy")
def all_finite(x):
    """Whether every entry of ``x`` (n,) is finite."""
    for i in range(x.shape[0]):
        if not math.isfinite(x[i]):
            return False
    return True


@njit(cache=True, error_model="numpy")
def fill_rows_at(t, y, t_out, i_out, Y_out):
    """Copy ``y`` into rows ``i_out...`` of ``Y_out`` whose time equals ``t``; return next row."""
    m = t_out.shape[0]
    while i_out < m and t_out[i_out] <= t:
        for i in range(y.shape[0]):
            Y_out[i_out, i] = y[i]
        i_out += 1
    return i_out


@njit(cache=True, error_model="numpy")
def starting_step(system_rhs, t, y, f0, p, rtol, atol, order, t_end, work_y, work_f):
    """Starting step size [s] of Hairer et al. (1993), Sec. II.4; returns ``(h, nfev)``.

    ``system_rhs`` is the model's first-class right-hand side.
    ``y``, ``f0``, ``atol``, ``work_y``, ``work_f`` are (n,); ``order`` is the method's order.
    """
    n = y.shape[0]
    d0 = 0.0
    d1 = 0.0
    for i in range(n):
        sk = atol[i] + rtol * abs(y[i])
        d0 += (y[i] / sk) ** 2
        d1 += (f0[i] / sk) ** 2
    d0 = math.sqrt(d0 / n)
    d1 = math.sqrt(d1 / n)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    h0 = min(h0, t_end - t)
    for i in range(n):
        work_y[i] = y[i] + h0 * f0[i]
    code = system_rhs(t + h0, work_y, p, work_f)
    if code != 0 or not all_finite(work_f):
        return h0, 1
    d2 = 0.0
    for i in range(n):
        sk = atol[i] + rtol * abs(y[i])
        d2 += ((work_f[i] - f0[i]) / sk) ** 2
    d2 = math.sqrt(d2 / n) / h0
    big = max(d1, d2)
    if big <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / big) ** (1.0 / (order + 1))
    return min(100.0 * h0, h1, t_end - t), 1


@njit(cache=True, error_model="numpy")
def dop853_dense_fill(system_rhs, t, h, y, K, rc, t_out, i_out, t_new, Y_out, p, ytmp):
    """Fill rows of ``Y_out`` with ``t < t_out[i] <= t_new`` from the order-7 dense output.

    ``rc[0]`` holds ``y_new - y`` on entry. Computes the three extra stages ``K[13:16]``
    (n each) and the other coefficients ``rc[1:]`` (6, n),
    then evaluates, with ``s = (t_out - t) / h``,
    ``y + s (rc0 + (1-s) (rc1 + s (rc2 + (1-s) (rc3 + s (rc4 + (1-s) (rc5 + s rc6))))))``.
    ``K[12]`` holds the derivative at the step's end. Returns ``(i_out, nfev, code)``.
    """
    n = y.shape[0]
    m = t_out.shape[0]
    if i_out >= m or t_out[i_out] > t_new:
        return i_out, 0, 0
    nfev = 0
    for s in range(13, 16):
        for i in range(n):
            acc = 0.0
            for j in range(s):
                acc += DOP853_A[s, j] * K[j, i]
            ytmp[i] = y[i] + h * acc
        code = system_rhs(t + DOP853_C[s] * h, ytmp, p, K[s])
        nfev += 1
        if code != 0:
            return i_out, nfev, code
    for i in range(n):
        delta = rc[0, i]  # y_new - y, set by the caller
        rc[1, i] = h * K[0, i] - delta
        rc[2, i] = 2.0 * delta - h * (K[0, i] + K[12, i])
        for k in range(4):
            acc = 0.0
            for j in range(16):
                acc += DOP853_D[k, j] * K[j, i]
            rc[3 + k, i] = h * acc
    while i_out < m and t_out[i_out] <= t_new:
        s = (t_out[i_out] - t) / h
        s1 = 1.0 - s
        for i in range(n):
            v = rc[5, i] + s * rc[6, i]
            v = rc[4, i] + s1 * v
            v = rc[3, i] + s * v
            v = rc[2, i] + s1 * v
            v = rc[1, i] + s * v
            v = rc[0, i] + s1 * v
            Y_out[i_out, i] = y[i] + s * v
        i_out += 1
    return i_out, nfev, 0


@njit(cache=True, error_model="numpy")
def dop853_chunk(system_rhs, t, y, h, t_out, p, rtol, atol, max_steps, Y_out, t_stop=-math.inf):
    """Integrate with DOP853 from ``t`` to ``t_out[-1]``, filling ``Y_out`` (see module docstring).

    Parameters: ``system_rhs`` the model's first-class right-hand side, ``t`` float, ``y`` (n,),
    ``h`` float (<= 0: automatic), ``t_out`` (m,), ``p`` (n_p,), ``rtol`` float, ``atol`` (n,),
    ``max_steps`` int, ``Y_out`` (m, n), ``t_stop`` float (optional soft stop).
    Returns ``(t, y, h, status, nfev, naccept, nreject, nstiff)``.
    """
    t_start = t
    n = y.shape[0]
    y = y.copy()
    K = np.empty((16, n))
    rc = np.empty((7, n))
    ytmp = np.empty(n)
    ynew = np.empty(n)
    nfev = 0
    naccept = 0
    nreject = 0
    nstiff = 0
    t_end = t_out[-1]
    i_out = fill_rows_at(t, y, t_out, 0, Y_out)
    code = system_rhs(t, y, p, K[0])
    nfev += 1
    if code != 0:
        return t, y, h, code, nfev, naccept, nreject, nstiff
    if not all_finite(K[0]):
        return t, y, h, 2, nfev, naccept, nreject, nstiff
    if t >= t_end:
        return t, y, h, 0, nfev, naccept, nreject, nstiff
    if h <= 0.0:
        h, extra = starting_step(system_rhs, t, y, K[0], p, rtol, atol, 8, t_end, ytmp, ynew)
        nfev += extra
    facold = 1e-4
    expo1 = 1.0 / 8.0 - DOP853_BETA * 0.2
    rejected = False
    failure = 0  # cause (2 or 4) of the current run of rejected steps, 0 if none
    while True:
        if naccept + nreject >= max_steps:
            return t, y, h, 3, nfev, naccept, nreject, nstiff
        h_min = 16.0 * UNIT_ROUNDOFF * max(abs(t), 1e-300)
        if h < h_min:
            return t, y, h, failure if failure != 0 else 1, nfev, naccept, nreject, nstiff
        last = False
        h_untruncated = h
        if t + 1.01 * h >= t_end:
            h = t_end - t
            last = True
        bad = 0
        for s in range(1, 12):
            for i in range(n):
                acc = 0.0
                for j in range(s):
                    acc += DOP853_A[s, j] * K[j, i]
                ytmp[i] = y[i] + h * acc
            code = system_rhs(t + DOP853_C[s] * h, ytmp, p, K[s])
            nfev += 1
            if code != 0:
                bad = code
                break
        if bad == 0:
            for i in range(n):
                acc = 0.0
                for j in range(12):
                    acc += DOP853_B[j] * K[j, i]
                ynew[i] = y[i] + h * acc
            code = system_rhs(t + h, ynew, p, K[12])
            nfev += 1
            if code != 0:
                bad = code
            elif not (all_finite(ynew) and all_finite(K[12])):
                bad = 2
        err = math.inf
        if bad == 0:
            e5 = 0.0
            e3 = 0.0
            for i in range(n):
                a5 = 0.0
                a3 = 0.0
                for j in range(13):
                    a5 += DOP853_E5[j] * K[j, i]
                    a3 += DOP853_E3[j] * K[j, i]
                sk = atol[i] + rtol * max(abs(y[i]), abs(ynew[i]))
                e5 += (a5 / sk) ** 2
                e3 += (a3 / sk) ** 2
            deno = e5 + 0.01 * e3
            if deno <= 0.0:
                deno = 1.0
            err = abs(h) * e5 / math.sqrt(n * deno)
            if not math.isfinite(err):
                bad = 2
        if bad != 0:
            # A stage left the domain of the model (or overflowed): retry with a smaller step.
            failure = bad if failure == 0 or bad == 4 else failure
            nreject += 1
            rejected = True
            h = 0.25 * h
            continue
        fac11 = err ** expo1
        fac = fac11 / facold ** DOP853_BETA
        fac = max(1.0 / DOP853_MAX_FACTOR, min(1.0 / DOP853_MIN_FACTOR, fac / DOP853_SAFETY))
        h_new = h / fac
        if err <= 1.0:
            facold = max(err, 1e-4)
            naccept += 1
            # Stiffness test: stages 12 (argument ytmp) and 13 (argument ynew) are both at t + h.
            stnum = 0.0
            stden = 0.0
            for i in range(n):
                stnum += (K[12, i] - K[11, i]) ** 2
                stden += (ynew[i] - ytmp[i]) ** 2
            if stden > 0.0 and h * math.sqrt(stnum / stden) > DOP853_STIFF_HLAMBDA:
                nstiff += 1
            t_new = t_end if last else t + h
            for i in range(n):
                rc[0, i] = ynew[i] - y[i]
            i_out, extra, code = dop853_dense_fill(system_rhs, t, h, y, K, rc, t_out, i_out, t_new,
                                                  Y_out, p, ytmp)
            nfev += extra
            if code != 0:
                return t, y, h, code, nfev, naccept, nreject, nstiff
            for i in range(n):
                K[0, i] = K[12, i]
                y[i] = ynew[i]
            t = t_new
            if rejected:
                h_new = min(h_new, h)
            rejected = False
            failure = 0
            if last:
                # The step was shortened to end the chunk: propose the untruncated size next.
                h_next = max(h_new, h_untruncated) if h < h_untruncated else h_new
                return t, y, h_next, 0, nfev, naccept, nreject, nstiff
            if t >= t_stop > t_start:
                return t, y, h_new, 0, nfev, naccept, nreject, nstiff
            h = h_new
        else:
            h = h / min(1.0 / DOP853_MIN_FACTOR, fac11 / DOP853_SAFETY)
            rejected = True
            failure = 0
            nreject += 1


guard_namespace(globals())   # their files in Numba's cache are checked before loading
