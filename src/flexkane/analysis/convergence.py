"""Convergence studies: how a chain's frequencies and a chosen output change as modes are added.

For each number of modes n (every beam gets n shape functions, a spatial beam n in each bending
plane and of torsion that it has, :meth:`Model.with_modes`) the model is linearized (as
:func:`~flexkane.analysis.linearization.linearize`) and its first natural frequencies are recorded;
optionally the model is also integrated from its initial state to the time ``at`` and the value of
one output (e.g. ``tip_<beam>``, the tip deflection [m]) there is recorded. Assumed-modes
frequencies are Rayleigh-Ritz values: with shape functions that are admissible they decrease towards
the exact ones as modes are added. Each frequency carries the label of its mode (``bending 1``,
``flap 1``, ``torsion 2``, :mod:`flexkane.analysis.participation`).

The initial values of modal coordinates beyond the count under study (a model whose ``[initial]``
sets a second mode, studied with one) are dropped, with a note (:meth:`Model.with_modes`).

**Verdict.** Each tracked quantity (a frequency, followed by its label when the modes are labelled,
and the output) is judged on its relative change from one mode count to the next,
``c = |v_n - v_prev| / |v_n|``, against a tolerance (:data:`DEFAULT_TOLERANCE` unless stated): it has
**converged** when the last change is within the tolerance, and "converged to C relative at n = N"
says that the changes at the count N (from the count before) and at every later count were at most C
relative; else it is **not converged** ("last change C > tolerance"). A quantity known at fewer than the last two
counts is not judged (:func:`convergence_verdict`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ModelError, SolverFailure
from ..model import Model
from ..model.study_ranges import DEFAULT_TOLERANCE, check_tolerance, checked_mode_counts, parse_mode_counts
from .eigen import modal_analysis

__all__ = ["ConvergenceStudy", "Verdict", "convergence_study", "convergence_verdict", "parse_mode_counts",
           "checked_mode_counts", "DEFAULT_TOLERANCE"]

def relative_change(previous: float, value: float) -> float:
    """``|value - previous| / |value|`` [-]: 0 when both are 0, infinite when only ``value`` is,
    NaN when either is NaN."""
    if math.isnan(previous) or math.isnan(value):
        return math.nan
    if value == previous:
        return 0.0
    return abs(value - previous) / abs(value) if value != 0 else math.inf


@dataclass(frozen=True)
class Verdict:
    """Whether one quantity of a convergence study converged (module docstring).

    Attributes
    ----------
    quantity : str
        What is judged (``bending 1``, ``omega_2``, ``tip_B(t=0.8 s)``).
    tolerance : float
        Largest relative change of a converged quantity [-].
    converged : bool or None
        None when the quantity is not judged (known at fewer than the last two counts).
    change : float
        Converged: the largest relative change from ``n_modes`` on; not converged: the last
        relative change [-]; NaN when not judged.
    n_modes : int or None
        Converged: the first count whose change and every later one are within the tolerance; else
        the last count.
    """

    quantity: str
    tolerance: float
    converged: bool | None
    change: float
    n_modes: int | None

    @property
    def text(self) -> str:
        """The verdict in words (``converged to 2.1e-04 relative at n = 3``)."""
        if self.converged is None:
            return f"not judged: known at fewer than the last two mode counts (n = {self.n_modes})"
        if self.converged:
            return f"converged to {self.change:.1e} relative at n = {self.n_modes}"
        return f"not converged: last change {self.change:.1e} > {self.tolerance:g}"


def convergence_verdict(values, n_modes, tolerance: float = DEFAULT_TOLERANCE, quantity: str = "") -> Verdict:
    """Judge a quantity against the number of modes (module docstring).

    Parameters
    ----------
    values : sequence of float
        The quantity at each count, shape (s,); NaN where it is not known.
    n_modes : sequence of int
        The counts, increasing, shape (s,).
    tolerance : float
        Largest relative change of a converged quantity [-].
    quantity : str
        Its name, kept in the verdict.

    Returns
    -------
    Verdict
    """
    tolerance = check_tolerance(tolerance)
    values = [float(v) for v in values]
    counts = [int(n) for n in n_modes]
    if len(values) != len(counts) or not counts:
        raise ModelError("values", f"one value per mode count ({len(counts)})", len(values))
    changes = [relative_change(p, v) for p, v in zip(values, values[1:])]   # changes[k] at counts[k + 1]
    if not changes or math.isnan(changes[-1]):
        return Verdict(quantity, tolerance, None, math.nan, counts[-1])
    if not changes[-1] <= tolerance:
        return Verdict(quantity, tolerance, False, changes[-1], counts[-1])
    first = len(changes) - 1
    while first > 0 and changes[first - 1] <= tolerance:
        first -= 1
    return Verdict(quantity, tolerance, True, max(changes[first:]), counts[first + 1])


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
    tolerance : float
        Largest relative change per added count of modes of a converged quantity [-] (:meth:`verdicts`).
    """

    name: str
    n_modes: list
    frequencies: np.ndarray
    output: str | None = None
    time: float | None = None
    output_values: np.ndarray = field(default_factory=lambda: np.zeros(0))
    notes: list = field(default_factory=list)
    labels: list = field(default_factory=list)
    tolerance: float = DEFAULT_TOLERANCE

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

    def quantities(self) -> dict:
        """The tracked quantities against the number of modes, name -> values shape (s,): the modes
        by label (:meth:`curves`, [rad/s]) when they are labelled, so that a change compares a mode
        with itself when added modes fall between, else ``omega_<i>`` [rad/s]; then the output."""
        curves = self.curves()
        out = dict(curves) if curves else {f"omega_{i + 1}": self.frequencies[:, i]
                                           for i in range(self.frequencies.shape[1])}
        if self.output:
            out[f"{self.output}(t={self.time:g} s)"] = np.asarray(self.output_values, dtype=float)
        return out

    def table(self) -> str:
        """A text table of :meth:`quantities`, with the relative change from the previous row of each
        column."""
        quantities = self.quantities()
        frequencies = len(quantities) - bool(self.output)
        header = ["n_modes"] + [f"{k} [rad/s]" if i < frequencies else k for i, k in enumerate(quantities)]
        widths = [8] + [max(18, len(h) + 2) for h in header[1:]]
        lines = ["".join(f"{h:>{w}}" for h, w in zip(header, widths))]
        columns = list(quantities.values())
        for i, n in enumerate(self.n_modes):
            row = [float(c[i]) for c in columns]
            lines.append(f"{n:>8}" + "".join(f"{v:>{w}.10g}" if not math.isnan(v) else f"{'-':>{w}}"
                                              for v, w in zip(row, widths[1:])))
            if i:
                rels = [relative_change(float(c[i - 1]), v) for c, v in zip(columns, row)]
                lines.append(f"{'change':>8}" + "".join(f"{r:>{w}.2e}" if not math.isnan(r) else f"{'':>{w}}"
                                                        for r, w in zip(rels, widths[1:])))
        return "\n".join(lines)

    def verdicts(self) -> list[Verdict]:
        """Whether each of :meth:`quantities` converged, against :attr:`tolerance` (module docstring)."""
        return [convergence_verdict(values, self.n_modes, self.tolerance, name)
                for name, values in self.quantities().items()]

    def verdicts_text(self) -> str:
        """The tolerance and one verdict line per quantity."""
        lines = [f"tolerance: {self.tolerance:g} relative change per added count of modes"]
        return "\n".join(lines + [f"{v.quantity}: {v.text}" for v in self.verdicts()])

    def verdicts_csv_text(self) -> str:
        """The verdicts as CSV, one row per quantity: its name, the tolerance [-], whether it converged
        (``true``, ``false``, empty when not judged), the change [-], the count and the verdict."""
        import csv
        import io

        text = io.StringIO()
        writer = csv.writer(text, lineterminator="\n")
        writer.writerow(["quantity", "tolerance [-]", "converged", "change [-]", "n_modes", "verdict"])
        for v in self.verdicts():
            writer.writerow([v.quantity, repr(v.tolerance), "" if v.converged is None else str(v.converged).lower(),
                             "" if math.isnan(v.change) else repr(v.change), v.n_modes, v.text])
        return text.getvalue()


def convergence_study(model: Model, n_modes, *, about: str = "equilibrium", spin: float | None = None,
                      hub: str | None = None, count: int = 4, output: str | None = None,
                      at: float | None = None, rtol: float | None = None, atol: float | None = None,
                      tolerance: float = DEFAULT_TOLERANCE) -> ConvergenceStudy:
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
    tolerance : float
        Largest relative change per added count of modes of a converged quantity [-]
        (:meth:`ConvergenceStudy.verdicts`).

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
    tolerance = check_tolerance(tolerance)
    counts = checked_mode_counts(n_modes)
    rows, values, notes, labels = [], [], [], []
    sim = model.simulation
    for n in each_reported(counts, f"convergence study of {model.name}",
                           lambda n: f"{n} mode{'' if n == 1 else 's'} per beam"):
        variant = _study_variant(model, n, notes)
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
                            np.array(values), notes, labels, tolerance)


def _study_variant(model: Model, n: int, notes: list) -> Model:
    """The model with n modes per beam, valid (:meth:`Model.with_modes`); a note for the initial
    values it drops; a ModelError names ``--n-modes`` when the model cannot have n modes."""
    try:
        variant = model.with_modes(n).validate()
    except ModelError as error:
        raise ModelError("--n-modes", f"mode counts this model can have ({error})", n) from None
    dropped = model.initial_beyond_modes(n)
    if dropped:
        values = "values of " + ", ".join(dropped) + " are" if len(dropped) > 1 else f"value of {dropped[0]} is"
        notes.append(f"n = {n}: the initial {values} dropped (modes beyond the count under study, --n-modes)")
    return variant
