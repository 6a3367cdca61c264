"""Python source of the Numba right-hand side and output functions, from symbolic equations.

The equations of motion ``M(q, t) u' = f(q, u, t)`` with ``q' = qdot(q, u, t)`` become one
function ``rhs(t, y, p, dy) -> int`` of the first-order system ``y' = [q', u']``, ``y = [q, u]``:
common subexpressions of ``qdot``, the upper triangle of the symmetric ``M`` and ``f`` are
eliminated jointly (``sympy.cse``), printed as ``math``-module Python, and ``M u' = f`` is solved
by ``M = L D L^T`` (unrolled into scalar statements for ``nu <= UNROLL_LDL_MAX``, else by
``ldl_solve`` of :mod:`flexkane.numerics.linear_algebra`). ``rhs`` returns 0, or 2 (non-finite)
/ 4 (singular mass matrix) with ``dy`` filled with NaN.

Large models (many modes, many links) are split: when the printed statements exceed
``SPLIT_CHARS`` characters, they are distributed over functions ``rhs_part0, rhs_part1, ...``
of about ``SPLIT_CHARS`` characters each, which pass the common subexpressions they share
through a work array. Numba's compile time of one function grows faster than its length (LLVM
optimises a single basic block; measured for ``falling-beam-exact`` with 40 modes: 145 s for
one function, of which 110 s in LLVM), and linearly over many functions.

The text returned here is a fragment: :func:`flexkane.numerics.jit_module.build_module` puts it in
a module with the imports and the integrator templates.
"""

from __future__ import annotations

import keyword
import re
from collections.abc import Mapping, Sequence

import sympy
from sympy.printing.codeprinter import PrintMethodNotImplementedError
from sympy.printing.pycode import PythonCodePrinter

__all__ = ["SPLIT_CHARS", "SUM_TERMS_MAX", "UNROLL_LDL_MAX", "generate_outputs_source", "generate_rhs_source"]

# Largest number of speeds for which L D L^T is written as scalar statements (no allocation,
# about 20 ns saved per call); above it a loop over an allocated array is used.
UNROLL_LDL_MAX = 8

# Printed characters of statements per generated function above which the right-hand side is
# split into parts (see the module docstring; chosen by measuring compile times).
SPLIT_CHARS = 20_000
# Largest number of terms of one sum in a split right-hand side (longer sums become partial sums).
SUM_TERMS_MAX = 200

# Names of the generated functions' arguments, and names no model symbol may take.
_RESERVED = {"t", "y", "p", "dy", "math", "np", "njit", "min", "max", "abs", "range",
             "ldl_solve", "mass_matrix_failure", "float", "int", "complex", "bool", "len",
             "rhs", "outputs", "PIVOT_RTOL", "w", "M"}


class _MathPrinter(PythonCodePrinter):
    """Python printer for Numba: ``math.`` calls, floats printed exactly, errors on the unknown."""

    def __init__(self):
        super().__init__({"fully_qualified_modules": True, "standard": "python3"})

    def _print_Float(self, expr):
        return repr(float(expr))

    def _print_Rational(self, expr):
        return f"({int(expr.p)}/{int(expr.q)})"

    def _print_Half(self, expr):
        return "0.5"

    def _print_Piecewise(self, expr):
        # Without an "otherwise" branch the value is undefined there: NaN, which the integrator
        # reports as a non-finite derivative at that time.
        if expr.args[-1].cond is not sympy.true:
            expr = sympy.Piecewise(*expr.args, (sympy.nan, True), evaluate=False)
        return super()._print_Piecewise(expr)

    def _print_NaN(self, expr):
        return "math.nan"

    def _print_BooleanTrue(self, expr):
        return "True"

    def _print_BooleanFalse(self, expr):
        return "False"


def _print(printer: _MathPrinter, expr: sympy.Basic) -> str:
    """Print ``expr``; a function without a Python/Numba equivalent raises ``ValueError``."""
    try:
        return printer.doprint(expr)
    except PrintMethodNotImplementedError as exc:
        raise ValueError(f"cannot generate code for {expr}: {exc.args[0].splitlines()[0]}; "
                         "the generated functions support +, -, *, /, **, sin, cos, tan, exp, "
                         "log, sqrt, sinh, cosh, tanh, atan2, Abs, Min, Max and Piecewise") from exc


def _safe_names(symbols: Sequence[sympy.Basic], taken: set[str]) -> list[str]:
    """Python identifiers for ``symbols`` (one each, unique, not in ``taken``)."""
    names = []
    for sym in symbols:
        base = getattr(sym, "name", None) or getattr(getattr(sym, "func", None), "__name__", "s")
        base = re.sub(r"\W", "_", str(base))
        if not base or base[0].isdigit() or base.startswith("_") or keyword.iskeyword(base) \
                or base in _RESERVED or re.fullmatch(r"\w+_part\d+", base):
            base = "s_" + base.lstrip("_")
        name = base
        k = 1
        while name in taken:
            name = f"{base}_{k}"
            k += 1
        taken.add(name)
        names.append(name)
    return names


def _symbol_table(eom, time_name: str):
    """Map the model's symbols to safe local names; return ``(subs, q, u, c, time)`` names."""
    taken: set[str] = set()
    q_names = _safe_names(list(eom.q), taken)
    u_names = _safe_names(list(eom.u), taken)
    c_names = _safe_names(list(eom.constants), taken)
    t_name = getattr(eom.t, "name", "t")
    if t_name == time_name:
        taken.add(time_name)
    else:
        t_name = _safe_names([eom.t], taken)[0]
    subs = {}
    for sym, name in zip([*eom.q, *eom.u, *eom.constants, eom.t],
                         [*q_names, *u_names, *c_names, t_name]):
        subs[sym] = sympy.Symbol(name, real=True)
    return subs, q_names, u_names, c_names, t_name


def _check_free_symbols(exprs, subs: Mapping, what: str) -> None:
    allowed = set(subs.values())
    unknown = set()
    for expr in exprs:
        unknown |= {s for s in expr.free_symbols if s not in allowed}
    if unknown:
        names = ", ".join(sorted(str(s) for s in unknown))
        raise ValueError(f"{what} contain symbols that are neither q, u, t nor constants: {names}; "
                         "add them to the constants")


def _header(eom, q_names, u_names, c_names, title: str) -> list[str]:
    nq, nu = len(q_names), len(u_names)
    lines = [f"# ---- {title} ----",
             f"# State vector y = [q, u] (nq = {nq} coordinates, nu = {nu} speeds):"]
    for k, sym in enumerate([*eom.q, *eom.u]):
        lines.append(f"#   y[{k}] = {sym}")
    lines.append(f"# Constants vector p ({len(c_names)} entries):")
    for k, sym in enumerate(eom.constants):
        lines.append(f"#   p[{k}] = {sym}")
    lines.append(f"# Time: t = {eom.t}")
    return lines


def _unrolled_ldl(nu: int, nq: int, indent: str) -> list[str]:
    """Scalar statements solving ``M x = f`` for locals ``_m{i}_{j}`` (i <= j), ``_f{i}``."""
    out = []
    for j in range(nu):
        for k in range(j):
            out.append(f"{indent}_w{k} = _l{j}_{k} * _d{k}")
        terms = "".join(f" - _l{j}_{k} * _w{k}" for k in range(j))
        out.append(f"{indent}_d{j} = _m{j}_{j}{terms}")
        out.append(f"{indent}if not _d{j} > PIVOT_RTOL * _m{j}_{j}:")
        out.append(f"{indent}    return mass_matrix_failure(dy, _d{j})")
        for i in range(j + 1, nu):
            terms = "".join(f" - _l{i}_{k} * _w{k}" for k in range(j))
            out.append(f"{indent}_l{i}_{j} = (_m{j}_{i}{terms}) / _d{j}")
    for i in range(nu):  # forward substitution L z = f
        terms = "".join(f" - _l{i}_{k} * _z{k}" for k in range(i))
        out.append(f"{indent}_z{i} = _f{i}{terms}")
    for i in reversed(range(nu)):  # D L^T x = z
        terms = "".join(f" - _l{k}_{i} * _x{k}" for k in range(i + 1, nu))
        out.append(f"{indent}_x{i} = _z{i} / _d{i}{terms}")
        out.append(f"{indent}dy[{nq + i}] = _x{i}")
    return out


def generate_rhs_source(eom, name: str = "rhs") -> str:
    """Return the Python source of the Numba function ``name(t, y, p, dy) -> int``.

    Parameters
    ----------
    eom : object
        Equations of motion with SymPy attributes ``t`` (time symbol), ``q`` (nq symbols),
        ``u`` (nu symbols), ``constants`` (the parameter vector p, in order), ``qdot``
        (Matrix (nq, 1)), ``mass_matrix`` (Matrix (nu, nu), symmetric positive definite) and
        ``forcing`` (Matrix (nu, 1)). ``q`` and ``u`` may also be ``f(t)`` applications.
    name : str
        Name of the generated function; the module-level tuples it also defines are
        ``STATE_NAMES``, ``CONSTANT_NAMES`` and the integers ``NQ``, ``NU`` (prefixed by
        ``NAME_`` when ``name != "rhs"``).

    Returns
    -------
    str
        Source text: a comment header giving the order of ``y`` and ``p``, the module-level
        constants and the ``@njit(cache=True)`` function. It writes ``dy`` (nq + nu,) in place
        and returns 0 (ok), 2 (non-finite mass matrix) or 4 (singular mass matrix).

    Raises
    ------
    ValueError
        If the shapes disagree, an expression contains an undeclared symbol or a function
        that cannot be printed.
    """
    nq, nu = len(eom.q), len(eom.u)
    qdot = sympy.Matrix(eom.qdot)
    mass = sympy.Matrix(eom.mass_matrix)
    forcing = sympy.Matrix(eom.forcing)
    if qdot.shape != (nq, 1) or mass.shape != (nu, nu) or forcing.shape != (nu, 1):
        raise ValueError(f"shapes: qdot {qdot.shape} (expected ({nq}, 1)), mass_matrix "
                         f"{mass.shape} (expected ({nu}, {nu})), forcing {forcing.shape} "
                         f"(expected ({nu}, 1))")
    subs, q_names, u_names, c_names, t_name = _symbol_table(eom, "t")
    upper = [(i, j) for i in range(nu) for j in range(i, nu)]
    exprs = ([qdot[i].xreplace(subs) for i in range(nq)]
             + [mass[i, j].xreplace(subs) for i, j in upper]
             + [forcing[i].xreplace(subs) for i in range(nu)])
    _check_free_symbols(exprs, subs, "the equations of motion")
    replacements, reduced = sympy.cse(exprs, symbols=sympy.numbered_symbols("_c"), order="none")
    printer = _MathPrinter()
    prefix = "" if name == "rhs" else name.upper() + "_"
    texts = [_print(printer, expr) for expr in reduced]
    statements = [_Statement(str(sym), _print(printer, expr), expr) for sym, expr in replacements]
    split = sum(len(st.text) for st in statements) + sum(map(len, texts)) > SPLIT_CHARS
    unrolled = nu <= UNROLL_LDL_MAX and not split
    targets = ([f"dy[{i}]" for i in range(nq)]
               + [f"_m{i}_{j}" if unrolled else f"_M[{i}, {j}]" for i, j in upper]
               + [f"_f{i}" if unrolled else f"dy[{nq + i}]" for i in range(nu)])
    statements += [_Statement(target, text, expr)
                   for target, text, expr in zip(targets, texts, reduced)]
    if split:
        statements = _split_long_sums(statements, printer)
    lines = _header(eom, q_names, u_names, c_names, f"generated right-hand side {name}")
    lines += ["# Kinematic equations q' = qdot(q, u, t); dynamic equations M(q, t) u' = f(q, u, t)",
              "# solved by M = L D L^T (upper triangle of M only).",
              f"{prefix}NQ = {nq}",
              f"{prefix}NU = {nu}",
              f"{prefix}STATE_NAMES = {tuple(str(s) for s in [*eom.q, *eom.u])!r}",
              f"{prefix}CONSTANT_NAMES = {tuple(str(s) for s in eom.constants)!r}",
              "",
              ""]
    loads = {n: f"y[{k}]" for k, n in enumerate([*q_names, *u_names])}
    loads.update({n: f"p[{k}]" for k, n in enumerate(c_names)})
    if t_name != "t":
        loads[t_name] = "t"
    if split:
        lines += _split_rhs(name, statements, loads, nq, nu)
        return "\n".join(lines) + "\n"
    lines += ['@njit(cache=True, error_model="numpy")',
              f"def {name}(t, y, p, dy):",
              f'    """Write [q\', u\'] (nq + nu = {nq + nu},) into dy; return 0, 2 or 4."""']
    ind = "    "
    lines += [f"{ind}{local} = {source}" for local, source in loads.items()]
    if not unrolled:
        lines.append(f"{ind}_M = np.empty(({nu}, {nu}))")
    lines += [f"{ind}{st.target} = {st.text}" for st in statements]
    if unrolled:
        lines += _unrolled_ldl(nu, nq, ind)
        lines.append(f"{ind}return 0")
    else:
        lines.append(f"{ind}return ldl_solve(_M, dy[{nq}:])")
    return "\n".join(lines) + "\n"


class _Statement:
    """One generated assignment ``target = text``; ``uses`` are the names it reads."""

    __slots__ = ("target", "text", "expr", "uses")

    def __init__(self, target: str, text: str, expr: sympy.Basic):
        self.target = target
        self.text = text
        self.expr = expr
        self.uses = {s.name for s in expr.free_symbols}


def _split_long_sums(statements: list[_Statement], printer) -> list[_Statement]:
    """Replace sums of more than ``SUM_TERMS_MAX`` terms by sums of partial sums ``_s{k}``.

    A statement of many thousand terms (``M_33 = sum_ij G_ij q_i q_j`` with 40 modes) would
    otherwise make one part, hence one basic block, too long for LLVM.
    """
    out: list[_Statement] = []
    counter = [0]

    def shrink(expr):
        if not expr.args or expr.is_Atom:
            return expr
        args = [shrink(a) for a in expr.args]
        if isinstance(expr, sympy.Add) and len(args) > SUM_TERMS_MAX:
            partial = []
            for start in range(0, len(args), SUM_TERMS_MAX):
                chunk = sympy.Add(*args[start:start + SUM_TERMS_MAX], evaluate=False)
                symbol = sympy.Symbol(f"_s{counter[0]}")
                counter[0] += 1
                out.append(_Statement(symbol.name, _print(printer, chunk), chunk))
                partial.append(symbol)
            return sympy.Add(*partial, evaluate=False)
        if any(a is not b for a, b in zip(args, expr.args)):
            return expr.func(*args, evaluate=False)
        return expr

    for st in statements:
        if len(st.text) <= SUM_TERMS_MAX * 8:
            out.append(st)
            continue
        expr = shrink(st.expr)
        out.append(st if expr is st.expr else _Statement(st.target, _print(printer, expr), expr))
    return out


def _split_rhs(name: str, statements: list[_Statement], loads: dict[str, str], nq: int,
               nu: int) -> list[str]:
    """Lines of ``name`` calling parts of about ``SPLIT_CHARS`` characters each.

    Part ``k`` is ``name_part{k}(t, y, p, w, _M, dy)``: it loads the states and constants it
    uses, reads the common subexpressions of earlier parts from the work array ``w``, stores
    there those that later parts read, and writes its entries of ``dy`` and of ``_M``.
    """
    parts: list[list[_Statement]] = [[]]
    size = 0
    for st in statements:
        if size > SPLIT_CHARS and parts[-1]:
            parts.append([])
            size = 0
        parts[-1].append(st)
        size += len(st.text)
    defined_in = {st.target: k for k, part in enumerate(parts) for st in part
                  if not st.target.startswith(("dy[", "_M["))}
    slots: dict[str, int] = {}
    for k, part in enumerate(parts):
        for st in part:
            for used in sorted(st.uses):
                if defined_in.get(used, k) < k and used not in slots:
                    slots[used] = len(slots)
    lines = []
    for k, part in enumerate(parts):
        own = {st.target for st in part}
        uses = set().union(*(st.uses for st in part))
        lines += ['@njit(cache=True, error_model="numpy")',
                  f"def {name}_part{k}(t, y, p, w, _M, dy):",
                  f'    """Part {k} of {name}: {len(part)} statements."""']
        lines += [f"    {local} = {source}" for local, source in loads.items() if local in uses]
        lines += [f"    {used} = w[{slots[used]}]" for used in sorted(uses - own)
                  if used in slots]
        for st in part:
            lines.append(f"    {st.target} = {st.text}")
            if st.target in slots:
                lines.append(f"    w[{slots[st.target]}] = {st.target}")
        lines += ["", ""]
    lines += ['@njit(cache=True, error_model="numpy")',
              f"def {name}(t, y, p, dy):",
              f'    """Write [q\', u\'] (nq + nu = {nq + nu},) into dy; return 0, 2 or 4."""',
              f"    w = np.empty({max(len(slots), 1)})",
              f"    _M = np.empty(({nu}, {nu}))"]
    lines += [f"    {name}_part{k}(t, y, p, w, _M, dy)" for k in range(len(parts))]
    lines.append(f"    return ldl_solve(_M, dy[{nq}:])")
    return lines


def generate_outputs_source(exprs: Mapping[str, sympy.Expr], args, name: str = "outputs",
                            rhs_name: str = "rhs") -> str:
    """Return the Python source of a Numba function evaluating outputs over many samples.

    Parameters
    ----------
    exprs : mapping of str to sympy.Expr
        Output name (e.g. ``"energy"``) to expression of ``q``, ``u``, ``t``, the constants and,
        if ``args`` has them, the speed derivatives ``ud``.
    args : object
        Provides the argument symbols as attributes ``t``, ``q``, ``u``, ``constants`` and
        optionally ``ud`` (nu symbols of ``u'``); the equations of motion object serves.
    name : str
        Name of the generated function; the names of its columns are the module-level tuple
        ``OUTPUT_NAMES`` (``NAME_OUTPUT_NAMES`` when ``name != "outputs"``).
    rhs_name : str
        Name of the generated right-hand side in the same module, called for each sample when an
        expression contains ``ud``.

    Returns
    -------
    str
        Source of ``name(t, Y, p) -> ndarray (N, len(exprs))`` with ``t`` (N,) times [s],
        ``Y`` (N, nq + nu) states and ``p`` the constants. Rows where the mass matrix is
        singular hold NaN in the columns that use ``ud``.
    """
    subs, q_names, u_names, c_names, t_name = _symbol_table(args, "t")
    keys = list(exprs)
    values = [sympy.sympify(exprs[k]) for k in keys]
    ud_symbols = list(getattr(args, "ud", None) or [])
    used = set().union(*(v.free_symbols for v in values)) if values else set()
    needs_ud = any(s in used for s in ud_symbols)
    ud_names = _safe_names(ud_symbols, {s.name for s in subs.values()}) if needs_ud else []
    subs.update({s: sympy.Symbol(n, real=True) for s, n in zip(ud_symbols, ud_names)})
    values = [v.xreplace(subs) for v in values]
    _check_free_symbols(values, subs, "the output expressions")
    replacements, reduced = sympy.cse(values, symbols=sympy.numbered_symbols("_c"), order="none")
    printer = _MathPrinter()
    prefix = "" if name == "outputs" else name.upper() + "_"
    nq = len(q_names)
    lines = _header(args, q_names, u_names, c_names, f"generated outputs {name}")
    lines += ["# Columns of the result:"]
    lines += [f"#   [:, {k}] = {key}" for k, key in enumerate(keys)]
    lines += [f"{prefix}OUTPUT_NAMES = {tuple(keys)!r}", "", "",
              '@njit(cache=True, error_model="numpy")',
              f"def {name}(_t, _Y, _p):",
              f'    """Outputs (N, {len(keys)}) at times _t (N,) and states _Y (N, nq + nu)."""',
              f"    _out = np.empty((_t.shape[0], {len(keys)}))"]
    if needs_ud:
        lines.append(f"    _dy = np.empty({nq + len(u_names)})")
    for k, cn in enumerate(c_names):
        lines.append(f"    {cn} = _p[{k}]")
    lines.append("    for _k in range(_t.shape[0]):")
    ind = "        "
    lines.append(f"{ind}{t_name} = _t[_k]")
    for k, qn in enumerate([*q_names, *u_names]):
        lines.append(f"{ind}{qn} = _Y[_k, {k}]")
    if needs_ud:
        lines.append(f"{ind}{rhs_name}(_t[_k], _Y[_k], _p, _dy)")
        for k, un in enumerate(ud_names):
            lines.append(f"{ind}{un} = _dy[{nq + k}]")
    for sym, expr in replacements:
        lines.append(f"{ind}{sym} = {_print(printer, expr)}")
    for k, expr in enumerate(reduced):
        lines.append(f"{ind}_out[_k, {k}] = {_print(printer, expr)}")
    lines.append("    return _out")
    return "\n".join(lines) + "\n"
