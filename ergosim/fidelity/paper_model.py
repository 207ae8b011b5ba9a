"""The paper's equations alone, fed with the twin's measurements: what would reproduce a §7.2 row (issue 23).

A standalone simulation of eq. 3-11 and Algorithm 2 at the level of whole actions, with no scene and no
motion. For each subject it takes what a twin run measured (:func:`inputs_from_run`): the calibrated α of
every action (eq. 9), how long the worker takes each action alone, how long a robot action lasts and how
much the worker wears while taking the part at the hand-over. It then replays the protocol:

- every decision predicts V̂ = 1 - α (1 - V) for each candidate action (eq. 9), prices the worker's
  hyper-arc with eq. 10-11 and the robot's with c_r, and gives each action the cheaper agent;
- a1 first, a2-a4 in the order of the tie rule (:mod:`ergosim.planner.tie_break`), a5 last, the worker's;
- the worker's action wears V by its α (eq. 4); a robot action lets the worker recover for its length
  (eq. 5) and then wears by the hand-over's α;
- repetitions start at their takt slot (``takt_paced``) or back to back, and the worker recovers while
  waiting.

It reproduces the twin's shares closely (docs/fidelity.md compares them) and runs in milliseconds, so it
answers what-if questions the twin would take hours over: :func:`scaled` multiplies an action's wear
(and its duration, as a longer action of the same postures would) by a factor.
"""

from __future__ import annotations

import csv
import dataclasses
import json
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from ergosim.ergonomics.cost import CostParams, human_cost
from ergosim.ergonomics.kwear import KWearParams
from ergosim.posture import KWEAR_JOINTS

__all__ = ["SubjectInputs", "inputs_from_run", "simulate", "scaled", "Shares"]

FIRST, FREE, LAST = "a1", ("a2", "a3", "a4"), "a5"


@dataclasses.dataclass(frozen=True)
class SubjectInputs:
    """One subject's measured inputs. ``alpha``: action -> (5,) calibrated α (eq. 9); ``worker_s``: action ->
    the worker's duration alone [s]; ``robot_s``: action -> a robot action's duration, hand-over included
    [s]; ``handover_alpha``: action -> (5,) α of the worker's part of a hand-over."""

    alpha: Mapping[str, np.ndarray]
    worker_s: Mapping[str, float]
    robot_s: Mapping[str, float]
    handover_alpha: Mapping[str, np.ndarray]


@dataclasses.dataclass(frozen=True)
class Shares:
    """Robot share of a1-a4 and per action, over every subject and repetition."""

    total: float
    by_action: dict[str, float]
    repetition_s: float
    """mean repetition [s]"""


def scaled(inputs: SubjectInputs, factors: Mapping[str, float]) -> SubjectInputs:
    """The same subject with each action's wear per execution raised to the power ``factors[action]``
    (1 - α grows about that many times) and its duration times that factor."""
    alpha = {a: np.asarray(v) ** factors.get(a, 1.0) for a, v in inputs.alpha.items()}
    worker = {a: v * factors.get(a, 1.0) for a, v in inputs.worker_s.items()}
    return dataclasses.replace(inputs, alpha=alpha, worker_s=worker)


def simulate(subjects: Sequence[SubjectInputs], *, repetitions: int = 10, takt: float = 38.0,
             takt_paced: bool = False, tie: str = "costliest-first",
             cost: CostParams = CostParams(robot_cost=2.5), kwear: KWearParams = KWearParams()) -> Shares:
    """Replay the protocol for every subject (module docstring) and count the robot's actions."""
    robot = {a: 0 for a in (FIRST, *FREE)}
    durations = []
    decay = kwear.r / kwear.C
    for s in subjects:
        v, t = np.zeros(len(KWEAR_JOINTS)), 0.0
        for rep in range(repetitions):
            if takt_paced and t < rep * takt:
                v, t = v * np.exp(-decay * (rep * takt - t)), rep * takt
            start = t
            left = list(FREE)
            for slot in (FIRST, None, None, None, LAST):
                agent_cost = {a: _costs(s, a, v, cost) for a in ([slot] if slot else left)}
                action = slot or _pick(agent_cost, left, tie)
                if slot is None:
                    left.remove(action)
                human, robot_c = agent_cost[action]
                if action != LAST and robot_c < human:
                    robot[action] += 1
                    v = v * np.exp(-decay * s.robot_s[action])
                    v = 1.0 - s.handover_alpha[action] * (1.0 - v)
                    t += s.robot_s[action]
                else:
                    v = 1.0 - s.alpha[action] * (1.0 - v)
                    t += s.worker_s[action]
            durations.append(t - start)
    n = len(subjects) * repetitions
    by_action = {a: robot[a] / n for a in robot}
    return Shares(float(np.mean(list(by_action.values()))), by_action, float(np.mean(durations)))


def _costs(s: SubjectInputs, action: str, v: np.ndarray, cost: CostParams) -> tuple[float, float]:
    """(worker's hyper-arc cost, robot's) for ``action`` at wear ``v`` (eq. 9-11)."""
    v_hat = 1.0 - np.asarray(s.alpha[action]) * (1.0 - v)
    return float(human_cost(v_hat, cost)), cost.robot_cost


def _pick(costs: Mapping[str, tuple[float, float]], order: Sequence[str], tie: str) -> str:
    """The next free action: every order of a2-a4 costs the same, the tie rule decides."""
    if tie == "task-order":
        return order[0]
    step = {a: min(c) for a, c in costs.items()}
    sign = -1.0 if tie == "costliest-first" else 1.0
    return min(order, key=lambda a: (sign * step[a], order.index(a)))


def inputs_from_run(folder: str | Path, mode: str = "hrc") -> list[SubjectInputs]:
    """Every subject's inputs from a run folder: α from summary.json, the worker's and the robot's
    durations from allocations.csv (means over the run), and a hand-over's α from ticks.csv (the KWear
    after over before the worker's acting ticks of each robot action). Actions the robot never did take
    the run's mean over subjects; a subject without any takes the worker's own α for the hand-over."""
    folder = Path(folder)
    summary = json.loads((folder / "summary.json").read_text())
    alphas = summary["calibration"]["alpha_by_subject"]
    rows = [r for r in csv.DictReader((folder / "allocations.csv").open()) if r["mode"] == mode
            and r["status"] == "done"]
    ticks = np.genfromtxt(folder / "ticks.csv", delimiter=",", names=True, dtype=None, encoding=None)
    out = []
    for subject, alpha in enumerate(alphas):
        mine = [r for r in rows if int(r["subject"]) == subject]
        worker, robot, ho = {}, {}, {}
        tk = ticks[(ticks["subject"] == subject) & (ticks["mode"] == mode)]
        v = np.stack([tk[f"kwear_{j}"] for j in KWEAR_JOINTS], axis=1)
        for r in mine:
            t0, t1 = float(r["t_start"]), float(r["t_end"])
            if r["agent"] == "human":
                worker.setdefault(r["action"], []).append(t1 - t0)
                continue
            robot.setdefault(r["action"], []).append(t1 - t0)
            acting = np.flatnonzero((tk["t"] > t0) & (tk["t"] <= t1) & (tk["acting"] == 1))
            if len(acting) and acting[0] > 0:
                ho.setdefault(r["action"], []).append((1.0 - v[acting[-1]]) / (1.0 - v[acting[0] - 1]))
        out.append(SubjectInputs({a: np.asarray(x, dtype=float) for a, x in alpha.items()},
                                 {a: float(np.mean(x)) for a, x in worker.items()},
                                 {a: float(np.mean(x)) for a, x in robot.items()},
                                 {a: np.mean(x, axis=0) for a, x in ho.items()}))
    return _filled(out)


def _filled(subjects: list[SubjectInputs]) -> list[SubjectInputs]:
    """Missing robot durations and hand-over α from the other subjects' means (or the worker's own α)."""
    actions = (FIRST, *FREE)
    robot_mean = {a: float(np.mean([s.robot_s[a] for s in subjects if a in s.robot_s]))
                  for a in actions if any(a in s.robot_s for s in subjects)}
    out = []
    for s in subjects:
        robot = {a: s.robot_s.get(a, robot_mean.get(a, 14.0)) for a in actions}
        ho = {a: s.handover_alpha.get(a, s.alpha[a]) for a in actions}
        out.append(dataclasses.replace(s, robot_s=robot, handover_alpha=ho))
    return out
