"""Workcells: cell files (furniture, parts, slots, targets, worker, robots, actions), builder, registry."""

from ergosim.scenes.cellbuild import build_cell
from ergosim.scenes.cellfile import apply_cell_overrides, parse_cell, read_cell_file
from ergosim.scenes.cellspec import (
    ACTION_KINDS,
    Action,
    Box,
    CellSpec,
    Part,
    Robot,
    Shelf,
    Slot,
    Surface,
    Table,
    Target,
    View,
    Worker,
)
from ergosim.scenes.registry import (
    build_scene,
    cell_document,
    default_config,
    load_cell,
    register_scene,
    scene_names,
    scene_path,
)
from ergosim.scenes.render import render_workcell
from ergosim.scenes.separation import Capsules, Separation, SeparationModel, segment_distances
from ergosim.scenes.shapes import PART_COLLISION
from ergosim.scenes.workcell import ActionGeometry, SeatResult, Workcell

__all__ = [
    "Capsules",
    "Separation",
    "SeparationModel",
    "segment_distances",
    "ACTION_KINDS",
    "Action",
    "Box",
    "CellSpec",
    "Part",
    "Robot",
    "Shelf",
    "Slot",
    "Surface",
    "Table",
    "Target",
    "View",
    "Worker",
    "PART_COLLISION",
    "apply_cell_overrides",
    "build_cell",
    "build_scene",
    "cell_document",
    "default_config",
    "load_cell",
    "parse_cell",
    "read_cell_file",
    "register_scene",
    "scene_names",
    "scene_path",
    "render_workcell",
    "ActionGeometry",
    "SeatResult",
    "Workcell",
]
