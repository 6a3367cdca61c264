"""Figures drawn by two processes: this one and a fork of it, on the second core.

Drawing a figure with matplotlib (text layout, rasterizing, PNG encoding) takes Python's one core
for about 70 ms; a run writes ten to a hundred of them. :func:`draw_in_two` gives every other
figure to a fork of the process (which has matplotlib and the results loaded already) and draws
the others here. Each figure is drawn by the same code and written atomically either way, so the
files are the same bytes as when one process draws them all.

An exception in the fork (a figure that cannot be drawn) is sent back through a pipe and raised
here as :class:`PlotWorkerError`, with the fork's traceback, after this process has finished its
own figures: the files both completed stay. A signal (Ctrl-C, SIGTERM) stops both, whichever of
them receives it (:class:`KeyboardInterrupt` here): the fork's atomic writes remove their
temporary files as this process's do.
"""

from __future__ import annotations

import os
import signal
import sys
import traceback
from pathlib import Path

__all__ = ["PlotWorkerError", "draw_in_two"]

#: Longest traceback text [bytes] the fork sends back.
_MAX_REPORT = 16000
#: Exit status of a fork stopped by a signal (SIGINT, SIGTERM).
_STOPPED = 130


class PlotWorkerError(RuntimeError):
    """A figure could not be drawn in the fork that draws part of the plots (its traceback included)."""


def _interrupt(signum, frame):
    raise KeyboardInterrupt


def _worker(jobs: list, shared, report: int) -> None:
    """The fork: draw ``jobs``; on an exception write its traceback to the pipe ``report``; never
    returns (exit status 0 when every figure was written)."""
    status = 1
    try:
        if signal.getsignal(signal.SIGTERM) in (signal.SIG_DFL, None):   # stopped as Ctrl-C stops it
            signal.signal(signal.SIGTERM, _interrupt)
        figure = shared()
        for _, draw in jobs:
            draw(figure)
        status = 0
    except KeyboardInterrupt:   # a signal: the parent stops as if it had received it
        status = _STOPPED
    except BaseException:   # noqa: BLE001 - everything goes back to the parent, which raises it
        try:
            os.write(report, traceback.format_exc().encode("utf-8", "replace")[-_MAX_REPORT:])
        except OSError:
            pass
    finally:
        os._exit(status)


def _read_all(fd: int) -> bytes:
    chunks = []
    while chunk := os.read(fd, 65536):
        chunks.append(chunk)
    return b"".join(chunks)


def draw_in_two(jobs: list, shared) -> list[Path]:
    """Run the figure ``jobs`` in this process and a fork of it, every other one each.

    Parameters
    ----------
    jobs : list of (pathlib.Path, callable)
        Each figure's file and the function that draws and writes it, given the figure object that
        the jobs of one process may share (``shared()``, made once in each process).
    shared : callable
        Makes the shared figure object of a process (no arguments).

    Returns
    -------
    list of pathlib.Path
        The files written, in the order of ``jobs``.

    Raises
    ------
    PlotWorkerError
        When the fork failed to draw a figure (after this process has drawn its own).
    """
    here, there = jobs[0::2], jobs[1::2]
    read, write = os.pipe()
    sys.stdout.flush()
    sys.stderr.flush()
    pid = os.fork()
    if pid == 0:
        os.close(read)
        _worker(there, shared, write)
    os.close(write)
    finished = False
    try:
        figure = shared()
        mine = [draw(figure) for _, draw in here]
        report = _read_all(read)   # end of file when the fork exits
        _, code = os.waitpid(pid, 0)
        finished = True
    finally:
        os.close(read)
        if not finished:   # an exception or a signal here: stop the fork, which cleans up after itself
            try:
                os.kill(pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
            os.waitpid(pid, 0)
    if os.waitstatus_to_exitcode(code) == _STOPPED:
        raise KeyboardInterrupt   # the fork was stopped (by a signal sent to it alone): so is this process
    if os.waitstatus_to_exitcode(code) != 0:
        text = report.decode("utf-8", "replace").strip() or f"exit status {os.waitstatus_to_exitcode(code)}"
        raise PlotWorkerError(f"a figure could not be drawn in the second plotting process; {len(mine)} of "
                              f"{len(jobs)} figures were written by this one. Its error:\n{text}")
    return [path for path, _ in jobs]
