"""A progress bar for long runs and sweeps: shown on a terminal after about a second, silent otherwise."""

from __future__ import annotations

import sys
import time

__all__ = ["ProgressBar"]


class ProgressBar:
    """Progress of simulated time (or of variants done), drawn on standard error.

    Parameters
    ----------
    total : float
        Value at completion (end time [s], or number of variants).
    enabled : bool
        False for ``--quiet``.
    unit : str
        Unit shown after the numbers.
    delay : float
        Seconds before the bar first appears [s]; short runs never show it.
    stream : file, optional
        Where to draw; standard error by default. Nothing is drawn unless it is a terminal.
    """

    def __init__(self, total: float, *, enabled: bool = True, unit: str = "", delay: float = 1.0,
                 stream=None, width: int = 30):
        self.total = float(total) if total else 1.0
        self.stream = stream or sys.stderr
        self.enabled = enabled and hasattr(self.stream, "isatty") and self.stream.isatty()
        self.unit = unit
        self.delay = delay
        self.width = width
        self.start = time.perf_counter()
        self.drawn = False

    def __enter__(self) -> "ProgressBar":
        return self

    def __exit__(self, *exc) -> None:
        if self.drawn:
            self.stream.write("\n")
            self.stream.flush()

    def update(self, done: float, total: float | None = None) -> None:
        """Report progress ``done`` out of ``total`` (the constructor's total by default)."""
        if not self.enabled:
            return
        total = float(total) if total else self.total
        elapsed = time.perf_counter() - self.start
        if elapsed < self.delay:
            return
        frac = min(max(done / total, 0.0), 1.0)
        filled = int(round(frac * self.width))
        bar = "#" * filled + "-" * (self.width - filled)
        self.stream.write(f"\r[{bar}] {done:.4g}/{total:.4g} {self.unit} {elapsed:6.1f} s")
        self.stream.flush()
        self.drawn = True
