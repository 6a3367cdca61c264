"""Sweep plots carry units on their axes: of the varied key (a field, a parameter through the field it
feeds, an initial condition through its coordinate) and of the metric."""

import flexkane
from flexkane.sweep.plot import _label, column_units, plot_metric


def test_units_of_fields_parameters_and_initial_conditions():
    arm = flexkane.builtin_model("flexible-arm")
    units = column_units(arm, ["beams.link.EI", "EI", "parameters.rho", "initial.q_shoulder", "u_shoulder",
                               "bodies.hub.mass", "joints.shoulder.torque", "no_such_key"])
    assert units["beams.link.EI"] == units["EI"] == "N m^2"
    assert units["parameters.rho"] == "kg/m" and units["bodies.hub.mass"] == "kg"
    assert units["initial.q_shoulder"] == "rad" and units["u_shoulder"] == "rad/s"
    assert units["joints.shoulder.torque"] == "N m" and "no_such_key" not in units
    assert units["final_q_link_1"] == "m"
    beam = flexkane.builtin_model("falling-beam-exact")
    assert column_units(beam, ["g", "initial.q4"]) == {**column_units(beam, []), "g": "m/s^2", "initial.q4": "m"}


def test_axis_labels_name_the_units(tmp_path, monkeypatch):
    import matplotlib.axes

    labels = []
    for name in ("set_xlabel", "set_ylabel"):
        original = getattr(matplotlib.axes.Axes, name)

        def record(self, text, *args, _original=original, **kwargs):
            labels.append(text)
            return _original(self, text, *args, **kwargs)

        monkeypatch.setattr(matplotlib.axes.Axes, name, record)
    rows = [{"variant": str(k), "status": "ok", "beams.link.EI": ei, "max_abs_tip_link": 1.0 / ei}
            for k, ei in enumerate((8.0, 16.0, 24.0))]
    units = column_units(flexkane.builtin_model("flexible-arm"), ["beams.link.EI"])
    plot_metric(rows, "max_abs_tip_link", ["beams.link.EI"], tmp_path / "p.png", units=units)
    assert "beams.link.EI [N m^2]" in labels and "max_abs_tip_link [m]" in labels
    assert _label("energy_error") == "energy_error [-]"
