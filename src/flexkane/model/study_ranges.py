"""What the analysis commands are given to study, read from their options: spin rates, mode counts, a
tolerance.

``campbell --spin START:STOP:COUNT`` (or ``A,B,C``) [rad/s], ``converge --n-modes A..B`` (or ``A,B,C``,
``N``) and ``converge --tolerance TOL`` [-] are read and bounded here, before any model is derived and
before anything is allocated (the count of spin rates by :func:`flexkane.limits.check_count`, the mode
counts by :data:`flexkane.model.validate.MAX_MODES`). The module imports neither SymPy nor SciPy, so
that a command answered from the cache of results (:mod:`flexkane.result_cache`) does not load the
analyses; :mod:`flexkane.analysis.campbell` and :mod:`flexkane.analysis.convergence` use the same
functions.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from ..errors import ModelError

__all__ = ["DEFAULT_TOLERANCE", "SPIN_LIMIT", "check_tolerance", "checked_mode_counts", "parse_mode_counts",
           "parse_spin_range"]

#: The forms of ``--spin``.
_SPIN_FORMS = "spin rates [rad/s] as START:STOP:COUNT (e.g. 0:8:33) or a list A,B,C"
#: What ``--spin`` allows at most (:func:`flexkane.limits.check_count`).
SPIN_LIMIT = "at most {limit} spin rates (as many as the largest sweep has variants)"


#: Relative change per added count of modes under which a quantity is converged, unless stated.
DEFAULT_TOLERANCE = 1e-3
#: The forms of ``--n-modes`` in a convergence study.
_COUNT_FORMS = "mode counts as 1..N, a list A,B,C (increasing) or N, each 1 to {limit}"


def parse_spin_range(text: str, flag: str = "--spin") -> np.ndarray:
    """Spin rates from ``START:STOP:COUNT`` (COUNT rates from START to STOP) or ``A,B,C`` [rad/s].

    The count is bounded by :data:`flexkane.limits.MAX_VARIANTS`, checked before the rates are made.

    Returns
    -------
    numpy.ndarray
        Shape (COUNT,).
    """
    from ..limits import check_count

    text = str(text).strip()
    count = text.count(",") + 1
    try:
        if ":" in text:
            parts = text.split(":")
            if len(parts) != 3:
                raise ValueError
            start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
            if count < 1 or not (math.isfinite(start) and math.isfinite(stop)):
                raise ValueError
    except ValueError:
        raise ModelError(flag, _SPIN_FORMS, text) from None
    check_count(count, flag, SPIN_LIMIT, text)
    try:
        if ":" in text:
            values = np.linspace(start, stop, count)
        else:
            values = np.array([float(v) for v in text.split(",")], dtype=float)
            if values.size == 0 or not np.all(np.isfinite(values)):
                raise ValueError
    except ValueError:
        raise ModelError(flag, _SPIN_FORMS, text) from None
    return values


def parse_mode_counts(text: str, flag: str = "--n-modes") -> list[int]:
    """Mode counts from ``A..B`` (every count from A to B), ``A,B,C`` or ``N``.

    Returns
    -------
    list of int
        Increasing, each from 1 to :data:`~flexkane.model.validate.MAX_MODES`.
    """
    from .validate import MAX_MODES

    text = str(text).strip()
    counts: list = []
    try:
        if ".." in text:
            first, last = (int(v) for v in text.split(".."))
            if 1 <= first <= last <= MAX_MODES:       # bounded before the range is made
                counts = list(range(first, last + 1))
        elif text.count(",") < MAX_MODES:
            counts = [int(v) for v in text.split(",")]
    except ValueError:
        counts = []
    try:
        return checked_mode_counts(counts, flag)
    except ModelError:
        raise ModelError(flag, _COUNT_FORMS.format(limit=MAX_MODES), text) from None


def checked_mode_counts(counts, flag: str = "--n-modes") -> list[int]:
    """The mode counts of a study as a list: integers, increasing, each from 1 to
    :data:`~flexkane.model.validate.MAX_MODES` (a ModelError naming ``flag`` otherwise)."""
    from .validate import MAX_MODES

    counts = list(itertools.islice(iter(counts), MAX_MODES + 1))     # never more than one too many
    counts = counts if len(counts) <= MAX_MODES else []
    if (not counts or any(isinstance(c, bool) or not isinstance(c, (int, np.integer)) or not 1 <= c <= MAX_MODES
                          for c in counts) or counts != sorted(set(counts))):
        raise ModelError(flag, _COUNT_FORMS.format(limit=MAX_MODES), counts)
    return [int(c) for c in counts]


def check_tolerance(tolerance, flag: str = "--tolerance") -> float:
    """The tolerance of a convergence verdict: a finite number between 0 and 1 [-] (a ModelError
    naming ``flag`` otherwise)."""
    if isinstance(tolerance, bool) or not isinstance(tolerance, (int, float)) or not 0 < tolerance < 1:
        raise ModelError(flag, "a relative change between 0 and 1 (e.g. 1e-3)", tolerance)
    return float(tolerance)
