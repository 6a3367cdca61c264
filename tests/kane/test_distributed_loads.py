"""Distributed loads on beams: F_r = int v_P,r . f(x, t) dx (issue 14, item 7)."""

import numpy as np
import pytest
import sympy as sp

import flexkane
from flexkane.errors import ModelError
from flexkane.modes import get_family

CANTILEVER = """
name = "cantilever-distributed-load"
[parameters]
L = 1.0
EI = 2.0
rho = 0.5
q0 = 0.3
[beams.beam]
L = "L"
EI = "EI"
rho = "rho"
n_modes = {n}
[joints.clamp]
type = "weld"
parent = "ground"
child = "beam"
[distributed_loads.w]
beam = "beam"
fy = "{fy}"
"""


def _static_tip(model):
    """Tip deflection [m] at the static equilibrium of the derived equations (forcing = 0 at u = 0)."""
    eom = flexkane.derive(model)
    values = eom.constant_values(model)
    rest = {**{u: 0 for u in eom.u}, eom.t: 0.0}
    forcing = sp.Matrix([sp.sympify(f).xreplace(values).xreplace(rest) for f in eom.forcing])
    K = np.array(forcing.jacobian(list(eom.q)).evalf(), dtype=float)
    f0 = np.array(forcing.xreplace({q: 0 for q in eom.q}).evalf(), dtype=float).ravel()
    q = np.linalg.solve(K, -f0)
    return float(sp.sympify(eom.outputs["tip_beam"]).xreplace(values).xreplace(dict(zip(eom.q, q))))


@pytest.mark.parametrize("fy", ["-q0", "-q0*cos(x*t)"])   # separable; evaluated at quadrature nodes
def test_uniform_load_on_a_cantilever_gives_q0_L4_over_8EI(fy):
    exact = -0.3 * 1.0 ** 4 / (8 * 2.0)
    errors = [abs(_static_tip(flexkane.loads_model(CANTILEVER.format(n=n, fy=fy))) / exact - 1)
              for n in (1, 2, 4, 8)]
    # the modal truncation error of the static solution, falling with the number of modes
    assert errors[0] < 2e-2 and errors[-1] < 2e-6
    assert all(b < a for a, b in zip(errors, errors[1:]))


PENDULUM = """
name = "beam-in-the-wind"
[parameters]
L = 2.0
EI = 5.0
rho = 0.8
[beams.B]
L = "L"
EI = "EI"
rho = "rho"
n_modes = 3
[joints.pin]
type = "revolute"
parent = "ground"
child = "B"
[distributed_loads.wind]
beam = "B"
frame = "{frame}"
fx = "0.4*x*sin(2*t) + 0.1"
fy = "sin(3*x/L - 2*t)*exp(x/L)"
quadrature_nodes = 24
"""


@pytest.mark.parametrize("frame", ["ground", "beam"])
def test_power_of_a_distributed_load_equals_the_integral_of_v_dot_f(frame):
    """sum_r u_r F_r equals int v_P . f dx computed directly along the beam from the shape functions."""
    model = flexkane.loads_model(PENDULUM.format(frame=frame))
    eom = flexkane.derive(model)
    values = eom.constant_values(model)
    rng = np.random.default_rng(7)
    L, n = 2.0, 3
    family = get_family("clamped-free")
    x = np.linspace(0.0, L, 4001)
    phi = family.phi(x / L, n)
    t_sym = eom.t
    for _ in range(3):
        q = rng.normal(size=n + 1) * np.array([1.0, 0.05, 0.02, 0.01])
        u = rng.normal(size=n + 1)
        t = float(rng.uniform(0, 3))
        state = {**dict(zip(eom.q, q)), **dict(zip(eom.u, u)), t_sym: t}
        power = sum(float(sp.sympify(f).xreplace(values).xreplace(state)) * ur
                    for f, ur in zip(eom.F_r["loads"], u))
        theta, modes = q[0], q[1:]
        y, ydot = modes @ phi, u[1:] @ phi
        # velocity of the beam point in the beam frame: w x (x, y) + (0, y')
        v_beam = np.vstack([-u[0] * y, u[0] * x + ydot])
        fx = 0.4 * x * np.sin(2 * t) + 0.1
        fy = np.sin(3 * x / L - 2 * t) * np.exp(x / L)
        if frame == "ground":
            c, s = np.cos(theta), np.sin(theta)
            fx, fy = c * fx + s * fy, -s * fx + c * fy
        direct = np.trapezoid(v_beam[0] * fx + v_beam[1] * fy, x)
        assert power == pytest.approx(direct, rel=1e-6, abs=1e-9)


def test_distributed_load_fields_are_checked():
    text = CANTILEVER.format(n=2, fy="-q0")
    with pytest.raises(ModelError, match=r"distributed_loads\.w\.beam.*did you mean 'beam'"):
        flexkane.loads_model(text.replace('beam = "beam"\nfy', 'beam = "bam"\nfy'))
    with pytest.raises(ModelError, match=r"distributed_loads\.w\.frame"):
        flexkane.loads_model(text + 'frame = "local"\n')
    with pytest.raises(ModelError, match=r"distributed_loads\.w\.fy.*finite"):
        flexkane.loads_model(CANTILEVER.format(n=2, fy="1/x"))
    with pytest.raises(ModelError, match=r"distributed_loads\.w\.fy"):
        flexkane.loads_model(CANTILEVER.format(n=2, fy="q0*y"))
    with pytest.raises(ModelError, match=r"distributed_loads\.w\.quadrature_nodes"):
        flexkane.loads_model(text + "quadrature_nodes = 0\n")
    with pytest.raises(ModelError, match=r"distributed_loads\.w\.fz.*did you mean 'fy'"):
        flexkane.loads_model(text + 'fz = "1"\n')
    model = flexkane.loads_model(text)
    assert flexkane.loads_model(flexkane.dumps_model(model)) == model


@pytest.mark.slow
def test_slowly_applied_uniform_load_settles_at_the_static_tip_deflection():
    """A damped cantilever under a load ramped up over 2 s ends at q0 L^4 / (8 EI) (4 modes)."""
    text = CANTILEVER.format(n=4, fy="-q0*min(t/2, 1)").replace("n_modes = 4", "n_modes = 4\ndamping = [0.7]")
    model = flexkane.loads_model(text)
    res = flexkane.simulate(flexkane.compile_model(flexkane.derive(model)), t_end=6.0, dt_out=0.05,
                            rtol=1e-10, atol=1e-12)
    assert res["tip_beam"][-1] == pytest.approx(-0.3 / 16, rel=1e-4)


@pytest.mark.slow
def test_work_of_a_time_varying_distributed_load_equals_the_change_of_energy():
    model = flexkane.loads_model(PENDULUM.format(frame="ground"))
    res = flexkane.simulate(flexkane.compile_model(flexkane.derive(model)), t_end=2.0, dt_out=1e-4,
                            rtol=1e-11, atol=1e-12)
    power = res["power_nonconservative"]
    work = np.concatenate([[0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * np.diff(res.t))])
    change = res["energy"] - res["energy"][0]
    assert np.max(np.abs(work)) > 0.1                              # the load does work
    assert np.max(np.abs(change - work)) < 1e-6 * np.max(np.abs(work)) + 1e-9
