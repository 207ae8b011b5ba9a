"""Scene registry: name -> (default config, builder). Add a scene by registering it here."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, NamedTuple

from ergosim.errors import ConfigError
from ergosim.scenes import kwear_validation, multi_subject
from ergosim.scenes.config import WorkcellConfig, with_overrides
from ergosim.scenes.workcell import Workcell

__all__ = ["SceneEntry", "register_scene", "scene_names", "default_config", "build_scene"]


class SceneEntry(NamedTuple):
    default_config: Callable[[], WorkcellConfig]
    build: Callable[[Any], Workcell]


_SCENES: dict[str, SceneEntry] = {}


def register_scene(name: str, default_config: Callable[[], WorkcellConfig],
                   build: Callable[[Any], Workcell]) -> None:
    _SCENES[name] = SceneEntry(default_config, build)


register_scene(kwear_validation.NAME, kwear_validation.default_config, kwear_validation.build_workcell)
register_scene(multi_subject.NAME, multi_subject.default_config, multi_subject.build_workcell)


def scene_names() -> tuple[str, ...]:
    return tuple(_SCENES)


def _entry(name: str) -> SceneEntry:
    entry = _SCENES.get(name) or _SCENES.get(name.replace("_", "-"))
    if entry is None:
        raise ConfigError(f"unknown scene {name!r}; valid scenes: {', '.join(_SCENES)}", where="scene")
    return entry


def default_config(name: str) -> WorkcellConfig:
    """The frozen default layout of scene ``name``."""
    return _entry(name).default_config()


def build_scene(name: str, config: WorkcellConfig | None = None, **overrides: Any) -> Workcell:
    """Build scene ``name`` from ``config`` (default: its default config) with fields overridden by name."""
    entry = _entry(name)
    cfg = config if config is not None else entry.default_config()
    cfg = with_overrides(cfg, overrides, where=f"scene {name}")
    return entry.build(cfg)
