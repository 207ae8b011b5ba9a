"""Per-operation arrays of a compiled graph: the table the outside pass and the team decisions read.

The hyper-arc layout (:mod:`ergosim.planner.layout`) groups hyper-arcs by father for the bottom-up pass;
this table groups them by operation, pads every operation's children to one width, and lists the levels
top-down for the outside pass (:mod:`ergosim.planner.outside`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ergosim.planner.frozen import FrozenDict, read_only
from ergosim.planner.layout import Layout

__all__ = ["OperationTable", "build_operation_table"]


@dataclass(frozen=True)
class OperationTable:
    """Per-operation arrays of a compiled graph (read-only).

    ``op_perm`` (n_hyperarcs,) hyper-arc indices grouped by operation, ``op_start`` (n_ops + 1,) where each
    operation's group starts; ``op_children`` (n_ops, k) child nodes padded with the dummy node
    ``n_nodes``; ``op_father`` (n_ops,); ``levels``: per father size, largest first, (operation indices,
    their fathers, their child columns (k, m), writeable for ``np.minimum.at``); ``others``: for each child
    slot j, the other slots;
    ``action_ops``: action label -> its operations' indices."""

    op_perm: np.ndarray
    op_start: np.ndarray
    op_children: np.ndarray
    op_father: np.ndarray
    levels: tuple[tuple[np.ndarray, np.ndarray, np.ndarray], ...]
    others: tuple[tuple[int, ...], ...]
    action_ops: Mapping[str, np.ndarray]

    def hyperarcs(self, op: int) -> np.ndarray:
        """The hyper-arcs of operation ``op`` (one per allowed agent), in layout order."""
        return self.op_perm[self.op_start[op]:self.op_start[op + 1]]


def build_operation_table(layout: Layout, op_father: Sequence[int], op_children: Sequence[tuple[int, ...]],
                          op_actions: Sequence[str], n_nodes: int) -> OperationTable:
    """The table of a graph with hyper-arc ``layout``, per-operation fathers, children and action labels,
    and ``n_nodes`` nodes (the padding node's index)."""
    n_ops = len(op_actions)
    perm = np.argsort(layout.op, kind="stable")
    start = np.searchsorted(layout.op[perm], np.arange(n_ops + 1), side="left")
    width = max((len(c) for c in op_children), default=2)
    children = np.full((n_ops, width), n_nodes, dtype=np.int64)
    for i, ch in enumerate(op_children):
        children[i, : len(ch)] = ch
    father = np.asarray(op_father, dtype=np.int64).reshape(-1)
    levels = []
    for level in reversed(layout.levels):
        ops = np.unique(layout.op[level.lo : level.hi])
        # the child columns go to np.minimum.at on every outside pass (writeable: planner/frozen.py says why)
        levels.append((read_only(ops), read_only(father[ops]), np.ascontiguousarray(children[ops].T)))
    others = tuple(tuple(c for c in range(width) if c != j) for j in range(width))
    by_action: dict[str, list[int]] = {}
    for i, action in enumerate(op_actions):
        by_action.setdefault(action, []).append(i)
    action_ops = FrozenDict({a: read_only(np.array(v, dtype=np.int64)) for a, v in by_action.items()})
    return OperationTable(read_only(perm), read_only(start), read_only(children), read_only(father),
                          tuple(levels), others, action_ops)
