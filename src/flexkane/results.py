"""Results of a run: the state on the output grid, derived outputs, and the files they go to.

``results.csv``: header ``t``, the generalized coordinates, the generalized speeds (by name), then the
outputs of :mod:`flexkane.kane.outputs` (tip deflections, energy, ...), one row per output time.
``results.npz``: the same arrays, the model file text, the parameter values, solver statistics and the
flexkane version; :func:`load_results` reads it back. Every array but ``timing`` (wall, compile and
derive times) is the same for the same model and options on any machine load.
"""

from __future__ import annotations

import io
import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import __version__
from .atomic import atomic_write_bytes, atomic_write_text

__all__ = ["Results", "load_results", "csv_text"]

#: Output columns written to results.csv after the state, when present.
CSV_OUTPUTS_PREFIXES = ("tip_", "effort_")
CSV_OUTPUTS = ("kinetic", "potential_gravity", "strain", "potential_springs", "energy", "work",
               "energy_balance")
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
        Coordinates then speeds at the output times.
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

    def csv_columns(self) -> list[str]:
        """Column names of results.csv."""
        extra = [k for k in self.outputs if k.startswith(CSV_OUTPUTS_PREFIXES)]
        extra += [k for k in CSV_OUTPUTS if k in self.outputs]
        return ["t"] + list(self.state_names) + extra

    def write(self, directory: Path) -> list[Path]:
        """Write results.csv and results.npz into ``directory`` (atomically); return the paths."""
        directory = Path(directory)
        csv_path = directory / "results.csv"
        atomic_write_text(csv_path, csv_text(self))
        npz_path = directory / "results.npz"
        buffer = io.BytesIO()
        arrays = {"t": self.t, "state": self.state,
                  "state_names": np.array(self.state_names, dtype=str),
                  "output_names": np.array(list(self.outputs), dtype=str),
                  "outputs": np.array([self.outputs[k] for k in self.outputs]).reshape(len(self.outputs), -1),
                  "model_text": np.array(self.model_text),
                  "parameters": np.array(json.dumps(self.parameters, sort_keys=True)),
                  "solver": np.array(json.dumps({k: v for k, v in self.solver.items() if k not in TIMING_FIELDS},
                                                sort_keys=True, default=str)),
                  "timing": np.array(json.dumps({k: v for k, v in self.solver.items() if k in TIMING_FIELDS},
                                                sort_keys=True, default=str)),
                  "partial": np.array(self.partial), "version": np.array(self.version)}
        _savez_fixed_dates(buffer, arrays)
        atomic_write_bytes(npz_path, buffer.getvalue())
        return [csv_path, npz_path]


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


def load_results(path: str | Path) -> Results:
    """Read ``results.npz`` (or the directory that holds it) back into :class:`Results`."""
    from .errors import ModelError

    path = Path(path)
    if path.is_dir():
        path = path / "results.npz"
    if not path.is_file():
        raise ModelError("RUN_DIR", "a run directory holding results.npz (or the file itself)", str(path))
    with np.load(path, allow_pickle=False) as data:
        names = [str(n) for n in data["output_names"]]
        outputs = {n: data["outputs"][i] for i, n in enumerate(names)}
        return Results(t=data["t"], state=data["state"], state_names=[str(n) for n in data["state_names"]],
                       outputs=outputs, model_text=str(data["model_text"]),
                       parameters=json.loads(str(data["parameters"])),
                       solver={**json.loads(str(data["solver"])),
                               **(json.loads(str(data["timing"])) if "timing" in data.files else {})},
                       partial=bool(data["partial"]), version=str(data["version"]))
