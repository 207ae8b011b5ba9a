"""Override fields of a task document by dotted path (``--set task.PATH=VALUE``).

Paths follow the file's tables (docs/task_format.md): ``name``, ``description``, ``parts``,
``agents.<agent>.<kind|cost>``, ``liaisons.<action>.<agents|cost[.<agent>]|parts>`` (a liaison is named by
its action label), ``operations.<name>.<agents|cost[.<agent>]|action|joins>``. A ``--set`` string becomes
the TOML value the field takes: a list of names split at commas (``agents=human``), a number (``cost``),
else a string. The document is rebuilt through the task parser afterwards, so every override is checked like
the file itself.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from typing import Any

from ergosim.errors import TaskFileError
from ergosim.overrides import finite_float

__all__ = ["apply_task_overrides", "task_keys"]

_AGENT = ("kind", "cost")
_LIAISON = ("parts", "action", "agents", "cost")
_OPERATION = ("name", "action", "joins", "father", "agents", "cost")
_LISTS = {"parts", "agents", "father"}


def task_keys(doc: Mapping[str, Any]) -> list[str]:
    """Every dotted path of ``doc`` an override may set (per-agent costs as ``...cost.<agent>``)."""
    agents = list(doc.get("agents") or {})
    keys = ["name", "description", "parts"]
    keys += [f"agents.{a}.{k}" for a in agents for k in _AGENT]
    for table, fields, label in (("liaisons", _LIAISON, "action"), ("operations", _OPERATION, "name")):
        for entry in doc.get(table) or []:
            if isinstance(entry, dict) and isinstance(entry.get(label), str):
                head = f"{table}.{entry[label]}"
                keys += [f"{head}.{k}" for k in fields if k not in ("cost", label)]
                keys += [f"{head}.cost.{a}" for a in agents]
    return keys


def _entry(doc: dict, table: str, name: str, where: str) -> dict:
    label = "action" if table == "liaisons" else "name"
    for entry in doc.get(table) or []:
        if isinstance(entry, dict) and entry.get(label) == name:
            return entry
    names = [e.get(label) for e in doc.get(table) or [] if isinstance(e, dict)]
    raise TaskFileError(f"no {table[:-1]} {name!r} in the task; {table}: "
                        f"{', '.join(map(str, names)) or 'none'}", where=where)


def _value(raw: Any, key: str, said: str, where: str) -> Any:
    if not isinstance(raw, str):
        return list(raw) if isinstance(raw, tuple) else raw
    if key in _LISTS:
        return [s.strip() for s in raw.split(",") if s.strip()]
    if key == "joins":
        return [[p.strip() for p in child.split("+") if p.strip()] for child in raw.split(",")]
    if key == "cost":
        return finite_float(raw, said.partition("=")[0], where=where, error=TaskFileError)
    return raw


def apply_task_overrides(doc: Mapping[str, Any], overrides: Mapping[str, Any], where: str) -> dict[str, Any]:
    """A deep copy of the task document ``doc`` with ``overrides`` (dotted path -> value) set."""
    out = copy.deepcopy(dict(doc))
    for path, raw in overrides.items():
        said = f"task.{path}={raw!r}"
        parts = path.split(".")
        if path not in task_keys(out):
            sample = ", ".join(task_keys(out)[:10])
            raise TaskFileError(f"unknown task field {path!r}; task fields include: {sample}, ... "
                                "(docs/workcell_format.md)", where=where)
        if parts[0] in ("name", "description", "parts"):
            out[parts[0]] = _value(raw, parts[0], said, where)
            continue
        if parts[0] == "agents":
            node = out["agents"][parts[1]]
        else:
            node = _entry(out, parts[0], parts[1], where)
        if parts[2] == "cost" and len(parts) == 4:
            cost = node.get("cost")
            node["cost"] = cost = dict(cost) if isinstance(cost, dict) else {}
            cost[parts[3]] = _value(raw, "cost", said, where)
        else:
            node[parts[2]] = _value(raw, parts[2], said, where)
    return out
