"""A parallel team that can no longer move: a robot held in a protective stop next to the idle worker.

Speed and separation monitoring (ISO/TS 15066 §5.5.4, :mod:`ergosim.twin.ssm_monitor`) stops a robot
below the protective separation distance and lets it resume once the worker has moved away. The twin's idle
worker keeps its posture: it does not step aside for a stopped robot. So a robot whose place, insertion
or way home passes within S_p(0) of the idle worker would wait for good, and its repetition with it (found
with the §7.2 cell without hand-over poses: the robot setting J down at the assembly area). A hand-over
never stops (it goes on at the contact speed). :class:`StandoffWatch` says when such a stop has lasted
:data:`STANDOFF_TIMEOUT`; the team session then abandons the repetition.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

__all__ = ["STANDOFF_TIMEOUT", "StandoffWatch"]

STANDOFF_TIMEOUT = 10.0
"""s a robot may stay in a protective stop while the worker is idle before the repetition is abandoned as a
standoff (assumed: the twin's idle worker does not step aside, so nothing changes after that; ten times the
longest settle of a released part)."""


class StandoffWatch:
    """Counts, per robot, how long it has been in a protective stop while the worker is idle."""

    def __init__(self) -> None:
        self.since: dict[str, int] = {}
        """robot -> the control tick since which it has been stopped with the worker idle."""

    def check(self, plant, worker_idle: bool, robot_jobs: Iterable) -> str | None:
        """Why the team can no longer move, or None. ``plant``: its ``ticks`` and ``dt_control`` [s];
        ``robot_jobs``: the robots' jobs (``agent``, ``state``, ``geom.action``, ``track`` with ``moving``,
        ``speed`` and ``cell``). A worker at work may still clear the way: the count waits for it."""
        if not worker_idle:
            self.since.clear()
            return None
        for job in robot_jobs:
            track = job.track
            if not (track.moving and track.speed <= 0.0):
                self.since.pop(job.agent, None)
                continue
            start = self.since.setdefault(job.agent, plant.ticks)
            if (plant.ticks - start) * plant.dt_control >= STANDOFF_TIMEOUT:
                return _message(job)
        return None


def _message(job) -> str:
    cell = job.track.cell
    where = np.round(cell.data.site_xpos[cell.robot(job.agent).tcp], 3).tolist()
    doing = "on its way home after " if job.state == "homing" else "doing "
    return (f"standoff: {job.agent}, {doing}{job.geom.action}, has been in a protective stop for "
            f"{STANDOFF_TIMEOUT:.0f} s with its TCP at {where} (speed and separation monitoring, ISO/TS "
            "15066) while the idle worker stays within the protective separation distance; move the "
            "action's target or the robot away from where the worker stands, or set ssm = \"off\"")
