"""Atomic output files and the output directory.

A file flexkane writes appears complete or not at all: the data go to a temporary file in the
same directory, which is flushed, synced to disk and then renamed over the target with
:func:`os.replace` (atomic on POSIX and Windows within one file system). If anything fails
before the rename, the temporary file is removed and a previous version of the target is left
untouched. A symbolic link at the target is replaced by a regular file. Under a command's
:class:`~flexkane.interruption.StopRequest`, a signal cannot cut the creation or the removal of the
temporary file or the rename: an interruption leaves no temporary file behind.

Durability takes two syncs and no more: the file's data before the rename (else a crash could
leave the new name on an empty or partial file) and the directory after it (else a crash could
lose the rename itself). A batch of files (:func:`directory_syncs_batched`, a run's outputs) syncs
each file's data as it is written and each directory once, at the end of the batch.
"""

from __future__ import annotations

import contextlib
import os
import pathlib
import tempfile
import threading
from collections.abc import Iterator
from typing import IO

from .errors import ModelError
from .interruption import held_signals

__all__ = ["OutputExistsError", "atomic_write_bytes", "atomic_write_text", "atomic_writer",
           "directory_syncs_batched", "prepare_output_dir"]

_MODES = ("wb", "w", "path")
_UMASK_LOCK = threading.Lock()
_BATCH = threading.local()   # .directories: the directories of the open batch whose sync is due


class OutputExistsError(ModelError):
    """The output directory already holds files and overwriting was not asked for.

    Parameters
    ----------
    directory : str or os.PathLike
        The directory given with ``--out``.
    """

    def __init__(self, directory: str | os.PathLike):
        super().__init__("--out", "a new or empty directory (or --force to overwrite)",
                         str(directory))


def _default_file_mode() -> int:
    """Permissions of a newly created file under the current umask (0o666 & ~umask)."""
    with _UMASK_LOCK:
        umask = os.umask(0o022)
        os.umask(umask)
    return 0o666 & ~umask


def _sync_directory(directory: pathlib.Path) -> None:
    """Make a rename in ``directory`` durable, where the platform allows it."""
    with contextlib.suppress(OSError, AttributeError):
        handle = os.open(directory, os.O_RDONLY)
        try:
            os.fsync(handle)
        finally:
            os.close(handle)


def _renamed_in(directory: pathlib.Path) -> None:
    """A file was renamed into ``directory``: sync it now, or at the end of the open batch."""
    pending = getattr(_BATCH, "directories", None)
    if pending is None:
        _sync_directory(directory)
    else:
        pending.setdefault(os.path.abspath(directory), directory)


@contextlib.contextmanager
def directory_syncs_batched() -> Iterator[None]:
    """Sync each directory written into once, when the block ends, instead of after every file.

    Each file's data are still synced before its rename (a file appears complete or not at all);
    only the durability of the renames waits for the end of the block, which syncs every directory
    a file was renamed into, also when the block ends by an exception. A nested block belongs to
    the outermost one.
    """
    if getattr(_BATCH, "directories", None) is not None:
        yield
        return
    _BATCH.directories = directories = {}
    try:
        yield
    finally:
        _BATCH.directories = None
        for directory in directories.values():
            _sync_directory(directory)


@contextlib.contextmanager
def atomic_writer(path: str | os.PathLike, mode: str = "wb", *,
                  encoding: str = "utf-8") -> Iterator[IO | pathlib.Path]:
    """Write a file through a temporary file renamed over ``path`` on success only.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write; its directory must exist.
    mode : {"wb", "w", "path"}
        ``"wb"`` yields a binary file object, ``"w"`` a text file object (``encoding``),
        ``"path"`` the :class:`pathlib.Path` of the temporary file for libraries that open the
        file themselves; its name ends with the suffix of ``path`` (so ``np.savez`` and
        ``savefig`` keep it and infer the format from it).
    encoding : str
        Encoding of text mode.

    Yields
    ------
    file object or pathlib.Path
        Where to write.

    Examples
    --------
    >>> with atomic_writer(directory / "figure.png") as handle:   # doctest: +SKIP
    ...     figure.savefig(handle, format="png")
    """
    if mode not in _MODES:
        raise ValueError(f"mode must be one of {_MODES}, not {mode!r}")
    target = pathlib.Path(path)
    handle = temporary = None
    try:
        with held_signals():  # a signal here is raised at the end of the block, inside the try
            handle = tempfile.NamedTemporaryFile(
                mode="w" if mode == "w" else "wb", encoding=encoding if mode == "w" else None,
                dir=target.parent, prefix=f".{target.name}.", suffix=f".tmp{target.suffix}",
                delete=False)
            temporary = pathlib.Path(handle.name)
        if mode == "path":
            handle.close()
            yield temporary
            with open(temporary, "rb") as written:
                os.fsync(written.fileno())
        else:
            with handle:
                yield handle
                handle.flush()
                os.fsync(handle.fileno())
        with held_signals():
            os.chmod(temporary, _default_file_mode())
            os.replace(temporary, target)
    except BaseException:
        with held_signals():
            if handle is not None:
                handle.close()
            if temporary is not None:
                with contextlib.suppress(OSError):
                    temporary.unlink()
        raise
    _renamed_in(target.parent)


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> pathlib.Path:
    """Write ``data`` to ``path`` atomically; return the path.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write; its directory must exist.
    data : bytes
        The content.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    with atomic_writer(path, "wb") as handle:
        handle.write(data)
    return pathlib.Path(path)


def atomic_write_text(path: str | os.PathLike, text: str, *, encoding: str = "utf-8") -> pathlib.Path:
    """Write ``text`` to ``path`` atomically (``encoding``, newlines as given); return the path.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write; its directory must exist.
    text : str
        The content.
    encoding : str
        Text encoding.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    return atomic_write_bytes(path, text.encode(encoding))


def prepare_output_dir(path: str | os.PathLike, *, force: bool) -> pathlib.Path:
    """Create the output directory, or accept an existing one that is empty.

    Parameters
    ----------
    path : str or os.PathLike
        The directory given with ``--out``; missing parents are created.
    force : bool
        Accept a non-empty directory. Its other files are kept; the files flexkane writes
        replace those of the same name.

    Returns
    -------
    pathlib.Path
        The directory.

    Raises
    ------
    OutputExistsError
        If the directory holds files and ``force`` is false.
    ModelError
        If ``path`` is an existing file or the directory cannot be created.
    """
    directory = pathlib.Path(path)
    if directory.is_dir():
        if not force and any(directory.iterdir()):
            raise OutputExistsError(directory)
        return directory
    if directory.exists():
        raise ModelError("--out", "a directory", str(directory), "a file of that name exists")
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ModelError("--out", "a directory that can be created", str(directory),
                         exc.strerror or str(exc)) from None
    return directory
