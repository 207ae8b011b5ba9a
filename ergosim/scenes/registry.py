"""Workcells by name: the bundled cell files, plus any a user registers.

A workcell is a file (docs/workcell_format.md); a name is a short handle on one. ``build_scene(name,
**overrides)`` reads the file, applies the overrides (dotted paths such as ``parts.L.xy``, or the file's
aliases such as ``l_xy``), checks it, and compiles it.
"""

from __future__ import annotations

import os
from importlib import resources
from pathlib import Path
from typing import Any

from ergosim.registry import Registry
from ergosim.scenes.cellbuild import build_cell
from ergosim.scenes.cellfile import apply_cell_overrides, parse_cell, read_cell_file
from ergosim.scenes.cellspec import CellSpec
from ergosim.scenes.workcell import Workcell

__all__ = ["SCENES", "register_scene", "scene_names", "scene_path", "cell_document", "load_cell",
           "default_config", "build_scene"]

SCENES: Registry[Path] = Registry("scene", where="scene")
"""The workcell files by name."""


def register_scene(name: str, path: str | os.PathLike[str]) -> None:
    """Make the workcell file at ``path`` buildable by ``name``."""
    SCENES.register(name, Path(path))


for _f in sorted(resources.files("ergosim").joinpath("data", "cells").iterdir(), key=lambda f: f.name):
    if _f.name.endswith(".toml"):
        register_scene(_f.name.removesuffix(".toml"), Path(str(_f)))


def scene_names() -> tuple[str, ...]:
    return SCENES.names()


def scene_path(name: str) -> Path:
    """The file of registered workcell ``name`` (``multi_subject`` finds ``multi-subject``)."""
    dashed = name.replace("_", "-")
    return SCENES.get(dashed if name not in SCENES and dashed in SCENES else name)


def _source(path: Path) -> str:
    """How a file is named in messages: bundled files relative to the package."""
    text = str(path)
    marker = os.sep.join(("ergosim", "data", ""))
    return text[text.index(marker):] if marker in text else text


def cell_document(name_or_path: str | os.PathLike[str]) -> tuple[dict[str, Any], str]:
    """The TOML document of a registered workcell or a workcell file, and its name for messages. A part's
    mesh ``file`` given relative to the workcell file is made absolute here, so the cell builds from
    anywhere."""
    path = Path(name_or_path)
    if str(name_or_path).endswith(".toml") or path.is_file():
        return _meshes_from(read_cell_file(path), path.parent), str(path)
    path = scene_path(str(name_or_path))
    return _meshes_from(read_cell_file(path), path.parent), _source(path)


def _meshes_from(doc: dict[str, Any], folder: Path) -> dict[str, Any]:
    for part in (doc.get("parts") or {}).values():
        file = part.get("file") if isinstance(part, dict) else None
        if isinstance(file, str) and not Path(file).is_absolute():
            part["file"] = str(folder / file)
    return doc


def load_cell(name_or_path: str | os.PathLike[str], **overrides: Any) -> CellSpec:
    """The checked :class:`CellSpec` of a workcell (name or file) with ``overrides`` applied."""
    doc, source = cell_document(name_or_path)
    doc = apply_cell_overrides(doc, overrides, where=f"{source} (overrides)") if overrides else doc
    return parse_cell(doc, source=source)


def default_config(name: str) -> CellSpec:
    """The workcell ``name`` as its file describes it."""
    return load_cell(name)


def build_scene(name: str | os.PathLike[str], config: CellSpec | None = None, **overrides: Any) -> Workcell:
    """Build workcell ``name`` (a registered name or a file), or ``config`` when given, with ``overrides``."""
    if config is not None and not overrides:
        return build_cell(config)
    return build_cell(load_cell(name, **overrides))
