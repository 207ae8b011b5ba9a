"""Which action goes next when several optimal plans differ only in their order: the tie rule.

With free actions (a2..a4 of §7.2 in any order), every order is a different plan tree of the same cost,
because one call's costs do not depend on the order (eq. 10-11 price every candidate from the same
V(t_k)). The candidates for the next step are the operations possible now whose cheapest completion costs
no more than the optimal plan. Algorithm 2 dispatches the first step of the path Algorithm 1 returns
("nextAction = opt_path.Node.action", the edge next to the goal Θ_i), so the search breaks the tie:

- ``costliest-first`` (the paper's rule). Algorithm 1 expands states in order of their cost from Θ_f. The
  fathers of the goal are the configurations one step further on; the father reached by doing step k
  first costs the plan's total minus c_k, so the father of the *costliest* candidate is expanded first,
  sets the goal's score, and (OPEN is only updated by a strictly lower score) stays the goal's father. With
  exactly representable costs the paper's search (:mod:`ergosim.planner.paper_search`) returns the
  costliest candidate first in every case tested (``tests/test_tie_break.py``); in floating point the sums
  of different orders can differ in their last bit and decide some ties by rounding instead.
- ``task-order``: the candidate whose operation comes first in the task file (the planners' own execution
  order when their tree has several steps ready, :mod:`ergosim.planner.plan`).
- ``cheapest-first``: the cheapest candidate first.

Exact ties of the step costs go to the task order in every rule.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING

import numpy as np

from ergosim.errors import ConfigError, InfeasiblePlanError
from ergosim.planner.plan import Plan, PlanStep

if TYPE_CHECKING:
    from ergosim.planner.graph import AndOrGraph

__all__ = ["TIE_RULES", "PAPER_TIE_RULE", "optimal_next_steps", "next_step"]

TIE_RULES = ("costliest-first", "task-order", "cheapest-first")
PAPER_TIE_RULE = "costliest-first"
"""The order Algorithm 1 + 2 give equal-cost plans (module docstring)."""


def _step_cost(op, agent: str, costs: Mapping[tuple[str, str], float] | None,
               added: Mapping[tuple[str, str], float] | None) -> float:
    key = (op.action, agent)
    base = costs[key] if costs is not None and key in costs else op.cost_of(agent)
    return float(base) + float((added or {}).get(key, 0.0))


def optimal_next_steps(graph: AndOrGraph, done: Iterable[str], costs=None, pruned=(), planner: str = "fast",
                       added=None) -> tuple[Plan, list[PlanStep]]:
    """The optimal plan from the operations ``done`` and every (operation, agent) that can start now and
    begins a plan of the same cost, in the task's operation order (arguments as :meth:`AndOrGraph.plan`)."""
    done = list(done)
    pruned = set(pruned)
    best = graph.plan(done=done, costs=costs, pruned=pruned, planner=planner, added=added)
    existing = set(graph.configuration(done))
    tol = 1e-9 * max(1.0, abs(best.cost))
    out = []
    for op in graph.operations:
        if op.name in done or not all(child in existing for child in op.children):
            continue
        try:
            rest = graph.plan(done=done + [op.name], costs=costs, pruned=pruned, planner=planner, added=added)
        except InfeasiblePlanError:
            continue
        for agent in op.agents:
            if (op.action, agent) in pruned:
                continue
            c = _step_cost(op, agent, costs, added)
            if np.isfinite(c) and c + rest.cost <= best.cost + tol:
                out.append(PlanStep(op.name, op.action, agent, c))
    return best, out


def next_step(graph: AndOrGraph, done: Iterable[str], costs=None, pruned=(), planner: str = "fast",
              added=None, rule: str = PAPER_TIE_RULE) -> PlanStep | None:
    """The step to dispatch now under tie ``rule`` (:data:`TIE_RULES`); None when the assembly is complete."""
    if rule not in TIE_RULES:
        raise ConfigError(f"unknown tie rule {rule!r}; expected one of {', '.join(TIE_RULES)}",
                          where="tie_break")
    best, candidates = optimal_next_steps(graph, done, costs, pruned, planner, added)
    if not candidates:
        return best.next
    if rule == "task-order":
        return candidates[0]
    sign = -1.0 if rule == "costliest-first" else 1.0
    return min(enumerate(candidates), key=lambda kc: (sign * kc[1].cost, kc[0]))[1]
