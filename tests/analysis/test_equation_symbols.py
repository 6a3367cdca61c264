"""The free symbols of the linearized equations (linearization.free_symbols), which decide whether a
prescribed coordinate is cyclic and whether the equations depend explicitly on time: the same set as
SymPy's ``free_symbols``, each shared subexpression visited once."""

import sympy as sp

from flexkane.analysis.linearization import free_symbols

t, x, y, a = sp.symbols("t x y a")


def test_free_symbols_are_sympys():
    f = sp.Function("f")
    exprs = [sp.Integer(3), a * sp.sin(x) + y ** 2, sp.Integral(x * a, (x, 0, t)), sp.Lambda(x, x + y),
             f(t).diff(t), sp.Piecewise((x, t > 1), (0, True)), sp.Float(1.5) * sp.pi]
    assert free_symbols(exprs) == set().union(*[e.free_symbols for e in exprs])
    assert free_symbols([sp.Integral(x * a, (x, 0, 1))]) == {a}    # the integration variable is bound


def test_deeply_shared_equations_are_walked_once_per_subexpression():
    """A subexpression used twice at each of 64 levels: 2^64 occurrences, about 200 distinct nodes
    (``e.free_symbols`` would walk every occurrence)."""
    e = t
    for _ in range(64):
        e = sp.sin(e) * y + sp.cos(e)
    assert free_symbols([e, a]) == {t, y, a}
    assert x not in free_symbols([e])
