"""The sweep's columnar tables (pyarrow, Parquet): ``results.parquet`` and ``allocations.parquet``.

``results.parquet`` has one row per unit, in the order of the plan (cell, seed, subject, mode):

- ``unit`` (the unit's id), ``cell`` (its index in the design);
- ``param.<name>`` for a zip: its level's name (a string);
- ``param.<key>`` for every axis (float, integer, bool or string; a vector field as a list of floats);
- ``subject``, ``seed``, ``mode``, ``status`` (``complete``, ``abandoned`` or ``failed``), ``error``;
- the metrics of :func:`~ergosim.sweep.metrics.metric_columns`: ``robot_share`` and ``robot_share.<a>``,
  ``kwear_integral`` [s], ``time_above_vth`` [s], ``kwear_mean``, ``takt_overruns``, ``duration`` [s],
  ``robot_failures``, ``worker_failures``, ... and ``rula_g.<a>``; null where the unit failed.

A unit not finished yet has no row. ``allocations.parquet`` has one row per attempt of every finished unit
(``unit``, ``cell``, ``subject``, ``seed``, ``mode`` and the attempt's columns of ``allocations.csv``), and
``failures.parquet`` one row per failed attempt or abandoned repetition with its message (``time``,
``repetition``, ``action``, ``agent``, ``status`` such as ``failed:unreachable``, and ``message``, the
failure in words, as ``failures.csv``): a run output with a ``unit_table``
(:data:`~ergosim.experiment.outputs.OUTPUTS`) becomes ``<name>.parquet`` through :func:`unit_rows_table`.
All are written atomically; the same finished units give the same rows whichever executor ran them.
"""

from __future__ import annotations

import io
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import pyarrow as pa
import pyarrow.parquet as pq

from ergosim.atomic import write_bytes
from ergosim.experiment.outputs import Output
from ergosim.sweep.metrics import is_integer_metric, metric_columns
from ergosim.sweep.units import Unit

__all__ = ["results_table", "unit_rows_table", "param_type", "param_value", "write_parquet", "read_parquet",
           "RESULT_KEYS"]

RESULT_KEYS = ("unit", "cell", "subject", "seed", "mode", "status", "error")


def param_type(values: Sequence[Any]) -> pa.DataType:
    """The column type of an axis with ``values``."""
    if all(isinstance(v, bool) for v in values):
        return pa.bool_()
    if all(isinstance(v, int) and not isinstance(v, bool) for v in values):
        return pa.int64()
    if all(isinstance(v, int | float) and not isinstance(v, bool) for v in values):
        return pa.float64()
    if all(isinstance(v, tuple) and all(isinstance(x, int | float) for x in v) for v in values):
        return pa.list_(pa.float64())
    return pa.string()


def param_value(value: Any, kind: pa.DataType) -> Any:
    if kind == pa.string():
        from ergosim.sweep.design import set_string  # noqa: PLC0415

        return value if isinstance(value, str) else set_string(value, "param")
    if kind == pa.float64():
        return float(value)
    if kind == pa.list_(pa.float64()):
        return [float(x) for x in value]
    return value


def results_table(sweep, units: Sequence[Unit], docs: Mapping[str, dict]) -> pa.Table:
    """One row per unit of ``units`` that has a document in ``docs``, in ``units`` order."""
    cols = metric_columns(sweep.actions)
    params = [(a.column, a.key, param_type(a.values)) for a in sweep.axes]
    zips = [f for f in sweep.factors if f.block == "zip"]
    fields = [pa.field("unit", pa.string()), pa.field("cell", pa.int32())]
    fields += [pa.field(f.column, pa.string()) for f in zips]
    fields += [pa.field(col, kind) for col, _, kind in params]
    fields += [pa.field("subject", pa.int32()), pa.field("seed", pa.int64()), pa.field("mode", pa.string()),
               pa.field("status", pa.string()), pa.field("error", pa.string())]
    fields += [pa.field(c, pa.int64() if is_integer_metric(c) else pa.float64()) for c in cols]
    data: dict[str, list] = {f.name: [] for f in fields}
    for u in units:
        doc = docs.get(u.id)
        if doc is None:
            continue
        cell = sweep.cells[u.cell]
        data["unit"].append(u.id)
        data["cell"].append(u.cell)
        for f in zips:
            data[f.column].append(cell.levels[f.name])
        for col, key, kind in params:
            data[col].append(param_value(cell.params[key], kind))
        for key in ("subject", "seed", "mode", "status", "error"):
            data[key].append(getattr(u, key) if key in ("subject", "seed", "mode") else doc.get(key, ""))
        metrics = doc.get("metrics") or {}
        for c in cols:
            data[c].append(metrics.get(c))
    return pa.table(data, schema=pa.schema(fields))


def unit_rows_table(output: Output, units: Sequence[Unit], docs: Mapping[str, dict]) -> pa.Table:
    """``<output>.parquet``: the unit's own columns, then the rows of ``output`` each finished unit kept
    (:attr:`~ergosim.experiment.outputs.Output.unit_table`), in ``units`` order, then each unit's order."""
    columns = output.unit_table.columns
    fields = [pa.field("unit", pa.string()), pa.field("cell", pa.int32()), pa.field("subject", pa.int32()),
              pa.field("seed", pa.int64()), pa.field("mode", pa.string())]
    fields += [pa.field(name, pa.type_for_alias(kind)) for name, kind in columns]
    data: dict[str, list] = {f.name: [] for f in fields}
    for u in units:
        doc = docs.get(u.id)
        for row in (doc or {}).get(output.name, []):
            for key in ("unit", "cell", "subject", "seed", "mode"):
                data[key].append(u.id if key == "unit" else getattr(u, key))
            for (name, _), v in zip(columns, row, strict=True):
                data[name].append(v)
    return pa.table(data, schema=pa.schema(fields))


def write_parquet(path: Path, table: pa.Table) -> None:
    """``table`` as a Parquet file at ``path``, atomically."""
    buf = io.BytesIO()
    pq.write_table(table, buf, compression="zstd")
    write_bytes(path, buf.getvalue())


def read_parquet(path: Path) -> pa.Table:
    return pq.read_table(path)
