"""A model that fails legitimately, compiled once per session for the solver-failure and
interruption tests (the compiled module goes to the session's FLEXKANE_CACHE_DIR, where the
subprocesses of those tests find it)."""

import pathlib

import pytest

MODELS = pathlib.Path(__file__).parent / "models"


@pytest.fixture(scope="session")
def torque_pendulum_file() -> pathlib.Path:
    """Rigid pendulum driven by the torque T0/(t1 - t), infinite at t = t1 = 1 s."""
    return MODELS / "torque-pendulum.toml"


@pytest.fixture(scope="session")
def torque_pendulum(torque_pendulum_file):
    """The model and its compiled equations (one Numba compilation for the whole session)."""
    import flexkane

    model = flexkane.load_model(torque_pendulum_file)
    return model, flexkane.compile_model(flexkane.derive(model))
