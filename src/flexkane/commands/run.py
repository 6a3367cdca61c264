"""``flexkane run``: derive, compile and integrate a model; write results, plots and equations."""

from __future__ import annotations

import sys
import time
from pathlib import Path

from ..errors import ModelError, SolverFailure
from ..interruption import StopRequest
from ..model.parts import METHODS
from ._common import add_equilibrium_argument, add_max_steps_argument, add_model_arguments, default_out, model_from_args
from .animate import add_animation_arguments
from .derive import add_no_cache_argument

__all__ = ["register", "run_model"]


def register(subparsers) -> None:
    p = subparsers.add_parser("run", help="simulate a model and write results, plots and equations",
                              description="Derive Kane's equations of a model, integrate them and write "
                                          "results.csv, results.npz, plots (PNG) and equations.md to DIR.")
    add_model_arguments(p)
    p.add_argument("--out", metavar="DIR", default=None, help="output directory [default: out/MODEL_NAME]")
    p.add_argument("--t-end", type=float, default=None, metavar="T", help="end time [s]")
    p.add_argument("--dt-out", type=float, default=None, metavar="DT", help="output interval [s]")
    p.add_argument("--rtol", type=float, default=None, metavar="R", help="relative tolerance")
    p.add_argument("--atol", type=float, default=None, metavar="A", help="absolute tolerance")
    p.add_argument("--method", default=None, choices=METHODS,
                   help="integration method [default: the model's, else auto]")
    add_max_steps_argument(p)
    add_equilibrium_argument(p)
    p.add_argument("--force", action="store_true", help="write into an existing non-empty directory")
    p.add_argument("--animate", action="store_true",
                   help="also write animation.gif (and animation.mp4 where ffmpeg exists), as 'flexkane animate'")
    add_animation_arguments(p, movie_options=False)
    p.add_argument("--no-plots", action="store_true",
                   help="write no PNG plots (results, model and equations only; faster)")
    p.add_argument("--pdf", action="store_true",
                   help="also render equations.tex to equations.pdf (needs pdflatex on PATH)")
    p.add_argument("--quiet", action="store_true", help="no progress bar and no summary")
    add_no_cache_argument(p)
    p.set_defaults(handler=_handle)


def _handle(args) -> int:
    model = model_from_args(args)
    out = Path(args.out) if args.out else default_out(model.name)
    return run_model(model, out, t_end=args.t_end, dt_out=args.dt_out, rtol=args.rtol, atol=args.atol,
                     method=args.method, max_steps=args.max_steps, force=args.force, quiet=args.quiet,
                     animation=args if args.animate else None, pdf=args.pdf, plots=not args.no_plots,
                     cache=not args.no_cache)


def energy_balance_text(results) -> str:
    """Energy balance of a run, relative: ``max |E - E0 - W| / max(|E|, |kinetic|)``.

    ``W`` is the work of drivers, loads, actuator torques and dampers, integrated with the motion
    to the solver's tolerance (output ``work``; 0 for a conservative model, whose balance is then
    its energy drift), so the balance falls with the tolerance.
    """
    import numpy as np

    e = results["energy"]
    scale = max(np.abs(e).max(), np.abs(results["kinetic"]).max(), 1e-300)
    balance = results["energy_balance"] if "energy_balance" in results.outputs else e - e[0]
    error = np.abs(balance).max() / scale
    if "work" not in results.outputs or np.abs(results["work"]).max() == 0:
        return f"energy drift {error:.2e} (relative, no work done on the system)"
    return f"energy balance E - E0 - W {error:.2e} (relative; W = work of drivers, loads and dampers)"


def run_model(model, out: Path, *, t_end=None, dt_out=None, rtol=None, atol=None, method=None, max_steps=None,
              force=False, quiet=False, animation=None, pdf=False, plots=True, cache=True) -> int:
    """Run a validated model into directory ``out``; return the exit code (0 ok, 3 solver failure).

    ``animation``: options of :func:`~flexkane.commands.animate.add_animation_arguments` (``magnify``,
    ``trace``) to also write animation.gif, or None. ``pdf``: also render equations.tex to a PDF.
    ``plots``: write the PNG plots (:func:`flexkane.plots.write_plots`). ``cache``: take the equations,
    their generated code and the model's numbers from the cache of derived equations (else derive
    them afresh and store nothing).
    """
    sim = model.simulation
    t_end = t_end if t_end is not None else sim.t_end
    if t_end is None:
        raise ModelError("--t-end", "an end time [s] (the model has no simulation.t_end)", None, show_given=False)
    dt_out = dt_out if dt_out is not None else (sim.dt_out or t_end / 100)
    rtol = rtol if rtol is not None else sim.rtol
    atol = atol if atol is not None else sim.atol
    method = method or sim.method
    max_steps = max_steps if max_steps is not None else sim.max_steps
    from ..model.validate import validate_run_arguments
    from ._common import prepare_out

    validate_run_arguments(t_end=t_end, dt_out=dt_out, rtol=rtol, atol=atol, method=method, max_steps=max_steps)
    if animation is not None:
        from ..animation import check_animation_options

        check_animation_options(model, animation.magnify, animation.trace, getattr(animation, "view", None))
    out = prepare_out(out, force=force)
    from ..atomic import directory_syncs_batched

    with StopRequest() as stop, directory_syncs_batched():   # out/ (and the cache) synced once each
        return _run_phases(model, out, stop, t_end=t_end, dt_out=dt_out, rtol=rtol, atol=atol, method=method,
                           max_steps=max_steps, quiet=quiet, animation=animation, pdf=pdf, plots=plots,
                           cache=cache)


def _run_phases(model, out: Path, stop, *, t_end, dt_out, rtol, atol, method, max_steps, quiet, animation, pdf,
                plots, cache) -> int:
    """The phases of :func:`run_model` under the command's stop request ``stop``.

    Derivation, code generation and waiting for the compilation (a child process) stop at once on a
    signal (:class:`KeyboardInterrupt`, exit 130, nothing written). From the integration until
    the results files are written, a signal is deferred: the integration stops between chunks and
    the files hold the rows computed (marked partial); results.csv and results.npz are written
    first, then model.toml. A signal while the equations and the plots are written stops them at
    once, leaves no temporary file, and the message says which files are complete.
    """
    from ..atomic import atomic_write_text
    from ..derivation_cache import Derivation
    from ..model import dumps_model
    from ..numerics.jit_module import compile_in_subprocess
    from ..progress import activity
    from ..simulation import COMPILING_MESSAGE, INTEGRATORS_MESSAGE, compile_model, simulate

    started = time.perf_counter()
    # the equations as far as the run needs them: from the cache, SymPy only for what it lacks
    derivation = Derivation(model, cache=cache)   # deriving, generating, compiling: flexkane.progress says so
    derivation.manifest    # loaded, or made from the equations (derived or loaded first)
    derive_time = time.perf_counter() - started

    def meanwhile():   # while a child compiles: what the run needs afterwards anyway (kept)
        derivation.equations(model, remember=True)
        if plots:
            from ..plots import load_matplotlib

            load_matplotlib()

    # a structure new to the cache compiles in a child process (a signal stops it at once)
    with compile_in_subprocess(announce=COMPILING_MESSAGE, announce_integrators=INTEGRATORS_MESSAGE,
                               meanwhile=meanwhile):
        compiled = compile_model(derivation)
    with stop.deferred():
        with activity(f"integrating {model.name} to t = {t_end:g} s", delay=1.0, thread=False) as bar:
            def progress(t_reached, t_total):
                bar.update(t_reached, t_total, "s")
                stop.check()

            results = simulate(compiled, t_end=t_end, dt_out=dt_out, rtol=rtol, atol=atol, method=method,
                               model=model, progress=progress, max_steps=max_steps, remember=True)
        results.solver["derive_time"] = derive_time
        written = results.write(out)
        atomic_write_text(out / "model.toml", dumps_model(model))
        written.append(out / "model.toml")
    interrupted = results.partial and results.solver.get("status") == "interrupted"
    if stop.requested:
        return _stopped(out, written, [], interrupted, results)
    before = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    try:  # the equations (minutes for the largest models) and the plots: a signal stops them at once
        equations = derivation.equations(model, remember=True)
        atomic_write_text(out / "equations.md", equations["md"])
        atomic_write_text(out / "equations.tex", equations["tex"])
        written += [out / "equations.md", out / "equations.tex"]
        if pdf:
            from ..report import render_pdf

            pdf_path, message = render_pdf(out / "equations.tex")
            if pdf_path is not None:
                written.append(pdf_path)
            if message:
                print(f"flexkane: {message}", file=sys.stderr)
        if plots and len(results.t) > 1:
            from ..plots import write_plots

            written += write_plots(results, derivation.manifest["units"], out, model.name, workers=2)
        if animation is not None and len(results.t) > 0:
            from .animate import animate_run

            written += animate_run(results, out / "animation.gif", animation, quiet=quiet)
    except KeyboardInterrupt:
        done = sorted(p.name for p in out.iterdir() if not p.name.startswith(".")
                      and p.name not in {w.name for w in written} and before.get(p.name) != p.stat().st_mtime_ns)
        return _stopped(out, written, done, interrupted, results)
    if stop.requested:  # came while a file was being renamed into place, once the last one was done
        return _stopped(out, written, [], interrupted, results)
    s = results.solver
    if not quiet or results.partial:
        drift = ""
        if "energy" in results.outputs and len(results.t) > 1:
            drift = ", " + energy_balance_text(results)
        stream = sys.stderr if results.partial else sys.stdout
        print(f"{model.name}: {s['method']}, {s['nsteps']} steps, {s['nfev']} evaluations, "
              f"derive {derive_time:.2f} s, compile {s['compile_time']:.2f} s, integrate {s['wall_time']:.3f} s"
              f"{drift}", file=stream)
        if "equilibrium" in s:
            e = s["equilibrium"]
            print(f"started at rest in the static equilibrium: found in {e['iterations']} iterations, generalized "
                  f"accelerations left {e['residual']:.3g} (m/s^2 or rad/s^2), {e['relative_residual']:.2g} of "
                  "the forces' scale", file=stream)
        print(f"wrote {len(written)} files to {out}", file=stream)
    for warning in results.warnings:
        print(f"flexkane: warning: {warning}", file=sys.stderr)
    if results.partial:
        if s.get("status") == "interrupted":
            print(f"flexkane: interrupted at t = {s['t_reached']:.6g} s; the files hold the results up to "
                  "there (marked partial)", file=sys.stderr)
            return 130
        raise SolverFailure(s["t_reached"], f"{s['message']}; partial results written to {out}")
    return 0


def _stopped(out: Path, written: list, plots: list, interrupted: bool, results) -> int:
    """Report a stop request honoured after the integration; return exit code 130.

    ``written``: the files complete before the equations and plots; ``plots``: the other files
    complete when they were stopped. ``interrupted``: whether the integration itself was cut short.
    """
    files = ", ".join([p.name for p in written] + plots)
    if interrupted:
        s = results.solver
        print(f"flexkane: interrupted at t = {s['t_reached']:.6g} s; the files hold the results up to "
              f"there (marked partial): {files} in {out}; the other files were not written", file=sys.stderr)
    else:
        print(f"flexkane: interrupted after the integration; complete files in {out}: {files}; the other "
              "files were not written", file=sys.stderr)
    return 130
