"""Algorithm 2 of the paper (RecursiveAO*): plan, dispatch the next action, update the costs, until done."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping

from ergosim.planner.graph import AndOrGraph
from ergosim.planner.plan import PlanStep

__all__ = ["CostUpdate", "replan_until_done"]

CostUpdate = Callable[
    [tuple[str, ...]], tuple[Mapping[tuple[str, str], float] | None, Iterable[tuple[str, str]]]
]


def replan_until_done(
    graph: AndOrGraph,
    update: CostUpdate | None = None,
    planner: str = "paper",
    done: Iterable[str] = (),
) -> tuple[PlanStep, ...]:
    """Algorithm 2 (RecursiveAO*): plan, dispatch the next action, update the goals, until complete.

    ``update(done)`` returns ``(costs, pruned)`` for the next search, given the operations done so far
    (the twin's cost update, eq. 2). Returns the executed steps in order; their agents and costs are
    those of the plan current when each step was dispatched.
    """
    done_list = list(done)
    executed = []
    while True:
        costs, pruned = update(tuple(done_list)) if update is not None else (None, ())
        step = graph.plan(done=done_list, costs=costs, pruned=pruned, planner=planner).next
        if step is None:
            return tuple(executed)
        executed.append(step)
        done_list.append(step.operation)
