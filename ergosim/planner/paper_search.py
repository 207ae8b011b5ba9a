"""The ``paper`` planner: Algorithm 1 (AO* search) of the paper, over assembly configurations.

A SearchState holds a configuration Θ (a set of disjoint sub-assemblies covering every part), a
father pointer and a score c. The search starts from Θ_f = {full assembly} and ends at the goal, the
current configuration (Θ_i at the start of the task; after each action, Algorithm 2 calls it again with
the configuration reached, see :func:`ergosim.planner.replan.replan_until_done`). Expanding a state
replaces one of its sub-assemblies θ_j by the children of one hyper-arc with father θ_j; the successor's
score is the father's score plus the hyper-arc cost. The state of minimum score is expanded next
(OPEN ordered by (score, insertion order)), improved states in CLOSE are re-opened, and the optimal path
is read back from the goal along the father pointers. The hyper-arcs on that path form the plan tree.

Only successors whose sub-assemblies are unions of goal sub-assemblies are generated: the others can
never reach the goal. This is the paper's "reduced tree" when re-planning from a later configuration
and changes nothing at the start of the task. A configuration is a Python int with one bit per node.
"""

from __future__ import annotations

import heapq
import time

import numpy as np

from ergosim.errors import ConfigError, InfeasiblePlanError
from ergosim.planner import bottom_up, diagnose
from ergosim.planner.compiled import CompiledGraph
from ergosim.planner.limits import MAX_PAPER_STATES

__all__ = ["solve", "SearchBudgetExceeded", "SearchMemoryExceeded"]

_CHECK_EVERY = 1024


class SearchBudgetExceeded(TimeoutError):
    """The search ran past its ``time_budget``; raised so a benchmark can record it as skipped."""


class SearchMemoryExceeded(ConfigError):
    """The search created more configurations than its ``max_states`` memory budget.

    A :class:`~ergosim.errors.ConfigError`, so the CLI prints it as one line; a benchmark catches it by
    this type and records the row as over budget.
    """


def _successor_table(graph: CompiledGraph, config: np.ndarray, cost: np.ndarray) -> list[list[tuple]]:
    """Per node: (cost, hyper-arc, children bits) of the usable hyper-arcs of this call."""
    masks = graph.node_masks
    element_of_part = [0] * len(graph.parts)
    for n in config.tolist():
        m = masks[n]
        for i in range(len(graph.parts)):
            if m >> i & 1:
                element_of_part[i] = m
    consistent = 0
    for n, m in enumerate(masks):
        union, rest = 0, m
        while rest:
            low = rest & -rest
            union |= element_of_part[low.bit_length() - 1]
            rest ^= low
        if union == m:
            consistent |= 1 << n
    c = cost.tolist()
    return [
        [(c[h], h, bits) for h, bits in edges if c[h] != float("inf") and bits & consistent == bits]
        for edges in graph.node_edges
    ]


def solve(
    graph: CompiledGraph,
    config: np.ndarray,
    cost: np.ndarray,
    *,
    time_budget: float | None = None,
    max_states: int | None = None,
) -> list[int]:
    """Hyper-arc indices of an optimal plan tree from Θ = ``config`` to the root (Algorithm 1).

    ``max_states``: configurations the search may create (default :data:`MAX_PAPER_STATES`), its memory
    budget.

    Raises:
        InfeasiblePlanError: OPEN ran empty before the goal was reached.
        SearchBudgetExceeded: the search took longer than ``time_budget`` seconds.
        SearchMemoryExceeded: the search created more than ``max_states`` configurations (a ConfigError).
    """
    limit = MAX_PAPER_STATES if max_states is None else max_states
    deadline = None if time_budget is None else time.perf_counter() + time_budget
    succ = _successor_table(graph, config, cost)
    start = 1 << graph.root
    goal = 0
    for n in config.tolist():
        goal |= 1 << n
    open_ = {start: 0.0}
    close: dict[int, float] = {}
    father: dict[int, tuple[int, int]] = {start: (0, -1)}
    heap = [(0.0, 0, start)]
    pushed = 1
    popped = 0
    curr = None
    while heap:
        score, _, state = heapq.heappop(heap)
        if open_.get(state) != score:
            continue  # stale heap entry: the state was improved or closed since
        popped += 1
        if deadline is not None and popped % _CHECK_EVERY == 0 and time.perf_counter() > deadline:
            raise SearchBudgetExceeded(f"paper search exceeded {time_budget} s after {popped} expansions")
        if pushed > limit:
            raise SearchMemoryExceeded(
                f"the paper planner (Algorithm 1) created {pushed} configurations, more than its memory "
                f"budget of {limit} (--max-states); plan this task with --planner fast",
                where=graph.source,
            )
        if state == goal:
            curr = state
            break
        rest = state
        while rest:
            low = rest & -rest
            rest ^= low
            base = state ^ low
            for c, h, bits in succ[low.bit_length() - 1]:
                nxt = base | bits
                sc = score + c
                if nxt in open_:
                    if sc < open_[nxt]:
                        open_[nxt] = sc
                        father[nxt] = (state, h)
                        heapq.heappush(heap, (sc, pushed, nxt))
                        pushed += 1
                elif nxt in close:
                    if sc < close[nxt]:
                        del close[nxt]
                        open_[nxt] = sc
                        father[nxt] = (state, h)
                        heapq.heappush(heap, (sc, pushed, nxt))
                        pushed += 1
                else:
                    open_[nxt] = sc
                    father[nxt] = (state, h)
                    heapq.heappush(heap, (sc, pushed, nxt))
                    pushed += 1
        del open_[state]
        close[state] = score
    if curr is None:
        _infeasible(graph, config, cost)
    return _path(father, start, curr)


def _infeasible(graph: CompiledGraph, config: np.ndarray, cost: np.ndarray) -> None:
    """OPEN ran empty: raise InfeasiblePlanError with the reason the bottom-up pass finds."""
    value, _ = bottom_up.node_costs(graph, config, cost)
    reason, op_name, part = diagnose.explain(graph, config, cost, value)
    raise InfeasiblePlanError(f"no feasible plan: {reason}", where=graph.where(op_name, part))


def _path(father: dict[int, tuple[int, int]], start: int, goal: int) -> list[int]:
    """The hyper-arcs from ``goal`` back to ``start`` along the father pointers."""
    path = []
    while goal != start:
        goal, h = father[goal]
        path.append(h)
    return path
