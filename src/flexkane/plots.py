"""Plots of a run: every coordinate and speed against t, tip deflections, energies and the energy balance.

The chapter's notebook plots u1, u2, u3, u4, q3 and q4 against t; :func:`write_plots` draws those
and every other state variable, each as ``<name>.png``, with labelled axes and units.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .atomic import atomic_writer
from .results import Results
from .run_manifest import units  # noqa: F401 - the columns' units, here too for plotting scripts

__all__ = ["write_plots", "plot_series", "plot_energy", "plot_runs", "units", "load_matplotlib"]


def load_matplotlib() -> None:
    """Import the parts of matplotlib that the plots draw with (about half a second of CPU), so that a
    caller can do it while it waits for something else (a model structure compiling)."""
    import matplotlib.backends.backend_agg  # noqa: F401
    import matplotlib.figure  # noqa: F401


def _new_figure(width: float, height: float, rows: int = 1, columns: int = 1, **subplots):
    """A figure on its own Agg canvas (no pyplot: no global state, no backend switch) and its axes.

    Parameters
    ----------
    width, height : float
        Size of the figure [inch].
    rows, columns : int
        Grid of axes, as :meth:`matplotlib.figure.Figure.subplots` (``squeeze`` etc. in ``subplots``).
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(width, height))
    FigureCanvasAgg(figure)
    return figure, figure.subplots(rows, columns, **subplots)


def _margins(figure, *, title: bool, space: float = 0.3) -> None:
    """Fixed margins [inch] that hold tick labels and axis labels: no layout engine to iterate."""
    width, height = figure.get_size_inches()
    top = 0.5 if title else 0.2
    figure.subplots_adjust(left=0.95 / width, right=1.0 - 0.2 / width, bottom=0.55 / height,
                           top=1.0 - top / height, wspace=space + 0.1, hspace=space)


def _save(fig, path: Path) -> Path:
    """Write the figure as a PNG (110 dpi) atomically; fast zlib level, the files stay small."""
    with atomic_writer(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png", pil_kwargs={"compress_level": 1})
    return path


class _SeriesFigure:
    """One figure reused for every single-column plot of a run: its line's data, the labels and the
    limits change from plot to plot; the figure, axes, grid and ticks are made once."""

    def __init__(self):
        self.fig = self.ax = self.line = None

    def draw(self, results: Results, name: str, unit: str, path: Path, title: str) -> Path:
        if self.fig is None:
            self.fig, self.ax = _new_figure(6.4, 3.8)
            (self.line,) = self.ax.plot(results.t, results[name], label=name, lw=1.4)
            self.ax.set_xlabel("t [s]")
            self.ax.grid(alpha=0.3)
            self.title = self.ax.set_title(title, fontsize=10)
            _margins(self.fig, title=True)
        else:
            self.line.set_data(results.t, results[name])
            self.line.set_label(name)
            self.ax.relim()
            self.ax.autoscale_view()
        self.ax.set_ylabel(f"{name} [{unit}]")
        self.title.set_text(title)
        _save(self.fig, path)
        return path


def plot_series(results: Results, names: list[str], unit: str, path: Path, title: str = "") -> Path:
    """One figure of the named columns against t [s]."""
    fig, ax = _new_figure(6.4, 3.8)
    for name in names:
        ax.plot(results.t, results[name], label=name, lw=1.4)
    ax.set_xlabel("t [s]")
    ax.set_ylabel(f"{', '.join(names)} [{unit}]")
    if len(names) > 1:
        ax.legend(loc="best", fontsize=8)
    if title:
        ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    _margins(fig, title=bool(title))
    _save(fig, path)
    return path


def plot_energy(results: Results, path: Path, title: str = "") -> Path:
    """Energies [J] and the work done, and the energy balance ``(E - E0 - W)/max|E|`` against t.

    The upper panel shows the total energy ``E``, its kinetic, potential (gravity and springs) and
    strain parts, and the work ``W`` of drivers, loads and dampers (integrated with the motion);
    the lower one the balance ``E - E0 - W``, which the solver's error alone keeps from 0.
    """
    energy = results["energy"]
    scale = max(np.max(np.abs(energy)), np.max(np.abs(results["kinetic"])), 1e-300)
    outputs = results.outputs
    work = outputs["work"] if "work" in outputs else np.zeros_like(energy)
    balance = outputs["energy_balance"] if "energy_balance" in outputs else energy - energy[0] - work
    fig, (ax1, ax2) = _new_figure(6.4, 5.6, 2, 1, sharex=True)
    ax1.plot(results.t, energy, lw=1.6, color="k", label="total E")
    ax1.plot(results.t, results["kinetic"], lw=1.0, ls="--", label="kinetic")
    potential = sum((outputs[k] for k in ("potential_gravity", "potential_springs") if k in outputs),
                    np.zeros_like(energy))
    if np.any(potential):
        ax1.plot(results.t, potential, lw=1.0, ls="-.", label="potential")
    if "strain" in outputs and np.any(outputs["strain"]):
        ax1.plot(results.t, outputs["strain"], lw=1.0, ls=":", label="strain")
    if np.any(work):
        ax1.plot(results.t, energy[0] + work, lw=1.0, color="C3", alpha=0.8, label="E0 + work W")
    ax1.set_ylabel("energy [J]")
    ax1.legend(fontsize=8, loc="best")
    ax1.grid(alpha=0.3)
    ax2.plot(results.t, balance / scale, lw=1.2, color="C3")
    ax2.set_ylabel("balance (E - E0 - W)/max|E| [-]", fontsize=9)
    ax2.set_xlabel("t [s]")
    ax2.grid(alpha=0.3)
    ax2.ticklabel_format(axis="y", style="sci", scilimits=(-2, 2))
    if title:
        ax1.set_title(title, fontsize=10)
    _margins(fig, title=bool(title))
    _save(fig, path)
    return path


def plot_runs(runs: dict, names: list[str], path: Path, *, units: dict | None = None, title: str = "",
              log: bool = False, columns: int = 2) -> Path:
    """Several runs compared: one panel per named column, one curve per run.

    Parameters
    ----------
    runs : dict of str to Results
        Runs by label (the legend).
    names : list of str
        Columns to plot (state variables or outputs), one panel each.
    path : pathlib.Path
        PNG file to write.
    units : dict of str to str, optional
        Unit of each column (see :func:`units`), shown in the axis labels.
    title : str
        Title of the figure.
    log : bool
        Plot ``|value|`` on a logarithmic axis (growth over decades, e.g. a tip deflection).
    columns : int
        Panels per row.

    Returns
    -------
    pathlib.Path
    """
    units = units or {}
    columns = max(1, min(columns, len(names)))
    rows = -(-len(names) // columns)
    width = max(4.2 * columns + 0.6, 6.4)
    fig, axes = _new_figure(width, 2.9 * rows + 0.6 + 0.6 * (rows == 1), rows, columns, squeeze=False)
    for ax, name in zip(axes.flat, names):
        for k, (label, results) in enumerate(runs.items()):
            values = np.abs(results[name]) if log else results[name]
            ax.plot(results.t, values, lw=1.3, label=label, color=f"C{k}", ls="-" if k == 0 else "--")
        if log:
            ax.set_yscale("log")
        shown = f"|{name}|" if log else name
        ax.set_ylabel(f"{shown} [{units.get(name, '-')}]")
        ax.set_xlabel("t [s]")
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(names):]:
        ax.set_visible(False)
    axes.flat[0].legend(fontsize=8, loc="best")
    if title:
        fig.suptitle(title, fontsize=11)
    _margins(fig, title=bool(title), space=0.45)
    _save(fig, Path(path))
    return Path(path)


def _unit(results: Results, names: list[str]) -> str:
    """The declared unit of the outputs ``names`` (one for all), ``-`` where none is declared."""
    units = {results.declared[k].unit for k in names if k in results.declared} - {None}
    return units.pop() if len(units) == 1 else "-"


def _plot_jobs(results: Results, unit: dict, directory: Path, title: str) -> list:
    """The figures of :func:`write_plots`, in its order: each its file and a function of a
    :class:`_SeriesFigure` (the figure that the single-column plots of one process share) that draws
    and writes it. The outputs are grouped by their declared groups (:data:`flexkane.model.columns.GROUPS`)."""
    jobs = []
    for name in results.state_names:
        path = directory / f"{name}.png"
        jobs.append((path, lambda single, name=name, path=path: single.draw(results, name, unit.get(name, "-"),
                                                                           path, title)))
    tips = results.outputs_of("tip")
    if tips:
        where = "along the sections' principal axes" if results.outputs_of("slope") else "in the beam frame"
        path = directory / "tip_deflection.png"
        jobs.append((path, lambda single, path=path: plot_series(results, tips, _unit(results, tips), path,
                                                                 f"{title}: tip deflection {where}")))
    twists = results.outputs_of("twist", "slope")
    if twists:
        path = directory / "tip_twist.png"
        jobs.append((path, lambda single, path=path: plot_series(results, twists, _unit(results, twists), path,
                                                                 f"{title}: twist and slopes of the beams' tips")))
    for name in results.outputs_of("effort", "actuator"):
        path = directory / f"{name}.png"
        what = "driver effort" if results.declared[name].group == "effort" else \
            "actuator " + ("torque" if results.declared[name].unit == "N m" else "force")
        jobs.append((path, lambda single, name=name, path=path, what=what: single.draw(
            results, name, _unit(results, [name]), path, f"{title}: {what}")))
    if "energy" in results.outputs and len(results.t) > 1:
        path = directory / "energy.png"
        jobs.append((path, lambda single, path=path: plot_energy(results, path, title)))
    momentum = results.outputs_of("angular_momentum")
    if momentum:
        path = directory / "angular_momentum.png"
        jobs.append((path, lambda single, path=path: plot_series(
            results, momentum, _unit(results, momentum), path,
            f"{title}: angular momentum about the mass centre, ground axes")))
    norms = results.outputs_of("quaternion_norm")
    if norms:
        path = directory / "quaternion_norm.png"
        jobs.append((path, lambda single, path=path: plot_series(results, norms, _unit(results, norms), path,
                                                                 f"{title}: norm of the Euler parameters minus 1")))
    return jobs


def write_plots(results: Results, unit: dict, directory: Path, title: str, *, workers: int = 1) -> list[Path]:
    """Write a PNG per state variable, one of tip deflections (if any), and the energy plot.

    Parameters
    ----------
    results : Results
    unit : dict of str to str
        Unit of every state variable (:func:`units` of the equations); the outputs' units are
        those declared with them (:attr:`Results.declared <flexkane.results.Results>`).
    directory : pathlib.Path
    title : str
        Title of the figures (the model's name).
    workers : int
        Processes that draw: 1 draws here; 2 (or more) draws every other figure in a fork of this
        process (:func:`~flexkane.plot_workers.draw_in_two`), on a second core, where forking is
        allowed (:func:`~flexkane.forking.fork_allowed`), else here. The files are the same bytes.

    Returns
    -------
    list of pathlib.Path
        The files written, in the same order whatever ``workers``.
    """
    jobs = _plot_jobs(results, unit, Path(directory), title)
    if workers > 1 and len(jobs) > 1:
        from .forking import fork_allowed

        if fork_allowed():
            from .plot_workers import draw_in_two

            return draw_in_two(jobs, _SeriesFigure)
    single = _SeriesFigure()
    return [draw(single) for _, draw in jobs]
