"""The constant block of a mass matrix, factored once per run (block elimination, Schur complement).

A beam's modal mass ``G_ij = integral rho phi_i phi_j dx`` (eq. 8.22) enters the mass matrix as a
block whose entries depend on the constants only, not on ``q``, ``u`` or ``t``. With the speeds
split into that block ``c`` and the rest ``r``, ``M u' = f`` is solved by block elimination::

    S = M_rr - M_rc G^-1 M_cr,   S u'_r = f_r - M_rc G^-1 f_c,   u'_c = G^-1 (f_c - M_cr u'_r)

where ``G = M_cc = L D L^T`` is factored once per run, so that a call costs O(c^2 r + c r^2 + r^3)
instead of O((c + r)^3) (``falling-beam-exact`` with 40 modes: c = 42, r = 1).

Here: :func:`constant_block` finds the block in the symbolic mass matrix, :func:`block_is_cheaper`
decides whether it pays, :func:`prepare_lines` generates the function that factors it
(``<name>_prepare(p) -> p_prepared``: the constants followed by the factors) and
:func:`prepared_parameters` is what callers of a generated module use to call it once. The solve
itself is :func:`~flexkane.numerics.linear_algebra.schur_solve`.

The same once-per-run step computes the coefficients of the term tables of a large right-hand
side (their constant factors multiplied out, :mod:`~flexkane.numerics.large_rhs`), whether or
not the mass matrix has a constant block: a module has ``<name>_prepare`` and ``NP_PREPARED``
when it has either. A generated right-hand side that has them also accepts the constants alone:
it then prepares them on every call (correct, but no longer once per run), which is why every
caller that evaluates it many times passes :func:`prepared_parameters` instead.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

__all__ = ["PREPARED_HEADER", "block_is_cheaper", "block_operations", "constant_block",
           "constant_intermediates", "plain_operations", "prepare_lines", "prepared_parameters"]

#: Entries of a prepared vector between the constants and the factors: status, failing pivot.
PREPARED_HEADER = 2
#: The block solve is used when it needs at most this fraction of the operations of the plain one.
BLOCK_OPERATIONS_FRACTION = 0.75


def constant_intermediates(eom) -> dict:
    """Intermediate symbols of ``eom`` whose value depends on the constants only, expanded.

    Parameters
    ----------
    eom : object
        Equations of motion; ``eom.intermediates`` (optional) is an ordered list of
        ``(symbol, expression)`` pairs, each expression in terms of ``q``, ``u``, ``t``, the
        constants and earlier intermediates.

    Returns
    -------
    dict
        Symbol -> expression of the constants alone, for every intermediate whose expression is,
        recursively, free of ``q``, ``u``, ``t`` and of the other intermediates. Any other
        intermediate counts as state-dependent.
    """
    import sympy

    constants = set(eom.constants)
    found: dict = {}
    for symbol, expr in getattr(eom, "intermediates", None) or []:
        expr = sympy.sympify(expr)
        if expr.free_symbols <= constants | set(found):
            found[symbol] = expr.xreplace(found)
    return found


def constant_block(eom, mass: sympy.Matrix, intermediates: dict | None = None) -> list[int]:
    """Indices of a principal block of ``mass`` whose entries depend on the constants only.

    Parameters
    ----------
    eom : object
        Equations of motion (``constants``, and optionally ``intermediates``).
    mass : sympy.Matrix (nu, nu)
        The symmetric mass matrix.
    intermediates : dict, optional
        :func:`constant_intermediates` of ``eom`` (computed if not given).

    Returns
    -------
    list of int
        Increasing indices ``c`` such that every ``mass[i, j]``, ``i, j`` in ``c``, is free of
        ``q``, ``u``, ``t`` and of state-dependent intermediates: found greedily (a largest
        such block is a largest clique of the graph of constant entries), speeds with the most
        constant entries in their row first, ties by index, so the result is deterministic.
        Empty when no diagonal entry is constant.
    """
    import sympy

    if intermediates is None:
        intermediates = constant_intermediates(eom)
    allowed = set(eom.constants) | set(intermediates)
    n = mass.shape[0]

    def is_constant(i, j):
        return sympy.sympify(mass[i, j]).free_symbols <= allowed

    candidates = [i for i in range(n) if is_constant(i, i)]
    constant = {(i, j): i == j or is_constant(i, j) for i in candidates for j in candidates}
    order = sorted(candidates, key=lambda i: (-sum(constant[i, j] for j in candidates), i))
    block: list[int] = []
    for i in order:
        if all(constant[i, j] for j in block):
            block.append(i)
    return sorted(block)


def plain_operations(n: int) -> int:
    """Floating-point operations of one L D L^T solve of an n x n system."""
    return (n ** 3 + 6 * n ** 2) // 3


def block_operations(c: int, r: int) -> int:
    """Floating-point operations of one :func:`~flexkane.numerics.linear_algebra.schur_solve`.

    ``c`` speeds in the constant block (its factors given), ``r`` others: the forward
    substitutions ``L^-1 M_cr``, ``L^-1 f_c`` (c^2 r + c^2), ``S`` and its right-hand side
    (c r^2 + 4 c r), the solve with ``S``, and ``x_c`` (2 c r + c^2 + c).
    """
    return c * c * r + c * c + c * r * r + 6 * c * r + c * c + c + plain_operations(r)


def block_is_cheaper(c: int, n: int) -> bool:
    """Whether the block solve with ``c`` of ``n`` speeds constant pays (see the constant above)."""
    return c > 0 and block_operations(c, n - c) <= BLOCK_OPERATIONS_FRACTION * plain_operations(n)


def prepare_lines(name: str, n_constants: int, block_exprs: Sequence[Sequence[sympy.Expr]],
                  constant_names: Sequence[str], print_expr: Callable[[sympy.Expr], str],
                  n_coefficients: int = 0) -> list[str]:
    """Source of ``<name>_prepare(p)``: the constants, the factors of the constant block, then
    the coefficients of the term tables.

    Parameters
    ----------
    name : str
        Name of the generated right-hand side.
    n_constants : int
        Length of the parameter vector ``p``.
    block_exprs : (c, c) nested sequence of sympy.Expr
        The block ``G`` in the local names of the constants (upper triangle read); empty when
        the mass matrix has no constant block worth eliminating.
    constant_names : sequence of str
        Local name of each entry of ``p``, in order.
    print_expr : callable
        Prints a SymPy expression as Python.
    n_coefficients : int
        Number of coefficients of the term tables (:mod:`~flexkane.numerics.large_rhs`),
        computed by ``<name>_table_coefficients`` after the factors; 0: none.

    Returns
    -------
    list of str
        Lines of the function; it returns an array of ``n_constants`` entries, then, with a
        block, ``2 + c * c`` (:func:`~flexkane.numerics.linear_algebra.constant_block_factor`),
        then ``n_coefficients``.
    """
    import sympy

    c = len(block_exprs)
    index = {local: k for k, local in enumerate(constant_names)}
    # entries that are one constant (most modal masses G_ij) or 0 are copied by a loop over an index
    # table, the others computed (few, usually): the function's compile time stays small
    copies, computed = [], []
    for i in range(c):
        for j in range(i, c):
            expr = sympy.sympify(block_exprs[i][j])
            if expr.is_Symbol and expr.name in index:
                copies += [i, j, index[expr.name]]
            elif expr != 0:
                computed.append(((i, j), expr))
    replacements, reduced = sympy.cse([e for _, e in computed],
                                      symbols=sympy.numbered_symbols("_c"), order="none")
    used = set().union(set(), *(e.free_symbols for _, e in replacements),
                       *(e.free_symbols for e in reduced))
    used = {s.name for s in used}
    factors = PREPARED_HEADER + c * c if c else 0
    size = n_constants + factors + n_coefficients
    table = f"{name.upper()}_PREPARE_COPY"
    lines = []
    if copies:
        lines += [f"{table} = np.array({copies!r}, dtype=np.int64).reshape({len(copies) // 3}, 3)",
                  "", ""]
    parts = ["the constants p"] + (["the factors of the constant block of the mass matrix"]
                                   if c else []) \
        + (["the coefficients of the term tables"] if n_coefficients else [])
    lines += ['@njit(cache=True, error_model="numpy")',
              f"def {name}_prepare(p):",
              f'    """{", ".join(parts[:-1])} and {parts[-1]} ({size},)."""' if len(parts) > 1
              else f'    """{parts[0]} ({size},)."""',
              f"    _out = np.empty({size})",
              f"    for _i in range({n_constants}):",
              "        _out[_i] = p[_i]"]
    if c:
        lines.append(f"    _G = np.zeros(({c}, {c}))")
        if copies:
            lines += [f"    for _k in range({len(copies) // 3}):",
                      f"        _G[{table}[_k, 0], {table}[_k, 1]] = p[{table}[_k, 2]]"]
        lines += [f"    {local} = p[{k}]" for k, local in enumerate(constant_names) if local in used]
        lines += [f"    {sym} = {print_expr(expr)}" for sym, expr in replacements]
        lines += [f"    _G[{i}, {j}] = {print_expr(expr)}"
                  for ((i, j), _), expr in zip(computed, reduced)]
        lines.append(f"    constant_block_factor(_G, _out, {n_constants})")
    if n_coefficients:
        lines.append(f"    {name}_table_coefficients(p, _out, {n_constants + factors})")
    lines.append("    return _out")
    return lines


def prepared_parameters(module, p, name: str = "rhs") -> np.ndarray:
    """The parameter vector to pass to a generated right-hand side for a whole run.

    Parameters
    ----------
    module : module
        Generated module (:func:`~flexkane.numerics.jit_module.build_module`).
    p : array_like (n_p,)
        Constants, in the order of the module's ``CONSTANT_NAMES``; a vector prepared already is
        returned as it is.
    name : str
        Name of the generated right-hand side.

    Returns
    -------
    ndarray
        ``p`` itself (contiguous float64) when the module has nothing to prepare; else ``p``
        followed by the factors of the constant block and the coefficients of the term tables
        (``<name>_prepare(p)``, computed once here).
    """
    p = np.ascontiguousarray(np.asarray(p, dtype=np.float64))
    prepare = getattr(module, f"{name}_prepare", None)
    prefix = "" if name == "rhs" else name.upper() + "_"
    if prepare is None or p.shape[0] == getattr(module, f"{prefix}NP_PREPARED", -1):
        return p
    return prepare(p)
