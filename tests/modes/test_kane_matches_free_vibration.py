"""Kane's equations of a cantilever on a fixed base, integrated numerically, reproduce the modal
free-vibration solution of eqs. 8.3 and 8.5 (FreeVibration) to integrator tolerance."""

import numpy as np

import flexkane
from flexkane import Model
from flexkane.model.parts import Beam, Joint
from flexkane.modes import get_family
from flexkane.modes.free_vibration import FreeVibration

L, EI, RHO, N = 1.2, 20.0, 0.8, 4


def cantilever(alpha, velocities):
    """The beam B welded to the ground at its root, released with modal coordinates ``alpha`` [m]
    and modal speeds ``velocities`` [m/s]."""
    model = Model(name="cantilever", parameters={"L": L, "EI": EI, "rho": RHO})
    model.beams["B"] = Beam(name="B", L="L", EI="EI", rho="rho", n_modes=N)
    model.joints["clamp"] = Joint(name="clamp", type="weld", parent="ground", child="B")
    for i in range(N):
        model.initial[f"q_B_{i + 1}"] = float(alpha[i])
        model.initial[f"u_B_{i + 1}"] = float(velocities[i])
    return model.validate()


def test_kane_model_of_cantilever_matches_modal_free_vibration():
    family = get_family("clamped-free")
    shape = lambda xi: 0.02 * xi ** 2 * (3 - xi) / 2         # noqa: E731  released from a tip-load shape
    push = lambda xi: 0.05 * xi ** 3                          # noqa: E731  and given a velocity
    vibration = FreeVibration(family, N, L, EI, RHO, shape, push)
    p = vibration.frequencies
    model = cantilever(vibration.alpha, vibration.beta * p)
    t_end = 2 * (2 * np.pi / p[0])                            # two periods of the first mode
    eom = flexkane.derive(model)
    results = flexkane.simulate(flexkane.compile_model(eom), t_end=t_end, dt_out=t_end / 400,
                                rtol=1e-11, atol=1e-13)
    assert not results.partial
    x = np.array([L / 2, L])
    exact = vibration.deflection(x, results.t)                 # (T, 2): mid-span and tip
    modes = np.column_stack([results[f"q_B_{i + 1}"] for i in range(N)])
    kane = modes @ family.phi(x / L, N)
    scale = np.abs(exact).max()
    np.testing.assert_allclose(kane, exact, atol=1e-9 * scale)
    np.testing.assert_allclose(results["tip_B"], exact[:, 1], atol=1e-9 * scale)
    velocity = np.column_stack([results[f"u_B_{i + 1}"] for i in range(N)]) @ family.phi(x / L, N)
    np.testing.assert_allclose(velocity, vibration.velocity(x, results.t),
                               atol=1e-9 * np.abs(vibration.velocity(x, results.t)).max())
