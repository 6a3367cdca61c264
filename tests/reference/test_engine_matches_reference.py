"""The engine gives the numbers of the stored reference set (``tests/reference/*.npz``).

Why this is the oracle for a rebuilt engine
-------------------------------------------
The reference set was written by ``tests/reference/generate.py`` with the engine of the commit named
in each file's ``engine`` entry, the one whose equations the rest of the test suite checks against
physics (eqs. 8.23 and 8.31 term by term, energy balance, ``sympy.physics.mechanics``, published
values). A rebuild of the derivation (body-by-body kinematics with named intermediates, another code
generator, integrators compiled once) must change how the equations are computed, not what they are:
the right-hand side ``[q', u']`` of every built-in model and example at any state must be the same
function. Comparing at stored states catches any term that is lost, doubled or changed, in every
model at once, without re-deriving the old engine; the short runs check the whole path (constants,
initial state, loop closure, outputs) end to end.

What is compared, and how
-------------------------
Only engine-agnostic values, by name: the model is rebuilt from the model text stored with the
values; its constants come from the public ``eom.constant_values(model)`` (never a stored constants
vector, whose order and internal names an engine may change); stored states are placed by the names
of ``eom.state_names`` (other state entries, e.g. quadratures an engine appends after ``[q, u]``,
are 0 and not compared); outputs are looked up by name in the results.

* Right-hand side: ``|dy_new - dy_ref| <= 1e-10 |dy_ref| + 1e-11 s_k`` for each component ``k`` at
  each stored state, ``s_k`` the largest ``|dy_ref_k|`` over the stored states (the component's
  scale; the floor admits round-off of a component that is a near-cancelling sum at one state). The
  stored values carry round-off of about 1e-15 of ``s_k`` (``rhs_check``: their difference from
  ``M^-1 f`` evaluated in 30-digit arithmetic), so the tolerance is four orders above it.
* Trajectory (DOP853 at the stored ``traj_rtol = 1e-11``, ``traj_atol = 1e-13``):
  ``|y_new - y_ref| <= e_c + 1e-10 s_c + 1e-12`` for each column ``c``, with ``s_c`` the largest
  ``|y_ref_c|`` over the run (for energies, the largest of any energy column) and ``e_c`` the stored
  ``traj_error``: the largest difference between the stored run and the same run at ten times the
  tolerances, an estimate of the global error at those looser tolerances, hence about ten times the
  stored run's own error. So an engine that integrates the same equations at the same tolerances,
  with whatever round-off, step sequence or even another integrator of that accuracy, passes, while
  a change of the physics larger than the integration error does not. ``1e-12`` is an absolute
  floor in SI units (m, rad, J, N ...) for columns that are 0 or round-off in the reference (a spring
  energy of a model without springs, the tip of a pinned-pinned rod).

Cost: the models are derived and compiled once per module (fixture ``engine``). Measured on the
2-core machine: the right-hand-side half (default run) 56 s from an empty compiled-model cache and
20 s with a warm one (derivations); the trajectory half compiles the integrator loops of every model
too, 256 s from an empty cache, so it is marked slow (``pytest -m slow tests/reference``).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import flexkane

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
REFERENCE_NAMES = sorted(path.stem for path in HERE.glob("*.npz"))

#: Relative tolerance of the right-hand side, and its floor as a fraction of the component's scale.
RHS_RTOL = 1e-10
RHS_FLOOR = 1e-11
#: Trajectory: relative part (of the column's scale) and absolute floor (SI units) of the tolerance,
#: added to the stored error estimate ``traj_error``.
TRAJ_RTOL = 1e-10
TRAJ_ABS_FLOOR = 1e-12
ENERGY_COLUMNS = ("kinetic", "potential_gravity", "strain", "potential_springs", "energy")


def load_reference(name: str) -> dict:
    with np.load(HERE / f"{name}.npz", allow_pickle=False) as data:
        return {key: data[key] for key in data.files}


@pytest.fixture(scope="module")
def engine():
    """``engine(name) -> (reference, model, eom, compiled, p)``, built once per model per module."""
    cache = {}

    def build(name):
        if name not in cache:
            ref = load_reference(name)
            model = flexkane.loads_model(str(ref["model_text"]), source=name)
            eom = flexkane.derive(model)
            compiled = flexkane.compile_model(eom, outputs=False)   # the outputs compile when a run needs them
            values = eom.constant_values(model)
            p = np.array([values[s] for s in eom.constants], dtype=float)
            cache[name] = (ref, model, eom, compiled, p)
        return cache[name]

    return build


def state_positions(eom, names) -> list[int]:
    """Positions in ``eom.state_names`` of the stored state names (all must be there)."""
    current = list(eom.state_names)
    missing = [n for n in names if n not in current]
    assert not missing, f"state variables {missing} of the reference are not in the state {current}"
    return [current.index(n) for n in names]


def test_every_builtin_model_and_example_has_a_reference():
    names = set(flexkane.builtin_names()) | {path.stem for path in (ROOT / "examples").glob("*.toml")}
    missing = sorted(names - set(REFERENCE_NAMES))
    assert not missing, (f"no stored reference for {missing}: run tests/reference/generate.py with the "
                         "engine the reference set comes from")


def test_reference_set_is_small():
    sizes = {name: (HERE / f"{name}.npz").stat().st_size for name in REFERENCE_NAMES}
    assert max(sizes.values()) < 100_000 and sum(sizes.values()) < 2_000_000, sizes


@pytest.mark.parametrize("name", REFERENCE_NAMES)
def test_right_hand_side_matches_reference(name, engine):
    check_right_hand_side(name, *engine(name))


#: The references of the models whose bases gained static correction shapes (their beams carry
#: something at the tip), stored before the shapes were added: ``static_corrections = false``
#: restores those numbers (the planar one in the default run; the spatial one compiles for ~20 s).
MODES_ONLY = sorted(path.stem for path in (HERE / "modes-only").glob("*.npz"))


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n != "flexible-arm" else n
                                  for n in MODES_ONLY])
def test_static_corrections_off_gives_the_reference_of_the_modes_alone(name):
    with np.load(HERE / "modes-only" / f"{name}.npz", allow_pickle=False) as data:
        ref = {key: data[key] for key in data.files}
    text = re.sub(r"^(\[beams\.[A-Za-z_0-9]+\])$", r"\1\nstatic_corrections = false", str(ref["model_text"]),
                  flags=re.MULTILINE)
    model = flexkane.loads_model(text, source=name)
    assert all(beam.static_corrections is False for beam in model.beams.values())
    eom = flexkane.derive(model)
    values = eom.constant_values(model)
    check_right_hand_side(name, ref, model, eom, flexkane.compile_model(eom, outputs=False),
                          np.array([values[s] for s in eom.constants], dtype=float))


def check_right_hand_side(name, ref, model, eom, compiled, p) -> None:
    """Fail unless the compiled right-hand side gives the reference's at its stored states."""
    names = [str(n) for n in ref["state_names"]]
    where = state_positions(eom, names)
    n_state = len(eom.state_names)
    expected = ref["rhs_dy"]
    scale = np.abs(expected).max(axis=0)
    scale = np.where(scale > 0, scale, np.abs(expected).max())
    for k, (t, y_ref) in enumerate(zip(ref["rhs_t"], ref["rhs_y"])):
        y = np.zeros(n_state)
        y[where] = y_ref
        dy = compiled.rhs(float(t), y, p)[where]
        error = np.abs(dy - expected[k])
        tol = RHS_RTOL * np.abs(expected[k]) + RHS_FLOOR * scale
        if np.all(error <= tol):
            continue
        # which equation differs: residual of the reference M u' = f with the new u'
        nq, nu = len(eom.q), ref["rhs_forcing"].shape[1]
        residual = ref["rhs_mass_matrix"][k] @ dy[nq:nq + nu] - ref["rhs_forcing"][k]
        bad = [f"{names[j]}: {dy[j]!r} vs {expected[k, j]!r}" for j in np.flatnonzero(error > tol)]
        pytest.fail(f"{name}, state {k} (t = {t}): right-hand side differs from the reference in "
                    f"{'; '.join(bad)}; residual of the reference M u' = f: {residual}")


@pytest.mark.slow
@pytest.mark.parametrize("name", REFERENCE_NAMES)
def test_trajectory_matches_reference(name, engine):
    ref, model, eom, compiled, p = engine(name)
    t_ref = ref["traj_t"]
    results = flexkane.simulate(compiled, t_end=float(t_ref[-1]), dt_out=float(t_ref[-1]) / (len(t_ref) - 1),
                                rtol=float(ref["traj_rtol"]), atol=float(ref["traj_atol"]),
                                method=str(ref["traj_method"]), model=model)
    assert not results.partial, results.solver["message"]
    np.testing.assert_allclose(results.t, t_ref, rtol=1e-14, atol=0)
    columns = [str(n) for n in ref["traj_names"]]
    expected = ref["traj_values"]
    scale = np.abs(expected).max(axis=0)
    energy = [j for j, c in enumerate(columns) if c in ENERGY_COLUMNS]
    if energy:
        scale[energy] = scale[energy].max()
    tol = ref["traj_error"] + TRAJ_RTOL * scale + TRAJ_ABS_FLOOR
    failures = []
    for j, column in enumerate(columns):
        error = np.abs(results[column] - expected[:, j])
        if np.any(error > tol[j]):
            failures.append(f"{column}: largest difference {error.max():.3e} > {tol[j]:.3e}")
    assert not failures, f"{name}: trajectory differs from the reference: " + "; ".join(failures)
