"""The numeric functions of a linearization, kept on disk per structure.

The forcing's values and Jacobian, the mass matrix, the kinematic matrices and the outputs'
Jacobian of a :class:`~flexkane.analysis.linearization.Linearization` are functions of the state and
the constants vector: their code depends on the structure of the prepared model only (its derived
equations, :mod:`flexkane.derivation_cache`), never on the values. Forming them (the forward
Jacobian, :mod:`flexkane.analysis.jacobian`, and SymPy's printing of the code) is most of a
linearization of a large model; a linearization of the same structure with other values (``--set``,
another spin rate or mode count of the same structure) loads the code instead.

:func:`function_key` names the functions of one linearization: the key of its derived equations,
the arguments (names, in order), the operating point's kind and hub, and the digest of flexkane's
sources and libraries (:func:`flexkane.result_cache.code_digest`). :func:`numeric_function_cached`
returns the function stored under ``<cache directory>/analyses/functions/<key>-<name>.json`` (the
Python source that ``sympy.lambdify`` generated and the names it imports, with their SHA-256), or forms, stores and returns it.
A stored function is the same code, so it gives the same numbers bit for bit; a file that is damaged
or does not match is formed again and replaced; at most :data:`LIMIT` are kept. Like the derivation
cache, the files are written by flexkane into the user's own cache only.
"""

from __future__ import annotations

import builtins
import hashlib
import importlib
import json
import linecache
from pathlib import Path

import sympy as sp

from .jacobian import numeric_function

__all__ = ["LIMIT", "function_key", "numeric_function_cached"]

#: Number of functions kept (four per structure and operating point); storing one more removes the oldest.
LIMIT = 400
_FORMAT = 1
_GENERATED = "_lambdifygenerated"       # the name sympy.lambdify gives the function it defines


def function_key(derivation_key: str | None, args, **point) -> str | None:
    """Key of the numeric functions of one linearization, or None when the equations are not from the
    cache of derived equations (then nothing is kept).

    Parameters
    ----------
    derivation_key : str or None
        ``eom.derivation_key`` of the prepared model's equations.
    args : sequence of sympy.Symbol
        The functions' arguments, in order.
    **point
        What else selects the functions (the kind of operating point, the hub, a free spin), JSON-able.
    """
    if not derivation_key:
        return None
    from ..result_cache import code_digest

    text = json.dumps({"derivation": derivation_key, "args": [str(a) for a in args], "point": point},
                      sort_keys=True, default=repr)
    return hashlib.sha256((code_digest() + "\0" + text).encode("utf-8")).hexdigest()[:40]


def _path(key: str, name: str) -> Path:
    from ..numerics.jit_module import usable_cache_dir

    return usable_cache_dir() / "analyses" / "functions" / f"{key}-{name}.json"


def _namespace() -> dict:
    """The globals of a function sympy.lambdify generates for NumPy (NumPy's names, builtins)."""
    return dict(sp.lambdify([], 0, modules="numpy").__globals__)


def _namespace_with(imports: dict) -> dict:
    """:func:`_namespace` and the names the code imports, as lambdify's ``from MODULE import NAME``."""
    namespace = _namespace()
    for module, names in imports.items():
        for item in names:
            namespace[item] = getattr(importlib.import_module(module), item)
    return namespace


def _self_contained(function) -> bool:
    """Whether every global name of the function's code is in the namespace a stored copy gets (a
    function of SymPy's ``implemented_function`` would not be: such code is not stored)."""
    namespace = _namespace_with(function.module_imports)
    return all(n in namespace or hasattr(builtins, n) for n in function.__code__.co_names)


def _digest(source: str, imports: dict) -> str:
    return hashlib.sha256(json.dumps([source, imports], sort_keys=True).encode("utf-8")).hexdigest()


def _load(path: Path, key: str, name: str):
    try:
        stored = json.loads(path.read_text(encoding="utf-8"))
        source, imports = stored["source"], stored["imports"]
        if not (stored["format"] == _FORMAT and stored["key"] == key and stored["name"] == name
                and isinstance(source, str) and stored["digest"] == _digest(source, imports)):
            return None
        namespace = _namespace_with(imports)
        filename = f"<flexkane-linearization-{name}>"
        linecache.cache[filename] = (len(source), None, source.splitlines(True), filename)
        exec(compile(source, filename, "exec"), namespace)       # noqa: S102 - code flexkane generated
        return namespace[_GENERATED]
    except (OSError, ValueError, KeyError, TypeError, AttributeError, ImportError, SyntaxError):
        return None


def numeric_function_cached(key: str | None, name: str, args, make):
    """:func:`~flexkane.analysis.jacobian.numeric_function` of ``make()``, stored under ``key`` and ``name``.

    Parameters
    ----------
    key : str or None
        From :func:`function_key`; None forms the function and keeps nothing.
    name : str
        Which function of the linearization (``forcing``, ``mass``, ``kinematic``, ``outputs``).
    args : sequence of sympy.Symbol
        The arguments, in order.
    make : callable
        ``make()`` returns ``(exprs, jacobian)``, the arguments of ``numeric_function`` (called only
        when the function is not stored).

    Returns
    -------
    callable
    """
    from ..atomic import atomic_write_text
    from ..result_cache import prune

    path = _path(key, name) if key is not None else None
    if path is not None and path.exists():
        function = _load(path, key, name)
        if function is not None:
            return function
    exprs, jacobian = make()
    function = numeric_function(args, exprs, jacobian)
    if path is not None:
        source = "".join(linecache.getlines(function.__code__.co_filename))
        imports = function.module_imports
        if source and _self_contained(function):
            text = json.dumps({"format": _FORMAT, "key": key, "name": name, "source": source, "imports": imports,
                               "digest": _digest(source, imports)})
            try:
                path.parent.mkdir(parents=True, exist_ok=True)
                atomic_write_text(path, text)
                prune(path.parent, LIMIT)
            except OSError:
                pass    # a cache that cannot be written only costs time
    return function
