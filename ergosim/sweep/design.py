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

    [zip]                                  # values taken together, position by position: one factor
    name = "layout"                        # the factor's name (default: its keys joined by "+")
    levels = ["A", "B"]                    # its levels' names (default: the values joined by " / ")
    "scene.l_xy" = [[0.20, 0.82], [0.24, 0.86]]
    "scene.s1_xy" = [[0.30, 0.90], [0.34, 0.94]]

    [sample]                               # a random or Latin-hypercube design over ranges
    method = "lhs"                         # "random" or "lhs"
    n = 8
    seed = 7
    takt = [34.0, 42.0]                    # [low, high]; integer bounds draw integers
    "scene.j_xy" = [[0.10, 0.70], [0.20, 0.80]]   # vector fields: [low vector, high vector]

Any ``--set`` key is an axis, in any one block. The cells are the product of the blocks present, grid
(first key slowest) × zip × sample; no axis gives one cell. The tables, plots and ``ergosim compare`` vary
*factors*: each grid or sample axis is one, and the whole zip is one, with named levels. Values are
written as ``--set`` strings (a
vector as ``0.2,0.82``), so a sweep cell is exactly ``ergosim run SCENARIO --set ...``. Every cell is
resolved against the base scenario when the file is read: a bad file or a bad cell is one
:class:`~ergosim.errors.ConfigError` naming the file, the entry and the value, before any simulation.
"""

from __future__ import annotations

import collections
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
from ergosim.experiment.scenario import Scenario, load_scenario
from ergosim.scenes.cellfile import read_toml
from ergosim.schema.document import check_table, table
from ergosim.schema.values import RAW
from ergosim.sweep.file_values import (
    MAX_UNITS,
    check_key,
    flat_keys,
    read_metrics,
    read_modes,
    read_seeds,
    read_string,
    read_subjects,
    read_table,
    scenario_reference,
    set_string,
    typed_value,
)
from ergosim.sweep.metrics import DEFAULT_METRICS

__all__ = ["Axis", "Factor", "Cell", "Sampling", "Sweep", "load_sweep", "parse_sweep", "set_string",
           "MAX_CELLS",
           "MAX_UNITS", "SAMPLE_METHODS"]

MAX_CELLS = 10_000
"""Largest number of cells in a sweep (assumed: a design larger than this is a typo in a range)."""
SAMPLE_METHODS = ("random", "lhs")

SweepTable = table("SweepTable", **dict.fromkeys(("name", "description", "scenario", "subjects", "seeds",
                                                 "modes", "metrics", "set", "grid", "zip", "sample"), RAW))
"""The top level of a sweep file (docs/sweeps.md); each key is read by its own reader below."""
_SAMPLE_KEYS = ("method", "n", "seed")
_ZIP_KEYS = ("name", "levels")


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
class Factor:
    """What the design varies, as the tables, plots and ``compare`` show it: a [grid] or [sample] axis (one
    key, its levels the values' ``--set`` strings), or the whole [zip] block (its keys move together, its
    levels named by ``levels``)."""

    name: str
    block: str
    keys: tuple[str, ...]
    levels: tuple[str, ...]

    @property
    def column(self) -> str:
        return f"param.{self.name}"


@dataclasses.dataclass(frozen=True)
class Cell:
    """One point of the design: its axis values (``params``), their ``--set`` strings and the level of
    each factor (``levels``: factor name -> level name)."""

    index: int
    params: Mapping[str, Any]
    overrides: Mapping[str, str]
    levels: Mapping[str, str] = dataclasses.field(default_factory=dict)

    def label(self) -> str:
        """``layout=B, takt=45.0``: each factor's level."""
        return ", ".join(f"{k}={v}" for k, v in self.levels.items()) or "base"

    def settings(self) -> str:
        """The label, with the ``--set`` values behind a zip's level: ``layout=B (scene.l_xy=0.24,0.86,
        scene.s1_xy=0.34,0.94)``."""
        if set(self.levels) == set(self.overrides):
            return self.label()
        return f"{self.label()} ({', '.join(f'{k}={v}' for k, v in self.overrides.items())})"


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
    factors: tuple[Factor, ...]
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
    check_table(SweepTable, doc, source, top=True)
    if "scenario" not in doc:
        raise ConfigError("missing key 'scenario' (a bundled scenario or a scenario file)", where=source)
    name = read_string(doc.get("name", default_name), at("name"))
    description = read_string(doc.get("description", "-"), at("description"))
    scenario_ref = scenario_reference(doc["scenario"], base_dir, at("scenario"))
    fixed_doc = flat_keys(read_table(doc, "set", source), at("set"))
    fixed = {k: set_string(v, at(f"set.{k}")) for k, v in fixed_doc.items()}
    for key in fixed:
        check_key(key, at(f"set.{key}"))
    axes, blocks = _axes(doc, source)
    for key in fixed:
        if key in {a.key for a in axes}:
            raise ConfigError(f"{key!r} is both fixed in [set] and an axis; give it once",
                              where=at(f"set.{key}"))
    factors = _factors(blocks, source)
    _check_size(blocks, source)
    subjects = read_subjects(doc.get("subjects", 1), at("subjects"))
    seeds = read_seeds(doc.get("seeds", 0), at("seeds"))
    try:
        base = load_scenario(scenario_ref, fixed)
    except ErgosimError as err:
        raise ConfigError(f"scenario {scenario_ref!r} with [set]: {err}",
                          where=at("set" if fixed else "scenario")) from None
    base_modes = tuple(base.protocol.modes)
    modes = read_modes(doc.get("modes", list(base_modes)), at("modes"))
    extra = [m for m in modes if m not in base_modes]
    slots = {m: base_modes.index(m) if m in base_modes else len(base_modes) + extra.index(m) for m in modes}
    actions = tuple(base.task().actions)
    metrics = read_metrics(doc.get("metrics", list(DEFAULT_METRICS)), actions, at("metrics"))
    points, seen = [], set()
    for p, levels in _product(blocks, factors):  # coinciding sample points (integer ranges): one cell
        key = json.dumps(p, sort_keys=True)
        if key not in seen:
            seen.add(key)
            points.append((p, levels))
    cells = tuple(Cell(i, params, {k: set_string(v, source) for k, v in params.items()}, levels)
                  for i, (params, levels) in enumerate(points))
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
            raise ConfigError(f"cell {cell.index} ({cell.settings()}): {err.what}",
                              where=at(_block_of(cell, axes))) from None
    sampling = blocks[-1][2] if blocks and blocks[-1][0] == "sample" else None
    return Sweep(name=name, source=source, description=description, scenario=scenario_ref, fixed=fixed,
                 axes=axes, factors=factors, cells=cells, subjects=subjects, seeds=seeds, modes=modes,
                 metrics=metrics,
                 actions=actions, slots=slots, sampling=sampling, base=base, scenarios=tuple(scenarios))


# -- the design ------------------------------------------------------------------------------------------
def _axes(doc: Mapping[str, Any], source: str) -> tuple[tuple[Axis, ...], list]:
    """The axes and the blocks ``(kind, [(key, values)...], sampling)`` in product order."""
    seen: dict[str, str] = {}
    blocks = []

    def claim(key: str, block: str) -> None:
        where = f"{source}: {block}.{key}"
        check_key(key, where)
        if key in seen:
            raise ConfigError(f"{key!r} is an axis in both [{seen[key]}] and [{block}]; give it once",
                              where=where)
        seen[key] = block

    def listed(block: str, table: Mapping[str, Any]) -> list[tuple[str, list[Any]]]:
        """The (key, values) of a [grid] or [zip] table, each key claimed."""
        entries = []
        for key, values in flat_keys(table, f"{source}: {block}").items():
            claim(key, block)
            entries.append((key, _values(values, f"{source}: {block}.{key}")))
        return entries

    entries = listed("grid", read_table(doc, "grid", source))
    if entries:
        blocks.append(("grid", entries, None))
    table = dict(read_table(doc, "zip", source))
    named = {k: table.pop(k) for k in _ZIP_KEYS if k in table}
    entries = listed("zip", table)
    if named and not entries:
        raise ConfigError("a [zip] with a name or levels needs its keys and their lists",
                          where=f"{source}: zip")
    if entries:
        lengths = {len(v) for _, v in entries}
        if len(lengths) > 1:
            counts = ", ".join(f"{k} {len(v)}" for k, v in entries)
            raise ConfigError(f"the lists of a zip must have one length; got {counts}",
                              where=f"{source}: zip")
        blocks.append(("zip", entries, _zip_names(named, entries, source)))
    sample = read_table(doc, "sample", source)
    if sample:
        blocks.append(_sample(sample, source, claim))
    axes = []
    for kind, entries, _ in blocks:
        for key, values in entries:
            axes.append(Axis(key, kind, tuple(dict.fromkeys(typed_value(v) for v in values))))
    return tuple(axes), blocks


def _values(values: Any, where: str) -> list[Any]:
    if not isinstance(values, list) or not values:
        raise ConfigError(f"expected a non-empty list of values, got {values!r}", where=where)
    if len(values) > MAX_CELLS:
        raise ConfigError(f"{len(values)} values are more cells than the limit of {MAX_CELLS} (MAX_CELLS)",
                          where=where)
    for v in values:
        set_string(v, where)
    typed = [typed_value(v) for v in values]
    dupes = [v for v, k in collections.Counter(typed).items() if k > 1]
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
    if n > MAX_CELLS:
        raise ConfigError(f"{n} samples are more cells than the limit of {MAX_CELLS} (MAX_CELLS)",
                          where=f"{where}.n")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ConfigError(f"expected seed as an integer >= 0 (the design is random), got {seed!r}",
                          where=f"{where}.seed")
    ranges = flat_keys({k: v for k, v in table.items() if k not in _SAMPLE_KEYS}, where)
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


def _zip_names(named: Mapping[str, Any], entries: Sequence[tuple[str, list]], source: str
               ) -> tuple[str, tuple[str, ...]]:
    """(factor name, level names) of a [zip]: as given, or its keys joined by "+" and each position's
    values joined by " / "."""
    n = len(entries[0][1])
    name = named.get("name", "+".join(k for k, _ in entries))
    if not isinstance(name, str) or not name.strip():
        raise ConfigError(f"expected the zip's name as a non-empty string, got {name!r}",
                          where=f"{source}: zip.name")
    levels = named.get("levels")
    if levels is None:
        return name, tuple(" / ".join(set_string(v[i], source) for _, v in entries) for i in range(n))
    if not isinstance(levels, list) or not all(isinstance(x, str) and x.strip() for x in levels):
        raise ConfigError(f"expected levels as a list of non-empty strings, got {levels!r}",
                          where=f"{source}: zip.levels")
    if len(levels) != n:
        raise ConfigError(f"{len(levels)} level names for {n} positions of the zip",
                          where=f"{source}: zip.levels")
    if len(set(levels)) != len(levels):
        raise ConfigError(f"a level name is given twice: {levels}", where=f"{source}: zip.levels")
    return name, tuple(levels)


def _factors(blocks: list, source: str) -> tuple[Factor, ...]:
    """The design's factors: one per grid or sample axis, one for the zip."""
    out = []
    for kind, entries, extra in blocks:
        if kind == "zip":
            name, levels = extra
            keys = tuple(k for k, _ in entries)
            others = {k for b in blocks if b[0] != "zip" for k, _ in b[1]}
            if (name in keys and len(keys) > 1) or name in others:
                raise ConfigError(f"the zip's name {name!r} is also an axis key; give it another name",
                                  where=f"{source}: zip.name")
            out.append(Factor(name, kind, keys, levels))
        else:
            for key, values in entries:
                labels = tuple(dict.fromkeys(set_string(v, source) for v in values))
                out.append(Factor(key, kind, (key,), labels))
    return tuple(out)


def _check_size(blocks: list, source: str) -> None:
    """Refuse a design over MAX_CELLS from the blocks' sizes, before a cell is made."""
    size = 1
    for kind, entries, _ in blocks:
        size *= math.prod(len(v) for _, v in entries) if kind == "grid" else len(entries[0][1])
    if size > MAX_CELLS:
        raise ConfigError(f"the design has {size} cells, more than the limit of {MAX_CELLS} (MAX_CELLS)",
                          where=source)


def _product(blocks: list, factors: Sequence[Factor]) -> list[tuple[dict[str, Any], dict[str, str]]]:
    """(cell parameters, factor levels): the grid's full product (first key slowest) × the zip's rows ×
    the samples."""
    factors_rows: list[list[tuple[dict[str, Any], dict[str, str]]]] = []
    zip_factor = next((f for f in factors if f.block == "zip"), None)
    for kind, entries, _ in blocks:
        if kind == "grid":
            keys = [k for k, _ in entries]
            combos = itertools.product(*(v for _, v in entries))
            rows = [dict(zip(keys, combo, strict=True)) for combo in combos]
            factors_rows.append([(r, {k: set_string(v, "grid") for k, v in r.items()}) for r in rows])
        elif kind == "zip":
            n = len(entries[0][1])
            factors_rows.append([({k: v[i] for k, v in entries}, {zip_factor.name: zip_factor.levels[i]})
                                 for i in range(n)])
        else:
            n = len(entries[0][1])
            rows = [{k: v[i] for k, v in entries} for i in range(n)]
            factors_rows.append([(r, {k: set_string(v, "sample") for k, v in r.items()}) for r in rows])
    cells = []
    for combo in itertools.product(*factors_rows):
        params: dict[str, Any] = {}
        levels: dict[str, str] = {}
        for part, named in combo:
            params.update({k: typed_value(v) for k, v in part.items()})
            levels.update(named)
        cells.append((params, levels))
    return cells or [({}, {})]


def _block_of(cell: Cell, axes: Sequence[Axis]) -> str:
    blocks = list(dict.fromkeys(a.block for a in axes if a.key in cell.params))
    return "/".join(blocks) or "set"
