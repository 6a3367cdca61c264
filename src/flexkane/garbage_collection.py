"""Python's cyclic garbage collector during a command: young objects only, as a rule.

CPython collects its oldest generation whenever it has grown by a quarter; each such full pass
walks every object alive. A command imports SymPy, Numba and matplotlib (some 200 000 objects that
live until it ends) and makes as many again while it derives, compiles and draws, so that the full
passes of one run of ``flexkane run falling-beam`` from an empty cache took 0.4 s to 0.55 s of its
CPU (four passes), and the young generations 0.2 s. Within :func:`long_lived_objects`, a full
pass comes only after :data:`FULL_PASS_EVERY` passes over the middle generation instead of 10:
cyclic garbage of the young generations is still collected as before; what outlives them (the
libraries, the equations, the compiled functions) is kept for the command anyway.
"""

from __future__ import annotations

import contextlib
import gc
from collections.abc import Iterator

__all__ = ["FULL_PASS_EVERY", "long_lived_objects"]

#: Passes over the middle generation between two full passes within :func:`long_lived_objects`
#: (CPython's default: 10): a full pass after some 7 million allocations not freed at once (700 per
#: young pass, 10 young passes per middle one) instead of 70 000. A fresh run of falling-beam makes
#: about 45 passes over the middle generation.
FULL_PASS_EVERY = 1_000


@contextlib.contextmanager
def long_lived_objects() -> Iterator[None]:
    """Within the block, Python's collector rarely walks the oldest generation; restored after it.

    Collections of the young and middle generations (thresholds unchanged) still free the cyclic
    garbage made and dropped in between; an explicit :func:`gc.collect` still collects everything.
    """
    before = gc.get_threshold()
    gc.set_threshold(before[0], before[1], max(before[2], FULL_PASS_EVERY))
    try:
        yield
    finally:
        gc.set_threshold(*before)
