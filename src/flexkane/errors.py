"""Errors that flexkane reports to its users.

Every error a user can cause carries enough to fix it without reading code: the key path of the
offending field (``beams.arm.EI``), what was expected (with the unit) and what was given. The
command-line interface turns :class:`ModelError` and :class:`ResultsError` into exit code 2 and
:class:`SolverFailure` into exit code 3, without a traceback.
"""

from __future__ import annotations

__all__ = ["FlexkaneError", "ModelError", "ModelErrors", "ResultsError", "SolverFailure", "describe_value"]


def describe_value(value: object, limit: int = 60) -> str:
    """Return a short, printable description of a user-given value.

    Parameters
    ----------
    value : object
        The value as given.
    limit : int
        Maximum number of characters kept.

    Returns
    -------
    str
        ``repr(value)``, shortened with an ellipsis beyond ``limit`` characters.
    """
    text = repr(value)
    if len(text) > limit:
        text = text[: limit - 3] + "..."
    return text


class FlexkaneError(Exception):
    """Base class of every error flexkane raises on purpose."""


class ModelError(FlexkaneError, ValueError):
    """A model field or an argument is invalid.

    Parameters
    ----------
    path : str
        Key path of the field, e.g. ``"beams.arm.EI"`` or ``"--n-modes"``.
    expected : str
        What was expected, with the unit where there is one, e.g.
        ``"a positive number [N m^2]"``.
    given : object, optional
        The value that was given. Omitted from the message when ``None``
        and ``show_given`` is false.
    hint : str, optional
        A suggestion, e.g. ``"did you mean 'EI'?"``.
    show_given : bool
        Whether to print ``given`` even when it is ``None``.
    """

    def __init__(self, path: str, expected: str, given: object = None, hint: str | None = None,
                 *, show_given: bool = True):
        self.path = path
        self.expected = expected
        self.given = given
        self.hint = hint
        message = f"{path}: expected {expected}"
        if given is not None or show_given:
            shown = describe_value(given) if not isinstance(given, str) or given == "" else repr(given)
            message += f", got {shown}"
        if hint:
            message += f" ({hint})"
        super().__init__(message)


class ModelErrors(ModelError):
    """Several problems of one model, reported together.

    Its ``path``, ``expected``, ``given`` and ``hint`` are those of the first problem; its message
    starts with the first problem's and lists each other problem on a line of its own.

    Parameters
    ----------
    errors : list of ModelError
        The problems, in the order they were found (at least two).
    limit : int, optional
        The most problems one report lists, when the validation stopped there.
    """

    def __init__(self, errors, limit: int | None = None):
        errors = list(errors)
        first = errors[0]
        super().__init__(first.path, first.expected, first.given, first.hint)
        self.errors = errors
        self.limit = limit
        lines = [str(first)] + [f"also {error}" for error in errors[1:]]
        total = f"{len(errors)} problems" + (f" (the first {limit}; fix them and check again)" if limit else "")
        self.args = ("\n".join(lines) + f"\n({total})",)

    def __str__(self) -> str:
        return self.args[0]


class SolverFailure(FlexkaneError, RuntimeError):
    """The integration stopped before the end of the time span.

    Parameters
    ----------
    t_reached : float
        Last time [s] at which the state is known.
    cause : str
        Human-readable likely cause (step size too small, non-finite state, ...).
    """

    def __init__(self, t_reached: float, cause: str):
        self.t_reached = float(t_reached)
        self.cause = cause
        super().__init__(f"integration stopped at t = {self.t_reached:.6g} s: {cause}")


class ResultsError(FlexkaneError, ValueError):
    """A results file cannot be read: it is truncated, damaged, not a results file or incomplete.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    problem : str
        What is wrong with it, e.g. ``"array 'state' is missing"``.
    """

    def __init__(self, path, problem: str):
        self.path = str(path)
        self.problem = problem
        super().__init__(f"{self.path}: not a readable flexkane results file: {problem}")
