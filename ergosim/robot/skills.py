"""Robot skills on a workcell: pick-and-place and hand-over (paper §7), steppable one physics step at a time.

A skill is planned, then executed. Its planner (:mod:`ergosim.robot.skill_plan`) turns the action into a
timed program (:mod:`ergosim.robot.skill_program`): the motions (waypoints and speeds,
:mod:`ergosim.robot.skill_motion`), the pauses and the gripper. The executor
(:class:`~ergosim.robot.skill_exec.Skill`) steps that program with the physics, and
:meth:`~ergosim.robot.skill_exec.Skill.planned_time` reads the same program. Here are the two skills:
which program each plans and how each reports its end.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ergosim.quat import to_mat
from ergosim.robot.kinematics import ArmKinematics
from ergosim.robot.skill_exec import Skill
from ergosim.robot.skill_motion import UP
from ergosim.robot.skill_params import SkillParams
from ergosim.robot.skill_plan import CarryGoal, CarryPlan
from ergosim.robot.skill_program import (
    Arrive,
    Carry,
    Contacts,
    Grasp,
    Leave,
    LetGo,
    Move,
    Open,
    Segment,
    SkillProgram,
    Wait,
    pause,
)
from ergosim.robot.status import SkillResult, SkillStatus
from ergosim.robot.trajectory import PathError, Pose

__all__ = ["SkillParams", "Skill", "PickPlace", "Handover", "pick_place", "handover"]


class _Carrying(Skill):
    """What both skills do until the part arrives: reach, pause, close on the part, settle, carry, settle."""

    def _to_arrival(self, plan: CarryPlan) -> tuple[Segment, ...]:
        p, dt, c = self.params, self.dt, self.carrier
        return (Move(plan.reach, grip=self.robot.gripper_open), pause(p.grasp_pause, dt),
                Grasp(c.grasp_body, c.grasp_site, c.width, c.gripper_steps()), pause(p.settle, dt),
                Carry(plan.carry), pause(p.settle, dt), Arrive())


class PickPlace(_Carrying):
    """Pick ``part`` and put its origin at the world pose ``target_pos`` (3,) [m], ``target_quat`` wxyz.

    ``approach``: world direction the part arrives from (default +z, from above; for a part going into a
    slot, the slot's axis). ``seat``: weld an inserted part into its slot when it is within
    tolerance. ``hold`` [s]: keep holding the part at the target before letting go (fastening: the turn).
    ``receive``: the target is a pose in the air where a receiver outside the cell takes the part
    (``Workcell.receive``, the handover kind) before the fingers open; ``not_seated`` if it is out of the
    receiver's tolerance there.
    """

    name = "pick_place"

    def __init__(self, workcell, part: str, target_pos, target_quat, *, approach=None, seat: bool = False,
                 hold: float = 0.0, receive: bool = False, kin: ArmKinematics | None = None,
                 params: SkillParams = SkillParams(), robot: str | None = None) -> None:
        super().__init__(workcell, part, kin, params, robot)
        self.target = Pose(np.asarray(target_pos, dtype=float), to_mat(target_quat))
        a = UP if approach is None else np.asarray(approach, dtype=float)
        self.approach_dir = a / np.linalg.norm(a)
        self.seat = seat
        self.hold = float(hold)
        self.receive = receive

    def plan(self) -> SkillProgram:
        p, dt = self.params, self.dt
        # an insertion runs its whole stroke at the contact speed; a place only its last contact zone
        stand = p.insert_approach if self.seat else p.approach
        plan = self.carrier.plan(lambda zone: CarryGoal(self.target, self.approach_dir, stand,
                                                        stand if self.seat else zone))
        # Insertion is a weld within tolerance, not a contact fit: the fingers that hold the part down to
        # its seat pass the host's walls, as the last millimetres of a chamfered bore would let them.
        seat_off = (Contacts(self.part, False),) if self.seat else ()
        seat_on = (Contacts(self.part, True),) if self.seat else ()
        turn = (pause(self.hold, dt, "contact"),) if self.hold > 0 else ()
        return SkillProgram(plan, (*seat_off, *self._to_arrival(plan), *turn,
                                   LetGo(receive=self.receive, seat=self.seat),
                                   Open(self.carrier.gripper_steps()), pause(p.settle, dt), *seat_on,
                                   Leave(plan.leave), pause(p.settle, dt)), dt)

    def _unreachable(self, error: PathError) -> str:
        return f"cannot take {self.part} to {np.round(self.target.pos, 3).tolist()}: {error}"

    def _outcome(self) -> SkillResult:
        error = float(np.linalg.norm(self.wc.body_pose(self.part)[0] - self.target.pos))
        seated = self._seated
        if seated is not None and not seated.seated:
            if self.receive:
                return self._finish(SkillStatus.NOT_SEATED, f"{self.part} arrived "
                                    f"{seated.pos_error * 1000:.1f} mm from the handover pose, outside the "
                                    "receiver's tolerance", error)
            return self._finish(SkillStatus.NOT_SEATED, f"{self.part} ended {seated.pos_error * 1000:.1f} mm "
                                f"and {seated.rot_error_deg:.1f} deg from its seat", error)
        return self._finish(SkillStatus.OK, f"{self.part} placed {error * 1000:.1f} mm from its target",
                            error)


def _worker_holds(part: str) -> Callable[[object], bool]:
    def taken(wc) -> bool:
        return any(wc.is_held(h, part) for h in wc.holders if h not in wc.robots)
    return taken


class Handover(_Carrying):
    """Bring ``part`` to the world pose ``pos``/``quat`` (of the part's origin), hold it there until
    ``taken(workcell)`` is true (default: a worker hand weld holds it), let go, and return home."""

    name = "handover"

    def __init__(self, workcell, part: str, pos, quat, taken: Callable[[object], bool] | None = None, *,
                 kin: ArmKinematics | None = None, params: SkillParams = SkillParams(),
                 robot: str | None = None) -> None:
        super().__init__(workcell, part, kin, params, robot)
        self.target = Pose(np.asarray(pos, dtype=float), to_mat(quat))
        self.taken = taken or _worker_holds(part)

    def plan(self) -> SkillProgram:
        # the part comes down into the hand-over pose and the hand leaves upwards, both next to the worker
        plan = self.carrier.plan(lambda zone: CarryGoal(self.target, UP, zone, zone))
        return SkillProgram(plan, (*self._to_arrival(plan), Wait(self.params.handover_timeout), LetGo(),
                                   Open(self.carrier.gripper_steps()), Leave(plan.leave)), self.dt)

    def _taken(self) -> bool:
        return self.taken(self.wc)

    def _unreachable(self, error: PathError) -> str:
        return f"cannot hand {self.part} over at {np.round(self.target.pos, 3).tolist()}: {error}"

    def _outcome(self) -> SkillResult:
        return self._finish(SkillStatus.OK, f"{self.part} handed over {self._release_error * 1000:.1f} mm "
                            "from the handover pose", self._release_error)


def pick_place(workcell, part: str, target_pos, target_quat, **kwargs) -> PickPlace:
    """A :class:`PickPlace` skill (not started: step it, or call ``run_to_completion``)."""
    return PickPlace(workcell, part, target_pos, target_quat, **kwargs)


def handover(workcell, part: str, pos, quat, taken: Callable[[object], bool] | None = None,
             **kwargs) -> Handover:
    """A :class:`Handover` skill (not started: step it, or call ``run_to_completion``)."""
    return Handover(workcell, part, pos, quat, taken, **kwargs)
