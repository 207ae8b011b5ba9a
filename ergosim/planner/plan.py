"""Plans: the planners' result, its execution order, and Algorithm 2 (re-plan after every action).

A plan is a tree of hyper-arcs from the current configuration Θ up to the full assembly. Its cost is
the sum of its hyper-arc costs. Its steps are listed in *execution order*: repeatedly, among the steps
whose children all exist (are in Θ or made by an earlier step), the one whose operation comes first in
the task's operation order. ``next`` is the first step. Both planners use this rule, so a plan's order
depends only on its tree.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ergosim.planner.graph import AndOrGraph

__all__ = ["PlanStep", "Plan", "assemble_plan", "replan_until_done"]


@dataclass(frozen=True)
class PlanStep:
    """One hyper-arc of a plan: ``agent`` does ``operation`` (physical action ``action``) at ``cost``."""

    operation: str
    action: str
    agent: str
    cost: float

    def to_dict(self) -> dict[str, object]:
        return {"operation": self.operation, "action": self.action, "agent": self.agent, "cost": self.cost}


@dataclass(frozen=True)
class Plan:
    """An optimal plan: ``steps`` in execution order, ``cost`` = Σ step costs (math.fsum)."""

    steps: tuple[PlanStep, ...]
    cost: float

    @property
    def next(self) -> PlanStep | None:
        """The step to dispatch now, or None when the assembly is already complete."""
        return self.steps[0] if self.steps else None

    def to_dict(self) -> dict[str, object]:
        """``{"cost", "next", "plan"}`` as in the ``ergosim plan --json`` output."""
        return {
            "cost": self.cost,
            "next": None if self.next is None else self.next.to_dict(),
            "plan": [s.to_dict() for s in self.steps],
        }


def assemble_plan(graph: AndOrGraph, hyperarcs: Iterable[int], config: np.ndarray, cost: np.ndarray) -> Plan:
    """Order a plan tree (hyper-arc indices) for execution and wrap it as a :class:`Plan`."""
    lay = graph._layout
    hyperarcs = list(hyperarcs)
    ops = [int(lay.op[h]) for h in hyperarcs]
    made_by = {graph._op_father[op]: k for k, op in enumerate(ops)}
    existing = set(config.tolist())
    waiting = [0] * len(ops)
    parent = [-1] * len(ops)
    for k, op in enumerate(ops):
        for child in graph._op_children[op]:
            if child not in existing:
                waiting[k] += 1
                parent[made_by[child]] = k
    ready = [(op, k) for k, op in enumerate(ops) if waiting[k] == 0]
    heapq.heapify(ready)
    steps = []
    while ready:
        op, k = heapq.heappop(ready)
        operation = graph.operations[op]
        h = hyperarcs[k]
        steps.append(
            PlanStep(operation.name, operation.action, graph.agents[int(lay.agent[h])].name, float(cost[h]))
        )
        up = parent[k]
        if up >= 0:
            waiting[up] -= 1
            if waiting[up] == 0:
                heapq.heappush(ready, (ops[up], up))
    return Plan(tuple(steps), math.fsum(s.cost for s in steps))


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
