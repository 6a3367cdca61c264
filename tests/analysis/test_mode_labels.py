"""Mode labels: the printed share of a mode's motion is the one modes.csv gives, and the modes of a
free joint are named by the motion of its body (translation along, rotation about an axis).

The spatial model is a free bus with two equal booms cantilevered from its sides (one bending mode per
plane each, no torsion): free in space it has six rigid-body modes, and each bending mode moves both
booms with the bus (the booms symmetric, the mode shared), so that no boom owns it.
"""

from __future__ import annotations

import csv
import re

import numpy as np
import pytest

import flexkane
from flexkane.analysis import Linearization, modal_analysis
from flexkane.cli import main
from flexkane.model import loads_model

BOOM = """
L = 1.5
rho = 2.0
EI_y = 50.0
EI_z = 400.0
GJ = 30.0
rho_Ip = 0.01
n_modes_y = 1
n_modes_z = 1
"""

BUS_WITH_BOOMS = f"""
dimensions = 3
name = "bus-with-booms"

[bodies.bus]
mass = 20.0
inertia = [2.0, 2.5, 3.0]
points = {{ left = [0, -0.5, 0], right = [0, 0.5, 0] }}

[beams.right]
{BOOM}
[beams.left]
{BOOM}
[joints.float]
type = "free"
parent = "ground"
child = "bus"

[joints.right_root]
type = "weld"
parent = "bus"
parent_point = "right"
child = "right"
orientation = {{ axis = [0, 0, 1], angle = "pi/2" }}

[joints.left_root]
type = "weld"
parent = "bus"
parent_point = "left"
child = "left"
orientation = {{ axis = [0, 0, 1], angle = "-pi/2" }}
"""

MOTIONS = [f"translation along {a} of bus" for a in "xyz"] + [f"rotation about {a} of bus" for a in "xyz"]


@pytest.fixture(scope="module")
def bus():
    return modal_analysis(Linearization(loads_model(BUS_WITH_BOOMS), about="rest").at(outputs=False))


def printed_shares(table: str) -> list[tuple[str, float]]:
    """(label, share [-]) of every row of a printed table of modes."""
    return [(m.group(1), float(m.group(2)) / 100) for m in re.finditer(r"  ((?:\S+ )*\S+) \((\d+) %\)$", table, re.M)]


def test_printed_share_of_a_mode_shared_by_two_beams_is_the_share_modes_csv_gives(bus):
    rows = list(csv.DictReader(bus.csv_text().splitlines()))
    shared = [r for r in rows if r["motion"] == "bending z 1"]
    assert len(shared) == 1          # labelled by its kind, owned by neither boom
    row = shared[0]
    per_boom = [float(row["participation bending z left"]), float(row["participation bending z right"])]
    assert per_boom[0] == pytest.approx(per_boom[1], rel=1e-6) and per_boom[0] < 0.75 * sum(per_boom)
    assert float(row["motion share [-]"]) == pytest.approx(sum(per_boom), rel=1e-12)
    printed = dict(printed_shares(bus.table()))
    assert printed["bending z 1"] == pytest.approx(sum(per_boom), abs=0.005) and printed["bending z 1"] > 0.5
    for label, share in printed_shares(bus.table()):     # every label: the share written beside it
        written = next(float(r["motion share [-]"]) for r in rows if r["motion"] == label)
        assert share == pytest.approx(written, abs=0.005)


def test_rigid_body_modes_of_a_free_joint_are_named_by_the_motion_of_its_body(bus):
    assert [m.label for m in bus.rigid] == [f"{motion} 1" for motion in MOTIONS]
    coordinates = bus.linear.coordinates
    moved = ["q_float_x", "q_float_y", "q_float_z", "rx_float", "ry_float", "rz_float"]
    for mode, coordinate in zip(bus.rigid, moved):
        assert mode.share == pytest.approx(1.0, abs=1e-12)
        expected = np.zeros(len(coordinates))
        expected[coordinates.index(coordinate)] = 1.0
        np.testing.assert_allclose(mode.shape, expected, atol=1e-9)
    assert not any("joint float" in m.label for m in bus.modes)
    assert {f"participation {motion}" for motion in MOTIONS} <= set(bus.csv_text().splitlines()[0].split(","))


def test_rigid_translation_of_a_turned_planar_body_is_along_its_own_axis():
    model = flexkane.builtin_model("falling-beam-exact")    # RB turned by q3 = 1 rad, on a free joint
    model.parameters["g"] = 0
    modal = modal_analysis(Linearization(model, about="rest").at(outputs=False))
    assert [m.label for m in modal.rigid] == ["translation along x of RB 1", "translation along y of RB 1",
                                              "rotation of RB 1"]
    along_x, along_y = (modal.rigid[k].shape[:2] for k in (0, 1))
    turn = float(modal.linear.q0[2])
    assert turn == pytest.approx(1.0)
    np.testing.assert_allclose(along_x / np.linalg.norm(along_x), [np.cos(turn), np.sin(turn)], atol=1e-9)
    np.testing.assert_allclose(along_y / np.linalg.norm(along_y) * np.sign(along_y[1]),
                               [-np.sin(turn), np.cos(turn)], atol=1e-9)
    assert all(m.share == pytest.approx(1.0, abs=1e-12) for m in modal.rigid)


def test_linearize_prints_the_share_that_modes_csv_writes(tmp_path, capsys):
    out = tmp_path / "lin"
    model = tmp_path / "bus.toml"
    model.write_text(BUS_WITH_BOOMS)
    assert main(["linearize", str(model), "--about", "rest", "--out", str(out)]) == 0
    printed = printed_shares(capsys.readouterr().out)
    with open(out / "modes.csv", newline="") as handle:
        written = {r["motion"]: float(r["motion share [-]"]) for r in csv.DictReader(handle)}
    assert [label for label, _ in printed] == list(written)
    for label, share in printed:
        assert share == pytest.approx(written[label], abs=0.005)
    assert ("rotation about z of bus 1", 1.0) in printed and written["bending z 1"] > 0.5


SPHERICAL_PENDULUM = """
dimensions = 3
name = "spherical-pendulum"

[bodies.bob]
mass = 1.5
inertia = [0.01, 0.02, 0.03]
points = { top = [0, 0, 0.4] }

[joints.pivot]
type = "spherical"
parent = "ground"
child = "bob"
child_point = "top"

[gravity]
g = 9.81
direction = [0, 0, -1]
"""


def test_modes_of_a_spherical_joint_are_turns_of_its_body_about_its_axes():
    modal = modal_analysis(Linearization(loads_model(SPHERICAL_PENDULUM), about="equilibrium").at(outputs=False))
    labels = {m.label: m for m in modal.modes}
    assert sorted(labels) == ["rotation about x of bob 1", "rotation about y of bob 1", "rotation about z of bob 1"]
    assert labels["rotation about z of bob 1"].kind == "rigid"        # a turn about the vertical
    m, g, length = 1.5, 9.81, 0.4                                      # swings about the pivot's axes
    for axis, inertia in (("x", 0.01), ("y", 0.02)):
        mode = labels[f"rotation about {axis} of bob 1"]
        assert mode.omega == pytest.approx(np.sqrt(m * g * length / (inertia + m * length ** 2)), rel=1e-9)
        assert mode.share == pytest.approx(1.0, abs=1e-12)
