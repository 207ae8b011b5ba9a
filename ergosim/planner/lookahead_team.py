"""Parallel decisions that look at time: what each idle agent starts now, read off the cheapest schedule.

With ``execution = "parallel"`` several agents work at once (issue 17). The paper's cost gives no reason to
keep an idle robot idle, so the first team rule gave it any ready operation within Γ of the optimum: in the
gearbox the robot then takes g3 at t = 0 and needs 18.6 s for what the worker does in 4.4 s, and the worker,
done with g1 and g2, waits 12 s for it. The look-ahead prices *schedules* instead (Lamon, Fusaro et al.'s
HRT weighs makespan beside ergonomics in the same way):

- a sequence of hyper-arcs is a priority list; each step starts as soon as its agent is free and its
  children exist (list scheduling: a semi-active schedule, no agent idles while its next step could start);
- a worker step rests the worker from its last step to its start (eq. 5) and wears it over the step
  (eq. 9), priced Σ γ_i (eq. 10-11);
- a robot step costs c_r; a robot's place, insertion or fastening is done when it lets the part go, and the
  robot is free again after its way home (``leave``), which overlaps the next steps; a robot's handover
  fetches the part from when the robot is free and the part's sub-assembly exists (or, when the part is
  not known, the operation's children are under way), and ends with the worker taking it when the part is
  at the handover pose, the worker is free and the operation's other children exist (the worker rests
  until then; the take's own wear is not predicted);
- time: ``time_weight`` × the schedule's makespan (its critical path through durations and waits) and
  ``takt_weight`` × its overrun of the takt (:mod:`ergosim.planner.wear_chain`).

The cheapest schedule is searched with the sequential look-ahead's exact search or beam (same limits, same
reported bound; :mod:`ergosim.planner.lookahead`). The decision: the first step of every idle agent in that
schedule, if it starts now; an idle agent whose first step starts later waits for it. A robot gets an action
that the worker would finish long before it only if the wear the worker is spared (and its rest while it
waits) outweighs ``time_weight`` × the longer makespan: the gearbox's parallel runs still show it
(docs/allocation_modes.md).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from ergosim.errors import ConfigError
from ergosim.planner.chain_pricing import Pricing
from ergosim.planner.lookahead import LookaheadPlan, SearchLimits, search_sequences
from ergosim.planner.plan import PlanStep
from ergosim.planner.wear_chain import WearModel

__all__ = ["TeamState", "TeamPricing", "TeamLookahead", "lookahead_team"]

_NOW_TOL = 1e-9  # s: a step predicted to start within this of now starts now


@dataclass(frozen=True)
class TeamState:
    """The team when it decides. Times in seconds from the repetition's start: ``now``; ``worker_free``
    (≥ now) when the worker is next free, and ``v`` (p,) its predicted KWear then (after the action it is
    doing); ``free`` robot -> when it is next free; ``running`` operation -> its predicted end (it holds its
    children until then); ``reserved`` action -> the robot fetching its part to hand it over (started early,
    already paid for, and kept for that robot even if pruned; the robot's ``free`` is when the part reaches
    the handover pose)."""

    now: float
    v: np.ndarray
    worker_free: float
    free: Mapping[str, float]
    running: Mapping[str, float]
    reserved: Mapping[str, str]
    moving: Mapping[tuple[str, str], str] = field(default_factory=dict)
    """(action, robot) -> the part a robot's handover carries: its fetch needs only that part's
    sub-assembly, not the operation's other children (which the take joins, as the twin's board does)."""


class TeamPricing(Pricing):
    """Schedules from a :class:`TeamState`. State of a partial sequence: (cost, worker V (n, p) at its last
    busy end, that time (n,), each agent's free time (n, N), each part's sub-assembly ready time (n, P) and
    the start of the step that makes it (n, P), the makespan (n,))."""

    def __init__(self, graph, model: WearModel, team: TeamState,
                 pruned: Iterable[tuple[str, str]] = ()) -> None:
        super().__init__(graph, model, pruned)
        if self.human < 0:
            raise ConfigError("parallel look-ahead needs the task's human agent in the wear model",
                              where="lookahead_team")
        self.team = team
        self.take = np.where(np.arange(len(graph.agents))[None, :] == self.human, 0.0,
                             self.duration - self.rest_s)
        """(A, N) the worker's seconds at the end of a robot's handover (0: not a handover)."""
        self.fetch = self.duration - self.take
        agent_of = {a.name: i for i, a in enumerate(graph.agents)}
        act_of = {a: i for i, a in enumerate(graph.actions)}
        part_of = {p: i for i, p in enumerate(graph.parts)}
        self.moving = np.full((len(act_of), len(agent_of)), -1, dtype=np.int64)
        """(A, N) the part index a robot's handover carries (-1: unknown: its fetch waits for the
        children)."""
        for (action, robot), part in team.moving.items():
            if action in act_of and robot in agent_of and part in part_of:
                self.moving[act_of[action], agent_of[robot]] = part_of[part]
        for action, robot in team.reserved.items():
            if action not in act_of or robot not in agent_of:
                raise ConfigError(f"reserved action {action!r} by {robot!r} is not in task {graph.name!r}",
                                  where="lookahead_team")
            i, j = act_of[action], agent_of[robot]
            self.allowed[i] = False
            self.allowed[i, j] = True
            self.cost[i, j] = 0.0  # paid when it started
            self.fetch[i, j] = 0.0  # the robot is at the handover pose when it is next free
            self.duration[i, j] = self.take[i, j]
        self.derive()

    def start(self, v0=None, elapsed: float | None = None):
        team, graph = self.team, self.graph
        n_agents, n_parts = len(graph.agents), len(graph.parts)
        free = np.full((1, n_agents), float(team.now))
        for name, t in team.free.items():
            free[0, self.agent_column(name)] = max(float(t), team.now)
        free[0, self.human] = max(float(team.worker_free), team.now)
        part_t = np.full((1, n_parts), float(team.now))
        bit = {p: i for i, p in enumerate(graph.parts)}
        for name, t in team.running.items():
            part_t[0, [bit[p] for p in graph.operation(name).father]] = max(float(t), team.now)
        end = np.array([max(float(team.now), float(free.max()), float(part_t.max()))])
        v = np.asarray(team.v if v0 is None else v0, dtype=float)[None, :]
        begun = np.full((1, n_parts), float(team.now))
        return np.zeros(1), v, free[:, self.human].copy(), free, part_t, begun, end

    def agent_column(self, name: str) -> int:
        """The index of agent ``name`` in the graph's agents (a ConfigError names the agents if unknown)."""
        for j, a in enumerate(self.graph.agents):
            if a.name == name:
                return j
        raise ConfigError(f"unknown agent {name!r}; agents are {[a.name for a in self.graph.agents]}",
                          where="lookahead_team")

    def step(self, state, op, action, agent):
        g, v, w_last, free, part_t, part_s, end = state
        rows = np.arange(len(op))
        h = self.human
        fm = self.view.father_parts[op]
        ready = np.where(fm, part_t, -np.inf).max(axis=1)
        moving = self.moving[action, agent]
        begun = np.where(moving >= 0, part_t[rows, np.maximum(moving, 0)],
                         np.where(fm, part_s, -np.inf).max(axis=1))
        human = agent == h
        take = self.take[action, agent]
        handover = ~human & (take > 0)
        own = free[rows, agent]
        start = np.where(handover, np.maximum(own, begun), np.maximum(own, ready))
        take_at = np.maximum(np.maximum(start + self.fetch[action, agent], free[:, h]), ready)
        worker = human | handover
        worker_at = np.where(human, start, take_at)
        rest = np.where(worker, np.maximum(0.0, worker_at - w_last), 0.0)
        v_rest = v * np.exp(-self.k * rest)[:, None]
        v_hat = 1.0 - self.alpha[action] * (1.0 - v_rest)
        v_new = np.where(human[:, None], v_hat, v_rest)
        finish = np.where(handover, take_at + take, start + self.duration[action, agent])
        free = free.copy()
        free[rows, agent] = finish + self.leave[action, agent]
        free[handover, h] = finish[handover]
        part_t = np.where(fm, finish[:, None], part_t)
        part_s = np.where(fm, start[:, None], part_s)
        makespan = np.maximum(end, finish)
        price = np.where(human, self.model.price(v_hat), self.cost[action, agent])
        out = (g + price + self.time_terms(end, makespan), v_new, np.where(worker, finish, w_last), free,
               part_t, part_s, makespan)
        return out, price, start

    def estimate(self, state, need, *, lowest: bool, cids=None):
        if not self.view.action_once:
            return np.zeros(len(need))
        _, v, w_last, free, _, _, end = state
        h = self.human
        if lowest:
            # the worker idles only while others work: what they still have, and every needed robot step
            robot_time = np.where(self.allowed, self.duration, 0.0)
            robot_time[:, h] = 0.0
            idle = np.maximum(0.0, free.max(axis=1) - w_last) + (need * robot_time.max(axis=1)).sum(axis=1)
            v = v * np.exp(-self.k * idle)[:, None]
        after = self.next_cost(v)
        work = (need * self.min_duration).sum(axis=1)
        alone = (need & ~np.isfinite(self.robot_min)) * self.duration[:, h]
        t_end = np.maximum.reduce([end, free.min(axis=1) + work / free.shape[1],
                                   free[:, h] + alone.sum(axis=1)])
        return self.needed_cost(need, v) + self.time_terms(end, t_end) + after

    def end_wear(self, state):
        _, v, w_last, _, _, _, end = state
        return v * np.exp(-self.k * np.maximum(0.0, end - w_last))[:, None]


@dataclass(frozen=True)
class TeamLookahead:
    """``starts``: the steps the idle agents start now (at most one each); ``plan``: the cheapest schedule
    found, its steps in priority order with their predicted starts."""

    starts: tuple[PlanStep, ...]
    plan: LookaheadPlan


def lookahead_team(graph, model: WearModel, team: TeamState, *, done: Iterable[str] = (),
                   idle: Sequence[str] = (), pruned: Iterable[tuple[str, str]] = (),
                   limits: SearchLimits = SearchLimits()) -> TeamLookahead:
    """The steps the ``idle`` agents start now, from the cheapest schedule from ``team`` (module docstring):
    ``done`` operations, ``team.running`` ones committed, ``team.reserved`` actions kept for their robots.

    Raises:
        InfeasiblePlanError: the assembly cannot be completed with the pairs left after ``pruned``.
        ConfigError: unknown agents, operations or actions.
    """
    pricing = TeamPricing(graph, model, team, pruned)
    cid0 = pricing.view.start(list(done) + list(team.running))
    plan = search_sequences(pricing, cid0, pricing.start(), limits)
    waiting = list(dict.fromkeys(idle))
    for name in waiting:
        pricing.agent_column(name)  # unknown idle agents are refused here
    starts = []
    for step, start in zip(plan.steps, plan.starts, strict=True):
        if step.agent in waiting:
            waiting.remove(step.agent)
            if start <= team.now + _NOW_TOL and step.action not in team.reserved:
                starts.append(step)
    return TeamLookahead(tuple(starts), plan)
