"""On-disk cache of derived equations of motion, keyed by the structure of the model.

The derivation keeps every number of a model as a symbol (:mod:`flexkane.model.values`), so two
models that differ only in numbers have the same equations. :func:`structure_signature` hashes
what the equations depend on; :func:`cached_derive` stores each
:class:`~flexkane.kane.EquationsOfMotion` under that hash (with the versions of the derivation
code) and returns the stored one, bound to the model given, when the hash is known. The source of the
generated module of the equations (:func:`model_source`) is cached beside them (:func:`cached_rhs_source`).

What belongs to the structure
-----------------------------
* the topology: names and types of bodies, beams, joints, loads, springs, loop constraints, the
  points and stations they use, ``naming``, the parameters' names;
* the options that change the equations: ``n_modes``, ``n_axial``, shape families and their
  options, ``gravity`` and ``elastic_forces`` models, ``geometric_stiffening``, how many damping
  ratios a beam lists, the gravity direction, the stabilization rate of a loop constraint;
* for every constant field (a mass, a length, a stiffness, ...) only its class: literal zero,
  the name of a parameter, or any other value (a symbol of its own);
* the texts of the laws of time (torques, loads, drivers), and the texts of beam stations and of
  beam lengths given as numbers, because the derivation names the constants evaluated at a
  station after that text (``Phi_1(0.8)``).

What does not: parameter values, the values of constant fields, typed roots of eq. 8.6, the
tip-mass ratios of a shape family, body outlines, initial conditions, simulation settings, the
model's name. One exception: a model with
loop constraints whose dependent speeds are left to the derivation (chosen by pivoting at the
initial configuration) is keyed on all its numbers; name them (``dependent = [...]``) to share one
derivation across numeric variants.

Loading is about 10 to 25 times faster than deriving (measured in benchmarks/RESULTS.md): SymPy
expressions are pickled with their arguments and rebuilt without re-evaluation (they were stored
in canonical form), which is what makes loading cheap.

The cache directory is ``<default_cache_dir()>/derived`` (``$FLEXKANE_CACHE_DIR`` or
``~/.cache/flexkane``); when that is a file, cannot be created or is read-only, a temporary cache
is used with a warning (:func:`flexkane.numerics.jit_module.usable_cache_dir`). Files are written
atomically, each with its digest beside it (:mod:`flexkane.checked_cache`), and read only when the
digest matches: a changed, truncated or unreadable file is derived (or generated) again and replaced,
with a note. The digest guards against damage, not against someone who can write to the cache: like
any pickle, the files must come from a trusted source; they are only ever written by flexkane into
the user's own cache.
"""

from __future__ import annotations

import dataclasses
import hashlib
import io
import json
import pickle
import re
import sys
from functools import lru_cache
from pathlib import Path

from ._version import __version__
from .checked_cache import read_checked, write_checked
from .model import Model, schema

__all__ = ["VALUE_FIELDS", "Derivation", "cache_path", "cached_derive", "cached_rhs_source", "derive",
           "model_source", "structure_signature", "work_integrands"]

# Key paths of the constant fields that the derivation turns into a symbol, a parameter's symbol or
# a zero (``FieldSymbols.value``): only that class is structure. A field missing here is compared by
# value, which can only cause a needless re-derivation, never a wrong cache hit. Each field's kind
# (structure, value, numbers only, ignored) is declared in flexkane.model.schema.
VALUE_FIELDS = (schema.one_pattern(schema.value_path_patterns()),)
# Fields that never enter the equations, and fields that give them numbers only.
_IGNORED = (schema.one_pattern(schema.path_patterns("ignored")),)
_NUMBERS = (schema.one_pattern(schema.path_patterns("number")),)
# A beam length is a value field, but its text names the constants at the tip (``Phi_1(L)``).
_BEAM_LENGTH = re.compile(r"beams\.[^.]+\.L")
_FORMAT = 2  # layout of the cache files (2: with digests)
# Sources that compute a run's numbers, its manifest and its generated module beside the equations.
_RUN_SOURCES = ("modes/*.py", "report.py", "validity.py", "run_manifest.py", "plots.py", "natural_order.py",
                "expression_syntax.py", "expression_values.py", "simulation.py", "derivation_cache.py",
                "numerics/codegen.py", "numerics/large_rhs.py", "numerics/code_budget.py", "equations_document.py")


# ---------------------------------------------------------------------- structure signature
def _value_class(value, parameters) -> list:
    """Class of a constant field as the derivation sees it (see ``FieldSymbols.value``)."""
    if value is None:       # an optional field left out (a beam's rotary_inertia) adds no terms
        return ["absent"]
    if isinstance(value, (int, float)) and not isinstance(value, bool) and value == 0:
        return ["zero"]
    if isinstance(value, str) and value.strip() in parameters:
        return ["parameter", value.strip()]
    if isinstance(value, str) and _names_beyond(value, parameters):
        return ["law", value.strip()]    # of t or the state (a moving rest position): structure
    return ["symbol"]


def _names_beyond(text: str, parameters) -> bool:
    """Whether an expression names something other than the parameters, pi and the functions."""
    from .expression_syntax import RESERVED_NAMES

    return any(name not in parameters and name not in RESERVED_NAMES
               for name in re.findall(r"(?<![\w.])[A-Za-z_]\w*", text))


def _canonical(value, path: str, parameters, keep_numbers: bool):
    """JSON-able structural view of one field (recursively)."""
    if any(p.fullmatch(path) for p in _IGNORED) \
            or (not keep_numbers and any(p.fullmatch(path) for p in _NUMBERS)):
        return None
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: _canonical(getattr(value, f.name), f"{path}.{f.name}".lstrip("."),
                                   parameters, keep_numbers)
                for f in dataclasses.fields(value)}
    if isinstance(value, dict):
        return [[str(k), _canonical(v, f"{path}.{k}", parameters, keep_numbers)]
                for k, v in value.items()]
    if isinstance(value, (list, tuple)):
        return [_canonical(v, f"{path}[{i}]", parameters, keep_numbers) for i, v in enumerate(value)]
    if not keep_numbers:
        if any(p.fullmatch(path) for p in VALUE_FIELDS):
            return _value_class(value, parameters)
        if _BEAM_LENGTH.fullmatch(path) and isinstance(value, str) and value.strip() in parameters:
            return ["parameter", value.strip()]
    if isinstance(value, float):
        return ["float", repr(value)]
    if value is None or isinstance(value, (bool, int, str)):
        return value
    return ["repr", type(value).__name__, repr(value)]


def _needs_numbers(model: Model) -> bool:
    """Whether the derivation reads numbers: loop constraints with automatic dependent speeds."""
    return any(not getattr(c, "dependent", None) for c in getattr(model, "constraints", {}).values())


def structure_signature(model: Model) -> str:
    """Return the hash (64 hex digits of a SHA-256) of the structure of ``model``.

    Parameters
    ----------
    model : Model
        A model (not modified).

    Returns
    -------
    str
        Equal for models whose derived equations are equal (see the module docstring for what
        counts as structure), different otherwise. Parameter values, the values of constant
        fields and typed roots do not change it; topology, mode counts, shape families, options
        that change the equations, which fields are zero or name a parameter, and the texts of
        laws of time do.
    """
    keep = _needs_numbers(model)
    view = {"parameters": sorted(model.parameters),
            "model": _canonical(model, "", set(model.parameters), keep)}
    text = json.dumps(view, separators=(",", ":"), sort_keys=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def _sympy_version() -> str:
    """SymPy's version, from its installed metadata (a cached run does not import SymPy)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("sympy")
    except PackageNotFoundError:   # not installed as a distribution: ask the package itself
        import sympy

        return sympy.__version__


@lru_cache(maxsize=1)
def _run_digest() -> str:
    """Digest of the sources that make a run's manifest, numbers and module from the equations."""
    root = Path(__file__).resolve().parent
    digest = hashlib.sha256(_code_digest().encode())
    for pattern in _RUN_SOURCES:
        for path in sorted(root.glob(pattern)):
            digest.update(str(path.relative_to(root)).encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()


def equation_sources() -> list[Path]:
    """The package's source files that produce the equations, whose contents key the cache.

    Everything the derivation reads: the engine (``kane/``), the model layer, the shape functions
    and the expression language that parses and evaluates the fields.

    Returns
    -------
    list of pathlib.Path
        Sorted paths of the files.
    """
    root = Path(__file__).resolve().parent
    return sorted([*root.glob("kane/*.py"), *root.glob("model/*.py"), *root.glob("modes/*.py"),
                   *root.glob("expression*.py")])


@lru_cache(maxsize=1)
def _code_digest() -> str:
    """Digest of the versions and sources that produce the equations (invalidates old files)."""
    root = Path(__file__).resolve().parent
    digest = hashlib.sha256()
    for text in (__version__, _sympy_version(), sys.version.split()[0], str(_FORMAT)):
        digest.update(text.encode() + b"\0")
    for path in equation_sources():
        digest.update(str(path.relative_to(root)).encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()


def _key(model: Model) -> str:
    digest = hashlib.sha256((structure_signature(model) + _code_digest()).encode())
    return digest.hexdigest()[:32]


def _cache_root(cache_dir) -> Path:
    """The cache root, or a temporary one (with a warning) when it is not a writable directory."""
    from .numerics.jit_module import usable_cache_dir

    return usable_cache_dir(cache_dir)


def cache_path(model: Model, cache_dir=None) -> Path:
    """Path of the cache file of ``model``'s equations (it may not exist yet).

    Parameters
    ----------
    model : Model
    cache_dir : path-like, optional
        Root of the cache; default :func:`flexkane.numerics.default_cache_dir`.
    """
    return _cache_root(cache_dir) / "derived" / f"{_key(model)}.pkl"


# ---------------------------------------------------------------------- fast pickling of SymPy
def _rebuild_assoc(cls, args):
    return cls._from_args(args)


def _rebuild_pow(base, exp):
    import sympy as sp

    return sp.Pow(base, exp, evaluate=False)


def _rebuild_function(cls, args):
    return cls(*args, evaluate=False)


class _ExpressionPickler(pickle.Pickler):
    """Pickles Add, Mul, Pow and functions so that loading does not evaluate them again.

    SymPy's default reduction rebuilds ``Add(*args)``, which flattens and sorts its arguments
    again: the stored arguments are already canonical, so ``_from_args`` is equal and 10 times
    faster to load.
    """

    def reducer_override(self, obj):
        import sympy as sp
        from sympy.core.function import AppliedUndef

        kind = type(obj)
        if kind is sp.Add or kind is sp.Mul:
            return _rebuild_assoc, (kind, obj.args)
        if kind is sp.Pow:
            return _rebuild_pow, obj.args
        if isinstance(obj, sp.Function) and not isinstance(obj, (AppliedUndef, sp.Piecewise)) \
                and type(obj).__module__.startswith("sympy."):
            return _rebuild_function, (kind, obj.args)
        return NotImplemented


def _store(path: Path, data: bytes) -> None:
    """Write a cache file with its digest (:func:`flexkane.checked_cache.write_checked`); a read-only
    cache only costs speed."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        write_checked(path, data)
    except OSError:
        pass


def _read_text(path: Path, what: str, remedy: str) -> str | None:
    """A checked cache file as text (UTF-8), or None."""
    data = read_checked(path, what, remedy)
    try:
        return None if data is None else data.decode("utf-8")
    except UnicodeDecodeError:
        return None


#: What the cached generated code is (for the note when it was damaged).
_SOURCE = ("the generated code of this model structure", "generated again")


def _dumps(obj) -> bytes:
    buffer = io.BytesIO()
    _ExpressionPickler(buffer, protocol=pickle.HIGHEST_PROTOCOL).dump(obj)
    return buffer.getvalue()


def _bind(eom, model: Model):
    """Point the stored equations at ``model``, whose numbers they will use by default."""
    eom.model = model
    chain = getattr(eom, "chain", None)
    if chain is not None:
        chain.model = model
        symbols = getattr(chain, "symbols", None)
        if symbols is not None:
            symbols.model = model
            definitions = getattr(symbols, "definitions", None)
            if definitions:
                from .model.paths import get_value

                for symbol, (path, value) in list(definitions.items()):
                    try:
                        definitions[symbol] = (path, get_value(model, path))
                    except Exception:  # noqa: BLE001 - keep the stored text
                        definitions[symbol] = (path, value)
    return eom


# ---------------------------------------------------------------------- public functions
def derive(model: Model, *, cache: bool = True, cache_dir=None, announce=None):
    """Derive Kane's equations of motion of a model, from the cache of its structure when it has them.

    Parameters
    ----------
    model : Model
        A model (validated here).
    cache : bool
        Use the cache of derived equations (default); ``False`` derives afresh and stores nothing.
    cache_dir : path-like, optional
        Root of the cache; default :func:`flexkane.numerics.default_cache_dir`.
    announce : callable, optional
        Called without arguments before deriving.

    Returns
    -------
    EquationsOfMotion
        ``M(q, t) u' = f(q, u, t)`` with ``q' = qdot``; ``eom.model`` is the model given. From the
        cache, ``eom.derivation_key`` names the stored equations, so that
        :func:`flexkane.compile_model` also finds their generated code there.
    """
    if cache:
        return cached_derive(model, cache_dir, announce=announce)
    from .kane import derive as derive_afresh

    if announce is not None:
        announce()
    return derive_afresh(model)


def cached_derive(model: Model, cache_dir=None, *, announce=None):
    """Derive Kane's equations of ``model``, or load them from the cache of its structure.

    Parameters
    ----------
    model : Model
        A model (validated here).
    cache_dir : path-like, optional
        Root of the cache; default :func:`flexkane.numerics.default_cache_dir`.
    announce : callable, optional
        Called without arguments before deriving, when the cache does not hold the equations.

    Returns
    -------
    EquationsOfMotion
        Equal to ``flexkane.derive(model, cache=False)``, with ``eom.model`` the model given (so
        its numbers are the default ones) and ``eom.derivation_key`` the cache key.
    """
    from .errors import ModelError
    from .kane import derive as derive_afresh

    if not isinstance(model, Model):
        raise ModelError("model", "a flexkane Model (flexkane.load_model, flexkane.builtin_model)",
                         type(model).__name__)
    model.validate()
    path = cache_path(model, cache_dir)
    eom = None
    data = read_checked(path, "the equations of this model structure", "derived again")   # checked before unpickling
    if data is not None:
        try:
            stored = pickle.loads(data)
            if stored.get("format") == _FORMAT:
                eom = stored["eom"]
        except Exception:  # noqa: BLE001 - an incompatible file (another SymPy) is derived again
            eom = None
    if eom is None:
        if announce is not None:
            announce()
        eom = derive_afresh(model)
        _store(path, _dumps({"format": _FORMAT, "eom": eom}))
    eom = _bind(eom, model)
    eom.derivation_key = path.stem
    return eom


def _source_path(root: Path, key: str) -> Path:
    return root / "derived" / f"{key}-{_run_digest()[:16]}.module.py"


def work_integrands(eom) -> dict:
    """Integrands of the quadrature states of a run: ``{"work": power}`` [W], or ``{}``.

    The power of the non-conservative forces (drivers with their efforts, applied loads, actuator
    torques, dampers; :mod:`flexkane.kane.outputs`) is integrated with the motion, so the work
    ``W`` and the balance ``E - E0 - W`` are exact to the solver's tolerance. A model without such
    forces (power identically 0) gets none.
    """
    outputs = eom.compact.outputs if hasattr(eom, "compact") else eom.outputs   # named intermediates kept
    power = outputs.get("power_nonconservative", 0)
    return {} if power == 0 else {"work": power}


def model_source(eom) -> str:
    """Source of the generated module of ``eom`` (before :func:`~flexkane.numerics.jit_module.build_module`).

    Parameters
    ----------
    eom : EquationsOfMotion

    Returns
    -------
    str
        ``rhs`` and ``system_rhs`` (:func:`flexkane.numerics.generate_rhs_source`, with the
        quadratures of :func:`work_integrands`), ``outputs`` (every output of ``eom.outputs``,
        :func:`flexkane.numerics.generate_outputs_source`; outputs that contain u' call ``rhs``)
        and, when a beam's spin is checked, ``spin_rates`` (the angular velocities of
        :func:`flexkane.validity.spin_expressions`).
    """
    from .numerics.codegen import generate_outputs_source, generate_rhs_source
    from .progress import activity
    from .validity import spin_expressions

    with activity(f"generating the code of {eom.model.name}", delay=0):   # on stderr (flexkane.progress)
        parts = [generate_rhs_source(eom, quadratures=work_integrands(eom)),
                 generate_outputs_source(eom.compact.outputs if hasattr(eom, "compact") else eom.outputs, eom)]
        spins = spin_expressions(eom)
        if spins:
            parts.append(generate_outputs_source(spins, eom, name="spin_rates"))
    return "\n\n".join(parts)


def cached_rhs_source(eom, cache_dir=None) -> str:
    """Generated code of ``eom`` (right-hand side, quadratures, outputs), from the cache when it has it.

    Parameters
    ----------
    eom : EquationsOfMotion
        Equations; when they carry a ``derivation_key`` (from :func:`cached_derive`) the source
        is stored under that key and the digest of the code generator, so that compiling them
        again (another run, a sweep's worker) does not generate it again.
    cache_dir : path-like, optional
        Root of the cache.

    Returns
    -------
    str
        :func:`model_source` of ``eom``.
    """
    key = getattr(eom, "derivation_key", None)
    if not key:
        return model_source(eom)
    path = _source_path(_cache_root(cache_dir), key)
    source = _read_text(path, *_SOURCE)
    if source is None:
        source = model_source(eom)
        _store(path, source.encode("utf-8"))
    return source


def _read_json(path: Path, what: str, remedy: str):
    """A stored JSON file of this layout, or None (missing, damaged, other layout)."""
    from .run_manifest import MANIFEST_FORMAT

    text = _read_text(path, what, remedy)
    try:
        data = None if text is None else json.loads(text)
    except ValueError:
        return None
    return data if isinstance(data, dict) and data.get("format") == MANIFEST_FORMAT else None


def _write_json(path: Path, data: dict) -> None:
    _store(path, json.dumps(data, separators=(",", ":")).encode("utf-8"))


def _is_printed(data: dict) -> bool:
    """Whether stored data has the layout of the printed equations of a structure."""
    from .equations_document import PRINTED_KEYS

    return (all(key in data for key in PRINTED_KEYS) and isinstance(data["md"], str)
            and isinstance(data["tex"], str) and isinstance(data["constants"], list)
            and all(isinstance(row, list) and len(row) == 7 for row in data["constants"]))


class Derivation:
    """The equations of a model's structure as a run uses them, from the cache as far as it has them.

    A run needs the generated module, the run manifest and the model's numbers
    (:mod:`flexkane.run_manifest`); each is read from the cache when stored there, else made from
    the equations (loaded or derived, with SymPy, on first need) and stored. A run of a model whose
    structure and numbers ran before therefore loads neither the equations nor SymPy.

    Parameters
    ----------
    model : Model
        The model (validated here).
    cache_dir : path-like, optional
        Root of the cache; default :func:`flexkane.numerics.default_cache_dir`.
    announce : callable, optional
        Called without arguments before the equations are derived (not found in the cache).
    eom : EquationsOfMotion, optional
        The equations, when the caller has them already (``model`` is then ``eom.model``); without
        a ``derivation_key`` (derived without the cache) nothing is read from or written to it.
    cache : bool
        Whether to use the cache; ``False`` derives the equations afresh on first need and reads
        and stores nothing (the compiled module still comes from Numba's cache).
    """

    def __init__(self, model: Model | None = None, cache_dir=None, *, announce=None, eom=None,
                 cache: bool = True):
        if eom is not None:
            model = eom.model
            self.key = getattr(eom, "derivation_key", None) if cache else None
        else:
            from .errors import ModelError

            if not isinstance(model, Model):
                raise ModelError("model", "a flexkane Model (flexkane.load_model, flexkane.builtin_model)",
                                 type(model).__name__)
            model.validate()
            self.key = _key(model) if cache else None
        self.model = model
        self._cache_dir = cache_dir
        self._root = _cache_root(cache_dir) if self.key else None
        self._announce = announce
        self._cache = cache
        self._eom = eom
        self._manifest = None
        self._printed = None
        self._numbers: dict = {}

    @property
    def eom(self):
        """The equations (:class:`~flexkane.kane.EquationsOfMotion`), loaded or derived on first use."""
        if self._eom is None:
            self._eom = derive(self.model, cache=self._cache, cache_dir=self._cache_dir, announce=self._announce)
        return self._eom

    @property
    def loaded(self) -> bool:
        """Whether the symbolic equations were needed (loaded or derived) so far."""
        return self._eom is not None

    @property
    def manifest(self) -> dict:
        """The run manifest of the structure (:func:`flexkane.run_manifest.manifest_of`)."""
        if self._manifest is None:
            path = self._root / "derived" / f"{self.key}-{_run_digest()[:16]}.manifest.json" if self.key else None
            manifest = _read_json(path, "the run manifest of this model structure", "made again") \
                if path is not None else None
            if manifest is None:
                from .run_manifest import manifest_of

                manifest = manifest_of(self.eom)
                if path is not None:
                    _write_json(path, manifest)
            self._manifest = manifest
        return self._manifest

    def _of_structure(self, name: str, make, valid, what: str) -> dict:
        """Plain data of the structure made by ``make()`` from the equations (with SymPy), stored once
        per structure beside the manifest as ``<key>-<run digest>.<name>.json``; read from there when
        it is stored (and ``valid``). ``what`` names the data in the note on a damaged file."""
        path = self._root / "derived" / f"{self.key}-{_run_digest()[:16]}.{name}.json" if self.key else None
        data = _read_json(path, what, "rendered again") if path is not None else None
        if data is None or not valid(data):
            from .run_manifest import MANIFEST_FORMAT

            data = {"format": MANIFEST_FORMAT, **make()}
            if path is not None:
                _write_json(path, data)
        return data

    @property
    def printed(self) -> dict:
        """The printed equations of the structure (:func:`flexkane.report.printed_structure`),
        rendered with SymPy once and stored beside the manifest."""
        if self._printed is None:
            def render():
                from .report import printed_structure

                return printed_structure(self.eom)

            self._printed = self._of_structure("equations", render, _is_printed,
                                               "the printed equations of this model structure")
        return self._printed

    def forces_text(self, latex: bool = False) -> str:
        """F*_r and F_r of the structure as ``flexkane derive`` prints them
        (:func:`flexkane.report.format_equations`), rendered once and stored.

        Parameters
        ----------
        latex : bool
            LaTeX lines instead of text.
        """
        def render():
            from .report import format_equations

            return {"text": format_equations(self.eom, latex=latex)}

        data = self._of_structure("forces-latex" if latex else "forces-text", render,
                                  lambda stored: isinstance(stored.get("text"), str),
                                  "the printed forces of this model structure")
        return data["text"]

    def equations(self, model: Model, *, remember: bool = False) -> dict:
        """``equations.md`` and ``equations.tex`` of ``model`` (a model of this structure).

        The printed equations of the structure (:attr:`printed`) with the model's name and values
        (:func:`flexkane.equations_document.documents`): a model whose numbers alone changed costs
        its constants vector p, no rendering.

        Parameters
        ----------
        model : Model
        remember : bool
            Store the model's p in the cache (as :meth:`numbers`).

        Returns
        -------
        dict
            ``{"md": text, "tex": text}``.
        """
        from .equations_document import documents

        p = self.numbers(model, ("p",), remember=remember)["p"]
        return documents(self.printed, model.name, p, model.parameters)

    def source(self) -> str:
        """Source of the generated module (:func:`cached_rhs_source`)."""
        if not self.key:
            return model_source(self.eom)
        if self._eom is None:
            source = _read_text(_source_path(self._root, self.key), *_SOURCE)
            if source is not None:
                return source
        return cached_rhs_source(self.eom, self._cache_dir)

    def _numbers_path(self, model: Model) -> Path | None:
        if not self.key:
            return None
        from .model import dumps_model

        digest = hashlib.sha256((_run_digest() + "\0" + dumps_model(model)).encode("utf-8")).hexdigest()[:32]
        return self._root / "derived" / f"{self.key}.numbers" / f"{digest}.json"

    def numbers(self, model: Model, fields, *, remember: bool = False, extra=None) -> dict:
        """Numbers of ``model`` (a model of this structure) for a run: fields of
        :func:`flexkane.run_manifest.numbers_of`, and others computed by the caller.

        Parameters
        ----------
        model : Model
        fields : collection of str
            The fields wanted, among :data:`flexkane.run_manifest.NUMBER_FIELDS` and the keys of
            ``extra``.
        remember : bool
            Store the numbers in the cache (the command line's runs do, so that a run repeated
            with the same model needs no SymPy); the numbers stored already are read in any case.
        extra : mapping of str to callable, optional
            Fields computed by a later layer, each by a function without arguments returning JSON
            data (the initial state at the static equilibrium,
            :func:`flexkane.analysis.equilibrium_start.initial_state`); called only when the field
            is not known for this model's text.

        Returns
        -------
        dict
            The fields asked for (and any others known).
        """
        from .model import dumps_model

        text = dumps_model(model)
        known = self._numbers.get(text)
        path = None
        if known is None:
            path = self._numbers_path(model)
            known = (_read_json(path, "the numbers of this model", "computed again") if path is not None
                     else None) or {}
            known.pop("format", None)
            self._numbers = {text: known}   # the last model only (a sweep runs many)
        missing = [f for f in fields if f not in known]
        if missing:
            from .run_manifest import MANIFEST_FORMAT, numbers_of

            extra = extra or {}
            standard = [f for f in missing if f not in extra]
            if standard:
                known.update(numbers_of(self.eom, model, standard, self.manifest["spins"]))
            known.update({f: extra[f]() for f in missing if f in extra})
            if remember:
                path = path or self._numbers_path(model)
                if path is not None:
                    _write_json(path, {"format": MANIFEST_FORMAT, **known})
        return known
