"""What a sweep varies and how: ``--vary KEY=...`` options and the ``[sweep]`` table of a model file.

A varied key is a model key path (:mod:`flexkane.model.paths`): ``beams.arm.EI``, ``initial.q3``,
``parameters.L`` or a bare parameter or coordinate name. Its values are given as

* a range ``START:STOP:COUNT`` (``COUNT`` evenly spaced values, both ends included), or
  ``START:STOP:COUNT:log`` (geometric spacing); with random sampling a range is the interval the
  values are drawn from (uniformly, or log-uniformly) and ``COUNT`` may be left out;
* a list ``v1,v2,...`` of numbers, ``true``/``false`` or expression strings (a single value is a
  list of one).

In a model file::

    [sweep]
    sampling = "grid"              # or "random", with samples = N and seed = S
    t_end = 0.5                    # optional overrides of [simulation]: t_end, dt_out, rtol, atol, method
    save_trajectories = false
    metric = "max_abs_tip_B"       # plotted by --plot

    [sweep.vary]
    "beams.B.EI" = "20:80:4"       # a range, as on the command line
    g = [0.0, 9.81]                # a list of values
    "initial.q3" = { start = 0.5, stop = 1.5, count = 3, scale = "linear" }
"""

from __future__ import annotations

import difflib
import math
import re
import tomllib
from dataclasses import dataclass, replace

import numpy as np

from ..errors import ModelError
from ..limits import MAX_VARIANTS, check_count

__all__ = ["Vary", "SweepSpec", "SAMPLINGS", "MAX_VARIANTS", "sweep_spec_from_toml", "split_values"]

#: Ways to turn the varied values into variants.
SAMPLINGS = ("grid", "random")
_SCALES = ("linear", "log")
_NUMBER = re.compile(r"^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$")
_INT = re.compile(r"^[+-]?\d+$")
_SPEC_KEYS = ("sampling", "samples", "seed", "t_end", "dt_out", "rtol", "atol", "method", "max_steps",
              "save_trajectories", "metric", "vary")
_RANGE_KEYS = ("start", "stop", "count", "scale")


def _scalar(text: str, where: str):
    """A value written on the command line: int, float, bool or expression text."""
    text = text.strip()
    if not text:
        raise ModelError(where, "a value (number, true/false or expression)", text)
    if _INT.match(text):
        return int(text)
    if _NUMBER.match(text):
        number = float(text)
        if not math.isfinite(number):
            raise ModelError(where, "a finite number", text)
        return number
    if text in ("true", "false"):
        return text == "true"
    return text


def split_values(text: str) -> list[str]:
    """Split ``v1,v2,...`` at commas outside parentheses (``min(a, b)`` stays one value)."""
    parts, depth, current = [], 0, []
    for char in text:
        if char == "(":
            depth += 1
        elif char == ")":
            depth -= 1
        if char == "," and depth == 0:
            parts.append("".join(current))
            current = []
        else:
            current.append(char)
    parts.append("".join(current))
    return parts


def _finite(value, where: str, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ModelError(where, f"a finite number ({what})", value)
    return value


@dataclass(frozen=True)
class Vary:
    """The values one key takes in a sweep.

    Either ``values`` (an explicit list) or a range ``start``, ``stop``, ``count``, ``scale``.

    Parameters
    ----------
    key : str
        Model key path, e.g. ``"beams.B.EI"``, ``"initial.q3"`` or ``"g"``.
    values : tuple, optional
        Explicit values (numbers, booleans or expression strings), in their units.
    start, stop : int or float, optional
        Ends of the range, both included in a grid, in the key's unit.
    count : int, optional
        Number of grid values (required for grid sampling of a range).
    scale : {"linear", "log"}
        Spacing of the grid values, or distribution of random draws.
    """

    key: str
    values: tuple | None = None
    start: int | float | None = None
    stop: int | float | None = None
    count: int | None = None
    scale: str = "linear"

    def __post_init__(self):
        where = f"vary {self.key}"
        if not isinstance(self.key, str) or not self.key.strip():
            raise ModelError("vary", "KEY=VALUES with a non-empty key", self.key)
        if self.values is not None:
            if self.start is not None or self.stop is not None or self.count is not None:
                raise ModelError(where, "either a list of values or a range START:STOP:COUNT, not both",
                                 self.values)
            if not self.values:
                raise ModelError(where, "at least one value", list(self.values))
            object.__setattr__(self, "values", tuple(self.values))
            for value in self.values:
                if isinstance(value, float) and not math.isfinite(value):
                    raise ModelError(where, "finite values", value)
                if not isinstance(value, (int, float, str)):
                    raise ModelError(where, "numbers, true/false or expression strings", value)
            return
        if self.start is None or self.stop is None:
            raise ModelError(where, "a list v1,v2,... or a range START:STOP:COUNT", None, show_given=False)
        _finite(self.start, where, "START")
        _finite(self.stop, where, "STOP")
        if self.count is not None and (isinstance(self.count, bool) or not isinstance(self.count, int)
                                       or self.count < 1):
            raise ModelError(where, "a positive integer COUNT of values", self.count)
        if self.count is not None:
            check_count(self.count, where, "a COUNT of at most {limit} values (the largest sweep)")
        if self.scale not in _SCALES:
            raise ModelError(where, f"a scale among {', '.join(_SCALES)}", self.scale)
        if self.scale == "log" and (self.start <= 0 or self.stop <= 0):
            raise ModelError(where, "positive START and STOP for a log scale", f"{self.start}:{self.stop}")

    @property
    def size(self) -> int | None:
        """Number of grid values (None for a range without COUNT, which only random sampling takes)."""
        return len(self.values) if self.values is not None else self.count

    @property
    def is_range(self) -> bool:
        """True for a range, False for an explicit list of values."""
        return self.values is None

    @classmethod
    def parse(cls, text: str) -> "Vary":
        """Parse ``KEY=START:STOP:COUNT[:log]``, ``KEY=START:STOP[:log]`` (random only) or ``KEY=v1,v2``.

        Parameters
        ----------
        text : str
            The argument of ``--vary``.

        Returns
        -------
        Vary
        """
        if "=" not in text:
            raise ModelError("vary", "KEY=START:STOP:COUNT or KEY=v1,v2,...", text)
        key, spec = (part.strip() for part in text.split("=", 1))
        if not key or not spec:
            raise ModelError("vary", "KEY=VALUES with a non-empty key and values", text)
        return cls.from_text(key, spec)

    @classmethod
    def from_text(cls, key: str, spec: str) -> "Vary":
        """The values of ``key`` from the text after ``=`` (see :meth:`parse`)."""
        where = f"vary {key}"
        if ":" in spec and "(" not in spec:
            parts = [p.strip() for p in spec.split(":")]
            scale = "linear"
            if parts[-1] in _SCALES:
                scale = parts.pop()
            if len(parts) not in (2, 3) or not all(_NUMBER.match(p) for p in parts[:2]):
                raise ModelError(where, "START:STOP:COUNT with numbers START, STOP and an integer COUNT",
                                 spec)
            if len(parts) == 3 and not (_INT.match(parts[2]) and int(parts[2]) >= 1):
                raise ModelError(where, "an integer COUNT >= 1 in START:STOP:COUNT", spec)
            start, stop = (_scalar(p, where) for p in parts[:2])
            count = int(parts[2]) if len(parts) == 3 else None
            return cls(key, start=start, stop=stop, count=count, scale=scale)
        return cls(key, values=tuple(_scalar(v, where) for v in split_values(spec)))

    def grid_values(self, integer: bool = False) -> list:
        """The values of a grid sweep.

        Parameters
        ----------
        integer : bool
            The key holds an integer (``n_modes``): range values must be whole numbers.

        Returns
        -------
        list
            Python numbers (or the explicit values as given).
        """
        if not self.is_range:
            return list(self.values)
        if self.count is None:
            raise ModelError(f"vary {self.key}", "START:STOP:COUNT (a grid needs COUNT)",
                             f"{self.start}:{self.stop}")
        if self.scale == "log":
            values = np.geomspace(self.start, self.stop, self.count)
        else:
            values = np.linspace(self.start, self.stop, self.count)
        if integer:
            if not np.allclose(values, np.round(values), rtol=0, atol=1e-9):
                raise ModelError(f"vary {self.key}", "a range of whole numbers (the key is an integer)",
                                 f"{self.start}:{self.stop}:{self.count}")
            return [int(round(v)) for v in values]
        return [float(v) for v in values]

    def random_values(self, rng: np.random.Generator, n: int, integer: bool = False) -> list:
        """``n`` values drawn with ``rng``: uniform (or log-uniform) in a range, uniform over a list."""
        if not self.is_range:
            picks = rng.integers(0, len(self.values), size=n)
            return [self.values[int(i)] for i in picks]
        low, high = sorted((self.start, self.stop))
        if integer:
            return [int(v) for v in rng.integers(int(math.ceil(low)), int(math.floor(high)) + 1, size=n)]
        if self.scale == "log":
            return [float(v) for v in np.exp(rng.uniform(math.log(low), math.log(high), size=n))]
        return [float(v) for v in rng.uniform(low, high, size=n)]

    def describe(self) -> str:
        """The command-line form, e.g. ``beams.B.EI=20:80:4``."""
        if not self.is_range:
            return f"{self.key}=" + ",".join(str(v).lower() if isinstance(v, bool) else str(v)
                                             for v in self.values)
        count = f":{self.count}" if self.count is not None else ""
        scale = ":log" if self.scale == "log" else ""
        return f"{self.key}={self.start}:{self.stop}{count}{scale}"


@dataclass(frozen=True)
class SweepSpec:
    """A parameter sweep: varied keys, sampling, and run settings.

    Parameters
    ----------
    vary : tuple of Vary
        The varied keys, in order (a grid varies the last one fastest); ``KEY=VALUES`` strings
        are parsed with :meth:`Vary.parse`.
    sampling : {"grid", "random"}
        Every combination of the values, or ``samples`` random draws.
    samples : int, optional
        Number of random variants (random sampling).
    seed : int, optional
        Seed of the random draws (required by random sampling: the same seed gives the same
        variants, which is what resuming needs).
    t_end : float, optional
        End time [s]; the model's ``[simulation]`` value when omitted.
    dt_out : float, optional
        Output interval [s]; the model's, else ``t_end / 100``.
    rtol, atol : float, optional
        Integrator tolerances [-]; the model's when omitted.
    method : str, optional
        ``auto``, ``dop853`` or ``radau``; the model's when omitted.
    max_steps : int, optional
        Most integration steps of each variant; the model's ``simulation.max_steps`` when omitted.
    save_trajectories : bool
        Keep each variant's results (``variants/<id>/results.npz`` and ``results.csv``).
    metric : str, optional
        Table column plotted by ``--plot``.
    """

    vary: tuple = ()
    sampling: str = "grid"
    samples: int | None = None
    seed: int | None = None
    t_end: float | None = None
    dt_out: float | None = None
    rtol: float | None = None
    atol: float | None = None
    method: str | None = None
    max_steps: int | None = None
    save_trajectories: bool = False
    metric: str | None = None

    def __post_init__(self):
        vary = tuple(Vary.parse(v) if isinstance(v, str) else v for v in self.vary)
        for v in vary:
            if not isinstance(v, Vary):
                raise ModelError("vary", "Vary objects or KEY=VALUES strings", v)
        object.__setattr__(self, "vary", vary)
        keys = [v.key for v in vary]
        for key in keys:
            if keys.count(key) > 1:
                raise ModelError(f"vary {key}", "each key varied once", f"{keys.count(key)} times")
        if self.sampling not in SAMPLINGS:
            raise ModelError("sweep.sampling", f"one of {', '.join(SAMPLINGS)}", self.sampling)
        if self.sampling == "random":
            if isinstance(self.samples, bool) or not isinstance(self.samples, int) or self.samples < 1:
                raise ModelError("samples", "a positive number of random variants N", self.samples)
            if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
                raise ModelError("seed", "a non-negative integer seed with random sampling (the same seed "
                                 "regenerates the same variants, which is what resuming needs)", self.seed)
        count = self.variant_count
        if count is not None:
            what = "samples" if self.sampling == "random" else "vary"
            check_count(count, what, "a sweep of at most {limit} variants",
                        f"{count:,} variants" if count < 10**30 else f"{count:.3g} variants")
        from ..model.validate import RUN_SETTINGS, validate_run_arguments

        validate_run_arguments(t_end=self.t_end, dt_out=self.dt_out, rtol=self.rtol, atol=self.atol,
                               method=self.method, max_steps=self.max_steps, optional=RUN_SETTINGS)

    @property
    def variant_count(self) -> int | None:
        """Number of variants before duplicates are dropped (None while a grid range lacks COUNT)."""
        if self.sampling == "random":
            return self.samples
        sizes = [v.size for v in self.vary]
        return None if None in sizes else math.prod(sizes)

    def merged(self, other: "SweepSpec") -> "SweepSpec":
        """This spec (from a model file) overridden by ``other`` (from the command line).

        Varied keys of ``other`` replace those of the same key and are appended otherwise; its run
        settings and metric replace those given here when they are not ``None``, and
        ``save_trajectories`` when true. Sampling is kept (the command line sets it with
        :func:`dataclasses.replace`).
        """
        vary = {v.key: v for v in self.vary}
        vary.update({v.key: v for v in other.vary})
        changes = {"vary": tuple(vary.values())}
        for name in ("t_end", "dt_out", "rtol", "atol", "method", "max_steps", "metric"):
            if getattr(other, name) is not None:
                changes[name] = getattr(other, name)
        if other.save_trajectories:
            changes["save_trajectories"] = True
        return replace(self, **changes)


def _nearest(name: str, options) -> str | None:
    close = difflib.get_close_matches(str(name), options, n=1, cutoff=0.6)
    return f"did you mean {close[0]!r}?" if close else None


def _vary_from_toml(key: str, value) -> Vary:
    if isinstance(value, str):
        return Vary.from_text(key, value)
    if isinstance(value, list):
        return Vary(key, values=tuple(value))
    if isinstance(value, dict):
        for name in value:
            if name not in _RANGE_KEYS:
                raise ModelError(f"sweep.vary.{key}.{name}", f"one of {', '.join(_RANGE_KEYS)}", name,
                                 _nearest(name, _RANGE_KEYS))
        return Vary(key, start=value.get("start"), stop=value.get("stop"), count=value.get("count"),
                    scale=value.get("scale", "linear"))
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return Vary(key, values=(value,))
    raise ModelError(f"sweep.vary.{key}", "\"START:STOP:COUNT\", a list of values or { start, stop, count }",
                     value)


#: Command-line names of the settings in errors raised by SweepSpec, and their [sweep] keys.
_FILE_PATHS = {"vary": "sweep.vary", "samples": "sweep.samples", "seed": "sweep.seed", "t_end": "sweep.t_end",
               "dt_out": "sweep.dt_out", "rtol": "sweep.rtol", "atol": "sweep.atol", "max_steps": "sweep.max_steps"}


def sweep_spec_from_toml(text: str) -> SweepSpec | None:
    """The ``[sweep]`` table of a model file, or ``None`` when it has none.

    Parameters
    ----------
    text : str
        The model file's text.

    Returns
    -------
    SweepSpec or None
    """
    try:
        table = tomllib.loads(text).get("sweep")
    except tomllib.TOMLDecodeError as exc:
        raise ModelError("MODEL", "a valid TOML model file", str(exc)) from None
    if table is None:
        return None
    if not isinstance(table, dict):
        raise ModelError("sweep", "a table", table)
    for key in table:
        if key not in _SPEC_KEYS:
            raise ModelError(f"sweep.{key}", f"one of {', '.join(_SPEC_KEYS)}", key, _nearest(key, _SPEC_KEYS))
    vary_table = table.get("vary", {})
    if not isinstance(vary_table, dict):
        raise ModelError("sweep.vary", "a table of KEY = values", vary_table)
    vary = []
    for key, value in vary_table.items():
        try:
            vary.append(_vary_from_toml(key, value))
        except ModelError as exc:
            path = exc.path if exc.path.startswith("sweep.") else f"sweep.vary.{key}"
            raise ModelError(path, exc.expected, exc.given, exc.hint) from None
    try:
        return SweepSpec(vary=tuple(vary), **{k: v for k, v in table.items() if k != "vary"})
    except ModelError as exc:
        raise ModelError(_FILE_PATHS.get(exc.path, exc.path), exc.expected, exc.given, exc.hint) from None
