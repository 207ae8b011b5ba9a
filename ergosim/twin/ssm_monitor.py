"""Speed and separation monitoring in the loop: measure the human-robot separation, scale the robots.

At every ergonomics tick (20 Hz) the monitor measures each robot's separation from the worker (capsules,
:mod:`ergosim.scenes.separation`; a part the robot holds counts as the robot) and the worker's speed
towards it (the nearest segment's, from the tracked posture between two samples), and, when scaling is on,
sets the robot's speed factor from ISO/TS 15066 (:mod:`ergosim.robot.ssm`): full speed above the
protective separation distance, slower closer, a stop below S_p(0). A robot at a standstill on purpose
(closing or opening the gripper, holding a part out at a handover, where the worker takes it from a
stopped robot: ISO 10218-2 §5.11.5 hand-over window) is not scaled. On a hand-over, a collaborative
operation under power and force limiting (ISO/TS 15066 §5.5.5), the robot slows no further than the
contact speed, the paper's 0.05 m/s, and its contact-speed phases are not slowed. The
monitor's figures (:class:`SafetyRecord`) go into the run's records.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ergosim.robot.skills import Handover
from ergosim.robot.ssm import SSMParams, speed_scale
from ergosim.scenes.separation import Capsules, SeparationModel, capsules_of
from ergosim.twin.loop import PlantHook

__all__ = ["SafetyRecord", "SafetyMonitor"]


@dataclasses.dataclass(frozen=True)
class SafetyRecord:
    """What the monitor saw over one run. Distances [m], times [s] of simulated time.

    ``scaled``: the robots' speed was scaled (SSM on); ``min_separation`` and when it happened;
    ``slowed``/``stopped``: per robot, the time its motion ran below full speed / was stopped;
    ``overlap``: time any robot capsule overlapped a worker capsule (separation <= 0: the worker's kinematic
    body reaching into the robot, or taking a part from its gripper), of which ``overlap_moving`` while that
    robot was moving (neither stopped by the monitor nor holding still);
    ``end_separation``: the separation when the run ended (the robot must not end inside the worker)."""

    scaled: bool
    min_separation: float
    min_separation_time: float
    slowed: dict[str, float]
    stopped: dict[str, float]
    overlap: float
    end_separation: float
    overlap_moving: float = 0.0
    params: dict = dataclasses.field(default_factory=dict)
    """The monitoring parameters (the workcell's ``[safety]`` table)."""

    def to_dict(self) -> dict:
        def num(x: float) -> float | None:
            return float(x) if math.isfinite(x) else None

        return {"ssm": self.scaled, "min_separation_m": num(self.min_separation),
                "min_separation_t": num(self.min_separation_time),
                "robot_slowed_s": dict(self.slowed), "robot_stopped_s": dict(self.stopped),
                "overlap_s": self.overlap, "overlap_moving_s": self.overlap_moving,
                "end_separation_m": num(self.end_separation)}


class SafetyMonitor(PlantHook):
    """Monitors ``robots`` (name -> :class:`~ergosim.twin.robot_track.RobotTrack`) in ``cell`` every
    ``every`` control ticks of ``dt_control`` [s]; ``scale``: set the robots' speed factors (else measure
    only)."""

    def __init__(self, cell, robots: dict, params: SSMParams, *, scale: bool, every: int,
                 dt_control: float) -> None:
        self.cell = cell
        self.robots = dict(robots)
        self.params = params
        self.scale = scale
        self.every = int(every)
        self.dt = self.every * dt_control
        human = cell.human.kin_model
        self.sep = SeparationModel(cell.model, {r: cell.robot(r).base for r in self.robots},
                                   [human.body(b).name for b in range(1, human.nbody)])
        self._parts: dict[tuple[int, ...], Capsules] = {}
        self._prev: tuple[np.ndarray, np.ndarray] | None = None
        self.min_separation = math.inf
        self.min_time = math.nan
        self.slowed = dict.fromkeys(self.robots, 0.0)
        self.stopped = dict.fromkeys(self.robots, 0.0)
        self.overlap = 0.0
        self.overlap_moving = 0.0

    @staticmethod
    def _in_handover(track) -> bool:
        """The robot is on a hand-over (a :class:`~ergosim.robot.skills.Handover`: to the part, with it to
        the worker, away and home). A hand-over is a collaborative operation near the worker by design (the
        part presented where the worker needs it, at the assembly, issue 23), under power and force limiting
        (ISO/TS 15066 §5.5.5): where separation would stop the robot, it goes on at the contact speed, the
        paper's 0.05 m/s, instead; its contact-speed phases are not slowed. An idle worker waiting for the
        part, who does not step aside, would otherwise hold the robot still for good (the parallel runs of
        multi-subject hung so: on the way in, on the way out, and on the retreat after a hand-over)."""
        return isinstance(track.skill, Handover)

    def _held(self, robot: str) -> Capsules | None:
        cell = self.cell
        geoms = [g for p in cell.parts if cell.is_held(robot, p) for g in cell.collision_geoms(p).tolist()]
        if not geoms:
            return None
        key = tuple(geoms)
        if key not in self._parts:
            self._parts[key] = capsules_of(cell.model, geoms)
        return self._parts[key]

    def _human_speed(self, sep, now: tuple[np.ndarray, np.ndarray]) -> float:
        """The worker's speed towards the robot [m/s]: the nearest point's, between this and the last
        sample, along the line to the robot's nearest point."""
        if not self.params.measured_speed:
            return self.params.human_speed
        if self._prev is None:
            return 0.0
        j, t = sep.human_capsule, sep.human_t
        before = self._prev[0][j] + t * (self._prev[1][j] - self._prev[0][j])
        toward = sep.robot_point - sep.human_point
        norm = float(np.linalg.norm(toward))
        if norm < 1e-9:
            return 0.0
        return max(0.0, float((sep.human_point - before) @ toward) / (norm * self.dt))

    def measure(self, plant) -> float:
        """Measure (and scale) now; the smallest separation of any robot [m]."""
        data = plant.data
        human = self.sep.human_segments(data)
        closest = math.inf
        moving_overlap = False
        for name, track in self.robots.items():
            held = self._held(name)
            sep = self.sep.separation(data, name, human, held)
            closest = min(closest, sep.distance)
            if self.scale:
                factor = 1.0
                if track.moving:
                    limits = track.params.limits
                    nominal = limits.speed if track.skill.phase == "contact" else limits.transit_speed
                    floor = limits.speed / nominal if self._in_handover(track) else 0.0
                    factor = 1.0 if floor >= 1.0 else max(floor, speed_scale(
                        self.params, sep.distance, self._human_speed(sep, human), nominal))
                    if factor <= 0.0:
                        self.stopped[name] += self.dt
                    elif factor < 1.0:
                        self.slowed[name] += self.dt
                track.speed = factor
            moving_overlap |= sep.distance <= 0.0 and track.moving and track.speed > 0.0
        self._prev = human
        if closest < self.min_separation:
            self.min_separation, self.min_time = closest, plant.time
        if closest <= 0.0:
            self.overlap += self.dt
        if moving_overlap:
            self.overlap_moving += self.dt
        return closest

    def after_step(self, plant) -> None:
        if plant.ticks % self.every == 0:
            self.measure(plant)

    def record(self, plant) -> SafetyRecord:
        """The figures so far, with the separation now as the end separation."""
        end = self.measure(plant)
        for track in self.robots.values():
            track.speed = 1.0
        return SafetyRecord(self.scale, self.min_separation, self.min_time, dict(self.slowed),
                            dict(self.stopped), self.overlap, end, self.overlap_moving,
                            dataclasses.asdict(self.params))
