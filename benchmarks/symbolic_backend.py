"""SymEngine against SymPy on the algebra of the derivation of ``chain_model(k)`` (scaling.py).

The kinematics and Kane's generalized inertia forces of a chain of ``k`` flexible links on hubs
(2 modes each, a payload at the tip, the structure of ``benchmarks/scaling.py: chain_model``) are
built here by the same steps as ``flexkane.kane.kinematics`` and ``flexkane.kane.inertia``, written
once for either backend:

* **build**: frames joint by joint from the ground out: a hub turned by its joint angle from the
  frame at the deflected tip of the previous link (station ``L``: position ``(L, sum Phi_i(L) q_i)``,
  turned by the slope ``sum Phi_i'(L) q_i``); velocities in each link's own frame,
  ``v_C = R(-phi) (v_A + w_A x d + d')``, time derivatives by the chain rule
  ``d/dt e = sum_j (de/dq_j) q_j'`` (``q' = u`` for revolute joints and modes); beam velocity fields
  as coefficients of the atoms 1, x, Phi_1, Phi_2 (eq. 8.18);
* **partials**: partial velocities and partial angular velocities, ``d v / d u_r`` of every
  velocity component and field coefficient;
* **kane**: ``M_rs = sum m v_r . v_s + I w_r w_s + int rho v_P,r . v_P,s dx`` (the integrals of
  products of atoms are modal-constant symbols) and the remainder
  ``sum m v_r . a_rem + I w_r alpha + int rho v_P,r . a_P,rem dx`` (``a_rem`` by the chain rule plus
  ``w x v``, eq. 8.21), for the upper triangle;
* **subs**: the first joint prescribed, ``q_1 -> A sin(w t)``, ``u_1 -> A w cos(w t)``, in M and the
  remainder (``xreplace``, as ``flexkane.kane.equations`` substitutes drivers);
* **cse**: common subexpressions of M (upper triangle) and the remainder, as the code generator does;
* **expand**: full expansion of M and the remainder (not done by the derivation today; a measure of
  raw polynomial algebra), up to ``--expand-max`` links;
* the conversion of M and the remainder from SymPy to SymEngine and back (the cost of using SymEngine
  for some steps only).

Each backend runs the same code on its own expressions (SymPy's cache cleared before each chain).
Results are compared after converting SymEngine's back to SymPy: exactly (``sympy.expand(a - b) == 0``)
for small chains, numerically at a random point (relative 1e-12) for all; the common-subexpression
results are checked by substituting the replacements back, and their sizes are printed (the two
libraries choose different subexpressions).

Usage: ``python benchmarks/symbolic_backend.py [--links 1,2,3,4] [--expand-max 2] [--exact-max 2]``.
Needs the ``symengine`` package (``pip install symengine``, or the ``bench`` extra).
"""

from __future__ import annotations

import argparse
import os
import platform
import random
import sys
import time
from importlib import metadata

import sympy as sp
from sympy.core.cache import clear_cache

try:
    import symengine as se
except ImportError:  # pragma: no cover - a message, not a traceback
    sys.exit("benchmarks/symbolic_backend.py needs the symengine package: "
             "python -m pip install symengine (or pip install -e '.[bench]')")

MODES = 2
#: Runs of each small chain (k <= 2), of which the fastest is kept per stage.
REPEAT = 3
STAGES = ("build", "partials", "kane", "subs", "cse", "expand")


class Backend:
    """The few operations of the derivation, for one symbolic library."""

    def __init__(self, name: str):
        self.name = name
        self.lib = sp if name == "sympy" else se
        self.zero = self.lib.Integer(0)

    def symbol(self, name: str):
        return self.lib.Symbol(name)

    def sin(self, e):
        return self.lib.sin(e)

    def cos(self, e):
        return self.lib.cos(e)

    def diff(self, e, s):
        return self.lib.diff(e, s)

    def expand(self, e):
        return self.lib.expand(e)

    def xreplace(self, e, rule):
        return e.xreplace(rule)

    def cse(self, exprs):
        if self.name == "sympy":
            return sp.cse(exprs, order="none")
        return se.cse(exprs)

    def add(self, terms):
        return self.lib.Add(*terms) if terms else self.zero

    def is_zero(self, e) -> bool:
        return e == 0

    def free(self, e):
        return e.free_symbols


class Chain:
    """Kinematics and generalized inertia forces of ``chain_model(links)`` in one backend."""

    def __init__(self, b: Backend, links: int):
        self.b = b
        self.links = links
        S = b.symbol
        self.q, self.u = [], []
        self.hub = []   # (q, u) of each joint
        self.modes = []  # [(q, u) per mode] of each link
        for k in range(1, links + 1):
            self.hub.append((S(f"q_joint_{k}"), S(f"u_joint_{k}")))
            self.q.append(self.hub[-1][0])
            self.u.append(self.hub[-1][1])
            modes = [(S(f"q_link_{k}_{i}"), S(f"u_link_{k}_{i}")) for i in range(1, MODES + 1)]
            self.modes.append(modes)
            self.q += [m[0] for m in modes]
            self.u += [m[1] for m in modes]
        self.qdot = dict(zip(self.q, self.u))
        self.m, self.J, self.r, self.L = S("m"), S("J"), S("r"), S("L")
        self.m_tip, self.J_tip = S("m_tip"), S("J_tip")

    # -------------------------------------------------------------- calculus
    def dt(self, e):
        """Time derivative by the chain rule (q' = u); the speeds' own derivatives left out."""
        free = self.b.free(e)
        return self.b.add([self.b.diff(e, q) * qd for q, qd in self.qdot.items() if q in free])

    # -------------------------------------------------------------- frames: (omega, vx, vy)
    def point(self, frame, p):
        """The frame moved to the point p (components in the frame, may depend on q)."""
        w, vx, vy = frame
        return (w, vx - w * p[1] + self.dt(p[0]), vy + w * p[0] + self.dt(p[1]))

    def turned(self, frame, angle):
        w, vx, vy = frame
        c, s = self.b.cos(angle), self.b.sin(angle)
        return (w + self.dt(angle), c * vx + s * vy, -s * vx + c * vy)

    def build(self):
        """Frames of the hubs and the payload, velocity fields of the beams (atoms 1, x, Phi_i)."""
        b = self.b
        self.bodies = []   # (mass, inertia, frame)
        self.fields = []   # (k, {atom: coefficient} along x, along y, omega)
        attach = (b.zero, b.zero, b.zero)
        for k in range(self.links):
            q, u = self.hub[k]
            hub = self.turned(attach, q)
            self.bodies.append((self.m, self.J, hub))
            w, vx, vy = self.point(hub, (self.r, b.zero))
            modes = self.modes[k]
            fx = {"1": vx}
            fy = {"1": vy, "x": w}
            for i, (qi, ui) in enumerate(modes, 1):
                fx[f"phi{i}"] = -w * qi
                fy[f"phi{i}"] = ui
            self.fields.append((k, fx, fy, w))
            tip_y = b.add([b.symbol(f"Phi_{k + 1}_{i}(L)") * qi for i, (qi, _) in enumerate(modes, 1)])
            slope = b.add([b.symbol(f"dPhi_{k + 1}_{i}(L)") * qi for i, (qi, _) in enumerate(modes, 1)])
            attach = self.turned(self.point((w, vx, vy), (self.L, tip_y)), slope)
        self.bodies.append((self.m_tip, self.J_tip, attach))

    # -------------------------------------------------------------- Kane
    def partials(self):
        d = self.b.diff
        self.body_partials = [[(d(vx, u), d(vy, u), d(w, u)) for u in self.u]
                              for _, _, (w, vx, vy) in self.bodies]
        self.field_partials = [[({a: d(c, u) for a, c in fx.items()}, {a: d(c, u) for a, c in fy.items()})
                                for u in self.u] for _, fx, fy, _ in self.fields]

    def _integral(self, k, f, g):
        """int rho f g dx of two fields of beam k: sums of coefficient products times constants."""
        b = self.b
        terms = []
        for a, ca in f.items():
            if self.b.is_zero(ca):
                continue
            for c, cc in g.items():
                if self.b.is_zero(cc):
                    continue
                first, second = sorted((a, c))
                terms.append(ca * cc * b.symbol(f"K_{k + 1}_{first}_{second}"))
        return b.add(terms)

    def kane(self):
        """Upper triangle of M and the remainder of F*_r (eq. 8.22 split as in flexkane.kane.inertia)."""
        b = self.b
        n = len(self.u)
        M = [[[] for _ in range(n)] for _ in range(n)]
        rem = [[] for _ in range(n)]
        for (mass, inertia, (w, vx, vy)), parts in zip(self.bodies, self.body_partials):
            ax, ay = self.dt(vx) - w * vy, self.dt(vy) + w * vx
            alpha = self.dt(w)
            for r in range(n):
                Vr = parts[r]
                if all(self.b.is_zero(c) for c in Vr):
                    continue
                for s in range(r, n):
                    Vs = parts[s]
                    M[r][s].append(mass * (Vr[0] * Vs[0] + Vr[1] * Vs[1]) + inertia * Vr[2] * Vs[2])
                rem[r].append(mass * (Vr[0] * ax + Vr[1] * ay) + inertia * Vr[2] * alpha)
        for (k, fx, fy, w), parts in zip(self.fields, self.field_partials):
            arx = {a: self.dt(c) for a, c in fx.items()}
            ary = {a: self.dt(c) for a, c in fy.items()}
            for a, c in fy.items():
                arx[a] = arx.get(a, b.zero) - w * c
            for a, c in fx.items():
                ary[a] = ary.get(a, b.zero) + w * c
            for r in range(n):
                Pr = parts[r]
                for s in range(r, n):
                    Ps = parts[s]
                    M[r][s].append(self._integral(k, Pr[0], Ps[0]) + self._integral(k, Pr[1], Ps[1]))
                rem[r].append(self._integral(k, Pr[0], arx) + self._integral(k, Pr[1], ary))
        self.M = [b.add(M[r][s]) for r in range(n) for s in range(r, n)]
        self.rem = [b.add(terms) for terms in rem]
        return self.M + self.rem

    def drivers(self, exprs):
        b = self.b
        A, om, t = b.symbol("A"), b.symbol("w"), b.symbol("t")
        q1, u1 = self.hub[0]
        rule = {q1: A * b.sin(om * t), u1: A * om * b.cos(om * t)}
        return [b.xreplace(e, rule) for e in exprs]


def run_backend(name: str, links: int, do_expand: bool) -> tuple[dict, dict]:
    """Times [s] of each stage and the results, for one backend and one chain."""
    backend = Backend(name)
    if name == "sympy":
        clear_cache()
    chain = Chain(backend, links)
    times, out = {}, {}
    tic = time.perf_counter()
    chain.build()
    times["build"] = time.perf_counter() - tic
    tic = time.perf_counter()
    chain.partials()
    times["partials"] = time.perf_counter() - tic
    tic = time.perf_counter()
    out["kane"] = chain.kane()
    times["kane"] = time.perf_counter() - tic
    tic = time.perf_counter()
    out["subs"] = chain.drivers(out["kane"])
    times["subs"] = time.perf_counter() - tic
    tic = time.perf_counter()
    out["cse"] = backend.cse(out["kane"])
    times["cse"] = time.perf_counter() - tic
    if do_expand:
        tic = time.perf_counter()
        out["expand"] = [backend.expand(e) for e in out["kane"]]
        times["expand"] = time.perf_counter() - tic
    return times, out


def best_of(repeat: int, name: str, links: int, do_expand: bool) -> tuple[dict, dict]:
    """Smallest time of each stage over ``repeat`` runs (the machine is shared), last results."""
    best: dict = {}
    for _ in range(repeat):
        times, out = run_backend(name, links, do_expand)
        best = {s: min(t, best.get(s, t)) for s, t in times.items()}
    return best, out


def to_sympy(e) -> sp.Expr:
    return sp.sympify(e)


def _point(exprs, rng) -> dict:
    symbols = set().union(*(e.free_symbols for e in exprs))
    return {s: sp.Float(rng.uniform(0.3, 1.2), 30) for s in sorted(symbols, key=lambda s: s.name)}


def numerically_equal(a: list, b: list, rng, rtol=1e-12) -> float:
    """Largest relative difference of two lists of SymPy expressions at a random point."""
    point = _point(a + b, rng)
    worst = 0.0
    for x, y in zip(a, b):
        vx, vy = float(x.xreplace(point).evalf(30)), float(y.xreplace(point).evalf(30))
        worst = max(worst, abs(vx - vy) / max(abs(vx), abs(vy), 1e-300))
    return worst


def cse_reconstructed(replacements, reduced) -> list:
    """The expressions a common-subexpression result stands for (SymPy)."""
    rule = {}
    for symbol, value in replacements:
        rule[to_sympy(symbol)] = to_sympy(value).xreplace(rule)
    return [to_sympy(e).xreplace(rule) for e in reduced]


def cse_size(replacements, reduced) -> str:
    """Number of common subexpressions and operations (SymPy's count_ops) of a cse result."""
    ops = sum(sp.count_ops(to_sympy(v)) for _, v in replacements) + sum(sp.count_ops(to_sympy(e)) for e in reduced)
    return f"{len(replacements)} subexpressions, {ops} operations"


def compare(sympy_out: dict, symengine_out: dict, exact: bool, rng) -> dict:
    """For each stage, 'identical' (exactly), or the largest relative numerical difference."""
    report = {}
    for stage in ("kane", "subs", "expand"):
        if stage not in sympy_out:
            continue
        a = list(sympy_out[stage])
        b = [to_sympy(e) for e in symengine_out[stage]]
        if exact:
            same = all(sp.expand(x - y) == 0 for x, y in zip(a, b))
            report[stage] = "identical" if same else "DIFFERENT"
        else:
            report[stage] = numerically_equal(a, b, rng)
    inputs = list(sympy_out["kane"])
    for name, out in (("cse sympy", sympy_out["cse"]), ("cse symengine", symengine_out["cse"])):
        rebuilt = cse_reconstructed(*out)
        if exact:
            report[name] = "identical" if all(sp.expand(x - y) == 0 for x, y in zip(inputs, rebuilt)) \
                else "DIFFERENT"
        else:
            report[name] = numerically_equal(inputs, rebuilt, rng)
    return report


def machine() -> str:
    cpu = "unknown"
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as handle:
            for line in handle:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return (f"{os.cpu_count()} cores ({cpu}), Python {platform.python_version()}, "
            f"SymPy {metadata.version('sympy')}, SymEngine {metadata.version('symengine')} "
            f"(python wrappers {se.__version__})")


def fmt(seconds: float) -> str:
    return f"{seconds * 1e3:.1f} ms" if seconds < 1 else f"{seconds:.2f} s"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--links", default="1,2,3,4", help="numbers of links, comma-separated")
    parser.add_argument("--expand-max", type=int, default=2, help="expand M and the remainder up to this k")
    parser.add_argument("--exact-max", type=int, default=2,
                        help="compare exactly (expand(a - b) == 0) up to this k, numerically above")
    args = parser.parse_args(argv)
    links = [int(k) for k in args.links.split(",")]
    rng = random.Random(20261124)
    print(machine())
    for name in ("sympy", "symengine"):  # warm-up: first calls load code lazily
        run_backend(name, 1, True)
    rows = []
    for k in links:
        do_expand = k <= args.expand_max
        t_sp, out_sp = best_of(REPEAT if k <= 2 else 1, "sympy", k, do_expand)
        t_se, out_se = best_of(REPEAT if k <= 2 else 1, "symengine", k, do_expand)
        ops = sum(sp.count_ops(e) for e in out_sp["kane"]) if k <= 3 else None
        tic = time.perf_counter()
        converted = [se.sympify(e) for e in out_sp["kane"]]
        t_se["to symengine"] = time.perf_counter() - tic
        tic = time.perf_counter()
        [sp.sympify(e) for e in converted]
        t_se["to sympy"] = time.perf_counter() - tic
        check = compare(out_sp, out_se, k <= args.exact_max, rng)
        check["cse size sympy"] = cse_size(*out_sp["cse"])
        check["cse size symengine"] = cse_size(*out_se["cse"])
        rows.append((k, t_sp, t_se, ops, check))
        print(f"k = {k}: " + "; ".join(f"{s} {fmt(t_sp[s])} / {fmt(t_se[s])}" for s in STAGES if s in t_sp)
              + f"; checks {check}", flush=True)
    print()
    print("| links k | operations in M, rem (SymPy count_ops) | "
          + " | ".join(f"{s}: SymPy / SymEngine (ratio)" for s in STAGES) + " | total (build..cse) ratio |")
    print("|---" * (len(STAGES) + 3) + "|")
    for k, t_sp, t_se, ops, _ in rows:
        cells = []
        for s in STAGES:
            cells.append(f"{fmt(t_sp[s])} / {fmt(t_se[s])} ({t_sp[s] / t_se[s]:.0f}x)" if s in t_sp else "-")
        total_sp = sum(t_sp[s] for s in STAGES[:5])
        total_se = sum(t_se[s] for s in STAGES[:5])
        print(f"| {k} | {ops if ops is not None else '-'} | " + " | ".join(cells)
              + f" | {fmt(total_sp)} / {fmt(total_se)} ({total_sp / total_se:.0f}x) |")
    print()
    print("Conversion of M and the remainder from SymPy to SymEngine (symengine.sympify) and back "
          "(sympy.sympify):")
    for k, _, t_se, _, _ in rows:
        print(f"  k = {k}: to SymEngine {fmt(t_se['to symengine'])}, back to SymPy {fmt(t_se['to sympy'])}")
    print()
    print("Results (SymEngine's converted to SymPy; 'identical': expand(a - b) == 0; a number: largest "
          "relative difference at a random point, 30 digits):")
    for k, _, _, _, check in rows:
        print(f"  k = {k}: " + ", ".join(f"{s}: {v if isinstance(v, str) else f'{v:.1e}'}"
                                         for s, v in check.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
