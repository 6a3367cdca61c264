"""Write a generated module to the cache directory and import it (Numba on-disk cache).

A generated module is one Python file: imports, the linear-algebra template and the generated
fragments (``rhs``, ``system_rhs``, ``outputs``). The integrator loops are not in it: they are
functions of the package (:mod:`~flexkane.numerics.dop853`, :mod:`~flexkane.numerics.radau`),
compiled once per installation into the package's own Numba cache, that take the module's
``system_rhs`` as a first-class function (:mod:`~flexkane.numerics.system_function`); a new model
structure compiles only its own functions. Every Numba function in the module is
``@njit(cache=True)``, so Numba stores the machine code beside the file
(``<cache_dir>/<key>/__pycache__``) and a later process importing the same key loads it instead
of compiling (Numba's typing of scalar arithmetic is memoized for these compiles,
:mod:`~flexkane.numerics.scalar_typing`). Numba checks the file's source, so the file is written only
when it is missing or different, through a temporary file and ``os.replace`` (atomic): two
processes building the same key at once both end up with a complete, identical file. The file is
compared with the text it must hold again just before it is imported (a different file is noted and
written again), and Numba's index and machine code of its functions are checked against their digests
before they are loaded (:mod:`~flexkane.numerics.checked_numba_cache`): a damaged cache is compiled
again, with a note, instead of raising or loading damaged code.

The cache directory must be a writable directory. When ``$FLEXKANE_CACHE_DIR`` is a file, cannot
be created or is read-only, flexkane warns once (naming the path and the reason) and uses a
temporary cache for the process instead (:func:`usable_cache_dir`): nothing is kept for the next
run, nothing fails.

Numba compiles a function on its first call, in C, for seconds to minutes, and Python cannot handle
a signal meanwhile. Within :func:`compile_in_subprocess` (used by the command line), a structure
met for the first time is therefore compiled by a child process that fills the on-disk cache (on
Linux two forks of this process, which has Numba loaded already, one for the motion (the right-hand
side, the system function) and one for the outputs, side by side; elsewhere a new interpreter); this
process waits for it (a signal stops the child at once and raises :class:`KeyboardInterrupt`) and
then loads the machine code from the cache. The same child compiles the integrator loops when the
package's cache does not hold them yet (the first run of an installation); when it does, this process
loads them first (a fork inherits them and Numba's machinery) and the child compiles the structure's
functions only, while this process does the work it was given (``compile_in_subprocess(meanwhile=...)``,
e.g. the command's preparations of its output): on two cores that work costs no time.
"""

from __future__ import annotations

import atexit
import contextlib
import hashlib
import importlib.machinery
import importlib.util
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path
from types import ModuleType

import numba

from flexkane._version import __version__
from flexkane.checked_cache import note_damage, read_checked, write_checked
from flexkane.forking import fork_allowed as _fork_allowed   # may a compiling child be a fork
from flexkane.numerics import linear_algebra, modal_loops, scalar_typing
from flexkane.numerics.checked_numba_cache import entry_intact, files_intact, guard_namespace
from flexkane.numerics.system_function import SIGNATURE
from flexkane.progress import activity, tick, ticking

__all__ = ["TEMPLATE_BEGIN", "TEMPLATE_END", "build_module", "compile_in_subprocess", "compose_module_source",
           "default_cache_dir", "integrators_compiled", "is_compiled", "structure_key", "template_text",
           "usable_cache_dir"]

TEMPLATE_BEGIN = "# >>> flexkane template >>>"
TEMPLATE_END = "# <<< flexkane template <<<"
_KEY_LENGTH = 32  # hex digits of sha256 kept in keys (128 bits)
#: Layout of a module's directory (2: every file carries a digest, :mod:`flexkane.checked_cache`); in the
#: key, so that the files of another layout are never read.
_LAYOUT = "2"


def template_text(module: ModuleType) -> str:
    """Return the text between the template markers of a template module's file.

    Parameters
    ----------
    module : module
        A module with template markers (:mod:`~flexkane.numerics.linear_algebra`).

    Returns
    -------
    str
        The template source, markers excluded.
    """
    text = Path(module.__file__).read_text(encoding="utf-8")
    start = text.index(TEMPLATE_BEGIN) + len(TEMPLATE_BEGIN)
    return text[start:text.index(TEMPLATE_END, start)].strip("\n") + "\n"


def _templates() -> list[tuple[str, str]]:
    return [(m.__name__, template_text(m)) for m in (linear_algebra, modal_loops)]


def default_cache_dir() -> Path:
    """Return ``$FLEXKANE_CACHE_DIR`` if set, else ``~/.cache/flexkane``."""
    env = os.environ.get("FLEXKANE_CACHE_DIR")
    return Path(env) if env else Path.home() / ".cache" / "flexkane"


_fallback: dict[str, Path] = {}


def _warn(text: str) -> None:
    print(f"flexkane: warning: {text}", file=sys.stderr)


def usable_cache_dir(cache_dir: Path | str | None = None) -> Path:
    """Return the cache root to use: ``cache_dir`` (default :func:`default_cache_dir`) if it is, or
    can be made, a writable directory, else a temporary directory for this process.

    Parameters
    ----------
    cache_dir : path-like, optional
        The cache root asked for.

    Returns
    -------
    pathlib.Path
        ``cache_dir`` itself, created if missing; or, when it is a file, cannot be created or is
        not writable, a temporary directory (removed when the process ends), after a warning on
        standard error that names the path and the reason (once per path and process).
    """
    root = Path(cache_dir) if cache_dir is not None else default_cache_dir()
    if str(root) in _fallback:
        return _fallback[str(root)]
    reason = None
    if root.exists() and not root.is_dir():
        reason = "it is a file, not a directory"
    else:
        try:
            root.mkdir(parents=True, exist_ok=True)
            probe = tempfile.NamedTemporaryFile(dir=root, prefix=".flexkane-probe-")
            probe.close()
        except OSError as exc:
            reason = ("it cannot be created" if not root.is_dir() else "it is not writable") \
                + f" ({exc.strerror or exc})"
    if reason is None:
        return root
    temporary = Path(tempfile.mkdtemp(prefix="flexkane-cache-"))
    atexit.register(shutil.rmtree, temporary, ignore_errors=True)
    _fallback[str(root)] = temporary
    _warn(f"cache directory {root} (FLEXKANE_CACHE_DIR) is unusable: {reason}; using the temporary cache "
          f"{temporary} for this run (compiled models and derivations are not kept)")
    return temporary


def structure_key(*parts: str) -> str:
    """Return a key (32 hex digits of a SHA-256) for a generated module.

    Parameters
    ----------
    *parts : str
        What determines the module, typically the generated source fragments.

    Returns
    -------
    str
        Digest of the flexkane and Numba versions, the linear-algebra template and ``parts``: a
        change in any of them gives a new key, hence a new file and a fresh compilation. (The
        integrator loops are not part of a generated module: Numba's cache of the package
        follows their source.)
    """
    digest = hashlib.sha256()
    for text in (__version__, numba.__version__, _LAYOUT, *(t for _, t in _templates()), *parts):
        digest.update(text.encode("utf-8"))
        digest.update(b"\0")
    return digest.hexdigest()[:_KEY_LENGTH]


def compose_module_source(source: str, key: str) -> str:
    """Return the complete text of the generated module for ``source`` (see module docstring)."""
    blocks = [f'"""flexkane generated module {key}: do not edit, it is regenerated from the model.'
              '"""',
              "import math\n\nimport numpy as np\nfrom numba import njit"]
    for module, text in _templates():
        blocks.append(f"# ==== template {module} ====\n" + text)
    blocks.append("# ==== generated ====\n" + source)
    return "\n\n".join(block.rstrip("\n") for block in blocks) + "\n"


_in_subprocess: list = []


class _CheckedSourceLoader(importlib.machinery.SourceFileLoader):
    """Imports a generated module; Python's bytecode cache of it (``__pycache__/*.pyc``, in flexkane's cache)
    is written with its digest and read only when the digest matches, like every cache file."""

    def get_data(self, path):
        if not str(path).endswith(".pyc"):
            return super().get_data(path)
        data = read_checked(path, "Python's bytecode of a generated module", "compiled again")
        if data is None:    # missing or damaged: Python compiles the source (and stores the bytecode again)
            raise OSError(f"no checked bytecode at {path}")
        return data

    def set_data(self, path, data, *, _mode=0o666):
        if not str(path).endswith(".pyc"):
            super().set_data(path, data, _mode=_mode)
            return
        with contextlib.suppress(OSError):    # as Python's own loader: a bytecode cache only saves time
            Path(path).parent.mkdir(parents=True, exist_ok=True)
            write_checked(path, data)


def _module_spec(name: str, path: Path):
    """The import spec of the generated module at ``path`` (:class:`_CheckedSourceLoader`)."""
    return importlib.util.spec_from_file_location(name, path, loader=_CheckedSourceLoader(name, str(path)))


@contextlib.contextmanager
def compile_in_subprocess(announce=None, announce_integrators=None, meanwhile=None):
    """Within the block, :func:`build_module` compiles a structure new to the cache in a child process.

    Parameters
    ----------
    announce : callable or str, optional
        Called without arguments just before a child process starts compiling a model structure
        (e.g. to tell the user that a first compilation takes a while); a text instead: what the
        :func:`flexkane.progress.activity` of the wait shows (with its time, on standard error).
    announce_integrators : callable or str, optional
        The same for the integrator loops (compiled once per installation, see
        :func:`integrators_compiled`); default ``announce``.
    meanwhile : callable, optional
        Called without arguments in this process while a child compiles (at most once per child;
        not at all when nothing is compiled): work the caller needs later anyway and keeps (e.g.
        importing the plotting library), so that it overlaps the compilation. An exception in it
        stops the child and propagates.
    """
    announce = announce or (lambda: None)
    _in_subprocess.append((announce, announce_integrators or announce, meanwhile))
    try:
        yield
    finally:
        _in_subprocess.pop()


def _compiled_marker(path: Path) -> Path:
    return path.with_suffix(".compiled")


def _text_digest(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def _compile_file(path: str, loops: bool = True, part: str = "all") -> None:
    """Import the generated module at ``path`` and compile (into Numba's cache) everything a run calls.

    Run in the child process of :func:`_compile_in_child`, through the one function that compiles a
    module's integrators (:func:`~flexkane.numerics.integrate.compile_integrators`), so that the
    parent loads exactly the signatures it will call. ``loops``: also the integrator loops (when
    their cache does not hold them); otherwise the module's own functions only. ``part``: ``"all"``
    (and the marker that the module is compiled), or one of :data:`_PARTS` (no marker: the parent
    writes it once every part is compiled).
    """
    from flexkane.numerics.integrate import compile_integrators, compile_outputs

    scalar_typing.install()
    path = Path(path)
    spec = _module_spec(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[path.stem] = module
    spec.loader.exec_module(module)
    guard_namespace(module.__dict__)
    if part == "outputs":
        compile_outputs(module)
        return
    compile_integrators(module, loops=loops, outputs=part == "all")
    if part == "all":
        _write_marker(path)


def _write_marker(path: Path) -> None:
    """Mark the module at ``path`` as compiled (its text's digest: a changed text is not)."""
    write_checked(_compiled_marker(path), _text_digest(path.read_text(encoding="utf-8")).encode("ascii"))


def _is_marked(path: Path, text: str) -> bool:
    """Whether the module at ``path`` is marked compiled with ``text``."""
    marker = read_checked(_compiled_marker(path), "the mark of a compiled module", "compiled again")
    return marker is not None and marker == _text_digest(text).encode("ascii")


def _ensure_module_file(path: Path, text: str) -> None:
    """Make the file at ``path`` hold ``text`` (written with its digest when it does not: a changed file
    is noted as damaged)."""
    data = text.encode("utf-8")
    try:
        current = path.read_bytes()
    except FileNotFoundError:
        current = None
    if current != data:
        if current is not None:
            note_damage(path, "a generated module", "its text is not the one generated", "written again")
        write_checked(path, data)


#: The parts of a module that two forks compile side by side (:func:`_compile_in_fork`): the motion
#: (right-hand side, the system function, the integrator loops if they are not cached) and the outputs.
_PARTS = ("motion", "outputs")


def _compile_in_fork(path: Path, meanwhile=None, loops: bool = True) -> bool:
    """:func:`_compile_file` in forks of this process (which has Numba and flexkane loaded already):
    one for each of :data:`_PARTS`, so that the right-hand side and the outputs compile on two cores;
    ``meanwhile`` (no arguments, optional) is called here once they run. The module is marked
    compiled when both succeed."""
    sys.stdout.flush()
    sys.stderr.flush()
    pids, codes = [], {}   # the children, and the exit status of each one reaped
    try:
        for part in _PARTS:
            with warnings.catch_warnings():  # Python >= 3.12 warns of native threads (BLAS), unused by the child
                warnings.simplefilter("ignore", DeprecationWarning)
                pid = os.fork()
            if pid == 0:  # the child: its own session, default signals, no output; never returns
                status = 1
                try:
                    os.setsid()
                    for number in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
                        signal.signal(number, signal.SIG_DFL)
                    null = os.open(os.devnull, os.O_RDWR)
                    for fd in (0, 1, 2):
                        os.dup2(null, fd)
                    _compile_file(str(path), loops, part)
                    status = 0
                finally:
                    os._exit(status)
            pids.append(pid)
        if meanwhile is not None:
            with ticking():   # the children are forked: a thread may update the progress line now
                meanwhile()
        while len(codes) < len(pids):
            for pid in pids:
                if pid not in codes:
                    finished, code = os.waitpid(pid, os.WNOHANG)
                    if finished:
                        codes[pid] = code
            if len(codes) < len(pids):
                tick()
                time.sleep(0.02)
        ok = all(os.waitstatus_to_exitcode(code) == 0 for code in codes.values())
        if ok:
            _write_marker(path)
        return ok
    finally:   # a signal or an error here: the children not reaped yet are killed (a zombie too) and reaped
        for pid in pids:
            if pid not in codes:
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)


def _compile_in_child(path: Path, meanwhile=None, loops: bool = True) -> bool:
    """Compile the module at ``path`` into Numba's cache in a child process; return whether it worked.

    The child runs in a session of its own (Ctrl-C in the terminal reaches this process only). On any
    exception here, a signal among them (:class:`KeyboardInterrupt`), the child is killed first.
    ``meanwhile`` (optional, no arguments; e.g. loading what this process needs from Numba's cache)
    is called once in this process while the child compiles: on Linux a fork of this process (which
    has Numba's machinery loaded: about a second less per new structure than a new interpreter
    importing Numba), elsewhere, or with other threads running, a new interpreter. ``loops``: the
    child also compiles the integrator loops (when their cache lacks them; ``meanwhile`` must not
    load them then).
    """
    if _fork_allowed():
        return _compile_in_fork(path, meanwhile, loops)
    package_root = str(Path(__file__).resolve().parents[2])   # the folder that holds the package
    code = ("import sys; sys.path.insert(0, sys.argv[1]); "
            "from flexkane.numerics.jit_module import _compile_file; "
            "_compile_file(sys.argv[2], sys.argv[3] == 'loops')")
    with tempfile.TemporaryFile() as errors:
        child = subprocess.Popen([sys.executable, "-c", code, package_root, str(path),
                                  "loops" if loops else "module"],
                                 stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=errors,
                                 start_new_session=True)
        try:
            if meanwhile is not None:
                with ticking():
                    meanwhile()
            while True:
                try:
                    return child.wait(timeout=0.1) == 0
                except subprocess.TimeoutExpired:
                    tick()
        finally:
            if child.poll() is None:
                child.kill()
                child.wait()


def _compile_here_or_in_child(path: Path, integrators: bool, extra=None) -> None:
    """The compilation of :func:`build_module` within :func:`compile_in_subprocess`: the module at
    ``path`` in a child process, the integrator loops loaded here first when ``integrators`` (they
    are cached), else compiled by the child too; ``extra``: the caller's ``meanwhile``."""
    from flexkane.numerics.integrate import load_integrators

    # this process loads the integrators it will need from their cache (0.05 s, after 0.3 s
    # for Numba's machinery); when they are not cached, the child compiles them and this
    # process must not. A fork is made after the loading: the child inherits the machinery
    # instead of building it again; a new interpreter builds its own meanwhile.
    fork = _fork_allowed()
    if integrators and fork:
        load_integrators()

    def meanwhile():   # while the child compiles the structure
        if integrators and not fork:
            load_integrators()
        if extra is not None:
            extra()

    _compile_in_child(path, meanwhile=meanwhile, loops=not integrators)


def build_module(source: str, key: str, cache_dir: Path | None = None, *,
                 in_subprocess: bool | None = None) -> ModuleType:
    """Write the generated module for ``key`` (if needed) and import it.

    Parameters
    ----------
    source : str
        Generated fragments (:func:`~flexkane.numerics.codegen.generate_rhs_source`, optionally
        followed by :func:`~flexkane.numerics.codegen.generate_outputs_source`).
    key : str
        Identifier of the model structure, e.g. ``structure_key(source)``; letters, digits,
        ``_`` and ``-`` only.
    cache_dir : pathlib.Path, optional
        Root of the cache; default :func:`default_cache_dir` (through :func:`usable_cache_dir`).
    in_subprocess : bool, optional
        Compile a module not compiled before in a child process (see the module docstring);
        default: within :func:`compile_in_subprocess` only. If the child fails, the functions are
        compiled here on their first call, as without it.

    Returns
    -------
    module
        The imported module ``flexkane_generated_<key>`` with ``rhs``, ``system_rhs`` (and
        ``outputs`` when generated). Importing twice in one process returns the same module
        object.
    """
    if not key or not all(ch.isalnum() or ch in "_-" for ch in key):
        raise ValueError(f"key must be letters, digits, '_' or '-', got {key!r}")
    key = key.replace("-", "_")
    scalar_typing.install()   # the functions compile on their first call, in this process or a child
    root = usable_cache_dir(cache_dir)
    directory = root / key
    directory.mkdir(parents=True, exist_ok=True)
    module_name = f"flexkane_generated_{key}"
    path = directory / f"{module_name}.py"
    text = compose_module_source(source, key)
    loaded = sys.modules.get(module_name)
    if loaded is not None and getattr(loaded, "__file__", None) == str(path) \
            and getattr(loaded, "__flexkane_source__", None) == text:
        return loaded
    _ensure_module_file(path, text)
    if in_subprocess is None:
        in_subprocess = bool(_in_subprocess)
    if in_subprocess:
        compiled = _is_marked(path, text) and files_intact(path)   # a damaged file: compiled in the child
        integrators = integrators_compiled()
        if not (compiled and integrators):
            extra, shown = None, []
            if _in_subprocess:
                announce, announce_integrators, extra = _in_subprocess[-1]
                due = ([] if integrators else [announce_integrators]) \
                    + ([] if compiled or (announce is announce_integrators and not integrators) else [announce])
                for what in due:   # (once, when one callable announces both)
                    if isinstance(what, str):
                        shown.append(what)
                    else:
                        what()
            # what is compiled, with its time, on stderr while this process waits (a thread-less
            # activity: a fork is made while no other thread runs)
            with activity("; ".join(shown), delay=0, thread=False) if shown else contextlib.nullcontext():
                _compile_here_or_in_child(path, integrators, extra)
    _ensure_module_file(path, text)   # checked again just before the import (a child may have run meanwhile)
    spec = _module_spec(module_name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module
    try:
        spec.loader.exec_module(module)
    except RecursionError:   # Python's own compiler: an expression nested too deeply
        del sys.modules[module_name]
        from ..errors import ModelError

        raise ModelError("model size", "generated code whose expressions Python can compile", "an expression "
                         "nested too deeply for Python's compiler (RecursionError)",
                         "use fewer shape functions (n_modes of the beams)") from None
    except BaseException:
        del sys.modules[module_name]
        raise
    guard_namespace(module.__dict__)   # Numba's files of its functions are checked before loading
    module.__flexkane_source__ = text
    return module


def _compiled_or_cached(dispatcher, types: tuple) -> bool:
    """Whether a Numba dispatcher is compiled for the argument ``types`` here or in its disk cache.

    The disk cache counts when its index (for the function's current source) has the entry that a
    call with these types on this machine would load, and its files match their digests (a damaged
    one is deleted, with a note: the caller compiles it again).
    """
    if types in dispatcher.overloads:
        return True
    try:  # a private API of Numba (the key its cache looks up)
        return entry_intact(dispatcher, types)
    except Exception:  # noqa: BLE001 - unknown means "not cached"
        return False


def is_compiled(module: ModuleType) -> bool:
    """Whether the functions of a generated module that a run calls are compiled or in Numba's disk cache.

    Parameters
    ----------
    module : module
        Generated module (:func:`build_module`).

    Returns
    -------
    bool
        True when ``rhs`` and ``system_rhs`` are compiled, in this process or in the on-disk cache
        of the module's current source, for the arguments the integrators pass (a call will load
        rather than compile them); False otherwise, or when the cache cannot be read. The
        integrator loops are the package's: see :func:`integrators_compiled`.
    """
    return all(_compiled_or_cached(getattr(module, name, module.rhs), SIGNATURE.args)
               for name in ("rhs", "system_rhs"))


def integrators_compiled() -> bool:
    """Whether the integrator loops (DOP853, Radau IIA) are compiled here or in the package's Numba cache.

    Returns
    -------
    bool
        False before the first run of an installation (or after their source changed): the next
        run compiles them, for all models, once.
    """
    from flexkane.numerics.integrate import integrator_signatures

    return all(_compiled_or_cached(function, types) for function, types in integrator_signatures())
