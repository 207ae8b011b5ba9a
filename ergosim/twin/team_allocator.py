"""The role allocator of parallel execution: price the hyper-arcs as the mode says, then serve every idle
agent its best ready operation (:func:`~ergosim.planner.team.team_assign`).

Pricing is the sequential allocator's (:class:`~ergosim.twin.allocator.Allocator`: the mode's risk index,
eq. 9-11, and the time term); only the planner call differs. ``margin`` keeps an idle agent from an
operation that costs at least that much more than the optimal plan: by default Γ (eq. 11) for modes with a
threshold penalty, so the worker is never given an over-threshold action because it happens to be free.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from ergosim.planner.team import TeamStep, team_assign
from ergosim.twin.allocator import Allocator, Decision
from ergosim.twin.team_board import TeamBoard

__all__ = ["TeamAllocator", "team_margin"]


def team_margin(allocator: Allocator, margin: float | None) -> float | None:
    """The margin in use: ``margin`` if given, else Γ of the mode's cost rule (None for modes without one)."""
    if margin is not None:
        return float(margin)
    cost = allocator.cost
    return float(cost.gamma) if cost is not None else None


class TeamAllocator:
    """Team decisions for one worker and its robots, priced by ``allocator``; ``early``: (action, robot) ->
    moving part of the robots' handovers (they start early)."""

    def __init__(self, allocator: Allocator, *, early: Mapping[tuple[str, str], str] | None = None,
                 margin: float | None = None) -> None:
        self.allocator = allocator
        self.early = dict(early or {})
        self.margin = team_margin(allocator, margin)

    def decide(self, v_now: np.ndarray, board: TeamBoard, idle: Sequence[str], pruned: set[tuple[str, str]],
               time: float, repetition: int, *, guard: bool = True) -> list[tuple[Decision, TeamStep]]:
        """The decisions for the ``idle`` agents now (each with its team step); ``guard`` False drops the
        margin (a team that would otherwise stand still). Raises InfeasiblePlanError when the assembly can
        no longer be finished with what is running."""
        alloc = self.allocator
        done_actions = {alloc.action_of(o) for o in board.done}
        busy = {alloc.action_of(o) for o in board.running.values()} | set(board.reserved)
        remaining = [a for a in alloc.graph.actions if a not in done_actions]
        if not remaining:
            return []
        v_hat, costs, added = alloc.price(remaining)
        cut = alloc.base_pruned | pruned
        out = team_assign(alloc.graph, idle=idle, done=board.done, running=board.running.values(),
                          reserved=board.reserved, costs=costs, pruned=cut, added=added or None,
                          early=self.early, margin=self.margin if guard else None)
        decisions = []
        for step in out.steps:
            if step.action in busy:
                continue
            agents = alloc.allowed[step.action] - {a for (act, a) in cut if act == step.action}
            extra = step.through - out.cost
            decisions.append((Decision(
                time=time, repetition=repetition, v_now=np.array(v_now), v_hat=v_hat, costs=costs,
                action=step.action, agent=step.agent, operation=step.operation, had_choice=len(agents) > 1,
                basis=alloc.basis, through=step.through if math.isfinite(step.through) else math.nan,
                excess=extra if extra > 1e-9 * max(1.0, abs(out.cost)) else 0.0, early=step.early,
                part=str(step.part) if step.early else ""), step))
        return decisions
