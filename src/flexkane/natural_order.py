"""Natural order of names: ``E_1, E_2, ..., E_10`` rather than ``E_1, E_10, E_11, ..., E_2``."""

from __future__ import annotations

import re

__all__ = ["natural_key"]

_DIGITS = re.compile(r"(\d+)")


def natural_key(text: str) -> tuple:
    """Sort key of a name or a printed term that compares runs of digits as numbers.

    Parameters
    ----------
    text : str
        A symbol name (``G_12``) or any text (``2*E_10*u13*u3``).

    Returns
    -------
    tuple
        Pairs of a text part and the number after it (-1 after the last text part), then the text:
        ``"E_10" -> (("E_", 10), ("", -1)), "E_10")``, so that ``m`` sorts before ``m1`` (a text part
        is never compared with a number); ties between texts whose numbers are written differently
        (``q01``, ``q1``) are broken by the text itself.
    """
    parts = _DIGITS.split(text) + [None]
    return tuple((parts[k], int(parts[k + 1]) if parts[k + 1] is not None else -1)
                 for k in range(0, len(parts) - 1, 2)), text
