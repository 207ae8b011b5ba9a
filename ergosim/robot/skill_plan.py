"""The planning half of a carrying skill: how to reach the part, grasp it, carry it and leave.

:class:`CarryPlanner` reads the scene as it is now -- the part's pose and its grasp site, the robot's joints,
its finger pads, the target -- and never changes it. Poses come from the cell and speeds, the gripper and
the home pose from the robot, so a robot or a hand-over pose placed elsewhere plans here unchanged.

A pick descends at the transit speed to the contact zone above the grasp and goes the rest of the way,
and the first contact zone of the lift-off, at the contact speed; a place or a hand-over arrives the same
way; an insertion runs its whole stroke at the contact speed; the retreat after letting go is
contact-critical, the way home a transit.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ergosim.quat import to_mat
from ergosim.robot.handle import RobotHandle
from ergosim.robot.skill_motion import UP, Motion, MotionPlanner, Waypoint, is_up
from ergosim.robot.trajectory import BaseFrame, PathError, Pose

__all__ = ["RobotView", "CarryGoal", "CarryPlan", "CarryPlanner"]


class RobotView:
    """One robot of a cell as the skills read it: ``handle`` its indices, ``base`` its base frame (world),
    ``pads`` per finger the geoms that touch, ``gripper_open`` the widest opening per finger [m]."""

    def __init__(self, cell, handle: RobotHandle) -> None:
        m = cell.model
        self.cell = cell
        self.handle = handle
        self.pads = [{g for g in range(m.ngeom) if m.geom_bodyid[g] == m.body(f).id and m.geom_contype[g]}
                     for f in handle.fingers]
        self.gripper_open = handle.gripper_open(m)
        pos, quat = cell.robot_base_pose(handle.name)
        self.base = BaseFrame(pos, to_mat(quat))

    def q(self) -> np.ndarray:
        """The arm's joint positions now [rad]."""
        return self.cell.data.qpos[self.handle.arm_qpos].copy()

    def tcp(self) -> Pose:
        """The TCP's world pose now."""
        d, tcp = self.cell.data, self.handle.tcp
        return Pose(d.site_xpos[tcp].copy(), d.site_xmat[tcp].reshape(3, 3).copy())


@dataclass(frozen=True)
class CarryGoal:
    """Where the part's origin ends (``target``, world) and how it arrives: along ``-approach`` (a world unit
    vector) from ``stand`` [m] away, the last ``contact`` [m] at the contact speed. The hand leaves along
    ``approach``, its first ``contact`` [m] at the contact speed."""

    target: Pose
    approach: np.ndarray
    stand: float
    contact: float


@dataclass(frozen=True, eq=False)
class CarryPlan:
    """A planned carry: ``reach`` to the grasp TCP pose ``grasp`` (world), ``carry`` from there to the TCP
    pose ``place`` that puts the part on the goal, ``leave`` from there back home; ``zone`` [m] the contact
    zone it was planned with (:meth:`CarryPlanner.contact_zone`)."""

    zone: float
    goal: CarryGoal
    grasp: Pose
    reach: Motion
    carry: Motion
    place: Pose
    leave: Motion


def _flip_z(rot: np.ndarray) -> np.ndarray:
    """The same top-down grasp turned 180 deg about the TCP z axis (fingers swap sides)."""
    return rot @ np.diag([-1.0, -1.0, 1.0])


class CarryPlanner:
    """Plans how ``robot`` (a :class:`RobotView`) carries ``part`` in its cell, with ``motion`` its motion
    planner. ``grasp_site``, ``grasp_body``: where the part is held; ``width`` [m]: the grasped body's width
    between the fingers."""

    def __init__(self, robot: RobotView, part: str, motion: MotionPlanner) -> None:
        cell = robot.cell
        self.robot = robot
        self.part = part
        self.motion = motion
        self.params = motion.params
        self.grasp_site = cell.grasp_site(part)
        self.grasp_body = cell.grasp_body(part)
        self.width = cell.grip_width(self.grasp_body)

    def contact_zone(self) -> float:
        """The contact-critical length [m] at the end of the approach to the grasp (and of the lift-off,
        the approach to the target and the retreat): how far above the grasp the TCP is when the
        fingertips reach the top of the grasped body, from the scene's geometry now, plus
        ``contact_margin``; at most ``approach``."""
        cell = self.robot.cell
        m, d, tcp = cell.model, cell.data, self.robot.handle.tcp
        rot_tcp = d.site_xmat[tcp].reshape(3, 3)
        tip = 0.0  # how far the finger pads reach beyond the TCP along its approach axis (z)
        for g in set().union(*self.robot.pads):
            rel = rot_tcp.T @ d.geom_xmat[g].reshape(3, 3)
            centre = rot_tcp.T @ (d.geom_xpos[g] - d.site_xpos[tcp]) + rel @ m.geom_aabb[g, :3]
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

    def gripper_steps(self) -> int:
        """Physics steps the fingers take to close on the part (they stop where they touch it, its width
        apart), and as many to open again, at ``finger_speed``."""
        travel = max(0.0, self.robot.gripper_open - self.width / 2)
        return max(1, math.ceil(travel / (self.params.finger_speed * self.motion.dt)))

    def plan(self, goal_of: Callable[[float], CarryGoal]) -> CarryPlan:
        """Plan reach, carry and leave to ``goal_of(zone)`` (the goal may depend on the contact zone), or
        raise PathError.

        Both grasps of the part (the top-down grasp and the same turned 180 deg) are planned and the one
        that is done sooner is taken: with the wrist near a limit, one of them may need the wrist wound the
        long way round, there or on the way home."""
        cell, motion = self.robot.cell, self.motion
        zone = self.contact_zone()
        goal = goal_of(zone)
        part_pos, part_quat = cell.body_pose(self.part)
        part_rot = to_mat(part_quat)
        q0, tcp0 = self.robot.q(), self.robot.tcp()
        error: PathError | None = None
        best = None
        site_pos, site_quat = cell.site_pose(cell.grasp_site(self.part))
        site = Pose(site_pos, to_mat(site_quat))
        for g in (site, Pose(site.pos, _flip_z(site.rot))):
            rel_p, rel_r = g.rot.T @ (part_pos - g.pos), g.rot.T @ part_rot
            way, place = self.waypoints(g, rel_p, rel_r, goal, zone)
            pre_grasp = Pose(g.pos + UP * self.params.approach, g.rot)
            reach_z = max(tcp0.pos[2], pre_grasp.pos[2])
            try:
                reach = motion.through(q0, [Waypoint(Pose(np.r_[tcp0.pos[:2], reach_z], tcp0.rot)),
                                            Waypoint(pre_grasp, "joint"), Waypoint(g, slow_last=zone)])
                carry = motion.through(reach.end, way)
                leave = motion.leave(carry.end, place, goal.approach, goal.contact)
            except PathError as err:
                error = err
                continue
            steps = reach.steps + carry.steps + leave.steps
            if best is None or steps < best.reach.steps + best.carry.steps + best.leave.steps:
                best = CarryPlan(zone, goal, g, reach, carry, place, leave)
        if best is None:
            raise error  # type: ignore[misc]
        return best

    def waypoints(self, g: Pose, rel_p: np.ndarray, rel_r: np.ndarray, goal: CarryGoal,
                  zone: float) -> tuple[list[Waypoint], Pose]:
        """Carry waypoints from grasp TCP ``g`` for a part held at (rel_p, rel_r) in the TCP frame, and the
        TCP pose that puts the part's origin on the goal's target: the lift-off (its first ``zone`` [m] at
        the contact speed) up to the carry height, across, and down to the target along ``-approach`` from
        ``stand`` [m] away, the last ``contact`` [m] at the contact speed. An approach from above is one
        straight descent; from the side, a descent to the stand-off and a straight insertion."""
        p = self.params
        place_rot = goal.target.rot @ rel_r.T
        place = Pose(goal.target.pos - place_rot @ rel_p + goal.approach * p.place_drop, place_rot)
        pre_grasp = Pose(g.pos + UP * p.approach, g.rot)
        pre_place = Pose(place.pos + goal.approach * goal.stand, place_rot)
        carry_z = max(pre_grasp.pos[2], pre_place.pos[2], self.robot.cell.config.carry_height) + p.lift
        way = [Waypoint(Pose(np.r_[g.pos[:2], carry_z], g.rot), slow_first=zone),
               Waypoint(Pose(np.r_[pre_place.pos[:2], carry_z], place_rot), "joint")]
        if not is_up(goal.approach):
            way.append(Waypoint(pre_place))
        way.append(Waypoint(place, slow_last=goal.contact))
        return way, place

    def replan_carry(self, plan: CarryPlan) -> Motion:
        """The carry re-planned from the actual grasp (the fingers may have shifted the part), from the
        planned grasp configuration; the planned one if the new one fails."""
        tcp = self.robot.tcp()
        pos, quat = self.robot.cell.body_pose(self.part)
        rel_p, rel_r = tcp.rot.T @ (pos - tcp.pos), tcp.rot.T @ to_mat(quat)
        way, _ = self.waypoints(plan.grasp, rel_p, rel_r, plan.goal, plan.zone)
        try:
            return self.motion.through(plan.reach.end, way)
        except PathError:
            return plan.carry
