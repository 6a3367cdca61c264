"""Run a parameter sweep: derive once per structure, run the missing variants, keep every result.

The steps of :func:`run_sweep`:

1. expand the spec into variants (grid or random) and hash each one (:mod:`.variants`);
2. read the directory's log: variants already finished are not run again (resume);
3. group them by structure, derive and compile each structure once, here (:mod:`.structure`);
4. validate each variant where it runs: an invalid one (a negative ``EI``) is recorded as failed;
5. run them here or on Dask (:mod:`.execute`); each finished variant is appended to the log (and
   its trajectory written) as it arrives, and the table is rewritten from the log at most every
   ``table_interval`` seconds, at the end, and on interruption.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path

from .._version import __version__
from ..errors import ModelError
from ..model import Model, dumps_model
from .spec import SweepSpec
from .store import SweepStore
from .structure import derive_equations, group_by_structure
from .table import table_columns, table_rows
from .variants import RunSettings, key_kind, make_variants
from .worker import Structure, Task

__all__ = ["run_sweep", "SweepOutcome", "SweepInterrupted"]


@dataclass
class SweepOutcome:
    """What a sweep did.

    Attributes
    ----------
    directory : pathlib.Path
    variants : int
        Variants in the sweep.
    computed : int
        Variants run (or found invalid) by this call.
    reused : int
        Variants found finished in the directory's log.
    failed : int
        Rows of the table with status ``failed``.
    lost : int
        Variants the cluster could not run (not recorded; a re-run computes them).
    lost_messages : list of str
        The distinct errors of the cluster behind ``lost``.
    structures : int
        Structures derived (or loaded from the derivation cache) and compiled by this call.
    elapsed : float
        Wall time of the call [s].
    workers : int
        Worker processes (1: run in this process).
    rows : list of dict
        The table.
    interrupted : bool
        True when Ctrl-C (or SIGTERM) stopped the sweep.
    """

    directory: Path
    variants: int = 0
    computed: int = 0
    reused: int = 0
    failed: int = 0
    lost: int = 0
    structures: int = 0
    elapsed: float = 0.0
    workers: int = 1
    rows: list = field(default_factory=list)
    interrupted: bool = False
    lost_messages: list = field(default_factory=list)


class SweepInterrupted(KeyboardInterrupt):
    """Ctrl-C (or SIGTERM) during a sweep; the table holds the variants finished so far.

    Attributes
    ----------
    outcome : SweepOutcome
    """

    def __init__(self, outcome: SweepOutcome):
        super().__init__("sweep interrupted")
        self.outcome = outcome


def _is_done(record: dict, store: SweepStore, save_trajectories: bool, retry_failed: bool) -> bool:
    if record.get("status") not in ("ok", "failed"):
        return False
    if retry_failed and record["status"] == "failed":
        return False
    if save_trajectories and record.get("trajectory") and \
            not (store.directory / record["trajectory"] / "results.npz").exists():
        return False
    if save_trajectories and record["status"] == "ok" and not record.get("trajectory"):
        return False
    return True


def _check_initial_keys(spec: SweepSpec, base: Model) -> None:
    """Initial conditions varied must name a coordinate or speed (of the base model, unless the sweep
    changes the counts of modes, whose variants are then checked one by one)."""
    from ..model.coordinates import coordinate_names
    from ..model.paths import parse_path

    if any(str(parse_path(v.key)[-1]).startswith("n_") for v in spec.vary):
        return
    coordinates = coordinate_names(base)
    names = [c.q for c in coordinates if c.driver != "coordinate"]
    names += [c.u for c in coordinates if c.driver is None and c.u is not None]
    for vary in spec.vary:
        if key_kind(base, vary.key) == "initial":
            name = parse_path(vary.key)[-1]
            if name not in names:
                raise ModelError(f"vary {vary.key}", "a parameter of the model, or one of its coordinates "
                                 f"and speeds ({', '.join(names)})", name)


class _Recorder:
    """Handles each finished variant: trajectory, log line, periodic table, progress."""

    def __init__(self, store, variants, spec, records, metadata, outcome, table_interval, bar, on_result):
        self.store = store
        self.variants = variants
        self.keys = [v.key for v in spec.vary]
        self.by_id = {v.id: v for v in variants}
        self.records = records
        self.metadata = metadata
        self.outcome = outcome
        self.table_interval = table_interval
        self.bar = bar
        self.on_result = on_result
        self.last_write = time.perf_counter()
        self.done = sum(1 for v in variants if v.id in records)

    def __call__(self, record: dict) -> None:
        variant = self.by_id[record["variant"]]
        results = record.pop("results", None)
        entry = {"variant": variant.id, "assignments": [list(a) for a in variant.assignments],
                 "status": record["status"], "error": record.get("error", ""),
                 "metrics": record.get("metrics", {})}
        if results is not None:
            results.write(self.store.variant_dir(variant.id))
            entry["trajectory"] = f"variants/{variant.id}"
        self.store.append(entry)
        self.records[variant.id] = entry
        self.outcome.computed += 1
        self.done += 1
        if self.bar is not None:
            self.bar.update(self.done)
        if time.perf_counter() - self.last_write >= self.table_interval:
            self.write_table()
        if self.on_result is not None:
            self.on_result(dict(entry, index=variant.index))

    def lost(self, task, message: str) -> None:
        self.outcome.lost += 1
        if message not in self.outcome.lost_messages:
            self.outcome.lost_messages.append(message)

    def write_table(self) -> list[dict]:
        """Rewrite the table from the records; the next rewrite waits at least ten times as long."""
        start = time.perf_counter()
        rows = table_rows(self.variants, self.records)
        self.store.write_table(rows, table_columns(self.keys, rows), self.metadata)
        self.last_write = time.perf_counter()
        self.table_interval = max(self.table_interval, 10 * (self.last_write - start))
        return rows


def _resolve_model(model) -> Model:
    if isinstance(model, Model):
        return model.copy().validate()
    if isinstance(model, (str, Path)):
        from ..builtin import resolve_model
        return resolve_model(str(model)).validate()
    raise ModelError("model", "a Model, a built-in model name or a model file path", model)


def _check_same_sweep(store: SweepStore, variants: list, description: dict, force: bool) -> None:
    """Refuse to run into a directory whose table holds variants this sweep does not have: its table
    would be replaced by one without them. A sweep that only adds variants (more values) extends it."""
    if force:
        return
    previous = _table_variants(store)
    dropped = previous - {v.id for v in variants}
    if not dropped:
        return
    before = store.read_spec() or {}
    changes = [f"{k}: {_shown(before.get(k))} there, {_shown(description.get(k))} here"
               for k in ("model", "vary", "sampling", "samples", "seed", "settings")
               if k in before and before.get(k) != description.get(k)]
    if before.get("model_text") not in (None, description.get("model_text")):
        changes.append("another base model (file or overrides)")
    raise ModelError("out", "a new directory or one holding this sweep (to resume or extend it)",
                     str(store.directory),
                     f"it holds a different sweep whose table has {len(dropped)} variant(s) this one lacks"
                     + (f" ({'; '.join(changes)})" if changes else "")
                     + "; choose another directory, or force to replace its table (its log keeps every "
                     "finished variant)")


def _shown(value) -> str:
    return ", ".join(map(str, value)) if isinstance(value, list) else str(value)


def _table_variants(store: SweepStore) -> set:
    """Ids of the variants in the directory's table (else in its log)."""
    import csv

    if store.csv_path.exists():
        try:
            with open(store.csv_path, newline="", encoding="utf-8") as handle:
                return {row["variant"] for row in csv.DictReader(handle) if row.get("variant")}
        except (OSError, KeyError, csv.Error, UnicodeDecodeError):
            pass
    return set(store.read_log())


def run_sweep(model, spec: SweepSpec, *, out, workers: int | None = None, scheduler: str | None = None,
              client=None, batch_size: int | None = None, retry_failed: bool = False, progress: bool = False,
              on_result=None, table_interval: float = 1.0, force: bool = False) -> SweepOutcome:
    """Run every variant of a sweep that the output directory does not hold yet.

    Parameters
    ----------
    model : Model or str
        The base model, or a built-in model name or model file path.
    spec : SweepSpec
        Varied keys, sampling and run settings (:func:`flexkane.sweep.sweep_spec_from_toml` reads the
        ``[sweep]`` table of a model file).
    out : str or os.PathLike
        Sweep directory: created, or resumed when it holds a log of finished variants.
    workers : int, optional
        Local worker processes of a Dask LocalCluster; 1 runs everything in this process (no Dask).
        By default all cores, unless the sweep would take less than :data:`SERIAL_SECONDS` here
        (estimated from its first two variants, run here).
    scheduler : str, optional
        Address of an existing Dask scheduler (``tcp://host:port``) instead of a local cluster.
    client : distributed.Client, optional
        An existing Dask client to use (left open).
    batch_size : int, optional
        Variants per Dask task; adaptive by default (about 0.25 s of work per task, see
        :mod:`flexkane.sweep.execute`).
    retry_failed : bool
        Run again the variants recorded as failed.
    progress : bool
        Show a progress bar on a terminal.
    on_result : callable, optional
        Called with each finished variant's log record (plus its ``index``) as it arrives.
    table_interval : float
        Shortest time between two rewrites of the table while the sweep runs [s].
    force : bool
        Run into a directory that holds a different sweep (its table has variants this one lacks:
        other varied keys or values, sampling, settings or base model), replacing its table; without
        it that is refused. A sweep that only adds variants extends the table without it.

    Returns
    -------
    SweepOutcome

    Raises
    ------
    ModelError
        If a varied key, a value or a setting is invalid (nothing is run).
    SweepInterrupted
        On Ctrl-C (a ``KeyboardInterrupt``); the log and the table hold every finished variant.

    Examples
    --------
    >>> from flexkane.sweep import SweepSpec, Vary, run_sweep                       # doctest: +SKIP
    >>> spec = SweepSpec(vary=(Vary.parse("beams.B.EI=20:80:4"),), t_end=0.5)      # doctest: +SKIP
    >>> outcome = run_sweep("falling-beam-exact", spec, out="out/ei-sweep")         # doctest: +SKIP
    """
    from ..extras import require
    from ..progress import ProgressBar

    require("pyarrow.parquet")   # the table needs it: say so before anything is computed
    started = time.perf_counter()
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ModelError("workers", "a positive number of worker processes", workers)
    if scheduler is not None and client is not None:
        raise ModelError("client", "either a scheduler address or a client, not both", scheduler)
    if workers is not None and (scheduler is not None or client is not None):
        raise ModelError("workers", "either a number of workers or a scheduler address, not both", workers)
    if batch_size is not None and (isinstance(batch_size, bool) or not isinstance(batch_size, int)
                                   or batch_size < 1):
        raise ModelError("batch_size", "a positive number of variants per task", batch_size)
    base = _resolve_model(model)
    settings = RunSettings.resolve(spec, base)
    variants = make_variants(base, spec, settings)
    _check_initial_keys(spec, base)
    store = SweepStore(out)
    outcome = SweepOutcome(directory=store.directory, variants=len(variants))
    metadata = {"flexkane": __version__, "model": base.name, "vary": [v.describe() for v in spec.vary],
                "sampling": spec.sampling, "samples": spec.samples, "seed": spec.seed,
                "settings": settings.as_dict(), "variants": len(variants)}
    description = {**metadata, "save_trajectories": spec.save_trajectories, "metric": spec.metric,
                   "model_text": dumps_model(base)}
    _check_same_sweep(store, variants, description, force)
    store.write_spec(description)
    records = store.read_log()
    records = {k: r for k, r in records.items()
               if _is_done(r, store, spec.save_trajectories, retry_failed)}
    pending = [v for v in variants if v.id not in records]
    outcome.reused = len(variants) - len(pending)
    bar = ProgressBar(len(variants), enabled=progress, unit="variants")
    recorder = _Recorder(store, variants, spec, records, metadata, outcome, table_interval, bar, on_result)
    try:
        with bar:
            bar.update(recorder.done)
            jobs = _prepare(base, spec, settings, pending, recorder, outcome)
            if jobs:
                _execute(jobs, recorder, outcome, workers=workers, scheduler=scheduler, client=client,
                         batch_size=batch_size)
    except KeyboardInterrupt:
        store.close()
        # the interruption may have come between a log line and its record here: the log decides
        recorder.records.update({k: r for k, r in store.read_log().items()
                                 if _is_done(r, store, spec.save_trajectories, retry_failed)})
        outcome.interrupted = True
        outcome.rows = recorder.write_table()
        outcome.failed = sum(r["status"] == "failed" for r in outcome.rows)
        outcome.elapsed = time.perf_counter() - started
        raise SweepInterrupted(outcome) from None
    finally:
        store.close()
    outcome.rows = recorder.write_table()
    outcome.failed = sum(r["status"] == "failed" for r in outcome.rows)
    outcome.elapsed = time.perf_counter() - started
    return outcome


def _validation_error(variant) -> str | None:
    """The message of a variant's validation error, or None when it is valid."""
    try:
        variant.model.validate()
    except ModelError as exc:
        return str(exc)
    return None


def _prepare(base, spec, settings, pending, recorder, outcome) -> list:
    """Derive and compile each structure of the pending variants; return ``(structure, task)`` jobs.

    Variants are validated by whoever runs them (in parallel); here only one valid variant per
    structure is needed, to derive it. A structure without any valid variant is recorded as failed.
    """
    from ..simulation import compile_model

    jobs = []
    for group in group_by_structure(pending):
        start = time.perf_counter()
        errors = []
        for variant in group.variants:
            message = _validation_error(variant)
            if message is None:
                try:
                    group.eom, _ = derive_equations(variant.model)
                except (ModelError, ValueError, ArithmeticError) as exc:
                    message = f"derivation failed: {exc}"
                else:
                    break
            errors.append((variant, message))
        for variant, message in errors:  # tried as representatives: invalid, recorded here
            recorder({"variant": variant.id, "status": "failed", "error": message, "metrics": {}})
        if group.eom is None:
            continue
        group.key = compile_model(group.eom).key  # built once here; workers load it from the cache
        group.derive_time = time.perf_counter() - start
        outcome.structures += 1
        shared = Structure(group.eom, group.key, base)
        jobs += [(shared, Task(v.id, v.assignments, settings, keep_results=spec.save_trajectories))
                 for v in group.variants[len(errors):]]
    jobs.sort(key=lambda job: recorder.by_id[job[1].variant_id].index)
    return jobs


#: A sweep estimated to take less than this in one process [s] is not worth starting a LocalCluster.
SERIAL_SECONDS = 10.0


def _execute(jobs, recorder, outcome, *, workers, scheduler, client, batch_size) -> None:
    """Run the jobs on the given cluster, or here, or on a LocalCluster of ``workers`` processes.

    With no choice made (``workers`` None), two variants run here first; when the others would take
    less than :data:`SERIAL_SECONDS` here too, they do, else a LocalCluster of all cores runs them.
    """
    from .execute import dask_client, default_worker_count, run_on_dask, run_serial

    if client is not None:
        outcome.workers = len(client.nthreads())
        run_on_dask(client, jobs, recorder, recorder.lost, batch_size=batch_size)
        return
    if scheduler is None:
        if workers is None and (default_worker_count() == 1 or len(jobs) <= 2):
            workers = 1
        elif workers is None:
            run_serial(jobs[:1], recorder)  # the first run here also loads the compiled model
            start = time.perf_counter()
            run_serial(jobs[1:2], recorder)
            jobs = jobs[2:]
            if (time.perf_counter() - start) * len(jobs) < SERIAL_SECONDS:
                workers = 1
        workers = min(workers or default_worker_count(), len(jobs))
        if workers <= 1:
            outcome.workers = 1
            run_serial(jobs, recorder)
            return
    from .execute import SCRATCH_NAME

    with dask_client(workers=workers, scheduler=scheduler, scratch=recorder.store.directory / SCRATCH_NAME) as dask:
        outcome.workers = len(dask.nthreads())
        run_on_dask(dask, jobs, recorder, recorder.lost, batch_size=batch_size)


def describe_outcome(outcome: SweepOutcome) -> str:
    """One line for the command line: counts, structures, time, throughput."""
    rate = outcome.computed / outcome.elapsed if outcome.elapsed > 0 else math.nan
    where = "in this process" if outcome.workers <= 1 else f"on {outcome.workers} workers"
    text = (f"{outcome.variants} variants: {outcome.computed} computed {where}, {outcome.reused} already done"
            f", {outcome.failed} failed; {outcome.structures} structure(s); "
            f"{outcome.elapsed:.1f} s ({rate:.1f} variants/s)")
    if outcome.lost:
        text += f"; {outcome.lost} lost on the cluster (re-run to compute them): {outcome.lost_messages[0]}"
    return text
