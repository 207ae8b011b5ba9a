"""A robot's contract held against the task, before any physics: what each robot may not do.

:func:`robot_refusals` follows the task's plan (:func:`plan_points`: where each part lies when its action
starts and where the action takes it) and asks each robot's contract (:mod:`ergosim.robot.capability`)
about every action the task allows it: the gripper's opening against the part, the payload against the
mass carried (:func:`carried`), the reach sphere against the part and the target, and, at a hand-over, the
clearance from the worker's head and neck (ISO/TS 15066 body region 1, :mod:`ergosim.scenes.park`).
An action a robot refuses is the worker's for the whole run.
"""

from __future__ import annotations

import mujoco
import numpy as np

from ergosim import quat
from ergosim.planner import AndOrGraph
from ergosim.robot.capability import refusal
from ergosim.robot.ik import solve_ik
from ergosim.robot.kinematics import ArmKinematics
from ergosim.scenes.park import HANDOVER_CLEARANCE, HEAD_AND_NECK, clearance_to, robot_geoms

__all__ = ["robot_refusals", "plan_points", "handover_poses", "carried", "handover_clearance"]


def plan_points(task: AndOrGraph, cell) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """(action, where its part lies when it starts, where the action takes it) [m, world] in the task's
    plan order: a placed part is at its target site, a seated one where its host is; a slot's site moves
    with its host (its offset turned with the host)."""
    return [(action, start, end) for action, start, end, _ in _plan_walk(task, cell)]


def handover_poses(task: AndOrGraph, cell) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """action -> its hand-over pose (position [m], quaternion wxyz; world) where the task's plan has it
    when the action starts: a hand-over at a part's slot (the paper's parts presented at their hollows,
    issue 23) is where that part has been placed by then, not where it was laid out."""
    return {action: pose for action, _, _, pose in _plan_walk(task, cell) if pose is not None}


def _plan_walk(task: AndOrGraph, cell):
    """(action, start, end, hand-over pose or None) in the task's plan order (:func:`plan_points`)."""
    slots = cell.config.slots()
    pose = {p: cell.body_pose(p) for p in cell.parts}  # (pos, quat wxyz), as laid out
    start_pose = dict(pose)
    host: dict[str, str] = {}

    def root(part: str) -> str:
        while part in host:
            part = host[part]
        return part

    def site_now(name: str) -> tuple[np.ndarray, np.ndarray]:
        """A site's pose now: one on a part (a slot, a presentation pose) turned and moved with that part
        since the layout."""
        p, q = cell.site_pose(name)
        body = cell.model.body(cell.model.site(name).bodyid[0]).name
        if body not in pose:
            return p, q
        (p0, q0), (p1, q1) = start_pose[body], pose[body]
        turn = quat.to_mat(q1) @ quat.to_mat(q0).T
        return p1 + turn @ (p - p0), quat.from_mat(turn @ quat.to_mat(q))

    for step in task.plan().steps:
        geom = cell.actions[step.action]
        start = pose[root(geom.part)][0]
        handover = site_now(geom.handover) if geom.handover else None
        if geom.seats:
            end = site_now(geom.target)[0]
            host[geom.part] = slots[cell.config.action(step.action).target].host
        else:
            end = cell.site_pose(geom.target)[0]
            pose[geom.part] = cell.site_pose(geom.target)
        yield step.action, start, end, handover


def carried(task: AndOrGraph, cell) -> dict[str, float]:
    """action -> the mass [kg] it moves: its part, with every part seated in it by the actions before it
    in the task's plan when the action moves an assembly (the compiled model's body masses)."""
    slots = cell.config.slots()
    inside: dict[str, set[str]] = {p: {p} for p in cell.parts}
    out = {}
    for step in task.plan().steps:
        geom = cell.actions[step.action]
        bodies = inside[geom.part] if geom.moves_assembly else {geom.part}
        out[step.action] = float(sum(cell.model.body_mass[cell.model.body(b).id] for b in bodies))
        if geom.seats:
            host = slots[cell.config.action(step.action).target].host
            for group in inside.values():
                if host in group:
                    group.update(inside[geom.part])
    return out


def robot_refusals(task: AndOrGraph, cell) -> dict[tuple[str, str], str]:
    """(action, robot) -> why the robot cannot do an action the task allows it, in words: its gripper
    against the part's width, its payload against the mass carried, its reach (the datasheet's, to the
    flange, plus the gripper) against the distance from its shoulder to the part and to the target. Empty
    when every robot can do all its actions."""
    allowed: dict[str, set[str]] = {}
    for op in task.operations:
        allowed.setdefault(op.action, set()).update(op.agents)
    mass = carried(task, cell)
    walk = list(_plan_walk(task, cell))
    points = {a: (s, e) for a, s, e, _ in walk}
    handovers = {a: pose for a, _, _, pose in walk if pose is not None}
    out = {}
    for action, agents in allowed.items():
        geom = cell.actions[action]
        start = points[action][0]
        end = handovers[action][0] if geom.handover else points[action][1]
        for agent in sorted(agents & set(cell.robots)):
            handle = cell.robot(agent)
            shoulder, radius = _reach_sphere(cell, handle)
            far = [name for name, p in ((geom.part, start), (geom.handover or geom.target, end))
                   if np.linalg.norm(np.asarray(p) - shoulder) > radius]
            width = cell.grip_width(cell.grasp_body(geom.part))
            why = refusal(handle.robot, action, geom.part, width, mass.get(action), not far,
                          far[0] if far else "")
            if why is None and geom.handover and _has_worker(cell):
                clear = handover_clearance(cell, handle, geom, handovers[action])
                if clear is None:
                    why = refusal(handle.robot, action, geom.part, width, None, False, geom.handover)
                elif clear < HANDOVER_CLEARANCE:
                    why = (f"{handle.robot.name} cannot do {action}: holding {geom.part} out at "
                           f"{geom.handover} it would come {clear:.2f} m from the worker's head or neck "
                           f"(at least {HANDOVER_CLEARANCE:g} m)")
            if why is not None:
                out[(action, agent)] = why
    return out


def handover_clearance(cell, handle, geom, at: tuple[np.ndarray, np.ndarray] | None = None) -> float | None:
    """The robot's clearance [m] from the worker's head and neck (at the worker's rest posture)
    while it holds ``geom``'s part out at its hand-over pose (``at``, position and quaternion wxyz, world:
    where the plan has it, :func:`handover_poses`; the site as laid out if None), grasped as laid out
    (top-down at its grasp site); None if no IK solution holds it there."""
    m, d = cell.model, cell.data
    kin = ArmKinematics(handle.robot)
    base_p, base_q = cell.robot_base_pose(handle.name)
    base_r = quat.to_mat(base_q)
    part_p, part_q = cell.body_pose(geom.part)
    site = m.site(cell.grasp_site(geom.part)).id
    rel_p = quat.to_mat(part_q).T @ (d.site_xpos[site] - part_p)
    rel_r = quat.to_mat(part_q).T @ d.site_xmat[site].reshape(3, 3)
    to_p, to_q = at if at is not None else cell.site_pose(geom.handover)
    tcp_p, tcp_r = to_p + quat.to_mat(to_q) @ rel_p, quat.to_mat(to_q) @ rel_r
    for flip in (np.eye(3), np.diag([-1.0, -1.0, 1.0])):  # the grasp turned 180 deg about the TCP z
        res = solve_ik(kin, base_r.T @ (tcp_p - base_p), base_r.T @ tcp_r @ flip, kin.ready, restarts=4,
                       rng=np.random.default_rng(0))
        if res.ok:
            saved = d.qpos.copy()
            d.qpos[handle.arm_qpos] = res.q
            mujoco.mj_kinematics(m, d)
            regions = [m.geom(n).id for n in HEAD_AND_NECK]
            clear = clearance_to(m, d, robot_geoms(m, handle.base), regions)
            d.qpos[:] = saved
            mujoco.mj_kinematics(m, d)
            return float(clear)
    return None


def _has_worker(cell) -> bool:
    return all(mujoco.mj_name2id(cell.model, mujoco.mjtObj.mjOBJ_GEOM, n) >= 0 for n in HEAD_AND_NECK)


def _reach_sphere(cell, handle) -> tuple[np.ndarray, float]:
    """The robot's shoulder (its first moving link, world [m]) and the radius [m] its TCP reaches: the
    datasheet reach to the flange plus the flange-to-TCP length of its gripper."""
    kin = ArmKinematics(handle.robot)
    flange = kin.fk(kin.home, handle.robot.arm_joints[-1])[0]  # the last joint's frame, at the wrist
    tcp = kin.fk(kin.home)[0]
    shoulder = cell.body_pose(handle.prefix + handle.robot.mount.link)[0]
    return shoulder, handle.robot.reach + float(np.linalg.norm(tcp - flange))
