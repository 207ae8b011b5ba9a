"""Checks that bind a task to a workcell, run before any physics.

:func:`check_scenario` needs no kinematics: every action of the task has a physical action in the cell,
every physical action moves a part of the task, every agent has a body (the worker, or a robot of that
name), and no action is left to robots whose grippers cannot take its part. :func:`robot_refusals` holds
each robot to its contract (:mod:`ergosim.robot.capability`): the gripper's opening, the payload against
the mass carried, and its reach (inverse kinematics once per action); an action a robot cannot do is taken
from it for the whole run, in words. :func:`check_reachability` refuses the run before it starts when an
action is left to nobody, or a robot can do none of its actions, naming the agent and the part.
"""

from __future__ import annotations

import mujoco
import numpy as np

from ergosim import quat
from ergosim.errors import ConfigError
from ergosim.planner import AndOrGraph
from ergosim.robot.capability import refusal
from ergosim.robot.ik import solve_ik
from ergosim.robot.kinematics import ArmKinematics
from ergosim.robot.robot_model import get_robot
from ergosim.scenes import CellSpec
from ergosim.scenes.park import HANDOVER_CLEARANCE, HEAD_AND_CHEST, clearance_to, robot_geoms

__all__ = ["check_scenario", "robot_refusals", "check_reachability", "precheck"]


def check_scenario(scenario, task: AndOrGraph, cell: CellSpec) -> None:
    """The task and the workcell of ``scenario`` fit together; one ConfigError naming the problem if not."""
    where = scenario.source
    cell_actions = {a.label: a for a in cell.actions}
    missing = [a for a in task.actions if a not in cell_actions]
    if missing:
        op = next(o.name for o in task.operations if o.action == missing[0])
        raise ConfigError(f"operation {op!r} (action {missing[0]!r}) has no physical action in the "
                          f"workcell {cell.source}: add [actions.{missing[0]}] there (kind, part, target); "
                          f"its actions: {', '.join(cell_actions) or 'none'}",
                          where=f"{scenario.task_source}: {missing[0]}")
    parts = set(task.parts)
    for a in cell.actions:
        if a.part not in parts:
            raise ConfigError(f"action {a.label} moves part {a.part!r}, which is not a part of the task "
                              f"{scenario.task_source} ({', '.join(task.parts)})",
                              where=f"{cell.source}: actions.{a.label}.part")
    robots = {r.name for r in cell.robots}
    allowed: dict[str, set[str]] = {}
    for op in task.operations:
        allowed.setdefault(op.action, set()).update(op.agents)
    humans = [a.name for a in task.agents if a.kind == "human"]
    if len(humans) != 1:
        raise ConfigError(f"the twin simulates one worker; the task has {len(humans)} human agents",
                          where=where)
    bodies = {cell.worker.name: "human", **{r: "robot" for r in robots}}
    for agent in task.agents:
        if bodies.get(agent.name) != agent.kind:
            have = f"the worker {cell.worker.name!r} (worker.name) and the robots {sorted(robots)}"
            raise ConfigError(f"{agent.kind} agent {agent.name!r} has no body in the workcell "
                              f"{cell.source}, which has {have}",
                              where=f"{scenario.task_source}: agents.{agent.name}")
    models = {r.name: get_robot(r.model) for r in cell.robots}
    cfg = scenario.protocol
    for name, model in models.items():
        for field in ("ee_speed", "transit_speed"):
            speed = getattr(cfg.robot, field)
            if speed > model.max_speed:
                raise ConfigError(f"{field} must be at most {model.max_speed:g} m/s (the {model.name}'s "
                                  f"Cartesian limit, robot {name!r}), got {speed:g}",
                                  where=f"{where}: protocol")
    for action, agents in allowed.items():
        part = cell.part(cell_actions[action].part)
        able = [a for a in agents if a not in robots or part.grip_width <= models[a].gripper.max_opening]
        if not able:
            agent = sorted(agents & robots)[0]
            raise ConfigError(
                f"robot {agent!r} may do {action}, but its gripper cannot take {part.name} "
                f"({part.grip_width * 1000:.0f} mm wide; the {models[agent].name} opens "
                f"{models[agent].gripper.max_opening * 1000:.0f} mm): give that operation agents = "
                f"[\"{humans[0]}\"] in the task", where=f"{scenario.task_source}: {action}")


def precheck(scenario) -> list[str]:
    """Everything checked before a run of ``scenario`` starts that needs the built workcell: the
    reachability of every action (:func:`check_reachability`) in the cell as the file describes it.
    Returns the robots' refusals (:func:`robot_refusals`), one line each, for the caller to print."""
    from ergosim.scenes import build_cell  # noqa: PLC0415

    return check_reachability(scenario, scenario.task(), build_cell(scenario.cell()))


def _start_positions(task: AndOrGraph, cell) -> list[tuple[str, np.ndarray]]:
    """(action, where its part lies when the action starts) [m, world], in an order the task allows (its
    optimal plan with the file's costs): a part is where the last earlier action put it, a seated part
    where its host is."""
    return [(action, start) for action, start, _ in _plan_points(task, cell)]


def _plan_points(task: AndOrGraph, cell) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """(action, where its part lies when it starts, where the action takes it) [m, world] in the task's
    plan order: a placed part is at its target site, a seated one where its host is; a slot's site moves
    with its host (its offset turned with the host)."""
    slots = cell.config.slots()
    pose = {p: cell.body_pose(p) for p in cell.parts}  # (pos, quat wxyz), as laid out
    start_pose = dict(pose)
    host: dict[str, str] = {}

    def root(part: str) -> str:
        while part in host:
            part = host[part]
        return part

    out = []
    for step in task.plan().steps:
        geom = cell.actions[step.action]
        start = pose[root(geom.part)][0]
        if geom.seats:
            holder = slots[cell.config.action(step.action).target].host
            p0, q0 = start_pose[holder]
            p1, q1 = pose[holder]
            offset = quat.to_mat(q1) @ quat.to_mat(q0).T @ (cell.site_pose(geom.target)[0] - p0)
            end = p1 + offset
            host[geom.part] = holder
        else:
            end = cell.site_pose(geom.target)[0]
            pose[geom.part] = cell.site_pose(geom.target)
        out.append((step.action, start, end))
    return out


def _carried(task: AndOrGraph, cell) -> dict[str, float]:
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
    mass = _carried(task, cell)
    points = {a: (s, e) for a, s, e in _plan_points(task, cell)}
    out = {}
    for action, agents in allowed.items():
        geom = cell.actions[action]
        start = points[action][0]
        end = cell.site_pose(geom.handover)[0] if geom.handover else points[action][1]
        for agent in sorted(agents & set(cell.robots)):
            handle = cell.robot(agent)
            shoulder, radius = _reach_sphere(cell, handle)
            far = [name for name, p in ((geom.part, start), (geom.handover or geom.target, end))
                   if np.linalg.norm(np.asarray(p) - shoulder) > radius]
            width = cell.grip_width(cell.grasp_body(geom.part))
            why = refusal(handle.robot, action, geom.part, width, mass.get(action), not far,
                          far[0] if far else "")
            if why is None and geom.handover and _has_worker(cell):
                clear = _handover_clearance(cell, handle, geom)
                if clear is None:
                    why = refusal(handle.robot, action, geom.part, width, None, False, geom.handover)
                elif clear < HANDOVER_CLEARANCE:
                    why = (f"{handle.robot.name} cannot do {action}: holding {geom.part} out at "
                           f"{geom.handover} it would come {clear:.2f} m from the worker's head, neck or "
                           f"chest (at least {HANDOVER_CLEARANCE:g} m)")
            if why is not None:
                out[(action, agent)] = why
    return out


def _handover_clearance(cell, handle, geom) -> float | None:
    """The robot's clearance [m] from the worker's head, neck and chest (at the worker's rest posture)
    while it holds ``geom``'s part out at its hand-over pose, grasped as laid out (top-down at its grasp
    site); None if no IK solution holds it there."""
    m, d = cell.model, cell.data
    kin = ArmKinematics(handle.robot)
    base_p, base_q = cell.robot_base_pose(handle.name)
    base_r = quat.to_mat(base_q)
    part_p, part_q = cell.body_pose(geom.part)
    site = m.site(cell.grasp_site(geom.part)).id
    rel_p = quat.to_mat(part_q).T @ (d.site_xpos[site] - part_p)
    rel_r = quat.to_mat(part_q).T @ d.site_xmat[site].reshape(3, 3)
    to_p, to_q = cell.site_pose(geom.handover)
    tcp_p, tcp_r = to_p + quat.to_mat(to_q) @ rel_p, quat.to_mat(to_q) @ rel_r
    for flip in (np.eye(3), np.diag([-1.0, -1.0, 1.0])):  # the grasp turned 180 deg about the TCP z
        res = solve_ik(kin, base_r.T @ (tcp_p - base_p), base_r.T @ tcp_r @ flip, kin.ready, restarts=4,
                       rng=np.random.default_rng(0))
        if res.ok:
            saved = d.qpos.copy()
            d.qpos[handle.arm_qpos] = res.q
            mujoco.mj_kinematics(m, d)
            regions = [m.geom(n).id for n in HEAD_AND_CHEST]
            clear = clearance_to(m, d, robot_geoms(m, handle.base), regions)
            d.qpos[:] = saved
            mujoco.mj_kinematics(m, d)
            return float(clear)
    return None


def _has_worker(cell) -> bool:
    return all(mujoco.mj_name2id(cell.model, mujoco.mjtObj.mjOBJ_GEOM, n) >= 0 for n in HEAD_AND_CHEST)


def _reach_sphere(cell, handle) -> tuple[np.ndarray, float]:
    """The robot's shoulder (its first moving link, world [m]) and the radius [m] its TCP reaches: the
    datasheet reach to the flange plus the flange-to-TCP length of its gripper."""
    kin = ArmKinematics(handle.robot)
    flange = kin.fk(kin.home, handle.robot.arm_joints[-1])[0]  # the last joint's frame, at the wrist
    tcp = kin.fk(kin.home)[0]
    shoulder = cell.body_pose(handle.prefix + handle.robot.mount.link)[0]
    return shoulder, handle.robot.reach + float(np.linalg.norm(tcp - flange))


def _reach_table(task: AndOrGraph, cell) -> tuple[dict[str, list[str]], dict[tuple[str, str], str]]:
    """Which allowed agents reach each action (action -> agents), and what each robot misses ((action,
    robot) -> the pose, in words)."""
    robots = set(cell.robots)
    allowed: dict[str, set[str]] = {}
    for op in task.operations:
        allowed.setdefault(op.action, set()).update(op.agents)
    human = next(a.name for a in task.agents if a.kind == "human")
    kins = {r: ArmKinematics(cell.robot(r).robot, cell.robot_home(r)) for r in robots}
    reach_human = _human_reach(cell)
    able: dict[str, list[str]] = {}
    missed: dict[tuple[str, str], str] = {}
    for action, part_pos in _start_positions(task, cell):
        geom = cell.actions[action]
        target = cell.site_pose(geom.target)[0]
        where = geom.handover or geom.target
        end = cell.site_pose(geom.handover)[0] if geom.handover else target
        points = [(geom.part, part_pos), (where, end)]
        able[action] = []
        for agent in sorted(allowed.get(action, ())):
            if agent == human:
                if all(reach_human(p) for p in (part_pos, target)):
                    able[action].append(agent)
            elif agent in robots:
                miss = [name for name, p in points if not _robot_reaches(cell, agent, kins[agent], p)]
                if miss:
                    missed[(action, agent)] = miss[0]
                else:
                    able[action].append(agent)
    return able, missed


def check_reachability(scenario, task: AndOrGraph, cell) -> list[str]:
    """IK pre-check in the built workcell ``cell``: each robot-allowed action's grasp and target poses for
    the robot, each worker-allowed action's part and target for a nominal worker of the cell's stature,
    with every part where the earlier actions leave it. An action no allowed agent can do (for a robot: its
    reach, gripper and payload, :func:`robot_refusals`), or a robot that can do none of its actions, is a
    ConfigError naming the agent, the part and the action. Returns the robots' refusals, one line each
    ("ur5 cannot do g4: ...; the worker does it")."""
    src = cell.config.source
    robots = set(cell.robots)
    allowed: dict[str, set[str]] = {}
    for op in task.operations:
        allowed.setdefault(op.action, set()).update(op.agents)
    human = next(a.name for a in task.agents if a.kind == "human")
    able, missed = _reach_table(task, cell)
    refused = robot_refusals(task, cell)
    positions = dict(_start_positions(task, cell))
    for action, agents in able.items():
        if not [a for a in agents if (action, a) not in refused]:
            geom = cell.actions[action]
            part_pos = positions[action]
            point = cell.site_pose(geom.handover or geom.target)[0]
            who = " or ".join(sorted(allowed.get(action, ()))) or "no agent"
            if any((action, r) in refused for r in robots):
                why = "; ".join(refused[(action, r)] for r in sorted(robots) if (action, r) in refused)
                raise ConfigError(f"no agent can do {action}: {why}", where=f"{src}: actions.{action}")
            raise ConfigError(f"{who} cannot reach {geom.part} for {action} (from "
                              f"{np.round(part_pos, 2).tolist()} to {geom.handover or geom.target} at "
                              f"{np.round(point, 2).tolist()}): the run would fail",
                              where=f"{src}: actions.{action}")
    for robot in robots:
        tried = [a for a, agents in allowed.items() if robot in agents]
        if tried and all((a, robot) in missed for a in tried):
            base = cell.robot_base_pose(robot)[0]
            raise ConfigError(f"robot {robot!r} at {np.round(base, 2).tolist()} reaches none of the "
                              f"{len(tried)} actions it may do; move its base or take it out of the task",
                              where=f"{src}: robots.{robot}.base")
    lines = [f"{why}; the {human} does it" if human in allowed[action] else why
             for (action, _), why in sorted(refused.items())]
    for name, park in cell.parks.items():
        if not park.met:
            wanted = next(r.park_clearance for r in cell.config.robots if r.name == name)
            lines.append(f"robot {name!r} parks {park.clearance:.2f} m from the worker's head, neck and "
                         f"chest: no pose from its base keeps {wanted:g} m (robots.{name}.park_clearance)")
    return lines


def _robot_reaches(cell, robot: str, kin, point: np.ndarray) -> bool:
    """A top-down TCP pose of ``robot`` 5 cm above ``point`` (world) within 1 cm of a solution."""
    base_p, base_q = cell.robot_base_pose(robot)
    r = quat.to_mat(base_q)
    local = r.T @ (np.asarray(point) + np.array([0, 0, 0.05]) - base_p)
    down = r.T @ np.diag([1.0, -1.0, -1.0])
    res = solve_ik(kin, local, down, kin.robot.home, restarts=4, rng=np.random.default_rng(0))
    return bool(res.ok or res.pos_error < 0.01)


def _human_reach(cell):
    """A reach test for the cell's worker: within the arm's length plus a trunk lean of either shoulder."""
    from ergosim.human.model import SHOULDER_BODIES  # noqa: PLC0415

    stature = cell.config.worker.stature
    shoulders = [cell.body_pose(b)[0] for b in SHOULDER_BODIES.values()]
    # Arm length, shoulder to grip centre, ~0.36 of stature (Drillis & Contini segment proportions); bending
    # and twisting the trunk adds up to ~0.25 of stature of reach (assumed lean allowance, generous: the
    # worker's IK decides the rest at run time).
    limit = (0.36 + 0.25) * stature

    def reach(point: np.ndarray) -> bool:
        return bool(min(np.linalg.norm(np.asarray(point) - s) for s in shoulders) <= limit)

    return reach
