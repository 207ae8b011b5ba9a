"""Override fields of a task document by dotted path (``--set task.PATH=VALUE``), by the one override of
every file format (:func:`ergosim.schema.document.override`) over the task's schema
(:mod:`ergosim.planner.task_schema`, which lists the paths). The document is rebuilt through the task parser
afterwards, so every override is checked like the file itself.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ergosim.errors import TaskFileError
from ergosim.planner.task_schema import TASK
from ergosim.schema.document import override, paths

__all__ = ["apply_task_overrides", "task_keys"]


def task_keys(doc: Mapping[str, Any]) -> list[str]:
    """Every dotted path of ``doc`` an override may set (per-agent costs as ``...cost.<agent>``)."""
    return paths(TASK, doc)


def _unknown(path: str, valid: list[str]) -> str:
    return (f"unknown task field {path!r}; task fields include: {', '.join(valid[:10])}, ... "
            "(docs/workcell_format.md)")


def apply_task_overrides(doc: Mapping[str, Any], overrides: Mapping[str, Any], where: str) -> dict[str, Any]:
    """A deep copy of the task document ``doc`` with ``overrides`` (dotted path -> value) set."""
    return override(TASK, doc, overrides, where, error=TaskFileError, said=lambda p: f"task.{p}",
                    unknown=_unknown)
