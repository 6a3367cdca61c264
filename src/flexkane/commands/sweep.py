"""``flexkane sweep``: run a model over a grid or random draws of parameter values."""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

from ..errors import ModelError
from ..interruption import StopRequest
from ..model.parts import METHODS
from ._common import (add_equilibrium_argument, add_max_steps_argument, add_model_arguments, add_out_arguments,
                      model_from_args, prepare_out)

__all__ = ["register"]

_EPILOG = """\
values of --vary:
  KEY=START:STOP:COUNT     COUNT evenly spaced values from START to STOP (add :log for geometric)
  KEY=v1,v2,...            a list of values (numbers, true/false or expressions)
  KEY is a key path (beams.B.EI, initial.q3, parameters.L) or a parameter or coordinate name.
  With --random N a range is the interval the N values are drawn from (COUNT may be left out).

The model file may hold a [sweep] table (vary, sampling, samples, seed, t_end, dt_out, rtol, atol,
method, max_steps, save_trajectories, metric); the command line adds to it and overrides it.

DIR receives sweep.parquet and sweep.csv (one row per variant: its values, status, error message,
max |tip| of each beam, final state, energy drift or power-balance error, solver steps, wall time),
sweep-log.jsonl (appended as each variant finishes), sweep.json and, with --save-trajectories,
variants/<id>/results.npz. Running the same command again computes only the missing variants; a
directory holding something else (another sweep, other files) needs --force. Local Dask workers keep
their scratch space in DIR/.dask-scratch while they run; it is removed when they stop.
Exit codes: 0 done (failed variants are rows with status "failed"), 2 invalid arguments,
130 interrupted (the table holds the variants finished so far).

examples:
  flexkane sweep falling-beam-exact --vary beams.B.EI=20:80:7 --t-end 0.5 --out out/ei --plot
  flexkane sweep flexible-arm --vary T0=1:3:5 --vary EI=8,12,16 --workers 4 --out out/arm
  flexkane sweep arm.toml --random 500 --seed 1 --scheduler tcp://10.0.0.5:8786 --out out/arm-mc
"""


def register(subparsers) -> None:
    import argparse

    p = subparsers.add_parser("sweep", help="run a model over many parameter values (local cores or Dask)",
                              description="Run a model for every combination (--grid) or random draws\n"
                                          "(--random) of the values of the varied keys, on all local cores\n"
                                          "or on a Dask cluster, and write one table row per variant.",
                              epilog=_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_model_arguments(p, default=None)
    p.add_argument("--vary", action="append", default=[], metavar="KEY=VALUES",
                   help="a varied key and its values (START:STOP:COUNT or v1,v2,...); repeatable")
    sampling = p.add_mutually_exclusive_group()
    sampling.add_argument("--grid", action="store_true", help="every combination of the values [default]")
    sampling.add_argument("--random", type=int, default=None, metavar="N", help="N random variants")
    p.add_argument("--seed", type=int, default=None, metavar="S", help="seed of --random (required with it)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, default=None, metavar="N",
                       help="local Dask worker processes (1: no Dask, in this process) [default: all cores, "
                            "or this process when the sweep would take under 10 s]")
    where.add_argument("--scheduler", default=None, metavar="ADDRESS",
                       help="address of an existing Dask scheduler, e.g. tcp://host:8786")
    add_out_arguments(p, "", required=True)
    p.add_argument("--save-trajectories", action="store_true",
                   help="keep each variant's results.npz and results.csv under DIR/variants/<id>/")
    p.add_argument("--t-end", type=float, default=None, metavar="T", help="end time [s]")
    p.add_argument("--dt-out", type=float, default=None, metavar="DT", help="output interval [s]")
    p.add_argument("--rtol", type=float, default=None, metavar="R", help="relative tolerance")
    p.add_argument("--atol", type=float, default=None, metavar="A", help="absolute tolerance")
    p.add_argument("--method", default=None, choices=METHODS, help="integration method")
    add_max_steps_argument(p)
    add_equilibrium_argument(p)
    p.add_argument("--batch-size", type=int, default=None, metavar="K",
                   help="variants per Dask task [default: adaptive, about 0.25 s of work per task]")
    p.add_argument("--retry-failed", action="store_true", help="run again the variants recorded as failed")
    p.add_argument("--metric", default=None, metavar="NAME",
                   help="table column to plot [default: max_abs_tip_ of the first beam]")
    p.add_argument("--plot", action="store_true",
                   help="plot the metric against the first one or two varied keys (DIR/<metric>_vs_<keys>.png)")
    p.add_argument("--plot-against", default=None, metavar="KEY[,KEY]", help="the keys on the plot's axes")
    p.add_argument("--quiet", action="store_true", help="no progress bar and no summary")
    p.set_defaults(handler=_handle)


def _model_text(spec: str) -> str | None:
    """The model file text of MODEL (built-in or path), for its [sweep] table."""
    from ..builtin import builtin_names, builtin_text

    if spec in builtin_names():
        return builtin_text(spec)
    path = Path(spec)
    return path.read_text(encoding="utf-8") if path.is_file() else None


def sweep_spec_from_args(args):
    """The model file's [sweep] table overridden by the command line."""
    from ..sweep import SweepSpec, Vary, sweep_spec_from_toml

    text = _model_text(args.model)
    base = (sweep_spec_from_toml(text) if text else None) or SweepSpec()
    cli = SweepSpec(vary=tuple(Vary.parse(v) for v in args.vary), t_end=args.t_end, dt_out=args.dt_out,
                    rtol=args.rtol, atol=args.atol, method=args.method, max_steps=args.max_steps,
                    save_trajectories=args.save_trajectories, metric=args.metric)
    spec = base.merged(cli)
    if args.random is not None:
        spec = replace(spec, sampling="random", samples=args.random,
                       seed=args.seed if args.seed is not None else spec.seed)
    elif args.grid:
        spec = replace(spec, sampling="grid")
    elif args.seed is not None:
        spec = replace(spec, seed=args.seed)
    if not spec.vary:
        raise ModelError("--vary", "at least one KEY=VALUES (or a [sweep.vary] table in the model file)", None,
                         show_given=False)
    return spec


def _is_sweep_directory(directory: Path) -> bool:
    """A directory a sweep wrote (resumed without --force; run_sweep checks it is the same sweep)."""
    from ..sweep.store import LOG_NAME, SPEC_NAME

    return (directory / SPEC_NAME).is_file() or (directory / LOG_NAME).is_file()


def _handle(args) -> int:
    from ..numerics.jit_module import compile_in_subprocess
    from ..simulation import COMPILING_MESSAGE, INTEGRATORS_MESSAGE
    from ..sweep import SweepInterrupted, default_metric, describe_outcome, plot_metric, run_sweep

    model = model_from_args(args)
    spec = sweep_spec_from_args(args)
    out = prepare_out(args.out, force=args.force, resumable=_is_sweep_directory)
    try:
        # SIGTERM behaves as Ctrl-C: the table keeps what is finished; a first compilation can be stopped
        with StopRequest(), compile_in_subprocess(announce=COMPILING_MESSAGE, announce_integrators=INTEGRATORS_MESSAGE):
            outcome = run_sweep(model, spec, out=out, workers=args.workers, scheduler=args.scheduler,
                                batch_size=args.batch_size, retry_failed=args.retry_failed,
                                progress=not args.quiet, force=args.force)
    except ModelError as exc:
        if exc.path != "out":
            raise
        raise ModelError("--out", exc.expected, exc.given,
                         exc.hint.replace("or force to", "or --force to") if exc.hint else None) from None
    except SweepInterrupted as exc:
        done = len(exc.outcome.rows)
        print(f"flexkane: sweep interrupted; {exc.outcome.directory / 'sweep.parquet'} holds {done} of "
              f"{exc.outcome.variants} variants; run the same command again to compute the rest",
              file=sys.stderr)
        return 130
    if not args.quiet:
        print(describe_outcome(outcome))
    if outcome.failed:
        print(f"flexkane: {outcome.failed} variant(s) failed; their messages are in the error column",
              file=sys.stderr)
    if args.plot:
        metric = spec.metric or default_metric(outcome.rows)
        keys = args.plot_against.split(",") if args.plot_against else _plotted_keys(spec, outcome.rows)
        keys = [k.strip() for k in keys]
        from ..sweep.plot import column_units

        path = plot_metric(outcome.rows, metric, keys, outcome.directory / f"{metric}_vs_{'_'.join(keys)}.png",
                           units=column_units(model, keys))
        if not args.quiet:
            print(f"wrote {path}")
    return 0


def _plotted_keys(spec, rows) -> list[str]:
    """The first one or two varied keys that take more than one value."""
    keys = [v.key for v in spec.vary if len({repr(r.get(v.key)) for r in rows}) > 1]
    return (keys or [spec.vary[0].key])[:2]
