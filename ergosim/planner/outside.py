"""Outside costs on the AND/OR graph: what it costs to finish the assembly once a node exists.

The bottom-up pass (:mod:`ergosim.planner.bottom_up`) gives V(n), the cheapest cost to *build* node n from
the configuration Θ. Its dual is the outside cost U(n): the cheapest cost to build the root *given* n
exists, counting every hyper-arc above n and the building of n's siblings, but not n itself:

    U(root) = 0,
    U(m) = min over hyper-arcs h with child m of [ U(father(h)) + c_h + Σ_{children m' ≠ m of h} V(m') ].

With both, the cheapest complete plan that uses hyper-arc h costs

    J(h) = c_h + Σ_{children m of h} V(m) + U(father(h)),

for every h at once, which is what a team decision needs: for an idle agent, the price of each operation it
could start now (:mod:`ergosim.planner.team`). The pass visits the levels top-down (largest fathers
first), so U of a father is final before its children receive from it; it is a few numpy passes per level,
linear in the operations, like the bottom-up pass.
"""

from __future__ import annotations

import numpy as np

from ergosim.planner.compiled import CompiledGraph

__all__ = ["outside_costs", "through_costs"]


def outside_costs(graph: CompiledGraph, value: np.ndarray, cost: np.ndarray) -> np.ndarray:
    """U (n_nodes + 1,) for node costs ``value`` (from :func:`~ergosim.planner.bottom_up.node_costs`) and
    hyper-arc costs ``cost`` (+inf = pruned). Nodes that cannot lie on any complete plan get +inf."""
    tl = graph.op_table
    best = np.full(len(graph.operations), np.inf)  # per operation, its cheapest hyper-arc
    starts = tl.op_start[:-1]
    some = tl.op_start[1:] > starts  # an operation no agent may do has no hyper-arc
    if some.any():
        best[some] = np.minimum.reduceat(cost[tl.op_perm], starts[some])
    outside = np.full(graph.n_nodes + 1, np.inf)
    outside[graph.root] = 0.0
    with np.errstate(over="ignore"):
        for ops, fathers, cols in tl.levels:
            base = outside[fathers] + best[ops]
            vals = value[cols]
            for j, rest in enumerate(tl.others):
                cand = base + vals[rest[0]] if len(rest) == 1 else base + vals[list(rest)].sum(axis=0)
                np.minimum.at(outside, cols[j], cand)
    outside[-1] = 0.0  # the padding node
    return outside


def through_costs(graph: CompiledGraph, totals: np.ndarray, outside: np.ndarray,
                  hyperarcs: np.ndarray | None = None) -> np.ndarray:
    """J(h) = totals[h] + U(father(h)) for ``hyperarcs`` (default: all): the cost of the cheapest complete
    plan through each. ``totals`` are the bottom-up pass's c_h + Σ V(children)."""
    lay = graph.layout
    if hyperarcs is None:
        return totals + outside[lay.father]
    return totals[hyperarcs] + outside[lay.father[hyperarcs]]
