"""compile_model compiles eagerly: a simulation after it compiles nothing, and the CLI says so.

Deterministic signals instead of times: the Numba dispatchers hold their compiled signatures once
``compile_model`` returns, and ``simulate`` adds none.
"""

from __future__ import annotations

import pytest

from flexkane.builtin import builtin_model
from flexkane.derivation_cache import cached_derive
from flexkane.numerics import dop853, radau
from flexkane.numerics.jit_module import integrators_compiled, is_compiled
from flexkane.simulation import compile_model, simulate

FUNCTIONS = ("system_rhs", "rhs")  # the model's own; the integrators are the package's
INTEGRATORS = (dop853.dop853_chunk, radau.radau5_chunk, radau.fd_jacobian)


@pytest.fixture(scope="module")
def falling_beam():
    model = builtin_model("falling-beam")
    return model, cached_derive(model)


def test_integrators_are_compiled_before_simulate_and_not_after(falling_beam):
    model, eom = falling_beam
    messages = []
    compiled = compile_model(eom, announce=messages.append)
    module = compiled.module
    before = {name: list(getattr(module, name).signatures) for name in FUNCTIONS}
    before.update({f.py_func.__name__: list(f.signatures) for f in INTEGRATORS})
    assert all(before.values()), before
    assert is_compiled(module) and integrators_compiled()
    for method in ("auto", "dop853", "radau"):
        res = simulate(compiled, t_end=0.05, dt_out=0.01, method=method, model=model)
        assert not res.partial
        assert {"compile_time", "wall_time"} <= set(res.solver)
    after = {name: list(getattr(module, name).signatures) for name in FUNCTIONS}
    after.update({f.py_func.__name__: list(f.signatures) for f in INTEGRATORS})
    assert after == before
    # compiled in this process now: compiling again announces nothing
    again = []
    compile_model(eom, announce=again.append)
    assert again == []


def test_the_first_compile_of_the_integrators_is_announced(falling_beam, monkeypatch):
    from flexkane.numerics import jit_module
    from flexkane.simulation import COMPILING_MESSAGE, INTEGRATORS_MESSAGE

    model, eom = falling_beam
    compile_model(eom)
    monkeypatch.setattr(jit_module, "integrators_compiled", lambda: False)  # as on a new installation
    messages = []
    compile_model(eom, announce=messages.append)
    assert messages == [INTEGRATORS_MESSAGE]
    assert COMPILING_MESSAGE not in messages  # the model's own functions are compiled already


def test_outputs_compiled_on_first_use_give_the_same_results(falling_beam):
    """compile_model(outputs=False) leaves the outputs functions to their first call (a caller that
    evaluates the right-hand side only compiles less); a run then gives the same numbers."""
    import numpy as np

    from flexkane.errors import ModelError

    model, eom = falling_beam
    eager = simulate(compile_model(eom), t_end=0.05, dt_out=0.01, model=model)
    lazy_model = compile_model(eom, outputs=False)
    assert is_compiled(lazy_model.module)   # the right-hand side is
    lazy = simulate(lazy_model, t_end=0.05, dt_out=0.01, model=model)
    assert list(lazy.outputs) == list(eager.outputs)
    for name in eager.outputs:
        assert np.array_equal(lazy[name], eager[name]), name
    with pytest.raises(ModelError, match="outputs"):
        compile_model(eom, outputs="no")


#: A pendulum whose only coordinate a driver prescribes: nothing to integrate.
PRESCRIBED_PENDULUM = """
name = "prescribed-pendulum"
[bodies.bob]
mass = 1.0
inertia = 0.1
points = { pin = [-0.5, 0] }
[joints.pin]
type = "revolute"
parent = "ground"
child = "bob"
child_point = "pin"
driver = { coordinate = "sin(t)" }
[gravity]
g = 9.81
direction = [0, -1]
"""


def test_a_fully_prescribed_chain_derives_its_efforts_but_is_refused_a_run(tmp_path, capsys):
    """Inverse dynamics: the effort of the driver is derived; compiling a run of no state was a
    ValueError traceback of the code generator, now a ModelError (exit 2)."""
    import sympy as sp

    import flexkane
    from flexkane.cli import main

    model = flexkane.loads_model(PRESCRIBED_PENDULUM)
    eom = flexkane.derive(model)
    assert eom.state_names == [] and "effort_pin" in eom.output_names
    # at t = 0: q = 0, q' = 1, q'' = 0: the effort holds the weight's moment m g r = 1 * 9.81 * 0.5
    effort = sp.sympify(eom.outputs["effort_pin"]).xreplace(eom.constant_values(model)).xreplace({eom.t: 0})
    assert float(effort) == pytest.approx(9.81 * 0.5, rel=1e-12)
    with pytest.raises(flexkane.errors.ModelError, match="at least one coordinate that no coordinate driver"):
        flexkane.compile_model(eom, cache_dir=tmp_path)
    path = tmp_path / "prescribed.toml"
    path.write_text(PRESCRIBED_PENDULUM, "utf-8")
    assert main(["run", str(path), "--quiet", "--no-plots", "--out", str(tmp_path / "run")]) == 2
    assert "Traceback" not in capsys.readouterr().err
