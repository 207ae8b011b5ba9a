"""Scenario files: read one, resolve its task and workcell, apply overrides, and register scenarios by name.

A :class:`Scenario` is everything a run needs, resolved and checked before any physics: the protocol
(:class:`~ergosim.experiment.protocol.ScenarioConfig`), the task's TOML text and the workcell document, with
the workcell overrides kept apart so each subject's workcell can add its own body to them. It is plain
data, so it travels to worker processes as it is.
"""

from __future__ import annotations

import dataclasses
import logging
import os
import tomllib
from collections.abc import Mapping
from importlib import resources
from pathlib import Path
from typing import Any

from ergosim.errors import ConfigError, TaskFileError
from ergosim.experiment.protocol import ScenarioConfig
from ergosim.overrides import apply_overrides, list_fields
from ergosim.planner import AndOrGraph, bundled_task_source, bundled_task_text, task_from_dict
from ergosim.planner.bundled import BUNDLED_TASKS
from ergosim.planner.task_overrides import apply_task_overrides
from ergosim.registry import Registry
from ergosim.scenes import CellSpec, apply_cell_overrides, cell_document, parse_cell
from ergosim.scenes.cellfile import override_paths, read_toml
from ergosim.schema.document import check_table, table
from ergosim.schema.values import RAW, TEXT, Text

__all__ = ["Scenario", "SCENARIOS", "register_scenario", "scenario_names", "scenario_path", "scenario_info",
           "load_scenario", "scenario_config", "split_overrides"]

log = logging.getLogger(__name__)

ScenarioTable = table("ScenarioTable", name=TEXT, description=Text(empty=True), task=RAW, workcell=RAW,
                      protocol=RAW)
"""The top level of a scenario file (docs/workcell_format.md); ``[protocol]`` is read by the protocol's
config dataclass (:func:`~ergosim.overrides.apply_overrides`), the task and the workcell by their readers."""
_TOP = tuple(ScenarioTable.model_fields)
_LABEL_FIELDS = ("scene", "task")
_LIST_FIELDS = list_fields(ScenarioConfig)

SCENARIOS: Registry[Path] = Registry("scenario", where="ergosim run", hint="or the path of a scenario file")
"""The scenario files by name."""


def register_scenario(name: str, path: str | os.PathLike[str]) -> None:
    """Make the scenario file at ``path`` runnable by ``name`` (``ergosim run NAME``, ``ergosim
    scenarios``)."""
    SCENARIOS.register(name, Path(path))


for _f in sorted(resources.files("ergosim").joinpath("data", "scenarios").iterdir(), key=lambda f: f.name):
    if _f.name.endswith(".toml"):
        register_scenario(_f.name.removesuffix(".toml"), Path(str(_f)))


def scenario_names() -> tuple[str, ...]:
    return SCENARIOS.names()


def scenario_path(name_or_path: str | os.PathLike[str]) -> Path:
    """The file of a registered scenario, or ``name_or_path`` itself when it is a file."""
    text = str(name_or_path)
    if text not in SCENARIOS and (text.endswith(".toml") or os.sep in text):
        return Path(text)
    return SCENARIOS.get(text)


def scenario_info(name: str) -> dict[str, Any]:
    """What ``ergosim scenarios`` shows of scenario ``name``, read from its file alone (nothing is built):
    name, description, task, workcell, subjects, repetitions, modes and the file's path."""
    path = scenario_path(name)
    doc = read_toml(path, what="scenario file")
    protocol = doc.get("protocol") if isinstance(doc.get("protocol"), dict) else {}
    modes = protocol.get("modes", ())
    return {"name": name, "description": str(doc.get("description", "")),
            "task": doc.get("task") if isinstance(doc.get("task"), str) else "(inline)",
            "workcell": doc.get("workcell") if isinstance(doc.get("workcell"), str) else "(inline)",
            "subjects": protocol.get("subjects"), "repetitions": protocol.get("repetitions"),
            "modes": [str(m) for m in modes] if isinstance(modes, list) else [str(modes)],
            "path": str(path)}


@dataclasses.dataclass(frozen=True)
class Scenario:
    """A resolved scenario. ``cell_overrides``: workcell overrides (dotted path or alias -> value, as the
    user gave them) on top of ``cell_doc`` for every subject; ``cell_resolved``: ``cell_doc`` with them
    applied, converted and checked once, when they were set (None without overrides). ``overrides``: every
    ``--set`` applied, as given (``run.json`` and the subject records keep them, and ``ergosim merge``
    refuses shards whose overrides differ)."""

    name: str
    source: str
    protocol: ScenarioConfig
    task_doc: Mapping[str, Any]
    task_source: str
    cell_doc: Mapping[str, Any]
    cell_source: str
    cell_overrides: Mapping[str, Any] = dataclasses.field(default_factory=dict)
    cell_resolved: Mapping[str, Any] | None = None
    overrides: Mapping[str, str] = dataclasses.field(default_factory=dict)

    def task(self) -> AndOrGraph:
        return task_from_dict(dict(self.task_doc), source=self.task_source)

    def cell(self, **extra: Any) -> CellSpec:
        """The workcell with the scenario's overrides and ``extra`` (typed fields by dotted path, e.g. a
        subject's body) where no override set the same field: the scenario's overrides win. Messages name the
        file with the overrides, e.g. ``multi-subject.toml (with scene.side_table_height=1.15)``, so a
        problem an override made says which one."""
        doc = self.cell_doc if self.cell_resolved is None else self.cell_resolved
        fixed = {p for key in self.cell_overrides for p in override_paths(self.cell_doc, key)}
        extra = {k: v for k, v in extra.items() if k not in fixed}
        if extra:
            doc = apply_cell_overrides(doc, extra, where=f"{self.cell_source} (overrides)")
        said = ", ".join(f"scene.{k}={_said(v)}" for k, v in self.cell_overrides.items())
        return parse_cell(doc, source=f"{self.cell_source} (with {said})" if said else self.cell_source)

    def with_overrides(self, overrides: Mapping[str, Any], where: str = "--set") -> Scenario:
        """A copy with any field overridden by its ``--set`` key (see :func:`split_overrides`): the task or
        the workcell swapped for another (``task=FILE``, ``workcell=NAME``), a field of the task
        (``task.agents.robot.cost=3``), of the workcell (``scene.parts.L.xy=0.2,0.8`` or an alias such as
        ``scene.l_xy``) or of the protocol (``takt=40``). Everything is checked now, before any physics."""
        groups = split_overrides(overrides)
        new = self
        base = Path.cwd()
        if "task" in groups["refs"]:
            doc, source, label = _resolve_task(groups["refs"]["task"], base, f"{where} task")
            new = dataclasses.replace(new, task_doc=doc, task_source=source,
                                      protocol=dataclasses.replace(new.protocol, task=label))
        if "workcell" in groups["refs"]:
            doc, source = _resolve_cell(groups["refs"]["workcell"], base, f"{where} workcell")
            label = parse_cell(doc, source).name
            new = dataclasses.replace(new, cell_doc=doc, cell_source=source,
                                      protocol=dataclasses.replace(new.protocol, scene=label))
        if groups["task"]:
            said = ", ".join(f"task.{k}={_said(v)}" for k, v in groups["task"].items())
            doc = apply_task_overrides(new.task_doc, groups["task"], where=f"{new.task_source} ({where})")
            new = dataclasses.replace(new, task_doc=doc, task_source=f"{new.task_source} (with {said})")
        own = groups["protocol"]
        protocol = apply_overrides(new.protocol, own, where=where) if own else new.protocol
        protocol.validate(where=where)
        given = {**dict(new.overrides), **{k: _said(v) for k, v in overrides.items()}}
        cell = {**dict(new.cell_overrides), **groups["cell"]}
        resolved = apply_cell_overrides(new.cell_doc, cell, where=f"{new.cell_source} (overrides)") \
            if cell else None
        new = dataclasses.replace(new, protocol=protocol, overrides=given, cell_overrides=cell,
                                  cell_resolved=resolved)
        if new is not self and (groups["cell"] or groups["task"] or groups["refs"] or own):
            from ergosim.experiment.scenario_check import check_scenario  # noqa: PLC0415

            check_scenario(new, new.task(), new.cell())  # a bad key or value fails now, before any physics
        return new


def _said(value: Any) -> str:
    """An override value as ``--set`` would spell it."""
    if isinstance(value, list | tuple):
        return ",".join(_said(v) for v in value)
    return str(value)


def split_overrides(overrides: Mapping[str, Any]) -> dict[str, dict[str, Any]]:
    """Overrides by ``--set`` key into groups: ``refs`` (``task=``, ``workcell=``: another task or workcell,
    by bundled name or file), ``task`` (``task.PATH``: a field of the task document), ``cell``
    (``scene.PATH`` or ``workcell.PATH``: a field of the workcell, or an alias), ``protocol`` (a bare key or
    ``protocol.KEY``)."""
    groups: dict[str, dict[str, Any]] = {"refs": {}, "task": {}, "cell": {}, "protocol": {}}
    for key, value in overrides.items():
        head, _, rest = key.partition(".")
        if head in ("scene", "workcell") and rest:
            groups["cell"][rest] = value
        elif head == "task" and rest:
            groups["task"][rest] = value
        elif head == "protocol" and rest:
            if rest in _LABEL_FIELDS:
                raise ConfigError(f"{key!r} is a label set from the scenario's task and workcell; set "
                                  "task=FILE or workcell=FILE to use others", where="--set")
            groups["protocol"][rest] = value
        elif key in ("task", "workcell"):
            groups["refs"][key] = value
        elif key == "scene":
            groups["refs"]["workcell"] = value
        else:
            groups["protocol"][key] = value
    return groups


def _resolve_task(value: Any, base: Path, where: str) -> tuple[dict[str, Any], str, str]:
    """(task document, its source for messages, its label) of a scenario's ``task`` entry."""
    if isinstance(value, dict):
        return value, f"{where}: task", str(value.get("name", "task"))
    if not isinstance(value, str) or not value:
        raise ConfigError(f"expected a bundled task, a task file or a [task] table, got {value!r}",
                          where=f"{where}: task")
    if value in BUNDLED_TASKS:
        source = bundled_task_source(value)
        doc = tomllib.loads(bundled_task_text(value))
        return doc, source, _task_name(doc, source)
    path = (base / value) if not Path(value).is_absolute() else Path(value)
    if not path.is_file():
        raise ConfigError(f"no such task file {str(path)!r} (nor a bundled task: {', '.join(BUNDLED_TASKS)})",
                          where=f"{where}: task")
    try:
        doc = read_toml(path, what="task file")
    except ConfigError as err:
        raise TaskFileError(err.what, where=err.where) from None
    return doc, str(path), _task_name(doc, str(path))


def _task_name(doc: Mapping[str, Any], source: str) -> str:
    """The task's label (``config.task``): its ``name``, as the task reader takes it (default: the file's
    stem)."""
    name = doc.get("name")
    return name if isinstance(name, str) and name else Path(source).stem


def _resolve_cell(value: Any, base: Path, where: str) -> tuple[dict[str, Any], str]:
    if isinstance(value, dict):
        return value, f"{where}: workcell"
    if not isinstance(value, str) or not value:
        raise ConfigError("expected a bundled workcell, a workcell file or a [workcell] table, got "
                          f"{value!r}", where=f"{where}: workcell")
    if value.endswith(".toml"):
        path = (base / value) if not Path(value).is_absolute() else Path(value)
        return cell_document(path)
    return cell_document(value)


def load_scenario(name_or_path: str | os.PathLike[str],
                  overrides: Mapping[str, Any] | None = None) -> Scenario:
    """Read, resolve and check a scenario (a registered name or a scenario file), with ``overrides``."""
    path = scenario_path(name_or_path)
    doc = read_toml(path, what="scenario file")
    bundled = str(name_or_path) in SCENARIOS
    source = f"ergosim/data/scenarios/{path.name}" if bundled else str(path)
    top = check_table(ScenarioTable, doc, source, required=("task", "workcell"), top=True)
    name = top.get("name", path.stem)
    task_doc, task_source, task_label = _resolve_task(doc["task"], path.parent, source)
    cell_doc, cell_source = _resolve_cell(doc["workcell"], path.parent, source)
    cell = parse_cell(cell_doc, source=cell_source)
    protocol = doc.get("protocol", {})
    if not isinstance(protocol, dict):
        raise ConfigError(f"expected a table, got {protocol!r}", where=f"{source}: protocol")
    bad = [k for k in protocol if k in _LABEL_FIELDS]
    if bad:
        origin = "workcell" if bad[0] == "scene" else "task"
        raise ConfigError(f"{bad[0]!r} comes from the scenario's {origin}", where=f"{source}: protocol")
    missing = [k for k in ("subjects", "repetitions", "modes", "robot_cost") if k not in protocol]
    if missing:
        raise ConfigError(f"missing key {missing[0]!r}", where=f"{source}: protocol")
    for key, value in protocol.items():  # a --set string is a comma list; in a file, a list is a list
        if key in _LIST_FIELDS and not isinstance(value, list):
            raise ConfigError(f"{key} must be a list such as {key} = [\"hrc\"], got {value!r}",
                              where=f"{source}: protocol.{key}")
    base = ScenarioConfig(scene=cell.name, task=task_label)
    cfg = apply_overrides(base, {k: (tuple(v) if isinstance(v, list) else v) for k, v in protocol.items()},
                          where=f"{source}: protocol")
    cfg.validate(where=f"{source}: protocol")
    scenario = Scenario(name=name, source=source, protocol=cfg, task_doc=task_doc, task_source=task_source,
                        cell_doc=cell_doc, cell_source=cell_source)
    from ergosim.experiment.scenario_check import check_scenario  # noqa: PLC0415

    check_scenario(scenario, scenario.task(), cell)
    log.debug("scenario %s (%s): task %s, workcell %s", name, source, task_source, cell_source)
    return scenario.with_overrides(overrides) if overrides else scenario


def scenario_config(name: str) -> ScenarioConfig:
    """The protocol of scenario ``name`` (a registered name or a scenario file)."""
    return load_scenario(name).protocol
