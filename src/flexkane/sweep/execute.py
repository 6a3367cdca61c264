"""Where the variants run: in this process one after the other, or on a Dask cluster.

Dask is the engine for parallel runs: by default a :class:`distributed.LocalCluster` of one
single-threaded worker process per core, or an existing cluster reached at a scheduler address.
Each structure's equations are sent to the workers once (``Client.scatter`` with broadcast); the
variants are submitted as tasks, at most a few per worker thread at a time so that a sweep of any
size keeps the scheduler light, and their records are handled as they complete
(:class:`distributed.as_completed`), whatever the order.

A task round trip (client, scheduler, worker and back) costs milliseconds, as much as a short
variant. Tasks therefore carry batches of variants of one structure, run one after the other on
the worker: the first tasks carry one variant each, later ones as many as take about
:data:`BATCH_SECONDS` by the run times measured so far, and fewer towards the end of the sweep so
that every worker stays busy until the last variant.
"""

from __future__ import annotations

import contextlib
import logging
import os
import shutil
from collections import deque
from pathlib import Path

from ..errors import FlexkaneError, ModelError
from ..extras import require
from ..interruption import deferred_signals
from .worker import run_batch, run_variant

__all__ = ["run_serial", "run_on_dask", "dask_client", "default_worker_count", "BatchSizer",
           "TASKS_PER_THREAD", "BATCH_SECONDS", "MAX_BATCH"]

#: Tasks kept in flight per worker thread.
TASKS_PER_THREAD = 3
#: Work per task aimed at by adaptive batches [s].
BATCH_SECONDS = 0.25
#: Most variants in one task.
MAX_BATCH = 256
#: Cluster errors (not the variant's) accepted before any variant came back, then the sweep stops.
_MAX_EARLY_CLUSTER_ERRORS = 20


def default_worker_count() -> int:
    """Cores available to this process."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def run_serial(jobs, on_record) -> None:
    """Run ``(structure, task)`` jobs here, in order, passing each record to ``on_record``.

    Raises
    ------
    KeyboardInterrupt
        On Ctrl-C, after the variants finished so far were handed over; the variant that was
        running is not recorded (a re-run computes it).
    """
    for structure, task in jobs:
        record = run_variant(structure, task)
        if record["status"] == "interrupted":
            raise KeyboardInterrupt
        on_record(record)


#: Folder of a sweep directory that holds the scratch space of the local Dask workers while they run.
SCRATCH_NAME = ".dask-scratch"


@contextlib.contextmanager
def dask_client(*, workers: int | None = None, scheduler: str | None = None, scratch=None):
    """A :class:`distributed.Client` of an existing cluster, or of a LocalCluster started here.

    Parameters
    ----------
    workers : int, optional
        Worker processes of the local cluster (one thread each); all cores by default.
    scheduler : str, optional
        Address of an existing scheduler, e.g. ``tcp://10.0.0.5:8786``; its workers need flexkane.
    scratch : str or os.PathLike, optional
        Directory for the local workers' scratch space (Dask's ``dask-scratch-space``), removed
        when the cluster closes; Dask's temporary directory by default.

    Yields
    ------
    distributed.Client
        Closed on exit, with the local cluster if one was started.
    """
    distributed = require("distributed", "dask[distributed]")
    Client, LocalCluster = distributed.Client, distributed.LocalCluster
    if scheduler:
        try:
            client = Client(scheduler, timeout="30s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise ModelError("scheduler", "the address of a running Dask scheduler (tcp://host:port)",
                             scheduler, f"{type(exc).__name__}: {exc}") from None
        try:
            yield client
        finally:
            client.close()
        return
    import dask

    # Dask's start and close cannot be cut by KeyboardInterrupt (it leaves the cluster half started and
    # Dask fails with its own errors): a signal meanwhile is honoured once the cluster is up, or closed.
    # Workers stopped with the cluster log heartbeat failures (with tracebacks) at level ERROR: the
    # sweep reports lost variants itself, so only CRITICAL messages of the cluster are shown.
    options = {}
    if scratch is not None:
        scratch = Path(scratch)
        scratch.mkdir(parents=True, exist_ok=True)
        options["local_directory"] = str(scratch)
    cluster = client = None
    interrupted = False
    try:
        with deferred_signals(), dask.config.set({"temporary-directory": str(scratch)} if scratch is not None else {}):
            cluster = LocalCluster(n_workers=workers or default_worker_count(), threads_per_worker=1,
                                   processes=True, dashboard_address=":0", silence_logs=logging.CRITICAL,
                                   **options)
            client = Client(cluster)
            with contextlib.suppress(Exception):
                client.run(_ignore_interrupts)
        yield client
    except BaseException:
        interrupted = True
        raise
    finally:
        with deferred_signals(), _unretrieved_cluster_errors_dropped(interrupted):
            for part in (client, cluster):
                if part is not None:
                    with contextlib.suppress(Exception):
                        part.close()
        if scratch is not None:
            shutil.rmtree(scratch, ignore_errors=True)


class _UnretrievedClusterError(logging.Filter):
    """Drops asyncio's report of a task of Dask's that failed unobserved ("Task exception was never
    retrieved"): a request the scheduler was serving when an interruption closed the cluster."""

    def filter(self, record: logging.LogRecord) -> bool:
        message = record.getMessage()
        return not (message.startswith("Task exception was never retrieved") and "distributed" in message)


@contextlib.contextmanager
def _unretrieved_cluster_errors_dropped(interrupted: bool):
    """While a cluster closes after an interruption or an error (``interrupted``), drop the reports
    of its requests cut short (:class:`_UnretrievedClusterError`), collecting them before the filter
    goes; the close at the end of a sweep shows everything."""
    if not interrupted:
        yield
        return
    import gc

    logger, dropped = logging.getLogger("asyncio"), _UnretrievedClusterError()
    logger.addFilter(dropped)
    try:
        yield
        gc.collect()   # a failed task reports when it is collected: here, not at exit
    finally:
        logger.removeFilter(dropped)


def _ignore_interrupts() -> None:
    """Run on the workers of a LocalCluster started here: Ctrl-C in the terminal reaches every process
    of the group; the sweep process handles it (and closes the cluster), the workers need not."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _threads(client) -> int:
    try:
        return max(1, sum(client.nthreads().values()))
    except Exception:  # noqa: BLE001 - a cluster still starting reports nothing useful
        return 1


class BatchSizer:
    """Number of variants for the next task.

    Parameters
    ----------
    threads : int
        Worker threads of the cluster.
    fixed : int, optional
        Always this many (1: one variant per task); adaptive when None.
    """

    def __init__(self, threads: int, fixed: int | None = None):
        self.threads = threads
        self.fixed = fixed
        self.seconds_per_variant = None

    def observe(self, records: list[dict]) -> None:
        """Update the mean run time per variant [s] from the records of a finished task."""
        times = [r["metrics"].get("run_time") for r in records if r.get("metrics")]
        times = [t for t in times if isinstance(t, float)]
        if times:
            mean = sum(times) / len(times)
            previous = self.seconds_per_variant
            self.seconds_per_variant = mean if previous is None else 0.7 * previous + 0.3 * mean

    def size(self, remaining: int) -> int:
        """Batch size when ``remaining`` variants are still to be submitted."""
        if self.fixed is not None:
            return self.fixed
        if self.seconds_per_variant is None:
            return 1
        target = int(BATCH_SECONDS / max(self.seconds_per_variant, 1e-6))
        fair = remaining // (2 * self.threads)  # leave work for every worker until the end
        return max(1, min(target, fair, MAX_BATCH))


def run_on_dask(client, jobs, on_record, on_lost, *, batch_size: int | None = None) -> None:
    """Run ``(structure, task)`` jobs on a Dask cluster, passing records to ``on_record`` as they complete.

    Parameters
    ----------
    client : distributed.Client
    jobs : list of (Structure, Task)
        Jobs of one structure share one :class:`~flexkane.sweep.worker.Structure` object, sent to the
        workers once.
    on_record : callable
        Called in this thread with each record returned by :func:`~flexkane.sweep.worker.run_variant`.
    on_lost : callable
        ``on_lost(task, message)`` for a variant the cluster could not run (a worker lost, flexkane
        missing on a worker, ...): it is not recorded, so a re-run computes it. A task that killed
        its workers repeatedly (``KilledWorker``) is recorded as failed instead.
    batch_size : int, optional
        Variants per task; adaptive when None (see the module docstring).

    Raises
    ------
    KeyboardInterrupt
        On Ctrl-C; the tasks still queued are cancelled.
    FlexkaneError
        When the first tasks all fail on the cluster (the workers cannot run flexkane).
    """
    from distributed import as_completed

    scattered: dict[int, tuple] = {}
    in_flight: dict = {}
    pending = deque(jobs)
    sizer = BatchSizer(_threads(client), batch_size)
    # results are fetched in the background as tasks finish, not one round trip at a time
    completed = as_completed(with_results=True, raise_errors=False)
    returned = 0
    early_errors = 0

    def submit_next() -> bool:
        if not pending:
            return False
        structure = pending[0][0]
        tasks = []
        for _ in range(sizer.size(len(pending))):
            if not pending or pending[0][0] is not structure:
                break
            tasks.append(pending.popleft()[1])
        if id(structure) not in scattered:
            # not cut by a signal: the scheduler would go on broadcasting to the workers of a cluster
            # that closes, and its failure would be printed by asyncio (the signal acts right after)
            with deferred_signals():
                scattered[id(structure)] = (structure, client.scatter(structure, broadcast=True, hash=False))
        future = client.submit(run_batch, scattered[id(structure)][1], tasks, pure=False)
        in_flight[future] = tasks
        completed.add(future)
        return True

    for _ in range(TASKS_PER_THREAD * sizer.threads + 1):
        if not submit_next():
            break
    try:
        for future, result in completed:
            tasks = in_flight.pop(future)
            error = result[1] if future.status == "error" else result if isinstance(result, BaseException) else None
            if error is not None:  # an error of the cluster, not of a variant (run_variant returns those)
                message = f"{type(error).__name__}: {error}"
                if type(error).__name__ != "KilledWorker":
                    for task in tasks:
                        on_lost(task, message)
                    early_errors += returned == 0
                    if returned == 0 and early_errors >= _MAX_EARLY_CLUSTER_ERRORS:
                        raise FlexkaneError(f"the Dask workers cannot run the sweep: {message}")
                    submit_next()
                    continue
                result = [{"variant": task.variant_id, "status": "failed", "results": None, "metrics": {},
                           "error": f"the worker running it died repeatedly ({message})"} for task in tasks]
            returned += 1
            sizer.observe(result)
            for record in result:
                if record["status"] != "interrupted":  # a worker hit by Ctrl-C: computed again next time
                    on_record(record)
            for task in tasks[len(result):]:
                on_lost(task, "interrupted on the worker")
            submit_next()
    except BaseException:
        with contextlib.suppress(Exception):
            client.cancel(list(in_flight))
        raise
    finally:
        scattered.clear()
