"""The ``kwear-lookahead`` mode in parallel execution: each idle agent starts what the cheapest schedule
starts now (:mod:`ergosim.planner.lookahead_team`), or waits.

The team's state comes from the session's jobs (:class:`~ergosim.twin.team_allocator.Busy`) and the expected
durations: an agent's job ends at its start plus the expected duration of its (action, agent); a robot
fetching a part to hand it over holds the action (reserved) and reaches the handover pose at its start plus
the robot's part of the handover; the worker taking a handed part is busy for the worker's take; a robot
that let its part go is free after its expected way home (``leave``). The
worker's V at the end of its current action is predicted from the share of the action still to come (wear
spread evenly over the action, eq. 9 with α^share). A job past its expected end is taken to end just after
now (it is still running).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from ergosim.planner.lookahead_team import TeamState, lookahead_team
from ergosim.planner.team import TeamStep
from ergosim.twin.allocator import Decision, SequenceChoice
from ergosim.twin.lookahead_allocator import LookaheadAllocator
from ergosim.twin.team_allocator import Busy
from ergosim.twin.team_board import TeamBoard

__all__ = ["LookaheadTeamAllocator", "team_state"]

_STILL_RUNNING = 1e-3  # s after now at which a job past its expected end is taken to end


def team_state(alloc: LookaheadAllocator, v_now: np.ndarray, board: TeamBoard, busy: Sequence[Busy],
               time: float, start: float) -> TeamState:
    """The :class:`~ergosim.planner.lookahead_team.TeamState` of the board and the session's jobs at sim time
    ``time``, in seconds from the repetition's ``start``."""
    model = alloc.model
    now = time - start
    human = alloc.human

    def seconds(action: str, agent: str) -> float:
        return float(model.duration[model.action_index[action], model.agent_index[agent]])

    def take(action: str, robot: str) -> float:
        i, j = model.action_index[action], model.agent_index[robot]
        return float(model.duration[i, j] - model.rest[i, j])

    def leave(action: str, robot: str) -> float:
        return float(model.leave[model.action_index[action], model.agent_index[robot]])

    v = np.array(v_now, dtype=float)
    worker_free = now
    free: dict[str, float] = {}
    ends: dict[str, float] = {}  # action -> predicted end of the job that makes it
    for job in busy:
        t0 = job.t0 - start
        if job.agent == human:
            d = take(job.action, job.robot) if job.take else seconds(job.action, human)
            end = max(t0 + d, now + _STILL_RUNNING)
            worker_free = end
            if not job.take and d > 0:
                share = min(1.0, (end - now) / d)
                v = 1.0 - model.alpha[model.action_index[job.action]] ** share * (1.0 - v)
            ends[job.action] = end
        elif job.state in ("fetching", "waiting"):
            free[job.agent] = max(t0 + seconds(job.action, job.agent) - take(job.action, job.agent), now)
        elif job.state in ("moving", "settling"):
            end = max(t0 + seconds(job.action, job.agent), now + _STILL_RUNNING)
            ends[job.action] = end
            free[job.agent] = end + leave(job.action, job.agent)
        elif job.state == "taken":  # the worker's take, then the way home
            free[job.agent] = max(worker_free, now) + leave(job.action, job.agent)
        elif job.state == "homing":  # on its way home after letting the part go
            free[job.agent] = max(t0 + seconds(job.action, job.agent) + leave(job.action, job.agent),
                                  now + _STILL_RUNNING)
        else:
            free[job.agent] = now + _STILL_RUNNING
    running = {op: ends.get(alloc.action_of(op), now + _STILL_RUNNING) for op in board.running.values()}
    reserved = {action: agent for action, (agent, _) in board.reserved.items()}
    return TeamState(now, v, worker_free, free, running, reserved, dict(board.early))


class LookaheadTeamAllocator:
    """Team decisions of the look-ahead, priced by ``allocator`` (a prepared :class:`LookaheadAllocator`);
    ``early``: (action, robot) -> moving part of the robots' handovers (they start early); ``margin`` is the
    team rule's and is not used (the schedule decides whether an agent waits)."""

    def __init__(self, allocator: LookaheadAllocator, *, early: Mapping[tuple[str, str], str] | None = None,
                 margin: float | None = None) -> None:
        self.allocator = allocator
        self.early = dict(early or {})
        self.margin = margin

    def decide(self, v_now: np.ndarray, board: TeamBoard, idle: Sequence[str], pruned: set[tuple[str, str]],
               time: float, repetition: int, *, guard: bool = True,
               busy: Sequence[Busy] = ()) -> list[tuple[Decision, TeamStep]]:
        """The decisions for the ``idle`` agents now; ``guard`` False (a team that would otherwise stand
        still) starts the first step of an idle agent even if the schedule starts it later."""
        alloc = self.allocator
        done_actions = {alloc.action_of(o) for o in board.done}
        taken = {alloc.action_of(o) for o in board.running.values()} | set(board.reserved)
        remaining = [a for a in alloc.graph.actions if a not in done_actions]
        if not remaining:
            return []
        start = alloc.repetition_start(repetition, time)
        team = team_state(alloc, v_now, board, busy, time, start)
        v_hat, costs, _ = alloc.price(remaining)
        cut = alloc.base_pruned | pruned | alloc.unreachable
        out = lookahead_team(alloc.graph, alloc.model, team, done=board.done, idle=idle, pruned=cut,
                             limits=alloc.limits)
        plan = out.plan
        alloc.last_plan = plan
        starts = list(out.starts)
        if not starts and not guard:
            firsts = [s for s in plan.steps if s.agent in idle and s.action not in taken]
            starts = firsts[:1]
        decisions = []
        for step in starts:
            if step.action in taken:
                continue
            agents = alloc.allowed[step.action] - {a for (act, a) in cut if act == step.action}
            part = self.early.get((step.action, step.agent))
            sequence = SequenceChoice(tuple((s.action, s.agent) for s in plan.steps), plan.cost, math.nan,
                                      plan.exact, plan.gap)
            decisions.append((Decision(
                time=time, repetition=repetition, v_now=np.array(v_now), v_hat=v_hat, costs=costs,
                action=step.action, agent=step.agent, operation=step.operation, had_choice=len(agents) > 1,
                basis=alloc.basis, through=plan.cost, early=part is not None, part=part or "",
                sequence=sequence),
                TeamStep(step.operation, step.action, step.agent, step.cost, plan.cost,
                         early=part is not None, part=part)))
        return decisions
