"""On-disk cache of analysis results: a repeated ``linearize``, ``campbell`` or ``converge`` answered at once.

An analysis of a model (the equilibrium search, the Jacobians and eigenvalues at each operating
point, the figures) depends on the model's structure and numbers, on the operating point and the
options of the command, and on flexkane's code and the installed libraries. :func:`result_key`
hashes all of them:

* the structure signature of the model (:func:`flexkane.derivation_cache.structure_signature`) and
  its whole text (:func:`flexkane.model.dumps_model`: every value, initial condition and name);
* the analysis and its options (operating point, spin rates, mode counts, ...), as JSON;
* the digest of flexkane's source files and the versions of Python, NumPy, SciPy, SymPy and
  matplotlib (a result is reproduced bit for bit on one installation only).

An :class:`AnalysisResult` is what the command writes and prints: the bytes of each file written to
its output directory and the lines it prints (but the one naming the directory). It is stored as
JSON, the files' bytes in base64 (plain data: no pickle), under
``<cache directory>/analyses/<key>.json`` with its digest beside it (:mod:`flexkane.checked_cache`);
:func:`answer` returns it from there, or computes, stores and returns it. A stored result is checked
when loaded (its digest, then its format, key and plain file names): one that is damaged or does not
match is computed again and replaced, with a note on standard error. The files written from the cache are byte-identical to those the computation wrote.
At most :data:`LIMIT` results are kept (the oldest are removed).
"""

from __future__ import annotations

import base64
import hashlib
import json
import sys
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

from .model import Model

__all__ = ["AnalysisResult", "LIMIT", "analysis_options", "answer", "load_result", "prune", "result_key",
           "result_path", "store_result"]

#: Number of analysis results kept in the cache directory; storing one more removes the oldest.
LIMIT = 200
_FORMAT = 2
_LIBRARIES = ("numpy", "scipy", "sympy", "matplotlib")


@dataclass
class AnalysisResult:
    """What an analysis command writes and prints.

    Attributes
    ----------
    files : dict of str to bytes
        Name of each file written to the output directory (a plain file name) and its content,
        in the order written.
    lines : list of str
        The lines printed, but the last one that names the output directory.
    """

    files: dict = field(default_factory=dict)
    lines: list = field(default_factory=list)

    def write(self, out: Path) -> None:
        """Write the files to the directory ``out`` (atomically, each)."""
        from .atomic import atomic_write_bytes

        for name, data in self.files.items():
            atomic_write_bytes(Path(out) / name, data)


def _version(name: str) -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(name)
    except PackageNotFoundError:
        return "absent"


@lru_cache(maxsize=1)
def code_digest() -> str:
    """SHA-256 of flexkane's source files and of the versions of Python and the numeric libraries.

    Every source file, not only the analyses': the equations, their numbers, the labels of the modes
    and the figures all come from the package.
    """
    root = Path(__file__).resolve().parent
    digest = hashlib.sha256(f"{_FORMAT}\0{sys.version}\0".encode())
    for name in _LIBRARIES:
        digest.update(f"{name}={_version(name)}\0".encode())
    for path in sorted(root.rglob("*.py")):
        digest.update(str(path.relative_to(root)).encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()


def result_key(analysis: str, model: Model, options: dict) -> str:
    """The cache key of an analysis of ``model`` with ``options`` (module docstring).

    Parameters
    ----------
    analysis : str
        Name of the analysis (the command: ``linearize``, ``campbell``, ``converge``).
    model : Model
        The model analysed, values set.
    options : dict
        Everything else the result depends on, JSON-able (numbers, strings, lists; others by repr).

    Returns
    -------
    str
        64 hex digits.
    """
    from .derivation_cache import structure_signature
    from .model import dumps_model

    text = json.dumps({"analysis": analysis, "options": options}, sort_keys=True, default=repr)
    digest = hashlib.sha256()
    for part in (code_digest(), structure_signature(model), dumps_model(model), text):
        digest.update(part.encode("utf-8") + b"\0")
    return digest.hexdigest()


def _root(cache_dir=None) -> Path:
    from .numerics.jit_module import usable_cache_dir

    return usable_cache_dir(cache_dir) / "analyses"


def result_path(key: str, cache_dir=None) -> Path:
    """Where the result of ``key`` is stored (it may not exist)."""
    return _root(cache_dir) / f"{key}.json"


def _plain_name(name) -> bool:
    return isinstance(name, str) and name not in ("", ".", "..") and Path(name).name == name and "\\" not in name


#: What a stored result is, and what is done when it is damaged (the cache's notes).
_WHAT, _REMEDY = "an analysis result", "computed again"


def load_result(key: str, cache_dir=None) -> AnalysisResult | None:
    """The stored result of ``key``, or None when there is none or it is damaged (then with a note).

    The file's digest is checked before it is read (:func:`flexkane.checked_cache.read_checked`),
    then its layout: the format, the key, plain file names and base64 contents, lines of text.

    Parameters
    ----------
    key : str
        From :func:`result_key`.
    cache_dir : path-like, optional
        Root of the cache; default :func:`flexkane.numerics.default_cache_dir`.

    Returns
    -------
    AnalysisResult or None
    """
    from .checked_cache import discard, note_damage, read_checked

    path = result_path(key, cache_dir)
    data = read_checked(path, _WHAT, _REMEDY)
    if data is None:
        return None
    try:
        stored = json.loads(data.decode("utf-8"))
        files, lines = stored["files"], stored["lines"]
        if (stored["format"] == _FORMAT and stored["key"] == key and isinstance(files, dict)
                and all(_plain_name(n) and isinstance(v, str) for n, v in files.items())
                and isinstance(lines, list) and all(isinstance(line, str) for line in lines)):
            return AnalysisResult({n: base64.b64decode(v, validate=True) for n, v in files.items()}, list(lines))
    except (TypeError, ValueError, KeyError):      # not JSON, not the layout, not base64
        pass
    discard(path)
    note_damage(path, _WHAT, "not the layout of a result of this key", _REMEDY)
    return None


def store_result(key: str, result: AnalysisResult, cache_dir=None) -> None:
    """Store ``result`` under ``key`` with its digest (:func:`flexkane.checked_cache.write_checked`),
    removing the oldest results beyond :data:`LIMIT`. A cache that cannot be written only costs the
    time of computing again."""
    from .checked_cache import write_checked

    files = {name: base64.b64encode(data).decode("ascii") for name, data in result.files.items()}
    text = json.dumps({"format": _FORMAT, "key": key, "files": files, "lines": list(result.lines)},
                      separators=(",", ":"))
    path = result_path(key, cache_dir)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        write_checked(path, text.encode("utf-8"))
        prune(path.parent, LIMIT)
    except OSError:
        pass


def prune(directory: Path, limit: int) -> None:
    """Remove the oldest ``*.json`` files of ``directory`` (with their digests) beyond the ``limit`` newest."""
    from .checked_cache import discard

    stored = sorted(Path(directory).glob("*.json"), key=lambda p: (p.stat().st_mtime_ns, p.name))
    for old in stored[:max(0, len(stored) - limit)]:
        discard(old)


def answer(analysis: str, model: Model, options: dict, out: Path, compute, *, cache: bool = True,
           cache_dir=None) -> AnalysisResult:
    """The result of an analysis, from the cache or computed; its files written to ``out`` either way.

    Parameters
    ----------
    analysis, model, options
        As for :func:`result_key`.
    out : pathlib.Path
        The output directory (existing).
    compute : callable
        ``compute(out)`` runs the analysis, writes its files to ``out`` and returns
        ``(lines, names)``: the lines to print (list of str) and the names of the files written.
    cache : bool
        Answer from the cache and store the result there (default); ``False`` computes afresh and
        stores nothing (``--no-cache``).
    cache_dir : path-like, optional
        Root of the cache; default :func:`flexkane.numerics.default_cache_dir`.

    Returns
    -------
    AnalysisResult
    """
    key = result_key(analysis, model, options) if cache else None
    stored = load_result(key, cache_dir) if key is not None else None
    if stored is not None:
        stored.write(out)
        return stored
    lines, names = compute(out)
    result = AnalysisResult({name: (Path(out) / name).read_bytes() for name in names}, list(lines))
    if key is not None:
        store_result(key, result, cache_dir)
    return result


def analysis_options(args, *, drop=("out", "force", "quiet", "no_cache", "handler")) -> dict:
    """The options of a command line that a result depends on: every argument but the output
    directory, --force, --quiet, --no-cache and the handler."""
    return {k: v for k, v in sorted(vars(args).items()) if k not in drop and not callable(v)}
