"""The C99 printer and names of numerics.c_source: doubles printed exactly, C identifiers only."""

from __future__ import annotations

import pytest
import sympy as sp

from flexkane.numerics.c_source import C_RESERVED, _CPrinter, c_identifier, check_prefix


def test_numbers_are_doubles_printed_exactly():
    x = sp.Symbol("x", real=True)
    printer = _CPrinter()
    assert printer.doprint(sp.Integer(3) ** 50 * x) == f"{float(3 ** 50)!r}*x"   # no int overflow
    assert float(printer.doprint(sp.Float(0.1))) == 0.1
    assert printer.doprint(x / 3) in (f"{1 / 3!r}*x", f"({1 / 3!r})*x")        # no integer division
    assert printer.doprint(sp.pi * x) == f"{3.141592653589793!r}*x"             # no M_PI (not C99)
    assert printer.doprint(x ** 2) == "(x*x)" and printer.doprint(x ** -3) == "(1.0/pow(x, 3.0))"
    assert printer.doprint(sp.sqrt(x)) == "sqrt(x)"


def test_piecewise_without_otherwise_is_nan_there():
    x = sp.Symbol("x", real=True)
    text = _CPrinter().doprint(sp.Piecewise((x, x > 0)))
    assert "NAN" in text and "\n" not in text


def test_identifiers_from_labels():
    assert c_identifier("falling-beam") == "falling_beam"
    assert c_identifier("../2 arms") == "arms"
    assert c_identifier("***") == "model"
    assert check_prefix("arm_1") == "arm_1"
    for bad in ("1arm", "_arm", "a-b", "sin", "double", "x" * 61, 3):
        with pytest.raises(ValueError, match="C identifier"):
            check_prefix(bad)
    assert {"sin", "NAN", "y0", "int", "isfinite"} <= C_RESERVED
