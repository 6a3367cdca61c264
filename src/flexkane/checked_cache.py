"""Cache files that carry their digest: written with it, checked against it before use.

Every file flexkane keeps in its cache (derived equations, generated code, run manifests, numbers,
the compiled modules and Numba's index and machine code of flexkane's functions) is written through
:func:`write_checked` and read through :func:`read_checked`. Beside each file ``<name>`` lies
``<name>.sha256``: the SHA-256 digests (64 hex digits a line) of the contents written to that path.
A file is used only if the digest of its bytes is among them; otherwise (a changed or truncated
file, or no digest at all) it is deleted, the caller makes it again, and a note names the file once
per process and kind of file.

The digest of a content is appended to the list *before* the content replaces the file (atomically,
:func:`flexkane.atomic.atomic_write_bytes`), so that a process reading while another writes never
sees a content whose digest is not listed: two processes may write the same path at once (two
compiling children save the same function's index) without a false alarm. The list is kept short
(:data:`MAX_DIGESTS`).

What this protects against: damage (a disk or a copy that changed or cut a file, a file edited by
mistake). Not against an attacker who can write to the cache directory: such a person can write a
matching digest as well. Pickles among the cache files are still only ever read from the user's own
cache, after their digest matched.
"""

from __future__ import annotations

import hashlib
import os
import re
import sys
from pathlib import Path

from .atomic import atomic_write_bytes

__all__ = ["MAX_DIGESTS", "SUFFIX", "digest_path", "discard", "note_damage", "read_checked", "write_checked"]

#: Suffix of the file that lists the digests of a cache file.
SUFFIX = ".sha256"
#: Digests kept in a list: beyond this, a write starts a new list with its own digest alone.
MAX_DIGESTS = 16
_DIGEST = re.compile(r"[0-9a-f]{64}")
_noted: set = set()   # (what, remedy) of the notes printed by this process


def digest_path(path: str | os.PathLike) -> Path:
    """The file that lists the digests of the cache file ``path`` (``<path>.sha256``)."""
    path = Path(path)
    return path.with_name(path.name + SUFFIX)


def _digests(path: Path) -> set[str] | None:
    """The digests listed for ``path``; None when there is no list."""
    try:
        text = digest_path(path).read_bytes().decode("ascii", errors="replace")
    except FileNotFoundError:
        return None
    except OSError:
        return set()
    return {line for line in text.split() if _DIGEST.fullmatch(line)}


def _list_digest(path: Path, digest: str) -> None:
    """Add ``digest`` to the list of ``path`` (one append of one line: atomic on a local file system)."""
    listed = _digests(path)
    if listed is not None and digest in listed:
        return
    if listed is not None and len(listed) >= MAX_DIGESTS:
        atomic_write_bytes(digest_path(path), f"{digest}\n".encode("ascii"))
        return
    handle = os.open(digest_path(path), os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o666)
    try:   # a leading newline: a list cut in the middle of a line does not spoil this one
        os.write(handle, f"\n{digest}\n".encode("ascii"))
    finally:
        os.close(handle)


def write_checked(path: str | os.PathLike, data: bytes) -> Path:
    """Write a cache file atomically, its digest listed beside it first.

    Parameters
    ----------
    path : str or os.PathLike
        The cache file, in an existing directory; ``<path>.sha256`` gets the digest of ``data``.
    data : bytes
        What the file is to hold.

    Returns
    -------
    pathlib.Path
        The cache file's path.

    Raises
    ------
    OSError
        When the file or its digest cannot be written (a read-only cache: the caller decides
        whether that matters).
    """
    path = Path(path)
    _list_digest(path, hashlib.sha256(data).hexdigest())
    return atomic_write_bytes(path, data)


def discard(path: str | os.PathLike) -> None:
    """Delete a cache file and its list of digests (what is missing is ignored)."""
    for target in (Path(path), digest_path(path)):
        try:
            target.unlink()
        except OSError:
            pass


def note_damage(path: str | os.PathLike, what: str, reason: str, remedy: str) -> None:
    """Print, once per process for each ``what`` and ``remedy``, that a cache file was damaged.

    Parameters
    ----------
    path : str or os.PathLike
        The file (named in the note).
    what : str
        What the file holds, e.g. ``"the equations of this model structure"``.
    reason : str
        How it was found damaged, e.g. ``"digest mismatch"``.
    remedy : str
        What flexkane does instead, e.g. ``"derived again"``.
    """
    if (what, remedy) in _noted:
        return
    _noted.add((what, remedy))
    print(f"flexkane: note: damaged cache file {path} ({what}: {reason}); {remedy}", file=sys.stderr)


def read_checked(path: str | os.PathLike, what: str, remedy: str) -> bytes | None:
    """The content of a cache file whose digest is listed beside it; None if it is missing or damaged.

    Parameters
    ----------
    path : str or os.PathLike
        The cache file.
    what : str
        What the file holds, for the note (see :func:`note_damage`).
    remedy : str
        What the caller does when None is returned, for the note.

    Returns
    -------
    bytes or None
        The content, verified; None when the file is missing or unreadable (no note) or when its
        digest is not listed (a changed or truncated file, or no list at all): then the file and
        its list are deleted and a note is printed (once per ``what`` and ``remedy``).
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError:
        return None
    listed = _digests(path)
    if listed is not None and hashlib.sha256(data).hexdigest() in listed:
        return data
    discard(path)
    note_damage(path, what, "no digest" if listed is None else "digest mismatch", remedy)
    return None
