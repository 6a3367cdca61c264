"""What a long wait is doing and for how long: activities and steps on standard error.

A command of the command line reports within :func:`reporting` (``--quiet``: nothing at all);
outside it, in library use, every activity is silent. Code that may wait long opens an
:func:`activity` ("deriving the equations of motion of robot-arm-3d", "compiling ...") or, for a
loop of similar steps (the spin rates of a Campbell diagram, the mode counts of a convergence
study), :func:`steps`. Everything is written to standard error, never to a result file.

On a terminal an activity is one line that updates once per second (``flexkane: compiling ...
12 s``) and ends as ``... done in 31.2 s``. The updates come from a ticker thread, or, where the
wait is a loop of its own (waiting for a compiling child process, the chunks of an integration),
from :func:`tick` in that loop: ``thread=False``. A ticker thread runs only while its activity is
the innermost one and stops (joined) when the activity ends or a nested one begins, so no thread
outlives its phase and a process that forks (:mod:`flexkane.forking`) forks with none: the compile
forks of :mod:`flexkane.numerics.jit_module` run within a thread-less activity, and :func:`ticking`
lends it a thread only while the children run.

Elsewhere (a log, a pipe) an activity writes plain lines: its start line at once when it announces
a phase known to be long (``delay=0``: derivation, code generation and compilation, which happen
only when the cache lacks their result) and, when the activity took :data:`LONG` seconds or more,
an end line with the elapsed time; a phase that may be quick (``delay`` > 0: an integration, a
stage of a linearization) writes only that end line. A log thus shows every phase that took long
and short runs stay tidy; a step line is written once the steps have taken ``delay`` seconds.
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
import time
from collections.abc import Iterator

__all__ = ["Activity", "LONG", "ProgressBar", "Steps", "activity", "each_reported", "enabled", "reporting", "steps",
           "tick", "ticking"]

#: Seconds from which a finished activity leaves an end line on a non-terminal [s].
LONG = 2.0
_PREFIX = "flexkane: "
_BAR = 20   # characters of a progress bar (Activity.update)


class _Reporting:
    """Where and whether activities report (:func:`reporting`)."""

    def __init__(self, quiet: bool, stream, clock, interval: float):
        self.quiet = quiet
        self.stream = stream
        self.clock = clock
        self.interval = interval
        self.terminal = bool(getattr(stream, "isatty", None) and stream.isatty())
        self.lock = threading.Lock()   # one writer at a time: the main thread or a ticker
        self.open = None               # the activity whose terminal line is not ended yet


_reporting: list[_Reporting] = []
_clock = time.monotonic   # the default clock of reporting() [s]
_active: list["Activity"] = []


@contextlib.contextmanager
def reporting(quiet: bool = False, *, stream=None, clock=None, interval: float = 1.0) -> Iterator[None]:
    """Let activities within the block report (a command of the command line).

    Parameters
    ----------
    quiet : bool
        ``--quiet``: report nothing.
    stream : file, optional
        Where to write; standard error by default. Its ``isatty()`` chooses the terminal form.
    clock : callable, optional
        Seconds of a monotonic clock [s]; :func:`time.monotonic` by default (tests give a fake one).
    interval : float
        Seconds between updates of a terminal line [s].
    """
    _reporting.append(_Reporting(bool(quiet), stream or sys.stderr, clock or _clock, float(interval)))
    try:
        yield
    finally:
        _reporting.pop()


def _seconds(value: float) -> str:
    return f"{value:.1f} s"


class Activity:
    """One phase of a wait (module docstring); a context manager, see :func:`activity`.

    Parameters
    ----------
    text : str
        What is being done, e.g. ``compiling the right-hand side of robot-arm-3d``.
    delay : float
        Seconds before it is shown [s]; 0 for a phase known to take long.
    thread : bool
        Update a terminal line from a ticker thread (else from :func:`tick` and :meth:`update`).
    """

    def __init__(self, text: str, *, delay: float = LONG, thread: bool = True):
        self.text = text
        self.delay = float(delay)
        self.thread = thread
        self.detail = ""
        self.elapsed = 0.0
        self._settings = None
        self._shown = False       # terminal: drawn; else: its start line written
        self._drawn = -1          # terminal: the whole seconds last drawn
        self._length = 0          # terminal: the length of the line drawn
        self._ticker = None
        self._borrowed = False    # a thread lent by ticking()

    # ---------------------------------------------------------------- context
    def __enter__(self) -> "Activity":
        if not enabled():
            return self
        settings = self._settings = _reporting[-1]
        if _active:
            _active[-1]._stop_ticker()    # the innermost activity is the one shown
        _active.append(self)
        self._start = settings.clock()
        if self.delay <= 0:
            self._show(0.0)
        self._start_ticker()
        return self

    def __exit__(self, kind, value, traceback) -> None:
        settings = self._settings
        if settings is None:
            return
        try:
            self._stop_ticker()
        finally:
            _active.remove(self)
        self.elapsed = settings.clock() - self._start
        with settings.lock:
            if kind is not None:          # an error or a stop: end the line, the message follows
                if settings.open is self:
                    settings.stream.write("\n")
                    settings.open = None
            elif settings.terminal and self._shown:
                self._draw(f" ... done in {_seconds(self.elapsed)}", end=True)
            elif not settings.terminal and self.elapsed >= LONG and self.elapsed >= self.delay:
                settings.stream.write(f"{_PREFIX}{self.text}{self.detail} ... done in "
                                      f"{_seconds(self.elapsed)}\n")
            settings.stream.flush()
        if _active:
            _active[-1]._start_ticker()

    # ---------------------------------------------------------------- updates
    def tick(self) -> None:
        """Show the activity if its delay has passed; on a terminal, redraw the elapsed seconds."""
        settings = self._settings
        if settings is None:
            return
        elapsed = settings.clock() - self._start
        if elapsed < self.delay:
            return
        if not self._shown:
            self._show(elapsed)
        elif settings.terminal and int(elapsed) != self._drawn:
            with settings.lock:
                self._draw(f" ... {int(elapsed)} s")
                self._drawn = int(elapsed)
                settings.stream.flush()

    def update(self, done: float, total: float, unit: str = "") -> None:
        """Progress ``done`` of ``total`` (e.g. simulated time, ``unit`` "s"), shown after the text as
        a bar and ``done/total unit`` (on a terminal updated once per second) and in the end line."""
        filled = int(round(min(max(done / total if total else 1.0, 0.0), 1.0) * _BAR))
        self.detail = f" [{'#' * filled}{'-' * (_BAR - filled)}] {done:.4g}/{total:.4g}{' ' + unit if unit else ''}"
        self.tick()

    def _show(self, elapsed: float) -> None:
        settings = self._settings
        self._shown = True
        with settings.lock:
            if settings.terminal:
                self._draw(f" ... {int(elapsed)} s")
                self._drawn = int(elapsed)
            elif self.delay <= 0:          # a long phase announced: its start line at once
                settings.stream.write(f"{_PREFIX}{self.text} ...\n")
            settings.stream.flush()

    def _draw(self, tail: str, end: bool = False) -> None:
        """Rewrite this activity's terminal line, ``tail`` after the text (the caller holds the lock)."""
        settings = self._settings
        if settings.open is not None and settings.open is not self:
            settings.stream.write("\n")   # the other activity's line stays as it is
        line = f"{_PREFIX}{self.text}{self.detail}"
        width = _width(settings.stream)
        if width and len(line) + len(tail) >= width:    # one row: "\r" goes back to its start only
            line = line[:max(width - len(tail) - 4, len(_PREFIX))] + "..."
        text = f"{line}{tail}"
        previous = self._length if settings.open is self else 0
        self._length = len(text)
        settings.stream.write("\r" + text + " " * max(previous - len(text), 0) + ("\n" if end else ""))
        settings.open = None if end else self

    # ---------------------------------------------------------------- ticker thread
    def _start_ticker(self) -> None:
        if (self.thread or self._borrowed) and self._ticker is None and self._settings.terminal:
            stop = threading.Event()
            thread = threading.Thread(target=self._tick_until, args=(stop,), name="flexkane-progress",
                                      daemon=True)
            self._ticker = (thread, stop)
            thread.start()

    def _stop_ticker(self) -> None:
        if self._ticker is not None:
            thread, stop = self._ticker
            stop.set()
            thread.join()
            self._ticker = None

    def _tick_until(self, stop: threading.Event) -> None:
        while not stop.wait(self._settings.interval):
            self.tick()


def _width(stream) -> int | None:
    """Columns of the terminal behind ``stream``, or None."""
    try:
        return os.get_terminal_size(stream.fileno()).columns
    except (AttributeError, OSError, ValueError):
        return None


def activity(text: str, *, delay: float = LONG, thread: bool = True) -> Activity:
    """An :class:`Activity` (a context manager): ``with activity("deriving ...", delay=0): ...``.

    Parameters
    ----------
    text : str
        What is being done.
    delay : float
        Seconds before it is shown [s] (default :data:`LONG`); 0 for a phase known to take long,
        whose start line a non-terminal then gets at once.
    thread : bool
        On a terminal, update the line from a ticker thread; False where a loop calls :func:`tick`
        (or :meth:`Activity.update`) instead, e.g. around a fork.
    """
    return Activity(text, delay=delay, thread=thread)


def enabled() -> bool:
    """Whether an activity opened now would report (within :func:`reporting`, not quiet, in the main
    thread: the work of other threads, e.g. a pool's, is not shown)."""
    return bool(_reporting) and not _reporting[-1].quiet and threading.current_thread() is threading.main_thread()


def tick() -> None:
    """Let the innermost activity update its line (from a loop that waits: cheap, at any rate)."""
    if _active:
        _active[-1].tick()


@contextlib.contextmanager
def ticking() -> Iterator[None]:
    """Update the innermost activity from a ticker thread within the block, even if it was opened
    with ``thread=False`` (e.g. once the compiling children are forked, while this process works)."""
    current = _active[-1] if _active else None
    if current is None or current._borrowed:
        yield
        return
    current._borrowed = True
    current._start_ticker()
    try:
        yield
    finally:
        current._borrowed = False
        if not current.thread:
            current._stop_ticker()


class Steps:
    """A loop of similar steps (:func:`steps`), a context manager: one line per finished step (``k/N``,
    what it was, its time and the time so far) once the steps have taken ``delay`` seconds.

    Parameters
    ----------
    text : str
        What the steps make, e.g. ``Campbell diagram of spin-up``.
    total : int
        Number of steps.
    delay : float
        Seconds of steps before the first line [s]: quick loops stay silent.
    """

    def __init__(self, text: str, total: int, *, delay: float = LONG):
        self.text = text
        self.total = int(total)
        self.delay = float(delay)
        self.count = 0
        self._settings = None

    def __enter__(self) -> "Steps":
        if enabled():
            self._settings = _reporting[-1]
            self._start = self._last = self._settings.clock()
        return self

    def __exit__(self, *exc) -> None:
        self._settings = None

    def done(self, what: str) -> None:
        """Report one finished step, e.g. ``Omega = 2.5 rad/s``."""
        self.count += 1
        settings = self._settings
        if settings is None:
            return
        now = settings.clock()
        step, total = now - self._last, now - self._start
        self._last = now
        if total < self.delay:
            return
        with settings.lock:
            if settings.open is not None:      # an activity's terminal line: it stays as it is
                settings.stream.write("\n")
                settings.open = None
            settings.stream.write(f"{_PREFIX}{self.text}: {self.count}/{self.total}, {what} "
                                  f"({_seconds(step)}; {_seconds(total)} so far)\n")
            settings.stream.flush()


def steps(text: str, total: int, *, delay: float = LONG) -> Steps:
    """:class:`Steps` (a context manager): ``with steps("Campbell diagram of spin-up", 33) as s: ...
    s.done("Omega = 0.5 rad/s")``."""
    return Steps(text, total, delay=delay)


def each_reported(values, text: str, each) -> Iterator:
    """``values`` one by one, each reported when it is done (a :class:`Steps` line: ``k/N``,
    ``each.format(value)``, or ``each(value)`` for a function, and its time), e.g. ``for spin in
    each_reported(spins, "Campbell diagram of spin-up", "Omega = {:g} rad/s")``."""
    with steps(text, len(values)) as progress:
        for value in values:
            yield value
            progress.done(each(value) if callable(each) else each.format(value))


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
