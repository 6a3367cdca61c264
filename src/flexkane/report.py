"""Printed equations in the chapter's notation: text, a Markdown report and a LaTeX document.

The report follows the chapter's steps: generalized coordinates and speeds with the kinematic
equations (eqs. 8.10-8.16), the velocities of the bodies and of a point P of every beam (eqs. 8.17,
8.18), the partial velocities, the generalized inertia forces F*_r (eq. 8.22, printed with the modal
constants m_B, e_B, I_B, E_i, F_i, G_ij as eq. 8.23 is), the generalized active forces F_r by source
(eqs. 8.28-8.35) and a table of every constant: its definition, unit and numeric value. A spatial
chain (``dimensions = 3``) is printed by the same steps in three dimensions; its report cites the
chapter's equations as the planar ones its own generalize, never as its own.
:func:`render_pdf` turns ``equations.tex`` into a PDF where ``pdflatex`` is installed.

All of it but the model's name and the values of the table depends on the structure alone:
:func:`printed_structure` renders that part once (both documents share one rendering of the forces),
and :mod:`flexkane.equations_document` completes it for a model without SymPy.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import sympy as sp
from sympy.printing.latex import LatexPrinter
from sympy.printing.precedence import precedence
from sympy.printing.str import StrPrinter

from ._version import __version__
from .equations_document import (latex_document, markdown_document, number_text, parameter_text,
                                 tex_escape)
from .expressions import bounded_expand
from .model import schema
from .natural_order import natural_key

__all__ = ["collect_terms", "latex_names", "format_equations", "equations_markdown", "equations_latex",
           "printed_structure", "constant_columns", "constant_rows", "render_pdf", "PDFLATEX_MISSING"]

#: Message shown by :func:`render_pdf` without a LaTeX installation.
PDFLATEX_MISSING = ("PDF skipped: pdflatex is not on PATH (install a LaTeX distribution, e.g. TeX Live, "
                    "or compile equations.tex elsewhere)")

#: Characters of LaTeX source after which a long sum is continued on a new line.
_LINE = 150


#: Expressions with more operations than this are grouped by u' without being expanded first.
_EXPAND_LIMIT = 600

#: Printed size (nodes of the expression trees of all F*_r and F_r, a repeated subtree counted each
#: time it is printed) above which the forces are printed in terms of intermediates (common
#: subexpressions) instead of term by term: printing term by term takes time in proportion to the
#: printed size, which grows far faster than the equations' distinct subexpressions (for
#: two-link-flexible-arm with 10 + 10 modes about 7 minutes of CPU time; benchmarks/RESULTS.md).
TERM_BY_TERM_MAX = 200_000


def printed_size(exprs) -> int:
    """Nodes of the expression trees of ``exprs``, every repeated subtree counted where it occurs.

    Computed over the distinct subexpressions (each visited once), so in time proportional to
    their number, however large the printed form.
    """
    size: dict = {}
    stack = [(e, False) for e in exprs]
    while stack:
        node, done = stack.pop()
        if node in size:
            continue
        if done:
            size[node] = 1 + sum(size[a] for a in node.args)
        else:
            stack.append((node, True))
            stack.extend((a, False) for a in node.args if a not in size)
    return sum(size[e] for e in exprs)


def _forces(eom):
    """The forces of the report: ``(intermediates, rows)``.

    ``rows[r]`` is ``(F*_r, {kind: F_r by source})`` of the r-th speed. Up to
    :data:`TERM_BY_TERM_MAX` printed nodes, each is grouped by u' (:func:`collect_terms`) and
    ``intermediates`` is empty; above it, the common subexpressions of all of them are the
    intermediates ``x_k = ...`` (in order of evaluation) and the forces are written in terms of them.
    """
    forces = getattr(eom, "compact_forces", None) or {"F_r_star": eom.F_r_star, "F_r": eom.F_r}
    rows = [(forces["F_r_star"][r], {k: v[r] for k, v in forces["F_r"].items() if v[r] != 0})
            for r in range(len(eom.all_speeds))]
    flat = [e for star, active in rows for e in (star, *active.values())]
    named = eom.chain.intermediates.used_by(flat)
    signals = _signal_symbols(eom)
    if signals:   # sensors and controller outputs stay by name (their definitions: _signal_rows)
        named = [(sym, d) for sym, d in named if sym not in signals]
    if named:
        from .kane.intermediates import written_out

        # a short chain's kinematic intermediates are written out, as the chapter's equations are
        full = written_out(named, fits=lambda e: printed_size([e]) <= TERM_BY_TERM_MAX)
        if full is not None:
            rows = [(star.xreplace(full), {k: v.xreplace(full) for k, v in active.items()})
                    for star, active in rows]
            flat = [e for star, active in rows for e in (star, *active.values())]
            named = []
    if not named and printed_size(flat) <= TERM_BY_TERM_MAX:
        return [], [(collect_terms(eom, star), {k: collect_terms(eom, v) for k, v in active.items()})
                    for star, active in rows]
    common, reduced = sp.cse(flat, symbols=sp.numbered_symbols("x_", real=True), order="none")
    it = iter(reduced)
    return named + common, [(next(it), {k: next(it) for k in active}) for _, active in rows]


def _signal_symbols(eom) -> set:
    """The named sensors and controller outputs that efforts use (intermediates kept by name)."""
    from .kane.intermediates import Intermediate

    chain = eom.chain
    return {e for e in getattr(chain.symbols, "signals", {}).values() if isinstance(e, Intermediate)}


def _signal_definitions(eom) -> list:
    """``(symbol, expression, is_rate)``: each sensor and controller output that efforts use, then the
    rate of each controller state, in terms of q, u, z, t, the constants and the signals listed before
    (each written once: the printed size stays linear in the number of chained signals)."""
    chain = eom.chain
    definitions = dict(chain.intermediates.definitions)
    order = {sym: k for k, sym in enumerate(definitions)}
    signals = _signal_symbols(eom)
    out = [(sym, chain.intermediates.expand(definitions[sym], keep=signals), False)
           for sym in sorted(signals, key=order.__getitem__)]
    rates = eom.compact.zdot if getattr(eom, "compact", None) is not None else getattr(eom, "zdot", ())
    out += [(z, chain.intermediates.expand(rate, keep=signals), True) for z, rate in zip(getattr(eom, "z", ()), rates)]
    return out


def _signal_rows(eom, names) -> list[str]:
    """Aligned LaTeX rows of :func:`_signal_definitions`."""
    rows = []
    for sym, expr, is_rate in _signal_definitions(eom):
        label = rf"\dot{{{_latex(sym, names)}}}" if is_rate else _latex(sym, names)
        rows += _aligned(label, _latex_lines(eom, expr, names))
    return rows


def _intermediates_note(intermediates) -> str:
    return (f"The equations are too long to print term by term (more than {TERM_BY_TERM_MAX} printed "
            f"nodes): they are written in terms of {len(intermediates)} intermediates $x_k$, in order of "
            "evaluation: for a long chain, first the named quantities of its links from the ground "
            "outwards (angles, angular velocities, positions and velocities of their frames, partial "
            "velocities $\\partial v/\\partial u_r$ and rates; composite mass, first moment and inertia "
            "from the tips inwards), then the common subexpressions.")


def collect_terms(eom, expr: sp.Expr) -> sp.Expr:
    """Group an expression by the speed derivatives u', as eq. 8.23 is written.

    Small expressions are expanded first (the chapter's form: sums of products of constants,
    coordinates and speeds); large ones (chains of several links, whose expanded forms run to
    thousands of terms) are split into ``sum_s (dF/du'_s) u'_s`` plus the rest, unexpanded.
    """
    ud = list(eom.chain.ud.values())
    # a sum of n terms has at least n - 1 operations: the bound spares counting those of a long sum
    if len(sp.Add.make_args(expr)) - 1 <= _EXPAND_LIMIT and sp.count_ops(expr) <= _EXPAND_LIMIT:
        variables = [*eom.chain.q, *eom.chain.u, *ud]
        expanded = bounded_expand(expr, variables, eom.t)   # user expressions (time laws) are never expanded
        if expanded is not None:
            grouped = _collect_linear(expanded, ud)
            return grouped if grouped is not None else sp.collect(expanded, ud)
    grouped = _collect_linear(expr, ud)      # each u' a factor of a term: group without expanding
    if grouped is not None:
        return grouped
    rest = expr.xreplace({s: 0 for s in ud})
    return sp.Add(*[sp.diff(expr, s) * s for s in ud if expr.has(s)], rest)


def _collect_linear(expr: sp.Expr, ud: list) -> sp.Expr | None:
    """A sum grouped by the speed derivatives ``ud``, when each is a factor of the terms it is in.

    Kane's equations are linear in the speed derivatives, so every term of their sums holds at most
    one of them as a factor: its coefficient goes to that derivative's group, in one pass over the
    terms. For an expanded sum this equals ``sympy.collect(expr, ud)`` (some 30 times slower: it
    matches every term against every symbol). ``None`` when a u' is not a plain factor of a term
    (inside a power, a function or a nested sum), for the caller's general method.
    """
    wanted = set(ud)
    groups: dict = {}
    rest = []
    for term in sp.Add.make_args(expr):
        factors = sp.Mul.make_args(term)
        found = [factor for factor in factors if factor in wanted]
        if not found:
            if term.has(*wanted):
                return None
            rest.append(term)
            continue
        coefficient = sp.Mul(*[factor for factor in factors if factor is not found[0]])
        if len(found) > 1 or coefficient.has(*wanted):
            return None
        groups.setdefault(found[0], []).append(coefficient)
    return sp.Add(*[sp.Add(*coefficients) * s for s, coefficients in groups.items()], *rest)


# ---------------------------------------------------------------------- names
_GREEK = {"Phi": r"\Phi", "Psi": r"\Psi", "zeta": r"\zeta", "theta": r"\theta", "rho": r"\rho",
          "alpha": r"\alpha", "omega": r"\omega", "lambda": r"\lambda", "phi": r"\phi", "psi": r"\psi"}
_NAME = re.compile(r"^(?P<stem>[A-Za-z]+)(?P<pre>'*)_(?P<idx>[^()']+)(?P<post>'*)(?P<arg>\(.*\))?$")


def _latex_symbol(name: str) -> str:
    """LaTeX of a symbol name: ``u3'`` -> ``\\dot{u}_{3}``, ``Phi_1'''(0)`` -> ``\\Phi_{1}'''(0)``."""
    if name.endswith("'") and name[:-1].startswith(("u", "v")):
        inner = _latex_symbol(name[:-1])
        head, _, idx = inner.partition("_")
        return r"\dot{" + head + "}" + ("_" + idx if idx else "")
    m = re.fullmatch(r"([qu])(\d+)", name)
    if m:
        return f"{m.group(1)}_{{{m.group(2)}}}"
    m = _NAME.match(name)
    if m:
        stem = m.group("stem")
        stem = _GREEK.get(stem, stem if len(stem) == 1 else rf"\mathrm{{{stem}}}")
        idx = m.group("idx").replace("_", ",")
        return f"{stem}{m.group('pre')}_{{{idx}}}{m.group('post')}{m.group('arg') or ''}"
    return _GREEK.get(name, name.replace("_", r"\_"))


def latex_names(eom) -> dict:
    """LaTeX names of the symbols of an equation set (for :func:`sympy.latex`)."""
    symbols = set(eom.constants) | set(eom.chain.q) | set(eom.chain.u) | set(eom.chain.ud.values())
    return {s: _latex_symbol(s.name) for s in symbols}


class _NaturalStrPrinter(StrPrinter):
    """SymPy's text printer with the terms of every sum in natural order of their text.

    Terms in a speed derivative u'_s come first, in the order of the speeds; the others follow in
    natural order (``E_1*q4 + E_2*q5 + ... + E_10*q13``, not ``E_1*q4 + E_10*q13 + ...``). Each term
    is printed once.
    """

    def __init__(self, ud=(), **settings):
        super().__init__({"order": "none", **settings})
        self._ud = {s: k for k, s in enumerate(ud)}

    def _print_Add(self, expr, order=None):
        prec = precedence(expr)
        items = []
        for term in expr.args:
            text = self._print(term)
            if text.startswith("-") and not term.is_Add:
                sign, text = "-", text[1:]
            else:
                sign = "+"
            if precedence(term) < prec or term.is_Add:
                text = f"({text})"
            items.append((_term_order(term, text, self._ud), sign, text))
        items.sort(key=lambda item: item[0])
        out = []
        for k, (_, sign, text) in enumerate(items):
            out.append(("-" if sign == "-" else "") + text if k == 0 else f"{sign} {text}")
        return " ".join(out)


class _NaturalLatexPrinter(LatexPrinter):
    """SymPy's LaTeX printer with the terms of every sum in natural order (see :class:`_NaturalStrPrinter`)."""

    def _as_ordered_terms(self, expr, order=None):
        return _natural_terms(expr)


def _term_order(term, text: str, ud: dict) -> tuple:
    """Sort key of a printed term: terms in u'_s first (in the order of the speeds), then natural order."""
    if ud:
        found = [ud[s] for s in sp.Mul.make_args(term) if s in ud]
        if found:
            return (0, min(found), ())
    return (1, 0, natural_key(text))


def _natural_terms(expr) -> list:
    """The terms of a sum in natural order of their text."""
    return sorted(sp.Add.make_args(expr), key=lambda term: natural_key(sp.sstr(term, order="none")))


def _str(expr, ud=()) -> str:
    """Text of an expression; terms of sums in natural order, those in the speed derivatives ``ud`` first."""
    return _NaturalStrPrinter(ud).doprint(expr)


def _term_key(eom):
    ud = list(eom.chain.ud.values())

    def key(term):
        found = [i for i, s in enumerate(ud) if term.has(s)]
        return (0, found[0], ()) if found else (1, 0, natural_key(sp.sstr(term, order="none")))
    return key


def _tokens(expr: sp.Expr, names: dict, order=None) -> list:
    """LaTeX pieces of an expression with the places where a line may break.

    Items are strings, ``"("`` / ``")"`` (a ``\\left(`` / ``\\right)`` pair that a line break must
    close and reopen) and ``None`` (a line may break here, before a sign). A sum breaks between its
    terms; a product with a sum among its factors breaks inside that sum.
    """
    if not isinstance(expr, sp.Add):
        return _product_tokens(expr, names)
    out = []
    for i, term in enumerate(sorted(sp.Add.make_args(expr), key=order) if order else _natural_terms(expr)):
        coeff, _ = term.as_coeff_Mul()
        negative = coeff.is_negative
        body = _product_tokens(-term if negative else term, names)
        if i:
            out += [None, " - " if negative else " + "]
        elif negative:
            out.append("- ")
        out += body
    return out


def _product_tokens(term: sp.Expr, names: dict) -> list:
    sums = [f for f in sp.Mul.make_args(term) if isinstance(f, sp.Add)] if isinstance(term, sp.Mul) else []
    if not sums:
        return [_latex(term, names)]
    inner = max(sums, key=sp.count_ops)
    others = sp.Mul(*[f for f in sp.Mul.make_args(term) if f is not inner])
    head = "" if others == 1 else ("- " if others == -1 else _latex(others, names) + " ")
    return [head, "("] + _tokens(inner, names) + [")"]


def _latex_lines(eom, expr: sp.Expr, names: dict, width: int = _LINE) -> list[str]:
    """LaTeX of a sum, terms in u' first (in the order of the speeds), cut into lines of about
    ``width`` characters; parentheses open across a line break are closed with ``\\right.`` and
    reopened with ``\\left.``."""
    lines, line, depth = [], "", 0
    tokens = _tokens(expr, names, _term_key(eom))
    for k, item in enumerate(tokens):
        if item is None:
            if len(line) > width or (len(line) > width // 2 and len(line) + _piece_length(tokens, k + 1) > width):
                lines.append(line + r"\right." * depth)
                line = r"\left." * depth
        elif item == "(":
            line += r"\left("
            depth += 1
        elif item == ")":
            line += r"\right)"
            depth -= 1
        else:
            line += item
    lines.append(line or "0")
    return lines


def _piece_length(tokens: list, start: int) -> int:
    """Length of the LaTeX from ``tokens[start]`` to the next place where a line may break."""
    length = 0
    for item in tokens[start:]:
        if item is None:
            break
        length += len(r"\left(") if item == "(" else len(r"\right)") if item == ")" else len(item)
    return length


def _aligned(label: str, lines: list[str]) -> list[str]:
    """``label &= line1 \\\\ &\\quad line2 ...`` rows of an aligned environment."""
    out = [f"{label} &= {lines[0]}"]
    out += [rf"&\quad {line}" for line in lines[1:]]
    return [row + r" \\" for row in out]


def format_equations(eom, latex: bool = False) -> str:
    """F*_r and F_r (by source) for every generalized speed r, as text or LaTeX lines."""
    names = latex_names(eom) if latex else None
    ud = list(eom.chain.ud.values())
    lines = []
    intermediates, forces = _forces(eom)
    if latex:
        lines += _signal_rows(eom, names)
    else:
        lines += [f"{sym}{chr(39) if is_rate else ''} = {_str(expr, ud)}" for sym, expr, is_rate in _signal_definitions(eom)]
    for sym, expr in intermediates:
        if latex:
            lines += _aligned(_latex(sym, names), _latex_lines(eom, expr, names))
        else:
            lines.append(f"{sym} = {_str(expr, ud)}")
    for r, u in enumerate(eom.all_speeds):
        fs, active = forces[r]
        if latex:
            lines += _aligned(rf"F^*_{{{_latex_symbol(u.name)}}}", _latex_lines(eom, fs, names))
            for kind, expr in active.items():
                lines += _aligned(rf"(F_{{{_latex_symbol(u.name)}}})_{{\mathrm{{{kind}}}}}",
                                  _latex_lines(eom, expr, names))
            if not active:
                lines.append(rf"F_{{{_latex_symbol(u.name)}}} &= 0 \\")
        else:
            lines.append(f"F*[{u.name}] = {_str(fs, ud)}")
            for kind, expr in active.items():
                lines.append(f"F[{u.name}]_{kind} = {_str(expr, ud)}")
            if not active:
                lines.append(f"F[{u.name}] = 0")
    return "\n".join(lines)


# ---------------------------------------------------------------------- kinematics
def _atom_latex(atom) -> str:
    kind = atom[0]
    if kind == "1":
        return ""
    if kind == "x":
        return "x"
    if kind == "theta":       # torsion shape function of a spatial beam
        return rf"\Theta_{{{atom[1]}}}(x)"
    if len(atom) == (3 if kind == "phi" else 4):    # a spatial beam's direction-labelled atom
        stem = r"\Phi" if kind == "phi" else "d"
        indices = "".join(str(i) for i in atom[1:-1])
        return rf"{stem}^{{{atom[-1]}}}_{{{indices}}}(x)"
    if kind == "phi":
        return rf"\Phi_{{{atom[1]}}}(x)"
    if kind == "psi":
        return rf"\Psi_{{{atom[1]}}}(x)"
    if kind == "dphi":
        label = f"^{{{atom[2]}}}" if len(atom) == 3 else ""     # a spatial beam's slope atom: its direction
        return rf"\Phi{label}_{{{atom[1]}}}'(x)"
    return rf"d_{{{atom[1]}{atom[2]}}}(x)"


def _field_latex(field, names: dict) -> str:
    """LaTeX of a modal field ``sum_a c_a f_a(x)`` (atom by atom, as eq. 8.18 is written)."""
    parts = []
    for atom, coefficient in field.items():
        c = _latex(coefficient, names)
        f = _atom_latex(atom)
        if not f:
            parts.append(c)
        elif coefficient == 1:
            parts.append(f)
        elif coefficient == -1:
            parts.append("-" + f)
        else:
            parts.append(rf"\left({c}\right) {f}" if isinstance(coefficient, sp.Add) else f"{c} {f}")
    text = " + ".join(parts) or "0"
    return re.sub(r"\+ -\s*", "- ", text)


def _latex(expr, names) -> str:
    """LaTeX of an expression with the chapter's symbol names, terms of sums in natural order."""
    return _NaturalLatexPrinter({"symbol_names": names or {}}).doprint(expr)


def _kinematics(eom, names) -> list[tuple[str, list[str]]]:
    """(heading, items) of the kinematics and the partial velocities; items are LaTeX-bearing text."""
    kin = eom.kinematics
    speeds = eom.all_speeds
    if getattr(kin, "dimensions", 2) == 3:
        return _spatial_kinematics(eom, names)
    velocities = []
    for name, frame in kin.bodies.items():
        velocities.append(f"body {name}: angular velocity $\\omega = {_latex(frame.omega, names)}$, velocity of "
                          f"the mass centre along the body axes $({_latex(frame.v[0], names)},\\ "
                          f"{_latex(frame.v[1], names)})$")
    for name, bm in kin.beams.items():
        velocities.append(f"beam {name}: angular velocity of its frame $\\omega = {_latex(bm.frame.omega, names)}$, "
                          f"velocity of the point P at x along the beam axes (eq. 8.18) "
                          f"$({_field_latex(bm.v[0], names)},\\ {_field_latex(bm.v[1], names)})$")
        if bm.rotation is not None:
            velocities.append(f"beam {name}: angular velocity of the section at x (Rayleigh beam) "
                              f"$\\omega_s = {_field_latex(bm.rotation, names)}$")
    partial = []
    for name, frame in kin.bodies.items():
        for u in speeds:
            vx, vy, w = (sp.diff(frame.v[0], u), sp.diff(frame.v[1], u), sp.diff(frame.omega, u))
            if vx != 0 or vy != 0 or w != 0:
                partial.append(f"body {name}, ${_latex_symbol(u.name)}$: $v_r = ({_latex(vx, names)},\\ "
                               f"{_latex(vy, names)})$, $\\omega_r = {_latex(w, names)}$")
    for name, bm in kin.beams.items():
        for u in speeds:
            vx, vy = (bm.v[k].map(lambda c: sp.diff(c, u)) for k in range(2))
            w = sp.diff(bm.frame.omega, u)
            if not (vx.is_zero() and vy.is_zero()) or w != 0:
                partial.append(f"beam {name}, ${_latex_symbol(u.name)}$: $\\partial v_P / \\partial "
                               f"{_latex_symbol(u.name)} = ({_field_latex(vx, names)},\\ {_field_latex(vy, names)})$, "
                               f"$\\omega_r = {_latex(w, names)}$")
    return [("Kinematics (eqs. 8.11-8.18)", velocities), ("Partial velocities", partial)]


def _spatial_kinematics(eom, names) -> list[tuple[str, list[str]]]:
    """(heading, items) of a spatial chain: each body's angular velocity and mass-centre velocity
    along its axes, and their partial velocities, in terms of the intermediates."""
    kin = eom.kinematics

    def vector(v):
        return "(" + ",\\ ".join(_latex(c, names) for c in v) + ")"

    velocities, partial = [], []
    for name, frame in kin.bodies.items():
        velocities.append(f"body {name}: angular velocity along the body axes $\\omega = {vector(frame.omega)}$, "
                          f"velocity of the mass centre along the body axes $v = {vector(frame.v)}$")
        for u in eom.all_speeds:
            v = [eom.chain.partial(c, u) for c in frame.v]
            w = [eom.chain.partial(c, u) for c in frame.omega]
            if any(c != 0 for c in v + w):
                partial.append(f"body {name}, ${_latex_symbol(u.name)}$: $v_r = {vector(v)}$, "
                               f"$\\omega_r = {vector(w)}$")
    return [("Kinematics", velocities), ("Partial velocities", partial)]


# ---------------------------------------------------------------------- constants
_PAIR_UNITS = {0: "kg", 1: "kg m", 2: "kg m^2"}


def _pair_definition(a, b) -> tuple[str, str]:
    if a == b == ("x",):
        body = r"x^2\,"
    else:
        body = "".join(f + r"\," for f in (_atom_latex(a), _atom_latex(b)) if f)
    power = sum(1 for atom in (a, b) if atom[0] == "x") - sum(1 for atom in (a, b) if atom[0] == "d")
    unit = _PAIR_UNITS.get(power, f"kg m^{power}")
    return rf"\int_0^L \rho\,{body}dx", unit


def _definition(spec) -> tuple[str, str]:
    """LaTeX definition and unit of a modal constant from its specification."""
    kind = spec[0]
    if kind == "pair":
        return _pair_definition(spec[1], spec[2])
    if kind == "rotary":
        body = "".join(f + r"\," for f in (_atom_latex(spec[1]), _atom_latex(spec[2])) if f)
        slopes = sum(1 for atom in spec[1:] if atom[0] == "dphi")
        return rf"\int_0^L \rho I\,{body}dx", ("kg m^2", "kg m", "kg")[slopes]
    if kind in ("section", "polar"):      # a spatial beam's turning sections
        pair = spec[2:] if kind == "section" else spec[1:]
        weight = "I_p" if kind == "polar" else {"y": "I_z", "z": "I_y"}[spec[1]]   # about b1, z_p, y_p
        body = "".join(f + r"\," for f in (_atom_latex(pair[0]), _atom_latex(pair[1])) if f)
        slopes = sum(1 for atom in pair if atom[0] == "dphi")
        return rf"\int_0^L \rho {weight}\,{body}dx", ("kg m^2", "kg m", "kg")[slopes]
    if kind == "Hs":
        rigidity, f = ("EI_z" if spec[1] == "y" else "EI_y"), rf"\Phi^{{{spec[1]}}}"
        return rf"\int_0^L {rigidity}\,{f}_{{{spec[2]}}}''\,{f}_{{{spec[3]}}}''\,dx", "N/m"
    if kind == "Kt":
        return rf"\int_0^L GJ\,\Theta_{{{spec[1]}}}'\,\Theta_{{{spec[2]}}}'\,dx", "N m"
    if kind == "H":
        return rf"\int_0^L EI\,\Phi_{{{spec[1]}}}''\,\Phi_{{{spec[2]}}}''\,dx", "N/m"
    if kind == "HA":
        return rf"\int_0^L EA\,\Psi_{{{spec[1]}}}'\,\Psi_{{{spec[2]}}}'\,dx", "N/m"
    if kind == "station":
        atom, deriv, x = spec[1], spec[2], spec[3]
        f = _atom_latex(atom).replace("(x)", "")
        unit = "-" if deriv == 0 else f"1/m^{deriv}" if deriv > 1 else "1/m"
        return rf"{f}{chr(39) * deriv}\ \mathrm{{at}}\ x = {sp.latex(x)}", unit
    if kind == "shear" and len(spec) == 5:    # a spatial beam's: its bending plane, the atom of the integral
        _, which, i, label, atom = spec
        f, a = rf"\Phi^{{{label}}}_{{{i}}}", _atom_latex(atom).replace("(x)", "")
        if which in ("M0", "V0"):
            return (rf"{f}''(0)", "1/m^2") if which == "M0" else (rf"{f}'''(0)", "1/m^3")
        return rf"\int_0^L {a + chr(92) + ',' if a else ''}{f}''''\,dx", "1/m^2" if which == "Jx" else "1/m^3"
    if kind == "shear":
        _, which, i, j = spec
        return {"M0": (rf"\Phi_{{{i}}}''(0)", "1/m^2"), "V0": (rf"\Phi_{{{i}}}'''(0)", "1/m^3"),
                "J": (rf"\int_0^L \Phi_{{{i}}}''''\,dx", "1/m^3"),
                "Jx": (rf"\int_0^L x\,\Phi_{{{i}}}''''\,dx", "1/m^2"),
                "JPhi": (rf"\int_0^L \Phi_{{{j}}}\,\Phi_{{{i}}}''''\,dx", "1/m^3")}[which]
    return "", ""


def constant_columns(eom) -> list[tuple[int, str, str, str, str, str, str]]:
    """The columns of the table of constants that the structure fixes, one row per constant.

    Returns
    -------
    list of (int, str, str, str, str, str, str)
        ``(index in eom.constants, name, kind, LaTeX symbol, beam or source, LaTeX definition, unit)``;
        modal constants first, then parameters and other values of the model. ``kind`` is
        ``"modal"``, ``"parameter"`` (its definition is the text given for it, a number of the
        model: :func:`flexkane.equations_document.parameter_text`), ``"defined"`` (a value field of
        the model, with the unit :mod:`flexkane.model.schema` declares for it) or ``""``.
    """
    modal = eom.beam_constant_symbols()
    defined = eom.chain.symbols.definitions
    params = eom.model.parameters
    rows_modal, rows_other = [], []
    for index, s in enumerate(eom.constants):
        if s in modal:
            beam, consts = modal[s]
            definition, unit = _definition(consts.used[s])
            rows_modal.append((index, s.name, "modal", _latex_symbol(s.name), f"beam {beam}", definition, unit))
        elif s.name in params:
            rows_other.append((index, s.name, "parameter", _latex_symbol(s.name), "parameter", "", ""))
        elif s in defined:    # a value field: its unit as the model schema declares it
            unit = schema.unit_of_path(defined[s][0], eom.model.dimensions, eom.model) or ""
            rows_other.append((index, s.name, "defined", _latex_symbol(s.name), f"`{defined[s][0]}`", "", unit))
        else:
            rows_other.append((index, s.name, "", _latex_symbol(s.name), "", "", ""))
    return rows_modal + rows_other


def constant_rows(eom, values: dict | None = None) -> list[tuple[str, str, str, str, str]]:
    """One row per constant of the equations: (LaTeX symbol, beam or source, LaTeX definition, unit,
    value as text); modal constants first, then parameters and other values of the model.

    Without ``values``, a value field of the model shows the value it is given as.
    """
    params = eom.model.parameters
    rows = []
    for index, name, kind, symbol, source, definition, unit in constant_columns(eom):
        s = eom.constants[index]
        if kind == "parameter":
            definition = parameter_text(params[name])
        if values is not None and s in values:
            value = number_text(values[s])
        else:
            value = tex_escape(str(eom.chain.symbols.definitions[s][1])) if kind == "defined" else ""
        rows.append((symbol, source, definition, unit, value))
    return rows


def _cite(eom, equations: str) -> str:
    """A citation of the chapter's ``equations`` (``"eqs. 8.22, 8.23"``) for the report of ``eom``: the
    equations themselves for a planar chain, what the printed equations generalize for a spatial one."""
    if eom.model.dimensions == 3:
        return f"the spatial generalization of the planar {equations}"
    return equations


def _modal_constants_source(eom) -> str:
    """Where the chapter defines the modal constants the table lists."""
    if eom.model.dimensions == 3:
        return ("the planar ones below eq. 8.22 and eq. 8.32 generalized to two bending planes, torsion "
                "and stretch")
    return "below eq. 8.22 and eq. 8.32"


def _as_planar(eom, equation: str) -> str:
    """``equation`` as a pattern the printed equations follow: ``"eq. 8.23"``, or for a spatial chain
    ``"the planar eq. 8.23"``."""
    return f"the planar {equation}" if eom.model.dimensions == 3 else equation


# ---------------------------------------------------------------------- documents
def _printed_parts(eom) -> dict:
    """The rendered pieces that ``equations.md`` and ``equations.tex`` share (rendered once for both):
    the LaTeX names, the kinematics items, the rows of the signals, the intermediates and their rows,
    and the rows of F*_r and F_r of every speed."""
    names = latex_names(eom)
    kinematics = _kinematics(eom, names)
    signal_rows = _signal_rows(eom, names)
    intermediates, forces = _forces(eom)
    return {"names": names, "kinematics": kinematics, "signal_rows": signal_rows,
            "intermediates": intermediates,
            "intermediate_rows": _intermediate_rows(eom, intermediates, names) if intermediates else [],
            "speeds": [_one_speed(eom, forces[r], u, names) for r, u in enumerate(eom.all_speeds)]}


def _markdown_body(eom, parts: dict) -> str:
    """The Markdown report between its title and its table of constants."""
    names = parts["names"]
    out = ["", f"Derived by flexkane {__version__} with Kane's method: $F^*_r + F_r = 0$ ({_cite(eom, 'eq. 8.36')}) "
           "for every generalized speed $u_r$, written as $M(q, t)\\,\\dot u = f(q, u, t)$.", "",
           "## Generalized coordinates and speeds", "",
           "| coordinate | speed | kinematic equation |", "|---|---|---|"]
    for c in eom.chain.coordinates:
        qd = eom.chain.qdot[c.q]
        law = f" (driven: {'$' + sp.latex(c.law) + '$'} {c.driver})" if c.driver else ""
        speed = f"${_latex_symbol(c.u.name)}$" if c.u is not None else "(none: an Euler parameter)"
        out.append(f"| ${_latex_symbol(c.q.name)}$ | {speed}{law} | "
                   f"$\\dot {_latex_symbol(c.q.name)} = {_latex(qd, names)}$ |")
    for heading, items in parts["kinematics"]:
        out += ["", f"## {heading}", ""] + [f"* {item}" for item in items]
    out += ["", f"## Generalized inertia and active forces ({_cite(eom, 'eqs. 8.22, 8.23, 8.28-8.35')})", "",
            "Vectors are resolved along the axes of the link they belong to. F*_r is grouped by the "
            f"derivatives of the speeds, as {_as_planar(eom, 'eq. 8.23')} is.", ""]
    if parts["signal_rows"]:
        out += ["Sensors and controller outputs the efforts use (by name below), and the rates of the "
                "controller states:", "", "$$", "\\begin{aligned}", *parts["signal_rows"], "\\end{aligned}",
                "$$", ""]
    if parts["intermediates"]:
        out += [_intermediates_note(parts["intermediates"]), "", "$$", "\\begin{aligned}"]
        out += parts["intermediate_rows"]
        out += ["\\end{aligned}", "$$", ""]
    for rows in parts["speeds"]:
        out += ["$$", "\\begin{aligned}", *rows, "\\end{aligned}", "$$", ""]
    out += ["## Equations of motion", "",
            f"State: {', '.join(eom.state_names)}. Mass matrix $M$ is {len(eom.u)} x {len(eom.u)}.", ""]
    return "\n".join(out)


def _latex_body(eom, parts: dict) -> str:
    """The LaTeX document between its title and its table of constants."""
    names = parts["names"]
    doc = [tex_escape(f"Derived by flexkane {__version__} with Kane's method: ") +
           rf"$F^*_r + F_r = 0$ ({tex_escape(_cite(eom, 'eq. 8.36'))}) for every generalized speed $u_r$, written as "
           r"$M(q, t)\,\dot u = f(q, u, t)$.", "",
           r"\subsection*{Generalized coordinates and speeds}", r"\begin{align*}"]
    for c in eom.chain.coordinates:
        qd = eom.chain.qdot[c.q]
        driven = rf" && \text{{(driven: {c.driver})}}" if c.driver else ""
        doc.append(rf"\dot {_latex_symbol(c.q.name)} &= {_latex(qd, names)}{driven} \\")
    doc.append(r"\end{align*}")
    for heading, items in parts["kinematics"]:
        doc += [rf"\subsection*{{{heading}}}", r"\begin{itemize}"]
        doc += [rf"\item {_md_to_tex(item)}" for item in items] or [r"\item none"]
        doc.append(r"\end{itemize}")
    doc += [rf"\subsection*{{Generalized inertia and active forces ({_cite(eom, 'eqs. 8.22, 8.23, 8.28--8.35')})}}"]
    if parts["signal_rows"]:
        doc += ["Sensors and controller outputs the efforts use, and the rates of the controller states:",
                r"\begin{align*}", *parts["signal_rows"], r"\end{align*}"]
    if parts["intermediates"]:
        doc += [_md_to_tex(_intermediates_note(parts["intermediates"])), r"\begin{align*}"]
        doc += parts["intermediate_rows"] + [r"\end{align*}"]
    for rows in parts["speeds"]:
        doc += [r"\begin{align*}", *rows, r"\end{align*}"]
    return "\n".join(doc)


def printed_structure(eom) -> dict:
    """The printed equations of a structure: all of ``equations.md`` and ``equations.tex`` that does not
    depend on the numbers or the name of one model of it.

    Rendered with SymPy (seconds to minutes for a large model); :mod:`flexkane.equations_document`
    completes it for a model without SymPy, and :class:`flexkane.derivation_cache.Derivation` stores it
    once per structure.

    Parameters
    ----------
    eom : EquationsOfMotion

    Returns
    -------
    dict
        Plain JSON data: ``md`` and ``tex`` (the text between the title and the table of constants),
        ``constants`` (:func:`constant_columns`, as lists) and ``constants_source`` (where the chapter
        defines the modal constants, as the table's introduction cites it).
    """
    parts = _printed_parts(eom)
    return {"md": _markdown_body(eom, parts), "tex": _latex_body(eom, parts),
            "constants": [list(row) for row in constant_columns(eom)],
            "constants_source": _modal_constants_source(eom)}


def equations_markdown(eom, values: dict | None = None) -> str:
    """A Markdown report (with LaTeX) of the derivation: coordinates, kinematics, partial velocities,
    F*_r, F_r and, when ``values`` are given, the constants with their definitions and values."""
    rows = constant_rows(eom, values) if values is not None else None
    return markdown_document(eom.model.name, _markdown_body(eom, _printed_parts(eom)), rows,
                             constants_source=_modal_constants_source(eom))


def _intermediate_rows(eom, intermediates, names) -> list[str]:
    rows = []
    for sym, expr in intermediates:
        rows += _aligned(_latex(sym, names), _latex_lines(eom, expr, names))
    return rows


def _one_speed(eom, force, u, names) -> list[str]:
    """Aligned rows of F*_r and F_r of one speed; ``force`` is its row of :func:`_forces`."""
    label = _latex_symbol(u.name)
    star, active = force
    rows = _aligned(rf"F^*_{{{label}}}", _latex_lines(eom, star, names))
    for kind, expr in active.items():
        rows += _aligned(rf"(F_{{{label}}})_{{\mathrm{{{kind}}}}}", _latex_lines(eom, expr, names))
    if not active:
        rows.append(rf"F_{{{label}}} &= 0 \\")
    return rows


def _md_to_tex(item: str) -> str:
    """Plain words of a list item escaped for LaTeX, its $...$ parts kept."""
    parts = item.split("$")
    return "$".join(p if i % 2 else tex_escape(p) for i, p in enumerate(parts))


def equations_latex(eom, values: dict | None = None) -> str:
    """A standalone LaTeX document: the same content as :func:`equations_markdown`."""
    rows = constant_rows(eom, values) if values is not None else None
    return latex_document(eom.model.name, _latex_body(eom, _printed_parts(eom)), rows)


def render_pdf(tex_path, *, timeout: float = 120.0) -> tuple[Path | None, str]:
    """Compile a LaTeX file with ``pdflatex`` into a PDF beside it.

    Parameters
    ----------
    tex_path : str or pathlib.Path
        The ``.tex`` file.
    timeout : float
        Longest time allowed for each pdflatex pass [s].

    Returns
    -------
    (pathlib.Path or None, str)
        The PDF (None when it could not be made) and a message for the user ("" on success). A
        missing LaTeX installation or a failed compilation is reported, never raised.
    """
    from .atomic import atomic_write_bytes

    tex_path = Path(tex_path)
    exe = shutil.which("pdflatex")
    if exe is None:
        return None, PDFLATEX_MISSING
    with tempfile.TemporaryDirectory(prefix="flexkane-latex-") as work:
        source = Path(work) / "equations.tex"
        source.write_bytes(tex_path.read_bytes())
        for _ in range(2):            # the second pass settles the widths of the long table
            try:
                proc = subprocess.run([exe, "-interaction=nonstopmode", "-halt-on-error", source.name],
                                      cwd=work, capture_output=True, text=True, timeout=timeout,
                                      stdin=subprocess.DEVNULL)
            except (OSError, subprocess.TimeoutExpired) as exc:
                return None, f"PDF skipped: pdflatex did not finish ({exc})"
            if proc.returncode != 0:
                errors = [line for line in proc.stdout.splitlines() if line.startswith("!")]
                detail = errors[0] if errors else f"exit code {proc.returncode}"
                return None, f"PDF skipped: pdflatex failed on {tex_path.name}: {detail}"
        pdf = tex_path.with_suffix(".pdf")
        atomic_write_bytes(pdf, (Path(work) / "equations.pdf").read_bytes())
    return pdf, ""
