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

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ergosim.planner.graph import AndOrGraph

__all__ = ["TeamLayout", "team_layout", "outside_costs", "through_costs"]


@dataclass(frozen=True)
class TeamLayout:
    """Per-operation arrays of a graph, built once (cached on the graph).

    ``op_perm`` (n_hyperarcs,) hyper-arc indices grouped by operation, ``op_start`` (n_ops + 1,) where each
    operation's group starts; ``op_children`` (n_ops, k) child nodes padded with the dummy node
    ``n_nodes``; ``op_father`` (n_ops,); ``levels``: per level, top-down, (operation indices, their
    fathers, their child columns (k, m)); ``others``: for each child slot j, the other slots;
    ``action_ops``: action label -> its operations' indices."""

    op_perm: np.ndarray
    op_start: np.ndarray
    op_children: np.ndarray
    op_father: np.ndarray
    levels: tuple[tuple[np.ndarray, np.ndarray, np.ndarray], ...]
    others: tuple[tuple[int, ...], ...]
    action_ops: dict[str, np.ndarray]


def team_layout(graph: AndOrGraph) -> TeamLayout:
    """The :class:`TeamLayout` of ``graph``, built on first use."""
    cached = graph._team_cache
    if cached is None:
        lay = graph._layout
        n_ops = len(graph.operations)
        perm = np.argsort(lay.op, kind="stable")
        start = np.searchsorted(lay.op[perm], np.arange(n_ops + 1), side="left")
        width = max((len(c) for c in graph._op_children), default=2)
        children = np.full((n_ops, width), graph.n_nodes, dtype=np.int64)
        for i, ch in enumerate(graph._op_children):
            children[i, : len(ch)] = ch
        father = np.asarray(graph._op_father, dtype=np.int64).reshape(-1)
        levels = []
        for level in reversed(lay.levels):
            ops = np.unique(lay.op[level.lo : level.hi])
            levels.append((ops, father[ops], np.ascontiguousarray(children[ops].T)))
        others = tuple(tuple(c for c in range(width) if c != j) for j in range(width))
        by_action: dict[str, list[int]] = {}
        for i, op in enumerate(graph.operations):
            by_action.setdefault(op.action, []).append(i)
        action_ops = {a: np.array(v, dtype=np.int64) for a, v in by_action.items()}
        cached = graph._team_cache = TeamLayout(perm, start, children, father, tuple(levels), others,
                                                action_ops)
    return cached  # type: ignore[return-value]


def outside_costs(graph: AndOrGraph, value: np.ndarray, cost: np.ndarray) -> np.ndarray:
    """U (n_nodes + 1,) for node costs ``value`` (from :func:`~ergosim.planner.bottom_up.node_costs`) and
    hyper-arc costs ``cost`` (+inf = pruned). Nodes that cannot lie on any complete plan get +inf."""
    tl = team_layout(graph)
    best = np.full(len(graph.operations), np.inf)  # per operation, its cheapest hyper-arc
    starts = tl.op_start[:-1]
    some = tl.op_start[1:] > starts  # an operation no agent may do has no hyper-arc
    if some.any():
        best[some] = np.minimum.reduceat(cost[tl.op_perm], starts[some])
    outside = np.full(graph.n_nodes + 1, np.inf)
    outside[graph._root] = 0.0
    with np.errstate(over="ignore"):
        for ops, fathers, cols in tl.levels:
            base = outside[fathers] + best[ops]
            vals = value[cols]
            for j, rest in enumerate(tl.others):
                cand = base + vals[rest[0]] if len(rest) == 1 else base + vals[list(rest)].sum(axis=0)
                np.minimum.at(outside, cols[j], cand)
    outside[-1] = 0.0  # the padding node
    return outside


def through_costs(graph: AndOrGraph, totals: np.ndarray, outside: np.ndarray,
                  hyperarcs: np.ndarray | None = None) -> np.ndarray:
    """J(h) = totals[h] + U(father(h)) for ``hyperarcs`` (default: all): the cost of the cheapest complete
    plan through each. ``totals`` are the bottom-up pass's c_h + Σ V(children)."""
    lay = graph._layout
    if hyperarcs is None:
        return totals + outside[lay.father]
    return totals[hyperarcs] + outside[lay.father[hyperarcs]]
