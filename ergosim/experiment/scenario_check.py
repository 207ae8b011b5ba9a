"""Checks that bind a task to a workcell, run before any physics.

:func:`check_scenario` needs no kinematics: every action of the task has a physical action in the cell,
every physical action moves a part of the task, every agent has a body (the worker, or a robot of that
name), and no robot is allowed an action whose part its gripper cannot take. :func:`check_reachability`
solves inverse kinematics once per (agent, action): a target that no allowed agent reaches, or a robot
that reaches none of its actions, refuses the run before it starts, naming the agent and the part.
"""

from __future__ import annotations

import numpy as np

from ergosim import quat
from ergosim.errors import ConfigError
from ergosim.planner import AndOrGraph
from ergosim.scenes import CellSpec

__all__ = ["PANDA_MAX_OPENING", "check_scenario", "check_reachability", "precheck"]

PANDA_MAX_OPENING = 0.08
"""Largest part width [m] the Panda's gripper closes on: its fingers open to 80 mm (Franka Emika Panda
datasheet, "Franka Hand: max. grasping width 80 mm")."""


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
    for action, agents in allowed.items():
        part = cell.part(cell_actions[action].part)
        for agent in sorted(agents & robots):
            if part.grip_width > PANDA_MAX_OPENING:
                raise ConfigError(
                    f"robot {agent!r} may do {action}, but its gripper cannot take {part.name} "
                    f"({part.grip_width * 1000:.0f} mm wide; the Panda opens "
                    f"{PANDA_MAX_OPENING * 1000:.0f} mm): give that operation agents = [\"{humans[0]}\"] "
                    "in the task", where=f"{scenario.task_source}: {action}")


def precheck(scenario) -> None:
    """Everything checked before a run of ``scenario`` starts that needs the built workcell: the
    reachability of every action (:func:`check_reachability`) in the cell as the file describes it."""
    from ergosim.scenes import build_cell  # noqa: PLC0415

    check_reachability(scenario, scenario.task(), build_cell(scenario.cell()))


def _start_positions(task: AndOrGraph, cell) -> list[tuple[str, np.ndarray]]:
    """(action, where its part lies when the action starts) [m, world], in an order the task allows (its
    optimal plan with the file's costs): a part is where the last earlier action put it, a seated part
    where its host is."""
    slots = cell.config.slots()
    at = {p: cell.body_pose(p)[0] for p in cell.parts}
    host: dict[str, str] = {}

    def where(part: str) -> np.ndarray:
        while part in host:
            part = host[part]
        return at[part]

    out = []
    for step in task.plan().steps:
        geom = cell.actions[step.action]
        out.append((step.action, where(geom.part)))
        if geom.seats:
            host[geom.part] = slots[cell.config.action(step.action).target].host
        else:
            at[geom.part] = cell.site_pose(geom.target)[0]
    return out


def check_reachability(scenario, task: AndOrGraph, cell) -> None:
    """IK pre-check in the built workcell ``cell``: each robot-allowed action's grasp and target poses for
    the robot, each worker-allowed action's part and target for a nominal worker of the cell's stature,
    with every part where the earlier actions leave it. An action no allowed agent reaches, or a robot
    that reaches none of its actions, is a ConfigError naming the agent, the part and the action."""
    from ergosim.robot.ik import solve_ik  # noqa: PLC0415
    from ergosim.robot.kinematics import PandaKinematics  # noqa: PLC0415

    src = cell.config.source
    robots = set(cell.robots)
    allowed: dict[str, set[str]] = {}
    for op in task.operations:
        allowed.setdefault(op.action, set()).update(op.agents)
    human = next(a.name for a in task.agents if a.kind == "human")
    kin = PandaKinematics() if robots else None
    reach_human = _human_reach(cell)
    reached: dict[str, int] = {r: 0 for r in robots}
    tried: dict[str, int] = {r: 0 for r in robots}
    for action, part_pos in _start_positions(task, cell):
        geom = cell.actions[action]
        target = cell.site_pose(geom.target)[0]
        points = [part_pos, cell.site_pose(geom.handover)[0] if geom.handover else target]
        able = []
        for agent in sorted(allowed.get(action, ())):
            if agent == human:
                if all(reach_human(p) for p in (part_pos, target)):
                    able.append(agent)
            elif agent in robots:
                tried[agent] += 1
                if all(_robot_reaches(cell, agent, kin, solve_ik, p) for p in points):
                    able.append(agent)
                    reached[agent] += 1
        if not able:
            who = " or ".join(sorted(allowed.get(action, ()))) or "no agent"
            raise ConfigError(f"{who} cannot reach {geom.part} for {action} (from "
                              f"{np.round(part_pos, 2).tolist()} to {geom.handover or geom.target} at "
                              f"{np.round(points[1], 2).tolist()}): the run would fail",
                              where=f"{src}: actions.{action}")
    for robot in robots:
        if tried[robot] and not reached[robot]:
            base = cell.robot_base_pose(robot)[0]
            raise ConfigError(f"robot {robot!r} at {np.round(base, 2).tolist()} reaches none of the "
                              f"{tried[robot]} actions it may do; move its base or take it out of the task",
                              where=f"{src}: robots.{robot}.base")


def _robot_reaches(cell, robot: str, kin, solve_ik, point: np.ndarray) -> bool:
    """A top-down TCP pose of ``robot`` 5 cm above ``point`` (world) within 1 cm of a solution."""
    base_p, base_q = cell.robot_base_pose(robot)
    r = quat.to_mat(base_q)
    local = r.T @ (np.asarray(point) + np.array([0, 0, 0.05]) - base_p)
    down = r.T @ np.diag([1.0, -1.0, -1.0])
    from ergosim.robot.mjcf import HOME_QPOS  # noqa: PLC0415

    res = solve_ik(kin, local, down, np.asarray(HOME_QPOS, dtype=float), restarts=4,
                   rng=np.random.default_rng(0))
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
