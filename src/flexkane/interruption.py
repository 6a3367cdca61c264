"""Stop requests: SIGINT (Ctrl-C) and SIGTERM during a command.

A command installs one :class:`StopRequest` for its whole duration. In ordinary Python code (the
derivation, the code generation, waiting for a compilation) the first signal raises
:class:`KeyboardInterrupt` at once, which the command line turns into exit code 130. Where an
exception must not land at an arbitrary point, the signal is *deferred*: inside
:meth:`StopRequest.deferred` (writing the results, starting or closing a Dask cluster) or during the
integration (the compiled integrator cannot be interrupted; the progress callback between its
chunks calls :meth:`StopRequest.check`), the request is recorded and honoured at the next check.
Only the first signal acts; later ones, while the command is cleaning up, are recorded and ignored.

Python runs a signal handler between any two bytecodes of the main thread, also inside a finalizer
(``__del__``, a weak reference's callback) that the garbage collector happens to run at that moment.
An exception raised there cannot propagate: Python would print it as "Exception ignored in ..." with
a traceback and go on. While a :class:`StopRequest` is active, such a lost :class:`KeyboardInterrupt`
is silenced and raised again in the main thread's own code (:func:`_thread.interrupt_main`, called
from a thread that ends at once).
"""

from __future__ import annotations

import _thread
import contextlib
import signal
import sys
import threading
from collections.abc import Iterator

__all__ = ["StopRequest", "deferred_signals", "held_signals", "SIGNALS"]

#: Signals that request a stop.
SIGNALS = (signal.SIGINT, signal.SIGTERM)

_active: list["StopRequest"] = []


class StopRequest:
    """Handler of :data:`SIGNALS` for the duration of a command (a context manager).

    Attributes
    ----------
    signum : int or None
        The first signal received, or None.

    Notes
    -----
    Installed only in the main thread (Python delivers signals there); elsewhere the context
    manager does nothing and :meth:`check` never raises.
    """

    def __init__(self):
        self.signum = None
        self._deferred = 0
        self._previous = {}
        self._previous_hook = None
        self._again = False     # a KeyboardInterrupt lost in a finalizer: raise it again

    @property
    def requested(self) -> bool:
        """Whether a stop was requested."""
        return self.signum is not None

    def __call__(self, signum, frame):
        first = self.signum is None
        if first:
            self.signum = signum
        again, self._again = self._again, False
        if (first or again) and self._deferred == 0:
            raise KeyboardInterrupt

    def _unraisable(self, unraisable) -> None:
        """``sys.unraisablehook`` while active: a :class:`KeyboardInterrupt` of this request that a
        finalizer swallowed is raised again in the main thread, silently; anything else is reported
        as before."""
        if issubclass(unraisable.exc_type, KeyboardInterrupt) and self.signum is not None:
            self._again = True
            # this handler again, from a short-lived thread: a signal made here would be handled at once,
            # inside this hook, and lost again. The low-level start does not wait for the thread, which
            # runs once this thread yields the interpreter, so the main thread handles it at a bytecode
            # of its own (should the finalizer still run then, this repeats until it ends)
            _thread.start_new_thread(_thread.interrupt_main, (signal.SIGINT,))
            return
        self._previous_hook(unraisable)

    def __enter__(self) -> "StopRequest":
        if threading.current_thread() is threading.main_thread():
            self._previous = {sig: signal.signal(sig, self) for sig in SIGNALS}
            self._previous_hook, sys.unraisablehook = sys.unraisablehook, self._unraisable
            _active.append(self)
        return self

    def __exit__(self, *exc) -> None:
        if self._previous:
            for sig, handler in self._previous.items():
                signal.signal(sig, handler)
            self._previous = {}
            sys.unraisablehook, self._previous_hook = self._previous_hook, None
            _active.remove(self)

    @contextlib.contextmanager
    def deferred(self) -> Iterator["StopRequest"]:
        """Record signals instead of raising within the block; :meth:`check` afterwards honours them."""
        self._deferred += 1
        try:
            yield self
        finally:
            self._deferred -= 1

    def check(self) -> None:
        """Raise :class:`KeyboardInterrupt` if a stop was requested."""
        if self.signum is not None:
            raise KeyboardInterrupt


@contextlib.contextmanager
def deferred_signals() -> Iterator[None]:
    """Defer :data:`SIGNALS` within the block, then honour a request received meanwhile.

    Under an active :class:`StopRequest`, the block is one of its deferred sections and a request
    raises :class:`KeyboardInterrupt` at the end of the block. Without one (library use, main
    thread), a temporary handler records the signal, the previous handlers come back at the end,
    and the signal is raised again then (so SIGTERM keeps its default action). Not in the main
    thread: the block runs as is.

    Raises
    ------
    KeyboardInterrupt
        At the end of the block, if a signal came during it (under a :class:`StopRequest`, or a
        SIGINT with Python's default handler).
    """
    if _active:
        request = _active[-1]
        with request.deferred():
            yield
        request.check()
        return
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    request = StopRequest()
    with request, request.deferred():
        yield
    if request.signum is not None:
        signal.raise_signal(request.signum)


@contextlib.contextmanager
def held_signals() -> Iterator[None]:
    """Hold a stop request within the block, for the few statements that must not be cut (creating
    and removing a temporary file, a rename), under an active :class:`StopRequest`.

    A signal received within the block raises :class:`KeyboardInterrupt` at its end, unless an
    enclosing section defers signals (then that section's check honours it). Without an active
    :class:`StopRequest` this does nothing.
    """
    if not _active:
        yield
        return
    request = _active[-1]
    before = request.signum
    with request.deferred():
        yield
    if before is None and request.signum is not None and request._deferred == 0:
        raise KeyboardInterrupt
