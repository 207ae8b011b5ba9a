"""Robot skills on a workcell: pick-and-place and handover (paper §7), steppable one physics step at a time.

Controller = pinocchio (plans every joint target before the first step); plant = MuJoCo (position
actuators track the targets under ``mj_step``). A skill is a generator program: :meth:`Skill.step` sets the
controls for the coming physics step and returns None while running, the :class:`SkillResult` once done;
the caller then calls ``mj_step``. Failures come back as statuses, never as exceptions from deep inside.

The gripper closes on the part for real; only when both fingertips touch it is the hand-part weld switched
on (and off again at release, after which the part rests or falls under gravity).

Every motion segment is contact-critical or a transit (:mod:`ergosim.robot.trajectory`). A pick descends
at the transit speed to ``contact`` above the grasp and goes the rest of the way, and the first ``contact``
of the lift-off, at the contact speed; a place or a handover arrives the same way; an insertion runs its
whole stroke at the contact speed; the retreat after letting go is contact-critical, the way home a
transit. The time a skill spends in each phase (:data:`~ergosim.robot.status.SKILL_PHASES`) comes back in
its result.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Generator, Iterator
from dataclasses import dataclass
from typing import NamedTuple

import mujoco
import numpy as np

from ergosim.robot.ik import solve_ik
from ergosim.robot.kinematics import PandaKinematics
from ergosim.robot.status import SKILL_PHASES, SkillResult, SkillStatus
from ergosim.robot.trajectory import (
    BaseFrame,
    MotionLimits,
    PathError,
    Pose,
    line_trajectory,
    transit_trajectory,
)

__all__ = ["SkillParams", "Skill", "PickPlace", "Handover", "pick_place", "handover"]

Program = Generator[None, None, SkillResult]


@dataclass(frozen=True)
class SkillParams:
    """Waypoint layout and gripper timing of the skills. Lengths [m], times [s].

    ``approach``: stand-off of the pre-grasp and pre-place poses along the approach direction, where the
    transits end; ``contact_margin``: added to the contact zone, the TCP distance from the grasp at which
    the fingertips first reach the part (:meth:`_Carry.contact_zone`), that runs at the contact speed
    at the end of an approach and the start of a lift-off or a retreat; ``insert_approach``: the insertion
    stroke, all at the contact speed;
    ``lift``: extra height of the carry above both stand-offs; ``finger_speed`` [m/s] per finger;
    ``settle``: pause after closing/opening; ``handover_timeout``; ``place_drop``: release height above the
    target; ``drop_check_every`` [physics steps] between checks that the part is still in the hand."""

    limits: MotionLimits = MotionLimits()
    approach: float = 0.10  # assumed: clears the parts' 3-4 cm heights and the fingertips below the TCP
    contact_margin: float = 0.01  # assumed: 1 cm of contact-speed travel before the first possible touch
    insert_approach: float = 0.06  # assumed: a profile's 3 cm sleeve engagement twice over
    lift: float = 0.05  # assumed
    finger_speed: float = 0.05  # assumed: 0.1 m/s of opening, frankx's Gripper::max_speed for the Franka Hand
    settle: float = 0.25  # assumed
    handover_timeout: float = 30.0
    place_drop: float = 0.002
    drop_check_every: int = 25


class _Motion(NamedTuple):
    """A planned motion: (n, 7) joint targets [rad], one per physics step, and the (phase, steps) spans of
    its rows in order."""

    q: np.ndarray
    spans: tuple[tuple[str, int], ...]

    @property
    def end(self) -> np.ndarray:
        return self.q[-1]

    def then(self, other: _Motion) -> _Motion:
        return _Motion(np.concatenate([self.q, other.q]), self.spans + other.spans)

    def phases(self) -> list[str]:
        """The phase of every row (n,)."""
        return [ph for ph, n in self.spans for _ in range(n)]


class _Waypoint(NamedTuple):
    """Where the TCP goes next (world pose) and how: ``mode`` "line" (straight) or "joint" (joint-space);
    ``kind`` of segment; a line's first ``slow_first`` and last ``slow_last`` metres are contact-critical."""

    pose: Pose
    mode: str = "line"
    kind: str = "transit"
    slow_first: float = 0.0
    slow_last: float = 0.0


def _runs(labels: np.ndarray) -> list[tuple[str, int]]:
    """(label, length) of each run of equal consecutive ``labels`` (n,)."""
    cut = np.flatnonzero(labels[1:] != labels[:-1]) + 1
    edges = np.concatenate([[0], cut, [len(labels)]])
    return [(str(labels[i]), int(j - i)) for i, j in zip(edges[:-1], edges[1:])]


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
        self._arrival = float("nan")
        self._phase = "transit"
        self._phase_steps = dict.fromkeys(SKILL_PHASES, 0)
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

    @abstractmethod
    def _program(self) -> Program: ...

    # -- helpers for programs -------------------------------------------------------------------------------
    def _finish(self, status: SkillStatus, message: str, place_error: float = float("nan")) -> SkillResult:
        phases = tuple((ph, n * self.dt) for ph, n in self._phase_steps.items())
        return SkillResult(self.name, self.part, status, message, self._steps * self.dt, place_error, phases,
                           self._arrival)

    def _q(self) -> np.ndarray:
        return self.wc.data.qpos[self._arm_q].copy()

    def _tcp_world(self) -> Pose:
        d = self.wc.data
        return Pose(d.site_xpos[self._tcp].copy(), d.site_xmat[self._tcp].reshape(3, 3).copy())

    def _site_world(self, name: str) -> Pose:
        pos, quat = self.wc.site_pose(name)
        return Pose(pos, _quat_to_mat(quat))

    def _plan(self, q0: np.ndarray, waypoints: list[_Waypoint], phase: str | None = None) -> _Motion:
        """Chain moves through world ``waypoints`` from configuration ``q0``.

        "line": the TCP goes straight (approach, descent, insertion, lift). "joint": a joint-space transit
        to an IK solution near the ready pose (large moves), replaced by a straight line if the TCP would
        dip more than 5 cm below both ends. Each move keeps the speed caps of its kind; its steps are
        labelled ``contact`` where contact-critical, else with ``phase`` (default: the kind). Raises
        PathError."""
        q = np.asarray(q0, dtype=float)
        start = Pose(*self.kin.fk(q))
        lim = self.params.limits
        rows, spans = [], []
        for way in waypoints:
            goal = self.base.to_base(way.pose)
            if np.linalg.norm(goal.pos - start.pos) < 1e-6 and np.allclose(goal.rot, start.rot, atol=1e-9):
                continue
            traj = None
            label = "contact" if way.kind == "contact" else (phase or way.kind)
            if way.mode == "joint":
                res = solve_ik(self.kin, goal.pos, goal.rot, self.kin.home, seeds=[q, *self._wrist_seeds(q)])
                if not res.ok:
                    raise PathError(f"no IK solution at {np.round(way.pose.pos, 3).tolist()} (world; "
                                    f"{np.round(goal.pos, 3).tolist()} in the base frame), "
                                    f"{res.pos_error * 1000:.0f} mm and {res.rot_error_deg:.0f} deg short",
                                    res.pos_error)
                traj = self._joint_move(q, res.q, start.pos[2], goal.pos[2], way.kind)
                if traj is not None:
                    spans.append((label, len(traj)))
            if traj is None:
                try:
                    traj, slow = line_trajectory(self.kin, q, start, goal, lim, self.dt, way.kind,
                                                 way.slow_first, way.slow_last)
                except PathError as err:  # say where in the world, too
                    if err.point is None:
                        raise
                    world = self.base.to_world(Pose(np.asarray(err.point), np.eye(3))).pos
                    raise PathError(f"{err}; in the world frame {np.round(world, 3).tolist()}",
                                    err.pos_error, err.point) from None
                spans += _runs(np.where(slow, "contact", label))
            rows.append(traj)
            q, start = traj[-1], goal
        if not rows:
            return _Motion(q[None, :], ((phase or "transit", 1),))
        return _Motion(np.concatenate(rows), tuple(spans))

    def _wrist_seeds(self, q: np.ndarray) -> list[np.ndarray]:
        """``q`` with the last (wrist) joint wound by -1, +1, -2, +2 rad: the IK from home and from ``q``
        stalls when the goal's hand yaw needs the wrist unwound past its limit the other way round."""
        out = []
        for turn in (-1.0, 1.0, -2.0, 2.0):
            seed = np.array(q, dtype=float)
            seed[-1] = np.clip(seed[-1] + turn, self.kin.lower[-1], self.kin.upper[-1])
            out.append(seed)
        return out

    def _joint_move(self, q: np.ndarray, q_goal: np.ndarray, z0: float, z1: float,
                    kind: str) -> np.ndarray | None:
        """A joint-space move, or None if its TCP dips more than 5 cm below both ends (base-frame z [m])."""
        traj, low = transit_trajectory(self.kin, q, q_goal, self.params.limits, self.dt, kind)
        return None if low < min(z0, z1) - 0.05 else traj

    def _follow(self, motion: _Motion, grip: float | None = None) -> Iterator[None]:
        ctrl = self.wc.data.ctrl
        if grip is not None:
            ctrl[self._grip] = grip
        arm = self._arm_ctrl
        i = 0
        for phase, n in motion.spans:
            self._phase = phase
            for row in motion.q[i:i + n]:
                ctrl[arm] = row
                yield
            i += n

    def _hold(self, seconds: float, phase: str = "gripper") -> Iterator[None]:
        self._phase = phase
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
        self._phase = "gripper"
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
        self._phase = "gripper"
        g = self._grip
        while d.ctrl[g] < self._gripper_open:
            d.ctrl[g] = min(self._gripper_open, d.ctrl[g] + rate)
            yield

    def _home(self, q_from: np.ndarray, tcp_from: Pose, slow_first: float = 0.0) -> _Motion:
        """Up by ``approach`` (at least to the home TCP's height), its first ``slow_first`` [m] at the
        contact speed, then a joint-space transit onto the ready configuration; labelled ``home`` where not
        contact-critical."""
        p = self.params
        home_base = Pose(*self.kin.fk(self.kin.home))
        high = max(tcp_from.pos[2] + p.approach, self.base.to_world(home_base).pos[2])
        up = None
        try:
            up = self._plan(q_from, [_Waypoint(Pose(np.r_[tcp_from.pos[:2], high], tcp_from.rot),
                                               slow_first=slow_first)], phase="home")
        except PathError:
            if slow_first > 0:  # at least the contact-critical retreat, if the climb is out of reach
                back = Pose(tcp_from.pos + np.array([0.0, 0.0, slow_first]), tcp_from.rot)
                try:
                    up = self._plan(q_from, [_Waypoint(back, kind="contact")])
                except PathError:
                    pass
        if up is None:
            up = _Motion(np.asarray(q_from, dtype=float)[None, :], (("home", 1),))
        traj = self._joint_move(up.end, self.kin.home, self.kin.fk(up.end)[0][2], home_base.pos[2], "transit")
        if traj is None:  # no straight alternative onto a joint configuration: take it, dip and all
            traj, _ = transit_trajectory(self.kin, up.end, self.kin.home, p.limits, self.dt)
        return up.then(_Motion(traj, (("home", len(traj)),)))

    def _leave(self, q_from: np.ndarray, tcp_from: Pose, away: np.ndarray, contact: float) -> _Motion:
        """Retreat ``contact`` [m] along the world direction ``away`` at the contact speed, then home. A
        retreat upwards flows into the way home without stopping."""
        if away[2] > 1 - 1e-9:
            return self._home(q_from, tcp_from, slow_first=contact)
        back = Pose(tcp_from.pos + away * contact, tcp_from.rot)
        retreat = self._plan(q_from, [_Waypoint(back, kind="contact")])
        return retreat.then(self._home(retreat.end, back))

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
        self.zone = params.approach

    def contact_zone(self) -> float:
        """The contact-critical length [m] at the end of the approach to the grasp (and of the lift-off,
        the approach to the target and the retreat): how far above the grasp the TCP is when the
        fingertips reach the top of the grasped body, from the scene's geometry now, plus
        ``contact_margin``; at most ``approach``."""
        m, d = self.wc.model, self.wc.data
        rot_tcp = d.site_xmat[self._tcp].reshape(3, 3)
        tip = 0.0  # how far the finger pads reach beyond the TCP along its approach axis (z)
        for g in set().union(*self._pads):
            rel = rot_tcp.T @ d.geom_xmat[g].reshape(3, 3)
            centre = rot_tcp.T @ (d.geom_xpos[g] - d.site_xpos[self._tcp]) + rel @ m.geom_aabb[g, :3]
            tip = max(tip, centre[2] + np.abs(rel[2]) @ m.geom_aabb[g, 3:])
        body = m.body(self.grasp_body).id
        grasp_z = d.site_xpos[m.site(self.grasp_site).id][2]
        top = grasp_z
        for g in range(m.ngeom):
            if m.geom_bodyid[g] == body and m.geom_contype[g]:
                rot = d.geom_xmat[g].reshape(3, 3)
                top = max(top, d.geom_xpos[g][2] + rot[2] @ m.geom_aabb[g, :3]
                          + np.abs(rot[2]) @ m.geom_aabb[g, 3:])
        return float(min(tip + (top - grasp_z) + self.params.contact_margin, self.params.approach))

    def _gripper_time(self) -> float:
        """Closing on the part and opening again at ``finger_speed`` [s]."""
        return 2.0 * max(0.0, self._gripper_open - self.width / 2) / self.params.finger_speed

    def _carry_waypoints(self, g: Pose, rel_p: np.ndarray, rel_r: np.ndarray, target: Pose,
                         approach_dir: np.ndarray, stand: float,
                         contact: float) -> tuple[list[_Waypoint], Pose]:
        """Carry waypoints from grasp TCP ``g`` for a part held at (rel_p, rel_r) in the TCP frame, and the
        TCP pose that puts the part's origin on ``target``: the lift-off (its first ``contact`` [m] at the
        contact speed) up to the carry height, across, and down to the target along ``-approach_dir``
        from ``stand`` [m] away, the last ``contact`` [m] at the contact speed. An approach from above is
        one straight descent; from the side, a descent to the stand-off and a straight insertion."""
        p = self.params
        up = np.array([0.0, 0.0, 1.0])
        place_rot = target.rot @ rel_r.T
        place = Pose(target.pos - place_rot @ rel_p + approach_dir * p.place_drop, place_rot)
        pre_grasp = Pose(g.pos + up * p.approach, g.rot)
        pre_place = Pose(place.pos + approach_dir * stand, place_rot)
        carry_z = max(pre_grasp.pos[2], pre_place.pos[2], self.wc.config.carry_height) + p.lift
        way = [_Waypoint(Pose(np.r_[g.pos[:2], carry_z], g.rot), slow_first=self.zone),
               _Waypoint(Pose(np.r_[pre_place.pos[:2], carry_z], place_rot), "joint")]
        if approach_dir[2] < 1 - 1e-9:
            way.append(_Waypoint(pre_place))
        way.append(_Waypoint(place, slow_last=contact))
        return way, place

    def _plan_carry(self, target: Pose, approach_dir: np.ndarray, stand: float,
                    contact: float) -> tuple[_Motion, _Motion, Pose, _Motion]:
        """Plan reach + carry for the part's origin to end at ``target`` (world), arriving along
        ``-approach_dir`` from ``stand`` [m] away, the last ``contact`` [m] at the contact speed, and the
        way out from there (:meth:`_leave` along ``approach_dir``, ``contact`` [m]). Returns (reach, carry,
        place_tcp, leave) or raises PathError.

        Both grasps of the part (the top-down grasp and the same turned 180 deg) are planned and the one
        that is done sooner is taken: with the wrist near a limit, one of them may need the wrist wound the
        long way round, there or on the way home."""
        part_pos, part_quat = self.wc.body_pose(self.part)
        part_rot = _quat_to_mat(part_quat)
        q0, tcp0 = self._q(), self._tcp_world()
        p = self.params
        up = np.array([0.0, 0.0, 1.0])
        error: PathError | None = None
        best = None
        for g in self._grasp_candidates(self.grasp_body):
            rel_p, rel_r = g.rot.T @ (part_pos - g.pos), g.rot.T @ part_rot
            way, place = self._carry_waypoints(g, rel_p, rel_r, target, approach_dir, stand, contact)
            pre_grasp = Pose(g.pos + up * p.approach, g.rot)
            reach_z = max(tcp0.pos[2], pre_grasp.pos[2])
            stage = "reaching for the grasp"
            try:
                reach = self._plan(q0, [_Waypoint(Pose(np.r_[tcp0.pos[:2], reach_z], tcp0.rot)),
                                        _Waypoint(pre_grasp, "joint"),
                                        _Waypoint(g, slow_last=self.zone)])
                stage = "on the carry (lift, transit at the carry height, approach)"
                carry = self._plan(reach.end, way)
                stage = "on the way out"
                leave = self._leave(carry.end, place, approach_dir, contact)
            except PathError as err:
                error = PathError(f"{stage}: {err}", err.pos_error)
                continue
            steps = len(reach.q) + len(carry.q) + len(leave.q)
            if best is None or steps < best[0]:
                best = (steps, reach, carry, place, leave, g)
        if best is None:
            raise error  # type: ignore[misc]
        _, reach, carry, place, leave, g = best
        self._plan_args = (g, target, approach_dir, stand, contact)
        return reach, carry, place, leave

    def plan_error(self) -> str | None:
        """Why this skill cannot be planned from the scene as it is now (where no IK solution exists, in the
        world frame: reaching, on the carry or on the way out), or None; nothing moves. The check before
        any physics (:func:`ergosim.experiment.scenario_check.check_reachability`) asks this."""
        self.zone = self.contact_zone()
        try:
            self._plan_carry(*self._arrival_plan())
        except PathError as err:
            return str(err)
        return None

    def _arrival_plan(self) -> tuple[Pose, np.ndarray, float, float]:
        """(target, approach direction, stand-off, contact length) of :meth:`_plan_carry`, after
        :meth:`contact_zone` set ``zone``."""
        raise NotImplementedError

    def _replan_carry(self, carry: _Motion) -> _Motion:
        """Re-plan the carry from the actual grasp (the fingers may have shifted the part); keeps the
        planned one if the new one fails."""
        g, target, approach_dir, stand, contact = self._plan_args
        tcp = self._tcp_world()
        pos, quat = self.wc.body_pose(self.part)
        rel_p, rel_r = tcp.rot.T @ (pos - tcp.pos), tcp.rot.T @ _quat_to_mat(quat)
        way, _ = self._carry_waypoints(g, rel_p, rel_r, target, approach_dir, stand, contact)
        try:
            return self._plan(self._planned_q_grasp, way)
        except PathError:
            return carry

    def _join_leave(self, leave: _Motion, planned_from: np.ndarray) -> _Motion:
        """The way out (:meth:`_leave`, planned from ``planned_from``) preceded by a contact-speed joint move
        from where the re-planned carry actually ended (a fraction of a millimetre away), so the retreat
        starts where the arm is."""
        if np.allclose(self._carried_to, planned_from, atol=1e-9):
            return leave
        bridge, _ = transit_trajectory(self.kin, self._carried_to, planned_from, self.params.limits, self.dt,
                                       kind="contact")
        return _Motion(bridge, (("contact", len(bridge)),)).then(leave)

    def _carry(self, reach: _Motion, carry: _Motion) -> Generator[None, None, SkillResult | None]:
        """Execute reach, grasp and carry; a failure result (after returning home) or None on arrival."""
        self._planned_q_grasp = reach.end
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
        self._carried_to = carry.end
        d, site = self.wc.data, self.wc.model.site(self.grasp_site).id
        every = self.params.drop_check_every
        tol = self.wc.config.grasp_tolerance
        tcp = self._tcp_world()
        grip = tcp.rot.T @ (d.site_xpos[site] - tcp.pos)  # where the part sits in the hand
        arm = self._arm_ctrl
        for i, (row, phase) in enumerate(zip(carry.q, carry.phases(), strict=True)):
            self._phase = phase
            d.ctrl[arm] = row
            yield
            if i % every == 0 and np.linalg.norm(d.site_xmat[self._tcp].reshape(3, 3).T
                                                 @ (d.site_xpos[site] - d.site_xpos[self._tcp]) - grip) > tol:
                self.wc.release(self.holder, self.grasp_body)
                yield from self._open()
                yield from self._follow(self._home(self._q(), self._tcp_world()))
                return self._finish(SkillStatus.DROPPED, f"{self.part} left the gripper while carried")
        yield from self._hold(self.params.settle)
        self._arrival = self._steps * self.dt
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

    def _arrival_plan(self) -> tuple[Pose, np.ndarray, float, float]:
        # an insertion runs its whole stroke at the contact speed; a place only its last ``contact``
        stand = self.params.insert_approach if self.seat else self.params.approach
        return self.target, self.approach_dir, stand, stand if self.seat else self.zone

    def planned_time(self) -> float:
        """How long the skill would take from the scene as it is now [s]: its planned joint trajectories,
        the gripper and the pauses (the expected robot duration of the time cost); NaN if unreachable. The
        scene is not changed."""
        p = self.params
        self.zone = self.contact_zone()
        try:
            reach, carry, _, leave = self._plan_carry(*self._arrival_plan())
        except PathError:
            return float("nan")
        steps = len(reach.q) + len(carry.q) + len(leave.q)
        return steps * self.dt + self._gripper_time() + 0.1 + 3 * p.settle + self.hold

    def _program(self) -> Program:
        p = self.params
        self.zone = self.contact_zone()
        try:
            reach, carry, place, leave = self._plan_carry(*self._arrival_plan())
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
            leave = self._join_leave(leave, carry.end)
            if self.hold > 0:
                yield from self._hold(self.hold, phase="contact")
            received = self.wc.receive(self.part, self.target.pos) if self.receive else None
            self.wc.release(self.holder, self.grasp_body)
            seated = self.wc.seat(self.part) if self.seat else received
            yield from self._open()
            yield from self._hold(p.settle)
        finally:
            if self.seat:
                self.wc.host_robot_contacts(self.part, True)
        yield from self._follow(leave)
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

    def _arrival_plan(self) -> tuple[Pose, np.ndarray, float, float]:
        # the part comes down into the handover pose and the hand leaves upwards, both next to the worker
        return self.target, np.array([0.0, 0.0, 1.0]), self.zone, self.zone

    def planned_time(self) -> float:
        """How long the robot's side of the handover would take from the scene as it is now [s]: reach,
        grasp, carry to the handover pose, let go and return (not the wait for the worker); NaN if
        unreachable. The scene is not changed."""
        try:
            self.zone = self.contact_zone()
            reach, carry, _, leave = self._plan_carry(*self._arrival_plan())
        except PathError:
            return float("nan")
        steps = len(reach.q) + len(carry.q) + len(leave.q)
        return steps * self.dt + self._gripper_time() + 0.1 + 2 * self.params.settle

    def _program(self) -> Program:
        p = self.params
        try:
            self.zone = self.contact_zone()
            reach, carry, place, leave = self._plan_carry(*self._arrival_plan())
        except PathError as err:
            yield
            return self._finish(SkillStatus.UNREACHABLE, f"cannot hand {self.part} over at "
                                f"{np.round(self.target.pos, 3).tolist()}: {err}")
        failure = yield from self._carry(reach, carry)
        if failure is not None:
            return failure
        leave = self._join_leave(leave, carry.end)
        waited = 0
        self._phase = "wait"
        while not self.taken(self.wc):
            waited += 1
            if waited * self.dt > p.handover_timeout:
                self.wc.release(self.holder, self.grasp_body)
                yield from self._open()
                yield from self._follow(leave)
                return self._finish(SkillStatus.TIMEOUT, f"nobody took {self.part} within "
                                    f"{p.handover_timeout:.0f} s")
            yield
        error = float(np.linalg.norm(self.wc.body_pose(self.part)[0] - self.target.pos))
        self.wc.release(self.holder, self.grasp_body)
        yield from self._open()
        yield from self._follow(leave)
        return self._finish(SkillStatus.OK, f"{self.part} handed over {error * 1000:.1f} mm from the "
                            "handover pose", error)


def pick_place(workcell, part: str, target_pos, target_quat, **kwargs) -> PickPlace:
    """A :class:`PickPlace` skill (not started: step it, or call ``run_to_completion``)."""
    return PickPlace(workcell, part, target_pos, target_quat, **kwargs)


def handover(workcell, part: str, pos, quat, taken: Callable[[object], bool] | None = None,
             **kwargs) -> Handover:
    """A :class:`Handover` skill (not started: step it, or call ``run_to_completion``)."""
    return Handover(workcell, part, pos, quat, taken, **kwargs)
