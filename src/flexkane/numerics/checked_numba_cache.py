"""Numba's on-disk cache of flexkane's functions, each file checked against its digest before it is loaded.

Numba keeps the machine code of an ``@njit(cache=True)`` function in two kinds of pickles beside
its source (``__pycache__``): an index (``<function>.nbi``: which data file holds which signature)
and the data (``<function>.<n>.nbc``). A truncated or changed file made the first call raise
``UnpicklingError`` (or ``EOFError``, ...) as a traceback, or could load damaged machine code.
:func:`guard` makes a dispatcher's cache write these files through
:func:`flexkane.checked_cache.write_checked` (a digest listed beside each one) and read them through
:func:`flexkane.checked_cache.read_checked`: a damaged index or data file, or one without a digest,
is deleted before anything in it is unpickled, a note names it, and Numba compiles the function
again (and stores it, checked). A failure to unpickle a file whose digest matched is treated the
same way.

The generated modules (:func:`flexkane.numerics.jit_module.build_module`) and the package's
integrator loops and linear algebra (:mod:`~flexkane.numerics.dop853`,
:mod:`~flexkane.numerics.radau`, :mod:`~flexkane.numerics.linear_algebra`,
:mod:`~flexkane.numerics.mass_assembly`) guard their functions; Numba's caches of other code are
left as they are.

This reaches into Numba's cache classes (``numba.core.caching.IndexDataCacheFile``: ``_load_index``,
``_load_data``, ``_open_for_write``, ``_data_path``; a dispatcher's ``_cache._cache_file`` and
``_cache._index_key``), checked with Numba 0.68 (``pyproject.toml`` keeps Numba below 0.69 until a newer
one is checked): :func:`guard` checks that they are there with the expected arguments and otherwise
leaves the dispatcher as it is (:func:`available` says which); files then carry no digests and are
not checked.
"""

from __future__ import annotations

import contextlib
import functools
import inspect
import io
import pickle
from pathlib import Path

from flexkane.checked_cache import discard, note_damage, read_checked, write_checked

__all__ = ["available", "entry_intact", "files_intact", "guard", "guard_namespace"]

_REMEDY = "compiled again"
#: Exceptions of a file that unpickles badly (its digest matched, yet it is not Numba's).
_UNPICKLING = (EOFError, ValueError, TypeError, AttributeError, ImportError, IndexError, KeyError,
               MemoryError, pickle.UnpicklingError)


def _what(path: str) -> str:
    """What a file of Numba's cache holds, by module (one note per module): ``dop853.dop853_chunk-218.py311.nbi``
    is Numba's compiled code of ``dop853``."""
    return f"Numba's compiled code of {Path(path).name.split('.')[0]}"


def _load_checked(path: str, load, nothing):
    """``load()`` (Numba's unpickling of the file at ``path``) when the file matches its digest, else
    ``nothing``; a file that fails to unpickle all the same is deleted too. Either is noted."""
    if read_checked(path, _what(path), _REMEDY) is None:
        return nothing
    try:
        return load()
    except _UNPICKLING as exc:
        discard(path)
        note_damage(path, _what(path), type(exc).__name__, _REMEDY)
        return nothing


def _checked_class():
    """The subclass of Numba's ``IndexDataCacheFile`` whose files carry digests; None if Numba differs."""
    try:
        from numba.core.caching import IndexDataCacheFile
    except ImportError:
        return None
    expected = {"_load_index": ["self"], "_load_data": ["self", "name"], "_open_for_write": ["self", "filepath"],
                "_data_path": ["self", "name"]}
    for name, arguments in expected.items():
        method = getattr(IndexDataCacheFile, name, None)
        if method is None or list(inspect.signature(method).parameters) != arguments:
            return None

    class CheckedIndexDataCacheFile(IndexDataCacheFile):
        """Numba's index and data files, written with their digests and checked before unpickling."""

        def _load_index(self):
            return _load_checked(self._index_path, super()._load_index, {})

        def _load_data(self, name):   # None: Numba's load() returns it and the function is compiled again
            return _load_checked(self._data_path(name), functools.partial(super()._load_data, name), None)

        @contextlib.contextmanager
        def _open_for_write(self, filepath):
            buffer = io.BytesIO()
            yield buffer
            write_checked(filepath, buffer.getvalue())

    return CheckedIndexDataCacheFile


_CHECKED = _checked_class()


def available() -> bool:
    """Whether this Numba's cache classes are those :func:`guard` was written for."""
    return _CHECKED is not None


def guard(dispatcher) -> bool:
    """Check the on-disk cache files of one Numba function against their digests (idempotent).

    Parameters
    ----------
    dispatcher : numba dispatcher
        An ``@njit(cache=True)`` function, before or after its first call.

    Returns
    -------
    bool
        Whether its cache files are now written with digests and checked before loading (False for
        a function without an on-disk cache, or when this Numba differs: then nothing is changed).
    """
    cache_file = getattr(getattr(dispatcher, "_cache", None), "_cache_file", None)
    if _CHECKED is None or cache_file is None:
        return False
    if not isinstance(cache_file, _CHECKED):
        if type(cache_file) is not _CHECKED.__mro__[1]:
            return False       # a cache of another kind: left alone
        cache_file.__class__ = _CHECKED     # same state, checked loading and writing
    return True


def guard_namespace(namespace: dict) -> int:
    """:func:`guard` every Numba function with an on-disk cache among the values of ``namespace``.

    Parameters
    ----------
    namespace : dict
        A module's ``globals()`` or ``__dict__``.

    Returns
    -------
    int
        How many functions are guarded.
    """
    from numba.core.dispatcher import Dispatcher

    return sum(guard(value) for value in list(namespace.values()) if isinstance(value, Dispatcher))


def entry_intact(dispatcher, types: tuple) -> bool:
    """Whether Numba's disk cache holds an intact entry of a guarded function for the argument ``types``.

    Parameters
    ----------
    dispatcher : numba dispatcher
        A function given to :func:`guard`.
    types : tuple of numba types
        The argument types of the call.

    Returns
    -------
    bool
        True when the index names a data file for the call and both files match their digests (a call
        loads rather than compiles); False otherwise: a damaged file is deleted, with a note, so that
        the caller compiles it again (in a child process, see :mod:`flexkane.numerics.jit_module`).
    """
    cache = dispatcher._cache
    cache_file = cache._cache_file
    name = cache_file._load_index().get(cache._index_key(types, dispatcher.targetctx.codegen()))
    if name is None:
        return False
    if _CHECKED is None or not isinstance(cache_file, _CHECKED):
        return True     # no digests to check
    path = cache_file._data_path(name)
    return read_checked(path, _what(path), _REMEDY) is not None


def files_intact(source: Path) -> bool:
    """Whether Numba's cache files beside the module at ``source`` (its ``__pycache__``) match their digests.

    Parameters
    ----------
    source : pathlib.Path
        A generated module's file, whose functions are guarded.

    Returns
    -------
    bool
        False when a file was damaged (it is deleted, with a note) so that the module's functions are
        compiled again before they are imported; True otherwise (no file at all included, or when this
        Numba's cache classes differ and files carry no digests).
    """
    if _CHECKED is None:
        return True
    intact = True
    for path in sorted((source.parent / "__pycache__").glob(f"{source.stem}.*.nb[ic]")):
        intact = read_checked(path, _what(str(path)), _REMEDY) is not None and intact
    return intact
