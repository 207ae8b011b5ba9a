"""Bundled task files, found by name in ``ergosim/data/tasks``.

A file ``NAME.toml`` there is the bundled task ``NAME``; a product with one task file per experiment keeps
them in a folder, ``PRODUCT/VARIANT.toml``, named ``PRODUCT:VARIANT`` (``corner-joint:kwear-validation``),
and ``PRODUCT`` alone names the variant that ``index.toml`` gives as its default. They are ordinary task
files and load through the same parser as a user's.
"""

from __future__ import annotations

import tomllib
from importlib import resources

from ergosim.errors import ConfigError
from ergosim.planner.graph import AndOrGraph
from ergosim.planner.taskfile import parse_task

__all__ = ["bundled_task", "bundled_task_text", "bundled_task_source", "BUNDLED_TASKS"]


def _index() -> dict[str, str]:
    """Bundled name -> path relative to ``ergosim/data/tasks``."""
    root = resources.files("ergosim").joinpath("data", "tasks")
    defaults = tomllib.loads(root.joinpath("index.toml").read_text(encoding="utf-8")).get("default", {})
    names: dict[str, str] = {}
    for entry in sorted(root.iterdir(), key=lambda e: e.name):
        if entry.is_dir():
            variants = sorted(f.name for f in entry.iterdir() if f.name.endswith(".toml"))
            if entry.name in defaults:
                names[entry.name] = f"{entry.name}/{defaults[entry.name]}.toml"
            for v in variants:
                names[f"{entry.name}:{v.removesuffix('.toml')}"] = f"{entry.name}/{v}"
        elif entry.name.endswith(".toml") and entry.name != "index.toml":
            names[entry.name.removesuffix(".toml")] = entry.name
    return names


_NAMES = _index()
BUNDLED_TASKS: tuple[str, ...] = tuple(_NAMES)


def bundled_task_source(name: str) -> str:
    """Where bundled task ``name`` lives, as messages name it (``ergosim/data/tasks/...``)."""
    try:
        return f"ergosim/data/tasks/{_NAMES[name]}"
    except KeyError:
        raise ConfigError(f"unknown bundled task {name!r}; bundled tasks are {list(BUNDLED_TASKS)}",
                          where="task") from None


def bundled_task_text(name: str) -> str:
    """The TOML text of bundled task ``name`` (e.g. ``"corner-joint:kwear-validation"``)."""
    bundled_task_source(name)
    return resources.files("ergosim").joinpath("data", "tasks", _NAMES[name]).read_text(encoding="utf-8")


def bundled_task(name: str) -> AndOrGraph:
    """Build bundled task ``name``."""
    return parse_task(bundled_task_text(name), source=bundled_task_source(name))
