"""Variants of a sweep: the assignments of the varied keys, the models they give, their ids.

A variant is identified by a hash of everything that determines its result: the base model's file
text, the assignments (sorted by key) and the run settings (end time, output interval, tolerances,
method). Re-running a sweep therefore recognises the variants it has already computed, whatever
their position in the sweep, and a changed base model or setting gives new ids (nothing stale is
reused).
"""

from __future__ import annotations

import hashlib
import itertools
import json
from collections.abc import Iterator
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..errors import ModelError
from ..model import Model, dumps_model
from ..model.paths import get_value, parse_path, set_value
from ..model.validate import validate_run_arguments
from .spec import SweepSpec

__all__ = ["Variant", "RunSettings", "key_kind", "check_keys", "check_sweep", "make_assignments",
           "apply_assignments", "variant_id", "make_variants"]

_ID_LENGTH = 16  # hex digits of sha256 (64 bits)


@dataclass(frozen=True)
class RunSettings:
    """Integration settings shared by every variant of a sweep.

    Parameters
    ----------
    t_end : float
        End time [s].
    dt_out : float
        Output interval [s].
    rtol, atol : float
        Integrator tolerances [-].
    method : str
        ``auto``, ``dop853`` or ``radau``.
    max_steps : int, optional
        Most integration steps of a variant (the variant's ``simulation.max_steps``, else 1,000,000,
        when None).
    """

    t_end: float
    dt_out: float
    rtol: float
    atol: float
    method: str
    max_steps: int | None = None

    @classmethod
    def resolve(cls, spec: SweepSpec, model: Model) -> "RunSettings":
        """The spec's settings, else the model's ``[simulation]`` ones (``dt_out``: ``t_end / 100``)."""
        sim = model.simulation
        t_end = spec.t_end if spec.t_end is not None else sim.t_end
        if t_end is None:
            raise ModelError("t_end", "an end time [s] (the model has no simulation.t_end)", None,
                             show_given=False)
        dt_out = spec.dt_out if spec.dt_out is not None else (sim.dt_out or t_end / 100)
        method = spec.method or sim.method
        settings = cls(t_end=float(t_end), dt_out=float(dt_out),
                       rtol=float(spec.rtol if spec.rtol is not None else sim.rtol),
                       atol=float(spec.atol if spec.atol is not None else sim.atol),
                       method=method, max_steps=spec.max_steps if spec.max_steps is not None else sim.max_steps)
        validate_run_arguments(**settings.as_dict())   # output grid bounded before anything runs
        return settings

    def as_dict(self) -> dict:
        """The settings by name (``max_steps`` only when set, so that the ids of sweeps without it
        stay those they had)."""
        settings = {"t_end": self.t_end, "dt_out": self.dt_out, "rtol": self.rtol, "atol": self.atol,
                    "method": self.method}
        if self.max_steps is not None:
            settings["max_steps"] = self.max_steps
        return settings


@dataclass(frozen=True)
class Variant:
    """One point of a sweep.

    Attributes
    ----------
    index : int
        Position in the sweep (table order).
    assignments : tuple of (str, object)
        Value of each varied key, in the order of the spec.
    id : str
        Hash of the base model text, the assignments and the run settings (16 hex digits).
    base : Model
        The sweep's base model (shared by every variant).
    """

    index: int
    assignments: tuple
    id: str
    base: Model

    @cached_property
    def model(self) -> Model:
        """The base model with the assignments applied (not validated)."""
        return apply_assignments(self.base, self.assignments)


def key_kind(model: Model, key: str) -> str:
    """``"parameter"``, ``"initial"`` or ``"field"``: what ``set_value`` changes for ``key``.

    A bare name is a parameter when the model has one of that name, else an initial condition.
    """
    parts = parse_path(key)
    if len(parts) == 1:
        return "parameter" if parts[0] in model.parameters else "initial"
    if len(parts) == 2 and parts[0] == "parameters":
        return "parameter"
    if len(parts) == 2 and parts[0] == "initial":
        return "initial"
    return "field"


def check_keys(model: Model, spec: SweepSpec) -> set[str]:
    """Check that every varied key exists in the model; return the keys that hold integers.

    Initial conditions are checked against the coordinates and speeds once the equations are
    derived (:func:`flexkane.sweep.runner.run_sweep`).

    Returns
    -------
    set of str
        Keys whose value is an integer count (``beams.B.n_modes``): their ranges give integers.
    """
    from .store import FIXED_COLUMNS

    reserved = {"variant", "index", "status", "error", *FIXED_COLUMNS}
    integer = set()
    for vary in spec.vary:
        if vary.key in reserved or vary.key.startswith(("max_abs_", "final_")):
            raise ModelError(f"vary {vary.key}", "a key that is not the name of a table column",
                             vary.key, f"write parameters.{vary.key} or initial.{vary.key}")
        kind = key_kind(model, vary.key)
        if kind == "parameter":
            name = parse_path(vary.key)[-1]
            if name not in model.parameters:
                raise ModelError(f"vary {vary.key}", f"a parameter of the model "
                                 f"({', '.join(model.parameters) or 'none'})", name)
        elif kind == "field":
            value = get_value(model, vary.key)
            last = parse_path(vary.key)[-1]
            if isinstance(value, int) and not isinstance(value, bool) and str(last).startswith("n_"):
                integer.add(vary.key)
    return integer


def make_assignments(spec: SweepSpec, integer_keys: set[str] = frozenset()) -> Iterator[tuple]:
    """The assignments of every variant, in sweep order, generated one at a time.

    The number of variants is bounded by :data:`~flexkane.limits.MAX_VARIANTS` (checked by
    :class:`~flexkane.sweep.spec.SweepSpec`); a grid is never built as a whole.

    Parameters
    ----------
    spec : SweepSpec
    integer_keys : set of str
        Keys whose values are integers (see :func:`check_keys`).

    Yields
    ------
    tuple of (str, object)
        Grid: every combination, the last key varying fastest. Random: ``spec.samples`` draws from
        ``numpy.random.default_rng(spec.seed)``, key by key in the spec's order.
    """
    if not spec.vary:
        yield ()
        return
    keys = [v.key for v in spec.vary]
    if spec.sampling == "grid":
        columns = [v.grid_values(v.key in integer_keys) for v in spec.vary]
        for combo in itertools.product(*columns):
            yield tuple(zip(keys, combo))
        return
    rng = np.random.default_rng(spec.seed)
    columns = [v.random_values(rng, spec.samples, v.key in integer_keys) for v in spec.vary]
    for row in zip(*columns):
        yield tuple(zip(keys, row))


def check_sweep(model: Model, spec: SweepSpec, settings: RunSettings) -> int:
    """Check a sweep without running it (``flexkane check`` of a model file with a ``[sweep]`` table).

    Checks the varied keys and the values of each (a grid's ranges give whole numbers for integer
    keys; ``settings`` were checked by :meth:`RunSettings.resolve`), and validates the model with
    every key at the first,
    then at the last of its values.

    Returns
    -------
    int
        Number of variants (before duplicate random draws are dropped).

    Raises
    ------
    ModelError
        Naming the key and the value at fault.
    """
    integer_keys = check_keys(model, spec)
    if spec.sampling == "grid":
        columns = [v.grid_values(v.key in integer_keys) for v in spec.vary]
    else:
        columns = [list(v.values) if not v.is_range else [v.start, v.stop] for v in spec.vary]
    for end in (0, -1):
        assignments = tuple((v.key, column[end]) for v, column in zip(spec.vary, columns)
                            if v.key.split(".")[0] != "initial" and key_kind(model, v.key) != "initial")
        try:
            apply_assignments(model, assignments).validate()
        except ModelError as exc:
            shown = ", ".join(f"{k}={val}" for k, val in assignments)
            raise ModelError(exc.path, exc.expected, exc.given,
                             f"with the sweep's values {shown}" + (f"; {exc.hint}" if exc.hint else "")) from None
    return spec.variant_count or 1


def apply_assignments(model: Model, assignments: tuple) -> Model:
    """A copy of ``model`` with each ``(key, value)`` set (see :func:`flexkane.model.paths.set_value`)."""
    variant = model.copy()
    for key, value in assignments:
        if key_kind(model, key) == "field" and str(parse_path(key)[-1]).startswith("n_"):
            if isinstance(value, float) and value.is_integer():
                value = int(value)
        set_value(variant, key, value)
    return variant


def variant_id(base_text: str, assignments: tuple, settings: RunSettings) -> str:
    """Hash (16 hex digits) of a base model's text, assignments and run settings."""
    text = json.dumps({"model": base_text, "assignments": sorted([k, v] for k, v in assignments),
                       **settings.as_dict()}, sort_keys=True)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:_ID_LENGTH]


def make_variants(model: Model, spec: SweepSpec, settings: RunSettings) -> list[Variant]:
    """Every variant of a sweep, in order (see :func:`make_assignments`).

    A random draw identical to an earlier one (likely when every key takes values from a short
    list) is dropped: each variant is computed once.

    Raises
    ------
    ModelError
        If a key does not exist in the model, or a grid holds the same variant twice (a value
        listed twice).
    """
    integer_keys = check_keys(model, spec)
    base_text = dumps_model(model)
    variants, seen = [], {}
    for index, assignments in enumerate(make_assignments(spec, integer_keys)):
        # 20 and 20.0 are the same value of a physical field: one variant, one id
        assignments = tuple((key, float(value) if key not in integer_keys and isinstance(value, int)
                             and not isinstance(value, bool) else value) for key, value in assignments)
        vid = variant_id(base_text, assignments, settings)
        if vid in seen and spec.sampling == "grid":
            raise ModelError("vary", "distinct variants (no value listed twice)",
                             ", ".join(f"{k}={v}" for k, v in assignments),
                             f"the same as variant {seen[vid]}")
        if vid in seen:
            continue  # a random draw that repeats an earlier one is computed once
        seen[vid] = index
        variants.append(Variant(index=len(variants), assignments=assignments, id=vid, base=model))
    return variants
