"""Summary and RESULTS.md of ``run_all.py``: tables of the measurements and the targets of issue 6."""

from __future__ import annotations

import datetime

from _common import fmt_time


def _rows(results, section, key=None):
    data = results.get(section) or {}
    if not isinstance(data, (dict, list)) or (isinstance(data, dict) and ("error" in data or "skipped" in data)):
        return None
    return data if key is None else data.get(key)


def targets(results) -> list[tuple[str, bool | None, str]]:
    """(target, met, measured) for each target of issue 6 item 4."""
    out = []
    deriv = _rows(results, "derivation")
    if deriv:
        row = next((r for r in deriv if r["n"] == 4), None)
        if row:
            out.append(("derivation n = 4 at least 100x faster than the SymPy baseline",
                        row["ratio"] >= 100, f"{row['ratio']:.0f}x"))
    modes = _rows(results, "scaling", "modes")
    if modes:
        for n, limit in ((10, 1.0), (40, 10.0)):
            row = next((r for r in modes if r["modes"] == n), None)
            if row:
                out.append((f"falling-beam-exact n = {n} derived in under {limit:g} s",
                            row["derive_s"] < limit, fmt_time(row["derive_s"])))
    sim = _rows(results, "simulation")
    if sim:
        for row in sim["solve_ivp"]:
            equal = row["flexkane_error"] <= 2.0 * row["solve_ivp_error"]
            out.append((f"{row['model']}: at least 50x faster than lambdify + solve_ivp at equal "
                        "accuracy", row["ratio"] >= 50 and equal,
                        f"{row['ratio']:.0f}x (tip errors {row['flexkane_error']:.1e} and "
                        f"{row['solve_ivp_error']:.1e})"))
        y = sim["yardstick"]
        out.append(("whole run within 2x of the @njit yardstick", y["run_ratio"] <= 2.0,
                    f"{y['run_ratio']:.2f}x the yardstick's time"))
    block = _rows(results, "constant_block")
    if block:
        from constant_block import target as block_target

        row = block_target(block)
        if row is not None:
            out.append(row)
    forms = _rows(results, "modal_forms")
    if forms:
        from modal_forms import target as forms_target

        row = forms_target(forms)
        if row is not None:
            out.append(row)
    integrators = _rows(results, "integrators")
    if integrators:
        from first_class_rhs import targets as integrator_targets

        out += integrator_targets(integrators)
    if "rows" in results.get("spatial_chains", {}):
        from spatial_chains import targets as spatial_targets

        out += spatial_targets(results["spatial_chains"])
    exu = _rows(results, "exudyn")
    if exu:
        for m in exu["matches"]:
            ratio = m["ratio"]
            out.append((f"faster than Exudyn at tip error <= {m['target']:g} ({m['family']} modes)",
                        None if ratio is None else ratio > 1.0,
                        "not reached" if ratio is None else f"{ratio:.0f}x"))
    return out


def summary_lines(results) -> list[str]:
    lines = ["Summary (ratios: time of the alternative / time of flexkane)"]
    deriv = _rows(results, "derivation")
    if deriv:
        lines += [f"  (a) derivation n = {r['n']}: {r['ratio']:.0f}x the SymPy baseline" for r in deriv]
    sim = _rows(results, "simulation")
    if sim:
        lines += [f"  (b) {r['model']}: {r['ratio']:.0f}x lambdify + solve_ivp" for r in sim["solve_ivp"]]
        y = sim["yardstick"]
        lines.append(f"  (d) yardstick / flexkane: rhs {1 / y['rhs_ratio']:.2f}x, whole run "
                     f"{1 / y['run_ratio']:.2f}x")
    if "rows" in results.get("spatial_chains", {}):
        from spatial_chains import targets as spatial_targets

        out += spatial_targets(results["spatial_chains"])
    exu = _rows(results, "exudyn")
    if exu:
        lines += [f"  (c) tip error <= {m['target']:g}, {m['family']}: "
                  + (f"{m['ratio']:.0f}x Exudyn" if m["ratio"] else "not matched") for m in exu["matches"]]
    ys = _rows(results, "recursive_yardstick")
    if ys:
        lines += [f"  recursive yardstick, {r['links']} links: flexkane / yardstick {r['ratio']:.2f}"
                  for r in ys["rows"] if r["ratio"] is not None]
    integrators = _rows(results, "integrators")
    if integrators:
        lines += [f"  (h) right-hand side through a first-class function, {r['method']}: "
                  f"{(r['ratio'] - 1) * 100:+.1f} % of a run" for r in integrators["indirection"]["rows"]]
        new = integrators["new_structure"]
        lines.append(f"  (h) new structure of falling-beam, integrators cached: wall {fmt_time(new['fresh_wall_s'])}, "
                     f"CPU {fmt_time(new['fresh_cpu_s'])}")
        if "fresh_plots_wall_s" in new:
            lines.append(f"  (h) the same with its plots (the whole command): wall {fmt_time(new['fresh_plots_wall_s'])}, "
                         f"CPU {fmt_time(new['fresh_plots_cpu_s'])}")
    lines.append("Targets of issue 6:")
    for name, met, value in targets(results):
        mark = "n/a" if met is None else ("met" if met else "MISSED")
        lines.append(f"  [{mark}] {name}: {value}")
    return lines


def _table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    out += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return out


def markdown(results) -> str:
    info = results["machine"]
    pk = info.get("packages", {})
    md = ["# flexkane benchmarks", "",
          f"Measured by `make bench` (`benchmarks/run_all.py`) on "
          f"{datetime.date.today().isoformat()}; the whole run took "
          f"{results['total_seconds'] / 60:.1f} min. Regenerate with `make bench`.", "",
          "## Machine", "",
          f"* CPU: {info.get('Model name', '?')}, {info.get('CPU(s)', '?')} CPUs "
          f"({info.get('Core(s) per socket', '?')} cores per socket, "
          f"{info.get('Thread(s) per core', '?')} thread per core), "
          f"hypervisor {info.get('Hypervisor vendor', 'none')}; L2 {info.get('L2 cache', '?')}, "
          f"L3 {info.get('L3 cache', '?')} (from `lscpu`)",
          f"* {info.get('platform', '')}; Python {info['python']}",
          "* " + ", ".join(f"{k} {v}" for k, v in pk.items()),
          f"* load average {info['load_average']:.2f} at the start, "
          f"{info.get('load_average_end', float('nan')):.2f} at the end: the machine is shared, so "
          "every time is the best of several runs unless said otherwise.", ""]
    md += ["## Targets of issue 6", ""]
    md += _table(["target", "result", "measured"],
                 [(n, "n/a" if m is None else ("met" if m else "**missed**"), v)
                  for n, m, v in targets(results)])
    md.append("")
    deriv = _rows(results, "derivation")
    md += ["## (a) Derivation: flexkane against a SymPy derivation integrating over x", "",
           "`falling-beam-exact` (the chapter's example with exact roots, distributed weight, "
           "eq. 8.31 elastic forces). The baseline (`benchmarks/sympy_baseline.py`) substitutes "
           "the numbers first and calls `sympy.integrate` on each expanded integrand of eq. 8.22, "
           "as the notebook does; flexkane keeps every number a symbol. SymPy's cache is cleared "
           "before each derivation. *agreement*: largest relative difference of M and f at random "
           "states.", ""]
    if deriv:
        md += _table(["modes", "flexkane", "SymPy baseline", "ratio", "load from cache", "agreement"],
                     [(r["n"], fmt_time(r["flexkane_s"]), fmt_time(r["baseline_s"]),
                       f"{r['ratio']:.0f}x", fmt_time(r["cache_load_s"]), f"{r['agreement']:.0e}")
                      for r in deriv])
    else:
        md.append(f"Not run: {results.get('derivation')}")
    md.append("")
    sim = _rows(results, "simulation")
    md += ["## (b) Simulation: flexkane against lambdify + solve_ivp, same equations", "",
           "rtol = 1e-8, atol = 1e-10; SciPy's `solve_ivp` with DOP853 (the method flexkane chose) "
           "on `sympy.lambdify(..., cse=True)` of M, f and q' with `numpy.linalg.solve`. Tip error: "
           "max over the output grid of the tip deflection's error against flexkane at "
           "rtol = 1e-12, relative to the largest deflection. flexkane's time is the integration "
           "(`flexkane.numerics.integrate`, compiled, outputs on the grid by dense output).", ""]
    if sim:
        md += _table(["model", "flexkane", "evaluations", "tip error", "lambdify + solve_ivp",
                      "evaluations", "tip error", "ratio"],
                     [(r["model"], fmt_time(r["flexkane_s"]) + f" ({r['method']})", r["flexkane_nfev"],
                       f"{r['flexkane_error']:.1e}", fmt_time(r["solve_ivp_s"]), r["solve_ivp_nfev"],
                       f"{r['solve_ivp_error']:.1e}", f"{r['ratio']:.0f}x") for r in sim["solve_ivp"]])
    md.append("")
    exu = _rows(results, "exudyn")
    md += ["## (c) flexible-arm: flexkane against Exudyn at matched tip-deflection accuracy", ""]
    if exu:
        md += [f"Exudyn {pk.get('exudyn', '?')}: `ObjectANCFCable2D` elements clamped to "
               "`ObjectRigidBody2D` hub and payload by `ObjectJointGeneric`, revolute joint, torque "
               "by a Python load function, implicit generalized-alpha with fixed step h (Exudyn's "
               "explicit solvers reject these joints). flexkane: the built-in model with "
               "`geometric_stiffening = true`, clamped-free modes (the built-in shape) or "
               "`clamped-free-tip-mass` modes, `method = \"auto\"`. Accuracy of a run: max over "
               "t in [0, 1.5] s of the tip-deflection error against the converged solution of the "
               "same tool, relative to the largest deflection "
               f"({exu['max_tip'] * 1e3:.1f} mm). Times are of the integration only.", "",
               f"The two converged solutions differ by {exu['model_difference']:.1e} of the largest "
               f"deflection, by {exu['model_difference_small']:.1e} with a tenth of the torque: the "
               "difference is the geometric nonlinearity of a 7 % tip deflection, which Exudyn's "
               "geometrically exact cable keeps and the second-order foreshortening of the assumed "
               "modes does not. The comparison is therefore of numerical accuracy, each tool "
               "against its own converged model.", ""]
        md += _table(["tip error target", "flexkane setting", "error", "time", "Exudyn setting",
                      "error", "time", "ratio"],
                     [(f"{m['target']:g}", m["flexkane"]["setting"] if m["flexkane"] else "-",
                       f"{m['flexkane']['error']:.1e}" if m["flexkane"] else "-",
                       fmt_time(m["flexkane"]["wall"]) if m["flexkane"] else "-",
                       m["exudyn"]["setting"] if m["exudyn"] else "-",
                       f"{m['exudyn']['error']:.1e}" if m["exudyn"] else "-",
                       fmt_time(m["exudyn"]["wall"]) if m["exudyn"] else "-",
                       f"{m['ratio']:.0f}x" if m["ratio"] else "-") for m in exu["matches"]])
        md += ["", "All settings tried:", ""]
        md += _table(["tool", "setting", "tip error", "time"],
                     [("flexkane", r["setting"], f"{r['error']:.1e}", fmt_time(r["wall"])) for r in exu["flexkane"]]
                     + [("Exudyn", r["setting"], f"{r['error']:.1e}", fmt_time(r["wall"])) for r in exu["exudyn"]])
    else:
        md.append(f"Not run: {results.get('exudyn')}")
    md.append("")
    if sim:
        y = sim["yardstick"]
        md += ["## (d) Against the hand-written @njit yardstick", "",
               "`benchmarks/njit_yardstick.py`: `falling-beam-exact`, n = 4, the right-hand side "
               "written by hand from eqs. 8.23 and 8.31 with loops over the modes and a Cholesky "
               "solve, inside an @njit DOP853 loop with Hairer's step control and nothing else. "
               "Whole run: t in [0, 1] s, rtol = 1e-8, atol = 1e-10, DOP853, no output grid "
               f"(final states differ by {y['end_difference']:.0e}).", ""]
        md += _table(["", "flexkane", "yardstick", "flexkane / yardstick"],
                     [("one evaluation of the right-hand side", fmt_time(y["rhs_flexkane_s"]),
                       fmt_time(y["rhs_yardstick_s"]), f"{y['rhs_ratio']:.2f}"),
                      ("whole run", fmt_time(y["run_flexkane_s"]) + f" ({y['nfev_flexkane']} evaluations)",
                       fmt_time(y["run_yardstick_s"]) + f" ({y['nfev_yardstick']} evaluations)",
                       f"{y['run_ratio']:.2f}"),
                      ("whole run with 1001 output rows (dense output)",
                       fmt_time(y["run_flexkane_grid_s"]), "-", "-")])
        md += ["", "flexkane's generated right-hand side is straight-line code after common-"
               "subexpression elimination with an unrolled L D L^T solve (no loops, no "
               "allocation), which is why it beats loops written by hand.", ""]
    modes = _rows(results, "scaling", "modes")
    links = _rows(results, "scaling", "links")
    md += ["## (e) Growth with the number of modes and of flexible links", "",
           "derive: first derivation (SymPy cache cleared); codegen: common subexpressions and "
           "source; compile: Numba, from an empty cache, the right-hand side and both integrator "
           "loops (the loops alone take about 8 s, once per model structure; the on-disk cache "
           "makes later runs start at once); run: the integration, best of 3, `method=\"auto\"`.", ""]
    if modes:
        tols = sorted({k.split("@")[1] for r in modes for k in r if k.startswith("run_s@")}, key=float)
        md += _table(["modes", "states", "derive", "codegen", "compile (of it: rhs)"]
                     + [f"run at rtol {t}" for t in tols],
                     [(r["modes"], r["states"], fmt_time(r["derive_s"]), fmt_time(r["codegen_s"]),
                       f"{fmt_time(r['compile_s'])} ({fmt_time(r['rhs_compile_s'])})")
                      + tuple(f"{fmt_time(r[f'run_s@{t}'])} ({r[f'method@{t}']}, {r[f'nfev@{t}']} ev.)"
                              for t in tols) for r in modes])
        md.append("")
    if links:
        md += ["Chains of k flexible links (2 modes each) on hubs driven by torque pulses, a payload "
               "at the end (`benchmarks/scaling.py: chain_model`), t in [0, 1.5] s:", ""]
        md += _table(["links", "states", "derive", "codegen", "compile (of it: rhs)", "run at rtol 1e-08"],
                     [(r["links"], r["states"], fmt_time(r["derive_s"]), fmt_time(r["codegen_s"]),
                       f"{fmt_time(r['compile_s'])} ({fmt_time(r['rhs_compile_s'])})",
                       f"{fmt_time(r['run_s@1e-08'])} ({r['method@1e-08']}, {r['nfev@1e-08']} ev.)")
                      for r in links])
        md.append("")
    ys = _rows(results, "recursive_yardstick")
    if ys:
        from recursive_yardstick import markdown as yardstick_markdown

        md += yardstick_markdown(ys)
    else:
        md += ["## Recursive yardstick (issue 16)", "", f"Not run: {results.get('recursive_yardstick')}", ""]
    block = _rows(results, "constant_block")
    if block:
        from constant_block import markdown as block_markdown

        md += block_markdown(block)
    else:
        md += ["## Constant modal block factored once per run (issue 16, item 6)", "",
               f"Not run: {results.get('constant_block')}", ""]
    if "rows" in results.get("modal_forms", {}):
        from modal_forms import markdown as forms_markdown

        md += forms_markdown(results["modal_forms"], info)
    integrators = _rows(results, "integrators")
    if integrators:
        from first_class_rhs import markdown as integrators_markdown

        md += integrators_markdown(integrators)
    else:
        md += ["## (h) Integrators compiled once (issue 16, item 5)", "", f"Not run: {results.get('integrators')}", ""]
    sweep = results.get("sweep") or {}
    md += ["## Sweep throughput (issue 11)", ""]
    if "serial_per_s" in sweep:
        md += _table(["mode", "variants per second"],
                     [(k.replace("_per_s", "").replace("_", " "), f"{v:.1f}")
                      for k, v in sweep.items() if k.endswith("_per_s")])
        md += ["", f"`benchmarks/sweep_throughput.py`, {sweep.get('variants')} variants of "
               f"{sweep.get('model')} (t_end = 0.2 s) per mode.", ""]
    else:
        md += [f"Not run: {sweep.get('skipped') or sweep.get('error')}", ""]
    md += ["## Notes", "", NOTES]
    if "rows" in results.get("chain_scaling", {}):
        from chain_scaling import markdown as chain_markdown
        md += [""] + chain_markdown(results["chain_scaling"], info)
    if "rows" in results.get("spatial_chains", {}):
        from spatial_chains import markdown as spatial_markdown
        md += [""] + spatial_markdown(results["spatial_chains"], info)
    if "rows" in results.get("startup", {}):
        from startup import markdown as startup_markdown

        md += [""] + startup_markdown(results["startup"], info)
    if "models" in results.get("iteration", {}):
        from iteration import markdown as iteration_markdown

        md += [""] + iteration_markdown(results["iteration"], info)
    if "rows" in results.get("analysis_cache", {}):
        from analysis_cache import markdown as analysis_cache_markdown

        md += [""] + analysis_cache_markdown(results["analysis_cache"], info)
    return "\n".join(md) + "\n"


NOTES = """\
* **Compile time of large models.** A right-hand side longer than 12,000 printed characters is
  generated with term tables (sums of 12 terms or more become rows of coefficients and factor
  indices, added by one compiled loop) and split into several functions
  (`flexkane.numerics.large_rhs`). Written out as one function, `falling-beam-exact` with 40
  modes (30,000 operations) took 145 s to compile, 110 s of it in LLVM, which is superlinear in
  the length of a basic block; split into 26 functions it still took 79 s (Numba's typing and
  lowering cost a few milliseconds per operation); with term tables the right-hand side compiles
  in about 10 s and evaluates faster (20 us against 43 us per call). The two integrator loops
  (about 8 s) are compiled once per installation, not with each model: see (h).
* **Where the 20 us of one evaluation go at 40 modes.** The L D L^T solve of the 43 x 43 mass
  matrix took 8.6 us of them. The block of the mass matrix that depends on the constants only (the
  modal mass G_ij and the two translations, 42 of the 43 speeds) is now factored once per run and
  eliminated by a Schur complement (`flexkane.numerics.constant_block`, section "Constant modal
  block" above); the rest of an evaluation is the term tables of the mass matrix and forcing
  (5,917 terms of up to 5 factors at 40 modes).
* **Automatic method choice.** At rtol = 1e-8 the beam is accuracy-limited and DOP853 wins or
  ties up to 40 modes. At loose tolerances the high modes, whose amplitudes are below the
  tolerance, hold DOP853 at its stability limit while Radau IIA steps over them;
  `method="auto"` watches DOP853's stiffness test and runs short trials of the other method,
  keeping the one measured to be faster (`flexkane.numerics.switching`). `falling-beam-exact`,
  t in [0, 1] s (CPU time): 20 modes, rtol = 1e-3: DOP853 0.44 s, Radau 0.03 s, auto 0.05 s;
  rtol = 1e-4: 0.66 s, 0.05 s, 0.05 s; rtol = 1e-8: 0.43 s, 2.0 s, 0.43 s. 40 modes,
  rtol = 1e-6: 28.8 s, 1.7 s, 1.8 s; rtol = 1e-8: 13.6 s, 12.5 s, 13.5 s. DOP853 at its
  stability limit is also inaccurate at loose tolerances (tip error 1.2e-1 at rtol = 1e-4 with
  10 modes, against 2e-3 for Radau).
* **Growth with the links.** Derivation time grows steeply with the links (3.8 s for 4, 20 s
  for 5): the kinematics of link k contain those of links 1 ... k-1, and the profile (4 links)
  puts 8.9 of 12.3 s in SymPy's `free_symbols`, called by `diff` for every partial velocity and
  time derivative, which walks repeated subtrees again each time. Code generation had the same
  problem (renaming symbols before common-subexpression elimination walked the whole trees: 26 s
  for 5 links); it now eliminates first and renames the reduced expressions.
* **Derivation cache.** Loading a derivation from `flexkane.derivation_cache` takes a few
  milliseconds (SymPy expressions are pickled with their arguments and rebuilt without
  re-evaluation, 10 times faster than SymPy's own pickling); deriving again is 10 to 25 times
  slower even for one mode, so the cache is always used.
* **Agreement at n = 4 in (a).** 8e-9 rather than 1e-13: the baseline evaluates closed-form
  integrals of products of cosh(lambda_i x / L) in floating point (cosh(lambda_4) is about 3e4),
  losing digits to cancellation; flexkane's modal constants come from Gauss-Legendre quadrature.
* **Exudyn's torque function** is a Python callback; replacing it by a constant torque changes
  Exudyn's time by less than 15 %, so it does not explain the ratios of (c).
"""
