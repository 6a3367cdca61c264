"""Campbell diagrams: the frequencies of a chain against the spin rate of its hub.

For each spin rate Omega the chain is linearized about the steady spin (its hub driven at the
constant rate Omega, the other coordinates in equilibrium in the rotating frame, see
:mod:`flexkane.analysis.linearization`); one symbolic linearization serves every Omega. The
frequency of a mode is the imaginary part of its eigenvalue (the frequency seen in the rotating frame)
[rad/s]; a mode that has become statically unstable (a real pair ``+-sigma``, as the first bending
mode of a rotating beam without geometric stiffening once Omega exceeds its frequency) has frequency 0,
and the largest growth rate ``max Re(lambda)`` [1/s] is reported for every Omega. Modes are sorted by
frequency at each Omega in :attr:`CampbellDiagram.frequencies`; each is labelled by its dominant
motion and its rank among the modes of that motion (``flap 1``, ``lag 1``, ``torsion 1``, ``axial 1``,
``joint <name> 1``: the modal participation of its eigenvector in the chain's coordinate families,
:mod:`flexkane.analysis.participation`), and the curves of the diagram join the modes of one label
across the spin rates (:meth:`CampbellDiagram.curves`), so that they cross where the frequencies do.
For a blade on a hub spinning about an axis normal to it, flap is the bending out of the plane of
rotation (along the spin axis) and lag the bending in it.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import ModelError
from ..model import Model
from ..model.study_ranges import SPIN_LIMIT, parse_spin_range
from .eigen import modal_analysis

__all__ = ["CampbellDiagram", "campbell_diagram", "parse_spin_range"]

#: Growth rates below this fraction of the largest frequency are rounding errors.
_GROWTH_TOLERANCE = 1e-9


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
    labels : numpy.ndarray
        The label of each frequency (``flap 1``, ``lag 1``, ``torsion 1``, ...), shape (s, k), ''
        where a row has fewer modes.
    participations : list of list of dict
        Per spin rate and mode (as ``frequencies``): the share of each family of motion in the
        mode's kinetic energy [-].
    """

    name: str
    hub: str
    spins: np.ndarray
    frequencies: np.ndarray
    growth_rates: np.ndarray
    notes: list = field(default_factory=list)
    labels: np.ndarray | None = None
    participations: list = field(default_factory=list)

    def curves(self) -> dict:
        """The frequencies of each label against the spin rates [rad/s], label -> shape (s,) (NaN
        where no mode has it), labels ordered by their frequency at the first spin rate that has them."""
        out: dict = {}
        if self.labels is None:
            return out
        for i in range(self.spins.size):
            for label, value in zip(self.labels[i], self.frequencies[i]):
                if label and label not in out:
                    out[label] = np.full(self.spins.size, np.nan)
                if label and np.isnan(out[label][i]):
                    out[label][i] = value
        first = {label: next(v for v in values if not np.isnan(v)) for label, values in out.items()}
        return {label: out[label] for label in sorted(out, key=lambda k: (np.flatnonzero(~np.isnan(out[k]))[0],
                                                                           first[k], k))}

    def modes_csv_text(self) -> str:
        """One row per spin rate and mode: Omega [rad/s], the mode's rank by frequency, its label,
        its frequency [rad/s] and the participation of every family of motion [-]."""
        families: list[str] = []
        for row in self.participations:
            for share in row:
                families += [k for k in share if k not in families]
        lines = [",".join(["Omega [rad/s]", "mode", "label", "omega [rad/s]"]
                          + [f"participation {f}" for f in families])]
        for i, spin in enumerate(self.spins):
            for k, value in enumerate(self.frequencies[i]):
                if np.isnan(value):
                    continue
                share = self.participations[i][k] if self.participations else {}
                label = self.labels[i, k] if self.labels is not None else ""
                lines.append(",".join([repr(float(spin)), str(k + 1), label, repr(float(value))]
                                      + [repr(float(share.get(f, 0.0))) for f in families]))
        return "\n".join(lines) + "\n"

    def json_text(self) -> str:
        """The diagram as JSON: model, hub, spin rates [rad/s], growth rates [1/s], the labelled
        curves (label -> frequencies [rad/s], null where absent) and every mode with its label and
        participations."""
        clean = lambda v: None if np.isnan(v) else float(v)    # noqa: E731
        data = {"model": self.name, "hub": self.hub, "spins": [float(v) for v in self.spins],
                "growth_rates": [float(v) for v in self.growth_rates],
                "curves": {label: [clean(v) for v in values] for label, values in self.curves().items()},
                "modes": [[{"omega": float(value),
                            "label": self.labels[i, k] if self.labels is not None else "",
                            "participation": self.participations[i][k] if self.participations else {}}
                           for k, value in enumerate(self.frequencies[i]) if not np.isnan(value)]
                          for i in range(self.spins.size)],
                "notes": list(self.notes)}
        return json.dumps(data, indent=1, sort_keys=False) + "\n"

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

    def table(self, columns: int = 6) -> str:
        """A text table of the first ``columns`` curves (by label, :meth:`curves`; the first
        ``columns`` frequencies of each row when the modes are not labelled)."""
        curves = self.curves()
        if curves:
            names = list(curves)[:columns]
            data = np.column_stack([curves[k] for k in names]) if names else np.zeros((self.spins.size, 0))
            heads = [f"{k} [rad/s]" for k in names]
        else:
            k = min(columns, self.frequencies.shape[1])
            data, heads = self.frequencies[:, :k], [f"omega_{i + 1} [rad/s]" for i in range(k)]
        width = max([18] + [len(h) + 2 for h in heads])
        lines = [f"{'Omega [rad/s]':>14}" + "".join(f"{h:>{width}}" for h in heads) + f"{'growth [1/s]':>16}"]
        for spin, row, growth in zip(self.spins, data, self.growth_rates):
            cells = "".join(f"{v:>{width}.8g}" if not np.isnan(v) else f"{'-':>{width}}" for v in row)
            lines.append(f"{spin:>14.6g}{cells}{growth:>16.4g}")
        return "\n".join(lines)

    def plot(self, path) -> Path:
        """Write the diagram as a PNG file: frequencies, the lines Omega and 2 Omega, unstable spins."""
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        from ..atomic import atomic_writer

        figure = Figure(figsize=(8.2, 4.8), layout="constrained")
        FigureCanvasAgg(figure)
        axes = figure.add_subplot()
        curves = self.curves()
        if curves:
            colours: dict = {}
            for label, values in curves.items():
                motion, rank = label.rsplit(" ", 1) if " " in label else (label, "1")
                colour = colours.setdefault(motion, f"C{len(colours) % 10}")
                style = ("-", "--", "-.", ":")[(int(rank) - 1) % 4 if rank.isdigit() else 0]
                axes.plot(self.spins, values, style, marker=".", markersize=3, color=colour, label=label)
        else:
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
        axes.legend(fontsize="small", loc="center left", bbox_to_anchor=(1.01, 0.5))
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
        Revolute joint spun (see :func:`flexkane.analysis.prepare.spin_hub`).
    t0 : float
        Time at which other time-dependent terms are frozen [s].
    spin_axis : sequence of 3 float, optional
        3D models: a spherical or free joint ``hub`` spinning freely about this axis of its child
        frame (:class:`~flexkane.analysis.linearization.Linearization`).

    Returns
    -------
    CampbellDiagram
    """
    from ..progress import each_reported
    from .linearization import Linearization

    from ..limits import check_count

    spins = np.atleast_1d(np.asarray(spins, dtype=float))
    if spins.ndim != 1 or spins.size == 0 or not np.all(np.isfinite(spins)):
        raise ModelError("--spin", "one or more finite spin rates [rad/s]", spins)
    check_count(spins.size, "--spin", SPIN_LIMIT, f"{spins.size:,} spin rates")
    lin = Linearization(model, about="spin", spin=float(spins[0]), hub=hub, t0=t0, spin_axis=spin_axis)
    rows, growth = [], []
    q = None
    for spin in each_reported(spins, f"Campbell diagram of {model.name}", "Omega = {:g} rad/s"):
        linear = lin.at(spin=float(spin), q_start=q, outputs=False)
        q = lin.full_operating_point(linear)
        modal = modal_analysis(linear)
        entries = [(m.damped_frequency, m.label, m.participation) for m in modal.modes if m.kind == "oscillatory"]
        real = [m for m in modal.modes if m.kind in ("overdamped", "divergent")]
        labelled: dict = {}     # the real eigenvalues of one label (a mode's pair): frequency 0 once
        for m in real:
            labelled.setdefault(m.label, []).append(m)
        for label, members in labelled.items():
            entries += [(0.0, label, members[0].participation)] * (1 if label else (len(members) + 1) // 2)
        rows.append(sorted(entries, key=lambda e: (e[0], e[1])))
        growth.append(modal.max_growth_rate())
    width = max((len(r) for r in rows), default=0)
    table = np.full((spins.size, width), np.nan)
    labels = np.full((spins.size, width), "", dtype=object)
    shares = []
    for i, r in enumerate(rows):
        table[i, :len(r)] = [e[0] for e in r]
        labels[i, :len(r)] = [e[1] for e in r]
        shares.append([e[2] for e in r])
    notes = [n for n in lin.notes if "spins at the constant rate" not in n and "spins freely at" not in n]
    return CampbellDiagram(model.name, lin.prepared.hub, spins, table, np.array(growth), notes, labels, shares)
