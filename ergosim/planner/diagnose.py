"""Why there is no feasible plan: walk down from the root to the first thing that cannot be made."""

from __future__ import annotations

import numpy as np

from ergosim.planner.compiled import CompiledGraph
from ergosim.planner.validation import format_parts

__all__ = ["explain"]


def explain(
    graph: CompiledGraph, config: np.ndarray, cost: np.ndarray, value: np.ndarray
) -> tuple[str, str | None, str | None]:
    """A one-line reason, and the operation or part it concerns (for the message's location).

    Args:
        config: node indices of the current configuration Θ.
        cost: (n_hyperarcs,) costs of this call (+inf = pruned or no agent).
        value: (n_nodes + 1,) node costs from :func:`ergosim.planner.bottom_up.node_costs`.
    """
    lay = graph.layout
    masks = graph.node_masks
    elements = [masks[n] for n in config.tolist()]
    node = graph.root
    while True:
        mask = masks[node]
        holders = [e for e in elements if e & mask and e != e & mask]
        if holders:
            held = [graph.parts[i] for i in range(len(graph.parts)) if (holders[0] & mask) >> i & 1]
            return (
                f"sub-assembly {format_parts(graph.node_parts(node))} can no longer be made: part(s) "
                f"{format_parts(held)} are already joined into {format_parts(_parts(graph, holders[0]))}",
                None,
                None,
            )
        ops = graph.node_ops[node]
        if not ops:
            if node == graph.root:
                return f"no operation joins the full assembly {format_parts(graph.parts)}", None, None
            return f"no operation forms sub-assembly {format_parts(graph.node_parts(node))}", None, None
        usable = []
        for op in ops:
            hs = np.flatnonzero(lay.op[lay.seg_start[node] : lay.seg_end[node]] == op) + lay.seg_start[node]
            if np.isfinite(cost[hs]).any():
                usable.append(op)
        if not usable:
            op = graph.operations[ops[0]]
            if not op.agents:
                why = f"no agent may do operation {op.name!r} (action {op.action!r})"
            else:
                why = (
                    f"every agent allowed to do operation {op.name!r} (action {op.action!r}) is pruned: "
                    + ", ".join(op.agents)
                )
            if len(ops) > 1:
                why += f", nor any of the other {len(ops) - 1} operation(s) forming " + format_parts(
                    graph.node_parts(node)
                )
            return why, op.name, None
        blocked = [c for c in graph.op_children[usable[0]] if not np.isfinite(value[c])]
        if not blocked:  # every child can be made and the hyper-arc is usable: the sum overflowed to inf
            return (f"the cost of forming {format_parts(graph.node_parts(node))} overflows to inf; "
                    "use smaller costs", graph.operations[usable[0]].name, None)
        node = blocked[0]


def _parts(graph: CompiledGraph, mask: int) -> tuple[str, ...]:
    return tuple(p for i, p in enumerate(graph.parts) if mask >> i & 1)
