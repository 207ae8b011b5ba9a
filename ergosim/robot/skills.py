"""Robot skills on a workcell: pick-and-place and handover (paper §7), steppable one physics step at a time.

Controller = pinocchio (plans every joint target before the first step); plant = MuJoCo (position
actuators track the targets under ``mj_step``). A skill is a generator program: :meth:`Skill.step` sets the
controls for the coming physics step and returns None while running, the :class:`SkillResult` once done;
the caller then calls ``mj_step``. Failures come back as statuses, never as exceptions from deep inside.

The gripper closes on the part for real; only when both fingertips touch it is the hand-part weld switched
on (and off again at release, after which the part rests or falls under gravity).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Generator, Iterator
from dataclasses import dataclass

import mujoco
import numpy as np

from ergosim.robot.ik import solve_ik
from ergosim.robot.kinematics import PandaKinematics
from ergosim.robot.mjcf import HOME_QPOS
from ergosim.robot.status import SkillResult, SkillStatus
from ergosim.robot.trajectory import (
    BaseFrame,
    MotionLimits,
    PathError,
    Pose,
    joint_trajectory,
    segment_trajectory,
    transit_trajectory,
)

__all__ = ["SkillParams", "Skill", "PickPlace", "Handover", "pick_place", "handover"]

Program = Generator[None, None, SkillResult]


@dataclass(frozen=True)
class SkillParams:
    """``approach`` [m] stand-off before grasp/place along the approach direction; ``lift`` [m] extra height
    of the carry above both stand-offs; ``finger_speed`` [m/s] per finger; ``settle`` [s] pause after
    closing/opening; ``handover_timeout`` [s]; ``place_drop`` [m] release height above the target."""

    limits: MotionLimits = MotionLimits()
    approach: float = 0.10
    insert_approach: float = 0.06
    lift: float = 0.05
    finger_speed: float = 0.05
    settle: float = 0.25
    handover_timeout: float = 30.0
    place_drop: float = 0.002
    drop_check_every: int = 25


def _quat_to_mat(q: np.ndarray) -> np.ndarray:
    m = np.empty(9)
    mujoco.mju_quat2Mat(m, np.asarray(q, dtype=float))
    return m.reshape(3, 3)


def _flip_z(rot: np.ndarray) -> np.ndarray:
    """The same top-down grasp turned 180 deg about the TCP z axis (fingers swap sides)."""
    return rot @ np.diag([-1.0, -1.0, 1.0])


class Skill(ABC):
    """A robot skill bound to a workcell (the extension point for new skills): subclasses write
    :meth:`_program`, a generator yielding once per physics step and returning a SkillResult. ``robot``:
    which of the cell's robots (its task agent's name; default the first)."""

    name = "skill"

    def __init__(self, workcell, part: str, kin: PandaKinematics | None = None,
                 params: SkillParams = SkillParams(), robot: str | None = None) -> None:
        self.wc = workcell
        handle = workcell.robot(robot)
        self.holder = handle.name  # the holder name of the robot (its task agent)
        self.part = part
        self.kin = kin or PandaKinematics()
        self.params = params
        m = workcell.model
        self.dt = float(m.opt.timestep)
        self._arm_q = handle.arm_qpos
        self._finger_q = handle.finger_qpos
        self._tcp = handle.tcp
        self._arm_ctrl, self._grip = handle.arm_ctrl, handle.grip_ctrl
        self._pads = [{g for g in range(m.ngeom) if m.geom_bodyid[g] == m.body(f).id and m.geom_contype[g]}
                      for f in handle.fingers]
        self._gripper_open = handle.gripper_open(m)
        pos, quat = workcell.robot_base_pose(handle.name)
        self.base = BaseFrame(pos, _quat_to_mat(quat))
        self._steps = 0
        self._result: SkillResult | None = None
        self._program_it: Iterator[None] | None = None

    # -- stepping -------------------------------------------------------------------------------------------
    def step(self, data: mujoco.MjData | None = None) -> SkillResult | None:
        """Set the controls for the next physics step; the result once the skill has finished."""
        if self._result is not None:
            return self._result
        if self._program_it is None:
            self._program_it = self._program()
        try:
            next(self._program_it)
            self._steps += 1
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

    @abstractmethod
    def _program(self) -> Program: ...

    # -- helpers for programs -------------------------------------------------------------------------------
    def _finish(self, status: SkillStatus, message: str, place_error: float = float("nan")) -> SkillResult:
        return SkillResult(self.name, self.part, status, message, self._steps * self.dt, place_error)

    def _q(self) -> np.ndarray:
        return self.wc.data.qpos[self._arm_q].copy()

    def _tcp_world(self) -> Pose:
        d = self.wc.data
        return Pose(d.site_xpos[self._tcp].copy(), d.site_xmat[self._tcp].reshape(3, 3).copy())

    def _site_world(self, name: str) -> Pose:
        pos, quat = self.wc.site_pose(name)
        return Pose(pos, _quat_to_mat(quat))

    def _plan(self, q0: np.ndarray, waypoints: list[tuple[Pose, str]]) -> tuple[np.ndarray, np.ndarray]:
        """Chain moves through world ``waypoints`` (pose, "line" | "joint") from configuration ``q0``.

        "line": the TCP goes straight (approach, descent, insertion, lift). "joint": a joint-space transit
        to an IK solution near the ready pose (large moves), replaced by a straight line if the TCP would
        dip more than 5 cm below both ends. Returns the (n, 7) joint targets and the final configuration;
        raises PathError."""
        q = np.asarray(q0, dtype=float)
        start = Pose(*self.kin.fk(q))
        lim = self.params.limits
        parts = []
        for pose_w, mode in waypoints:
            goal = self.base.to_base(pose_w)
            if np.linalg.norm(goal.pos - start.pos) < 1e-6 and np.allclose(goal.rot, start.rot, atol=1e-9):
                continue
            traj = None
            if mode == "joint":
                res = solve_ik(self.kin, goal.pos, goal.rot, self.kin.home, seeds=[q])
                if not res.ok:
                    raise PathError(f"no IK solution at {np.round(goal.pos, 3).tolist()} (base frame), "
                                    f"{res.pos_error * 1000:.0f} mm and {res.rot_error_deg:.0f} deg short",
                                    res.pos_error)
                traj, low = transit_trajectory(self.kin, q, res.q, lim, self.dt)
                if low < min(start.pos[2], goal.pos[2]) - 0.05:
                    traj = None
            if traj is None:
                traj = segment_trajectory(self.kin, q, start, goal, lim, self.dt)
            parts.append(traj)
            q, start = traj[-1], goal
        return (np.concatenate(parts) if parts else q[None, :]), q

    def _follow(self, traj: np.ndarray, grip: float | None = None) -> Iterator[None]:
        ctrl = self.wc.data.ctrl
        if grip is not None:
            ctrl[self._grip] = grip
        arm = self._arm_ctrl
        for row in traj:
            ctrl[arm] = row
            yield

    def _hold(self, seconds: float) -> Iterator[None]:
        for _ in range(max(1, int(round(seconds / self.dt)))):
            yield

    def _touching(self, body: int) -> tuple[bool, bool]:
        d, m = self.wc.data, self.wc.model
        left = right = False
        lp, rp = self._pads
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
        False if they close past the part's faces (``width`` [m] apart) or stall without touching both."""
        d = self.wc.data
        body = self.wc.model.body(body_name).id
        rate = self.params.finger_speed * self.dt
        stalled = 0
        g = self._grip
        while True:
            d.ctrl[g] = max(0.0, d.ctrl[g] - rate)
            yield
            left, right = self._touching(body)
            if left and right:
                self.wc.grasp(self.holder, body_name)
                d.ctrl[g] = d.qpos[self._finger_q].mean()  # hold the fingers where they touch the part
                return True
            stalled = stalled + 1 if d.ctrl[g] == 0.0 else 0
            if d.qpos[self._finger_q].mean() < width / 2 - 0.004 or stalled * self.dt > 0.3:
                return False

    def _open(self) -> Iterator[None]:
        d = self.wc.data
        rate = self.params.finger_speed * self.dt
        g = self._grip
        while d.ctrl[g] < self._gripper_open:
            d.ctrl[g] = min(self._gripper_open, d.ctrl[g] + rate)
            yield

    def _home(self, q_from: np.ndarray, tcp_from: Pose) -> np.ndarray:
        """Up by ``lift`` + ``approach``, straight to the home TCP, then joint-interpolate onto home."""
        p = self.params
        home_tcp = self.base.to_world(Pose(*self.kin.fk(self.kin.home)))
        up = Pose(tcp_from.pos + [0, 0, p.approach], tcp_from.rot)
        high = max(up.pos[2], home_tcp.pos[2])
        try:
            traj, q = self._plan(q_from, [(Pose(np.r_[up.pos[:2], high], tcp_from.rot), "line"),
                                          (home_tcp, "joint")])
        except PathError:
            traj, q = q_from[None, :], q_from
        return np.concatenate([traj, joint_trajectory(q, np.array(HOME_QPOS), self.kin, p.limits, self.dt)])

    def _grasp_candidates(self, part_body: str) -> list[Pose]:
        site = self._site_world(self.wc.grasp_site(self.part))
        return [site, Pose(site.pos, _flip_z(site.rot))]


class _Carry(Skill):
    """Shared program: reach, grasp, carry to a TCP pose; subclasses decide what happens there."""

    def __init__(self, workcell, part: str, kin: PandaKinematics | None = None,
                 params: SkillParams = SkillParams(), robot: str | None = None) -> None:
        super().__init__(workcell, part, kin, params, robot)
        self.grasp_site = workcell.grasp_site(part)
        self.grasp_body = workcell.grasp_body(part)
        self.width = workcell.grip_width(self.grasp_body)

    def _carry_waypoints(self, g: Pose, rel_p: np.ndarray, rel_r: np.ndarray, target: Pose,
                         approach_dir: np.ndarray, stand: float) -> tuple[list[tuple[Pose, float]], Pose]:
        """Carry waypoints from grasp TCP ``g`` for a part held at (rel_p, rel_r) in the TCP frame, and the
        TCP pose that puts the part's origin on ``target``."""
        p = self.params
        place_rot = target.rot @ rel_r.T
        place = Pose(target.pos - place_rot @ rel_p + approach_dir * p.place_drop, place_rot)
        pre_grasp = Pose(g.pos + [0, 0, p.approach], g.rot)
        pre_place = Pose(place.pos + approach_dir * stand, place_rot)
        carry_z = max(pre_grasp.pos[2], pre_place.pos[2], self.wc.config.carry_height) + p.lift
        return [(pre_grasp, "line"), (Pose(np.r_[g.pos[:2], carry_z], g.rot), "line"),
                (Pose(np.r_[pre_place.pos[:2], carry_z], place_rot), "joint"),
                (pre_place, "line"), (place, "line")], place

    def _plan_carry(self, target: Pose, approach_dir: np.ndarray, stand: float):
        """Plan reach + carry for the part's origin to end at ``target`` (world), arriving along
        ``-approach_dir`` from ``stand`` [m] away. Returns (reach, carry, q_place, place_tcp) or raises."""
        part_pos, part_quat = self.wc.body_pose(self.part)
        part_rot = _quat_to_mat(part_quat)
        q0, tcp0 = self._q(), self._tcp_world()
        error: PathError | None = None
        for g in self._grasp_candidates(self.grasp_body):
            rel_p, rel_r = g.rot.T @ (part_pos - g.pos), g.rot.T @ part_rot
            way, place = self._carry_waypoints(g, rel_p, rel_r, target, approach_dir, stand)
            pre_grasp = way[0][0]
            reach_z = max(tcp0.pos[2], pre_grasp.pos[2])
            try:
                reach, q_g = self._plan(q0, [(Pose(np.r_[tcp0.pos[:2], reach_z], tcp0.rot), "line"),
                                             (pre_grasp, "joint"), (g, "line")])
                carry, q_p = self._plan(q_g, way)
                self._plan_args = (g, target, approach_dir, stand)
                return reach, carry, q_p, place
            except PathError as err:
                error = err
        raise error  # type: ignore[misc]

    def _replan_carry(self, carry: np.ndarray) -> np.ndarray:
        """Re-plan the carry from the actual grasp (the fingers may have shifted the part); keeps the
        planned one if the new one fails."""
        g, target, approach_dir, stand = self._plan_args
        tcp = self._tcp_world()
        pos, quat = self.wc.body_pose(self.part)
        rel_p, rel_r = tcp.rot.T @ (pos - tcp.pos), tcp.rot.T @ _quat_to_mat(quat)
        way, _ = self._carry_waypoints(g, rel_p, rel_r, target, approach_dir, stand)
        try:
            new, _ = self._plan(self._planned_q_grasp, way)
        except PathError:
            return carry
        return new

    def _carry(self, reach: np.ndarray, carry: np.ndarray) -> Generator[None, None, SkillResult | None]:
        """Execute reach, grasp and carry; a failure result (after returning home) or None on arrival."""
        self._planned_q_grasp = reach[-1]
        yield from self._follow(reach, grip=self._gripper_open)
        yield from self._hold(0.1)
        grasped = yield from self._close_on(self.grasp_body, self.width)
        if not grasped:
            yield from self._open()
            yield from self._follow(self._home(self._q(), self._tcp_world()))
            return self._finish(SkillStatus.NOT_GRASPED,
                                f"the fingers closed without holding {self.part} "
                                f"(grasp site {self.grasp_site})")
        yield from self._hold(self.params.settle)
        carry = self._replan_carry(carry)
        d, site = self.wc.data, self.wc.model.site(self.grasp_site).id
        every = self.params.drop_check_every
        tol = self.wc.config.grasp_tolerance
        tcp = self._tcp_world()
        grip = tcp.rot.T @ (d.site_xpos[site] - tcp.pos)  # where the part sits in the hand
        arm = self._arm_ctrl
        for i, row in enumerate(carry):
            d.ctrl[arm] = row
            yield
            if i % every == 0 and np.linalg.norm(d.site_xmat[self._tcp].reshape(3, 3).T
                                                 @ (d.site_xpos[site] - d.site_xpos[self._tcp]) - grip) > tol:
                self.wc.release(self.holder, self.grasp_body)
                yield from self._open()
                yield from self._follow(self._home(self._q(), self._tcp_world()))
                return self._finish(SkillStatus.DROPPED, f"{self.part} left the gripper while carried")
        yield from self._hold(self.params.settle)
        return None


class PickPlace(_Carry):
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
                 hold: float = 0.0, receive: bool = False, kin: PandaKinematics | None = None,
                 params: SkillParams = SkillParams(), robot: str | None = None) -> None:
        super().__init__(workcell, part, kin, params, robot)
        self.target = Pose(np.asarray(target_pos, dtype=float), _quat_to_mat(target_quat))
        a = np.array([0.0, 0.0, 1.0]) if approach is None else np.asarray(approach, dtype=float)
        self.approach_dir = a / np.linalg.norm(a)
        self.seat = seat
        self.hold = float(hold)
        self.receive = receive

    def _program(self) -> Program:
        p = self.params
        stand = p.insert_approach if self.seat else p.approach
        try:
            reach, carry, q_place, place = self._plan_carry(self.target, self.approach_dir, stand)
            retreat, q_back = self._plan(q_place, [(Pose(place.pos + self.approach_dir * stand, place.rot),
                                                    "line")])
            home = self._home(q_back, Pose(place.pos + self.approach_dir * stand, place.rot))
        except PathError as err:
            yield
            return self._finish(SkillStatus.UNREACHABLE, f"cannot take {self.part} to "
                                f"{np.round(self.target.pos, 3).tolist()}: {err}")
        # Insertion is a weld within tolerance, not a contact fit: the fingers that hold the part down to
        # its seat pass the host's walls, as the last millimetres of a chamfered bore would let them.
        if self.seat:
            self.wc.host_robot_contacts(self.part, False)
        try:
            failure = yield from self._carry(reach, carry)
            if failure is not None:
                return failure
            if self.hold > 0:
                yield from self._hold(self.hold)
            received = self.wc.receive(self.part, self.target.pos) if self.receive else None
            self.wc.release(self.holder, self.grasp_body)
            seated = self.wc.seat(self.part) if self.seat else received
            yield from self._open()
            yield from self._hold(p.settle)
        finally:
            if self.seat:
                self.wc.host_robot_contacts(self.part, True)
        yield from self._follow(retreat)
        yield from self._follow(home)
        yield from self._hold(p.settle)
        error = float(np.linalg.norm(self.wc.body_pose(self.part)[0] - self.target.pos))
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


class Handover(_Carry):
    """Bring ``part`` to the world pose ``pos``/``quat`` (of the part's origin), hold it there until
    ``taken(workcell)`` is true (default: a worker hand weld holds it), let go, and return home."""

    name = "handover"

    def __init__(self, workcell, part: str, pos, quat, taken: Callable[[object], bool] | None = None, *,
                 kin: PandaKinematics | None = None, params: SkillParams = SkillParams(),
                 robot: str | None = None) -> None:
        super().__init__(workcell, part, kin, params, robot)
        self.target = Pose(np.asarray(pos, dtype=float), _quat_to_mat(quat))
        self.taken = taken or _worker_holds(part)
        self.hand_error = float("nan")

    def _program(self) -> Program:
        p = self.params
        up = np.array([0.0, 0.0, 1.0])
        try:
            reach, carry, q_place, place = self._plan_carry(self.target, up, 0.0)
            retreat, q_back = self._plan(q_place, [(Pose(place.pos + up * p.approach, place.rot), "line")])
            home = self._home(q_back, Pose(place.pos + up * p.approach, place.rot))
        except PathError as err:
            yield
            return self._finish(SkillStatus.UNREACHABLE, f"cannot hand {self.part} over at "
                                f"{np.round(self.target.pos, 3).tolist()}: {err}")
        failure = yield from self._carry(reach, carry)
        if failure is not None:
            return failure
        waited = 0
        while not self.taken(self.wc):
            waited += 1
            if waited * self.dt > p.handover_timeout:
                self.wc.release(self.holder, self.grasp_body)
                yield from self._open()
                yield from self._follow(home)
                return self._finish(SkillStatus.TIMEOUT, f"nobody took {self.part} within "
                                    f"{p.handover_timeout:.0f} s")
            yield
        error = float(np.linalg.norm(self.wc.body_pose(self.part)[0] - self.target.pos))
        self.wc.release(self.holder, self.grasp_body)
        yield from self._open()
        yield from self._follow(retreat)
        yield from self._follow(home)
        return self._finish(SkillStatus.OK, f"{self.part} handed over {error * 1000:.1f} mm from the "
                            "handover "
                            "pose", error)


def pick_place(workcell, part: str, target_pos, target_quat, **kwargs) -> PickPlace:
    """A :class:`PickPlace` skill (not started: step it, or call ``run_to_completion``)."""
    return PickPlace(workcell, part, target_pos, target_quat, **kwargs)


def handover(workcell, part: str, pos, quat, taken: Callable[[object], bool] | None = None,
             **kwargs) -> Handover:
    """A :class:`Handover` skill (not started: step it, or call ``run_to_completion``)."""
    return Handover(workcell, part, pos, quat, taken, **kwargs)
