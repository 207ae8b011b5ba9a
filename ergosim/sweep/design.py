"""Sweep files (TOML): a base scenario, fixed overrides, the axes of a design, subjects, seeds, metrics.

::

    name = "shelf-height"                  # default: the file's name
    scenario = "kwear-validation"          # a bundled scenario, or a scenario file (relative to this file)
    subjects = 4                           # N (subjects 0..N-1), "A:B" (A..B-1), or a list [0, 3, 7]
    seeds = [0, 1]                         # an integer, or a list
    modes = ["hrc"]                        # default: the scenario's modes
    metrics = ["robot_share", "robot_share.a1", "kwear_integral"]

    [set]                                  # --set overrides of every cell
    repetitions = 2

    [grid]                                 # every combination of the values
    scene.shelf_height = [1.3, 1.45, 1.6]
    robot_cost = [25.0, 50.0]

    [zip]                                  # values taken together, position by position
    "scene.l_xy" = [[0.20, 0.82], [0.24, 0.86]]
    "scene.s1_xy" = [[0.30, 0.90], [0.34, 0.94]]

    [sample]                               # a random or Latin-hypercube design over ranges
    method = "lhs"                         # "random" or "lhs"
    n = 8
    seed = 7
    takt = [34.0, 42.0]                    # [low, high]; integer bounds draw integers
    "scene.j_xy" = [[0.10, 0.70], [0.20, 0.80]]   # vector fields: [low vector, high vector]

Any ``--set`` key is an axis, in any one block. The cells are the product of the blocks present, grid
(first key slowest) × zip × sample; no axis gives one cell. Values are written as ``--set`` strings (a
vector as ``0.2,0.82``), so a sweep cell is exactly ``ergosim run SCENARIO --set ...``. Every cell is
resolved against the base scenario when the file is read: a bad file or a bad cell is one
:class:`~ergosim.errors.ConfigError` naming the file, the entry and the value, before any simulation.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ergosim.errors import ConfigError, ErgosimError
from ergosim.experiment.scenario import Scenario, load_scenario, scenario_names
from ergosim.scenes.cellfile import MAX_FILE_BYTES, read_toml
from ergosim.sweep.metrics import DEFAULT_METRICS, check_metric

__all__ = ["Axis", "Cell", "Sampling", "Sweep", "load_sweep", "parse_sweep", "set_string", "MAX_CELLS",
           "MAX_UNITS", "SAMPLE_METHODS"]

MAX_CELLS = 10_000
"""Largest number of cells in a sweep (assumed: a design larger than this is a typo in a range)."""
MAX_UNITS = 500_000
"""Largest number of work units (cells × subjects × seeds × modes); each leaves one small file."""
SAMPLE_METHODS = ("random", "lhs")

_TOP = ("name", "description", "scenario", "subjects", "seeds", "modes", "metrics", "set", "grid", "zip",
        "sample")
_SAMPLE_KEYS = ("method", "n", "seed")
_RESERVED = {"subjects": "the sweep's top-level 'subjects'", "protocol.subjects": "the sweep's 'subjects'",
             "modes": "the sweep's top-level 'modes'", "protocol.modes": "the sweep's 'modes'",
             "seed": "the sweep's top-level 'seeds'"}


@dataclasses.dataclass(frozen=True)
class Axis:
    """One swept ``--set`` key, its block (``grid``, ``zip`` or ``sample``) and the values its cells take
    (TOML-typed: bool, int, float, str, or a tuple of floats for a vector field)."""

    key: str
    block: str
    values: tuple[Any, ...]

    @property
    def column(self) -> str:
        return f"param.{self.key}"


@dataclasses.dataclass(frozen=True)
class Cell:
    """One point of the design: its axis values (``params``) and their ``--set`` strings."""

    index: int
    params: Mapping[str, Any]
    overrides: Mapping[str, str]

    def label(self) -> str:
        return ", ".join(f"{k}={v}" for k, v in self.overrides.items()) or "base"


@dataclasses.dataclass(frozen=True)
class Sampling:
    method: str
    n: int
    seed: int


@dataclasses.dataclass(frozen=True)
class Sweep:
    """A checked sweep file. ``base``: the scenario with ``fixed`` applied; ``scenarios``: per cell, the
    base with the cell's overrides applied (resolved and checked); ``slots``: each mode's random stream
    (its position in the base scenario's modes, the sweep's other modes after them)."""

    name: str
    source: str
    description: str
    scenario: str
    fixed: Mapping[str, str]
    axes: tuple[Axis, ...]
    cells: tuple[Cell, ...]
    subjects: tuple[int, ...]
    seeds: tuple[int, ...]
    modes: tuple[str, ...]
    metrics: tuple[str, ...]
    actions: tuple[str, ...]
    slots: Mapping[str, int]
    sampling: Sampling | None
    base: Scenario = dataclasses.field(repr=False, compare=False)
    scenarios: tuple[Scenario, ...] = dataclasses.field(repr=False, compare=False)

    @property
    def n_units(self) -> int:
        return len(self.cells) * len(self.subjects) * len(self.seeds) * len(self.modes)


def load_sweep(path: str | os.PathLike[str]) -> Sweep:
    """Read and check the sweep file at ``path``."""
    path = Path(path)
    return parse_sweep(read_toml(path, what="sweep file"), source=str(path), base_dir=path.parent,
                       default_name=path.stem)


def parse_sweep(doc: Mapping[str, Any], *, source: str = "<sweep>", base_dir: Path | None = None,
                default_name: str = "sweep") -> Sweep:
    """Check a sweep document (the parsed TOML) and resolve every cell against its base scenario."""
    at = lambda entry: f"{source}: {entry}"  # noqa: E731
    unknown = sorted(set(doc) - set(_TOP))
    if unknown:
        raise ConfigError(f"unknown key {unknown[0]!r}; valid keys: {', '.join(_TOP)}", where=source)
    if "scenario" not in doc:
        raise ConfigError("missing key 'scenario' (a bundled scenario or a scenario file)", where=source)
    name = _string(doc.get("name", default_name), at("name"))
    description = _string(doc.get("description", "-"), at("description"))
    scenario_ref = _scenario_ref(doc["scenario"], base_dir, at("scenario"))
    fixed_doc = _flat(_table(doc, "set", source), at("set"))
    fixed = {k: set_string(v, at(f"set.{k}")) for k, v in fixed_doc.items()}
    for key in fixed:
        _check_key(key, at(f"set.{key}"))
    axes, blocks = _axes(doc, source)
    for key in fixed:
        if key in {a.key for a in axes}:
            raise ConfigError(f"{key!r} is both fixed in [set] and an axis; give it once",
                              where=at(f"set.{key}"))
    subjects = _subjects(doc.get("subjects", 1), at("subjects"))
    seeds = _seeds(doc.get("seeds", 0), at("seeds"))
    try:
        base = load_scenario(scenario_ref, fixed)
    except ErgosimError as err:
        raise ConfigError(f"scenario {scenario_ref!r} with [set]: {err}",
                          where=at("set" if fixed else "scenario")) from None
    base_modes = tuple(base.protocol.modes)
    modes = _modes(doc.get("modes", list(base_modes)), at("modes"))
    extra = [m for m in modes if m not in base_modes]
    slots = {m: base_modes.index(m) if m in base_modes else len(base_modes) + extra.index(m) for m in modes}
    actions = tuple(base.task().actions)
    metrics = _metrics(doc.get("metrics", list(DEFAULT_METRICS)), actions, at("metrics"))
    points, seen = [], set()
    for p in _product(blocks):  # sample points that coincide (integer ranges) are one cell, the first kept
        key = json.dumps(p, sort_keys=True)
        if key not in seen:
            seen.add(key)
            points.append(p)
    cells = tuple(Cell(i, params, {k: set_string(v, source) for k, v in params.items()})
                  for i, params in enumerate(points))
    if len(cells) > MAX_CELLS:
        raise ConfigError(f"the design has {len(cells)} cells, more than the limit of {MAX_CELLS} "
                          "(MAX_CELLS)", where=source)
    n_units = len(cells) * len(subjects) * len(seeds) * len(modes)
    if n_units > MAX_UNITS:
        raise ConfigError(f"the sweep has {n_units} work units (cells × subjects × seeds × modes), more than "
                          f"the limit of {MAX_UNITS} (MAX_UNITS)", where=source)
    for axis in axes:  # each value alone first, so a bad key or value is named as the file has it
        for value in axis.values:
            text = set_string(value, source)
            try:
                base.with_overrides({axis.key: text})
            except ErgosimError as err:
                raise ConfigError(f"{axis.key}={text}: {err.what}", where=at(f"{axis.block}.{axis.key}")) \
                    from None
    scenarios = []
    for cell in cells:
        try:
            scenarios.append(base.with_overrides(dict(cell.overrides), where=at(f"cell {cell.index}")))
        except ErgosimError as err:
            raise ConfigError(f"cell {cell.index} ({cell.label()}): {err.what}",
                              where=at(_block_of(cell, axes))) from None
    sampling = blocks[-1][2] if blocks and blocks[-1][0] == "sample" else None
    return Sweep(name=name, source=source, description=description, scenario=scenario_ref, fixed=fixed,
                 axes=axes, cells=cells, subjects=subjects, seeds=seeds, modes=modes, metrics=metrics,
                 actions=actions, slots=slots, sampling=sampling, base=base, scenarios=tuple(scenarios))


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


def _typed(value: Any) -> Any:
    """A parameter value as stored: lists become tuples (vectors or name:value pairs)."""
    if isinstance(value, list):
        return tuple(tuple(v) if isinstance(v, list) else v for v in value)
    return value


def _string(value: Any, where: str) -> str:
    if not isinstance(value, str) or not value.strip():
        raise ConfigError(f"expected a non-empty string, got {value!r}", where=where)
    return value


def _table(doc: Mapping[str, Any], key: str, source: str) -> dict[str, Any]:
    table = doc.get(key, {})
    if not isinstance(table, dict):
        raise ConfigError(f"expected a table [{key}], got {table!r}", where=f"{source}: {key}")
    return table


def _flat(table: Mapping[str, Any], where: str, prefix: str = "") -> dict[str, Any]:
    """``{"scene": {"shelf_height": x}}`` (TOML's dotted keys) -> ``{"scene.shelf_height": x}``."""
    out: dict[str, Any] = {}
    for key, value in table.items():
        full = f"{prefix}{key}"
        if isinstance(value, dict):
            if not value:
                raise ConfigError(f"{full!r} is an empty table; expected values", where=where)
            out.update(_flat(value, where, prefix=f"{full}."))
        else:
            out[full] = value
    return out


def _check_key(key: str, where: str) -> None:
    if key in _RESERVED:
        raise ConfigError(f"{key!r} cannot be set per cell; use {_RESERVED[key]}", where=where)
    if key in ("scene", "workcell", "task") or key.startswith("task."):
        raise ConfigError(f"{key!r} is set by the scenario file, not by an override; use scene.<field>",
                          where=where)


def _scenario_ref(value: Any, base_dir: Path | None, where: str) -> str:
    ref = _string(value, where)
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


def _subjects(value: Any, where: str) -> tuple[int, ...]:
    if isinstance(value, bool):
        raise ConfigError(f"expected a count, 'A:B' or a list of subject indices, got {value!r}", where=where)
    if isinstance(value, int):
        if value < 1:
            raise ConfigError(f"expected at least 1 subject, got {value}", where=where)
        return tuple(range(value))
    if isinstance(value, str):
        first, sep, end = value.partition(":")
        try:
            a, b = int(first), int(end)
        except ValueError:
            a = b = -1
        if not sep or not 0 <= a < b:
            raise ConfigError(f"expected 'A:B' with 0 <= A < B (subjects A..B-1), got {value!r}", where=where)
        return tuple(range(a, b))
    return _indices(value, "subject index", where)


def _seeds(value: Any, where: str) -> tuple[int, ...]:
    if isinstance(value, int) and not isinstance(value, bool):
        value = [value]
    return _indices(value, "seed", where)


def _indices(value: Any, what: str, where: str) -> tuple[int, ...]:
    if not isinstance(value, list) or not value:
        raise ConfigError(f"expected a non-empty list of {what}s, got {value!r}", where=where)
    for v in value:
        if isinstance(v, bool) or not isinstance(v, int) or v < 0:
            raise ConfigError(f"expected {what}s as integers >= 0, got {v!r}", where=where)
    dupes = sorted({v for v in value if value.count(v) > 1})
    if dupes:
        raise ConfigError(f"{what} {dupes[0]} is listed twice", where=where)
    return tuple(value)


def _modes(value: Any, where: str) -> tuple[str, ...]:
    from ergosim.twin.modes import mode_names  # noqa: PLC0415

    if isinstance(value, str):
        value = [value]
    if not isinstance(value, list) or not value or not all(isinstance(m, str) for m in value):
        raise ConfigError(f"expected a non-empty list of modes, got {value!r}", where=where)
    for m in value:
        if m not in mode_names():
            raise ConfigError(f"unknown mode {m!r}; valid modes: {', '.join(mode_names())}", where=where)
    if len(set(value)) != len(value):
        raise ConfigError(f"a mode is listed twice: {value}", where=where)
    return tuple(value)


def _metrics(value: Any, actions: Sequence[str], where: str) -> tuple[str, ...]:
    if not isinstance(value, list) or not value or not all(isinstance(m, str) for m in value):
        raise ConfigError(f"expected a non-empty list of metric names, got {value!r}", where=where)
    return tuple(dict.fromkeys(check_metric(m, actions, where) for m in value))


# -- the design ------------------------------------------------------------------------------------------
def _axes(doc: Mapping[str, Any], source: str) -> tuple[tuple[Axis, ...], list]:
    """The axes and the blocks ``(kind, [(key, values)...], sampling)`` in product order."""
    seen: dict[str, str] = {}
    blocks = []

    def claim(key: str, block: str) -> None:
        where = f"{source}: {block}.{key}"
        _check_key(key, where)
        if key in seen:
            raise ConfigError(f"{key!r} is an axis in both [{seen[key]}] and [{block}]; give it once",
                              where=where)
        seen[key] = block

    def listed(block: str) -> list[tuple[str, list[Any]]]:
        """The (key, values) of a [grid] or [zip] table, each key claimed."""
        entries = []
        for key, values in _flat(_table(doc, block, source), f"{source}: {block}").items():
            claim(key, block)
            entries.append((key, _values(values, f"{source}: {block}.{key}")))
        return entries

    entries = listed("grid")
    if entries:
        blocks.append(("grid", entries, None))
    entries = listed("zip")
    if entries:
        lengths = {len(v) for _, v in entries}
        if len(lengths) > 1:
            counts = ", ".join(f"{k} {len(v)}" for k, v in entries)
            raise ConfigError(f"the lists of a zip must have one length; got {counts}",
                              where=f"{source}: zip")
        blocks.append(("zip", entries, None))
    sample = _table(doc, "sample", source)
    if sample:
        blocks.append(_sample(sample, source, claim))
    axes = []
    for kind, entries, _ in blocks:
        for key, values in entries:
            axes.append(Axis(key, kind, tuple(dict.fromkeys(_typed(v) for v in values))))
    return tuple(axes), blocks


def _values(values: Any, where: str) -> list[Any]:
    if not isinstance(values, list) or not values:
        raise ConfigError(f"expected a non-empty list of values, got {values!r}", where=where)
    for v in values:
        set_string(v, where)
    typed = [_typed(v) for v in values]
    dupes = [v for v in typed if typed.count(v) > 1]
    if dupes:
        raise ConfigError(f"value {dupes[0]!r} is listed twice", where=where)
    if all(isinstance(v, int | float) and not isinstance(v, bool) for v in values) and \
            any(isinstance(v, float) for v in values):
        return [float(v) for v in values]
    return values


def _sample(table: Mapping[str, Any], source: str, claim) -> tuple[str, list, Sampling]:
    where = f"{source}: sample"
    method = table.get("method", "lhs")
    if method not in SAMPLE_METHODS:
        raise ConfigError(f"method must be one of {', '.join(SAMPLE_METHODS)}, got {method!r}",
                          where=f"{where}.method")
    n, seed = table.get("n"), table.get("seed")
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ConfigError(f"expected n, the number of samples, as an integer >= 1, got {n!r}",
                          where=f"{where}.n")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ConfigError(f"expected seed as an integer >= 0 (the design is random), got {seed!r}",
                          where=f"{where}.seed")
    ranges = _flat({k: v for k, v in table.items() if k not in _SAMPLE_KEYS}, where)
    if not ranges:
        raise ConfigError("no ranges to sample; give KEY = [low, high]", where=where)
    bounds = []
    for key, value in ranges.items():
        claim(key, "sample")
        bounds.append((key, *_bounds(value, f"{where}.{key}")))
    dims = sum(len(lo) for _, lo, _, _ in bounds)
    rng = np.random.default_rng(seed)
    u = _lhs(rng, n, dims) if method == "lhs" else rng.random((n, dims))
    columns: list[tuple[str, list]] = []
    j = 0
    for key, lo, hi, integer in bounds:
        block = u[:, j:j + len(lo)]
        j += len(lo)
        if integer:
            vals = np.minimum(np.floor(lo + block * (hi - lo + 1)), hi).astype(int)
            cells = [[int(x) for x in row] for row in vals]
        else:
            cells = [[float(f"{x:.6g}") for x in lo + row * (hi - lo)] for row in block]
        columns.append((key, [c if len(lo) > 1 or _is_vector(ranges[key]) else c[0] for c in cells]))
    return "sample", columns, Sampling(method, n, seed)


def _is_vector(value: Any) -> bool:
    return isinstance(value, list) and len(value) == 2 and isinstance(value[0], list)


def _bounds(value: Any, where: str) -> tuple[np.ndarray, np.ndarray, bool]:
    """(low, high, integer) of ``[low, high]`` or ``[[low...], [high...]]``."""
    bad = ConfigError("expected [low, high] or, for a vector field, [[low, ...], [high, ...]], got "
                      f"{value!r}", where=where)
    if not isinstance(value, list) or len(value) != 2:
        raise bad
    lo, hi = ([v] if not isinstance(v, list) else v for v in value)
    if len(lo) != len(hi) or not lo or not all(isinstance(x, int | float) and not isinstance(x, bool)
                                                for x in (*lo, *hi)):
        raise bad
    if not all(math.isfinite(x) for x in (*lo, *hi)):
        raise ConfigError(f"expected finite bounds, got {value!r}", where=where)
    low, high = np.asarray(lo, float), np.asarray(hi, float)
    if np.any(low >= high):
        raise ConfigError(f"expected low < high, got {value!r}", where=where)
    integer = all(isinstance(x, int) for x in (*lo, *hi))
    return low, high, integer


def _lhs(rng: np.random.Generator, n: int, dims: int) -> np.ndarray:
    """(n, dims) Latin-hypercube sample of [0, 1)^dims: in every dimension one point per stratum
    [k/n, (k+1)/n) (McKay, Beckman & Conover 1979), strata in random order, uniform within a stratum."""
    u = np.empty((n, dims))
    for j in range(dims):
        u[:, j] = (rng.permutation(n) + rng.random(n)) / n
    return u


def _product(blocks: list) -> list[dict[str, Any]]:
    """Cell parameter dicts: the grid's full product (first key slowest) × the zip's rows × the samples."""
    factors: list[list[dict[str, Any]]] = []
    for kind, entries, _ in blocks:
        if kind == "grid":
            keys = [k for k, _ in entries]
            rows = [dict(zip(keys, combo, strict=True))
                    for combo in itertools.product(*(v for _, v in entries))]
        else:
            n = len(entries[0][1])
            rows = [{k: v[i] for k, v in entries} for i in range(n)]
        factors.append(rows)
    cells = []
    for combo in itertools.product(*factors):
        params: dict[str, Any] = {}
        for part in combo:
            params.update({k: _typed(v) for k, v in part.items()})
        cells.append(params)
    return cells or [{}]


def _block_of(cell: Cell, axes: Sequence[Axis]) -> str:
    blocks = list(dict.fromkeys(a.block for a in axes if a.key in cell.params))
    return "/".join(blocks) or "set"
