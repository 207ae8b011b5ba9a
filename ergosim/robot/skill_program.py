"""A skill's timed program: the segments a skill executes, one after the other, each with its planned steps.

The planner (:mod:`ergosim.robot.skill_plan`) turns an action into a :class:`SkillProgram`; the executor
(:class:`~ergosim.robot.skills.Skill`) steps it, one physics step at a time, and ``planned_time`` is the
same program's planned steps times the physics step. Only two segments can take other than planned: the
fingers close until they touch the part (:class:`Grasp`), and the carry is re-planned from the actual grasp
(:class:`Carry`); a hand-over's wait for the worker (:class:`Wait`) is not the robot's time.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

from ergosim.robot.skill_motion import Motion
from ergosim.robot.skill_plan import CarryPlan

__all__ = ["Move", "Pause", "Grasp", "Carry", "Arrive", "Wait", "LetGo", "Open", "Leave", "Contacts",
           "Segment", "SkillProgram", "pause"]


@dataclass(frozen=True, eq=False)
class Move:
    """Follow ``motion``; ``grip`` [m per finger], if given, is the gripper's opening from its first step."""

    motion: Motion
    grip: float | None = None

    @property
    def steps(self) -> int:
        return self.motion.steps


@dataclass(frozen=True)
class Pause:
    """Hold still for ``steps`` physics steps, in ``phase``."""

    steps: int
    phase: str = "gripper"


def pause(seconds: float, dt: float, phase: str = "gripper") -> Pause:
    """A pause of ``seconds`` at physics step ``dt`` [s] (at least one step)."""
    return Pause(max(1, int(round(seconds / dt))), phase)


@dataclass(frozen=True)
class Grasp:
    """Close the fingers on ``body`` (``width`` [m] between its faces, grasp site ``site``) until both touch
    it, then weld it to the hand; planned ``steps`` at the finger speed."""

    body: str
    site: str
    width: float
    steps: int


@dataclass(frozen=True, eq=False)
class Carry:
    """Carry the part along ``motion`` (re-planned from the actual grasp when it starts), checking that it
    stays in the hand."""

    motion: Motion

    @property
    def steps(self) -> int:
        return self.motion.steps


@dataclass(frozen=True)
class Arrive:
    """The part is at its target and the arm has settled: the skill's arrival time."""

    steps: int = 0


@dataclass(frozen=True)
class Wait:
    """Hold the part at the hand-over pose until the worker takes it, at most ``timeout`` [s] (the worker's
    time, planned as none)."""

    timeout: float
    steps: int = 0


@dataclass(frozen=True)
class LetGo:
    """Let go of the part: a receiver outside the cell takes it first (``receive``), or it is seated in its
    slot after (``seat``)."""

    receive: bool = False
    seat: bool = False
    steps: int = 0


@dataclass(frozen=True)
class Open:
    """Open the fingers fully; planned ``steps`` at the finger speed."""

    steps: int


@dataclass(frozen=True, eq=False)
class Leave:
    """Go back home along ``motion`` (from where the carry actually ended)."""

    motion: Motion

    @property
    def steps(self) -> int:
        return self.motion.steps


@dataclass(frozen=True)
class Contacts:
    """Switch the robot's contacts with the host of ``part``'s slot off or on (``enabled``)."""

    part: str
    enabled: bool
    steps: int = 0


Segment = Move | Pause | Grasp | Carry | Arrive | Wait | LetGo | Open | Leave | Contacts


@dataclass(frozen=True, eq=False)
class SkillProgram:
    """A skill's ``segments`` in order, planned from ``plan`` at physics step ``dt`` [s]."""

    plan: CarryPlan
    segments: tuple[Segment, ...]
    dt: float

    @property
    def planned_steps(self) -> int:
        """Physics steps the program takes as planned."""
        return sum(s.steps for s in self.segments)

    @property
    def planned_time(self) -> float:
        """How long the program takes as planned [s]."""
        return self.planned_steps * self.dt

    @functools.cached_property
    def release_index(self) -> int | None:
        """How many segments run until the fingers have opened on the part let go (the part is where it
        goes; the rest is the way home); None if the program lets nothing go."""
        let_go = False
        for k, s in enumerate(self.segments):
            let_go |= isinstance(s, LetGo)
            if let_go and isinstance(s, Open):
                return k + 1
        return None

    @property
    def release_steps(self) -> int:
        """Physics steps as planned until the part is let go (:attr:`release_index`): all of them if the
        program lets nothing go."""
        k = self.release_index
        return self.planned_steps if k is None else sum(s.steps for s in self.segments[:k])
