"""The workcell file's schema: one pydantic table per TOML table (docs/workcell_format.md).

Each field is a value kind of :mod:`ergosim.schema.values`; :data:`CELL` is the tree of tables that
:func:`ergosim.schema.document.override` walks for ``--set scene.PATH=VALUE``. What needs more than one
field (a shape's required sizes, surfaces that exist, overlaps) is checked by :mod:`ergosim.scenes.cellfile`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ergosim.schema.document import Listed, Named, Table, Tree, table
from ergosim.schema.values import AXIS, FLAG, NAMES, NUMBER, PAIRS, RAW, TEXT, Numbers

__all__ = ["CELL", "TABLES", "FURNITURE", "TopTable", "WorkerTable", "RobotTable", "PartTable", "SlotTable",
           "TargetTable", "ActionTable", "ViewTable", "SafetyTable"]

S, F, XY, XYZ, RGBA = TEXT, NUMBER, Numbers(2), Numbers(3), Numbers(4)

TopTable = table("TopTable", ("name",), name=S, description=S, timestep=F, seat_tolerance=F,
                 seat_tolerance_deg=F, place_tolerance=F, carry_height=F, grasp_tolerance=F)
WorkerTable = table("WorkerTable", name=S, xy=XY, yaw=F, hand=S, stature=F, human_scale=PAIRS,
                    standing_area=Numbers(4), max_turn=F)
RobotTable = table("RobotTable", model=S, base=XYZ, yaw=F, support=S, park_clearance=F)
FURNITURE: dict[str, type[Table]] = {
    "table": table("TableTable", ("type",), type=S, center=XY, size=XY, height=F, thickness=F, legs=FLAG,
                   rgba=RGBA, yaw=F),
    "shelf": table("ShelfTable", ("type",), type=S, center=XY, size=XY, height=F, low_height=F, top_depth=F,
                   thickness=F, rgba=RGBA, yaw=F, back=S),
    "box": table("BoxTable", ("type",), type=S, center=XYZ, half=XYZ, rgba=RGBA, stand_to=S, stand_offset=XY,
                 stand_half=XY, yaw=F),
}
"""Furniture tables by their ``type``."""
PartTable = table("PartTable", ("slots",), shape=S, size=XYZ, radius=F, length=F, file=S, scale=F, bore=F,
                  clearance=F, wall=F, sleeve_length=F, sleeves=NAMES, mass=F, density=F, section_area=F,
                  rgba=RGBA, on=S, xy=XY, yaw=F, pos=XYZ, rpy=XYZ, insert_axis=S, grasp=S, slots=RAW,
                  coupling=S)
SlotTable = table("SlotTable", ("name",), name=S, at=XYZ, axis=AXIS)
TargetTable = table("TargetTable", on=S, xy=XY, yaw=F, part=S, pos=XYZ)
ActionTable = table("ActionTable", kind=S, part=S, target=S, handover=S, turn_time=F)
ViewTable = table("ViewTable", azimuth=F, elevation=F, distance=F, lookat=XYZ)
SafetyTable = table("SafetyTable", ssm=S, human_speed=F, measured_speed=FLAG, reaction_time=F,
                    stopping_time=F, intrusion=F, human_uncertainty=F, robot_uncertainty=F)


def _furniture(entry: Mapping[str, Any]) -> type[Table]:
    return FURNITURE.get(entry.get("type", "table"), FURNITURE["table"])


CELL = Tree(TopTable, {
    "worker": Tree(WorkerTable),
    "robots": Named(Tree(RobotTable)),
    "furniture": Named(Tree(_furniture)),
    "parts": Named(Tree(PartTable, {"slots": Listed(Tree(SlotTable), label="name")})),
    "targets": Named(Tree(TargetTable)),
    "actions": Named(Tree(ActionTable)),
    "views": Named(Tree(ViewTable)),
    "safety": Tree(SafetyTable),
})
"""The workcell file as a tree of tables (``[aliases]`` is read by :mod:`ergosim.scenes.cellfile`)."""

TABLES = ("aliases", *CELL.children)
"""The tables of a workcell file."""
