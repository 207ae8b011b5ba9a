"""Plans: the planners' result and its execution order.

A plan is a tree of hyper-arcs from the current configuration Θ up to the full assembly. Its cost is
the sum of its hyper-arc costs. Its steps are listed in *execution order*: repeatedly, among the steps
whose children all exist (are in Θ or made by an earlier step), the one whose operation comes first in
the task's operation order. ``next`` is the first step. Both planners use this rule, so a plan's order
depends only on its tree.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from ergosim.planner.compiled import CompiledGraph

__all__ = ["PlanStep", "Plan", "assemble_plan"]


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


def assemble_plan(graph: CompiledGraph, hyperarcs: Iterable[int], config: np.ndarray,
                  cost: np.ndarray) -> Plan:
    """Order a plan tree (hyper-arc indices) for execution and wrap it as a :class:`Plan`."""
    lay = graph.layout
    hyperarcs = list(hyperarcs)
    ops = [int(lay.op[h]) for h in hyperarcs]
    made_by = {graph.op_father[op]: k for k, op in enumerate(ops)}
    existing = set(config.tolist())
    waiting = [0] * len(ops)
    parent = [-1] * len(ops)
    for k, op in enumerate(ops):
        for child in graph.op_children[op]:
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
