"""Checks that bind a task to a workcell, run before any physics.

:func:`check_scenario` needs no kinematics: every action of the task has a physical action in the cell,
every physical action moves a part of the task, every agent has a body (the worker, or a robot of that
name), and no robot is allowed an action whose part its gripper cannot take. A robot's contract
(:mod:`ergosim.twin.robot_refusals`: the gripper's opening, the payload against the mass carried,
its reach) takes an action it cannot do from it for the whole run, in words.
:func:`check_reachability` follows the task's plan with every part where the earlier actions leave it, and
plans each robot action's whole skill (reach, carry, insertion, way out) there: an action that no allowed
agent can do, or a robot that can do none of its actions, refuses the run before it starts, naming the
agent, the part and the point.
"""

from __future__ import annotations

import mujoco
import numpy as np

from ergosim import quat
from ergosim.errors import ConfigError
from ergosim.planner import AndOrGraph
from ergosim.robot.capability import OUT_OF_REACH
from ergosim.robot.robot_model import get_robot
from ergosim.scenes import CellSpec
from ergosim.twin.robot_refusals import robot_refusals

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


Pose = tuple[np.ndarray, np.ndarray]
"""A world pose: position (3,) [m] and rotation matrix (3, 3)."""


def _rot(q: np.ndarray) -> np.ndarray:
    return quat.to_mat(np.asarray(q, dtype=float))


class _Start:
    """The built cell's poses before anything moves: every part's and every action target's (world)."""

    def __init__(self, cell) -> None:
        self.slots = cell.config.slots()
        self.parts = {p: (cell.body_pose(p)[0], _rot(cell.body_pose(p)[1])) for p in cell.parts}
        self.sites = {g.target: (cell.site_pose(g.target)[0], _rot(cell.site_pose(g.target)[1]))
                      for g in cell.actions.values()}
        self.targets = {a.label: a.target for a in cell.config.actions}

    def target(self, geom, state: dict[str, Pose]) -> Pose:
        """Where ``geom``'s part ends with the parts at ``state``: a slot moves with its host."""
        sp, sr = self.sites[geom.target]
        slot = self.slots.get(self.targets[geom.action])
        if slot is None:
            return sp, sr
        (h0, r0), (h1, r1) = self.parts[slot.host], state[slot.host]
        return h1 + r1 @ r0.T @ (sp - h0), r1 @ r0.T @ sr


def _action_states(task: AndOrGraph, cell, start: _Start
                   ) -> list[tuple[str, dict[str, Pose], tuple[str, ...]]]:
    """(action, every part's world pose when the action starts, the parts seated then), in an order the
    task allows (its optimal plan with the file's costs). A placed, removed or handed-over part lies at its
    target with the target's pose; a seated part sits in its slot and moves with its host (the slot's site
    carries the seated pose), so a slot's target is read where earlier actions moved its host, not where
    the host starts."""
    own = dict(start.parts)  # each part's pose where it is free
    seated: dict[str, tuple[str, Pose]] = {}  # part -> (host, its pose in the host's frame)

    def world(part: str) -> Pose:
        if part not in seated:
            return own[part]
        host, (p, r) = seated[part]
        hp, hr = world(host)
        return hp + hr @ p, hr @ r

    out = []
    for step in task.plan().steps:
        geom = cell.actions[step.action]
        out.append((step.action, {p: world(p) for p in cell.parts}, tuple(seated)))
        if geom.seats:
            host = start.slots[start.targets[step.action]].host
            (hp, hr), (sp, sr) = start.parts[host], start.sites[geom.target]
            seated[geom.part] = (host, (hr.T @ (sp - hp), hr.T @ sr))
        else:
            seated.pop(geom.part, None)
            own[geom.part] = start.sites[geom.target]
    return out


def _lay_parts(cell, state: dict[str, Pose], seated: tuple[str, ...]) -> None:
    """Put every part at its pose in ``state`` and weld the ``seated`` ones into their slots (kinematics
    only: nothing is stepped), so a robot grasps an assembly the way it would then."""
    model, data = cell.model, cell.data
    for part, (pos, rot) in state.items():
        adr = model.jnt_qposadr[model.body_jntadr[model.body(part).id]]
        data.qpos[adr:adr + 3], data.qpos[adr + 3:adr + 7] = pos, quat.from_mat(rot)
    mujoco.mj_forward(model, data)
    data.eq_active[:] = 0
    for part in seated:
        cell.seat(part)


def _robot_turn(start: _Start, geom, state: dict[str, Pose], tolerance_deg: float) -> str | None:
    """Why a robot cannot seat ``geom``'s part as the slot needs, or None. The robot takes a part from
    above and can turn it only about the vertical (its hand stays pointing down): a seat that needs the
    part tilted (a part lying down that goes in upright, or standing on end that goes in sideways) is
    out of its reach however the arm moves. A robot that hands the part over leaves the seating to the
    worker."""
    if not geom.seats or geom.handover:  # at a handover the worker seats the part
        return None
    rot_now = state[geom.part][1]
    rot_seat = start.target(geom, state)[1]
    tilt = float(np.degrees(np.arccos(np.clip((rot_seat @ rot_now.T)[2, 2], -1.0, 1.0))))
    if tilt <= tolerance_deg:
        return None
    return (f"{geom.part} must turn {tilt:.0f} deg about a horizontal axis to go into "
            f"{start.targets[geom.action]}, and the robot takes a part from above and turns it only about "
            "the vertical: give the operation agents = [\"human\"], or lay the part as it goes in")


def check_reachability(scenario, task: AndOrGraph, cell) -> list[str]:
    """The check before any physics, in the built workcell ``cell``: each action with every part where the
    earlier actions leave it (:func:`_action_states`). A robot allowed an action plans its whole skill from
    home (reach, grasp, the carry at the cell's carry height, the approach or insertion along the slot's
    axis, the way out: every waypoint needs an IK solution) and must not need to tilt the part
    (:func:`_robot_turn`); the worker's part and target must be in reach of a nominal worker of the cell's
    stature, by the run's own worker planner (:func:`_human_reach`). An action no allowed agent can
    do, or a robot that can do none of its
    actions, is a ConfigError naming the agent, the part, the action and why (for the robot, the point with
    no IK solution). A robot's contract (:func:`robot_refusals`: gripper, payload, reach, hand-over
    clearance) comes first: an action it refuses is the worker's for the whole run. Returns those refusals,
    one line each ("ur5 cannot do g4: ...; the worker does it"), and a parking the cell could not keep."""
    from ergosim.twin.robot_track import RobotTrack  # noqa: PLC0415

    src = cell.config.source
    robots = set(cell.robots)
    allowed: dict[str, set[str]] = {}
    for op in task.operations:
        allowed.setdefault(op.action, set()).update(op.agents)
    human = next(a.name for a in task.agents if a.kind == "human")
    cfg = scenario.protocol
    tracks = {r: RobotTrack(cell, cfg.robot.ee_speed, cfg.robot.transit_speed, robot=r) for r in robots}
    reach_human = _human_reach(cell)
    reached: dict[str, int] = {r: 0 for r in robots}
    tried: dict[str, int] = {r: 0 for r in robots}
    start = _Start(cell)
    refused = robot_refusals(task, cell)
    try:
        for action, state, seated in _action_states(task, cell, start):
            geom = cell.actions[action]
            part_pos = state[geom.part][0]
            target = start.target(geom, state)[0]
            able, why = [], {}
            agents = sorted(allowed.get(action, ()))
            _lay_parts(cell, state, seated)
            for agent in agents:
                if agent == human:
                    worker_why = reach_human(geom)
                    if worker_why is None:
                        able.append(agent)
                    else:
                        why[agent] = worker_why
                elif agent in robots:
                    tried[agent] += 1
                    reason = (_robot_turn(start, geom, state, cell.config.seat_tolerance_deg)
                              or tracks[agent].skill_for(geom).plan_error())
                    beyond = refused.get((action, agent), "").endswith(OUT_OF_REACH)  # its reach sphere
                    reached[agent] += reason is None and not beyond
                    reason = refused.get((action, agent)) or reason  # the contract takes it for the run
                    if reason is None:
                        able.append(agent)
                    else:
                        why[agent] = reason
            if not able:
                if any((action, r) in refused for r in robots):
                    said = "; ".join(refused[(action, r)] for r in sorted(robots) if (action, r) in refused)
                    raise ConfigError(f"no agent can do {action}: {said}", where=f"{src}: actions.{action}")
                who = " or ".join(agents) or "no agent"
                said = "; ".join(f"{a}: {w}" for a, w in why.items())
                goal = f"{geom.handover or start.targets[action]} at {np.round(target, 2).tolist()}"
                raise ConfigError(f"{who} cannot reach {geom.part} for {action} (from "
                                  f"{np.round(part_pos, 2).tolist()} to {goal}; {said}): the run would fail",
                                  where=f"{src}: actions.{action}")
    finally:
        cell.reset()
    for robot in robots:
        if tried[robot] and not reached[robot]:
            base = cell.robot_base_pose(robot)[0]
            raise ConfigError(f"robot {robot!r} at {np.round(base, 2).tolist()} reaches none of the "
                              f"{tried[robot]} actions it may do; move its base or take it out of the task",
                              where=f"{src}: robots.{robot}.base")
    lines = [f"{why}; the {human} does it" if human in allowed[action] else why
             for (action, _), why in sorted(refused.items())]
    for name, park in cell.parks.items():
        if not park.met:
            wanted = next(r.park_clearance for r in cell.config.robots if r.name == name)
            lines.append(f"robot {name!r} parks {park.clearance:.2f} m from the worker's head, neck and "
                         f"chest: no pose from its base keeps {wanted:g} m (robots.{name}.park_clearance)")
    return lines


def _human_reach(cell):
    """The worker's reach test, the run's own: a nominal worker of the cell's stature plans the action with
    the same planner as the run (:class:`~ergosim.worker.motion.Worker`: the stance chosen first, the
    whole-body IK) from the cell as the earlier actions leave it. The action is reachable when the hand gets
    to the part and to the target within the cell's grasp tolerance. Returns ``reason(geom)``: None, or
    where the hand stops short."""
    from ergosim.worker.motion import Worker  # noqa: PLC0415
    from ergosim.worker.subjects import Subject  # noqa: PLC0415

    w = cell.config.worker
    subject = Subject("nominal", stature=w.stature, scale=tuple(w.human_scale), variability_deg=0.0,
                      timing_variability=0.0, handedness=w.hand)
    worker = Worker(subject)
    tolerance = cell.config.grasp_tolerance

    def reason(geom) -> str | None:
        motion = worker.plan(cell, geom, np.random.default_rng(0), action=geom.action)
        for error, what in ((motion.reach_error, "the part"), (motion.place_error, "the target")):
            if error > tolerance:
                return f"out of the worker's reach: the hand stops {error * 100:.0f} cm short of {what}"
        return None

    return reason
