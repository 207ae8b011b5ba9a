"""The values of a sweep file (:mod:`ergosim.sweep.design`): each ``[set]``/``[grid]`` value as ``--set``
takes it, and the top-level keys (``scenario``, ``subjects``, ``seeds``, ``modes``, ``metrics``) read and
checked with one-line errors naming the key."""

from __future__ import annotations

import collections
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ergosim.errors import ConfigError
from ergosim.experiment.scenario import scenario_names
from ergosim.scenes.cellfile import MAX_FILE_BYTES
from ergosim.sweep.metrics import check_metric

__all__ = ["set_string", "MAX_UNITS", "check_key", "flat_keys", "read_metrics", "read_modes", "read_seeds",
           "read_string", "read_subjects", "read_table", "scenario_reference", "typed_value"]

MAX_UNITS = 500_000
"""Largest number of work units (cells × subjects × seeds × modes); each leaves one small file."""
_RESERVED = {"subjects": "the sweep's top-level 'subjects'", "protocol.subjects": "the sweep's 'subjects'",
             "modes": "the sweep's top-level 'modes'", "protocol.modes": "the sweep's 'modes'",
             "seed": "the sweep's top-level 'seeds'"}


# -- values ----------------------------------------------------------------------------------------------
def set_string(value: Any, where: str) -> str:
    """A TOML value as the ``--set`` string ``ergosim run`` would take: numbers, booleans, strings,
    vectors (``[0.2, 0.8]`` -> ``0.2,0.8``) and name:value pairs (``[["upper_arm", 1.1]]``)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | float):
        return _number(value, where)
    if isinstance(value, str):
        return value
    if isinstance(value, list | tuple) and value:
        if all(isinstance(v, list | tuple) and len(v) == 2 and isinstance(v[0], str) for v in value):
            return ",".join(f"{n}:{_number(x, where)}" for n, x in value)
        if all(isinstance(v, int | float) and not isinstance(v, bool) for v in value):
            return ",".join(_number(v, where) for v in value)
    raise ConfigError(f"expected a number, a boolean, a string or a list of numbers, got {value!r}",
                      where=where)


def _number(value: Any, where: str) -> str:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ConfigError(f"expected a number, got {value!r}", where=where)
    if isinstance(value, float) and not math.isfinite(value):
        raise ConfigError(f"expected a finite number, got {value!r}", where=where)
    return str(value) if isinstance(value, int) else repr(float(value))


def typed_value(value: Any) -> Any:
    """A parameter value as stored: lists become tuples (vectors or name:value pairs)."""
    if isinstance(value, list):
        return tuple(tuple(v) if isinstance(v, list) else v for v in value)
    return value


def read_string(value: Any, where: str) -> str:
    if not isinstance(value, str) or not value.strip():
        raise ConfigError(f"expected a non-empty string, got {value!r}", where=where)
    return value


def read_table(doc: Mapping[str, Any], key: str, source: str) -> dict[str, Any]:
    table = doc.get(key, {})
    if not isinstance(table, dict):
        raise ConfigError(f"expected a table [{key}], got {table!r}", where=f"{source}: {key}")
    return table


def flat_keys(table: Mapping[str, Any], where: str, prefix: str = "") -> dict[str, Any]:
    """``{"scene": {"shelf_height": x}}`` (TOML's dotted keys) -> ``{"scene.shelf_height": x}``."""
    out: dict[str, Any] = {}
    for key, value in table.items():
        full = f"{prefix}{key}"
        if isinstance(value, dict):
            if not value:
                raise ConfigError(f"{full!r} is an empty table; expected values", where=where)
            out.update(flat_keys(value, where, prefix=f"{full}."))
        else:
            out[full] = value
    return out


def check_key(key: str, where: str) -> None:
    if key in _RESERVED:
        raise ConfigError(f"{key!r} cannot be set per cell; use {_RESERVED[key]}", where=where)
    if key in ("scene", "workcell", "task") or key.startswith("task."):
        raise ConfigError(f"{key!r} is set by the scenario file, not by an override; use scene.<field>",
                          where=where)


def scenario_reference(value: Any, base_dir: Path | None, where: str) -> str:
    ref = read_string(value, where)
    if ref in scenario_names():
        return ref
    path = Path(ref)
    if not path.is_absolute() and base_dir is not None:
        path = base_dir / path
    if not path.is_file():
        raise ConfigError(f"no scenario {ref!r}: neither a bundled scenario ({', '.join(scenario_names())}) "
                          f"nor a file", where=where)
    if path.stat().st_size > MAX_FILE_BYTES:
        raise ConfigError(f"larger than {MAX_FILE_BYTES // 1024 // 1024} MiB; not a scenario file",
                          where=where)
    return str(path)


def read_subjects(value: Any, where: str) -> tuple[int, ...]:
    if isinstance(value, bool):
        raise ConfigError(f"expected a count, 'A:B' or a list of subject indices, got {value!r}", where=where)
    if isinstance(value, int):
        if value < 1:
            raise ConfigError(f"expected at least 1 subject, got {value}", where=where)
        _at_most(value, "subjects", where)
        return tuple(range(value))
    if isinstance(value, str):
        first, sep, end = value.partition(":")
        try:
            a, b = int(first), int(end)
        except ValueError:
            a = b = -1
        if not sep or not 0 <= a < b:
            raise ConfigError(f"expected 'A:B' with 0 <= A < B (subjects A..B-1), got {value!r}", where=where)
        _at_most(b - a, "subjects", where)
        return tuple(range(a, b))
    return _indices(value, "subject index", where)


def _at_most(count: int, what: str, where: str) -> None:
    """A count of subjects or seeds cannot exceed the units a sweep may hold (checked before a list of
    that length is made)."""
    if count > MAX_UNITS:
        raise ConfigError(f"{count} {what} are more units than the limit of {MAX_UNITS} (MAX_UNITS)",
                          where=where)


def read_seeds(value: Any, where: str) -> tuple[int, ...]:
    if isinstance(value, int) and not isinstance(value, bool):
        value = [value]
    return _indices(value, "seed", where)


def _indices(value: Any, what: str, where: str) -> tuple[int, ...]:
    if not isinstance(value, list) or not value:
        raise ConfigError(f"expected a non-empty list of {what}s, got {value!r}", where=where)
    _at_most(len(value), f"{what}s", where)
    for v in value:
        if isinstance(v, bool) or not isinstance(v, int) or v < 0:
            raise ConfigError(f"expected {what}s as integers >= 0, got {v!r}", where=where)
    dupes = sorted(v for v, k in collections.Counter(value).items() if k > 1)
    if dupes:
        raise ConfigError(f"{what} {dupes[0]} is listed twice", where=where)
    return tuple(value)


def read_modes(value: Any, where: str) -> tuple[str, ...]:
    from ergosim.twin.modes import mode_names  # noqa: PLC0415

    if not isinstance(value, list) or not value or not all(isinstance(m, str) for m in value):
        raise ConfigError(f"expected a non-empty list of modes such as [\"hrc\"], got {value!r}", where=where)
    for m in value:
        if m not in mode_names():
            raise ConfigError(f"unknown mode {m!r}; valid modes: {', '.join(mode_names())}", where=where)
    if len(set(value)) != len(value):
        raise ConfigError(f"a mode is listed twice: {value}", where=where)
    return tuple(value)


def read_metrics(value: Any, actions: Sequence[str], where: str) -> tuple[str, ...]:
    if not isinstance(value, list) or not value or not all(isinstance(m, str) for m in value):
        raise ConfigError(f"expected a non-empty list of metric names, got {value!r}", where=where)
    return tuple(dict.fromkeys(check_metric(m, actions, where) for m in value))
