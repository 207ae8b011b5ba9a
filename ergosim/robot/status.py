"""What a robot skill reports: a status the allocator can re-plan on, with a one-line message."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

__all__ = ["SkillStatus", "SkillResult"]


class SkillStatus(Enum):
    OK = "ok"
    UNREACHABLE = "unreachable"
    """No joint path to a waypoint (IK failed or the straight line leaves the workspace)."""
    NOT_GRASPED = "not_grasped"
    """The fingers closed without both touching the part."""
    DROPPED = "dropped"
    """The part left the gripper while carried."""
    NOT_SEATED = "not_seated"
    """An inserted part ended outside the seat tolerance of its slot, or a part handed over outside the
    receiver's tolerance of the handover pose."""
    TIMEOUT = "timeout"
    """A handover nobody took within the allowed time."""


@dataclass(frozen=True)
class SkillResult:
    """``duration`` [s] of simulated time from the first step; ``place_error`` [m] of the part's origin to
    its target after release (NaN if it never got there)."""

    skill: str
    part: str
    status: SkillStatus
    message: str
    duration: float
    place_error: float = float("nan")

    @property
    def ok(self) -> bool:
        return self.status is SkillStatus.OK
