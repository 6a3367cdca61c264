"""Whether this process may fork a worker: a copy of itself that shares what it has loaded already.

A fork is safe while one thread runs (a lock held by another thread would stay locked in the copy
forever); on Linux only (macOS's system libraries are not fork-safe, Windows has no fork).
"""

from __future__ import annotations

import os
import sys
import threading

__all__ = ["fork_allowed"]


def fork_allowed() -> bool:
    """Whether a worker may be a fork of this process: Linux, and no other Python thread.

    Returns
    -------
    bool
    """
    return (sys.platform.startswith("linux") and hasattr(os, "fork") and threading.active_count() == 1
            and threading.current_thread() is threading.main_thread())
