"""Results of a run: the state on the output grid, derived outputs, and the files they go to.

``results.csv``: header ``t``, the generalized coordinates, the generalized speeds (by name), then the
outputs of the groups that results.csv writes (:data:`flexkane.model.columns.GROUPS`: tip
deflections, efforts, loads, sensors and controllers; twists, attitude angles and quaternion norms;
angular momentum and energies), one row per output time. ``results.units.json``: the unit of each
column of results.csv, in its order (``{"t": "s", "q1": "rad", ...}``; null where the model fixes
none), to read beside the CSV (``pandas.read_csv`` takes no units). ``results.npz``: every output,
the declaration of each (unit, group, description), the state variables' units, the model file
text, the parameter values, solver statistics, the validity warnings and the flexkane version;
:func:`load_results` reads it back. Every array but ``timing`` (wall, compile and derive times) is
the same for the same model and options on any machine load.
"""

from __future__ import annotations

import io
import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ._version import __version__
from .atomic import atomic_write_bytes, atomic_write_text
from .model.columns import GROUPS, Output

__all__ = ["Results", "load_results", "csv_text"]
#: Entries of ``Results.solver`` that measure time: the only ones that vary between identical runs.
#: results.npz keeps them apart, in the array ``timing``.
TIMING_FIELDS = ("wall_time", "compile_time", "derive_time", "run_time")


@dataclass
class Results:
    """A run's results.

    Attributes
    ----------
    t : ndarray, shape (N,)
        Output times [s].
    state : ndarray, shape (N, n)
        Coordinates then speeds at the output times, one row per time (``y`` is its transpose,
        shape (n, N), as :func:`scipy.integrate.solve_ivp` gives it).
    state_names : list of str
        Names of the state columns.
    outputs : dict of str to ndarray, shape (N,)
        Derived outputs (energy [J], positions [m], tip deflections [m], efforts ...).
    model_text : str
        The model file text of the run (with overrides applied).
    parameters : dict of str to float
        Numeric values of the constants (parameters, field values, modal constants).
    solver : dict
        Method, tolerances, number of steps and evaluations, wall time, status and message.
    partial : bool
        True when the run stopped before the end time (failure or interruption).
    warnings : list of str
        Where the run left the validity of its model (a beam deflected by more than a stated
        fraction of its length, a beam spun fast without geometric stiffening), see
        :mod:`flexkane.validity`; empty when none.
    state_units : dict of str to str
        The unit of each state variable whose unit is known, by name (a controller state's only
        where the model fixes it).
    declared : dict of str to Output
        The declaration of each output (:class:`~flexkane.model.columns.Output` without its value:
        unit, group, description), by name; results.csv writes the outputs of the groups it
        writes, plots group them. An output without a declaration (results made by hand, a file
        of an older version) is in results.npz only.
    """

    t: np.ndarray
    state: np.ndarray
    state_names: list
    outputs: dict = field(default_factory=dict)
    model_text: str = ""
    parameters: dict = field(default_factory=dict)
    solver: dict = field(default_factory=dict)
    partial: bool = False
    version: str = __version__
    warnings: list = field(default_factory=list)
    state_units: dict = field(default_factory=dict)
    declared: dict = field(default_factory=dict)

    def __post_init__(self):
        taken = duplicate_columns(self.state_names, self.outputs)
        if taken:   # the validation refuses models whose names collide (flexkane.model.columns)
            from .model.columns import DuplicateColumnError

            raise DuplicateColumnError(f"internal error: the result column(s) {', '.join(taken)} were made twice")

    # ------------------------------------------------------- the conventions of scipy.integrate.solve_ivp
    @property
    def y(self) -> np.ndarray:
        """The states as :func:`scipy.integrate.solve_ivp` returns them, shape (n_states, N):
        ``y[k]`` is the history of ``state_names[k]`` (the transpose of :attr:`state`)."""
        return self.state.T

    @property
    def status(self) -> int:
        """0: the end time was reached; -1: the integration failed (step size, non-finite state, step
        budget, singular mass matrix); -2: interrupted (Ctrl-C or SIGTERM). As ``solve_ivp``'s
        ``status`` (which has no interruption); ``solver["status"]`` names the cause."""
        if not self.partial:
            return 0
        return -2 if self.solver.get("status") == "interrupted" else -1

    @property
    def success(self) -> bool:
        """True when the integration reached the end time (``status == 0``)."""
        return self.status == 0

    @property
    def message(self) -> str:
        """Why the integration stopped, or that it reached the end time."""
        return str(self.solver.get("message", ""))

    def to_dataframe(self):
        """The results as a :class:`pandas.DataFrame` (needs pandas: ``pip install 'flexkane[dataframe]'``).

        Returns
        -------
        pandas.DataFrame
            Index ``t`` [s] (N rows); columns: the states (``state_names``) then every output;
            ``attrs["units"]``: the unit of each column and of ``t`` (:attr:`units`).

        Raises
        ------
        flexkane.extras.MissingExtraError
            When pandas is not installed (the message says how to install it).
        """
        from .extras import require

        pandas = require("pandas")
        columns = {name: self.state[:, k] for k, name in enumerate(self.state_names)}
        columns.update((name, values) for name, values in self.outputs.items() if name not in columns)
        frame = pandas.DataFrame(columns, index=pandas.Index(self.t, name="t"))
        frame.attrs["units"] = self.units
        return frame

    def __getitem__(self, name: str) -> np.ndarray:
        """A state column or an output by name (``res["q3"]``, ``res["energy"]``)."""
        if name == "t":
            return self.t
        if name in self.state_names:
            return self.state[:, self.state_names.index(name)]
        if name in self.outputs:
            return self.outputs[name]
        raise KeyError(f"{name!r} is neither a state variable ({', '.join(self.state_names)}) nor an output "
                       f"({', '.join(self.outputs)})")

    @property
    def units(self) -> dict:
        """The unit of every column by name (``t``, the state variables, the outputs), None where it
        is not known (a controller state or output whose unit the model does not fix, an output
        without a declaration)."""
        out = {"t": "s"}
        out.update((name, self.state_units.get(name)) for name in self.state_names)
        out.update((name, self.declared[name].unit if name in self.declared else None) for name in self.outputs)
        return out

    def csv_columns(self) -> list[str]:
        """Column names of results.csv: ``t``, the state, then the outputs of the groups results.csv
        writes (:attr:`OutputGroup.csv <flexkane.model.columns.OutputGroup>`), by rank, each rank
        in the order of :attr:`outputs`."""
        ranked = [(GROUPS[self.declared[k].group].csv, k) for k in self.outputs if k in self.declared]
        ranks = sorted({rank for rank, _ in ranked if rank is not None})
        return ["t"] + list(self.state_names) + [k for r in ranks for rank, k in ranked if rank == r]

    def outputs_of(self, *groups: str) -> list[str]:
        """Names of the outputs declared in any of ``groups``, in the order of :attr:`outputs`."""
        return [k for k in self.outputs if k in self.declared and self.declared[k].group in groups]

    def write(self, directory: Path) -> list[Path]:
        """Write results.csv, results.units.json and results.npz into ``directory`` (atomically);
        return the paths. The directory is made when missing."""
        directory = Path(directory)
        directory.mkdir(parents=True, exist_ok=True)
        csv_path = directory / "results.csv"
        atomic_write_text(csv_path, csv_text(self))
        units_path = directory / "results.units.json"
        units = self.units
        atomic_write_text(units_path, json.dumps({name: units[name] for name in self.csv_columns()}, indent=1) + "\n")
        npz_path = directory / "results.npz"
        buffer = io.BytesIO()
        arrays = {"t": self.t, "state": self.state,
                  "state_names": np.array(self.state_names, dtype=str),
                  "output_names": np.array(list(self.outputs), dtype=str),
                  "outputs": np.array([self.outputs[k] for k in self.outputs],
                                      dtype=float).reshape(len(self.outputs), len(self.t)),
                  "model_text": np.array(self.model_text),
                  "parameters": np.array(json.dumps(self.parameters, sort_keys=True)),
                  "solver": np.array(json.dumps({k: v for k, v in self.solver.items() if k not in TIMING_FIELDS},
                                                sort_keys=True, default=str)),
                  "timing": np.array(json.dumps({k: v for k, v in self.solver.items() if k in TIMING_FIELDS},
                                                sort_keys=True, default=str)),
                  "partial": np.array(self.partial), "version": np.array(self.version),
                  "warnings": np.array(json.dumps(list(self.warnings))),
                  "output_declarations": np.array(json.dumps([self.declared[k].to_json() for k in self.outputs
                                                              if k in self.declared])),
                  "state_units": np.array(json.dumps({k: self.state_units[k] for k in self.state_names
                                                      if k in self.state_units}))}
        _savez_fixed_dates(buffer, arrays)
        atomic_write_bytes(npz_path, buffer.getvalue())
        return [csv_path, units_path, npz_path]


def duplicate_columns(state_names, output_names) -> list[str]:
    """Names given to more than one column of the results (``t``, the states, the outputs), sorted."""
    names = ["t", *state_names, *output_names]
    return sorted({name for name in names if names.count(name) > 1})


def _savez_fixed_dates(buffer, arrays: dict) -> None:
    """``numpy.savez`` with a fixed date on every member, so that equal arrays give equal bytes."""
    import zipfile

    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_STORED, allowZip64=True) as archive:
        for name, value in arrays.items():
            member = io.BytesIO()
            np.lib.format.write_array(member, np.asanyarray(value), allow_pickle=False)
            info = zipfile.ZipInfo(f"{name}.npy", date_time=(1980, 1, 1, 0, 0, 0))
            archive.writestr(info, member.getvalue())


def _fmt(x: float) -> str:
    return repr(float(x))


def csv_text(results: Results) -> str:
    """results.csv as text: shortest round-trip representation of each number (deterministic)."""
    cols = results.csv_columns()
    data = np.column_stack([results[c] for c in cols])
    lines = [",".join(cols)]
    lines += [",".join(_fmt(v) for v in row) for row in data]
    if results.partial:
        lines.append(f"# partial: {results.solver.get('message', 'stopped early')}")
    return "\n".join(lines) + "\n"


#: Arrays of results.npz: name -> (dtype kinds accepted, number of dimensions).
NPZ_ARRAYS = {"t": ("f", 1), "state": ("f", 2), "state_names": ("U", 1), "output_names": ("U", 1),
              "outputs": ("f", 2), "model_text": ("U", 0), "parameters": ("U", 0), "solver": ("U", 0),
              "partial": ("b", 0), "version": ("U", 0)}
#: Arrays that files of older versions lack, with their kind and rank.
OPTIONAL_NPZ_ARRAYS = {"warnings": ("U", 0), "timing": ("U", 0), "output_declarations": ("U", 0),
                       "state_units": ("U", 0)}
_ZIP_MAGIC = b"PK\x03\x04"
_NPY_MAGIC = b"\x93NUMPY"


def _read_arrays(path: Path) -> dict:
    """Every array of ``NPZ_ARRAYS`` from the archive at ``path``, checked for dtype and rank.

    Raises
    ------
    ResultsError
        If the file is not a ZIP archive, is truncated or damaged (a bad CRC, a broken header),
        or an array is missing or has the wrong kind or number of dimensions.
    """
    from .errors import ResultsError

    try:
        with open(path, "rb") as handle:
            magic = handle.read(len(_NPY_MAGIC))
    except OSError as exc:
        raise ResultsError(path, f"cannot be opened ({exc.strerror or exc})") from None
    if magic.startswith(_NPY_MAGIC):
        raise ResultsError(path, "it is a single NumPy array (.npy), not a results archive (.npz)")
    if not magic.startswith(_ZIP_MAGIC):
        raise ResultsError(path, "it is not an NPZ (ZIP) archive" + (" (the file is empty)" if not magic else ""))
    arrays = {}
    try:
        with np.load(path, allow_pickle=False) as data:
            missing = [name for name in NPZ_ARRAYS if name not in data.files]
            if missing:
                held = ", ".join(map(repr, data.files)) or "nothing"
                raise ResultsError(path, f"array{'s' if len(missing) > 1 else ''} {', '.join(map(repr, missing))} "
                                         f"missing (the archive holds {held}); it is incomplete or not written "
                                         "by flexkane")
            for name in NPZ_ARRAYS:
                arrays[name] = data[name]
            for name in OPTIONAL_NPZ_ARRAYS:   # absent from files written before they existed
                if name in data.files:
                    arrays[name] = data[name]
    except ResultsError:
        raise
    except (Exception, MemoryError) as exc:  # noqa: BLE001 - zipfile, NumPy and OS errors of a damaged file
        reason = str(exc) or type(exc).__name__
        raise ResultsError(path, f"it is truncated or damaged ({type(exc).__name__}: {reason})") from None
    for name, (kinds, ndim) in {**NPZ_ARRAYS, **OPTIONAL_NPZ_ARRAYS}.items():
        if name not in arrays:
            continue
        value = arrays[name]
        if value.dtype.kind not in kinds or value.ndim != ndim:
            expected = {"f": "floating-point numbers", "U": "text", "b": "a boolean"}[kinds]
            raise ResultsError(path, f"array {name!r} should hold {expected} with {ndim} dimension(s), "
                                     f"it holds {value.dtype} with shape {value.shape}")
    return arrays


def load_results(path: str | Path) -> Results:
    """Read ``results.npz`` (or the directory that holds it) back into :class:`Results`.

    Parameters
    ----------
    path : str or pathlib.Path
        A run directory or its ``results.npz``.

    Returns
    -------
    Results

    Raises
    ------
    ModelError
        If there is no such file.
    ResultsError
        If the file is not a complete, consistent results archive: not an NPZ, truncated,
        damaged (a flipped byte fails a CRC or a header), an array missing, of the wrong type, or of
        a shape inconsistent with the others (``state`` (N, n) for ``t`` (N,) and ``n`` state
        names, ``outputs`` (k, N) for ``k`` output names), or metadata that is not JSON. Never a
        pickle: the file is read with ``allow_pickle=False``.
    """
    from .errors import ModelError, ResultsError

    path = Path(path)
    if path.is_dir():
        path = path / "results.npz"
    if not path.is_file():
        raise ModelError("RUN_DIR", "a run directory holding results.npz (or the file itself)", str(path))
    data = _read_arrays(path)
    t, state, outputs = data["t"], data["state"], data["outputs"]
    state_names = [str(n) for n in data["state_names"]]
    names = [str(n) for n in data["output_names"]]
    n_rows = t.shape[0]
    if state.shape != (n_rows, len(state_names)):
        raise ResultsError(path, f"array 'state' has shape {state.shape}, expected ({n_rows}, {len(state_names)}) "
                                 f"for {n_rows} output times and {len(state_names)} state names")
    if outputs.shape[0] != len(names) or (names and outputs.shape[1] != n_rows):
        raise ResultsError(path, f"array 'outputs' has shape {outputs.shape}, expected ({len(names)}, {n_rows}) "
                                 f"for {len(names)} output names and {n_rows} output times")
    taken = duplicate_columns(state_names, names)
    if taken:
        raise ResultsError(path, f"it names several columns alike ({', '.join(taken)}): not written by this flexkane")
    metadata = {"warnings": [], "timing": {}, "output_declarations": [], "state_units": {}}
    for key in ("parameters", "solver", "timing", "warnings", "output_declarations", "state_units"):
        if key not in data:
            continue
        try:
            metadata[key] = json.loads(str(data[key]))
        except ValueError as exc:
            raise ResultsError(path, f"array {key!r} is not JSON ({exc})") from None
        kind = list if key in ("warnings", "output_declarations") else dict
        if not isinstance(metadata[key], kind):
            raise ResultsError(path, f"array {key!r} should be a JSON {'list' if kind is list else 'object'}, "
                                     f"it is {type(metadata[key]).__name__}")
    return Results(t=t, state=state, state_names=state_names,
                   outputs={n: outputs[i] for i, n in enumerate(names)}, model_text=str(data["model_text"]),
                   parameters=metadata["parameters"], solver={**metadata["solver"], **metadata["timing"]},
                   partial=bool(data["partial"]), version=str(data["version"]),
                   warnings=[str(w) for w in metadata["warnings"]],
                   declared=_declarations(path, metadata["output_declarations"], names),
                   state_units=_state_units(path, metadata["state_units"], state_names))


def _state_units(path: Path, units: dict, state_names: list) -> dict:
    """The state variables' units of results.npz, checked: texts, for state variables of the file."""
    from .errors import ResultsError

    for name, unit in units.items():
        if name not in state_names or not isinstance(unit, str):
            raise ResultsError(path, f"array 'state_units' gives {name!r} the unit {unit!r}: not a text for a "
                                     "state variable of the file")
    return units


def _declarations(path: Path, entries: list, names: list) -> dict:
    """The outputs' declarations of results.npz (``[name, unit, group, description]`` each) by name.

    Raises
    ------
    ResultsError
        For an entry that is not such a list, names no output of the file or names one twice.
    """
    from .errors import ResultsError

    declared = {}
    for entry in entries:
        try:
            output = Output.from_json(entry)
            if not all(isinstance(x, str) for x in (output.name, output.group, output.description)) or \
                    not isinstance(output.unit, (str, type(None))):
                raise ValueError("a text is not a text")
        except (TypeError, ValueError) as exc:
            raise ResultsError(path, f"array 'output_declarations' holds {entry!r}, not [name, unit, group, "
                                     f"description] of a known group ({exc})") from None
        if output.name not in names or output.name in declared:
            raise ResultsError(path, f"array 'output_declarations' declares {output.name!r} "
                                     + ("twice" if output.name in declared else "which is not an output of the file"))
        declared[output.name] = output
    return declared
