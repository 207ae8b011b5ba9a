"""The robot's side of the loop: dispatch an action to a robot skill and step it with the physics.

A robot action is :class:`~ergosim.robot.skills.PickPlace` (the robot puts the part on its target, seats
it along its slot's axis, holds a fastener for its turns, or gives it to the receiver of a handover) or,
where the action names a handover pose (paper §7.2), :class:`~ergosim.robot.skills.Handover`: the robot
brings the part to that pose and waits until the worker's hand holds it. Skills set the controls one
physics step at a time, so while a skill runs the plant steps MuJoCo one step per skill step.

Two speeds time the robot (:mod:`ergosim.robot.trajectory`): ``ee_speed`` caps the contact-critical
segments (the paper's conservative 0.05 m/s, §7.2) and ``transit_speed`` the free-space transits (ISO
10218-1:2011 §5.6 reduced speed, 0.25 m/s).
"""

from __future__ import annotations

import mujoco

from ergosim.quat import to_mat
from ergosim.robot.kinematics import ArmKinematics
from ergosim.robot.skills import Handover, PickPlace, SkillParams
from ergosim.robot.status import SkillResult
from ergosim.robot.trajectory import CONTACT_SPEED, TRANSIT_SPEED, MotionLimits

__all__ = ["RobotTrack", "RobotGroup"]


class RobotTrack:
    """One robot in one workcell: ``robot`` its name (the task agent; default the cell's first robot).
    ``ee_speed`` [m/s]: TCP speed of contact-critical segments; ``transit_speed`` [m/s]: TCP speed of
    free-space transits. ``results``: every finished skill's result (with its time per phase), in order."""

    def __init__(self, cell, ee_speed: float = CONTACT_SPEED, transit_speed: float = TRANSIT_SPEED,
                 robot: str | None = None) -> None:
        self.cell = cell
        handle = cell.robot(robot)
        self.name = handle.name
        self.kin = ArmKinematics(handle.robot, cell.robot_home(handle.name))
        self.params = SkillParams(limits=MotionLimits(speed=ee_speed, transit_speed=transit_speed))
        self.skill = None
        self.result: SkillResult | None = None
        self.results: list[SkillResult] = []
        self.started: list[float] = []
        """Sim time [s] each skill of :attr:`results` (and the one running) was dispatched."""
        self.waiting = False
        self.speed = 1.0
        """Speed and separation monitoring's factor on the planned motion, in [0, 1]
        (:mod:`ergosim.robot.ssm`): the skill's clock advances by this much per physics step."""
        self._clock = 0.0

    @property
    def active(self) -> bool:
        return self.skill is not None and self.result is None

    @property
    def done(self) -> bool:
        return not self.active

    @property
    def ok(self) -> bool:
        return self.result is not None and self.result.ok

    @property
    def status_name(self) -> str:
        return "idle" if self.result is None else self.result.status.value

    @property
    def message(self) -> str:
        return "" if self.result is None else self.result.message

    def start(self, geom, plant=None) -> None:
        """Dispatch ``geom`` (an :class:`~ergosim.scenes.workcell.ActionGeometry`) to the matching skill."""
        self.result, self.waiting = None, False
        self.started.append(plant.time if plant is not None else float("nan"))
        self.skill = self.skill_for(geom)

    def planned_time(self, geom) -> float:
        """The robot's expected time for ``geom`` from the scene as it is now [s] (its planned trajectory;
        NaN if unreachable); nothing moves."""
        return self.skill_for(geom).planned_time()

    def planned_leave(self, geom) -> float:
        """The robot's expected way home for ``geom`` after it has let the part go [s] (NaN if unreachable);
        nothing moves."""
        return self.skill_for(geom).planned_leave()

    @property
    def released(self) -> bool:
        """The running skill has let its part go and is on its way home."""
        return self.active and self.skill.released

    def skill_for(self, geom):
        """The skill that does ``geom``, not started."""
        cell = self.cell
        if geom.handover is not None:
            pos, quat = cell.site_pose(geom.handover)
            return Handover(cell, geom.part, pos, quat, taken=self._taken(geom.part), kin=self.kin,
                            params=self.params, robot=self.name)
        pos, quat = cell.site_pose(geom.target)
        approach = None
        if geom.seats:
            # the part slides in along its slot's axis: the seat site's axis that the part's insert axis takes
            axis = "xyz".index(cell.config.part(geom.part).insert_axis)
            approach = to_mat(quat)[:, axis]
        return PickPlace(cell, geom.part, pos, quat, approach=approach, seat=geom.seats,
                         hold=geom.turn_time, receive=geom.received, kin=self.kin, params=self.params,
                         robot=self.name)

    def _taken(self, part: str):
        def taken(wc) -> bool:
            self.waiting = True  # called only once the part is at the handover pose
            return any(wc.is_held(h, part) for h in wc.holders if h not in wc.robots)
        return taken

    @property
    def moving(self) -> bool:
        """A skill is running a motion phase (not the gripper, nor holding the part out at a handover)."""
        return self.active and self.skill.phase in ("transit", "contact", "home")

    def control(self, data: mujoco.MjData) -> None:
        """Set the controls for the coming physics step. Below full speed (:attr:`speed`) the skill's clock
        advances by the factor only, and the arm holds its last joint targets in between (a stop at 0)."""
        if self.result is not None:
            return
        if self.speed < 1.0:
            self._clock += self.speed
            if self._clock < 1.0:
                return
            self._clock -= 1.0
        res = self.skill.step(data)
        if res is not None:
            self.result = res
            self.results.append(res)

    def advance(self, model: mujoco.MjModel, data: mujoco.MjData, n: int) -> None:
        """``n`` physics steps, the skill setting the controls before each."""
        for _ in range(n):
            self.control(data)
            mujoco.mj_step(model, data)


class RobotGroup:
    """Several robots acting at once (parallel execution): every active skill sets its controls before each
    physics step, then MuJoCo steps once. Stands in for one :class:`RobotTrack` as the plant's ``robot``."""

    def __init__(self, tracks) -> None:
        self.tracks = tuple(tracks)

    @property
    def active(self) -> bool:
        return any(t.active for t in self.tracks)

    def advance(self, model: mujoco.MjModel, data: mujoco.MjData, n: int) -> None:
        for _ in range(n):
            for t in self.tracks:
                t.control(data)
            mujoco.mj_step(model, data)
