"""Bundled task files: the corner-joint assembly of the paper's experiments (§7), in both variants.

``corner-joint:kwear-validation`` (§7.1): a1..a5 in a fixed sequence, both agents may do everything,
robot cost 50. ``corner-joint:multi-subject`` (§7.2, the default): a1 first, a2..a4 in any order, a5
last and human-only, robot cost 2.5. Both are ordinary task files in ``ergosim/data/tasks`` and load
through the same parser as user files.
"""

from __future__ import annotations

from importlib import resources

from ergosim.errors import ConfigError
from ergosim.planner.graph import AndOrGraph
from ergosim.planner.taskfile import parse_task

__all__ = ["corner_joint_task", "bundled_task", "bundled_task_text", "BUNDLED_TASKS", "CORNER_JOINT_VARIANTS"]

CORNER_JOINT_VARIANTS = ("multi-subject", "kwear-validation")
BUNDLED_TASKS = ("corner-joint",) + tuple(f"corner-joint:{v}" for v in CORNER_JOINT_VARIANTS)


def _file_name(name: str) -> str:
    base, _, variant = name.partition(":")
    if base != "corner-joint" or (variant and variant not in CORNER_JOINT_VARIANTS):
        raise ConfigError(
            f"unknown bundled task {name!r}; bundled tasks are {list(BUNDLED_TASKS)}", where="task"
        )
    return f"corner-joint-{variant or CORNER_JOINT_VARIANTS[0]}.toml"


def bundled_task_text(name: str) -> str:
    """The TOML text of bundled task ``name`` (e.g. ``"corner-joint:kwear-validation"``)."""
    return resources.files("ergosim").joinpath("data", "tasks", _file_name(name)).read_text(encoding="utf-8")


def bundled_task(name: str) -> AndOrGraph:
    """Build bundled task ``name``; ``"corner-joint"`` is the multi-subject variant."""
    return parse_task(bundled_task_text(name), source=f"ergosim/data/tasks/{_file_name(name)}")


def corner_joint_task(variant: str = "multi-subject") -> AndOrGraph:
    """The corner-joint task of §7: ``"multi-subject"`` (§7.2) or ``"kwear-validation"`` (§7.1)."""
    if variant not in CORNER_JOINT_VARIANTS:
        raise ConfigError(
            f"unknown corner-joint variant {variant!r}; expected one of {list(CORNER_JOINT_VARIANTS)}",
            where="variant",
        )
    return bundled_task(f"corner-joint:{variant}")
