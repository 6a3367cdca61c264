"""A hand-written recursive (order-n kinematics) right-hand side of ``chain_model(k)``, as a yardstick.

``benchmarks/scaling.py: chain_model(k)``: k planar flexible links (uniform Euler-Bernoulli beams,
n clamped-free modes each, eq. 8.4, no axial modes, no foreshortening, no rotary inertia of the
section), each clamped at point (r, 0) of a hub (mass m at the joint, inertia J); hub 1 turns on a
revolute joint at the ground origin, hub k > 1 on a revolute joint at the tip of link k - 1 (the
joint sits at the *deflected* tip and its frame is turned by the tip *slope*, as flexkane's
``beam_station`` does); a payload (m_tip, J_tip) is welded at the deflected, sloped tip of link k;
joint k carries the torque ``T sin(2 pi t / t1) / k`` for t < t1, else 0. The model has no gravity.

Coordinates and speeds are flexkane's, in its order: for every link, the joint angle and then the
link's modal coordinates, ``u = q'`` for all of them (eq. 8.16).

How the right-hand side is evaluated (all vectors in ground components, moments about the origin)
-----------------------------------------------------------------------------------------------
1. **Kinematics, body by body in tree order** (eqs. 8.11, 8.17-8.21 applied link after link): the
   angle, angular velocity, origin, root and tip of link k follow from those of the tip of link
   k - 1; the acceleration *remainder* (the part not multiplying u', eq. 8.21 with u' = 0) of the
   hub, root and tip likewise. For a point at x on beam k, with ``rho(x) = x e1 + y(x) e2``,
   ``y = sum Phi_i q_i`` (eq. 8.15):

       v_P = v_R + w k x rho + ydot e2                                (eq. 8.18)
       a_P = a_R + wdot k x rho - w^2 rho - 2 w ydot e1 + yddot e2    (eq. 8.21)

   (dots: time derivatives in the link frame).

   The angular velocities are linear in u with constant coefficients (joint rates and tip-slope
   rates ``Phi_i'(L) u_i``), so angular accelerations have no remainder.
2. **Partial velocities as twists.** The partial velocity field of every speed is, on every body
   outboard of where the speed acts, a rigid twist (w_r, v_r at the origin): ``(1, k x (0 - O_k))``
   for the joint k (rotation about the joint point O_k) and ``(Phi_i'(L), Phi_i(L) e2 +
   Phi_i'(L) k x (0 - tip))`` for mode i of link k (translation and turn of the tip). On its own
   beam a modal speed's partial velocity is the field ``Phi_i(x) e2`` instead.
3. **Generalized inertia forces as sums over bodies** (eq. 8.22): ``M_rs = sum_bodies int v_r . v_s
   dm`` and ``Fhat_r = sum_bodies int v_r . a_rem dm``. Grouping the bodies outboard of speed s
   (r before s) gives the composite-rigid-body form

       M_rs = t_r . (I_s t_s) + [beam of s: E_i (v_r(R) . e2) + F_i w_r, or G_ij for r, s modes of it]
       Fhat_s = t_s . W_s      + [beam of s: E_i (a_rem(R) . e2) - w^2 (G q)_i]

   where ``I_s`` is the composite inertia (mass, first and second moment about the origin) of the
   bodies that speed s moves rigidly, each beam counted at its current deflected shape
   (``J = m_B |R|^2 + 2 R . (e_B e1 + E.q e2) + I_B + q.G.q``, the constants of eq. 8.22), and
   ``W_s`` the composite of their inertia-force remainders. Composites are accumulated from the
   payload inwards, once, so each body is visited a bounded number of times; only the final
   products ``t_r . (I_s t_s)`` (3 multiply-adds per entry) make the assembly O(n^2) in the
   speeds, which is what filling an n x n mass matrix costs anyway.
4. **Generalized active forces** (eqs. 8.31, 8.35): joint torques ``F_r = tau_k`` for the joint
   speed (a couple between hub k and the beam station it sits on does work on the relative angular
   velocity only, which is the joint rate), elastic forces ``-sum_i H_ij q_i`` (eq. 8.31, H of
   eq. 8.32); no gravity (chain_model has none).
5. ``M u' = F - Fhat`` (eq. 8.36) is solved by a Cholesky factorization written out in loops.

Why composite bodies and a factorization rather than an articulated-body (truly O(n)) solve:
measured at 24 speeds (8 links, CPU time, profile of this function cut after each stage), the
kinematics, composites and twists take 0.43 us, filling M and f 0.73 us, the Cholesky
factorization and the two triangular solves 1.95 us (about 2,900 multiply-adds). An
articulated-body recursion for flexible links (per link a 6 x 6 projection of the link's inertia
and its outboard articulated inertia, and a 3 x 3 joint-and-modes block inverted) costs roughly
as many multiply-adds at 8 links, so it would gain less than 2x there; it wins for much longer
chains (at 20 links the factorization is about 36,000 multiply-adds). The composite-body form
also keeps "F*_r as a sum over bodies of partial velocities dotted with inertia forces", as the
chapter writes it (eq. 8.22), which makes it a readable check of the physics.

The modal constants (m_B, e_B, I_B, E_i, F_i, G_ij, H_ij of eqs. 8.22 and 8.32, Phi_i(L),
Phi_i'(L)) are computed here independently of flexkane: roots of eq. 8.6 by bisection, eq. 8.4
in an overflow-free form, Gauss-Legendre quadrature of NumPy.

Usage: ``python benchmarks/recursive_yardstick.py [--quick]`` compares with flexkane's generated
right-hand side at random states and times one evaluation of each; :func:`run` is used by
``benchmarks/run_all.py``.
"""

from __future__ import annotations

import math
import os
import sys
import tempfile
import time

import numpy as np
from numba import njit

#: Links compared with flexkane (each compiles a new model structure: 12 and 20 links take minutes
#: to compile, see chain_scaling.py).
FLEXKANE_LINKS = (1, 2, 4, 8)
#: Links timed for the yardstick alone as well.
YARDSTICK_LINKS = (12, 20)


# ---------------------------------------------------------------------------- modal constants
def cantilever_roots(n: int) -> np.ndarray:
    """First n roots of ``cos(l) cosh(l) + 1 = 0`` (eq. 8.6) by bisection, shape (n,)."""
    f = lambda lam: math.cos(lam) + 1.0 / math.cosh(lam)  # noqa: E731 - same roots, no overflow
    roots = np.empty(n)
    for i in range(n):
        a, b = (2 * i + 1) * math.pi / 2 - 0.5, (2 * i + 1) * math.pi / 2 + 0.5
        fa = f(a)
        for _ in range(200):
            mid = 0.5 * (a + b)
            fm = f(mid)
            if (fm > 0) == (fa > 0):
                a, fa = mid, fm
            else:
                b = mid
            if b - a < 1e-16 * b:
                break
        roots[i] = 0.5 * (a + b)
    return roots


def cantilever_modes(xi: np.ndarray, roots: np.ndarray, deriv: int = 0) -> np.ndarray:
    """``d^k Phi_i / d xi^k`` of eq. 8.4 at ``xi = x / L``, shape (n, len(xi)).

    Written as ``((1 - s) e^z + (1 + s) e^-z) / 2 - cos z + s sin z`` with ``z = lambda xi`` and
    ``s = (cosh l + cos l) / (sinh l + sin l)``, ``1 - s`` evaluated without cancellation.
    """
    out = np.empty((len(roots), len(xi)))
    for i, lam in enumerate(roots):
        den = math.sinh(lam) + math.sin(lam)
        s = (math.cosh(lam) + math.cos(lam)) / den
        one_minus_s = (math.sin(lam) - math.cos(lam) - math.exp(-lam)) / den
        z = lam * xi
        ep, em = np.exp(z) * 0.5 * one_minus_s, np.exp(-z) * 0.5 * (1.0 + s)
        c, sn = np.cos(z), np.sin(z)
        hyper = ep + em if deriv % 2 == 0 else ep - em
        trig = (-c + s * sn, sn + s * c, c - s * sn, -sn - s * c)[deriv % 4]
        out[i] = lam ** deriv * (hyper + trig)
    return out


def beam_constants(L: float, rho: float, EI: float, n: int, order: int | None = None) -> dict:
    """Modal constants of a uniform clamped-free beam (eqs. 8.22, 8.32) by Gauss-Legendre quadrature.

    Parameters
    ----------
    L, rho, EI : float
        Length [m], mass per unit length [kg/m], flexural rigidity [N m^2].
    n : int
        Number of modes.
    order : int, optional
        Quadrature order (default ``40 + 10 n``; the integrands are entire functions).

    Returns
    -------
    dict
        ``mB`` [kg], ``eB`` [kg m], ``IB`` [kg m^2], ``E`` (n,) [kg], ``F`` (n,) [kg m],
        ``G`` (n, n) [kg], ``H`` (n, n) [N/m], ``PhiL`` (n,) [-], ``dPhiL`` (n,) [1/m].
    """
    roots = cantilever_roots(n)
    t, w = np.polynomial.legendre.leggauss(order or 40 + 10 * n)
    xi, w = 0.5 * (t + 1.0), 0.5 * w
    x, wx = xi * L, w * L
    phi = cantilever_modes(xi, roots)
    d2 = cantilever_modes(xi, roots, 2) / L ** 2
    end = np.array([1.0])
    return {"mB": rho * L, "eB": rho * L ** 2 / 2, "IB": rho * L ** 3 / 3,
            "E": rho * phi @ wx, "F": rho * phi @ (wx * x), "G": rho * (phi * wx) @ phi.T,
            "H": EI * (d2 * wx) @ d2.T, "PhiL": cantilever_modes(end, roots)[:, 0],
            "dPhiL": cantilever_modes(end, roots, 1)[:, 0] / L}


#: Parameters of chain_model, by name (the values are those of benchmarks/scaling.py).
PARAMETER_NAMES = ("J", "m", "r", "L", "EI", "rho", "m_tip", "J_tip", "T", "t1")


class ChainData:
    """Numeric data of a chain of ``links`` identical links with ``n`` modes each.

    Parameters
    ----------
    links, n : int
    values : dict
        Parameter values by the names of :data:`PARAMETER_NAMES` (SI units).

    Attributes
    ----------
    hub : ndarray (links, 3)
        Hub mass [kg], inertia [kg m^2], clamp offset r [m].
    beam : ndarray (links, 4)
        m_B [kg], e_B [kg m], I_B [kg m^2], L [m].
    modal : ndarray (4, links, n)
        E_i, F_i, Phi_i(L), Phi_i'(L).
    G, H : ndarray (links, n, n)
    tip : ndarray (2,)
        Payload mass and inertia.
    drive : ndarray (2,)
        Torque amplitude T [N m] and pulse length t1 [s].
    """

    def __init__(self, links: int, n: int, values: dict):
        v = {k: float(values[k]) for k in PARAMETER_NAMES}
        c = beam_constants(v["L"], v["rho"], v["EI"], n)
        ones = np.ones(links)
        self.links, self.n = links, n
        self.hub = np.column_stack([v["m"] * ones, v["J"] * ones, v["r"] * ones])
        self.beam = np.column_stack([c["mB"] * ones, c["eB"] * ones, c["IB"] * ones, v["L"] * ones])
        self.modal = np.stack([np.tile(c[key], (links, 1)) for key in ("E", "F", "PhiL", "dPhiL")])
        self.G = np.tile(c["G"], (links, 1, 1))
        self.H = np.tile(c["H"], (links, 1, 1))
        self.tip = np.array([v["m_tip"], v["J_tip"]])
        self.drive = np.array([v["T"], v["t1"]])
        size = links * (1 + n)
        self.work = np.zeros((size + links + 2, max(3 * size, 34)))
        self.constants = c

    def args(self):
        """The arguments of :func:`rhs` after ``(t, y)`` and before ``dy``."""
        return (self.hub, self.beam, self.modal, self.G, self.H, self.tip, self.drive)


# ---------------------------------------------------------------------------- right-hand side
@njit(cache=True, error_model="numpy")
def rhs(t, y, hub, beam, modal, G, H, tip, drive, dy, work):
    """``dy = [q', u']`` of chain_model; ``y = [q, u]`` in flexkane's order.

    ``work`` (N + links + 2, >= max(3 N, 34)), N = links (1 + n): rows 0..N-1 hold M and its
    Cholesky factor, row N the forcing, rows N+1..N+links per-link scratch, the last row the
    twists of the speeds and then the diagonal of the factor (no allocation).
    """
    K = hub.shape[0]
    n = modal.shape[2]
    nl = 1 + n
    N = K * nl
    M = work[:N]
    f = work[N]
    S = work[N + 1:N + 1 + K]   # per-link scratch, see the slots below
    P = work[N + 1 + K]         # payload scratch
    # slots of S[k]: 0 th, 1 w, 2 c, 3 s, 4 Ox, 5 Oy, 6 aOx, 7 aOy, 8 Rx, 9 Ry, 10 aRx, 11 aRy,
    #                12 Tx, 13 Ty, 14 aTx, 15 aTy, 16 Eq, 17 Eu, 18 qGq, 19 qGu,
    #                20..23 composite after beam k (m, cx, cy, J), 24..26 its remainder wrench
    #                (fx, fy, n about the origin), 27..30 and 31..33 the same from hub k outwards
    # ------------------------------------------------------------ 1. kinematics, tree order
    th = 0.0
    w = 0.0
    Ox = Oy = aOx = aOy = 0.0
    for k in range(K):
        b = k * nl
        th = th + y[b]
        w = w + y[N + b]
        c, s = math.cos(th), math.sin(th)
        r = hub[k, 2]
        L = beam[k, 3]
        Rx, Ry = Ox + r * c, Oy + r * s
        aRx, aRy = aOx - w * w * r * c, aOy - w * w * r * s
        yL = ydL = sl = sld = Eq = Eu = 0.0
        for i in range(n):
            qi, ui = y[b + 1 + i], y[N + b + 1 + i]
            yL += modal[2, k, i] * qi
            ydL += modal[2, k, i] * ui
            sl += modal[3, k, i] * qi
            sld += modal[3, k, i] * ui
            Eq += modal[0, k, i] * qi
            Eu += modal[0, k, i] * ui
        rx, ry = L * c - yL * s, L * s + yL * c          # rho(L) = L e1 + y(L) e2
        Tx, Ty = Rx + rx, Ry + ry
        aTx = aRx - w * w * rx - 2.0 * w * ydL * c        # eq. 8.21 at x = L, u' = 0
        aTy = aRy - w * w * ry - 2.0 * w * ydL * s
        qGq = qGu = 0.0
        for i in range(n):
            gi = 0.0
            for j in range(n):
                gi += G[k, i, j] * y[b + 1 + j]
            qGq += gi * y[b + 1 + i]
            qGu += gi * y[N + b + 1 + i]
        Sk = S[k]
        Sk[0], Sk[1], Sk[2], Sk[3] = th, w, c, s
        Sk[4], Sk[5], Sk[6], Sk[7] = Ox, Oy, aOx, aOy
        Sk[8], Sk[9], Sk[10], Sk[11] = Rx, Ry, aRx, aRy
        Sk[12], Sk[13], Sk[14], Sk[15] = Tx, Ty, aTx, aTy
        Sk[16], Sk[17], Sk[18], Sk[19] = Eq, Eu, qGq, qGu
        # the next joint sits at the deflected tip, its frame turned by the slope
        th = th + sl
        w = w + sld
        Ox, Oy, aOx, aOy = Tx, Ty, aTx, aTy
    # ------------------------------------------------------------ 2. composites, payload inwards
    mt, Jt = tip[0], tip[1]
    Cm, Ccx, Ccy, CJ = mt, mt * Ox, mt * Oy, Jt + mt * (Ox * Ox + Oy * Oy)
    Wfx, Wfy = mt * aOx, mt * aOy
    Wn = Ox * Wfy - Oy * Wfx
    for k in range(K - 1, -1, -1):
        Sk = S[k]
        Sk[20], Sk[21], Sk[22], Sk[23] = Cm, Ccx, Ccy, CJ
        Sk[24], Sk[25], Sk[26] = Wfx, Wfy, Wn
        w, c, s = Sk[1], Sk[2], Sk[3]
        Rx, Ry, aRx, aRy = Sk[8], Sk[9], Sk[10], Sk[11]
        Eq, Eu, qGq, qGu = Sk[16], Sk[17], Sk[18], Sk[19]
        mB, eB, IB = beam[k, 0], beam[k, 1], beam[k, 2]
        # first moment about the root, e_B e1 + (E.q) e2, in ground components
        hx, hy = eB * c - Eq * s, eB * s + Eq * c
        Cm += mB
        Ccx += mB * Rx + hx
        Ccy += mB * Ry + hy
        CJ += mB * (Rx * Rx + Ry * Ry) + 2.0 * (Rx * hx + Ry * hy) + IB + qGq
        # remainder of int rho a_P dx and of its moment about the origin
        fx = mB * aRx - w * w * hx - 2.0 * w * Eu * c
        fy = mB * aRy - w * w * hy - 2.0 * w * Eu * s
        Wfx += fx
        Wfy += fy
        Wn += Rx * fy - Ry * fx + hx * aRy - hy * aRx + 2.0 * w * qGu
        mh, Jh = hub[k, 0], hub[k, 1]
        Ox, Oy, aOx, aOy = Sk[4], Sk[5], Sk[6], Sk[7]
        Cm += mh
        Ccx += mh * Ox
        Ccy += mh * Oy
        CJ += Jh + mh * (Ox * Ox + Oy * Oy)
        Wfx += mh * aOx
        Wfy += mh * aOy
        Wn += mh * (Ox * aOy - Oy * aOx)
        Sk[27], Sk[28], Sk[29], Sk[30] = Cm, Ccx, Ccy, CJ
        Sk[31], Sk[32], Sk[33] = Wfx, Wfy, Wn
    # ------------------------------------------------------------ 3. twists of every speed
    # P[3 s], P[3 s + 1], P[3 s + 2]: (w_r, v_r at the origin)
    for k in range(K):
        Sk = S[k]
        b = k * nl
        P[3 * b], P[3 * b + 1], P[3 * b + 2] = 1.0, Sk[5], -Sk[4]
        c, s, Tx, Ty = Sk[2], Sk[3], Sk[12], Sk[13]
        for i in range(n):
            ph, dph = modal[2, k, i], modal[3, k, i]
            j = 3 * (b + 1 + i)
            P[j], P[j + 1], P[j + 2] = dph, -ph * s + dph * Ty, ph * c - dph * Tx
    # ------------------------------------------------------------ 4. M and f (eqs. 8.22, 8.36)
    T0, t1 = drive[0], drive[1]
    pulse = T0 * math.sin(2.0 * math.pi * t / t1) if t < t1 else 0.0
    for k in range(K):
        Sk = S[k]
        b = k * nl
        for i in range(-1, n):
            sidx = b + 1 + i
            ws, vx, vy = P[3 * sidx], P[3 * sidx + 1], P[3 * sidx + 2]
            base = 27 if i < 0 else 20   # joint: everything from hub k; mode: after beam k
            Im, Icx, Icy, IJ = Sk[base], Sk[base + 1], Sk[base + 2], Sk[base + 3]
            gx = Im * vx - ws * Icy
            gy = Im * vy + ws * Icx
            gn = IJ * ws + Icx * vy - Icy * vx
            for ridx in range(sidx + 1):
                wr, vrx, vry = P[3 * ridx], P[3 * ridx + 1], P[3 * ridx + 2]
                M[ridx, sidx] = wr * gn + vrx * gx + vry * gy
            fs = -(ws * Sk[base + 6] + vx * Sk[base + 4] + vy * Sk[base + 5])
            if i < 0:
                fs += pulse / (k + 1)
            else:
                Ei, Fi = modal[0, k, i], modal[1, k, i]
                c, s, Rx, Ry = Sk[2], Sk[3], Sk[8], Sk[9]
                for ridx in range(b + 1):
                    wr, vrx, vry = P[3 * ridx], P[3 * ridx + 1], P[3 * ridx + 2]
                    # twist velocity at the root R, along e2 = (-s, c)
                    M[ridx, sidx] += Ei * (-(vrx - wr * Ry) * s + (vry + wr * Rx) * c) + Fi * wr
                for j in range(i + 1):
                    M[b + 1 + j, sidx] += G[k, j, i]
                w = Sk[1]
                aR2 = -Sk[10] * s + Sk[11] * c
                gq = hq = 0.0
                for j in range(n):
                    gq += G[k, i, j] * y[b + 1 + j]
                    hq += H[k, i, j] * y[b + 1 + j]
                fs -= Ei * aR2 - w * w * gq
                fs -= hq
            f[sidx] = fs
    # ------------------------------------------------------------ 5. Cholesky solve, M u' = f
    # M holds the upper triangle; the factor L goes to the strict lower triangle, 1 / L_jj to P
    for j in range(N):
        d = M[j, j]
        for k in range(j):
            d -= M[j, k] * M[j, k]
        d = 1.0 / math.sqrt(d)
        P[j] = d
        for i in range(j + 1, N):
            acc = M[j, i]
            for k in range(j):
                acc -= M[i, k] * M[j, k]
            M[i, j] = acc * d
    for i in range(N):
        acc = f[i]
        for k in range(i):
            acc -= M[i, k] * f[k]
        f[i] = acc * P[i]
    for i in range(N - 1, -1, -1):
        acc = f[i]
        for k in range(i + 1, N):
            acc -= M[k, i] * f[k]
        f[i] = acc * P[i]
    for i in range(N):
        dy[i] = y[N + i]
        dy[N + i] = f[i]


# ---------------------------------------------------------------------------- comparison
def chain_data(model, links: int, n: int = 2) -> ChainData:
    """The yardstick's data for ``chain_model(links, n)`` from the model's parameter values."""
    return ChainData(links, n, {k: float(v) for k, v in model.parameters.items()})


def yardstick_rhs(data: ChainData, t: float, y: np.ndarray) -> np.ndarray:
    """dy/dt of the yardstick at one state, shape (2 N,)."""
    dy = np.empty_like(y)
    rhs(float(t), np.ascontiguousarray(y, dtype=float), *data.args(), dy, data.work)
    return dy


class FlexkaneChain:
    """flexkane's derived and compiled ``chain_model(links)``: ``rhs(t, y) -> dy``.

    Attributes
    ----------
    eom : EquationsOfMotion
    module : module
        Generated Numba module; ``module.rhs(t, y, p, dy)``.
    p : ndarray
        Constants in the order of ``eom.constants`` (``eom.constant_values(model)``).
    derive_s, compile_s : float
        Time of ``flexkane.derive`` and of code generation plus the first call [s].
    """

    def __init__(self, model, cache_dir=None):
        import flexkane

        tic = time.perf_counter()
        self.eom = flexkane.derive(model)
        self.derive_s = time.perf_counter() - tic
        compiled = flexkane.compile_model(self.eom, cache_dir)
        self.module = compiled.module
        values = self.eom.constant_values(model)
        self.p = np.array([values[c] for c in self.eom.constants], dtype=float)
        self.rhs(0.0, np.zeros(2 * len(self.eom.q)))
        self.compile_s = time.perf_counter() - tic - self.derive_s

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        dy = np.empty(len(y))
        self.module.rhs(float(t), np.ascontiguousarray(y, dtype=float), self.p, dy)
        return dy


def random_states(links: int, n: int, count: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """``count`` random (t, y): joint angles in [-pi, pi], modal coordinates up to 2 cm, joint rates
    up to 3 rad/s, modal rates up to 0.5 m/s; times on both sides of the torque pulse's end."""
    rng = np.random.default_rng(seed)
    nl = 1 + n
    N = links * nl
    Y = np.empty((count, 2 * N))
    joint = np.zeros(N, dtype=bool)
    joint[::nl] = True
    Y[:, :N] = np.where(joint, rng.uniform(-np.pi, np.pi, (count, N)), rng.uniform(-0.02, 0.02, (count, N)))
    Y[:, N:] = np.where(joint, rng.uniform(-3.0, 3.0, (count, N)), rng.uniform(-0.5, 0.5, (count, N)))
    times = rng.uniform(0.0, 1.0, count)
    return times, Y


def agreement(fk: FlexkaneChain, data: ChainData, count: int = 20, seed: int = 1) -> float:
    """Largest ``|dy_yardstick - dy_flexkane| / max|dy_flexkane|`` over random states."""
    nq = len(fk.eom.q)
    if nq != data.links * (1 + data.n):
        raise ValueError(f"flexkane has {nq} coordinates, the yardstick {data.links * (1 + data.n)}")
    worst = 0.0
    for t, y in zip(*random_states(data.links, data.n, count, seed)):
        ref = fk.rhs(t, y)
        worst = max(worst, float(np.max(np.abs(yardstick_rhs(data, t, y) - ref)) / np.max(np.abs(ref))))
    return worst


# ---------------------------------------------------------------------------- timing
@njit(error_model="numpy")
def _time_flexkane(f, t, y, p, dy, calls):
    """``calls`` evaluations of a generated ``rhs(t, y, p, dy)``; returns a checksum."""
    acc = 0.0
    for i in range(calls):
        f(t + 1e-9 * i, y, p, dy)
        acc += dy[dy.shape[0] - 1]
    return acc


@njit(error_model="numpy")
def _time_yardstick(t, y, hub, beam, modal, G, H, tip, drive, dy, work, calls):
    """``calls`` evaluations of :func:`rhs`; returns a checksum."""
    acc = 0.0
    for i in range(calls):
        rhs(t + 1e-9 * i, y, hub, beam, modal, G, H, tip, drive, dy, work)
        acc += dy[dy.shape[0] - 1]
    return acc


def _calls_for(loop, budget: float = 0.02) -> int:
    """Number of calls that take about ``budget`` seconds."""
    loop(1)
    tic = time.perf_counter()
    loop(100)
    per = max((time.perf_counter() - tic) / 100, 1e-9)
    return int(min(max(budget / per, 100), 2_000_000))


def _loops(data: ChainData, fk=None, seed: int = 2):
    """Timing loops ``loop(calls)`` of the yardstick and (if given) of flexkane at one random state."""
    _, Y = random_states(data.links, data.n, 1, seed)
    y, dy_ys, dy_fk = Y[0].copy(), np.empty(Y.shape[1]), np.empty(Y.shape[1])
    ys = lambda calls: _time_yardstick(0.1, y, *data.args(), dy_ys, data.work, calls)  # noqa: E731
    if fk is None:
        return ys, None
    return ys, (lambda calls: _time_flexkane(fk.module.rhs, 0.1, y, fk.p, dy_fk, calls))  # noqa: E731


def time_one_evaluation(data: ChainData, fk=None, repeat: int = 9) -> tuple[float, float | None]:
    """Cost of one evaluation [s] of the yardstick and of flexkane's generated rhs (None without ``fk``).

    Each timing runs an @njit loop of many calls (no Python dispatch inside) and measures the
    process's CPU time (``time.process_time``: time spent descheduled on a shared machine does not
    count); the two loops are timed alternately, ``repeat`` times each, so both see the same load,
    and the median of each is returned.
    """
    medians = alternate_medians([loop for loop in _loops(data, fk) if loop is not None], repeat)
    return medians[0], (medians[1] if fk is not None else None)


def alternate_medians(loops, repeat: int = 9) -> list[float]:
    """CPU time [s] of one call of each timing loop ``loop(calls)``: the loops are run alternately,
    ``repeat`` times each, so that all see the same load; the median of each is returned."""
    calls = [_calls_for(loop) for loop in loops]
    times: list[list[float]] = [[] for _ in loops]
    for _ in range(repeat):
        for loop, n_calls, out in zip(loops, calls, times):
            tic = time.process_time()
            loop(n_calls)
            out.append((time.process_time() - tic) / n_calls)
    return [float(np.median(t)) for t in times]


def fmt(seconds: float) -> str:
    return f"{seconds * 1e9:.0f} ns" if seconds < 1e-6 else f"{seconds * 1e6:.2f} us"


def run(flexkane_links=FLEXKANE_LINKS, yardstick_links=YARDSTICK_LINKS) -> dict:
    """Agreement and cost of one evaluation, flexkane against the yardstick, for each link count.

    flexkane's modules are compiled into a temporary cache directory unless FLEXKANE_CACHE_DIR is
    set (as ``run_all.py`` does).
    """
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from scaling import chain_model

    from _common import machine_info

    info = machine_info()
    machine = {"cpu": info.get("Model name", "?"), "cpus": info.get("CPU(s)", "?"), "python": info["python"],
               "numba": info["packages"].get("numba", "?"), "load_average": info["load_average"],
               "date": time.strftime("%Y-%m-%d")}
    print("recursive yardstick: one right-hand-side evaluation of chain_model(k) (2 modes per link), "
          "flexkane's generated code against benchmarks/recursive_yardstick.py")
    rows = []
    with tempfile.TemporaryDirectory(prefix="flexkane-yardstick-") as tmp:
        cache = os.environ.get("FLEXKANE_CACHE_DIR") or tmp
        for k in flexkane_links:
            model = chain_model(k)
            fk = FlexkaneChain(model, cache)
            data = chain_data(model, k)
            agree = agreement(fk, data)
            t_ys, t_fk = time_one_evaluation(data, fk)
            rows.append({"links": k, "speeds": 3 * k, "agreement": agree, "flexkane_s": t_fk,
                         "yardstick_s": t_ys, "ratio": t_fk / t_ys, "derive_s": fk.derive_s,
                         "compile_s": fk.compile_s})
            print(f"  k = {k:2d} ({3 * k:2d} speeds): agreement {agree:.1e}, flexkane {fmt(t_fk)}, "
                  f"yardstick {fmt(t_ys)}, flexkane / yardstick {t_fk / t_ys:.2f} "
                  f"(derive {fk.derive_s:.2f} s, codegen + compile {fk.compile_s:.2f} s)", flush=True)
    for k in yardstick_links:
        data = chain_data(chain_model(k), k)
        t_ys, _ = time_one_evaluation(data)
        rows.append({"links": k, "speeds": 3 * k, "agreement": None, "flexkane_s": None,
                     "yardstick_s": t_ys, "ratio": None})
        print(f"  k = {k:2d} ({3 * k:2d} speeds): yardstick {fmt(t_ys)}; flexkane not compiled here "
              f"(see chain_scaling.py for its derivation and compile times)", flush=True)
    machine["load_average_end"] = os.getloadavg()[0]
    return {"rows": rows, "machine": machine}


def markdown(result: dict) -> list[str]:
    """Section of RESULTS.md for :func:`run`'s result."""
    md = ["## Recursive yardstick (issue 16)", "",
          "`benchmarks/recursive_yardstick.py`: a hand-written, Numba-compiled right-hand side of "
          "`chain_model(k)` (2 modes per link): kinematics link by link from the parent's tip, "
          "partial velocities as twists, mass matrix and remainder forces as sums over bodies by "
          "composite bodies accumulated from the payload inwards, Cholesky solve. One evaluation: "
          "CPU time of an @njit loop of many calls, median of 9, flexkane's and the yardstick's "
          "loops timed alternately; *agreement*: largest difference of dy/dt from flexkane's at 20 "
          "random states, relative to the largest component of flexkane's.", ""]
    m = result.get("machine")
    if m:
        md += [f"Measured on {m['date']}: {m['cpu']}, {m['cpus']} CPUs, Python {m['python']}, numba "
               f"{m['numba']}; load average {m['load_average']:.1f} at the start, "
               f"{m['load_average_end']:.1f} at the end (the machine is shared).", ""]
    md += ["| links | speeds | agreement | flexkane | yardstick | flexkane / yardstick |",
           "|---|---|---|---|---|---|"]
    for r in result["rows"]:
        md.append(f"| {r['links']} | {r['speeds']} | "
                  + (f"{r['agreement']:.0e}" if r["agreement"] is not None else "-") + " | "
                  + (fmt(r["flexkane_s"]) if r["flexkane_s"] is not None else "not derived") + " | "
                  + fmt(r["yardstick_s"]) + " | "
                  + (f"{r['ratio']:.2f}" if r["ratio"] is not None else "-") + " |")
    md += ["", "flexkane's right-hand side is compared up to 8 links here (its derivation and compile "
           "times for longer chains are in the chain-length section).", "",
           "How the yardstick is built (details in the module docstring): kinematics link by link "
           "(each hub at the deflected tip of the previous link, turned by the tip slope, as "
           "flexkane models it); the partial velocity of every speed is a rigid twist on the bodies "
           "outboard of where it acts, and a modal field on its own beam; so `M_rs = t_r . (I_s t_s)"
           " + beam terms (E_i, F_i, G_ij)` and the inertia-force remainder `t_s . W_s + beam "
           "terms`, with `I_s`, `W_s` the composite inertia and remainder wrench of the bodies "
           "outboard, accumulated once from the payload inwards (eqs. 8.18, 8.21, 8.22 body by "
           "body); elastic forces eq. 8.31; Cholesky solve. The mass matrix is filled in O(n^2) "
           "(3 multiply-adds per entry) and factored in O(n^3); at 24 speeds the factorization "
           "and solves are about 60 % of an evaluation, and an articulated-body O(n) recursion "
           "with flexible links would cost about as many operations (less than 2x to gain at 8 "
           "links, more for much longer chains). Its modal constants come from its own "
           "roots of eq. 8.6 and Gauss-Legendre quadrature and equal flexkane's to 1e-12 "
           "(`tests/benchmarks/test_recursive_yardstick.py`).", ""]
    return md


if __name__ == "__main__":
    if "--quick" in sys.argv:
        out = run((1, 2), (8,))
    else:
        out = run()
    print("\n".join(markdown(out)))
