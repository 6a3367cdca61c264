"""Store the results of the current engine for every built-in model and example file.

Run from the repository root, with the engine whose results are to be kept::

    PYTHONPATH=src python tests/reference/generate.py            # all models
    PYTHONPATH=src python tests/reference/generate.py four-bar   # some of them

For each model (the built-in models of :func:`flexkane.builtin_names` and the files
``examples/*.toml``, one file per distinct name) it derives and compiles the equations with the
engine on the path and writes ``tests/reference/<name>.npz`` holding only engine-agnostic values,
selected by name so that an engine that orders its constants or states differently, or appends
extra states (work quadratures) after ``[q, u]``, can be compared with it:

``model_text`` (str)
    The model file the values belong to (the test rebuilds the model from this text, so that a later
    change of an example file does not invalidate the comparison of engines).
``state_names`` (str, (n,))
    Names of the state ``[q, u, z]`` (coordinates, independent speeds, controller states).
``rhs_t`` (N,), ``rhs_y`` (N, n), ``rhs_dy`` (N, n)
    Times [s], states and the first-order right-hand side ``dy/dt = [q', u']`` at ``N`` seeded
    random states (see :func:`sample_states`).
``rhs_mass_matrix`` (N, nu, nu), ``rhs_forcing`` (N, nu)
    ``M`` and ``f`` of ``M u' = f`` at those states, for diagnosis only (a reformulation may change
    them legitimately, e.g. another choice of dependent speeds): the residual ``M u'_new - f`` shows
    which equation differs when the right-hand sides do.
``rhs_check`` (n,)
    Largest difference, over the states, between the compiled right-hand side and an independent
    evaluation of ``M^-1 f`` in 30-digit arithmetic, divided by the component's scale (largest
    |dy_k| over the states): the round-off of the stored values.
``traj_t`` (K,), ``traj_names`` (str, (m,)), ``traj_values`` (K, m)
    A short run from the model's initial state with DOP853 at ``traj_rtol``, ``traj_atol``: the state
    columns and the physical outputs (energies, tip deflections, driver efforts, centre of mass,
    momenta, dependent speeds) by name.
``traj_rtol``, ``traj_atol``, ``traj_method``
    The tolerances and method of that run.
``traj_error`` (m,)
    Largest difference over time between that run and the same run at ten times the tolerances:
    an estimate of the global error at the looser tolerance, about ten times the stored run's own.
``engine`` (str)
    flexkane version and the last commit that changed ``src/`` (the engine that produced the values).

The output is byte-for-byte reproducible (checked: regenerating with another ``PYTHONHASHSEED`` and
an empty compiled-model cache gives the same bytes): seeds come from the model name, and NumPy stamps
the archive's members with a fixed date.
"""

from __future__ import annotations

import io
import subprocess
import sys
import time
import zlib
from pathlib import Path

import mpmath
import numpy as np
import sympy as sp

import flexkane
from flexkane.atomic import atomic_write_bytes
from flexkane.expressions import parse_expression, resolve_parameters, to_float

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]

#: Number of random states at which the right-hand side is stored.
N_STATES = 5
#: Tolerances and method of the stored trajectory.
TRAJ_RTOL = 1e-11
TRAJ_ATOL = 1e-13
TRAJ_METHOD = "dop853"
#: Length [s] and number of output intervals of the stored trajectory (shorter when the model's
#: own run is shorter, or stiff: see TRAJ_T_END).
TRAJ_T_END_DEFAULT = 0.2
TRAJ_T_END = {"slider-crank": 0.01, "spin-up": 4.0, "spin-up-linear": 4.0, "spacecraft-slew": 2.0, "robot-arm-3d": 1.0}
TRAJ_INTERVALS = 10
#: Outputs stored with the trajectory: the physical ones (positions of frame origins, angles and loop
#: residuals are left out).
ENERGY_OUTPUTS = ("kinetic", "potential_gravity", "strain", "potential_springs", "energy")
OTHER_OUTPUTS = ("x_cm", "y_cm", "p_x", "p_y", "h_o", "z_cm", "p_z", "H_x", "H_y", "H_z")
OUTPUT_PREFIXES = ("tip_", "effort_")
#: Largest Jacobi-scaled condition number of M accepted at a random state (keeps the states away
#: from singular configurations, where the comparison of two engines would measure round-off).
MAX_CONDITION = 1e6


def model_sources() -> dict[str, str]:
    """Model name -> model file text, for the built-in models and examples/*.toml."""
    sources = {name: flexkane.builtin.builtin_text(name) for name in flexkane.builtin_names()}
    for path in sorted((ROOT / "examples").glob("*.toml")):
        text = path.read_text(encoding="utf-8")
        if path.stem in sources and sources[path.stem] != text:
            raise SystemExit(f"examples/{path.name} differs from the built-in model {path.stem}: "
                             "give one of them another name")
        sources[path.stem] = text
    return sources


def _numbers(model) -> dict:
    """Values of the model's parameters by symbol, for evaluating its fields."""
    params = resolve_parameters(model.parameters, path_prefix="parameters")
    return {sp.Symbol(k): float(v) for k, v in params.items()}


def _field(model, values, text, path) -> float:
    names = {s.name: s for s in values}
    return to_float(parse_expression(text, names, path=path), values, path=path)


def state_scales(eom) -> tuple[np.ndarray, np.ndarray]:
    """Scales (n,) of the random perturbations of the state, by the role of each coordinate.

    Joint angles 0.5 rad and 1 rad/s; translations 0.2 L and 1 m/s (``L`` the longest beam, 1 m
    without beams); bending modes ``0.01 L / i^2`` and that times the clamped-free estimate of the
    mode's frequency ``lambda_i^2 (EI / rho L^4)^(1/2)``; axial modes ``1e-5 L`` and that times
    ``(2k - 1) pi / 2 (EA / rho)^(1/2) / L``; a spatial beam's bending modes as these with ``EI_z``
    (along y) or ``EI_y`` (along z), its torsion modes ``0.01 / k`` rad and that times
    ``(2k - 1) pi / (2 L) (GJ / rho_Ip)^(1/2)``. Only orders of magnitude matter: the states must
    exercise every term of the equations with sensible weights.
    """
    model = eom.model
    values = _numbers(model)
    beams = {}
    for name, beam in model.beams.items():
        path = f"beams.{name}"
        L = _field(model, values, beam.L, f"{path}.L")
        rho = _field(model, values, beam.rho, f"{path}.rho")
        EA = _field(model, values, beam.EA, f"{path}.EA") if beam.EA is not None else None
        if beam.EI is not None:
            EI = _field(model, values, beam.EI, f"{path}.EI")
        else:   # a spatial beam: v (mode_y) bends with EI_z, w (mode_z) with EI_y; torsion GJ / rho_Ip
            EI = {role: _field(model, values, getattr(beam, key), f"{path}.{key}")
                  for role, key in (("mode_y", "EI_z"), ("mode_z", "EI_y")) if getattr(beam, key) is not None}
            if beam.GJ is not None and beam.rho_Ip is not None:
                EI["torsion"] = (_field(model, values, beam.GJ, f"{path}.GJ"),
                                 _field(model, values, beam.rho_Ip, f"{path}.rho_Ip"))
        beams[name] = (L, EI, rho, EA)
    length = max([b[0] for b in beams.values()], default=1.0)
    lambdas = [1.8751, 4.6941, 7.8548]
    by_symbol = {}
    for c in eom.chain.coordinates:
        if c.role == "angle":
            by_symbol[c.q], by_symbol[c.u] = 0.5, 1.0
        elif c.role in ("e0", "e1", "e2", "e3"):     # Euler parameters: kept unit, angular speeds 1 rad/s
            by_symbol[c.q] = 0.0
            if c.u is not None:
                by_symbol[c.u] = 1.0
        elif c.role in ("x", "y", "z", "slide"):
            by_symbol[c.q], by_symbol[c.u] = 0.2 * length, 1.0
        elif c.role == "torsion":      # 0.01 rad / k, times (2k - 1) pi / (2 L) (GJ / rho_Ip)^(1/2)
            L, stiffness, _, _ = beams[c.owner]
            GJ, rho_Ip = stiffness["torsion"]
            amplitude = 0.01 / c.index
            by_symbol[c.q] = amplitude
            by_symbol[c.u] = amplitude * (2 * c.index - 1) * np.pi / (2 * L) * np.sqrt(GJ / rho_Ip)
        elif c.role in ("mode", "mode_y", "mode_z"):
            L, EI, rho, _ = beams[c.owner]
            EI = EI[c.role] if isinstance(EI, dict) else EI
            lam = lambdas[c.index - 1] if c.index <= len(lambdas) else (c.index - 0.5) * np.pi
            amplitude = 0.01 * L / c.index ** 2
            by_symbol[c.q], by_symbol[c.u] = amplitude, amplitude * lam ** 2 * np.sqrt(EI / (rho * L ** 4))
        elif c.role == "axial":
            L, _, rho, EA = beams[c.owner]
            amplitude = 1e-5 * L
            by_symbol[c.q], by_symbol[c.u] = amplitude, amplitude * (2 * c.index - 1) * np.pi / 2 \
                * np.sqrt(EA / rho) / L
        else:
            raise SystemExit(f"no scale for the role {c.role!r} of {c.q.name}")
    symbols = list(eom.q) + list(eom.u)
    scale = np.array([by_symbol[s] for s in symbols])
    return scale[:len(eom.q)], scale[len(eom.q):]


class Equations:
    """``M`` and ``f`` of the current engine, in floating point and in 30-digit arithmetic."""

    def __init__(self, eom, p: np.ndarray):
        self.eom = eom
        self.p = p
        z = list(getattr(eom, "z", ()))   # controller states, after the speeds
        args = [eom.t] + list(eom.q) + list(eom.u) + z + list(eom.constants)
        self._float = sp.lambdify(args, [eom.mass_matrix, eom.forcing], modules="numpy", cse=True)
        self._mp = sp.lambdify(args, [eom.mass_matrix, eom.forcing], modules="mpmath", cse=True)
        self._mp_z = sp.lambdify(args, list(eom.zdot), modules="mpmath", cse=True) if z else None

    def numeric(self, t, y) -> tuple[np.ndarray, np.ndarray]:
        M, f = self._float(t, *y, *self.p)
        return np.array(M, dtype=float), np.array(f, dtype=float).ravel()

    def exact_ud(self, t, y) -> np.ndarray:
        """u' = M^-1 f, then z' of the controller states, in 30-digit arithmetic (for the round-off
        check of the stored values)."""
        with mpmath.workdps(30):
            args = [mpmath.mpf(float(v)) for v in (t, *y, *self.p)]
            M, f = self._mp(*args)
            ud = mpmath.lu_solve(mpmath.matrix(M), mpmath.matrix(f))
            zd = self._mp_z(*args) if self._mp_z is not None else []
            return np.array([float(v) for v in [*ud, *zd]])


def scaled_condition(M: np.ndarray) -> float:
    d = 1.0 / np.sqrt(np.abs(np.diag(M)))
    return float(np.linalg.cond(M * d[:, None] * d[None, :]))


def sample_states(name, eom, compiled, equations, p) -> tuple[np.ndarray, np.ndarray]:
    """``N_STATES`` times (N,) and states (N, n) drawn around the initial state.

    The first is the initial state at t = 0. The others perturb the coordinates and speeds by
    normal deviates of :func:`state_scales` (independent coordinates only with loop constraints,
    whose dependent coordinates are then closed by Newton's method at the drawn time), at times
    drawn uniformly over the model's run. A draw is rejected when the rhs is not finite or the
    Jacobi-scaled condition number of M exceeds :data:`MAX_CONDITION`.
    """
    rng = np.random.default_rng(zlib.crc32(name.encode()))
    y0 = eom.initial_state()
    nq = len(eom.q)
    q_scale, u_scale = state_scales(eom)
    values = eom.constant_values()
    dependent = [eom.q.index(s) for s in getattr(eom, "dependent_coordinates", [])] \
        if eom.dependent_speeds else []
    times, states = [0.0], [y0]
    t_end = eom.model.simulation.t_end
    attempts = 0
    while len(states) < N_STATES:
        attempts += 1
        if attempts > 100:
            raise SystemExit(f"{name}: no well-conditioned random state in 100 draws")
        t = float(rng.uniform(0.0, t_end))
        y = y0.copy()
        y[:nq] += q_scale * rng.standard_normal(nq)
        nu = len(u_scale)
        y[nq:nq + nu] += u_scale * rng.standard_normal(nu)
        y[nq + nu:] += 0.1 * rng.standard_normal(len(y0) - nq - nu)    # controller states
        if dependent:
            y[dependent] = y0[dependent]
            try:
                y[:nq] = eom.project_coordinates(y[:nq], values, t)
            except flexkane.errors.ModelError:
                continue
        dy = compiled.rhs(t, y, p)
        M, _ = equations.numeric(t, y)
        if not np.all(np.isfinite(dy)) or scaled_condition(M) > MAX_CONDITION:
            continue
        times.append(t)
        states.append(y)
    return np.array(times), np.array(states)


def trajectory_columns(results, eom) -> list[str]:
    names = list(eom.state_names)
    names += [k for k in results.outputs if k.startswith(OUTPUT_PREFIXES)]
    names += [k for k in ENERGY_OUTPUTS + OTHER_OUTPUTS if k in results.outputs]
    names += [u.name for u in eom.dependent_speeds]
    return names


def engine_id() -> str:
    try:
        commit = subprocess.run(["git", "log", "-1", "--format=%H", "--", "src"], cwd=ROOT, capture_output=True,
                                text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "src"], cwd=ROOT, capture_output=True,
                               text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        commit, dirty = "unknown", ""
    return f"flexkane {flexkane.__version__} commit {commit}{' (src modified)' if dirty else ''}"


def write_npz(path: Path, arrays: dict) -> None:
    """Compressed ``.npz``, written atomically (NumPy stamps its members with a fixed date)."""
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **{key: np.asanyarray(arrays[key]) for key in sorted(arrays)})
    atomic_write_bytes(path, buffer.getvalue())


def generate(name: str, text: str, engine: str) -> dict:
    """Derive, compile and evaluate one model; return the arrays to store."""
    start = time.perf_counter()
    model = flexkane.loads_model(text, source=name)
    eom = flexkane.derive(model)
    compiled = flexkane.compile_model(eom)
    values = eom.constant_values(model)
    p = np.array([values[s] for s in eom.constants], dtype=float)
    equations = Equations(eom, p)
    times, states = sample_states(name, eom, compiled, equations, p)
    nq = len(eom.q)
    dys, masses, forcings = [], [], []
    for t, y in zip(times, states):
        dys.append(compiled.rhs(t, y, p))
        M, f = equations.numeric(t, y)
        masses.append(M)
        forcings.append(f)
    dys = np.array(dys)
    exact = np.array([np.concatenate([dy[:nq], equations.exact_ud(t, y)])
                      for t, y, dy in zip(times, states, dys)])
    scale = np.abs(dys).max(axis=0)
    check = np.abs(dys - exact).max(axis=0) / np.where(scale > 0, scale, 1.0)
    t_end = min(TRAJ_T_END.get(name, TRAJ_T_END_DEFAULT), model.simulation.t_end)
    runs = []
    for factor in (1.0, 10.0):
        results = flexkane.simulate(compiled, t_end=t_end, dt_out=t_end / TRAJ_INTERVALS,
                                    rtol=TRAJ_RTOL * factor, atol=TRAJ_ATOL * factor, method=TRAJ_METHOD)
        if results.partial:
            raise SystemExit(f"{name}: the reference run stopped: {results.solver['message']}")
        runs.append(results)
    columns = trajectory_columns(runs[0], eom)
    traj = np.column_stack([runs[0][c] for c in columns])
    loose = np.column_stack([runs[1][c] for c in columns])
    print(f"{name}: {len(states)} states, rhs round-off {check.max():.1e} of scale, trajectory "
          f"{len(runs[0].t)} rows x {len(columns)} columns in {runs[0].solver['nsteps']} steps "
          f"({runs[0].solver['wall_time']:.2f} s), {time.perf_counter() - start:.1f} s in all", flush=True)
    return {"model_text": np.array(text), "state_names": np.array(eom.state_names, dtype=str),
            "rhs_t": times, "rhs_y": states, "rhs_dy": dys,
            "rhs_mass_matrix": np.array(masses), "rhs_forcing": np.array(forcings), "rhs_check": check,
            "traj_t": runs[0].t, "traj_names": np.array(columns, dtype=str), "traj_values": traj,
            "traj_rtol": np.array(TRAJ_RTOL), "traj_atol": np.array(TRAJ_ATOL),
            "traj_method": np.array(TRAJ_METHOD), "traj_error": np.abs(traj - loose).max(axis=0),
            "engine": np.array(engine)}


def main(argv: list[str]) -> int:
    sources = model_sources()
    names = argv or list(sources)
    unknown = [n for n in names if n not in sources]
    if unknown:
        print(f"unknown model(s) {', '.join(unknown)}; known: {', '.join(sources)}", file=sys.stderr)
        return 2
    engine = engine_id()
    for name in names:
        write_npz(HERE / f"{name}.npz", generate(name, sources[name], engine))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
