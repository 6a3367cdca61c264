"""Plots and results files of a run: every plot is rendered and checked for drawn curves and labelled
axes; results.npz reads back what was written."""

import pickle
import numpy as np
import pytest
from PIL import Image

import flexkane
from flexkane import plots
from flexkane.model import dumps_model
from flexkane.model.columns import Output
from flexkane.plots import plot_runs, write_plots
from flexkane.run_manifest import units
from flexkane.results import Results, load_results
from flexkane.numerics import evaluate_outputs

#: matplotlib's first two colours (C0, C1): the curves.
CURVE_COLOURS = ("#1f77b4", "#ff7f0e")


def synthetic_run(name: str, rows: int = 60):
    """Equations and made-up results of a built-in model: a slow oscillation of every state variable
    about the initial state, with the outputs evaluated on it (no integration)."""
    model = flexkane.builtin_model(name)
    eom = flexkane.derive(model)
    values = eom.constant_values(model)
    p = np.array([values[s] for s in eom.constants])
    t = np.linspace(0.0, 2.0, rows)
    y0 = eom.initial_state(model)
    waves = np.sin(np.outer(t, 1.0 + np.arange(len(y0))))
    state = y0 + 0.01 * waves
    outputs = evaluate_outputs(flexkane.compile_model(eom).module, t, state, p)   # compiled outputs
    res = Results(t=t, state=state, state_names=eom.state_names, outputs=outputs, model_text=dumps_model(model),
                  parameters={s.name: values[s] for s in eom.constants},
                  solver={"method": "none", "nsteps": 0}, declared={o.name: o for o in eom.output_declarations})
    return eom, res


def curve_pixels(path) -> int:
    """Pixels of the PNG drawn in the colours of the curves."""
    image = np.asarray(Image.open(path).convert("RGB")).astype(int)
    count = 0
    for colour in CURVE_COLOURS:
        rgb = np.array([int(colour[i:i + 2], 16) for i in (1, 3, 5)])
        count += int(np.all(np.abs(image - rgb) <= 40, axis=-1).sum())
    return count


@pytest.fixture
def captured_figures(monkeypatch):
    """The matplotlib figures the plot functions save, by file name (the files are still written)."""
    figures = {}
    save = plots._save

    def keep(fig, path):
        figures[path.name] = pickle.loads(pickle.dumps(fig))   # as saved (a figure may be reused)
        return save(fig, path)
    monkeypatch.setattr(plots, "_save", keep)
    return figures


def test_every_state_variable_tip_effort_and_energy_is_plotted_with_a_curve(tmp_path, captured_figures):
    eom, res = synthetic_run("spin-up-linear")
    paths = write_plots(res, units(eom), tmp_path, eom.model.name)
    names = {p.name for p in paths}
    assert {f"{n}.png" for n in res.state_names} <= names
    assert {"tip_deflection.png", "effort_hub.png", "energy.png"} <= names
    for path in paths:
        assert curve_pixels(path) > 150, path.name
    labels = {name: (fig.axes[0].get_xlabel(), fig.axes[0].get_ylabel()) for name, fig in captured_figures.items()}
    assert labels["q_hub.png"] == ("t [s]", "q_hub [rad]")
    assert labels["q_beam_1.png"] == ("t [s]", "q_beam_1 [m]")
    assert labels["u_beam_2.png"] == ("t [s]", "u_beam_2 [m/s]")
    assert labels["effort_hub.png"] == ("t [s]", "effort_hub [N m]")
    assert labels["tip_deflection.png"] == ("t [s]", "tip_beam [m]")
    energy = captured_figures["energy.png"]
    assert energy.axes[0].get_ylabel() == "energy [J]" and energy.axes[1].get_xlabel() == "t [s]"
    assert energy.axes[1].get_ylabel().startswith("balance (E - E0 - W)")


def test_tip_deflection_plot_has_one_curve_per_beam_in_its_frame(tmp_path, captured_figures):
    eom, res = synthetic_run("two-link-flexible-arm")
    one = Results(t=res.t, state=res.state[:, :1], state_names=res.state_names[:1], outputs=res.outputs,
                  declared=res.declared)
    write_plots(one, units(eom), tmp_path, eom.model.name)
    fig = captured_figures["tip_deflection.png"]
    assert [line.get_label() for line in fig.axes[0].get_lines()] == ["tip_upper", "tip_fore"]
    assert "beam frame" in fig.axes[0].get_title()
    assert curve_pixels(tmp_path / "tip_deflection.png") > 300


def test_runs_compared_on_a_log_scale_and_in_panels(tmp_path, captured_figures):
    eom, a = synthetic_run("spin-up-linear", rows=40)
    b = Results(t=a.t, state=a.state, state_names=a.state_names, outputs={k: 1e3 * v for k, v in a.outputs.items()})
    path = plot_runs({"linear": a, "stiffened": b}, ["tip_beam"], tmp_path / "tip.png", units=units(eom), log=True)
    assert curve_pixels(path) > 150
    ax = captured_figures["tip.png"].axes[0]
    assert ax.get_yscale() == "log" and ax.get_ylabel() == "|tip_beam| [m]"
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["linear", "stiffened"]
    six = plot_runs({"a": a}, a.state_names[:5], tmp_path / "grid.png", units=units(eom), columns=3)
    fig = captured_figures["grid.png"]
    assert sum(ax.get_visible() for ax in fig.axes) == 5 and curve_pixels(six) > 500


def test_results_npz_reads_back_state_outputs_model_parameters_and_solver(tmp_path):
    _, res = synthetic_run("flexible-arm", rows=7)
    res.solver = {"method": "dop853", "nsteps": 12, "rtol": 1e-8}
    res.write(tmp_path)
    back = load_results(tmp_path)
    np.testing.assert_array_equal(back.t, res.t)
    np.testing.assert_array_equal(back.state, res.state)
    assert back.state_names == res.state_names and list(back.outputs) == list(res.outputs)
    for name in res.outputs:
        np.testing.assert_array_equal(back[name], res[name])
    assert back.model_text == res.model_text and back.parameters == res.parameters
    assert back.solver == res.solver and back.version == flexkane.__version__ and not back.partial
    assert flexkane.loads_model(back.model_text).name == "flexible-arm"


def test_run_with_no_plots_writes_no_png(tmp_path, capsys):
    from flexkane.cli import main

    out = tmp_path / "run"
    assert main(["run", "falling-beam", "--out", str(out), "--quiet", "--t-end", "0.05", "--no-plots"]) == 0
    written = {p.name for p in out.iterdir()}
    assert {"results.csv", "results.npz", "equations.md"} <= written
    assert not [name for name in written if name.endswith(".png")]


def test_energy_plot_shows_energies_work_and_the_balance(tmp_path, captured_figures):
    _, res = synthetic_run("flexible-arm")
    e = res["energy"]
    res.outputs["work"] = (e - e[0]) * (1 + 1e-6)  # made up: a balance of 1e-6 (E - E0)
    res.outputs["energy_balance"] = e - e[0] - res.outputs["work"]
    plots.plot_energy(res, tmp_path / "energy.png")
    upper, lower = captured_figures["energy.png"].axes
    labels = [line.get_label() for line in upper.get_lines()]
    assert labels[0] == "total E" and "kinetic" in labels and "strain" in labels
    assert "E0 + work W" in labels
    scale = max(np.abs(e).max(), np.abs(res["kinetic"]).max())
    np.testing.assert_allclose(lower.get_lines()[0].get_ydata(), res["energy_balance"] / scale)


def test_results_npz_keeps_timing_apart_and_its_bytes_do_not_depend_on_the_clock(tmp_path):
    _, res = synthetic_run("flexible-arm", rows=7)
    for name in "abc":
        (tmp_path / name).mkdir()
    res.solver = {"method": "dop853", "nsteps": 12, "wall_time": 0.5, "compile_time": 2.0}
    res.write(tmp_path / "a")
    res.solver = {"method": "dop853", "nsteps": 12, "wall_time": 0.7, "compile_time": 3.0}
    res.write(tmp_path / "b")
    with np.load(tmp_path / "a" / "results.npz") as a, np.load(tmp_path / "b" / "results.npz") as b:
        assert "wall_time" not in str(a["solver"]) and "wall_time" in str(a["timing"])
        assert all(a[k].tobytes() == b[k].tobytes() for k in a.files if k != "timing")
    assert load_results(tmp_path / "b").solver["wall_time"] == 0.7
    res.write(tmp_path / "c")
    assert (tmp_path / "b" / "results.npz").read_bytes() == (tmp_path / "c" / "results.npz").read_bytes()


def test_spatial_beam_tips_are_plotted_deflections_in_metres_twist_and_slopes_in_radians(tmp_path, captured_figures):
    """A spatial beam's ``tip_<b>_y``, ``tip_<b>_z`` [m] share the tip deflection plot; its
    ``twist_<b>`` and slopes [rad] have a plot of their own."""
    t = np.linspace(0.0, 1.0, 40)
    outputs = {"tip_b_y": 0.01 * np.sin(3 * t), "tip_b_z": 0.02 * np.cos(2 * t), "slope_b_y": 0.01 * t,
               "slope_b_z": -0.02 * t, "twist_b": 0.05 * np.sin(5 * t)}
    declared = {n: Output(n, None, "rad" if n.startswith(("slope", "twist")) else "m", n.split("_")[0], n)
                for n in outputs}
    res = Results(t=t, state=np.zeros((len(t), 0)), state_names=[], outputs=outputs, declared=declared)
    write_plots(res, {}, tmp_path, "spatial")
    tips = captured_figures["tip_deflection.png"].axes[0]
    assert [line.get_label() for line in tips.get_lines()] == ["tip_b_y", "tip_b_z"]
    twist = captured_figures["tip_twist.png"].axes[0]
    assert [line.get_label() for line in twist.get_lines()] == ["slope_b_y", "slope_b_z", "twist_b"]
    assert twist.get_ylabel().endswith("[rad]")
    assert curve_pixels(tmp_path / "tip_twist.png") > 300
