"""The sweep table: one row per finished variant, its parameters, status and summary metrics.

Columns, in order: ``variant`` (id), ``index`` (position in the sweep), one column per varied key
(named by the key, in the unit of that key), ``status`` (``ok`` or ``failed``), ``error`` (the
message of a failed variant), then the metrics of :mod:`flexkane.sweep.metrics`.
"""

from __future__ import annotations

from pathlib import Path

from .store import CSV_NAME, FIXED_COLUMNS, TABLE_NAME

__all__ = ["table_rows", "table_columns", "read_table", "STATUSES"]

#: Values of the ``status`` column.
STATUSES = ("ok", "failed")


def table_rows(variants, records: dict) -> list[dict]:
    """Rows of the finished variants, in sweep order.

    Parameters
    ----------
    variants : list of Variant
        The variants of the current sweep.
    records : dict of str to dict
        Log records by variant id (records of other sweeps in the same directory are ignored).

    Returns
    -------
    list of dict
    """
    rows = []
    for variant in variants:
        record = records.get(variant.id)
        if record is None:
            continue
        row = {"variant": variant.id, "index": variant.index}
        row.update(dict(variant.assignments))
        row["status"] = record["status"]
        row["error"] = record.get("error", "")
        row.update(record.get("metrics", {}))
        rows.append(row)
    return rows


def table_columns(keys: list[str], rows: list[dict]) -> list[str]:
    """Column order: id, index, varied keys, status, error, fixed metrics, tips, other metrics, final state.

    Per-beam and per-state columns appear as the rows have them (in the order the first row that has
    them lists them), so a sweep over ``n_modes`` gets the union of the coordinates.
    """
    columns = ["variant", "index", *keys, "status", "error", *FIXED_COLUMNS]
    known = set(columns)
    tips, others, finals = [], [], []
    for row in rows:
        for name in row:
            if name not in known:
                known.add(name)
                group = tips if name.startswith("max_abs_") else finals if name.startswith("final_") else others
                group.append(name)
    return columns + sorted(tips) + sorted(others) + finals


def read_table(directory, *, as_rows: bool = False):
    """Read the table of a sweep directory.

    Parameters
    ----------
    directory : str or os.PathLike
        The sweep's ``--out`` directory (or the ``sweep.parquet`` file).
    as_rows : bool
        Return a list of dicts instead of a :class:`pyarrow.Table`.

    Returns
    -------
    pyarrow.Table or list of dict
    """
    from ..extras import require

    pq = require("pyarrow.parquet")
    path = Path(directory)
    if path.is_dir():
        path = path / TABLE_NAME
    if not path.exists():
        from ..errors import ModelError
        raise ModelError("out", f"a sweep directory holding {TABLE_NAME} (or {CSV_NAME})", str(directory))
    table = pq.read_table(path)
    return table.to_pylist() if as_rows else table
