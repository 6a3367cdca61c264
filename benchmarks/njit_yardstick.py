"""The practical limit: a hand-written compiled right-hand side inside a compiled DOP853 loop.

The chapter's example with n = 4 modes (``falling-beam-exact``), written by hand from eq. 8.23
(generalized inertia forces), eq. 8.31 (elastic forces) and the distributed weight of the beam,
with the modal constants E_i, F_i, G_ij, H_ij as arrays and loops over the modes; ``M u' = f`` is
solved by a hand-written Cholesky factorization of the (3 + n) x (3 + n) mass matrix. The loop is
the Dormand-Prince 8(5,3) method with the step-size control of Hairer, Norsett and Wanner (1993,
Sec. II.10), as flexkane's, but with nothing else: no output grid, no dense output, no chunks, no
status codes. Everything is ``@njit``; the whole run is one call.

``python benchmarks/njit_yardstick.py`` checks the right-hand side against flexkane's and prints
the cost of one evaluation and of a whole run. :func:`run_yardstick` is used by
``benchmarks/simulation.py``.
"""

from __future__ import annotations

import math
import time

import numpy as np
from numba import njit
from scipy.integrate._ivp import dop853_coefficients as dop

A = np.ascontiguousarray(dop.A[:12, :12])
B = np.ascontiguousarray(dop.B)
C = np.ascontiguousarray(dop.C[:12])
E3 = np.ascontiguousarray(dop.E3)
E5 = np.ascontiguousarray(dop.E5)


@njit(cache=True)
def rhs(t, y, s, E, F, G, H, dy, work):
    """``y = [q1..q(3+n), u1..u(3+n)]``; ``s = [mR, mB, eB, IB, Iz, b, g]``; E, F (n,), G, H (n, n).

    ``work`` (2 N + 1, N), N = 3 + n, holds M, its Cholesky factor and two vectors (no allocation).
    """
    n = E.shape[0]
    N = 3 + n
    mR, mB, eB, IB, Iz, b, g = s[0], s[1], s[2], s[3], s[4], s[5], s[6]
    q3 = y[2]
    u1, u2, u3 = y[N], y[N + 1], y[N + 2]
    c3, s3 = math.cos(q3), math.sin(q3)
    Eq = 0.0
    Eu = 0.0
    for i in range(n):
        Eq += E[i] * y[3 + i]
        Eu += E[i] * y[N + 3 + i]
    qGq = 0.0
    qGu = 0.0
    M = work[:N]
    Lc = work[N:2 * N]
    f = work[2 * N]
    Gq = dy[:n]  # free until the end
    for j in range(n):
        acc = 0.0
        for i in range(n):
            acc += G[i, j] * y[3 + i]
        Gq[j] = acc
        qGq += acc * y[3 + j]
        qGu += acc * y[N + 3 + j]
    m = mR + mB
    S = b * mB + eB
    M[0, 0] = m
    M[0, 2] = -Eq
    M[1, 1] = m
    M[1, 2] = S
    M[2, 2] = Iz + b * b * mB + 2.0 * b * eB + IB + qGq
    for j in range(n):
        M[1, 3 + j] = E[j]
        M[2, 3 + j] = b * E[j] + F[j]
        for i in range(n):
            M[3 + i, 3 + j] = G[i, j]
    f[0] = m * u2 * u3 + 2.0 * u3 * Eu + u3 * u3 * S - g * s3 * m
    f[1] = -m * u3 * u1 + u3 * u3 * Eq - g * c3 * m
    f[2] = -u2 * u3 * Eq - u3 * u1 * S - 2.0 * u3 * qGu + g * s3 * Eq - g * c3 * S
    for j in range(n):
        Hq = 0.0
        for i in range(n):
            Hq += H[i, j] * y[3 + i]
        f[3 + j] = -u3 * u1 * E[j] + u3 * u3 * Gq[j] - g * c3 * E[j] - Hq
    # Cholesky M = L L^T on the upper triangle (M is symmetric), then two triangular solves
    for j in range(N):
        d = M[j, j]
        for k in range(j):
            d -= Lc[j, k] * Lc[j, k]
        d = math.sqrt(d)
        Lc[j, j] = d
        for i in range(j + 1, N):
            acc = M[j, i]
            for k in range(j):
                acc -= Lc[i, k] * Lc[j, k]
            Lc[i, j] = acc / d
    for i in range(N):
        acc = f[i]
        for k in range(i):
            acc -= Lc[i, k] * f[k]
        f[i] = acc / Lc[i, i]
    for i in range(N - 1, -1, -1):
        acc = f[i]
        for k in range(i + 1, N):
            acc -= Lc[k, i] * f[k]
        f[i] = acc / Lc[i, i]
    dy[0] = u1 * c3 - u2 * s3
    dy[1] = u1 * s3 + u2 * c3
    for i in range(2, N):
        dy[i] = y[N + i]
    for i in range(N):
        dy[N + i] = f[i]


@njit(cache=True)
def dop853(t0, t_end, y0, rtol, atol, s, E, F, G, H):
    """Integrate from t0 to t_end; return ``(y_end, nfev, naccept, nreject)``."""
    n = y0.shape[0]
    y = y0.copy()
    K = np.empty((13, n))
    ytmp = np.empty(n)
    ynew = np.empty(n)
    work = np.zeros((n + 1, n // 2))
    rhs(t0, y, s, E, F, G, H, K[0], work)
    nfev = 1
    # starting step (Hairer et al. 1993, Sec. II.4)
    d0 = d1 = 0.0
    for i in range(n):
        sk = atol + rtol * abs(y[i])
        d0 += (y[i] / sk) ** 2
        d1 += (K[0, i] / sk) ** 2
    d0, d1 = math.sqrt(d0 / n), math.sqrt(d1 / n)
    h = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
    for i in range(n):
        ytmp[i] = y[i] + h * K[0, i]
    rhs(t0 + h, ytmp, s, E, F, G, H, K[1], work)
    nfev += 1
    d2 = 0.0
    for i in range(n):
        d2 += ((K[1, i] - K[0, i]) / (atol + rtol * abs(y[i]))) ** 2
    d2 = math.sqrt(d2 / n) / h
    h = min(100.0 * h, (0.01 / max(d1, d2)) ** (1.0 / 9.0) if max(d1, d2) > 1e-15 else max(1e-6, h * 1e-3))
    t = t0
    naccept = nreject = 0
    rejected = False
    while t < t_end:
        last = t + 1.01 * h >= t_end
        if last:
            h = t_end - t
        for st in range(1, 12):
            for i in range(n):
                acc = 0.0
                for j in range(st):
                    acc += A[st, j] * K[j, i]
                ytmp[i] = y[i] + h * acc
            rhs(t + C[st] * h, ytmp, s, E, F, G, H, K[st], work)
        for i in range(n):
            acc = 0.0
            for j in range(12):
                acc += B[j] * K[j, i]
            ynew[i] = y[i] + h * acc
        rhs(t + h, ynew, s, E, F, G, H, K[12], work)
        nfev += 12
        e5 = e3 = 0.0
        for i in range(n):
            a5 = a3 = 0.0
            for j in range(13):
                a5 += E5[j] * K[j, i]
                a3 += E3[j] * K[j, i]
            sk = atol + rtol * max(abs(y[i]), abs(ynew[i]))
            e5 += (a5 / sk) ** 2
            e3 += (a3 / sk) ** 2
        deno = e5 + 0.01 * e3
        err = abs(h) * e5 / math.sqrt(n * (deno if deno > 0.0 else 1.0))
        fac = max(1.0 / 6.0, min(1.0 / 0.333, err ** 0.125 / 0.9))
        if err <= 1.0:
            naccept += 1
            t = t_end if last else t + h
            for i in range(n):
                y[i] = ynew[i]
                K[0, i] = K[12, i]
            h_new = h / fac
            if rejected:
                h_new = min(h_new, h)
            rejected = False
            h = h_new
        else:
            nreject += 1
            rejected = True
            h = h / min(1.0 / 0.333, err ** 0.125 / 0.9)
    return y, nfev, naccept, nreject


def constants_from(eom, p: np.ndarray, n: int):
    """The yardstick's constants from flexkane's parameter vector (same model, same numbers)."""
    value = {sym.name: v for sym, v in zip(eom.constants, p)}
    s = np.array([value[k] for k in ("mR", "m_B", "e_B", "I_B", "Iz", "b", "g")])
    E = np.array([value[f"E_{i}"] for i in range(1, n + 1)])
    F = np.array([value[f"F_{i}"] for i in range(1, n + 1)])
    G = np.empty((n, n))
    H = np.empty((n, n))
    for i in range(1, n + 1):
        for j in range(1, n + 1):
            key = f"{min(i, j)}{max(i, j)}" if n < 10 else f"{min(i, j)}_{max(i, j)}"
            G[i - 1, j - 1] = value[f"G_{key}"]
            H[i - 1, j - 1] = value[f"H_{key}"]
    return s, E, F, G, H


@njit(cache=True)
def _many_rhs(count, y, s, E, F, G, H, dy):
    N = y.shape[0] // 2
    work = np.zeros((2 * N + 1, N))
    for _ in range(count):
        rhs(0.0, y, s, E, F, G, H, dy, work)


def rhs_cost(y, consts, count=200_000) -> float:
    """Seconds per evaluation, from a compiled loop of ``count`` calls."""
    dy = np.empty_like(y)
    _many_rhs(10, y, *consts, dy)
    tic = time.perf_counter()
    _many_rhs(count, y, *consts, dy)
    return (time.perf_counter() - tic) / count


def run_yardstick(y0, t_end, rtol, atol, consts, repeat=5):
    """Best wall time of ``repeat`` whole runs and the result of the last one."""
    dop853(0.0, 1e-3, y0, rtol, atol, *consts)  # compile or load
    best = math.inf
    for _ in range(repeat):
        tic = time.perf_counter()
        out = dop853(0.0, t_end, y0, rtol, atol, *consts)
        best = min(best, time.perf_counter() - tic)
    return best, out


if __name__ == "__main__":
    import flexkane

    model = flexkane.builtin_model("falling-beam-exact").with_modes(4)
    eom = flexkane.derive(model)
    compiled = flexkane.compile_model(eom)
    p, y0 = eom.parameter_vector(), eom.initial_state()
    consts = constants_from(eom, p, 4)
    rng = np.random.default_rng(0)
    y = y0 + 0.1 * rng.normal(size=y0.shape)
    ours, theirs = np.empty_like(y), compiled.rhs(0.0, y, p)
    rhs(0.0, y, *consts, ours, np.zeros((2 * 7 + 1, 7)))
    print(f"hand-written rhs vs flexkane: max relative difference "
          f"{np.abs(ours - theirs).max() / np.abs(theirs).max():.1e}")
    print(f"one evaluation: {rhs_cost(y, consts) * 1e9:.0f} ns")
    wall, (y_end, nfev, na, nr) = run_yardstick(y0, 1.0, 1e-8, 1e-10, consts)
    print(f"whole run (t in [0, 1] s, rtol 1e-8): {wall * 1e3:.2f} ms, {nfev} evaluations, "
          f"{na} accepted and {nr} rejected steps")
