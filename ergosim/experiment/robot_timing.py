"""The robot-only assembly (paper §7.2: the takt was set from it): every action a robot may do goes to the
robot, and where its time goes.

Each subject's r-only repetition runs in the real loop, with the same random streams as ``ergosim run
--mode r-only`` (calibration is skipped: no risk index prices anything in r-only), so the figures are those
of a normal run. Per robot action the skill's own phases (:data:`~ergosim.robot.status.SKILL_PHASES`) say
how much was transit, contact-critical motion, gripper, waiting for the worker at the handover and the way
home; the rest of an action's duration is the worker finishing a handover after the robot is back.
"""

from __future__ import annotations

import dataclasses
import statistics

import numpy as np

from ergosim.experiment.scenario import Scenario
from ergosim.experiment.subject import rig_spec, scenario_subject
from ergosim.robot.status import SKILL_PHASES, SkillResult
from ergosim.twin.rig import build_rig, make_allocator, streams
from ergosim.twin.session import Session

__all__ = ["ActionTiming", "RobotOnlyRun", "robot_only_runs", "timing_summary", "format_summary"]

_HOME_TIMEOUT_S = 30.0
"""Longest wait [s of simulated time] for the robot to finish its last action after the repetition ended."""


@dataclasses.dataclass(frozen=True)
class ActionTiming:
    """One action of a robot-only repetition: ``duration`` [s] from dispatch to completion (the scene's);
    ``robot`` the skill's result (None for the worker's actions)."""

    action: str
    agent: str
    status: str
    duration: float
    robot: SkillResult | None

    @property
    def robot_time(self) -> float:
        """The robot's own time [s]: its skill's duration less the wait for the worker at the handover."""
        return 0.0 if self.robot is None else self.robot.duration - self.robot.phase("wait")

    @property
    def delivery(self) -> float:
        """When the robot had brought the part to its target or handover pose [s from dispatch]; NaN for a
        robot action that never got there (it failed)."""
        return 0.0 if self.robot is None else self.robot.arrival

    @property
    def failed(self) -> bool:
        """A robot action whose part never reached its target or handover pose."""
        return self.robot is not None and not np.isfinite(self.robot.arrival)


@dataclasses.dataclass(frozen=True)
class RobotOnlyRun:
    """One subject's first r-only repetition: ``repetition`` [s] from start to completion (or abandonment)."""

    subject: int
    outcome: str
    repetition: float
    actions: tuple[ActionTiming, ...]

    @property
    def robot_time(self) -> float:
        """Sum of the robot's own time over its actions [s]."""
        return sum(a.robot_time for a in self.actions)

    @property
    def delivery(self) -> float:
        """Sum over the robot's actions of the time to bring the part to its target or handover pose [s]
        (the actions it delivered)."""
        return sum(a.delivery for a in self.actions if not a.failed)

    @property
    def robot_failures(self) -> int:
        return sum(a.failed for a in self.actions)


def robot_only_runs(scenario: Scenario, subjects: int, seed: int = 0) -> list[RobotOnlyRun]:
    """One r-only repetition for each of the first ``subjects`` subjects of ``seed``'s population."""
    sc = scenario.with_overrides({"repetitions": "1", "modes": "r-only"})
    spec = rig_spec(sc)
    out = []
    for index in range(subjects):
        subject = scenario_subject(sc, index, seed)
        rng = np.random.default_rng(streams(seed, index, (0,))[1])  # run_subject's stream of mode slot 0
        rig = build_rig(spec, subject, rng)
        allocator = make_allocator(spec.config, "r-only", rig, None)
        plant = rig.plant
        session = Session(cfg=spec.config, mode="r-only", subject_index=index, worker=rig.worker,
                          plant=plant, robot=rig.robots, allocator=allocator, rng=rng)
        run = session.run(1)
        # the repetition may end while the last robot action's arm is still on its way home (the worker
        # finishing a5 first): let it get there, so that action's skill result (its timing) exists
        plant.run_until(lambda: not any(t.active for t in rig.robots.values()), _HOME_TIMEOUT_S)
        results = iter([r for track in rig.robots.values() for r in track.results])
        human = session.allocator.human
        actions = tuple(ActionTiming(a.action, a.agent, a.status, a.t_end - a.t_start,
                                     None if a.agent in (human, "") else next(results, None))
                        for a in run.allocations)
        o = run.outcomes[0]
        out.append(RobotOnlyRun(index, o.outcome, o.t_end - o.t_start, actions))
    return out


def timing_summary(runs: list[RobotOnlyRun]) -> dict:
    """Means over subjects [s]: the repetition, the robot's own time, and per action its duration and each
    robot phase (plus ``worker_after``: the action's time beyond the robot's skill, the worker finishing)."""
    per_action: dict[str, dict[str, list[float]]] = {}
    for run in runs:
        for a in run.actions:
            row = per_action.setdefault(a.action, {"duration": []})
            row["duration"].append(a.duration)
            if a.robot is not None and not a.failed:
                for phase in SKILL_PHASES:
                    row.setdefault(phase, []).append(a.robot.phase(phase))
                row.setdefault("worker_after", []).append(max(0.0, a.duration - a.robot.duration))
                row.setdefault("delivery", []).append(a.delivery)
    reps = [r.repetition for r in runs]
    return {  # a robot action that failed counts in no phase nor delivery: "robot_failures" says how many
        "subjects": len(runs),
        "completed": sum(r.outcome == "completed" for r in runs),
        "repetition_mean_s": statistics.fmean(reps),
        "repetition_min_s": min(reps),
        "repetition_max_s": max(reps),
        "robot_time_mean_s": statistics.fmean(r.robot_time for r in runs),
        "delivery_mean_s": statistics.fmean(r.delivery for r in runs),
        "robot_failures": sum(r.robot_failures for r in runs),
        "actions": {a: {k: statistics.fmean(v) for k, v in row.items()} for a, row in per_action.items()},
    }


def format_summary(summary: dict) -> str:
    """The summary of :func:`timing_summary` as a text table (seconds)."""
    cols = ("duration", "delivery", *SKILL_PHASES, "worker_after")
    lines = [f"robot-only repetition: mean {summary['repetition_mean_s']:.1f} s (min "
             f"{summary['repetition_min_s']:.1f}, max {summary['repetition_max_s']:.1f}) over "
             f"{summary['subjects']} subject(s), {summary['completed']} completed; robot's own time "
             f"{summary['robot_time_mean_s']:.1f} s, of which bringing the parts "
             f"{summary['delivery_mean_s']:.1f} s" + (f"; {summary['robot_failures']} robot action(s) failed"
                                                       if summary.get("robot_failures") else ""),
             "action " + " ".join(f"{c:>12}" for c in cols)]
    for action, row in summary["actions"].items():
        cells = (f"{row[c]:12.2f}" if c in row else f"{'-':>12}" for c in cols)
        lines.append(f"{action:6s} " + " ".join(cells))
    return "\n".join(lines)
