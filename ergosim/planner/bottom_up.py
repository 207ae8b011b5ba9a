"""The ``fast`` planner: exact bottom-up dynamic programming on the AND/OR graph itself.

For the current configuration Θ, the cost-to-build of a node n is

    V(n) = 0                                     if n ∈ Θ,
    V(n) = min_h [ c_h + Σ_{children m of h} V(m) ]  over the hyper-arcs h with father n,

and +inf for a part no longer separate (it is already inside a bigger sub-assembly of Θ). Since the
cost of a plan is the sum of the costs of its hyper-arcs (the paper's plan cost), V(root) is the
optimal plan cost. Nodes are visited in topological order one *level* (father size) at a time, so one
replan is a few numpy passes whose total work is linear in the number of hyper-arcs; no
configuration is ever enumerated.

Tie-breaking: at each node, among the hyper-arcs whose total is within ``tolerance(V(n))`` of the
minimum, the first in (agent index, operation index) order wins, i.e. the lexicographically smallest
(cost, agent, operation) with a float tolerance. The result is therefore identical from run to run.
"""

from __future__ import annotations

import numpy as np

from ergosim.errors import InfeasiblePlanError
from ergosim.planner import diagnose
from ergosim.planner.compiled import CompiledGraph

__all__ = ["node_costs", "solve", "tolerance", "REL_TOL"]

REL_TOL = 1e-9


def tolerance(value: float) -> float:
    """Absolute tolerance under which two plan costs near ``value`` count as equal."""
    return REL_TOL * max(1.0, abs(value))


def node_costs(graph: CompiledGraph, config: np.ndarray, cost: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """V for every node, and the hyper-arc totals c_h + Σ V(children).

    Args:
        config: node indices of Θ.
        cost: (n_hyperarcs,) hyper-arc costs of this call (+inf = pruned).

    Returns:
        (n_nodes + 1,) V (the last entry is the zero-cost padding node) and (n_hyperarcs,) totals.
    """
    lay = graph.layout
    value = np.full(graph.n_nodes + 1, np.inf)
    value[-1] = 0.0
    value[config] = 0.0
    totals = np.empty_like(cost)
    for level in lay.levels:
        base = value[level.children].sum(axis=1)
        out = totals[level.lo : level.hi]
        with np.errstate(over="ignore"):  # a sum past the float range is inf, reported by diagnose
            np.add(cost[level.lo : level.hi], base[level.op_of], out=out)
        best = np.minimum.reduceat(out, level.starts)
        value[level.fathers] = np.minimum(value[level.fathers], best)
    return value, totals


def solve(graph: CompiledGraph, config: np.ndarray, cost: np.ndarray) -> list[int]:
    """Hyper-arc indices of an optimal plan tree from Θ = ``config`` to the root.

    Raises:
        InfeasiblePlanError: when the root cannot be built from Θ with the hyper-arcs left.
    """
    value, totals = node_costs(graph, config, cost)
    root = graph.root
    if not np.isfinite(value[root]):
        reason, op_name, part = diagnose.explain(graph, config, cost, value)
        raise InfeasiblePlanError(f"no feasible plan: {reason}", where=graph.where(op_name, part))
    lay = graph.layout
    in_config = set(config.tolist())
    chosen = []
    stack = [root]
    while stack:
        node = stack.pop()
        if node in in_config:
            continue
        lo = lay.seg_start[node]
        best = value[node]
        h = lo + int(np.argmax(totals[lo : lay.seg_end[node]] <= best + tolerance(best)))
        chosen.append(h)
        stack.extend(graph.op_children[lay.op[h]])
    return chosen
