"""What a robot skill reports: a status the allocator can re-plan on, with a one-line message."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

__all__ = ["SKILL_PHASES", "SkillStatus", "SkillResult"]

SKILL_PHASES = ("transit", "contact", "gripper", "wait", "home")
"""What a skill's time is spent on: ``transit`` free-space motion; ``contact`` contact-critical motion
(approach, lift-off, place or insertion, retreat) and holding the part at its target; ``gripper`` closing,
opening and the settling pauses; ``wait`` holding the part at the handover pose until the worker takes it;
``home`` the return to the ready pose."""


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
    its target after release (NaN if it never got there); ``phases``: (phase, seconds) for each of
    :data:`SKILL_PHASES`, summing to ``duration``; ``arrival`` [s from the first step]: when the part had
    reached its target pose (place, insertion or handover pose) and the arm had settled there (NaN if it
    never did)."""

    skill: str
    part: str
    status: SkillStatus
    message: str
    duration: float
    place_error: float = float("nan")
    phases: tuple[tuple[str, float], ...] = ()
    arrival: float = float("nan")

    def phase(self, name: str) -> float:
        """Seconds spent in phase ``name`` (0 if none)."""
        return sum(t for n, t in self.phases if n == name)

    @property
    def ok(self) -> bool:
        return self.status is SkillStatus.OK
