"""Generated right-hand sides of large models: term tables and parts.

Numba's compile time grows with the number of operations of a function (type inference and
lowering, a few milliseconds per operation on a 2-core machine) and, for one long function, faster
than that (LLVM works on one basic block). A beam with n modes brings O(n^2) terms:
``sum_ij G_ij q_i q_j`` in the mass matrix, ``sum_ij G_ij q_i u_j`` in the forcing, ``sum_i H_ij
q_i`` for each mode. Written out for ``falling-beam-exact`` with 40 modes that is 30,000
operations, which took 145 s to compile. So, above ``SPLIT_CHARS`` printed characters:

1. every sum of at least ``TABLE_TERMS_MIN`` terms becomes rows of a *term table*: each term is a
   coefficient times a product of at most ``FACTOR_MAX`` factors (states, constants, common
   subexpressions), and one compiled loop, ``<name>_table_sum``, adds them up. Common
   subexpressions that are products (``G_12*q_5``) are folded into the terms instead of being
   computed on their own. The compiled code no longer grows with the number of terms;
2. the statements that remain are distributed over functions ``<name>_part<k>`` of about
   ``SPLIT_CHARS`` characters each.

All values pass through one work array ``w``: ``w[:ny]`` the state, ``w[ny:ny + np]`` the
constants, then 1.0, t and 0.0, then the common subexpressions that tables or later parts read.
Outputs that are a state, a constant, 0 or 1 (most of the mass matrix, all of ``q' = u``) are
copied from ``w`` by a loop over an index table.
"""

from __future__ import annotations

import sympy

__all__ = ["FACTOR_MAX", "SPLIT_CHARS", "TABLE_TERMS_MIN", "Statement", "large_rhs_lines"]

# Printed characters of a right-hand side above which it is generated in this form, and size of
# each part (chosen by measuring compile times, see benchmarks/RESULTS.md).
SPLIT_CHARS = 12_000
# Sums with at least this many terms are evaluated from a term table.
TABLE_TERMS_MIN = 12
# Largest number of factors of one term of a table.
FACTOR_MAX = 6


class Statement:
    """One generated assignment ``target = text``; ``uses`` are the names it reads."""

    __slots__ = ("target", "text", "expr", "uses")

    def __init__(self, target: str, text: str, expr: sympy.Basic):
        self.target = target
        self.text = text
        self.expr = expr
        self.uses = {s.name for s in expr.free_symbols}

    @property
    def is_output(self) -> bool:
        return self.target.startswith(("dy[", "_M["))


class _Tables:
    """Collects the terms of the tabulated sums (coefficients and factor names)."""

    def __init__(self, statements: list[Statement]):
        self.defs = {st.target: st.expr for st in statements if not st.is_output}
        self.rows: list[tuple[float, tuple[str, ...]]] = []
        self.ranges: list[tuple[int, int]] = []
        self._monomials: dict[str, tuple | None] = {}

    def monomial(self, expr) -> tuple[float, tuple[str, ...]] | None:
        """``(coefficient, factor names)`` of a product of symbols, or None."""
        if expr.is_Number:
            return float(expr), ()
        if expr.is_Symbol:
            name = expr.name
            if name in self.defs:
                if name not in self._monomials:
                    self._monomials[name] = None  # no cycles
                    inner = self.monomial(self.defs[name])
                    ok = inner is not None and len(inner[1]) <= FACTOR_MAX // 2
                    self._monomials[name] = inner if ok else None
                if self._monomials[name] is not None:
                    return self._monomials[name]
            return 1.0, (name,)
        if expr.is_Pow and expr.exp.is_Integer and 0 < int(expr.exp) <= FACTOR_MAX:
            base = self.monomial(expr.base)
            if base is not None:
                return base[0] ** int(expr.exp), base[1] * int(expr.exp)
            return None
        if expr.is_Mul:
            coef, names = 1.0, ()
            for arg in expr.args:
                part = self.monomial(arg)
                if part is None:
                    return None
                coef, names = coef * part[0], names + part[1]
            return coef, names
        return None

    def add(self, terms) -> int:
        """Append the terms ``(coefficient, names)`` of one sum; return its table index."""
        start = len(self.rows)
        self.rows.extend(terms)
        self.ranges.append((start, len(self.rows)))
        return len(self.ranges) - 1


def _tabulate(statements: list[Statement], printer_fn, name: str):
    """Turn long sums into table rows; return ``(statements, tables, atoms)``."""
    tables = _Tables(statements)
    out: list[Statement] = []
    counter = 0
    for st in statements:
        expr = st.expr
        if not (isinstance(expr, sympy.Add) and len(expr.args) >= TABLE_TERMS_MIN):
            out.append(st)
            continue
        terms = []
        for arg in expr.args:
            mono = tables.monomial(arg)
            if mono is None or len(mono[1]) > FACTOR_MAX:
                # a factor that is not a product of symbols: computed on its own
                coef, rest = arg.as_coeff_Mul()
                temp = sympy.Symbol(f"_t{counter}")
                counter += 1
                out.append(Statement(temp.name, printer_fn(rest), rest))
                tables.defs[temp.name] = rest
                mono = (float(coef), (temp.name,))
            terms.append(mono)
        index = tables.add(terms)
        start, stop = tables.ranges[index]
        text = f"{name}_table_sum(w, {start}, {stop})"
        table_st = Statement(st.target, text, sympy.Integer(0))
        table_st.uses = set()
        out.append(table_st)
    atoms = {n for _, names in tables.rows for n in names}
    # keep only what an output, a table or a kept statement reads
    needed = set(atoms)
    kept = []
    for st in reversed(out):
        if st.is_output or st.target in needed:
            needed |= st.uses
            kept.append(st)
    return kept[::-1], tables, atoms


def _copy_source(st: Statement, fixed: dict[str, int]) -> int | None:
    """Index in ``w`` of the value an output statement copies, or None."""
    if not st.is_output or st.text.endswith(")") and "_table_sum(w, " in st.text:
        return None
    expr = st.expr
    if expr.is_Symbol and expr.name in fixed:
        return fixed[expr.name]
    if expr == 0 or expr == 1:
        return fixed[str(int(expr))]
    return None


def large_rhs_lines(name: str, statements: list[Statement], printer_fn, state_names: list[str],
                    constant_names: list[str], t_name: str, nq: int, nu: int, *,
                    prologue: list[str] = (), solve: str | None = None) -> list[str]:
    """Source lines of ``name`` (and its parts and tables) for a large right-hand side.

    Parameters
    ----------
    name : str
        Name of the generated function.
    statements : list of Statement
        Common subexpressions, then ``dy[i]`` (q', and f into ``dy[nq:]``) and ``_M[i, j]``
        (upper triangle), in order of evaluation.
    printer_fn : callable
        Prints a SymPy expression as Python.
    state_names, constant_names : list of str
        Local names of ``y`` (ny,) and ``p`` entries, in order.
    t_name : str
        Local name of the time.
    nq, nu : int
        Numbers of coordinates and speeds.
    prologue : list of str
        Lines (indented) that open ``name``, before anything reads ``p``.
    solve : str, optional
        Expression solving ``_M u' = dy[nq:]`` in place and giving the status code; default
        ``ldl_solve(_M, dy[nq:])`` (the block solve of
        :mod:`~flexkane.numerics.constant_block` otherwise). Entries of ``_M`` that it does
        not read need no statement.
    """
    statements, tables, atoms = _tabulate(statements, printer_fn, name)
    ny, n_p = len(state_names), len(constant_names)
    fixed = {n: k for k, n in enumerate(state_names)}
    fixed.update({n: ny + k for k, n in enumerate(constant_names)})
    one = ny + n_p
    fixed["1"] = one
    fixed[t_name] = one + 1
    fixed["0"] = one + 2
    # outputs that are a state, a constant, 0 or 1 (most of M, all of q' = u) are copied by a loop
    copy_dy, copy_m, rest = [], [], []
    for st in statements:
        source = _copy_source(st, fixed)
        if source is None:
            rest.append(st)
        elif st.target.startswith("dy["):
            copy_dy.append([int(st.target[3:-1]), source])
        else:
            i, j = (int(k) for k in st.target[3:-1].split(","))
            copy_m.append([i, j, source])
    statements = rest
    parts: list[list[Statement]] = [[]]
    size = 0
    for st in statements:
        if size > SPLIT_CHARS and parts[-1]:
            parts.append([])
            size = 0
        parts[-1].append(st)
        size += len(st.text)
    defined_in = {st.target: k for k, part in enumerate(parts) for st in part if not st.is_output}
    slots: dict[str, int] = {}
    for atom in sorted(atoms, key=lambda a: (a not in defined_in, a)):
        if atom not in fixed:
            slots[atom] = one + 3 + len(slots)
    for k, part in enumerate(parts):
        for st in part:
            for used in sorted(st.uses):
                if defined_in.get(used, k) < k and used not in slots:
                    slots[used] = one + 3 + len(slots)
    loads = {n: f"y[{k}]" for k, n in enumerate(state_names)}
    loads.update({n: f"p[{k}]" for k, n in enumerate(constant_names)})
    lines = []
    for label, rows in (("DY", copy_dy), ("M", copy_m)):
        if rows:
            flat = [v for row in rows for v in row]
            lines += [f"{name.upper()}_COPY_{label} = np.array({flat!r}, dtype=np.int64).reshape("
                      f"{len(rows)}, {len(rows[0])})"]
    if tables.rows:
        width = max(len(names) for _, names in tables.rows)
        index = [fixed.get(n, slots.get(n)) for _, names in tables.rows
                 for n in (list(names) + ["1"] * (width - len(names)))]
        coef = [c for c, _ in tables.rows]
        prefix = name.upper()
        lines += [f"# Term tables of {name}: {len(coef)} terms of at most {width} factors each; the "
                  "factors are entries of the work array w.",
                  f"{prefix}_TABLE_COEF = np.array({coef!r}, dtype=np.float64)",
                  f"{prefix}_TABLE_INDEX = np.array({index!r}, dtype=np.int64).reshape("
                  f"{len(coef)}, {width})",
                  "", "",
                  '@njit(cache=True, error_model="numpy")',
                  f"def {name}_table_sum(w, start, stop):",
                  f'    """Sum of the terms start:stop of the {name} tables."""',
                  "    s = 0.0",
                  "    for k in range(start, stop):",
                  f"        v = {prefix}_TABLE_COEF[k]",
                  f"        for f in range({width}):",
                  f"            v *= w[{prefix}_TABLE_INDEX[k, f]]",
                  "        s += v",
                  "    return s",
                  "", ""]
    for k, part in enumerate(parts):
        own = {st.target for st in part}
        uses = set().union(*(st.uses for st in part))
        lines += ['@njit(cache=True, error_model="numpy")',
                  f"def {name}_part{k}(t, y, p, w, _M, dy):",
                  f'    """Part {k} of {name}: {len(part)} statements."""']
        lines += [f"    {local} = {source}" for local, source in loads.items() if local in uses]
        if t_name != "t" and t_name in uses:
            lines.append(f"    {t_name} = t")
        lines += [f"    {used} = w[{slots[used]}]" for used in sorted(uses - own) if used in slots]
        for st in part:
            lines.append(f"    {st.target} = {st.text}")
            if st.target in slots:
                lines.append(f"    w[{slots[st.target]}] = {st.target}")
        lines += ["", ""]
    lines += ['@njit(cache=True, error_model="numpy")',
              f"def {name}(t, y, p, dy):",
              f'    """Write [q\', u\'] (nq + nu = {nq + nu},) into dy; return 0, 2 or 4."""',
              *prologue,
              f"    w = np.empty({one + 3 + len(slots)})",
              f"    for i in range({ny}):",
              "        w[i] = y[i]",
              f"    for i in range({n_p}):",
              f"        w[{ny} + i] = p[i]",
              f"    w[{one}] = 1.0",
              f"    w[{one + 1}] = t",
              f"    w[{one + 2}] = 0.0",
              f"    _M = np.empty(({nu}, {nu}))"]
    if copy_dy:
        lines += [f"    for k in range({len(copy_dy)}):",
                  f"        dy[{name.upper()}_COPY_DY[k, 0]] = w[{name.upper()}_COPY_DY[k, 1]]"]
    if copy_m:
        lines += [f"    for k in range({len(copy_m)}):",
                  f"        _M[{name.upper()}_COPY_M[k, 0], {name.upper()}_COPY_M[k, 1]] = "
                  f"w[{name.upper()}_COPY_M[k, 2]]"]
    lines += [f"    {name}_part{k}(t, y, p, w, _M, dy)" for k in range(len(parts))]
    lines.append(f"    return {solve or f'ldl_solve(_M, dy[{nq}:])'}")
    return lines
