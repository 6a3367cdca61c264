"""Stop requests (flexkane.interruption): a signal whose KeyboardInterrupt a finalizer would swallow.

Python runs a signal handler at the next bytecode of the main thread, also inside a ``__del__`` that
the garbage collector runs at that moment; the exception raised there cannot propagate and Python
prints "Exception ignored in ..." with a traceback. Under a StopRequest it is raised again in the
main thread's own code, and nothing is printed.
"""

import os
import signal
import sys

import pytest

from flexkane.interruption import StopRequest


class SignalsWhenCollected:
    """An object whose finalizer sends SIGINT to this process and runs on, so that the handler runs
    inside the finalizer."""

    def __del__(self):
        os.kill(os.getpid(), signal.SIGINT)
        for _ in range(1000):     # bytecodes inside the finalizer: the handler runs among them
            pass


def test_a_stop_request_lost_in_a_finalizer_is_raised_again_in_the_main_code_without_a_traceback(capsys):
    reached = []   # iterations of the main code between the finalizer and the stop
    with pytest.raises(KeyboardInterrupt):
        with StopRequest() as stop:
            obj = SignalsWhenCollected()
            del obj
            for _ in range(10**8):
                reached.append(1)
    assert stop.signum == signal.SIGINT
    assert len(reached) < 10**8              # raised again after the finalizer, not at the end
    assert capsys.readouterr().err == ""


def test_other_unraisable_exceptions_are_reported_as_before(monkeypatch):
    class Fails:
        def __del__(self):
            raise ValueError("a finalizer's own error")

    reported = []
    monkeypatch.setattr(sys, "unraisablehook", lambda unraisable: reported.append(unraisable.exc_type))
    with StopRequest():
        obj = Fails()
        del obj
    assert reported == [ValueError]


def test_the_unraisable_hook_is_restored_when_the_request_ends():
    before = sys.unraisablehook
    with StopRequest():
        assert sys.unraisablehook is not before
    assert sys.unraisablehook is before


def test_a_later_signal_while_cleaning_up_is_still_ignored():
    with pytest.raises(KeyboardInterrupt):
        with StopRequest() as stop:
            try:
                os.kill(os.getpid(), signal.SIGTERM)
                for _ in range(1000):
                    pass
            except KeyboardInterrupt:
                os.kill(os.getpid(), signal.SIGINT)      # a second signal while cleaning up: ignored
                for _ in range(1000):
                    pass
                raise
    assert stop.signum == signal.SIGTERM
