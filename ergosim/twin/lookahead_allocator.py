"""The ``kwear-lookahead`` mode's allocator: the next (action, agent) starts the cheapest *sequence*.

Pricing is the paper's (the subject's calibrated α, eq. 9-11, c_r) chained along the plan, with recovery
while a robot acts and the takt (:mod:`ergosim.planner.wear_chain`, :mod:`ergosim.planner.lookahead`). What
the twin supplies beside the KWear index: the expected duration of every (action, agent)
(:mod:`ergosim.twin.durations`: the worker's from calibration, a robot's from its planned trajectory, a
handover's with the worker's take), and when the repetition started (the takt is counted from there).

A robot whose skill cannot be planned from the cell as laid out (no expected duration) is not offered the
action. Once an (action, agent) has been executed, its expected duration is the mean of its executions so
far. A handover's planned estimate adds the worker's whole action for the take, which overstates it: once a
robot's handover has been observed, the worker's take (observed minus the robot's planned part) replaces
that estimate for the robot's other handovers too.

In parallel execution a handover's span includes its wait for the worker, so handovers keep their
expectations there. A robot's action is done when the robot has let the part go (a handover's after the
worker's take; the robot's way home overlaps the next actions, :mod:`ergosim.twin.team_session`): its
expected duration runs to the release, and the planned way home is the robot's ``leave``
(:class:`~ergosim.planner.wear_chain.WearModel`). The separation monitor slows a robot near the worker, so
its unobserved actions are expected as much slower than planned as its observed ones were, on average.

The decision record keeps the paper's order-free V̂ and costs of this decision point (what allocations.csv
prints) and adds, in ``through``, the cost of the chosen sequence.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from ergosim.errors import InfeasiblePlanError
from ergosim.planner.lookahead import LookaheadPlan, SearchLimits, lookahead_plan
from ergosim.planner.wear_chain import WearModel
from ergosim.twin.allocator import Allocator, Decision, SequenceChoice
from ergosim.twin.durations import expected_durations

__all__ = ["LookaheadAllocator", "lookahead_settings", "PARALLEL_TIME_SHARE"]


PARALLEL_TIME_SHARE = 1.0
"""The parallel default ``time_weight`` as a share of the takt weight: a second of the makespan costs what a
second past the takt costs (assumed, set before the sweep of docs/allocation_modes.md). The sweep over both
bundled team scenarios (shares 0.25-2) found a share, 0.375, at which the gearbox meets issue 24's goal on
its 3 subjects; it was searched for, on a steep part of the curve, so it is not the default (``--set
time_weight=...`` runs it)."""


def lookahead_settings(cfg) -> tuple[float, float, SearchLimits]:
    """(takt weight [cost per s past the takt], time weight [cost per s of plan duration], search limits)
    of protocol ``cfg``: ``takt_weight`` (None: Γ/takt, assumed: a whole takt of overrun costs as much as one
    joint past V_th, eq. 11), ``time_weight`` (None: 0 in sequential execution, :data:`PARALLEL_TIME_SHARE`
    × the takt weight in parallel), ``lookahead_exact`` and ``lookahead_beam``."""
    look = cfg.lookahead
    takt_weight = cfg.cost.gamma / cfg.pacing.takt if look.takt_weight is None else look.takt_weight
    time_weight = look.time_weight
    if time_weight is None:
        time_weight = PARALLEL_TIME_SHARE * takt_weight if cfg.team.execution == "parallel" else 0.0
    return float(takt_weight), float(time_weight), SearchLimits(exact_sequences=look.lookahead_exact,
                                                               beam_width=look.lookahead_beam)


class LookaheadAllocator(Allocator):
    """Decides by the look-ahead; the paper's :class:`Allocator` supplies the index, the costs for the
    record, the mode's pruning and the time term's durations. Call :meth:`prepare` before the first
    decision (the session's setup does)."""

    def __init__(self, graph, mode, *, index, cost, planner: str = "fast", w_time: float = 0.0,
                 durations: Mapping[tuple[str, str], float] | None = None,
                 refused: frozenset[tuple[str, str]] = frozenset()) -> None:
        super().__init__(graph, mode, index=index, cost=cost, planner=planner, w_time=0.0,
                         durations=durations, refused=refused)
        self.model: WearModel | None = None
        self.limits = SearchLimits()
        self.unreachable: set[tuple[str, str]] = set()
        self._start: dict[int, float] = {}
        self.last_plan: LookaheadPlan | None = None
        """The look-ahead's last plan (for tests and the Gym environment's info)."""

    def prepare(self, *, cfg, cell, robots, human_seconds: Mapping[str, float]) -> None:
        """Build the wear model from the subject's calibration (α, its KWear constants), the cell's expected
        durations and the protocol's cost and time settings."""
        self.durations = expected_durations(cell, robots, self.allowed, self.human, human_seconds)
        self.leaves: dict[tuple[str, str], float] = {}
        if cfg.team.execution == "parallel":  # the robot's way home overlaps the next actions
            for (action, agent), seconds in list(self.durations.items()):
                if agent in robots:
                    leave = robots[agent].planned_leave(cell.actions[action])
                    if math.isfinite(leave):
                        self.durations[(action, agent)] = seconds - leave
                        self.leaves[(action, agent)] = leave
        self.takes = {(a, r): human_seconds.get(a, 0.0) for a, agents in self.allowed.items()
                      if cell.actions[a].handover is not None for r in agents if r in self.robots}
        self.unreachable = {(a, r) for a, agents in self.allowed.items() for r in agents
                            if r in self.robots and (a, r) not in self.durations}
        self.takt_weight, self.time_weight, self.limits = lookahead_settings(cfg)
        self.takt, self.next_weight = cfg.pacing.takt, cfg.lookahead.lookahead_next
        self._observed: dict[tuple[str, str], list[float]] = {}
        self._build()

    def _build(self) -> None:
        durations = dict(self.durations)
        takes = dict(self.takes)
        robot_part = {k: durations[k] - takes[k] for k in takes if k in durations}
        seen_takes: dict[str, list[float]] = {}
        for key, seen in self._observed.items():
            if key in robot_part:  # the robot's part as planned; the take is what the executions add to it
                seen_takes.setdefault(key[1], []).append(max(0.0, sum(seen) / len(seen) - robot_part[key]))
        for key, part in robot_part.items():
            if key in self._observed:
                seen = self._observed[key]
                takes[key] = max(0.0, sum(seen) / len(seen) - part)
            elif key[1] in seen_takes:  # a take from the same handover pose, measured on another action
                takes[key] = sum(seen_takes[key[1]]) / len(seen_takes[key[1]])
            durations[key] = part + takes[key]
        for key, seen in self._observed.items():
            durations[key] = sum(seen) / len(seen)
        # In parallel the separation monitor slows a robot near the worker: a robot's executions so far,
        # against their plans, say how much slower its other actions will be than planned.
        slow: dict[str, list[float]] = {}
        for (action, agent), seen in self._observed.items():
            planned = self.durations.get((action, agent), 0.0)
            if (action, agent) in self.leaves and (action, agent) not in takes and planned > 0:
                slow.setdefault(agent, []).append(sum(seen) / len(seen) / planned)
        for key in self.leaves:
            if key not in self._observed and key[1] in slow:
                take = takes.get(key, 0.0)
                durations[key] = take + (durations[key] - take) * sum(slow[key[1]]) / len(slow[key[1]])
        self.model = WearModel.build(
            self.graph.actions, [a.name for a in self.graph.agents], self.human, alphas=self.index.alphas,
            kwear=self.index.params, cost=self.cost, durations=durations, takes=takes, takt=self.takt,
            takt_weight=self.takt_weight, time_weight=self.time_weight, next_weight=self.next_weight,
            robot_actions=[a for a, agents in self.allowed.items() if agents & set(self.robots)],
            leaves=self.leaves)

    def observe(self, action: str, agent: str, seconds: float) -> None:
        """A completed execution: from now on the (action, agent)'s expected duration is the mean of those
        observed in this run (the expectation from the plan and calibration until the first one)."""
        self._observed.setdefault((action, agent), []).append(float(seconds))
        self._build()

    def repetition_start(self, repetition: int, time: float) -> float:
        """When ``repetition`` started [s]: the time of its first decision."""
        return self._start.setdefault(repetition, time)

    def excluded(self, pruned: set[tuple[str, str]]) -> set[tuple[str, str]]:
        """As the paper's allocator, and the robot actions with no planned trajectory from the cell as laid
        out (:attr:`unreachable`)."""
        return super().excluded(pruned) | self.unreachable

    def decide(self, v_now: np.ndarray, done: list[str], pruned: set[tuple[str, str]], time: float,
               repetition: int) -> Decision | None:
        done_actions = {self.action_of(o) for o in done}
        remaining = [a for a in self.graph.actions if a not in done_actions]
        if not remaining:
            return None
        elapsed = time - self.repetition_start(repetition, time)
        v_hat, costs, _ = self.price(remaining)
        cut = self.excluded(pruned)
        plan = lookahead_plan(self.graph, self.model, v_now, done=done, pruned=cut, elapsed=elapsed,
                              limits=self.limits)
        self.last_plan = plan
        step = plan.next
        if step is None:
            return None
        agents = self.allowed[step.action] - {a for (act, a) in cut if act == step.action}
        other = math.nan
        if len(agents) > 1 and plan.exact:  # the cheapest sequence that gives the action to another agent
            try:
                other = lookahead_plan(self.graph, self.model, v_now, done=done, elapsed=elapsed,
                                       pruned=cut | {(step.action, step.agent)}, limits=self.limits).cost
            except InfeasiblePlanError:
                pass
        return Decision(
            time=time, repetition=repetition, v_now=np.array(v_now), v_hat=v_hat, costs=costs,
            action=step.action, agent=step.agent, operation=step.operation, had_choice=len(agents) > 1,
            basis=self.basis, through=plan.cost,
            sequence=SequenceChoice(tuple((s.action, s.agent) for s in plan.steps), plan.cost, other,
                                    plan.exact, plan.gap),
        )
