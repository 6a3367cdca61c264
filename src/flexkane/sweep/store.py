"""The files of a sweep directory: an append-only log of finished variants, compacted into tables.

``sweep-log.jsonl``
    One JSON line per finished variant (id, assignments, status, error message, metrics), written
    as each variant finishes (so it survives the process being killed) and synced to disk at most
    every :data:`SYNC_INTERVAL` seconds and at the end (so an operating-system crash loses at most
    that much). It is the sweep's memory: a re-run reads it and computes only the variants it lacks.
    A line cut short by a crash is dropped when the log is opened again.
``sweep.parquet``, ``sweep.csv``
    The table, one row per finished variant of the current sweep in sweep order, rewritten from
    the log atomically (a reader sees the previous complete table or the new one, never a torn one).
``sweep.json``
    The sweep's description: model, varied keys, sampling, run settings, variant count.
``variants/<id>/``
    ``results.npz`` and ``results.csv`` of each variant with ``--save-trajectories``.
"""

from __future__ import annotations

import csv
import io
import json
import os
import time
from pathlib import Path

from ..atomic import atomic_write_bytes, atomic_write_text
from ..errors import ModelError

__all__ = ["SweepStore", "LOG_NAME", "TABLE_NAME", "CSV_NAME", "SPEC_NAME", "FIXED_COLUMNS"]

LOG_NAME = "sweep-log.jsonl"
TABLE_NAME = "sweep.parquet"
CSV_NAME = "sweep.csv"
SPEC_NAME = "sweep.json"
#: Longest time between two syncs of the log to disk [s].
SYNC_INTERVAL = 0.5
#: Leading metric columns, in this order; per-beam and per-state columns follow.
FIXED_COLUMNS = ("t_reached", "nsteps", "nfev", "wall_time", "run_time", "energy_error", "energy_check")


class SweepStore:
    """The output directory of a sweep.

    Parameters
    ----------
    directory : str or os.PathLike
        Created if missing; an existing one is resumed.
    """

    def __init__(self, directory):
        self.directory = Path(directory)
        if self.directory.exists() and not self.directory.is_dir():
            raise ModelError("out", "a directory", str(self.directory), "a file of that name exists")
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise ModelError("out", "a directory that can be created", str(self.directory),
                             exc.strerror or str(exc)) from None
        self.log_path = self.directory / LOG_NAME
        self.table_path = self.directory / TABLE_NAME
        self.csv_path = self.directory / CSV_NAME
        self._repair_log()
        self._log = None
        self._synced = time.monotonic()

    # ------------------------------------------------------------------ log
    def _repair_log(self) -> None:
        """Drop a last line left incomplete by a crash, so that appends start on a new line."""
        if not self.log_path.exists():
            return
        data = self.log_path.read_bytes()
        if data and not data.endswith(b"\n"):
            with open(self.log_path, "r+b") as handle:
                handle.truncate(data.rfind(b"\n") + 1)
                os.fsync(handle.fileno())

    def read_log(self) -> dict[str, dict]:
        """Records of the finished variants by id (a later line replaces an earlier one)."""
        records: dict[str, dict] = {}
        if not self.log_path.exists():
            return records
        with open(self.log_path, encoding="utf-8") as handle:
            for line in handle:
                try:
                    record = json.loads(line)
                except json.JSONDecodeError:
                    continue  # a damaged line: its variant is computed again
                if isinstance(record, dict) and isinstance(record.get("variant"), str):
                    records[record["variant"]] = record
        return records

    def append(self, record: dict) -> None:
        """Append one finished variant to the log (one ``write``; synced every SYNC_INTERVAL)."""
        data = (json.dumps(record, sort_keys=True, default=_json_default) + "\n").encode("utf-8")
        if self._log is None:
            self._log = os.open(self.log_path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o666)
        written = os.write(self._log, data)
        while written < len(data):  # a short write (full disk, signal) continues where it stopped
            written += os.write(self._log, data[written:])
        if time.monotonic() - self._synced >= SYNC_INTERVAL:
            self.sync()

    def sync(self) -> None:
        """Flush the log to disk."""
        if self._log is not None:
            os.fsync(self._log)
        self._synced = time.monotonic()

    def close(self) -> None:
        """Sync and close the log."""
        if self._log is not None:
            self.sync()
            os.close(self._log)
            self._log = None

    def variant_dir(self, variant_id: str) -> Path:
        """``variants/<id>/``, created."""
        path = self.directory / "variants" / variant_id
        path.mkdir(parents=True, exist_ok=True)
        return path

    def read_spec(self) -> dict | None:
        """The description in ``sweep.json``, or None when there is none (or it cannot be read)."""
        try:
            description = json.loads((self.directory / SPEC_NAME).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None
        return description if isinstance(description, dict) else None

    def write_spec(self, description: dict) -> None:
        """Write ``sweep.json`` atomically."""
        atomic_write_text(self.directory / SPEC_NAME,
                          json.dumps(description, indent=2, sort_keys=False, default=_json_default) + "\n")

    # ------------------------------------------------------------------ table
    def write_table(self, rows: list[dict], columns: list[str], metadata: dict) -> None:
        """Write ``sweep.parquet`` and ``sweep.csv`` atomically.

        Parameters
        ----------
        rows : list of dict
            One dict per variant; missing columns are null.
        columns : list of str
            Column order.
        metadata : dict
            Stored as JSON under the key ``flexkane.sweep`` of the Parquet schema metadata.
        """
        from ..extras import require

        pa = require("pyarrow")
        pq = require("pyarrow.parquet")
        arrays = []
        for column in columns:
            values = [row.get(column) for row in rows]
            kind = _arrow_type(values)
            if kind == pa.string():
                values = [None if v is None else v if isinstance(v, str) else _text(v) for v in values]
            arrays.append(pa.array(values, type=kind))
        table = pa.Table.from_arrays(arrays, names=list(columns))
        table = table.replace_schema_metadata(
            {"flexkane.sweep": json.dumps(metadata, sort_keys=True, default=_json_default)})
        sink = pa.BufferOutputStream()
        pq.write_table(table, sink)
        atomic_write_bytes(self.table_path, sink.getvalue().to_pybytes())
        atomic_write_text(self.csv_path, csv_table(rows, columns))


def _json_default(value):
    if hasattr(value, "item"):  # numpy scalars
        return value.item()
    raise TypeError(f"{type(value).__name__} is not JSON serializable")


def _arrow_type(values: list):
    """Arrow type of a column: bool, int64, float64 or string (mixed values become text)."""
    from ..extras import require

    pa = require("pyarrow")

    present = [v for v in values if v is not None]
    if not present:
        return pa.float64()
    if all(isinstance(v, bool) for v in present):
        return pa.bool_()
    if any(isinstance(v, (bool, str)) for v in present):
        return pa.string()
    if all(isinstance(v, int) for v in present):
        return pa.int64()
    return pa.float64()


def _text(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def csv_table(rows: list[dict], columns: list[str]) -> str:
    """The table as CSV text: a header, then one line per row (floats in shortest round-trip form)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    for row in rows:
        writer.writerow(["" if row.get(c) is None else _text(row.get(c)) for c in columns])
    return buffer.getvalue()
