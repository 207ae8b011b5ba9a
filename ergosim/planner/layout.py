"""Array layout of an AND/OR graph, computed once at build time so that every replan is a few numpy passes.

Nodes are indexed in topological order (by number of parts, then by part indices), so children always
have lower indices than their father. Hyper-arcs (one per operation and allowed agent) are sorted by
(father node, agent index, operation index): the hyper-arcs of one father form a contiguous segment,
the segments of one father size form a contiguous *level*, and the order inside a segment is the
tie-breaking rank (see :mod:`ergosim.planner.bottom_up`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["Level", "Layout", "build_layout"]


@dataclass(frozen=True)
class Level:
    """Hyper-arcs whose fathers have the same number of parts.

    ``lo:hi`` is the hyper-arc range; ``children`` is (m, k) node indices of the level's m operations
    (padded with the zero-cost dummy node); ``op_of`` (hi - lo,) maps each hyper-arc to its row in
    ``children``; ``starts`` (s,) are the segment starts relative to ``lo`` and ``fathers`` (s,) the
    segment fathers.
    """

    lo: int
    hi: int
    children: np.ndarray
    op_of: np.ndarray
    starts: np.ndarray
    fathers: np.ndarray


@dataclass(frozen=True)
class Layout:
    """Hyper-arc arrays, all of length n_hyperarcs, plus per-node segment bounds and the levels."""

    op: np.ndarray
    agent: np.ndarray
    father: np.ndarray
    cost: np.ndarray
    seg_start: np.ndarray
    seg_end: np.ndarray
    levels: tuple[Level, ...]


def build_layout(
    node_size: np.ndarray,
    op_father: Sequence[int],
    op_children: Sequence[tuple[int, ...]],
    op_agents: Sequence[tuple[int, ...]],
    op_costs: Sequence[tuple[float, ...]],
) -> Layout:
    """Lay out the hyper-arcs. ``node_size`` (n_nodes,) parts per node; per-operation sequences as given."""
    n_nodes = len(node_size)
    counts = np.fromiter((len(a) for a in op_agents), dtype=np.int64, count=len(op_agents))
    n_h = int(counts.sum())
    ha_op = np.repeat(np.arange(len(op_agents), dtype=np.int64), counts)
    ha_agent = np.fromiter((a for agents in op_agents for a in agents), dtype=np.int64, count=n_h)
    ha_cost = np.fromiter((c for costs in op_costs for c in costs), dtype=np.float64, count=n_h)
    father_of_op = np.asarray(op_father, dtype=np.int64).reshape(-1)
    ha_father = father_of_op[ha_op]
    order = np.lexsort((ha_op, ha_agent, ha_father))
    ha_op, ha_agent, ha_father, ha_cost = ha_op[order], ha_agent[order], ha_father[order], ha_cost[order]

    width = max((len(c) for c in op_children), default=2)
    padded = np.full((len(op_children), width), n_nodes, dtype=np.int64)  # n_nodes = dummy, cost 0
    for i, children in enumerate(op_children):
        padded[i, : len(children)] = children

    nodes = np.arange(n_nodes)
    seg_start = np.searchsorted(ha_father, nodes, side="left")
    seg_end = np.searchsorted(ha_father, nodes, side="right")

    levels = []
    ha_size = node_size[ha_father]
    for size in np.unique(ha_size):
        lo = int(np.searchsorted(ha_size, size, side="left"))
        hi = int(np.searchsorted(ha_size, size, side="right"))
        ops = np.unique(ha_op[lo:hi])
        fathers, starts = np.unique(ha_father[lo:hi], return_index=True)
        levels.append(
            Level(
                lo=lo,
                hi=hi,
                children=padded[ops],
                op_of=np.searchsorted(ops, ha_op[lo:hi]),
                starts=starts.astype(np.int64),
                fathers=fathers,
            )
        )
    return Layout(ha_op, ha_agent, ha_father, ha_cost, seg_start, seg_end, tuple(levels))
