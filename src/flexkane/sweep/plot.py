"""Plot a metric of a sweep table against one or two varied parameters."""

from __future__ import annotations

import math
from pathlib import Path

from ..errors import ModelError

__all__ = ["plot_metric", "default_metric", "column_units"]

def default_metric(rows: list[dict]) -> str:
    """The first beam's ``max_abs_tip_<beam>`` column, else ``energy_error``."""
    for row in rows:
        for name in sorted(row):
            if name.startswith("max_abs_tip_"):
                return name
    return "energy_error"


def _field_unit(model, parts: list) -> str | None:
    """The unit of the field at a key path (split), as its declaration gives it."""
    from ..model import schema

    return schema.unit_of_path(".".join(p for p in parts if isinstance(p, str)), model.dimensions, model)


def column_units(model, keys) -> dict:
    """Units of the varied keys and of the ``final_<state>`` columns of a sweep of ``model``.

    A field's unit comes from its key (``beams.B.EI``: N m^2), an initial condition's from its
    coordinate (an angle: rad, a deflection: m; speeds per second), a parameter's from the field it is
    given to (``beams.link.EI = "EI"``: N m^2); a key whose unit cannot be told is left out.

    Parameters
    ----------
    model : Model
    keys : iterable of str

    Returns
    -------
    dict of str to str
    """
    import dataclasses

    from ..model.coordinates import coordinate_names
    from ..model.paths import get_value, parse_path

    roles = {"x": "m", "y": "m", "angle": "rad", "slide": "m", "mode": "m", "axial": "m"}
    states = {}
    try:
        for coord in coordinate_names(model):
            unit = roles.get(coord.role)
            if unit:
                states[coord.q], states[coord.u] = unit, f"{unit}/s"
    except Exception:  # noqa: BLE001 - a label is not worth a failure
        pass
    from ..model import schema

    uses = {}   # parameter name -> unit of a field whose value is exactly that name
    for declared in schema.TABLES.values():
        parts = getattr(model, declared.name, None)
        if not declared.named or not isinstance(parts, dict):
            continue
        for field in declared.of(model.dimensions):
            for name, part in parts.items():
                unit = field.unit_for(model.dimensions, getattr(part, "type", None))
                try:
                    value = get_value(model, f"{declared.name}.{name}.{field.key}") if unit else None
                except Exception:  # noqa: BLE001
                    continue
                if isinstance(value, str):
                    uses.setdefault(value.strip(), unit)
    if model.gravity is not None and isinstance(model.gravity.g, str):
        uses.setdefault(model.gravity.g.strip(), schema.GRAVITY.field("g").unit_in(model.dimensions))
    fields = {f.name for f in dataclasses.fields(model)}
    units = {f"final_{name}": unit for name, unit in states.items()}
    for key in keys:
        try:
            parts = parse_path(key)
        except Exception:  # noqa: BLE001
            continue
        unit = None
        if parts[0] == "initial" and len(parts) == 2:
            unit = states.get(parts[1])
        elif parts[0] == "parameters" and len(parts) == 2:
            unit = uses.get(parts[1])
        elif len(parts) == 1 and parts[0] not in fields:
            unit = uses.get(parts[0]) if parts[0] in model.parameters else states.get(parts[0])
        else:
            unit = _field_unit(model, parts)
        if unit:
            units[key] = unit
    return units


def _label(column: str, units: dict | None = None) -> str:
    """Axis label of a table column, with its unit where the column has one."""
    if units and column in units:
        return f"{column} [{units[column]}]"
    if column.startswith("max_abs_tip_"):
        return f"{column} [m]"
    if column in ("t_reached", "wall_time", "run_time"):
        return f"{column} [s]"
    if column in ("energy_error", "nsteps", "nfev"):
        return f"{column} [-]"
    return column


def _number(value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return math.nan
    return float(value)


def _log_axis(values: list[float]) -> bool:
    """Positive values spanning more than a factor 20 read better on a log axis."""
    finite = [v for v in values if math.isfinite(v)]
    return bool(finite) and min(finite) > 0 and max(finite) / min(finite) > 20


def plot_metric(rows: list[dict], metric: str, keys: list[str], path, units: dict | None = None) -> Path:
    """Plot ``metric`` of the successful variants against one or two varied keys; write a PNG.

    With one key, one line per combination of the other varied keys (at most 12, else points).
    With two keys, a colour map when the variants fill a grid, else coloured points.

    Parameters
    ----------
    rows : list of dict
        The sweep table (:func:`flexkane.sweep.read_table` with ``as_rows=True``).
    metric : str
        A numeric column, e.g. ``max_abs_tip_B`` [m] or ``energy_error`` [-].
    keys : list of str
        One or two varied keys for the axes.
    path : str or os.PathLike
        The PNG file to write (atomically).
    units : dict of str to str, optional
        Units of the keys and columns (:func:`column_units`), shown on the axes.

    Returns
    -------
    pathlib.Path
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..atomic import atomic_writer

    if not 1 <= len(keys) <= 2:
        raise ModelError("keys", "one or two varied keys to plot against", keys)
    columns = set().union(*(row.keys() for row in rows)) if rows else set()
    for key in keys:
        if key not in columns:
            raise ModelError("keys", f"a varied key ({', '.join(c for c in columns if '.' in c) or 'none'})",
                             key)
    if metric not in columns:
        numeric = sorted(c for c in columns if any(isinstance(r.get(c), float) for r in rows))
        raise ModelError("metric", f"a numeric column of the table ({', '.join(numeric)})", metric)
    ok = [r for r in rows if r.get("status") == "ok" and math.isfinite(_number(r.get(metric)))]
    if not ok:
        raise ModelError("metric", "a column with values for at least one successful variant", metric)
    figure, axes = plt.subplots(figsize=(6.4, 4.4), layout="constrained")
    x = [_number(r[keys[0]]) for r in ok]
    z = [_number(r[metric]) for r in ok]
    if len(keys) == 1:
        others = [k for k in ok[0] if k not in keys and k in _varied(rows, keys)]
        series: dict = {}
        for row, xi, zi in zip(ok, x, z):
            series.setdefault(tuple(row.get(k) for k in others), []).append((xi, zi))
        for label, points in sorted(series.items(), key=lambda item: str(item[0])):
            points.sort()
            style = "o-" if len(series) <= 12 else "o"
            text = ", ".join(f"{k}={v}" for k, v in zip(others, label)) if others and len(series) <= 12 else None
            axes.plot([p[0] for p in points], [p[1] for p in points], style, ms=4, label=text)
        if others and len(series) <= 12:
            axes.legend(fontsize="small")
        axes.set_ylabel(_label(metric, units))
        if _log_axis(z):
            axes.set_yscale("log")
    else:
        y = [_number(r[keys[1]]) for r in ok]
        xs, ys = sorted(set(x)), sorted(set(y))
        if len(xs) * len(ys) == len(ok) and len(xs) > 1 and len(ys) > 1:
            import numpy as np

            grid = np.full((len(ys), len(xs)), np.nan)
            for xi, yi, zi in zip(x, y, z):
                grid[ys.index(yi), xs.index(xi)] = zi
            mesh = axes.pcolormesh(xs, ys, grid, shading="nearest")
        else:
            mesh = axes.scatter(x, y, c=z, s=25)
        figure.colorbar(mesh, ax=axes, label=_label(metric, units))
        axes.set_ylabel(_label(keys[1], units))
        if _log_axis(y):
            axes.set_yscale("log")
    axes.set_xlabel(_label(keys[0], units))
    if _log_axis(x):
        axes.set_xscale("log")
    failed = sum(r.get("status") == "failed" for r in rows)
    axes.set_title(f"{metric}: {len(ok)} variants" + (f" ({failed} failed, not shown)" if failed else ""),
                   fontsize="medium")
    path = Path(path)
    with atomic_writer(path, "wb") as handle:
        figure.savefig(handle, format="png", dpi=120)
    plt.close(figure)
    return path


def _varied(rows: list[dict], exclude: list[str]) -> set[str]:
    """Columns named like key paths or parameters that take more than one value."""
    from .store import FIXED_COLUMNS

    fixed = {"variant", "index", "status", "error", *FIXED_COLUMNS}
    names = set()
    for name in rows[0]:
        if name in fixed or name in exclude or name.startswith(("max_abs_", "final_")):
            continue
        if len({repr(r.get(name)) for r in rows}) > 1:
            names.add(name)
    return names
