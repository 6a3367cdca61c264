"""Printed equations: F*_r and F_r in the chapter's notation, as text, Markdown or LaTeX.

The generalized inertia forces are printed with the modal constants of eq. 8.22 (m_B, e_B, I_B, E_i,
F_i, G_ij) and the elastic forces with H_ij of eq. 8.32, grouped by the derivatives of the speeds, as
eq. 8.23 is.
"""

from __future__ import annotations

import re

import sympy as sp

from . import __version__

__all__ = ["collect_terms", "latex_names", "format_equations", "equations_markdown", "equations_latex"]


def collect_terms(eom, expr: sp.Expr) -> sp.Expr:
    """Expand and group an expression by the speed derivatives u' and the speeds u."""
    ud = list(eom.chain.ud.values())
    return sp.collect(sp.expand(expr), ud)


_PRIME = re.compile(r"^(?P<stem>[A-Za-z]+)(?P<primes>'*)_(?P<idx>[^()]*)(?P<arg>\(.*\))?$")


def _latex_symbol(name: str) -> str:
    if name.endswith("'") and name[:-1].startswith(("u", "v")):
        inner = _latex_symbol(name[:-1])
        head, _, idx = inner.partition("_")
        return r"\dot{" + head + "}" + ("_" + idx if idx else "")
    m = re.fullmatch(r"([qu])(\d+)", name)
    if m:
        return f"{m.group(1)}_{{{m.group(2)}}}"
    m = _PRIME.match(name)
    if m:
        stem = {"Phi": r"\Phi", "Psi": r"\Psi", "zeta": r"\zeta", "theta": r"\theta",
                "rho": r"\rho", "alpha": r"\alpha"}.get(m.group("stem"), m.group("stem"))
        idx = m.group("idx").replace("_", r",")
        arg = m.group("arg") or ""
        return f"{stem}{m.group('primes')}_{{{idx}}}{arg}"
    return name.replace("_", r"\_")


def latex_names(eom) -> dict:
    """LaTeX names of the symbols of an equation set (for :func:`sympy.latex`)."""
    symbols = set(eom.constants) | set(eom.chain.q) | set(eom.chain.u) | set(eom.chain.ud.values())
    return {s: _latex_symbol(s.name) for s in symbols}


def _str(expr) -> str:
    return sp.sstr(expr, order="none")


def format_equations(eom, latex: bool = False) -> str:
    """F*_r and F_r (by source) for every generalized speed r, as text or LaTeX lines."""
    names = latex_names(eom) if latex else None
    lines = []
    for r, u in enumerate(eom.all_speeds):
        fs = collect_terms(eom, eom.F_r_star[r])
        active = {k: collect_terms(eom, v[r]) for k, v in eom.F_r.items() if v[r] != 0}
        if latex:
            lines.append(rf"F^*_{{{_latex_symbol(u.name)}}} &= {sp.latex(fs, symbol_names=names)} \\")
            for kind, expr in active.items():
                lines.append(rf"(F_{{{_latex_symbol(u.name)}}})_{{\mathrm{{{kind}}}}} &= "
                             rf"{sp.latex(expr, symbol_names=names)} \\")
        else:
            lines.append(f"F*[{u.name}] = {_str(fs)}")
            for kind, expr in active.items():
                lines.append(f"F[{u.name}]_{kind} = {_str(expr)}")
            if not active:
                lines.append(f"F[{u.name}] = 0")
    return "\n".join(lines)


def _constants_table(eom, values: dict | None) -> list[str]:
    if values is None:
        return []
    rows = ["| symbol | value |", "|---|---|"]
    for s in eom.constants:
        if s in values:
            rows.append(f"| ${_latex_symbol(s.name)}$ | {values[s]:.10g} |")
    return rows


def equations_markdown(eom, values: dict | None = None) -> str:
    """A Markdown report (with LaTeX) of the derivation: coordinates, kinematics, F*_r, F_r, constants."""
    names = latex_names(eom)
    model = eom.model
    out = [f"# Equations of motion: {model.name}", "",
           f"Derived by flexkane {__version__} with Kane's method: $F^*_r + F_r = 0$ (eq. 8.36) for every "
           "generalized speed $u_r$, written as $M(q, t)\\,\\dot u = f(q, u, t)$.", "",
           "## Generalized coordinates and speeds", "",
           "| coordinate | speed | kinematic equation |", "|---|---|---|"]
    for c in eom.chain.coordinates:
        qd = eom.chain.qdot[c.q]
        law = f" (driven: {'$' + sp.latex(c.law) + '$'} {c.driver})" if c.driver else ""
        out.append(f"| ${_latex_symbol(c.q.name)}$ | ${_latex_symbol(c.u.name)}${law} | "
                   f"$\\dot {_latex_symbol(c.q.name)} = {sp.latex(qd, symbol_names=names)}$ |")
    out += ["", "## Kinematics", ""]
    kin = eom.kinematics
    for name, frame in kin.bodies.items():
        out.append(f"* body {name}: angular velocity $\\omega = {sp.latex(frame.omega, symbol_names=names)}$, "
                   f"velocity of the mass centre along the body axes "
                   f"$({sp.latex(frame.v[0], symbol_names=names)},\\ {sp.latex(frame.v[1], symbol_names=names)})$")
    for name, bm in kin.beams.items():
        vx = sp.latex(sp.Add(*[c * sp.Symbol(_atom_name(a)) for a, c in bm.v[0].items()]), symbol_names=names)
        vy = sp.latex(sp.Add(*[c * sp.Symbol(_atom_name(a)) for a, c in bm.v[1].items()]), symbol_names=names)
        out.append(f"* beam {name}: velocity of the point at x along the beam axes (eq. 8.18): "
                   f"$({vx},\\ {vy})$")
    out += ["", "## Partial velocities", ""]
    for name, frame in kin.bodies.items():
        for u in eom.all_speeds:
            vx, vy, w = (sp.diff(frame.v[0], u), sp.diff(frame.v[1], u), sp.diff(frame.omega, u))
            if vx != 0 or vy != 0 or w != 0:
                out.append(f"* ${name}$, ${_latex_symbol(u.name)}$: $v_r = ({sp.latex(vx, symbol_names=names)},\\ "
                           f"{sp.latex(vy, symbol_names=names)})$, $\\omega_r = {sp.latex(w, symbol_names=names)}$")
    out += ["", "## Generalized inertia and active forces (eqs. 8.22, 8.23, 8.28-8.35)", "", "$$",
            "\\begin{aligned}", format_equations(eom, latex=True), "\\end{aligned}", "$$", ""]
    out += ["## Equations of motion", "",
            f"State: {', '.join(eom.state_names)}. Mass matrix $M$ is {len(eom.u)} x {len(eom.u)}.", ""]
    if values is not None:
        out += ["## Constants", "", "Modal constants (eq. 8.22, 8.32) and parameters, numeric values:", ""]
        out += _constants_table(eom, values)
        out.append("")
    return "\n".join(out)


def _atom_name(atom) -> str:
    kind = atom[0]
    if kind == "1":
        return "1"
    if kind == "x":
        return "x"
    if kind == "phi":
        return f"Phi_{atom[1]}(x)"
    if kind == "psi":
        return f"Psi_{atom[1]}(x)"
    return f"d_{atom[1]}{atom[2]}(x)"


def equations_latex(eom, values: dict | None = None) -> str:
    """A standalone LaTeX document of the printed equations."""
    body = format_equations(eom, latex=True)
    rows = ""
    if values is not None:
        rows = "\n".join(f"${_latex_symbol(s.name)}$ & {values[s]:.10g} \\\\" for s in eom.constants if s in values)
        rows = ("\\section*{Constants}\n\\begin{longtable}{ll}\n" + rows + "\n\\end{longtable}\n")
    return ("\\documentclass{article}\n\\usepackage{amsmath}\\usepackage{longtable}\n"
            "\\usepackage[margin=1.5cm,landscape]{geometry}\n\\begin{document}\n"
            f"\\section*{{Equations of motion: {eom.model.name}}}\n"
            "\\begin{align*}\n" + body + "\n\\end{align*}\n" + rows + "\\end{document}\n")
