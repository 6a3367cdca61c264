"""Standalone C99 source of a model's equations: right-hand side, mass matrix, forcing, outputs.

The same equations the Numba module evaluates (:mod:`flexkane.numerics.codegen`), in the same way:
the compact equations (``EquationsOfMotion.compact``: named intermediates, then ``q' = qdot``,
``M u' = f`` and the outputs in their terms; drivers and the dependent speeds of closed loops are
substituted there), the intermediates each needs in evaluation order, common subexpressions
eliminated jointly (``sympy.cse``), names made safe by :mod:`~flexkane.numerics.codegen`'s helpers,
printed by SymPy's C99 printer. ``M u' = f`` is solved by ``M = L D L^T`` of the upper triangle
with the pivot test of :mod:`~flexkane.numerics.linear_algebra` (status 0 ok, 2 non-finite, 4
singular, the integrators' codes). Large models are written as straight-line code (a C compiler
handles the size; the term tables and parts of :mod:`~flexkane.numerics.large_rhs` exist for
Numba's compile time), so generation costs what ``cse`` and printing cost.

:func:`c_sources` returns the text of a header and a source file that need nothing beyond
``math.h``; :mod:`flexkane.c_export` adds the model's numbers and writes them.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import sympy
from sympy.printing.c import C99CodePrinter
from sympy.printing.precedence import precedence

from flexkane.numerics.codegen import (
    _assignments,
    _check_free_symbols,
    _INTEGER_EXPONENT_MAX,
    _needed_definitions,
    _safe_names,
    _state_names,
    _symbol_table,
)
from flexkane.numerics.large_rhs import Statement
from flexkane.numerics.linear_algebra import PIVOT_RTOL

__all__ = ["C_FUNCTIONS", "C_RESERVED", "PREFIX_RULE", "CConstant", "CModelInfo", "c_identifier", "c_sources", "check_prefix"]

#: Functions of the generated file, by suffix of ``<prefix>_``.
C_FUNCTIONS = ("rhs", "mass_matrix", "forcing", "kinematics", "controller_rates", "outputs", "solve")
#: Global data of the generated file, by suffix of ``<prefix>_``.
_C_DATA = ("default_p", "default_y0", "state_names", "state_units", "constant_names", "constant_units",
           "output_names", "output_units", "frozen_values", "frozen_names", "frozen_units", "constants")

# Names no local variable of the generated functions may take: C99's keywords, the functions and
# macros of math.h (C99 and POSIX: a local ``sin`` would hide the function), and the names of
# the generated functions' arguments. Internal locals start with ``_``, which user names never do.
C_RESERVED = frozenset("""
auto break case char const continue default do double else enum extern float for goto if inline int
long register restrict return short signed sizeof static struct switch typedef union unsigned void
volatile while _Bool _Complex _Imaginary bool true false complex imaginary NULL main errno entry
t y p dy M f qdot zdot out b
acos acosh asin asinh atan atan2 atanh cbrt ceil copysign cos cosh erf erfc exp exp2 expm1 fabs fdim
floor fma fmax fmin fmod frexp hypot ilogb ldexp lgamma llrint llround log log10 log1p log2 logb lrint
lround modf nan nearbyint nextafter nexttoward pow remainder remquo rint round scalbln scalbn sin sinh
sqrt tan tanh tgamma trunc j0 j1 jn y0 y1 yn gamma signgam drem finite significand
NAN INFINITY HUGE_VAL HUGE_VALF HUGE_VALL isfinite isnan isinf isnormal signbit fpclassify isgreater
isgreaterequal isless islessequal islessgreater isunordered FP_NAN FP_INFINITE FP_ZERO FP_SUBNORMAL
FP_NORMAL FP_FAST_FMA FP_ILOGB0 FP_ILOGBNAN MATH_ERRNO MATH_ERREXCEPT math_errhandling float_t double_t
""".split())

_IDENTIFIER = re.compile(r"[A-Za-z][A-Za-z0-9_]*")
#: What a prefix of the generated names must be.
PREFIX_RULE = ("a C identifier of ASCII letters, digits and underscores starting with a letter, at most 60 "
               "characters, not a C keyword or a name of math.h")


def check_prefix(prefix) -> str:
    """Return ``prefix`` if it can prefix the generated names (:data:`PREFIX_RULE`), else raise ValueError."""
    if not isinstance(prefix, str) or not _IDENTIFIER.fullmatch(prefix) or len(prefix) > 60 \
            or prefix in C_RESERVED:
        raise ValueError(PREFIX_RULE)
    return prefix


def c_identifier(text: str, fallback: str = "model") -> str:
    """A C identifier made of a label: characters other than ASCII letters and digits become ``_``.

    Leading digits and underscores are dropped (no reserved ``_X`` names); at most 60 characters;
    an empty result gives ``fallback``.

    Examples
    --------
    >>> c_identifier("falling-beam")
    'falling_beam'
    >>> c_identifier("../2 arms")
    'arms'
    """
    text = re.sub(r"[^A-Za-z0-9]+", "_", str(text)).lstrip("_0123456789")[:60].rstrip("_")
    return text or fallback


class _CPrinter(C99CodePrinter):
    """C99 printer: every number a double printed exactly, no macros beyond math.h's."""

    def __init__(self):
        super().__init__({"math_macros": {}})

    def _print_Float(self, expr):
        value = float(expr)
        if value != value:
            return "NAN"
        if value in (float("inf"), float("-inf")):
            return "INFINITY" if value > 0 else "(-INFINITY)"
        return repr(value)

    # as in the Numba module: an integer such as 3**50 does not fit an int, a double keeps the
    # arithmetic in double precision
    def _print_Integer(self, expr):
        return self._print_Float(expr)

    _print_Zero = _print_One = _print_NegativeOne = _print_Rational = _print_Integer

    def _print_Half(self, expr):
        return "0.5"

    def _print_Pi(self, expr):
        return repr(float(sympy.pi))

    def _print_Exp1(self, expr):
        return repr(float(sympy.E))

    def _print_NaN(self, expr):
        return "NAN"

    def _print_BooleanTrue(self, expr):
        return "1"

    def _print_BooleanFalse(self, expr):
        return "0"

    def _print_Pow(self, expr, rational=False):
        exp = expr.exp
        base = self.parenthesize(expr.base, precedence(expr), strict=False)
        if exp.is_Integer and 1 < abs(int(exp)) <= _INTEGER_EXPONENT_MAX:
            n = abs(int(exp))
            power = f"({base}*{base})" if n == 2 else f"pow({self._print(expr.base)}, {n}.0)"
            return power if exp > 0 else f"(1.0/{power})"
        if exp == sympy.S.Half:
            return f"sqrt({self._print(expr.base)})"
        if exp == -sympy.S.Half:
            return f"(1.0/sqrt({self._print(expr.base)}))"
        if exp == -1:
            return f"(1.0/{base})"
        return f"pow({self._print(expr.base)}, {self._print(exp)})"

    def _print_Piecewise(self, expr):
        # without an "otherwise" branch the value is undefined there: NaN (as the Numba module)
        if expr.args[-1].cond is not sympy.true:
            expr = sympy.Piecewise(*expr.args, (sympy.nan, True), evaluate=False)
        return super()._print_Piecewise(expr).replace("\n", " ")


@dataclass
class CConstant:
    """One constant of the generated files: a symbol of the equations (or a value they come from).

    Attributes
    ----------
    symbol : sympy.Symbol
    unit : str
        Its unit (``""`` when not known).
    note : str
        What it is (a beam's modal constant, a parameter, a field's key path).
    value : float
        The model's value [unit].
    expression : sympy.Expr or None
        For a derived constant, its expression in the editable, frozen and earlier derived symbols.
    """

    symbol: sympy.Symbol
    unit: str
    note: str
    value: float
    expression: sympy.Expr | None = None


@dataclass
class CModelInfo:
    """What the generated files document and hold besides the equations.

    Attributes
    ----------
    model_name : str
        The model's name (a label, shown in comments).
    editable : list of CConstant
        The entries of ``p`` in their order (``<prefix>_default_p``): what a user may change.
    frozen : list of CConstant
        The constants frozen at export (``<prefix>_frozen_values``): modal constants and the values
        they were computed from.
    derived : list of CConstant
        The constants computed from the others on every call, in evaluation order (each with its
        ``expression``).
    y0 : list of float
        The model's initial state (``<prefix>_default_y0``).
    state_units : list of str
        Unit of each state entry.
    output_units : list of str
        Unit of each output (``""`` when not known).
    version : str
        flexkane version (comments).
    dimensions : int
        2 for a planar chain, 3 for a spatial one (the header says which).
    """

    model_name: str
    editable: list
    frozen: list
    derived: list
    y0: list
    state_units: list
    output_units: list
    version: str
    dimensions: int


#: What the header calls a chain of each number of dimensions.
_CHAIN_KIND = {2: "planar", 3: "spatial"}


def _comment(text: str) -> str:
    """Text safe inside a C comment: one line, printable ASCII, no comment end."""
    text = "".join(ch if " " <= ch <= "~" else "?" for ch in str(text))
    return text.replace("*/", "* /").replace("/*", "/ *")


def _string(text: str) -> str:
    """A C string literal of ``text`` (printable ASCII; escapes for quotes, backslashes, trigraphs)."""
    out = []
    for ch in str(text):
        if ch in '"\\?':
            out.append("\\" + ch)
        elif " " <= ch <= "~":
            out.append(ch)
        else:
            out.append(f"\\x{ord(ch):02x}" if ord(ch) < 256 else "?")
    return '"' + "".join(out) + '"'


def _number(value: float) -> str:
    return _CPrinter()._print_Float(sympy.Float(float(value))) if value == value else "NAN"


def _dim(n: int) -> int:
    """Length of a C array of ``n`` entries (C has no empty arrays)."""
    return max(n, 1)


class _Generator:
    """Names and statements of one model's C functions."""

    def __init__(self, eom, prefix: str):
        self.eom = eom
        self.prefix = prefix
        self.nq, self.nu = len(eom.q), len(eom.u)
        self.compact = getattr(eom, "compact", None) or eom
        self.zdot = list(getattr(self.compact, "zdot", None) or [])   # controller states: y = [q, u, z]
        self.reserved = C_RESERVED | {f"{prefix}_{s}" for s in (*C_FUNCTIONS, *_C_DATA)}
        self.printer = _CPrinter()

    def statements(self, values: Sequence, targets: Sequence[str]) -> tuple[list, dict, list]:
        """Statements computing ``values`` into ``targets``; ``(statements, loads, ud names)``.

        ``loads`` maps each local name the statements read to the C expression it is loaded from
        (``y[k]``, ``p[k]``, ``t``); ``ud names`` are the locals of u' (read from the right-hand side)
        or ``[]`` when no value needs u'.
        """
        eom = self.eom
        values = [sympy.sympify(v) for v in values]
        definitions = _needed_definitions(eom, values)
        subs, q_names, u_names, c_names, t_name = _symbol_table(eom, "t", [s for s, _ in definitions],
                                                                self.reserved)
        ud_symbols = list(getattr(eom, "ud", None) or [])
        used = set().union(*(v.free_symbols for v in values), *(e.free_symbols for _, e in definitions))
        ud_names = []
        if any(s in used for s in ud_symbols):
            ud_names = _safe_names(ud_symbols, {s.name for s in subs.values()} | set(self.reserved))
            subs.update({s: sympy.Symbol(n, real=True) for s, n in zip(ud_symbols, ud_names)})
        values = [v.xreplace(subs) for v in values]
        _check_free_symbols(values + [e.xreplace(subs) for _, e in definitions], subs, "the equations")
        statements = _assignments(values, definitions, subs, self.printer, list(targets))
        y_names = _state_names(eom, subs, q_names, u_names)
        names = [*y_names, *c_names, *ud_names, t_name]
        bad = [n for n in names if not _IDENTIFIER.fullmatch(n)]
        if bad:   # validated models have ASCII names; a hand-made equation set may not
            raise ValueError(f"names that are not C identifiers: {', '.join(bad)}")
        loads = {n: f"y[{k}]" for k, n in enumerate(y_names)}
        loads.update({n: f"_pc[{k}]" for k, n in enumerate(c_names)})
        loads.update({n: f"_dy[{self.nq + k}]" for k, n in enumerate(ud_names)})
        if t_name != "t":
            loads[t_name] = "t"
        return statements, loads, ud_names

    def body(self, values: Sequence, targets: Sequence[str]) -> tuple[list[str], list[str]]:
        """Lines of a function body that computes ``values`` into ``targets``; ``(lines, ud names)``."""
        statements, loads, ud_names = self.statements(values, targets)
        return self.lines(statements, loads, ud_names, targets), ud_names

    @staticmethod
    def select(statements: list, targets: Mapping[str, str]) -> list:
        """The statements that ``targets`` (keys) need, in their order, the targets renamed (values).

        One elimination of common subexpressions over the whole right-hand side serves the functions
        that compute parts of it (the mass matrix, the forcing, the kinematic equations).
        """
        producers = {st.target: st for st in statements}
        needed: set = set()
        stack = list(targets)
        while stack:
            target = stack.pop()
            if target not in needed:
                needed.add(target)
                stack += [u for u in producers[target].uses if u in producers and u not in needed]
        return [Statement(targets.get(st.target, st.target), st.text, st.expr)
                for st in statements if st.target in needed]

    def lines(self, statements: list, loads: dict, ud_names: list, targets: Sequence[str]) -> list[str]:
        """Lines of a function body: the locals it reads, then ``statements`` (``targets`` are outputs)."""
        used = set().union(*(st.uses for st in statements)) if statements else set()
        lines = []
        if any(n in used and source.startswith("_pc") for n, source in loads.items()):
            lines += [f"    double _pc[{_dim(len(self.eom.constants))}];",   # every constant, from p
                      f"    {self.prefix}_constants(p, _pc);"]
        lines += [f"    const double {n} = {source};" for n, source in loads.items()
                  if n in used and not source.startswith("_dy")]
        if ud_names:
            lines += [f"    double _dy[{self.prefix.upper()}_NY];",
                      f"    const int _status = {self.prefix}_rhs(t, y, p, _dy);"]
            lines += [f"    const double {n} = {source};" for n, source in loads.items()
                      if n in used and source.startswith("_dy")]
        given = set(targets)
        for st in statements:   # common subexpressions and intermediates are locals
            declare = "" if st.target in given else "const double "
            lines.append(f"    {declare}{st.target} = {st.text};")
        return lines


def _solve_lines(prefix: str, nu: int) -> list[str]:
    """The LDL^T solve of M x = b (M row-major nu x nu, upper triangle read), as linear_algebra."""
    P = prefix.upper()
    return [
        f"int {prefix}_solve(double *M, double *b)",
        "{",
        f"    double _w[{_dim(nu)}];",
        "    int _i, _j, _k;",
        f"    for (_j = 0; _j < {P}_NU; ++_j) {{",
        "        double _d = M[_j * " + P + "_NU + _j];",
        "        const double _mjj = _d;",
        "        for (_k = 0; _k < _j; ++_k) {",
        f"            _w[_k] = M[_j * {P}_NU + _k] * M[_k * {P}_NU + _k];",
        f"            _d -= M[_j * {P}_NU + _k] * _w[_k];",
        "        }",
        f"        if (!(_d > {_number(PIVOT_RTOL)} * _mjj)) {{",
        f"            for (_i = 0; _i < {P}_NU; ++_i) b[_i] = NAN;",
        "            return isfinite(_d) ? 4 : 2;",
        "        }",
        f"        M[_j * {P}_NU + _j] = _d;",
        f"        for (_i = _j + 1; _i < {P}_NU; ++_i) {{",
        f"            double _s = M[_j * {P}_NU + _i];",
        f"            for (_k = 0; _k < _j; ++_k) _s -= M[_i * {P}_NU + _k] * _w[_k];",
        f"            M[_i * {P}_NU + _j] = _s / _d;",
        "        }",
        "    }",
        f"    for (_i = 0; _i < {P}_NU; ++_i) {{",
        "        double _s = b[_i];",
        f"        for (_k = 0; _k < _i; ++_k) _s -= M[_i * {P}_NU + _k] * b[_k];",
        "        b[_i] = _s;",
        "    }",
        f"    for (_i = {P}_NU - 1; _i >= 0; --_i) {{",
        f"        double _s = b[_i] / M[_i * {P}_NU + _i];",
        f"        for (_k = _i + 1; _k < {P}_NU; ++_k) _s -= M[_k * {P}_NU + _i] * b[_k];",
        "        b[_i] = _s;",
        "    }",
        "    return 0;",
        "}",
    ]


def _constants_lines(prefix: str, constants: list, info: CModelInfo, printer) -> list[str]:
    """``<prefix>_constants(p, c)``: every constant of the equations (order of ``eom.constants``) from the
    parameters p, the frozen values and the derived constants' expressions."""
    source = {c.symbol: sympy.Symbol(f"p[{k}]") for k, c in enumerate(info.editable)}
    source.update({c.symbol: sympy.Symbol(f"{prefix}_frozen_values[{k}]") for k, c in enumerate(info.frozen)})
    locals_ = []
    for k, c in enumerate(info.derived):
        local = sympy.Symbol(f"_a{k}")
        locals_.append(f"    const double {local} = {printer.doprint(c.expression.xreplace(source))};"
                       f"  /* {_comment(c.symbol.name)} */")
        source[c.symbol] = local
    missing = [s.name for s in constants if s not in source]
    if missing:
        raise ValueError(f"constants neither parameters, frozen nor derived: {', '.join(missing)}")
    return [f"static void {prefix}_constants(const double *p, double *c)", "{", "    (void)p; (void)c;", *locals_,
            *(f"    c[{k}] = {source[s]};" for k, s in enumerate(constants)), "}"]


def _finite_check(array: str, count: str) -> list[str]:
    return ["    {", "        int _i;",
            f"        for (_i = 0; _i < {count}; ++_i) if (!isfinite({array}[_i])) return 2;", "    }"]


def c_sources(eom, prefix: str, info: CModelInfo) -> tuple[str, str]:
    """The header and the source file of a model's equations in C99.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations (their compact form is generated).
    prefix : str
        Prefix of every global name (``<prefix>_rhs`` ...), a C identifier (:func:`c_identifier`).
    info : CModelInfo
        Units, notes and the model's numbers; its editable, frozen and derived constants together
        give every constant of ``eom`` (``<prefix>_constants(p, c)``, a static function of the
        source, fills them in the order of ``eom.constants`` for the other functions).

    Returns
    -------
    header : str
        Text of ``<prefix>.h``: the sizes as macros, the order of the state, the parameters ``p``,
        the derived constants, the frozen values (name, unit, what it is, one per line) and the
        outputs in comments, the declarations.
    source : str
        Text of ``<prefix>.c``: the functions and the model's numbers; it includes ``math.h`` and
        the header only.

    Raises
    ------
    ValueError
        For a prefix that is not a C identifier, an expression with a function C cannot print,
        a symbol that is neither q, u, t nor a constant, or a constant that ``info`` does not give.
    """
    check_prefix(prefix)
    gen = _Generator(eom, prefix)
    P = prefix.upper()
    nq, nu = gen.nq, gen.nu
    zdot = gen.zdot
    nz = len(zdot)
    ny = nq + nu + nz
    constants = list(eom.constants)
    compact = gen.compact
    outputs = dict(compact.outputs)
    output_names = list(outputs)
    state_names = [str(s) for s in [*eom.q, *eom.u, *(getattr(eom, "z", None) or [])]]
    if len(state_names) != ny:
        raise ValueError(f"{nz} controller state rates (zdot) for {len(state_names) - nq - nu} controller states (z)")
    qdot = sympy.Matrix(compact.qdot)
    mass = sympy.Matrix(compact.mass_matrix)
    forcing = sympy.Matrix(compact.forcing)
    upper = [(i, j) for i in range(nu) for j in range(i, nu)]

    kin_targets = {f"dy[{i}]": f"qdot[{i}]" for i in range(nq)}
    mass_targets = {f"_M[{i * nu + j}]": f"M[{i * nu + j}]" for i, j in upper}
    force_targets = {f"dy[{nq + i}]": f"f[{i}]" for i in range(nu)}
    rate_targets = {f"dy[{nq + nu + k}]": f"zdot[{k}]" for k in range(nz)}
    rhs_targets = [*kin_targets, *mass_targets, *force_targets, *rate_targets]
    statements, loads, _ = gen.statements([qdot[i] for i in range(nq)] + [mass[i, j] for i, j in upper]
                                          + [forcing[i] for i in range(nu)] + zdot, rhs_targets)
    rhs_body = gen.lines(statements, loads, [], rhs_targets)
    kin_body, mass_body, force_body, rate_body = (
        gen.lines(gen.select(statements, targets), loads, [], list(targets.values()))
        for targets in (kin_targets, mass_targets, force_targets, rate_targets))
    mass_body += [f"    M[{j * nu + i}] = M[{i * nu + j}];" for i, j in upper if i != j]
    out_body, out_ud = gen.body([outputs[k] for k in output_names], [f"out[{k}]" for k in range(len(outputs))])

    model = _comment(info.model_name)
    head = [f"/* {prefix}: the equations of motion of the flexkane model \"{model}\", in C99.",
            f" * Generated by flexkane {_comment(info.version)}; do not edit (export the model again).",
            f" * Kane's equations of a {_CHAIN_KIND[info.dimensions]} chain: "
            "q' = qdot(t, q, u) and M(t, q) u' = f(t, q, u)"
            + (",\n * and the controller states' rates z' = zdot(t, q, u, z) (f may depend on z)." if nz else "."),
            " * Needs math.h only (link with -lm). No function keeps state: every one is reentrant."]
    header = head + [
        " *",
        f" * State y = [q, u, z], {P}_NY = {ny} entries ({P}_NQ = {nq} coordinates, {P}_NU = {nu} speeds,",
        f" * {P}_NZ = {nz} controller states, in the order of the controllers, each one's states as listed):"]
    header += [f" *   y[{k}] = {_comment(n)} [{_comment(u) or '?'}]"     # [?]: a unit not recorded
               for k, (n, u) in enumerate(zip(state_names, info.state_units))]
    editable, frozen, derived = info.editable, info.frozen, info.derived
    header += [" *",
               f" * Parameters p, {P}_NP = {len(editable)} entries, what a caller may change (name [unit]: what it",
               " * is; [unit unknown]: a parameter whose unit the model does not fix, the note says why; the",
               f" * model's values are {prefix}_default_p). A change of p[k] is the change of the model that",
               " * `--set NAME=VALUE` of a parameter, `--set KEY.PATH=VALUE` of a field (the note names it) makes:"]
    header += [f" *   p[{k}] = {_comment(c.symbol.name)} [{_comment(c.unit) or 'unit unknown'}]: {_comment(c.note)}"
               for k, c in enumerate(editable)]
    if derived:
        header += [" *",
                   " * Computed from p (and the frozen values) on every call, as flexkane computes them after",
                   " * a --set (not in p; name [unit] = expression):"]
        header += [f" *   {_comment(c.symbol.name)} [{_comment(c.unit) or 'unit unknown'}] = {_comment(c.note)}"
                   for c in derived]
    header += [" *",
               f" * Frozen at export, {P}_NFROZEN = {len(frozen)} values (name [unit] = value: what it is), read-only",
               f" * in {prefix}_frozen_values: the modal constants of the beams are integrals of their shape",
               " * functions that flexkane computes by quadrature from the beam's length, shape roots, stations",
               " * and load profiles. Those integrals are frozen (per unit section value, e.g. E_1/rho, when the",
               " * constant is proportional to the mass per length, a rigidity or a rotary inertia that are",
               " * parameters: those stay in p and multiply it above), with every parameter they were computed",
               " * from, directly or through other parameters' expressions; no entry of p influences them. To",
               " * change a frozen value, export again: flexkane export MODEL --set ..."
               + (" (none here)" if not frozen else "")]
    header += [f" *   frozen[{k}] = {_comment(c.symbol.name)} [{_comment(c.unit) or 'unit unknown'}] = "
               f"{_number(c.value)}: {_comment(c.note)}" for k, c in enumerate(frozen)]
    header += [" *", f" * Outputs, {P}_NOUT = {len(output_names)} entries (name [unit], [?]: not recorded):"]
    header += [f" *   out[{k}] = {_comment(n)} [{_comment(u) or '?'}]"
               for k, (n, u) in enumerate(zip(output_names, info.output_units))]
    header += [
        " *",
        " * Prescribed motions (drivers) are functions of t (or of the state) inside the equations; in a",
        " * closed loop the dependent speeds are functions of the state (they are outputs), all coordinates",
        " * are states.",
        " * Status codes returned: 0 success, 2 non-finite entry, 4 singular mass matrix (the pivot d_j of",
        f" * M = L D L^T is not above {_number(PIVOT_RTOL)} M_jj); on 2 or 4 the results hold NaN.",
        " * Arrays are of double; output arrays must not overlap the inputs.",
        " */",
        f"#ifndef FLEXKANE_{P}_H",
        f"#define FLEXKANE_{P}_H",
        "",
        "#ifdef __cplusplus",
        'extern "C" {',
        "#endif",
        "",
        f"#define {P}_NQ {nq}",
        f"#define {P}_NU {nu}",
        f"#define {P}_NZ {nz}",
        f"#define {P}_NY {ny}",
        f"#define {P}_NP {len(editable)}",
        f"#define {P}_NFROZEN {len(frozen)}",
        f"#define {P}_NOUT {len(output_names)}",
        "",
        "/* The model's parameters p (order above) and initial state y(0) = [q, u, z] (loops closed). */",
        f"extern const double {prefix}_default_p[{_dim(len(editable))}];",
        f"extern const double {prefix}_default_y0[{_dim(ny)}];",
        "/* The values frozen at export (order above; not parameters: export again to change them). */",
        f"extern const double {prefix}_frozen_values[{_dim(len(frozen))}];",
        "/* Names and units of the state entries, the parameters p, the frozen values and the outputs,",
        " * in their order. */",
        f"extern const char *const {prefix}_state_names[{_dim(ny)}];",
        f"extern const char *const {prefix}_state_units[{_dim(ny)}];",
        f"extern const char *const {prefix}_constant_names[{_dim(len(editable))}];",
        f"extern const char *const {prefix}_constant_units[{_dim(len(editable))}];",
        f"extern const char *const {prefix}_frozen_names[{_dim(len(frozen))}];",
        f"extern const char *const {prefix}_frozen_units[{_dim(len(frozen))}];",
        f"extern const char *const {prefix}_output_names[{_dim(len(output_names))}];",
        f"extern const char *const {prefix}_output_units[{_dim(len(output_names))}];",
        "",
        f"/* dy/dt = [q', u', z'] ({P}_NY) at time t [s], state y ({P}_NY), parameters p ({P}_NP);",
        " * u' by solving M u' = f. Returns 0, 2 or 4 (dy then all NaN). */",
        f"int {prefix}_rhs(double t, const double *y, const double *p, double *dy);",
        "",
        f"/* The mass matrix M ({P}_NU x {P}_NU, row-major, symmetric: both triangles written). Returns 0, or 2",
        " * if an entry is not finite. */",
        f"int {prefix}_mass_matrix(double t, const double *y, const double *p, double *M);",
        "",
        f"/* The forcing f ({P}_NU) of M u' = f. Returns 0, or 2 if an entry is not finite. */",
        f"int {prefix}_forcing(double t, const double *y, const double *p, double *f);",
        "",
        f"/* The kinematic equations q' = qdot ({P}_NQ). Returns 0, or 2 if an entry is not finite. */",
        f"int {prefix}_kinematics(double t, const double *y, const double *p, double *qdot);",
        "",
        f"/* The rates z' = zdot ({P}_NZ; nothing is written without controller states) of the controller",
        " * states. Returns 0, or 2 if an entry is not finite. */",
        f"int {prefix}_controller_rates(double t, const double *y, const double *p, double *zdot);",
        "",
        f"/* The outputs ({P}_NOUT, order above) at t, y." + (
            f" Outputs with u' call {prefix}_rhs; returns its status." if out_ud else " Returns 0.") + " */",
        f"int {prefix}_outputs(double t, const double *y, const double *p, double *out);",
        "",
        f"/* Solve M x = b in place by M = L D L^T: M ({P}_NU x {P}_NU, row-major; only its upper triangle",
        f" * is read, its lower triangle and diagonal are overwritten by L and D), b ({P}_NU) becomes x.",
        " * Returns 0, 2 (non-finite pivot) or 4 (singular: pivot not positive); then b is all NaN. */",
        f"int {prefix}_solve(double *M, double *b);",
        "",
        "#ifdef __cplusplus",
        "}",
        "#endif",
        "",
        f"#endif /* FLEXKANE_{P}_H */",
        ""]

    def data(kind: str, name: str, items: list, size: int) -> list[str]:
        rows = items or (["0.0"] if kind == "double" else ['""'])
        qualifier = "const double" if kind == "double" else "const char *const"
        return [f"{qualifier} {prefix}_{name}[{_dim(size)}] = {{"] + [f"    {r}," for r in rows] + ["};", ""]

    source = head + [" */", "#include <math.h>", "", f'#include "{prefix}.h"', ""]
    source += data("double", "default_p", [f"{_number(c.value)}  /* {_comment(c.symbol.name)} */"
                                           for c in editable], len(editable))
    source += data("double", "frozen_values", [f"{_number(c.value)}  /* {_comment(c.symbol.name)} */"
                                               for c in frozen], len(frozen))
    source += data("double", "default_y0", [f"{_number(v)}  /* {_comment(n)} */"
                                            for n, v in zip(state_names, info.y0)], ny)
    for name, items in (("state_names", state_names), ("state_units", info.state_units),
                        ("constant_names", [c.symbol.name for c in editable]),
                        ("constant_units", [c.unit for c in editable]),
                        ("frozen_names", [c.symbol.name for c in frozen]),
                        ("frozen_units", [c.unit for c in frozen]),
                        ("output_names", output_names), ("output_units", info.output_units)):
        source += data("str", name, [_string(x) for x in items], len(items))
    constants_function = _constants_lines(prefix, constants, info, gen.printer)
    bodies = (rhs_body, kin_body, mass_body, force_body, rate_body, out_body)
    if any(f"{prefix}_constants(p, _pc);" in line for body in bodies for line in body):   # else unused
        source += constants_function + [""]
    source += _solve_lines(prefix, nu) + [""]

    def function(name: str, array: str, body: list[str], tail: list[str]) -> list[str]:
        return [f"int {prefix}_{name}(double t, const double *y, const double *p, double *{array})",
                "{", "    (void)t; (void)y; (void)p;", *body, *tail, "}", ""]

    source += function("kinematics", "qdot", kin_body, _finite_check("qdot", f"{P}_NQ") + ["    return 0;"])
    source += function("controller_rates", "zdot", rate_body, _finite_check("zdot", f"{P}_NZ") + ["    return 0;"])
    source += function("mass_matrix", "M", mass_body,
                       _finite_check("M", f"{P}_NU * {P}_NU") + ["    return 0;"])
    source += function("forcing", "f", force_body, _finite_check("f", f"{P}_NU") + ["    return 0;"])
    source += function("rhs", "dy", [f"    double _M[{_dim(nu * nu)}];", "    int _status;", *rhs_body],
                       [f"    _status = {prefix}_solve(_M, dy + {P}_NQ);",
                        "    if (_status != 0) {",
                        "        int _i;",
                        f"        for (_i = 0; _i < {P}_NQ; ++_i) dy[_i] = NAN;",
                        f"        for (_i = {P}_NQ + {P}_NU; _i < {P}_NY; ++_i) dy[_i] = NAN;",
                        "    }",
                        "    return _status;"])
    source += function("outputs", "out", out_body, ["    return _status;" if out_ud else "    return 0;"])
    return "\n".join(header) + "\n", "\n".join(source).rstrip("\n") + "\n"
