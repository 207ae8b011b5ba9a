"""Expected durations of every (action, agent): the time term of the hyper-arc costs (w_time × duration).

- The worker's come from calibration (paper §5): the mean duration of the action's calibration executions,
  each planned from the scene and timed by MTM-1 at the subject's pace (:mod:`ergosim.worker.action_timing`).
- A robot's come from its planned trajectory: the skill is planned from the cell as it is laid out for a
  repetition (the robot at home, the parts at their initial poses) and timed from its joint trajectories,
  the gripper and its pauses (:meth:`~ergosim.robot.skills.PickPlace.planned_time`). Where the robot hands
  the part over, the worker then takes and places it: the worker's duration of the action is added.

A robot that cannot reach the action gets no entry (its hyper-arc keeps its cost without a time term; the
skill reports ``unreachable`` when dispatched).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

__all__ = ["human_durations", "expected_durations"]


def human_durations(passes) -> dict[str, float]:
    """action -> mean duration [s] of its executions in calibration ``passes`` (lists of action ->
    :class:`~ergosim.ergonomics.calibration.Execution`)."""
    out: dict[str, list[float]] = {}
    for p in passes:
        for action, ex in p.items():
            out.setdefault(action, []).append(len(ex.g) * ex.dt)
    return {a: sum(v) / len(v) for a, v in out.items()}


def expected_durations(cell, robots: Mapping[str, object], allowed: Mapping[str, set[str]], human: str,
                       human_seconds: Mapping[str, float]) -> dict[tuple[str, str], float]:
    """(action, agent) -> expected duration [s] for every agent ``allowed`` to do each action: the worker
    (``human``) from ``human_seconds``, each robot (name -> :class:`~ergosim.twin.robot_track.RobotTrack`)
    from its planned trajectory in ``cell`` as it is now."""
    out: dict[tuple[str, str], float] = {}
    for action, agents in allowed.items():
        geom = cell.actions[action]
        worker = human_seconds.get(action, 0.0)
        for agent in sorted(agents):
            if agent == human:
                if action in human_seconds:
                    out[(action, agent)] = human_seconds[action]
            elif agent in robots:
                t = robots[agent].planned_time(geom)
                if math.isfinite(t):
                    out[(action, agent)] = t + (worker if geom.handover is not None else 0.0)
    return out
