"""Campbell diagrams: the frequencies of a chain against the spin rate of its hub.

For each spin rate Omega the chain is linearized about the steady spin (its hub driven at the
constant rate Omega, the other coordinates in equilibrium in the rotating frame, see
:mod:`flexkane.linearize.linearization`); one symbolic linearization serves every Omega. The
frequency of a mode is the imaginary part of its eigenvalue (the frequency seen in the rotating frame)
[rad/s]; a mode that has become statically unstable (a real pair ``+-sigma``, as the first bending
mode of a rotating beam without geometric stiffening once Omega exceeds its frequency) has frequency 0,
and the largest growth rate ``max Re(lambda)`` [1/s] is reported for every Omega. Modes are sorted by
frequency at each Omega (they are not tracked through crossings).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import ModelError
from ..model import Model
from .eigen import modal_analysis

__all__ = ["CampbellDiagram", "campbell_diagram", "parse_spin_range"]

#: Growth rates below this fraction of the largest frequency are rounding errors.
_GROWTH_TOLERANCE = 1e-9


def parse_spin_range(text: str, flag: str = "--spin") -> np.ndarray:
    """Spin rates from ``START:STOP:COUNT`` (COUNT rates from START to STOP) or ``A,B,C`` [rad/s].

    Returns
    -------
    numpy.ndarray
        Shape (COUNT,).
    """
    text = str(text).strip()
    try:
        if ":" in text:
            parts = text.split(":")
            if len(parts) != 3:
                raise ValueError
            start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
            if count < 1 or not (math.isfinite(start) and math.isfinite(stop)):
                raise ValueError
            values = np.linspace(start, stop, count)
        else:
            values = np.array([float(v) for v in text.split(",")], dtype=float)
            if values.size == 0 or not np.all(np.isfinite(values)):
                raise ValueError
    except ValueError:
        raise ModelError(flag, "spin rates [rad/s] as START:STOP:COUNT (e.g. 0:8:33) or a list A,B,C",
                         text) from None
    return values


@dataclass
class CampbellDiagram:
    """Frequencies against spin rate (module docstring).

    Attributes
    ----------
    name : str
        Model name.
    hub : str
        The spun joint.
    spins : numpy.ndarray
        Omega [rad/s], shape (s,).
    frequencies : numpy.ndarray
        Frequencies of the modes in the rotating frame [rad/s], shape (s, k), ascending in each row,
        NaN where a row has fewer modes.
    growth_rates : numpy.ndarray
        Largest real part of the eigenvalues [1/s], shape (s,); positive where the steady spin is
        unstable.
    notes : list of str
    """

    name: str
    hub: str
    spins: np.ndarray
    frequencies: np.ndarray
    growth_rates: np.ndarray
    notes: list = field(default_factory=list)

    @property
    def unstable(self) -> np.ndarray:
        """Whether the steady spin is unstable, shape (s,)."""
        scale = np.nanmax(self.frequencies) if np.any(np.isfinite(self.frequencies)) else 1.0
        return self.growth_rates > _GROWTH_TOLERANCE * max(scale, 1.0)

    def header(self) -> list[str]:
        k = self.frequencies.shape[1]
        return ["Omega [rad/s]"] + [f"omega_{i + 1} [rad/s]" for i in range(k)] + ["max_growth_rate [1/s]"]

    def csv_text(self) -> str:
        """The diagram as CSV text, one row per spin rate."""
        lines = [",".join(self.header())]
        for spin, row, growth in zip(self.spins, self.frequencies, self.growth_rates):
            cells = [repr(float(spin))] + ["" if np.isnan(v) else repr(float(v)) for v in row]
            lines.append(",".join(cells + [repr(float(growth))]))
        return "\n".join(lines) + "\n"

    def table(self, columns: int = 4) -> str:
        """A text table of the first ``columns`` frequencies."""
        k = min(columns, self.frequencies.shape[1])
        head = f"{'Omega [rad/s]':>14}" + "".join(f"{f'omega_{i + 1} [rad/s]':>18}" for i in range(k)) \
            + f"{'growth [1/s]':>16}"
        lines = [head]
        for spin, row, growth in zip(self.spins, self.frequencies, self.growth_rates):
            cells = "".join(f"{v:>18.8g}" if not np.isnan(v) else f"{'-':>18}" for v in row[:k])
            lines.append(f"{spin:>14.6g}{cells}{growth:>16.4g}")
        return "\n".join(lines)

    def plot(self, path) -> Path:
        """Write the diagram as a PNG file: frequencies, the lines Omega and 2 Omega, unstable spins."""
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        from ..atomic import atomic_writer

        figure = Figure(figsize=(7.0, 4.8), layout="constrained")
        FigureCanvasAgg(figure)
        axes = figure.add_subplot()
        for i in range(self.frequencies.shape[1]):
            axes.plot(self.spins, self.frequencies[:, i], "-", marker=".", markersize=3,
                      label=f"mode {i + 1}" if i < 8 else None)
        top = np.nanmax(self.frequencies) if np.any(np.isfinite(self.frequencies)) else 1.0
        for multiple, style in ((1, ":"), (2, "--")):
            axes.plot(self.spins, multiple * self.spins, style, color="0.5", linewidth=0.8,
                      label=f"{multiple} x Omega" if multiple > 1 else "Omega")
        unstable = self.unstable
        if np.any(unstable):
            step = np.diff(self.spins).min() if self.spins.size > 1 else 0.0
            for spin in self.spins[unstable]:
                axes.axvspan(spin - step / 2, spin + step / 2, color="C3", alpha=0.15, linewidth=0)
            axes.plot([], [], color="C3", alpha=0.3, linewidth=6, label="unstable (growth > 0)")
        axes.set_ylim(0.0, 1.05 * max(top, 1e-12))
        axes.set_xlabel("spin rate Omega [rad/s]")
        axes.set_ylabel("frequency in the rotating frame [rad/s]")
        axes.set_title(f"Campbell diagram of {self.name} (joint {self.hub} spinning)")
        axes.legend(fontsize="small", loc="center right")
        with atomic_writer(path, "path") as temporary:
            figure.savefig(temporary, format="png", dpi=120)
        return Path(path)


def campbell_diagram(model: Model, spins, *, hub: str | None = None, t0: float = 0.0,
                     spin_axis=None) -> CampbellDiagram:
    """Frequencies of a chain against the spin rate of a hub.

    Parameters
    ----------
    model : Model
        A valid model.
    spins : array_like
        Spin rates Omega [rad/s], shape (s,).
    hub : str, optional
        Revolute joint spun (see :func:`flexkane.linearize.prepare.spin_hub`).
    t0 : float
        Time at which other time-dependent terms are frozen [s].
    spin_axis : sequence of 3 float, optional
        3D models: a spherical or free joint ``hub`` spinning freely about this axis of its child
        frame (:class:`~flexkane.linearize.linearization.Linearization`).

    Returns
    -------
    CampbellDiagram
    """
    from .linearization import Linearization

    spins = np.atleast_1d(np.asarray(spins, dtype=float))
    if spins.ndim != 1 or spins.size == 0 or not np.all(np.isfinite(spins)):
        raise ModelError("--spin", "one or more finite spin rates [rad/s]", spins)
    lin = Linearization(model, about="spin", spin=float(spins[0]), hub=hub, t0=t0, spin_axis=spin_axis)
    rows, growth = [], []
    q = None
    for spin in spins:
        linear = lin.at(spin=float(spin), q_start=q, outputs=False)
        q = lin.full_operating_point(linear)
        modal = modal_analysis(linear)
        frequencies = [m.damped_frequency for m in modal.modes if m.kind == "oscillatory"]
        real = sum(1 for m in modal.modes if m.kind in ("overdamped", "divergent"))
        frequencies += [0.0] * ((real + 1) // 2)
        rows.append(sorted(frequencies))
        growth.append(modal.max_growth_rate())
    width = max((len(r) for r in rows), default=0)
    table = np.full((spins.size, width), np.nan)
    for i, r in enumerate(rows):
        table[i, :len(r)] = r
    notes = [n for n in lin.notes if "spins at the constant rate" not in n and "spins freely at" not in n]
    return CampbellDiagram(model.name, lin.prepared.hub, spins, table, np.array(growth), notes)
