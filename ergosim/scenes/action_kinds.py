"""The action vocabulary: what an operation of a task physically does in a workcell, registered in one place.

Every action of a workcell file (``[actions.LABEL]``) has a ``kind``. A kind says what its ``target`` names,
how the part is taken, and how the scene decides that the action is complete -- the same check whoever does
it, the worker or a robot, so a worker action and a robot action on the same operation move the same part
to the same target:

========== =============== ===================================================== ===========================
kind       target          what happens                                          complete when
========== =============== ===================================================== ===========================
place      a place target  the part is set down on a surface                     released, origin within
                                                                                 ``place_tolerance``
insert     a slot          the part slides along the slot's axis to its depth    seated: within
                                                                                 ``seat_tolerance`` [m] and
                                                                                 ``seat_tolerance_deg``
fasten     a slot          insert, then hold and turn for ``turn_time`` [s]      seated, as insert
remove     a place target  the part *with everything seated in it* goes onto a   released, origin within
                           surface (an outfeed)                                  ``place_tolerance``
handover   a free target   the part with everything seated in it is handed to a  taken: the receiver holds
                           receiver outside the cell (a second operator, a       it, origin within
                           conveyor) at a pose in the air                        ``place_tolerance``
========== =============== ===================================================== ===========================

A robot that fails reports one of the skill statuses (:class:`~ergosim.robot.status.SkillStatus`):
``unreachable``, ``not_grasped``, ``dropped``, ``not_seated`` (insert, fasten: outside the seat tolerance;
handover: outside the receiver's tolerance, so nobody took it) or ``timeout``. A worker's attempt fails as
``unreachable`` (the hand cannot get to the part) or ``not_completed`` (the scene's check above failed).

Not to be confused with an action's ``handover = "POSE"`` field: that makes a *robot* doing the action
(of any kind) bring the part to the worker at POSE, who then finishes it (paper §7.2).

A new kind is one :func:`register_action_kind` call with an :class:`ActionKind`: its flags choose among the
behaviours above (what the target is, whether the part seats, is held, moves its assembly, is received).
"""

from __future__ import annotations

import dataclasses
from typing import Literal

from ergosim.registry import Registry

__all__ = ["ActionKind", "ACTION_KINDS", "register_action_kind", "action_kind"]


@dataclasses.dataclass(frozen=True)
class ActionKind:
    """One kind of physical action.

    ``target``: what the action's ``target`` names -- ``place`` a place target on a surface, ``slot`` a
    slot key ``host.slot``, ``free`` a free target (a pose in the air). ``seats``: the action ends with the
    part seated in its slot (a weld within the seat tolerances). ``holds``: once seated the part is held
    for the action's ``turn_time`` [s] (the turns of a screw). ``assembly``: the part is taken together
    with everything seated in it (grasped by what sticks up out of it). ``received``: the action ends with
    a receiver outside the cell holding the part at the target pose.
    """

    name: str
    target: Literal["place", "slot", "free"]
    description: str
    seats: bool = False
    holds: bool = False
    assembly: bool = False
    received: bool = False

    def __post_init__(self) -> None:
        if self.target not in ("place", "slot", "free"):
            raise ValueError(f"target must be place, slot or free, got {self.target!r}")
        if self.holds and not self.seats:
            raise ValueError("a kind that holds the part once seated must seat it")


ACTION_KINDS: Registry[ActionKind] = Registry("action kind", where="workcell")
"""Registered kinds by name."""


def register_action_kind(kind: ActionKind) -> None:
    """Make ``kind`` usable as ``kind = "NAME"`` in workcell files, in worker processes too."""
    ACTION_KINDS.register(kind.name, kind)


def action_kind(name: str) -> ActionKind:
    """The registered kind ``name`` (KeyError if there is none; workcell files are checked on reading)."""
    return ACTION_KINDS[name]


register_action_kind(ActionKind("place", "place", "the part onto a place target on a surface"))
register_action_kind(ActionKind("insert", "slot", "the part along its slot's axis to its depth", seats=True))
register_action_kind(ActionKind("fasten", "slot", "insert, then hold and turn for turn_time (a screw)",
                                seats=True, holds=True))
register_action_kind(ActionKind("remove", "place", "the part with its assembly onto a place target "
                                "(an outfeed)", assembly=True))
register_action_kind(ActionKind("handover", "free", "the part with its assembly to a receiver outside the "
                                "cell, at a free target", assembly=True, received=True))
