"""A straightforward SymPy derivation of the chapter's example, integrating over x as the notebook does.

The rigid body RB on a free planar joint carrying the cantilever B (Fig. 8.2), with n assumed modes
(eq. 8.4 with the roots of eq. 8.6), the weight of B distributed along it and the elastic forces of
eqs. 8.31-8.32: the model ``falling-beam-exact`` of flexkane, derived the way the chapter's
Mathematica notebook does it:

* the numbers are substituted first (L = 1, b = 0.1, ...), the roots lambda_i are floats;
* the velocity and acceleration of a point P of the beam are formed as vectors in the body frame
  (eqs. 8.18, 8.21) with q(t), u(t) functions of time and the kinematic rules of eq. 8.14;
* every generalized inertia force (eq. 8.22) and every generalized active force is the integral
  over x, computed by ``sympy.integrate`` after expanding the integrand (``ExpandAll`` then
  ``Integrate``);
* Kane's equations F_r + F*_r = 0 (eq. 8.36) give ``M u' = f`` by differentiating with respect to
  the u'.

Usage: ``python benchmarks/sympy_baseline.py N`` derives the equations with N modes and prints the
time taken; :func:`derive_baseline` is used by ``benchmarks/derivation.py``.
"""

from __future__ import annotations

import sys
import time

import numpy as np
import sympy as sp
from scipy.optimize import brentq

# The notebook's numbers (In[13]): L [m], b [m], c, d [m], mR [kg], ro [kg/m], EI [N m^2], g [m/s^2].
L, B_, C_, D_, M_R, RHO, EI, G = 1.0, 0.1, 0.2, 0.3, 1.0, 0.21991, 35.3, 9.81
I_Z = M_R * (C_ ** 2 + D_ ** 2) / 12


def cantilever_roots(n: int) -> list[float]:
    """First n roots of cos(l) cosh(l) + 1 = 0 (eq. 8.6)."""
    f = lambda lam: np.cos(lam) * np.cosh(lam) + 1.0  # noqa: E731
    return [brentq(f, (k - 0.5) * np.pi - 0.5, (k - 0.5) * np.pi + 0.5, xtol=1e-15)
            for k in range(1, n + 1)]  # root k lies within 0.3 of (k - 1/2) pi


def _cross(a, b):
    return sp.Matrix([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def derive_baseline(n: int) -> dict:
    """Derive ``M(q) u' = f(q, u)`` of the chapter's example with n modes by symbolic integration.

    Returns
    -------
    dict
        ``mass_matrix`` (3 + n, 3 + n) and ``forcing`` (3 + n, 1) as SymPy matrices of the plain
        symbols ``q3 ... q(3+n)``, ``u1 ... u(3+n)``, and ``q``, ``u``, the lists of those symbols.
    """
    t, x = sp.symbols("t x", real=True)
    nq = 3 + n
    q = [sp.Function(f"q{i}")(t) for i in range(1, nq + 1)]
    u = [sp.Function(f"u{i}")(t) for i in range(1, nq + 1)]
    lam = cantilever_roots(n)
    phi = []
    for li in lam:
        s = (np.cosh(li) + np.cos(li)) / (np.sinh(li) + np.sin(li))
        phi.append(sp.cosh(li * x / L) - sp.cos(li * x / L) - s * (sp.sinh(li * x / L) - sp.sin(li * x / L)))
    # kinematic differential equations (eq. 8.14), as the notebook's rule
    c3, s3 = sp.cos(q[2]), sp.sin(q[2])
    rule = {q[0].diff(t): u[0] * c3 - u[1] * s3, q[1].diff(t): u[0] * s3 + u[1] * c3}
    rule.update({q[i].diff(t): u[i] for i in range(2, nq)})
    wR = sp.Matrix([0, 0, u[2]])
    vCR = sp.Matrix([u[0], u[1], 0])
    y = sum(phi[i] * q[3 + i] for i in range(n))
    rP = sp.Matrix([B_ + x, y, 0])
    vP = (vCR + rP.diff(t) + _cross(wR, rP)).subs(rule)
    aR = wR.diff(t)
    aCR = (vCR.diff(t) + _cross(wR, vCR)).subs(rule)
    aP = (vP.diff(t) + _cross(wR, vP)).subs(rule)
    GR = sp.Matrix([-M_R * G * s3, -M_R * G * c3, 0])     # -mR g j0 in the body frame (eq. 8.33)
    gB = sp.Matrix([-RHO * G * s3, -RHO * G * c3, 0])     # weight per unit length of B
    H = [[sp.integrate(sp.expand(EI * phi[i].diff(x, 2) * phi[j].diff(x, 2)), (x, 0, L))
          for j in range(n)] for i in range(n)]           # eq. 8.32
    equations = []
    for r in range(nq):
        dwR, dvCR, dvP = (m.applyfunc(lambda e: e.diff(u[r])) for m in (wR, vCR, vP))
        f_star = dwR.dot(-I_Z * aR) + dvCR.dot(-M_R * aCR) \
            + sp.integrate(sp.expand(dvP.dot(-aP) * RHO), (x, 0, L))              # eq. 8.22
        f_grav = dvCR.dot(GR) + sp.integrate(sp.expand(dvP.dot(gB)), (x, 0, L))   # distributed weight
        f_elastic = -sum(H[i][r - 3] * q[3 + i] for i in range(n)) if r >= 3 else 0  # eq. 8.31
        equations.append(f_star + f_grav + f_elastic)
    ud = [ui.diff(t) for ui in u]
    plain = {**{qi: sp.Symbol(f"q{i + 1}") for i, qi in enumerate(q)},
             **{ui: sp.Symbol(f"u{i + 1}") for i, ui in enumerate(u)}}
    ud_symbols = [sp.Symbol(f"ud{i + 1}") for i in range(nq)]
    equations = [sp.expand(e.subs(dict(zip(ud, ud_symbols)))).subs(plain) for e in equations]
    mass = sp.Matrix(nq, nq, lambda i, j: -equations[i].diff(ud_symbols[j]))
    forcing = sp.Matrix([e.subs({s: 0 for s in ud_symbols}) for e in equations])
    return {"mass_matrix": mass, "forcing": forcing,
            "q": [plain[qi] for qi in q], "u": [plain[ui] for ui in u]}


if __name__ == "__main__":
    modes = int(sys.argv[1]) if len(sys.argv) > 1 else 1
    tic = time.perf_counter()
    derived = derive_baseline(modes)
    print(f"SymPy baseline, {modes} mode(s): derived in {time.perf_counter() - tic:.2f} s; "
          f"mass matrix {derived['mass_matrix'].shape}, forcing {derived['forcing'].shape}")
