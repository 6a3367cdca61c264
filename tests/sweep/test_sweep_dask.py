"""A real Dask LocalCluster with two worker processes gives the same table as the serial run."""

import json
import os

import pytest

from flexkane.cli import main
from flexkane.sweep import SweepSpec, read_table, run_sweep

distributed = pytest.importorskip("distributed")

MODEL = "falling-beam-exact"
# EI = -5 is rejected by validation: failures come back from the workers like any result
SPEC = SweepSpec(vary=("beams.B.EI=-5,20,50,80", "initial.q3=0.5,1.0"), t_end=0.2, dt_out=0.01)
VOLATILE = ("wall_time", "run_time")


def stable(rows):
    return [{k: v for k, v in row.items() if k not in VOLATILE} for row in rows]


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    out = tmp_path_factory.mktemp("serial")
    run_sweep(MODEL, SPEC, out=out, workers=1)
    rows = stable(read_table(out, as_rows=True))
    assert [r["status"] for r in rows] == ["failed"] * 2 + ["ok"] * 6
    return rows


@pytest.fixture(scope="module")
def cluster():
    # the workers inherit FLEXKANE_CACHE_DIR (set for the session by tests/conftest.py), so they load
    # the modules compiled by the serial run instead of compiling them again
    assert os.environ.get("FLEXKANE_CACHE_DIR")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=40) as local:
        yield local


def test_local_cluster_of_two_processes_gives_the_serial_table(tmp_path, serial, cluster):
    arrived = []
    with distributed.Client(cluster) as client:
        outcome = run_sweep(MODEL, SPEC, out=tmp_path, client=client, on_result=lambda r: arrived.append(r["index"]))
    assert outcome.workers == 2 and outcome.computed == 8 and outcome.structures == 1
    assert sorted(arrived) == list(range(8))  # streamed back one by one, in whatever order they finished
    assert stable(read_table(tmp_path, as_rows=True)) == serial
    logged = [json.loads(line)["variant"] for line in (tmp_path / "sweep-log.jsonl").read_text().splitlines()]
    assert sorted(logged) == sorted(row["variant"] for row in serial)  # each variant logged once


def test_batches_of_variants_per_task_give_the_serial_table(tmp_path, serial, cluster):
    with distributed.Client(cluster) as client:
        run_sweep(MODEL, SPEC, out=tmp_path, client=client, batch_size=3)
    assert stable(read_table(tmp_path, as_rows=True)) == serial


def test_cli_on_an_existing_scheduler_gives_the_serial_table(tmp_path, serial, cluster):
    assert main(["sweep", MODEL, "--vary", "beams.B.EI=-5,20,50,80", "--vary", "initial.q3=0.5,1.0",
                 "--t-end", "0.2", "--dt-out", "0.01", "--scheduler", cluster.scheduler_address,
                 "--out", str(tmp_path), "--quiet"]) == 0
    assert stable(read_table(tmp_path, as_rows=True)) == serial


@pytest.mark.slow
def test_default_local_cluster_started_by_the_sweep_gives_the_serial_table(tmp_path, serial):
    outcome = run_sweep(MODEL, SPEC, out=tmp_path, workers=2)
    assert outcome.workers == 2
    assert stable(read_table(tmp_path, as_rows=True)) == serial


def test_the_scratch_space_of_local_workers_is_in_the_sweep_directory_and_removed(tmp_path):
    from flexkane.sweep.execute import SCRATCH_NAME, dask_client

    scratch = tmp_path / SCRATCH_NAME
    with dask_client(workers=1, scratch=scratch) as client:
        places = client.run(lambda dask_worker: dask_worker.local_directory)
        assert places and all(str(place).startswith(str(scratch)) for place in places.values())
        assert scratch.is_dir()
    assert not scratch.exists()
