"""The executing half of a robot skill: steps a planned :class:`~ergosim.robot.skill_program.SkillProgram`.

Controller = pinocchio (plans every joint target before the first step); plant = MuJoCo (position
actuators track the targets under ``mj_step``). :meth:`Skill.step` sets the controls for the coming physics
step and returns None while running, the :class:`~ergosim.robot.status.SkillResult` once done; the caller
then calls ``mj_step``. Failures come back as statuses, never as exceptions from deep inside.

The gripper closes on the part for real; only when both fingertips touch it is the hand-part weld switched
on (and off again at release, after which the part rests or falls under gravity). The executor is the only
part of a skill that changes the scene. The time a skill spends in each phase
(:data:`~ergosim.robot.status.SKILL_PHASES`) comes back in its result.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Generator, Iterator
from dataclasses import replace

import mujoco
import numpy as np

from ergosim.robot import skill_program as sp
from ergosim.robot.kinematics import ArmKinematics
from ergosim.robot.skill_motion import Motion, MotionPlanner
from ergosim.robot.skill_params import SkillParams
from ergosim.robot.skill_plan import CarryPlanner, RobotView
from ergosim.robot.status import SKILL_PHASES, SkillResult, SkillStatus
from ergosim.robot.trajectory import PathError

__all__ = ["Skill"]

Program = Generator[None, None, SkillResult]
Outcome = Generator[None, None, SkillResult | None]


class Skill(ABC):
    """A robot skill that carries ``part`` in ``workcell`` (the extension point for new skills): a subclass
    plans its program from the scene (:meth:`plan`) and says how it ended (:meth:`_outcome`); this class
    executes the program. ``robot``: which of the cell's robots (its task agent's name; default the
    first); ``kin``: its kinematics; ``params``: the skill parameters."""

    name = "skill"

    def __init__(self, workcell, part: str, kin: ArmKinematics | None = None,
                 params: SkillParams = SkillParams(), robot: str | None = None) -> None:
        self.wc = workcell
        handle = workcell.robot(robot)
        self.holder = handle.name  # the holder name of the robot (its task agent)
        self.part = part
        self.kin = kin or ArmKinematics(handle.robot, workcell.robot_home(handle.name))
        params = replace(params, limits=params.limits.for_robot(handle.robot))
        self.params = params
        self.dt = float(workcell.model.opt.timestep)
        self.robot = RobotView(workcell, handle)
        self.base = self.robot.base
        self.motion = MotionPlanner(self.kin, self.base, params, self.dt)
        self.carrier = CarryPlanner(self.robot, part, self.motion)
        self.program: sp.SkillProgram | None = None
        """The program being executed (planned at the first step)."""
        self.executed: list[tuple[sp.Segment, int]] = []
        """Each segment run so far and the physics steps it took (the last one: until the skill ended)."""
        self._steps = 0
        self._arrival = float("nan")
        self._phase = "transit"
        self._phase_steps = dict.fromkeys(SKILL_PHASES, 0)
        self._result: SkillResult | None = None
        self._program_it: Iterator[None] | None = None
        self._carried_to: np.ndarray | None = None  # where the executed carry ended
        self._contacts_off: list[str] = []
        self._seated = None  # the seat's or the receiver's verdict at the release
        self._release_error = float("nan")  # [m] of the part's origin to its target at the release

    # -- planning ---------------------------------------------------------------------------------------
    @abstractmethod
    def plan(self) -> sp.SkillProgram:
        """The skill's program from the scene as it is now; changes nothing. Raises PathError."""

    def plan_error(self) -> str | None:
        """Why this skill cannot be planned from the scene as it is now (where no IK solution exists, in the
        world frame: reaching, on the carry or on the way out), or None; nothing moves. The check before
        any physics (:func:`ergosim.experiment.scenario_check.check_reachability`) asks this."""
        try:
            self.plan()
        except PathError as err:
            return str(err)
        return None

    @abstractmethod
    def _unreachable(self, error: PathError) -> str:
        """The message of a skill that cannot be planned."""

    @abstractmethod
    def _outcome(self) -> SkillResult:
        """The result once every segment has run."""

    def planned_time(self) -> float:
        """How long the skill would take from the scene as it is now [s]: its program's planned physics
        steps (motions, pauses, the gripper; not a hand-over's wait for the worker), the expected robot
        duration of the time cost; NaN if unreachable. The scene is not changed."""
        try:
            return self.plan().planned_time
        except PathError:
            return float("nan")

    def planned_leave(self) -> float:
        """How long the skill's way home would take as planned [s]: its planned time less the time until
        its fingers have opened on the part it let go (:attr:`~ergosim.robot.skill_program.SkillProgram.
        release_steps`; 0 if it lets nothing go); NaN if unreachable. One plan."""
        try:
            program = self.plan()
        except PathError:
            return float("nan")
        return program.planned_time - program.release_steps * program.dt

    @property
    def released(self) -> bool:
        """The part is let go and the fingers have opened (:attr:`~ergosim.robot.skill_program.SkillProgram.
        release_index`): what follows is the way home. Asked every tick of a parallel run: no scan."""
        k = None if self.program is None else self.program.release_index
        return k is not None and len(self.executed) >= k

    @property
    def zone(self) -> float:
        """The contact zone [m] the program was planned with (``approach`` before it is planned)."""
        return self.params.approach if self.program is None else self.program.plan.zone

    # -- stepping ---------------------------------------------------------------------------------------
    def step(self, data: mujoco.MjData | None = None) -> SkillResult | None:
        """Set the controls for the next physics step; the result once the skill has finished."""
        if self._result is not None:
            return self._result
        if self._program_it is None:
            self._program_it = self._run()
        try:
            next(self._program_it)
            self._steps += 1
            self._phase_steps[self._phase] += 1
            return None
        except StopIteration as stop:
            self._result = stop.value
            return self._result

    def run_to_completion(self, max_time: float = 600.0) -> SkillResult:
        """Step the skill and the physics until done (or ``max_time`` [s] of simulated time)."""
        m, d = self.wc.model, self.wc.data
        for _ in range(int(max_time / self.dt)):
            res = self.step(d)
            if res is not None:
                return res
            mujoco.mj_step(m, d)
        return self._finish(SkillStatus.TIMEOUT, f"not finished after {max_time:.0f} s")

    @property
    def result(self) -> SkillResult | None:
        return self._result

    @property
    def phase(self) -> str:
        """The phase (one of :data:`~ergosim.robot.status.SKILL_PHASES`) of the last physics step set."""
        return self._phase

    def _finish(self, status: SkillStatus, message: str, place_error: float = float("nan")) -> SkillResult:
        phases = tuple((ph, n * self.dt) for ph, n in self._phase_steps.items())
        return SkillResult(self.name, self.part, status, message, self._steps * self.dt, place_error, phases,
                           self._arrival)

    # -- the program --------------------------------------------------------------------------------------
    def _run(self) -> Program:
        try:
            self.program = self.plan()
        except PathError as err:
            yield
            return self._finish(SkillStatus.UNREACHABLE, self._unreachable(err))
        try:
            for segment in self.program.segments:
                start = self._steps
                failure = yield from self._execute(segment)
                self.executed.append((segment, self._steps - start))
                if failure is not None:
                    return failure
        finally:
            while self._contacts_off:
                self.wc.host_robot_contacts(self._contacts_off.pop(), True)
        return self._outcome()

    def _execute(self, seg: sp.Segment) -> Outcome:
        """Run one segment; a failure result ends the skill."""
        match seg:
            case sp.Move():
                yield from self._follow(seg.motion, seg.grip)
            case sp.Pause():
                self._phase = seg.phase
                for _ in range(seg.steps):
                    yield
            case sp.Grasp():
                return (yield from self._grasp(seg))
            case sp.Carry():
                return (yield from self._carry())
            case sp.Arrive():
                self._arrival = self._steps * self.dt
            case sp.Wait():
                return (yield from self._wait(seg))
            case sp.LetGo():
                self._let_go(seg)
            case sp.Open():
                yield from self._open()
            case sp.Leave():
                yield from self._follow(self._way_out())
            case sp.Contacts():
                self.wc.host_robot_contacts(seg.part, seg.enabled)
                if seg.enabled:
                    self._contacts_off.remove(seg.part)
                else:
                    self._contacts_off.append(seg.part)
        return None

    def _taken(self) -> bool:
        """Someone has taken the part the robot holds out: a hand-over's
        :class:`~ergosim.robot.skill_program.Wait` ends."""
        return True

    # -- segments -----------------------------------------------------------------------------------------
    def _follow(self, motion: Motion, grip: float | None = None) -> Iterator[None]:
        ctrl = self.wc.data.ctrl
        if grip is not None:
            ctrl[self.robot.handle.grip_ctrl] = grip
        arm = self.robot.handle.arm_ctrl
        i = 0
        for phase, n in motion.spans:
            self._phase = phase
            for row in motion.q[i:i + n]:
                ctrl[arm] = row
                yield
            i += n

    def _home_from_here(self) -> Motion:
        return self.motion.home(self.robot.q(), self.robot.tcp())

    def _way_out(self) -> Motion:
        """The planned way out, preceded by a contact-speed joint move from where the re-planned carry
        actually ended (a fraction of a millimetre away), so the retreat starts where the arm is."""
        plan = self.program.plan
        bridge = self.motion.bridge(self._carried_to, plan.carry.end)
        return bridge.then(plan.leave) if bridge.steps else plan.leave

    def _grasp(self, seg: sp.Grasp) -> Outcome:
        if (yield from self._close_on(seg.body, seg.width)):
            return None
        yield from self._open()
        yield from self._follow(self._home_from_here())
        return self._finish(SkillStatus.NOT_GRASPED,
                            f"the fingers closed without holding {self.part} (grasp site {seg.site})")

    def _carry(self) -> Outcome:
        """Carry along the carry re-planned from the actual grasp, checking every ``drop_check_every``
        steps that the part sits in the hand where it was taken."""
        carry = self.carrier.replan_carry(self.program.plan)
        self._carried_to = carry.end
        d, site = self.wc.data, self.wc.model.site(self.carrier.grasp_site).id
        every = self.params.drop_check_every
        tol = self.wc.config.grasp_tolerance
        tcp = self.robot.tcp()
        grip = tcp.rot.T @ (d.site_xpos[site] - tcp.pos)  # where the part sits in the hand
        arm, tcp_site = self.robot.handle.arm_ctrl, self.robot.handle.tcp
        for i, (row, phase) in enumerate(zip(carry.q, carry.phases(), strict=True)):
            self._phase = phase
            d.ctrl[arm] = row
            yield
            if i % every == 0 and np.linalg.norm(d.site_xmat[tcp_site].reshape(3, 3).T
                                                 @ (d.site_xpos[site] - d.site_xpos[tcp_site]) - grip) > tol:
                self.wc.release(self.holder, self.carrier.grasp_body)
                yield from self._open()
                yield from self._follow(self._home_from_here())
                return self._finish(SkillStatus.DROPPED, f"{self.part} left the gripper while carried")
        return None

    def _wait(self, seg: sp.Wait) -> Outcome:
        waited = 0
        self._phase = "wait"
        while not self._taken():
            waited += 1
            if waited * self.dt > seg.timeout:
                self.wc.release(self.holder, self.carrier.grasp_body)
                yield from self._open()
                yield from self._follow(self._way_out())
                return self._finish(SkillStatus.TIMEOUT,
                                    f"nobody took {self.part} within {seg.timeout:.0f} s")
            yield
        return None

    def _let_go(self, seg: sp.LetGo) -> None:
        target = self.program.plan.goal.target.pos
        self._release_error = float(np.linalg.norm(self.wc.body_pose(self.part)[0] - target))
        received = self.wc.receive(self.part, target) if seg.receive else None
        self.wc.release(self.holder, self.carrier.grasp_body)
        self._seated = self.wc.seat(self.part) if seg.seat else received

    def _touching(self, body: int) -> tuple[bool, bool]:
        d, m = self.wc.data, self.wc.model
        left = right = False
        lp, rp = self.robot.pads
        for i in range(d.ncon):
            c = d.contact[i]
            g1, g2 = c.geom1, c.geom2
            b1, b2 = m.geom_bodyid[g1], m.geom_bodyid[g2]
            if b1 == body or b2 == body:
                other = g2 if b1 == body else g1
                left |= other in lp
                right |= other in rp
        return left, right

    def _close_on(self, body_name: str, width: float) -> Generator[None, None, bool]:
        """Close the fingers at ``finger_speed`` until both touch ``body_name``, then weld it to the hand.
        False if they close ``close_overshoot`` past the part's faces (``width`` [m] apart) or stall
        ``close_stall`` without touching both."""
        d, p = self.wc.data, self.params
        body = self.wc.model.body(body_name).id
        rate = p.finger_speed * self.dt
        stalled = 0
        self._phase = "gripper"
        g, fingers = self.robot.handle.grip_ctrl, self.robot.handle.finger_qpos
        while True:
            d.ctrl[g] = max(0.0, d.ctrl[g] - rate)
            yield
            left, right = self._touching(body)
            if left and right:
                self.wc.grasp(self.holder, body_name)
                d.ctrl[g] = d.qpos[fingers].mean()  # hold the fingers where they touch the part
                return True
            stalled = stalled + 1 if d.ctrl[g] == 0.0 else 0
            if d.qpos[fingers].mean() < width / 2 - p.close_overshoot or stalled * self.dt > p.close_stall:
                return False

    def _open(self) -> Iterator[None]:
        d = self.wc.data
        rate = self.params.finger_speed * self.dt
        self._phase = "gripper"
        g, wide = self.robot.handle.grip_ctrl, self.robot.gripper_open
        while d.ctrl[g] < wide:
            d.ctrl[g] = min(wide, d.ctrl[g] + rate)
            yield
