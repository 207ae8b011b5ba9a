"""The workcells of paper §7: layout config, parts, welds, and the scene registry."""

from ergosim.scenes.config import Surface, WorkcellConfig, with_overrides
from ergosim.scenes.kwear_validation import KWearValidationConfig
from ergosim.scenes.multi_subject import MultiSubjectConfig
from ergosim.scenes.parts import ALUMINIUM_DENSITY, PARTS, PROFILES, PartDims, hollow_pose
from ergosim.scenes.registry import build_scene, default_config, register_scene, scene_names
from ergosim.scenes.render import render_workcell
from ergosim.scenes.workcell import ActionGeometry, SeatResult, Workcell

__all__ = [
    "Surface",
    "WorkcellConfig",
    "with_overrides",
    "KWearValidationConfig",
    "MultiSubjectConfig",
    "ALUMINIUM_DENSITY",
    "PARTS",
    "PROFILES",
    "PartDims",
    "hollow_pose",
    "build_scene",
    "default_config",
    "register_scene",
    "scene_names",
    "render_workcell",
    "ActionGeometry",
    "SeatResult",
    "Workcell",
]
