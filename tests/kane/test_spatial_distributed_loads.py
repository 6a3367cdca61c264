"""Distributed loads on spatial beams: F_r = int v_P,r . f(x, t) dx with f in three components.

Oracles: the static tip deflection of a clamped beam under a uniform load, q L^4 / (8 EI), in each
bending plane (EI_z for the deflection along y, EI_y along z), and the generalized forces of a load
with separable and non-separable terms against an independent adaptive quadrature of the load
times the mode shape (scipy.integrate.quad).
"""

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import quad

import flexkane
from flexkane.errors import ModelError
from flexkane.model import loads_model
from flexkane.modes import get_family

L, EI_Y, EI_Z = 1.2, 5.0, 9.0

CLAMPED = """
dimensions = 3
name = "clamped-spatial-beam-under-load"

[parameters]
qy = 0.2
qz = -0.3

[beams.b]
L = 1.2
rho = 0.7
EI_y = 5.0
EI_z = 9.0
n_modes_y = {n}
n_modes_z = {n}

[joints.weld]
type = "weld"
parent = "ground"
child = "b"
{orientation}

[distributed_loads.w]
beam = "b"
frame = "{frame}"
{components}
"""


def _static_deflection(n: int, frame: str, components: str, orientation: str = ""):
    """Tip deflections along the beam frame's y and z [m] at the static equilibrium (forcing = 0 at u = 0)."""
    model = loads_model(CLAMPED.format(n=n, frame=frame, components=components, orientation=orientation))
    eom = flexkane.derive(model, cache=False)
    values = eom.constant_values()
    rest = {**{u: 0 for u in eom.u}, eom.t: 0.0}
    forcing = sp.Matrix([sp.sympify(f).xreplace(values).xreplace(rest) for f in eom.forcing])
    K = np.array(forcing.jacobian(list(eom.q)).evalf(), dtype=float)
    f0 = np.array(forcing.xreplace({q: 0 for q in eom.q}).evalf(), dtype=float).ravel()
    q = np.linalg.solve(K, -f0)
    names = [s.name for s in eom.q]
    tip = get_family("clamped-free").phi(np.array([1.0]), n)[:, 0]
    return tuple(float(tip @ q[[names.index(f"q_b_{d}{i}") for i in range(1, n + 1)]]) for d in "yz")


def test_uniform_load_on_a_clamped_spatial_beam_gives_q_L4_over_8EI_in_each_plane():
    """q L^4 / (8 EI) along y (EI_z) and z (EI_y); the modal truncation error falls with the modes."""
    exact = np.array([0.2 * L ** 4 / (8 * EI_Z), -0.3 * L ** 4 / (8 * EI_Y)])
    errors = [np.abs(np.array(_static_deflection(n, "beam", 'fy = "qy"\nfz = "qz"')) / exact - 1).max()
              for n in (1, 4)]
    assert errors[0] < 2e-2 and errors[1] < 1e-4, errors


def test_ground_components_are_turned_into_the_beam_frame():
    """The beam turned by 90 degrees about z (its x along N's y, its y along -N's x): a load along
    -N's x bends it along its own +y, one along N's z along its z."""
    exact = np.array([0.2 * L ** 4 / (8 * EI_Z), -0.3 * L ** 4 / (8 * EI_Y)])
    deflection = _static_deflection(4, "ground", 'fx = "-qy"\nfz = "qz"',
                                    "orientation = { axis = [0, 0, 1], angle = 1.5707963267948966 }")
    assert np.abs(np.array(deflection) / exact - 1).max() < 1e-4, deflection


def test_generalized_forces_equal_the_integral_of_the_load_times_the_mode_shapes():
    """F_r of each modal speed at q = 0: int f_y Phi_i dx and int f_z Phi_j dx, for a load with a
    separable profile and a travelling (non-separable) term, against scipy's adaptive quadrature."""
    n, t = 3, 0.3
    fy = lambda x: 0.4 * x ** 2 + 0.1 * np.sin(2.0 * x - 3.0 * t)   # noqa: E731
    fz = lambda x: -0.25 * np.exp(-x) * np.cos(1.5 * t)             # noqa: E731
    model = loads_model(CLAMPED.format(
        n=n, frame="beam", orientation="",
        components='fy = "0.4*x**2 + 0.1*sin(2*x - 3*t)"\nfz = "-0.25*exp(-x)*cos(1.5*t)"\nquadrature_nodes = 24'))
    eom = flexkane.derive(model, cache=False)
    values = eom.constant_values()
    state = {**{q: 0.0 for q in eom.q}, **{u: 0.0 for u in eom.u}, eom.t: t}
    family = get_family("clamped-free")
    shape = lambda i: (lambda x: family.phi(np.array([x / L]), n)[i - 1, 0])   # noqa: E731
    loads = eom.F_r["loads"]
    speeds = [u.name for u in eom.all_speeds]
    for d, f in (("y", fy), ("z", fz)):
        for i in range(1, n + 1):
            computed = float(sp.sympify(loads[speeds.index(f"u_b_{d}{i}")]).xreplace(values).xreplace(state))
            expected = quad(lambda x: f(x) * shape(i)(x), 0.0, L, epsabs=1e-14, epsrel=1e-13)[0]
            assert abs(computed - expected) <= 1e-10 * max(1.0, abs(expected)), (d, i, computed, expected)


def test_a_planar_model_refuses_fz():
    text = CLAMPED.format(n=1, frame="beam", orientation="", components='fy = "qy"')
    planar = """
name = "planar"
[beams.b]
L = 1.0
rho = 1.0
EI = 1.0
n_modes = 1
[joints.weld]
type = "weld"
parent = "ground"
child = "b"
[distributed_loads.w]
beam = "b"
fy = 1.0
fz = 2.0
"""
    assert loads_model(text).validate() is not None
    with pytest.raises(ModelError) as info:
        loads_model(planar).validate()
    assert "distributed_loads.w.fz" in str(info.value)
