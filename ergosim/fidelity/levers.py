"""The levers issue 23 names for §7.1's G(a1) = 5 and a5 loading the trunk, each measured on the twin's own
calibration executions (:func:`~ergosim.fidelity.g_rules.measure`, seeds 0-4, three executions each).

Every lever is a what-if against the nominal twin: a layout override of the §7.1 cell or a multiplier on
the subjects' posture style. None of them is a calibration; docs/fidelity.md reports the table.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence

from ergosim.ergonomics.rula_action import G_RULE
from ergosim.fidelity.g_rules import measure

__all__ = ["Lever", "LEVERS", "LeverRow", "run_levers"]


@dataclasses.dataclass(frozen=True)
class Lever:
    name: str
    what: str
    overrides: Mapping[str, str] = dataclasses.field(default_factory=dict)
    subject_fields: Mapping[str, float] = dataclasses.field(default_factory=dict)


LEVERS = (
    Lever("nominal", "she turns on her spot without stepping (the cell's standing area), neck in the IK, "
          "ISO 11226 priors"),
    Lever("steps and turns", "the clear floor within a step (the default standing area of this cell)",
          {"scene.worker.standing_area": "-0.33,0.16,-0.23,0.33"}),
    Lever("feet planted", "no step, no turn: the knees and the trunk do what the pelvis does not",
          {"scene.worker.max_turn": "0"}),
    Lever("trunk prior x2", "the trunk bends and twists twice as readily (trunk_use x 2)",
          subject_fields={"trunk_use": 2.0}),
    Lever("eyes +50 %", "the eyes take half as much more gaze before the head turns (eye_down 20 -> 30 deg)",
          subject_fields={"eye_down_deg": 1.5}),
    Lever("lower ledge 0.8 m", "a5's ledge 0.2 m lower", {"scene.shelf_low_height": "0.8"}),
    Lever("top ledge 1.6 m", "a1's ledge 0.15 m higher", {"scene.shelf_height": "1.6"}),
)


@dataclasses.dataclass(frozen=True)
class LeverRow:
    lever: Lever
    g: dict[str, float]
    """G(a1..a5) under the twin's rule (G_RULE)."""
    loaded: dict[str, str]


def run_levers(levers: Sequence[Lever] = LEVERS, seeds: Sequence[int] = range(5),
               log: Callable[[str], None] = lambda _msg: None) -> list[LeverRow]:
    rows = []
    for lever in levers:
        log(f"lever: {lever.name}")
        m = measure("kwear-validation", seeds, overrides=lever.overrides, subject_fields=lever.subject_fields)
        rows.append(LeverRow(lever, m.g[G_RULE], m.loaded))
    return rows
