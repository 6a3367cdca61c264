"""Convergence studies: how a chain's frequencies and a chosen output change as modes are added.

For each number of modes n (every beam gets n shape functions, a spatial beam n in each bending
plane and of torsion that it has, :meth:`Model.with_modes`) the model is linearized (as
:func:`~flexkane.analysis.linearization.linearize`) and its first natural frequencies are recorded;
optionally the model is also integrated from its initial state to the time ``at`` and the value of
one output (e.g. ``tip_<beam>``, the tip deflection [m]) there is recorded. Assumed-modes
frequencies are Rayleigh-Ritz values: with shape functions that are admissible they decrease towards
the exact ones as modes are added. Each frequency carries the label of its mode (``bending 1``,
``flap 1``, ``torsion 2``, :mod:`flexkane.analysis.participation`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ModelError, SolverFailure
from ..model import Model
from .eigen import modal_analysis

__all__ = ["ConvergenceStudy", "convergence_study", "parse_mode_counts"]


def parse_mode_counts(text: str, flag: str = "--n-modes") -> list[int]:
    """Mode counts from ``A..B`` (every count from A to B), ``A,B,C`` or ``N``.

    Returns
    -------
    list of int
        Increasing, each from 1 to :data:`~flexkane.model.validate.MAX_MODES`.
    """
    text = str(text).strip()
    try:
        if ".." in text:
            first, last = (int(v) for v in text.split(".."))
            counts = list(range(first, last + 1))
        else:
            counts = [int(v) for v in text.split(",")]
    except ValueError:
        counts = []
    from ..model.validate import MAX_MODES

    if not counts or any(c < 1 or c > MAX_MODES for c in counts) or counts != sorted(set(counts)):
        raise ModelError(flag, f"mode counts as 1..N, a list A,B,C (increasing) or N, each 1 to {MAX_MODES}", text)
    return counts


@dataclass
class ConvergenceStudy:
    """Frequencies and an output against the number of modes (module docstring).

    Attributes
    ----------
    name : str
        Model name.
    n_modes : list of int
        Numbers of modes per beam, length s.
    frequencies : numpy.ndarray
        First natural frequencies of the oscillatory modes [rad/s], shape (s, k); NaN where fewer.
    output : str or None
        Output name (e.g. ``tip_B``).
    time : float or None
        Time at which the output is taken [s].
    output_values : numpy.ndarray
        The output at ``time`` for each n, shape (s,) (empty without an output).
    notes : list of str
    labels : list of list of str
        The label of each frequency (``torsion 1``), per row.
    """

    name: str
    n_modes: list
    frequencies: np.ndarray
    output: str | None = None
    time: float | None = None
    output_values: np.ndarray = field(default_factory=lambda: np.zeros(0))
    notes: list = field(default_factory=list)
    labels: list = field(default_factory=list)

    def header(self, labels: bool = False) -> list[str]:
        k = self.frequencies.shape[1]
        cells = ["n_modes"] + [f"omega_{i + 1} [rad/s]" for i in range(k)]
        if labels:
            cells += [f"motion_{i + 1}" for i in range(k)]
        if self.output:
            cells.append(f"{self.output}(t={self.time:g} s)")
        return cells

    def _rows(self):
        for k, n in enumerate(self.n_modes):
            row = list(self.frequencies[k])
            if self.output:
                row.append(self.output_values[k])
            yield n, row

    def csv_text(self) -> str:
        """The study as CSV, one row per number of modes: the frequencies, their labels
        (``motion_<i>``) and the output."""
        labelled = any(any(row) for row in self.labels)
        lines = [",".join(self.header(labels=labelled))]
        k = self.frequencies.shape[1]
        for i, (n, row) in enumerate(self._rows()):
            cells = ["" if math.isnan(v) else repr(float(v)) for v in row]
            if labelled:
                names = list(self.labels[i]) + [""] * (k - len(self.labels[i]))
                cells = cells[:k] + names + cells[k:]
            lines.append(",".join([str(n)] + cells))
        return "\n".join(lines) + "\n"

    def curves(self) -> dict:
        """The frequency of each label against the number of modes [rad/s], label -> shape (s,) (NaN
        where absent), in the order of the last row (the most modes); empty without labels."""
        if not self.labels or not any(self.labels[-1]):
            return {}
        out = {label: np.full(len(self.n_modes), np.nan) for label in self.labels[-1] if label}
        for i, names in enumerate(self.labels):
            for label, value in zip(names, self.frequencies[i]):
                if label in out:
                    out[label][i] = value
        return out

    def table(self) -> str:
        """A text table, with the relative change from the previous row of each column; the columns
        are the modes by label (:meth:`curves`) when they are labelled, so that a change compares a
        mode with itself when added modes fall between."""
        curves = self.curves()
        header, rows = self.header(), list(self._rows())
        if curves:
            header = ["n_modes"] + [f"{label} [rad/s]" for label in curves] + header[1 + self.frequencies.shape[1]:]
            rows = [(n, [curves[label][i] for label in curves] + row[self.frequencies.shape[1]:])
                    for i, (n, row) in enumerate(rows)]
        widths = [8] + [max(18, len(h) + 2) for h in header[1:]]
        lines = ["".join(f"{h:>{w}}" for h, w in zip(header, widths))]
        previous = None
        for n, row in rows:
            lines.append(f"{n:>8}" + "".join(f"{v:>{w}.10g}" if not math.isnan(v) else f"{'-':>{w}}"
                                              for v, w in zip(row, widths[1:])))
            if previous is not None:
                change = []
                for v, p, w in zip(row, previous, widths[1:]):
                    rel = abs(v - p) / abs(v) if not (math.isnan(v) or math.isnan(p)) and v != 0 else math.nan
                    change.append(f"{rel:>{w}.2e}" if not math.isnan(rel) else f"{'':>{w}}")
                lines.append(f"{'change':>8}" + "".join(change))
            previous = row
        return "\n".join(lines)


def convergence_study(model: Model, n_modes, *, about: str = "equilibrium", spin: float | None = None,
                      hub: str | None = None, count: int = 4, output: str | None = None,
                      at: float | None = None, rtol: float | None = None,
                      atol: float | None = None) -> ConvergenceStudy:
    """Frequencies (and an output at a time) for each number of modes.

    Parameters
    ----------
    model : Model
        A valid model with at least one beam.
    n_modes : sequence of int
        Numbers of shape functions per beam.
    about, spin, hub
        Operating point, as for :func:`~flexkane.analysis.linearization.linearize`.
    count : int
        Number of frequencies recorded.
    output : str, optional
        Name of an output of the equations (``tip_<beam>``, ``x_<link>``, ``energy``, ...).
    at : float, optional
        Time [s] at which the output is taken; required with ``output``.
    rtol, atol : float, optional
        Integrator tolerances; the model's ``[simulation]`` values by default.

    Returns
    -------
    ConvergenceStudy
    """
    from ..kane import derive
    from ..progress import each_reported
    from ..simulation import compile_model, simulate
    from .linearization import Linearization

    if not model.beams:
        raise ModelError("MODEL", "a model with at least one beam for a convergence study", model.name)
    if (output is None) != (at is None):
        raise ModelError("--at" if output else "--output", "--output NAME and --at T [s] together",
                         None, show_given=False)
    if at is not None and not (isinstance(at, (int, float)) and math.isfinite(at) and at > 0):
        raise ModelError("--at", "a positive time [s]", at)
    counts = list(n_modes)
    rows, values, notes, labels = [], [], [], []
    sim = model.simulation
    for n in each_reported(counts, f"convergence study of {model.name}", "{} modes per beam"):
        variant = model.with_modes(int(n))
        lin = Linearization(variant, about=about, spin=spin, hub=hub)
        modal = modal_analysis(lin.at(outputs=False))
        rows.append(modal.frequencies[:count])
        labels.append([m.label for m in modal.modes if m.kind == "oscillatory"][:count])
        for note in lin.notes:
            if note not in notes:
                notes.append(note)
        if output is not None:
            eom = derive(variant)
            if output not in eom.output_names:
                raise ModelError("--output", "an output of the model (" + ", ".join(sorted(eom.output_names)) + ")",
                                 output)
            results = simulate(compile_model(eom), t_end=float(at), dt_out=float(at),
                               rtol=rtol if rtol is not None else sim.rtol,
                               atol=atol if atol is not None else sim.atol, method=sim.method, model=variant)
            if results.partial:
                raise SolverFailure(results.solver["t_reached"], f"{results.solver['message']} (n_modes = {n})")
            values.append(float(results.outputs[output][-1]))
    width = max((len(r) for r in rows), default=0)
    table = np.full((len(counts), width), np.nan)
    for k, r in enumerate(rows):
        table[k, :len(r)] = r
    return ConvergenceStudy(model.name, counts, table, output, float(at) if at is not None else None,
                            np.array(values), notes, labels)
