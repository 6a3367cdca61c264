"""Generated right-hand sides of large models: term tables and parts.

Numba's compile time grows with the number of operations of a function (type inference and
lowering, a few milliseconds per operation on a 2-core machine) and, for one long function, faster
than that (LLVM works on one basic block). A beam with n modes brings O(n^2) terms:
``sum_ij G_ij q_i q_j`` in the mass matrix, ``sum_ij G_ij q_i u_j`` in the forcing, ``sum_i H_ij
q_i`` for each mode. Written out for ``falling-beam-exact`` with 40 modes that is 30,000
operations, which took 145 s to compile. So, above ``SPLIT_CHARS`` printed characters:

1. every sum of at least ``TABLE_TERMS_MIN`` terms becomes rows of a *term table*: each term is a
   coefficient times a product of at most ``FACTOR_MAX`` factors (states, constants, common
   subexpressions). Common subexpressions that are products (``G_12*q_5``) are folded into the
   terms instead of being computed on their own. The factors that are constants (entries of
   ``p``: modal constants, masses) are multiplied into the coefficient *once per run*, by
   ``<name>_table_coefficients`` called from ``<name>_prepare`` (terms with the same remaining
   factors share one coefficient), and the terms are stored by their number ``d`` of remaining
   factors, so that one compiled loop per ``d`` in ``<name>_table_sums`` multiplies exactly
   ``d`` factors (``u3^2 G_1j q_j`` costs two multiplications per call, not four). The compiled
   code does not grow with the number of terms; terms that share a linear form of the state (a
   modal sum such as ``sum_j G_ij q_j``) read it from ``w``, where ``<name>_table_forms``
   evaluates all such forms once per call as matrix-vector products (:func:`modal_forms`);
2. the statements that remain are distributed over functions ``<name>_part<k>`` of about
   ``SPLIT_CHARS`` characters each.

The tables' factors are read from one work array ``w``: ``w[:ny]`` the state, then 1.0, t and
0.0, then the tables' sums, the linear forms, the common subexpressions that tables or later parts read; their coefficients from the
prepared parameter vector (:func:`~flexkane.numerics.constant_block.prepared_parameters`).
Outputs that are a state, a constant, 0 or 1 (most of the mass matrix, all of ``q' = u``) are
copied from ``w`` or ``p`` by a loop over an index table.
"""

from __future__ import annotations

import math

import sympy

__all__ = ["FACTOR_MAX", "FORM_TERMS_MIN", "SPLIT_CHARS", "TABLE_TERMS_MIN", "ModalForms", "Statement",
           "Tabulated", "large_rhs_lines", "modal_forms", "table_lines", "tabulate"]

# Printed characters of a right-hand side above which it is generated in this form, and size of
# each part (chosen by measuring compile times, see benchmarks/RESULTS.md). Measured CPU time of the
# Numba compile of the right-hand side: chain_model(8) (many short statements) 19.0 s with parts of
# 12,000 characters, 16.9 s with 40,000, 11.4 s with 100,000; falling-beam-exact with 40 modes (its
# long sums in term tables) 4.1 s with each of them.
SPLIT_CHARS = 100_000
# Sums with at least this many terms are evaluated from a term table.
TABLE_TERMS_MIN = 12
# Largest number of factors of one term of a table.
FACTOR_MAX = 6
# A linear form of the state (a modal sum such as sum_j G_ij q_j) shared by at least this many terms
# of one sum is taken out of them and evaluated once per call (see modal_forms).
FORM_TERMS_MIN = 8


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


def tabulate(statements: list[Statement], printer_fn, name: str, constant_names: list[str],
             state_names: list[str] = ()) -> "Tabulated":
    """Turn the long sums of ``statements`` into term tables.

    Parameters
    ----------
    statements : list of Statement
        Common subexpressions and outputs, in order of evaluation.
    printer_fn : callable
        Prints a SymPy expression as Python.
    name : str
        Name of the generated right-hand side.
    constant_names : list of str
        Local names of the entries of ``p``: the factors folded into the coefficients.
    state_names : list of str
        Local names of the state ``w[:ny]``, in order: the factors that :func:`modal_forms`
        may take out of the tables' terms (none if empty).

    Returns
    -------
    Tabulated
    """
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
        text = f"{name}_table_sums(w, p, {index})"
        table_st = Statement(st.target, text, sympy.Integer(0))
        table_st.uses = set()
        out.append(table_st)
    constants = set(constant_names)
    groups = [_group_terms(tables.rows[a:b], constants) for a, b in tables.ranges]
    groups, forms = modal_forms(groups, state_names)
    atoms = {n for group in groups for names in group for n in names} - set(forms.names)
    # keep only what an output, a table or a kept statement reads
    needed = set(atoms)
    kept = []
    for st in reversed(out):
        if st.is_output or st.target in needed:
            needed |= st.uses
            kept.append(st)
    return Tabulated(kept[::-1], groups, atoms, constant_names, forms)


def _group_terms(rows, constants: set[str]) -> dict:
    """The terms of one sum by their state-dependent factors: ``{factors: [(coef, constants)]}``.

    ``factors`` is the sorted tuple of the factors that are not constants (entries of ``p``);
    terms with the same such factors share one coefficient, the sum of their ``coef`` times the
    product of their constants (computed once per run).
    """
    group: dict[tuple[str, ...], list] = {}
    for coef, names in rows:
        variable = tuple(sorted(n for n in names if n not in constants))
        fixed = tuple(n for n in names if n in constants)
        group.setdefault(variable, []).append((coef, fixed))
    return group


def _without(factors: tuple, x: str) -> tuple:
    """``factors`` (a sorted tuple of names) with one occurrence of ``x`` removed."""
    k = factors.index(x)
    return factors[:k] + factors[k + 1:]


class ModalForms:
    """Linear forms of the state taken out of the terms of the tables (see :func:`modal_forms`).

    Attributes
    ----------
    names : list of str
        Name of each form, ``_form<k>``, in the order of their values in the work array ``w``.
    blocks : list of tuple
        ``(lo, hi, first, rows)``: the forms ``first`` to ``first + rows - 1`` are linear in the
        state entries ``w[lo:hi]``; a block is evaluated as one matrix-vector product.
    entries : list of list
        Per block, the entries of its (hi - lo, rows) matrix, state entry by state entry, each a
        list of contributions ``(coefficient, constant names)`` (empty: zero).
    """

    def __init__(self, names, blocks, entries):
        self.names = list(names)
        self.blocks = list(blocks)
        self.entries = list(entries)

    @property
    def n_coefficients(self) -> int:
        """Number of matrix entries (coefficients computed once per run)."""
        return sum((hi - lo) * rows for lo, hi, _, rows in self.blocks)


def _scale(contributions) -> float:
    """The power of two (signed) nearest below the first coefficient of a form's contributions."""
    coef = contributions[0][0] if contributions else 1.0
    if coef == 0.0 or not math.isfinite(coef):
        return 1.0
    return math.copysign(2.0 ** (math.frexp(abs(coef))[1] - 1), coef)


def _signature(terms: dict, position: dict) -> tuple[float, tuple]:
    """``(scale, normalized coefficients)`` of a form ``{x: contributions}``.

    The coefficients divided by a power of two (exactly), so that forms that differ by such a
    factor (``sum_j G_ij q_j`` and ``sum_j 2 G_ij q_j``) have the same signature.
    """
    entries = sorted((position[x], c) for x, c in terms.items())
    scale = _scale(entries[0][1])
    return scale, tuple((j, tuple((coef / scale, fixed) for coef, fixed in c)) for j, c in entries)


def modal_forms(groups: list[dict], state_names: list[str]) -> tuple[list[dict], ModalForms]:
    """Take the linear forms of the state shared by many terms out of the tables' sums.

    A beam with n modes brings sums such as ``f_i = u3^2 sum_j G_ij q_j - sum_j H_ij q_j``,
    ``J = sum_ij G_ij q_i q_j`` or ``K = sum_ij 2 G_ij q_i u_j u3``: n^2 terms in all, each
    multiplying its factors again. Here a term (state-dependent factors ``F``, among them a state
    entry ``x``) joins the *form* ``(sum k, F without x)`` that most terms of its sum could join;
    a form of at least ``FORM_TERMS_MIN`` terms whose state entries are dense enough (at least
    half of the range they span) replaces them by one term, ``F without x`` times the form's value
    ``sum_x c_x x`` (``c_x`` the terms' coefficients).

    A term with two or more such best forms (``q_i q_j`` of ``J``: the forms of ``q_i`` and of
    ``q_j``; ``q_i u_j u3`` of ``K``: those of ``u_j u3`` and of ``q_i u3``) joins one whose form,
    with every term that could join it, equals a form of terms that had no choice, up to a power
    of two (``K = 2 u3 sum_j u_j (G q)_j`` with ``G q`` of the ``f_i``); else it joins each of
    them with an equal share of its coefficient (the symmetric rows ``J = sum_i q_i (G q)_i``
    rather than a triangle). Forms equal up to a power of two (exactly: the factor is kept in
    the term's coefficient) are one. The forms over overlapping ranges of the state are the rows
    of one matrix (zeros where a form has no term), evaluated once per call as a matrix-vector
    product (``<name>_table_forms``) before the tables; its entries are computed once per run
    with the terms' coefficients. At 40 modes the n^2 terms become two products, ``G q`` and
    ``H q``.

    Parameters
    ----------
    groups : list of dict
        Per sum: state-dependent factors (sorted tuple of names) -> contributions
        ``(coefficient, constant names)`` (see :func:`_group_terms`).
    state_names : list of str
        Names of the state entries ``w[:ny]``, in order.

    Returns
    -------
    groups : list of dict
        The sums with the forms' terms replaced by their products with the forms.
    forms : ModalForms
    """
    position = {n: k for k, n in enumerate(state_names)}
    counts: dict[tuple, int] = {}
    for k, group in enumerate(groups):
        for factors in group:
            for x in set(factors) & position.keys():
                key = (k, _without(factors, x))
                counts[key] = counts.get(key, 0) + 1
    # the best forms of each term; terms with one join it
    members: dict[tuple, dict] = {}
    choices: dict[tuple, list] = {}       # (k, factors) -> [(key, x)], best first
    for k, group in enumerate(groups):
        for factors, contributions in group.items():
            candidates = sorted(((counts[(k, _without(factors, x))], position[x], x)
                                 for x in set(factors) & position.keys()), reverse=True)
            if not candidates or candidates[0][0] < FORM_TERMS_MIN:
                continue
            best = [((k, _without(factors, x)), x) for n, _, x in candidates if n == candidates[0][0]]
            choices[(k, factors)] = best
            if len(best) == 1:
                members.setdefault(best[0][0], {})[best[0][1]] = contributions
    known = {_signature(terms, position)[1] for terms in members.values() if len(terms) >= FORM_TERMS_MIN}
    potential: dict[tuple, dict] = {}
    for (k, factors), best in choices.items():
        if len(best) > 1:
            for key, x in best:
                potential.setdefault(key, dict(members.get(key, {})))[x] = groups[k][factors]
    shares: dict[tuple, list] = {}        # (k, factors) -> [(key, x, contributions)]
    for (k, factors), best in choices.items():
        contributions = groups[k][factors]
        if len(best) > 1:
            chosen = [(key, x) for key, x in best if _signature(potential[key], position)[1] in known]
            if chosen:
                best, part = chosen[:1], contributions
            else:
                part = [(coef / len(best), fixed) for coef, fixed in contributions]
            for key, x in best:
                members.setdefault(key, {})[x] = part
        else:
            part = contributions
        shares[(k, factors)] = [(key, x, part) for key, x in best]
    # forms with enough terms, dense enough; one per signature
    signatures: dict[tuple, int] = {}
    form_of: dict[tuple, tuple[int, float]] = {}    # key -> (form, scale)
    for key, terms in members.items():
        span = sorted(position[x] for x in terms)
        if len(span) < FORM_TERMS_MIN or 2 * len(span) < span[-1] - span[0] + 1:
            continue
        scale, signature = _signature(terms, position)
        form_of[key] = (signatures.setdefault(signature, len(signatures)), scale)
    if not form_of:
        return groups, ModalForms([], [], [])
    # blocks: forms over overlapping ranges of the state, by their first entry
    spans = sorted((sig[0][0], sig[-1][0] + 1, f) for sig, f in signatures.items())
    merged: list[list] = []
    for lo, hi, f in spans:
        if merged and lo < merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], hi)
            merged[-1][2].append(f)
        else:
            merged.append([lo, hi, [f]])
    coefficients = {f: dict((j, list(c)) for j, c in sig) for sig, f in signatures.items()}
    number, blocks, entries = {}, [], []
    for lo, hi, fs in merged:
        blocks.append((lo, hi, len(number), len(fs)))
        entries.append([coefficients[f].get(j, []) for j in range(lo, hi) for f in fs])
        number.update({f: len(number) + i for i, f in enumerate(fs)})
    names = [f"_form{m}" for m in range(len(number))]
    out = []
    for k, group in enumerate(groups):
        new: dict[tuple, list] = {}
        for factors, contributions in group.items():
            parts = shares.get((k, factors), [(None, None, contributions)])
            for key, _, part in parts:
                if key in form_of:
                    form, scale = form_of[key]
                    new.setdefault(tuple(sorted(key[1] + (names[number[form]],))), [(scale, ())])
                else:
                    new.setdefault(factors, []).extend(part)
        out.append(new)
    return out, ModalForms(names, blocks, entries)


class Tabulated:
    """The statements of a large right-hand side once its long sums are term tables.

    Attributes
    ----------
    statements : list of Statement
        What remains to be written out; a tabulated sum is a statement
        ``target = <name>_table_sums(w, p, k)`` (written as a call of the loop over
        consecutive sums and a read of its result).
    groups : list of dict
        Per sum ``k``: state-dependent factors (tuple of names) -> contributions
        ``(coefficient, constant names)`` of its coefficient.
    atoms : set of str
        Names read by the tables (states, t, common subexpressions; no constants, no forms).
    forms : ModalForms
        Linear forms of the state that the terms of the tables read (:func:`modal_forms`).
    n_coefficients : int
        Number of coefficients that ``<name>_table_coefficients`` computes once per run: those
        of the terms, then the entries of the forms' matrices.
    """

    def __init__(self, statements, groups, atoms, constant_names, forms=None):
        self.statements = statements
        self.groups = groups
        self.atoms = atoms
        self.constant_names = list(constant_names)
        self.forms = forms if forms is not None else ModalForms([], [], [])
        self.n_coefficients = sum(len(g) for g in groups) + self.forms.n_coefficients
        self.sum_atoms = [{n for names in g for n in names} for g in groups]

    @property
    def table_operations(self) -> int:
        """Floating-point operations of one evaluation of the tables and the forms.

        A term of ``d`` factors costs ``d`` products and one sum; an entry of a form's matrix a
        product and a sum. The coefficients (computed once per run) are not counted.
        """
        return (sum(len(factors) + 1 for g in self.groups for factors in g)
                + 2 * self.forms.n_coefficients)


def _copy_source(st: Statement, fixed: dict[str, int], in_p: dict[str, int]) -> tuple | None:
    """``(from_p, index)`` of the value an output statement copies (from ``w`` or ``p``), or None."""
    if not st.is_output or st.text.endswith(")") and "_table_sums(w, p, " in st.text:
        return None
    expr = st.expr
    if expr.is_Symbol and expr.name in fixed:
        return False, fixed[expr.name]
    if expr.is_Symbol and expr.name in in_p:
        return True, in_p[expr.name]
    if expr == 0 or expr == 1:
        return False, fixed[str(int(expr))]
    return None


def large_rhs_lines(name: str, tabulated: Tabulated, state_names: list[str],
                    constant_names: list[str], t_name: str, nq: int, nu: int, *,
                    prologue: list[str] = (), solve: str | None = None,
                    coefficients_at: int = 0) -> list[str]:
    """Source lines of ``name`` (and its parts and tables) for a large right-hand side.

    Parameters
    ----------
    name : str
        Name of the generated function.
    tabulated : Tabulated
        :func:`tabulate` of the statements: common subexpressions, then ``dy[i]`` (q', and f
        into ``dy[nq:]``) and ``_M[i, j]`` (upper triangle), in order of evaluation.
    state_names, constant_names : list of str
        Local names of ``y`` (ny,) and ``p`` entries, in order.
    t_name : str
        Local name of the time.
    nq, nu : int
        Numbers of coordinates and speeds.
    prologue : list of str
        Lines (indented) that open ``name``, before anything reads ``p``; they must make ``p``
        the prepared vector when the tables have coefficients.
    solve : str, optional
        Expression solving ``_M u' = dy[nq:]`` in place and giving the status code; default
        ``ldl_solve(_M, dy[nq:])`` (the block solve of
        :mod:`~flexkane.numerics.constant_block` otherwise). Entries of ``_M`` that it does
        not read need no statement.
    coefficients_at : int
        Where the tables' coefficients start in the prepared parameter vector (written there by
        ``<name>_table_coefficients(p, out, coefficients_at)``, once per run).
    """
    statements, groups, atoms = tabulated.statements, tabulated.groups, tabulated.atoms
    ny = len(state_names)
    fixed = {n: k for k, n in enumerate(state_names)}
    one = ny
    fixed["1"] = one
    fixed[t_name] = one + 1
    fixed["0"] = one + 2
    in_p = {n: k for k, n in enumerate(constant_names)}
    # outputs that are a state, a constant, 0 or 1 (most of M, all of q' = u) are copied by a loop
    copies: dict[str, list] = {"DY": [], "M": [], "P_DY": [], "P_M": []}
    rest = []
    for st in statements:
        source = _copy_source(st, fixed, in_p)
        if source is None:
            rest.append(st)
            continue
        from_p, k = source
        label = ("P_" if from_p else "") + ("DY" if st.target.startswith("dy[") else "M")
        if st.target.startswith("dy["):
            copies[label].append([int(st.target[3:-1]), k])
        else:
            copies[label].append([*(int(i) for i in st.target[3:-1].split(",")), k])
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
    results = one + 3                   # w[results + k]: sum k of the tables
    forms = tabulated.forms
    forms_at = results + len(groups)    # w[forms_at + m]: form m (modal_forms)
    fixed.update({f: forms_at + m for m, f in enumerate(forms.names)})
    first_slot = forms_at + len(forms.names)
    slots: dict[str, int] = {}
    for atom in sorted(atoms, key=lambda a: (a not in defined_in, a)):
        if atom not in fixed:
            slots[atom] = first_slot + len(slots)
    for k, part in enumerate(parts):
        for st in part:
            for used in sorted(st.uses):
                if defined_in.get(used, k) < k and used not in slots:
                    slots[used] = first_slot + len(slots)
    index = {**fixed, **slots}
    loads = {n: f"y[{k}]" for k, n in enumerate(state_names)}
    loads.update({n: f"p[{k}]" for k, n in enumerate(constant_names)})
    prefix = name.upper()
    lines = []
    for label, rows in copies.items():
        if rows:
            flat = [v for row in rows for v in row]
            lines += [f"{_copy_table(prefix, label)} = np.array({flat!r}, dtype=np.int64).reshape("
                      f"{len(rows)}, {len(rows[0])})"]
    if groups:
        lines += table_lines(name, groups, index, tabulated.constant_names, results, forms)
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
        for batch in _batches(part, tabulated.sum_atoms):
            sums = [_sum_index(st) for st in batch]
            if sums[0] is not None:
                # consecutive sums, evaluated by one loop (one call site, not one per sum: LLVM
                # would inline and vectorize every call with constant bounds, doubling compile time)
                lines.append(f"    {name}_table_sums(w, p, {coefficients_at}, {sums[0]}, "
                             f"{sums[-1] + 1})")
            for st, k_sum in zip(batch, sums):
                text = st.text if k_sum is None else f"w[{results + k_sum}]"
                lines.append(f"    {st.target} = {text}")
                if st.target in slots:
                    lines.append(f"    w[{slots[st.target]}] = {st.target}")
        lines += ["", ""]
    lines += ['@njit(cache=True, error_model="numpy")',
              f"def {name}(t, y, p, dy):",
              f'    """Write [q\', u\'] (nq + nu = {nq + nu},) into dy; return 0, 2 or 4."""',
              *prologue,
              f"    w = np.empty({first_slot + len(slots)})",
              f"    for i in range({ny}):",
              "        w[i] = y[i]",
              f"    w[{one}] = 1.0",
              f"    w[{one + 1}] = t",
              f"    w[{one + 2}] = 0.0",
              f"    _M = np.empty(({nu}, {nu}))"]
    for label, rows in copies.items():
        if not rows:
            continue
        source = "p" if label.startswith("P_") else "w"
        table = _copy_table(prefix, label)
        lines.append(f"    for k in range({len(rows)}):")
        if label.endswith("DY"):
            lines.append(f"        dy[{table}[k, 0]] = {source}[{table}[k, 1]]")
        else:
            lines.append(f"        _M[{table}[k, 0], {table}[k, 1]] = {source}[{table}[k, 2]]")
    if forms.names:
        lines.append(f"    {name}_table_forms(w, p, {coefficients_at})")
    lines += [f"    {name}_part{k}(t, y, p, w, _M, dy)" for k in range(len(parts))]
    lines.append(f"    return {solve or f'ldl_solve(_M, dy[{nq}:])'}")
    return lines


def table_lines(name: str, groups: list[dict], index: dict[str, int], constant_names: list[str],
                results: int, forms: ModalForms | None = None) -> list[str]:
    """Module lines of the term tables: data, ``<name>_table_sums``, ``<name>_table_coefficients``
    and, with ``forms``, ``<name>_table_forms``.

    The coefficient of each term is the sum of its contributions, each a number times entries of
    ``p``; ``<name>_table_coefficients(p, out, at)`` computes them once per run into
    ``out[at:]``. The terms are stored by their number ``d`` of remaining factors (entries of
    the work array ``w``), so that the loop over the terms of ``d`` factors multiplies exactly
    ``d`` of them: ``<name>_table_sums(w, p, at, first, last)`` writes the sums ``first`` to
    ``last - 1`` into ``w[results + k]``. The entries of the forms' matrices
    (:func:`modal_forms`) are coefficients too, after those of the terms, column by column;
    ``<name>_table_forms(w, p, at)`` writes the forms into ``w[index[form]]`` (each block a
    matrix-vector product, column by column: a loop over the rows that needs no reduction).
    """
    forms = forms if forms is not None else ModalForms([], [], [])
    prefix = name.upper()
    in_p = {n: k for k, n in enumerate(constant_names)}
    degrees = sorted({len(f) for g in groups for f in g})
    # coefficient number of each term: degree by degree, sum by sum
    starts = []            # (n_sums + 1, len(degrees)): first term of sum k among those of degree d
    base = {}
    count = 0
    factor_rows: dict[int, list[int]] = {}
    contribution_ptr, contribution_coef, factor_ptr, factor_index = [0], [], [0], []
    for d in degrees:
        base[d] = count
        rows = factor_rows.setdefault(d, [])
        column = []
        for group in groups:
            column.append(count - base[d])
            for factors, contributions in group.items():
                if len(factors) != d:
                    continue
                rows.extend(index[f] for f in factors)
                for coef, fixed in contributions:
                    contribution_coef.append(coef)
                    factor_index.extend(in_p[f] for f in fixed)
                    factor_ptr.append(len(factor_index))
                contribution_ptr.append(len(contribution_coef))
                count += 1
        column.append(count - base[d])
        starts.append(column)
    n_terms = count
    form_rows = []              # per block: lo, hi, w index of its first form, rows, first coefficient
    for (lo, hi, first, rows), entries in zip(forms.blocks, forms.entries):
        form_rows += [lo, hi, index[forms.names[first]], rows, count]
        for contributions in entries:
            for coef, fixed in contributions:
                contribution_coef.append(coef)
                factor_index.extend(in_p[f] for f in fixed)
                factor_ptr.append(len(factor_index))
            contribution_ptr.append(len(contribution_coef))
            count += 1
    n_sums = len(groups)
    starts_flat = [starts[c][k] for k in range(n_sums + 1) for c in range(len(degrees))]
    lines = [f"# Term tables of {name}: {n_terms} terms in {n_sums} sums; a term is a coefficient "
             "(computed once per run from the constants) times d factors (entries of the work array",
             f"# w), stored by d = {degrees}.",
             f"{prefix}_TABLE_COEF = np.array({contribution_coef!r}, dtype=np.float64)",
             f"{prefix}_TERMS_TABLE_INDEX = np.array({contribution_ptr!r}, dtype=np.int64)",
             f"{prefix}_FACTORS_TABLE_INDEX = np.array({factor_ptr!r}, dtype=np.int64)",
             f"{prefix}_CONSTANTS_TABLE_INDEX = np.array({factor_index or [0]!r}, dtype=np.int64)",
             f"{prefix}_STARTS_TABLE_INDEX = np.array({starts_flat!r}, dtype=np.uint64).reshape("
             f"{n_sums + 1}, {len(degrees)})"]
    for d in degrees:
        if d:
            lines.append(f"{prefix}_D{d}_TABLE_INDEX = np.array({factor_rows[d]!r}, "
                         f"dtype=np.uint64).reshape({len(factor_rows[d]) // d}, {d})")
    lines += ["", "",
              '@njit(cache=True, error_model="numpy")',
              f"def {name}_table_coefficients(p, out, at):",
              f'    """The {count} coefficients of the {name} tables into out[at:], from the '
              'constants p."""',
              f"    for k in range({count}):",
              "        s = 0.0",
              f"        for j in range({prefix}_TERMS_TABLE_INDEX[k], {prefix}_TERMS_TABLE_INDEX[k + 1]):",
              f"            v = {prefix}_TABLE_COEF[j]",
              f"            for f in range({prefix}_FACTORS_TABLE_INDEX[j], {prefix}_FACTORS_TABLE_INDEX[j + 1]):",
              f"                v *= p[{prefix}_CONSTANTS_TABLE_INDEX[f]]",
              "            s += v",
              "        out[at + k] = s",
              "", "",
              '@njit(cache=True, error_model="numpy")',
              f"def {name}_table_sums(w, p, at, first, last):",
              f'    """Sums first:last of the {name} tables into w[{results} + k]; their coefficients '
              'are p[at:] (prepared)."""',
              "    # unsigned indices (the tables' dtype): no wraparound test of negative ones",
              *(f"    at{d} = np.uint64(at + {base[d]})" for d in degrees),
              "    for k in range(first, last):",
              "        s = 0.0"]
    for c, d in enumerate(degrees):
        product = "".join(f" * w[{prefix}_D{d}_TABLE_INDEX[i, {f}]]" for f in range(d))
        lines += [f"        for i in range({prefix}_STARTS_TABLE_INDEX[k, {c}], "
                  f"{prefix}_STARTS_TABLE_INDEX[k + 1, {c}]):",
                  f"            s += p[at{d} + i]{product}"]
    lines += [f"        w[{results} + k] = s", "", ""]
    if forms.blocks:
        n_blocks = len(forms.blocks)
        lines += [f"# Linear forms of the state shared by the terms: {len(forms.names)} forms in "
                  f"{n_blocks} matrices (first state entry, end, first form in w, rows, first "
                  "coefficient).",
                  f"{prefix}_FORMS_TABLE_INDEX = np.array({form_rows!r}, dtype=np.int64).reshape("
                  f"{n_blocks}, 5)",
                  "", "",
                  '@njit(cache=True, error_model="numpy")',
                  f"def {name}_table_forms(w, p, at):",
                  f'    """The {len(forms.names)} linear forms of the state read by the {name} tables, '
                  'into w; their matrices are p[at:] (prepared)."""',
                  "    # unsigned indices: no wraparound test of negative ones, so LLVM vectorizes the",
                  "    # loop over the rows (3.6 times faster, the same bits)",
                  f"    for b in range({n_blocks}):",
                  f"        lo = {prefix}_FORMS_TABLE_INDEX[b, 0]",
                  f"        out = np.uint64({prefix}_FORMS_TABLE_INDEX[b, 2])",
                  f"        rows = np.uint64({prefix}_FORMS_TABLE_INDEX[b, 3])",
                  "        for r in range(rows):",
                  "            w[out + r] = 0.0",
                  f"        for j in range(lo, {prefix}_FORMS_TABLE_INDEX[b, 1]):",
                  "            x = w[j]",
                  f"            c = np.uint64(at + {prefix}_FORMS_TABLE_INDEX[b, 4] + (j - lo) * "
                  f"{prefix}_FORMS_TABLE_INDEX[b, 3])",
                  "            for r in range(rows):",
                  "                w[out + r] += p[c + r] * x",
                  "", ""]
    return lines


def _copy_table(prefix: str, label: str) -> str:
    """Name of a copy table: ``label`` is DY or M (target), prefixed by P_ when read from p."""
    return f"{prefix}_{'P' if label.startswith('P_') else 'W'}_COPY_{label.split('_')[-1]}"


def _sum_index(st: Statement) -> int | None:
    """Number of the table sum a statement takes, or None for a written-out statement."""
    if "_table_sums(w, p, " in st.text and not st.uses:
        return int(st.text.rsplit(", ", 1)[1].rstrip(")"))
    return None


def _batches(part: list[Statement], sum_atoms: list[set]) -> list[list[Statement]]:
    """``part`` cut into runs of consecutive table sums (k, k + 1, ...) and single statements.

    A run ends where a sum reads (as a factor) the target of an earlier sum of the run.
    """
    out: list[list[Statement]] = []
    targets: set[str] = set()
    for st in part:
        k = _sum_index(st)
        last = out[-1] if out else None
        if k is not None and last and _sum_index(last[-1]) == k - 1 \
                and not (sum_atoms[k] & targets):
            last.append(st)
            targets.add(st.target)
            continue
        out.append([st])
        targets = {st.target} if k is not None else set()
    return out
