"""Bounds on how much work one command may be asked for, refused before anything is allocated.

A sweep runs one variant per combination of its varied values, a Campbell diagram one linearization
per spin rate: each is a count the user types (``--vary EI=20:80:COUNT``, ``--spin 0:8:COUNT``), and
a count without a bound would allocate its arrays without limit before the first result. One bound
serves them all: :data:`MAX_VARIANTS`, checked by :func:`check_count` on the count alone, before the
values are made.
"""

from __future__ import annotations

from .errors import ModelError

__all__ = ["MAX_VARIANTS", "check_count"]

#: Largest number of variants of one sweep (grid combinations or random samples) and of operating
#: points of one study (spin rates of a Campbell diagram); more is refused.
MAX_VARIANTS = 100_000


def check_count(count: int, where: str, expected: str, given: object = None) -> None:
    """Refuse a count above :data:`MAX_VARIANTS`.

    Parameters
    ----------
    count : int
        The number of variants (or spin rates) asked for.
    where : str
        The field or option that asked for it (``--spin``, ``vary``).
    expected : str
        What is allowed, with ``{limit}`` where the bound goes (``"at most {limit} spin rates"``).
    given : object, optional
        What the user gave, as shown in the message; ``count`` when omitted.

    Raises
    ------
    ModelError
        Naming ``where``, what is allowed and what was given, when ``count > MAX_VARIANTS``.
    """
    if count > MAX_VARIANTS:
        raise ModelError(where, expected.format(limit=f"{MAX_VARIANTS:,}"), count if given is None else given)
