"""Budget of one derivation: bounded time and bounded size of the equations.

A model file is untrusted input, so the symbolic work it asks for is bounded. The expressions a
user may write are bounded by :mod:`flexkane.expressions` (length, elements, depth, exponents) and
are never expanded; on top of that, the derivation as a whole has

* a time budget, :data:`DEFAULT_SECONDS` unless the environment variable ``FLEXKANE_DERIVE_SECONDS``
  sets another (checked between the stages of the derivation);
* a size budget, :data:`DEFAULT_NODES` distinct subexpressions in the equations of motion (a measure
  of the memory they take), unless ``FLEXKANE_DERIVE_NODES`` sets another.

Exceeding either raises :class:`~flexkane.errors.ModelError` (exit code 2) naming the budget, the
stage reached, and the variable that raises it. Neither budget changes any result of a derivation
that stays within it.
"""

from __future__ import annotations

import os
import time

import sympy as sp

from ..errors import ModelError

__all__ = ["DEFAULT_NODES", "DEFAULT_SECONDS", "DerivationBudget"]

#: Default time budget of one derivation [s].
DEFAULT_SECONDS = 1800.0
#: Default largest number of distinct subexpressions of the equations of motion.
DEFAULT_NODES = 20_000_000


def _setting(variable: str, default: float) -> float:
    text = os.environ.get(variable)
    if text is None or not text.strip():
        return default
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not value >= 0 or value == float("inf"):
        raise ModelError(variable, "a non-negative finite number (environment variable)", text)
    return value


class DerivationBudget:
    """Time and size limits of one derivation (read from the environment when created)."""

    def __init__(self):
        self.seconds = _setting("FLEXKANE_DERIVE_SECONDS", DEFAULT_SECONDS)
        self.nodes = int(_setting("FLEXKANE_DERIVE_NODES", DEFAULT_NODES))
        self.start = time.monotonic()

    def check_time(self, stage: str) -> None:
        """Raise ModelError when the derivation has run longer than its time budget."""
        elapsed = time.monotonic() - self.start
        if elapsed > self.seconds:
            raise ModelError("derivation", f"a derivation within its time budget of {self.seconds:g} s",
                             f"{elapsed:.1f} s spent by the end of {stage}",
                             "simplify the model (fewer modes or links, shorter expressions) or raise "
                             "the budget with the environment variable FLEXKANE_DERIVE_SECONDS")

    def check_size(self, exprs, stage: str) -> None:
        """Raise ModelError when ``exprs`` hold more distinct subexpressions than the size budget."""
        seen: set[int] = set()
        stack = list(exprs)
        while stack:
            node = stack.pop()
            key = id(node)
            if key in seen:
                continue
            seen.add(key)
            if len(seen) > self.nodes:
                raise ModelError("derivation", f"equations of at most {self.nodes} distinct "
                                 "subexpressions (the size budget of a derivation)",
                                 f"more by the end of {stage}",
                                 "simplify the model (fewer modes or links, shorter expressions) or "
                                 "raise the budget with the environment variable FLEXKANE_DERIVE_NODES")
            if isinstance(node, sp.Basic):
                stack.extend(node.args)
        self.check_time(stage)
