"""Which actions of a task may come in either order: the free-order groups of an AND/OR graph.

Action x may come before action y when some complete plan carries out an operation of x that is not an
ancestor of an operation of y: inside a sub-assembly that y then joins, or in a separate sub-assembly.
Two actions each of which may come before the other are linked, and a free-order group is a set of linked
actions (in the corner joint L, S1 and S2 go into J in any order: a2, a3 and a4 form one group). The paper's
cost (eq. 10-11) does not depend on that order; a look-ahead allocation does.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

from ergosim.planner.frozen import FrozenDict

__all__ = ["OrderReach", "order_reach", "may_precede", "free_order_groups"]


@dataclass(frozen=True)
class OrderReach:
    """What may come before what: ``usable`` the operations of some complete plan; ``under[op]`` the bit set
    of the operations some plan carries out inside ``op``'s children; ``apart``: per usable operation and
    pair of its children, the bit sets of the operations inside each; ``action_bits``: action -> bit set
    of its operations."""

    usable: tuple[int, ...]
    under: tuple[int, ...]
    apart: tuple[tuple[int, int], ...]
    action_bits: Mapping[str, int]


def order_reach(node_masks: Sequence[int], node_ops: Sequence[tuple[int, ...]],
                op_children: Sequence[tuple[int, ...]], op_actions: Sequence[str], root: int) -> OrderReach:
    """The :class:`OrderReach` of a graph: its nodes (part masks, in topological order) and the operations
    forming each, per operation its children and action label, and the root."""
    n_nodes = len(node_masks)
    buildable = [m.bit_count() == 1 for m in node_masks]
    for n in range(n_nodes):  # topological order: children first
        buildable[n] = buildable[n] or any(all(buildable[c] for c in op_children[o]) for o in node_ops[n])
    on_plan = [False] * n_nodes
    on_plan[root] = buildable[root]
    usable = []
    for n in reversed(range(n_nodes)):
        for o in node_ops[n] if on_plan[n] else ():
            if all(buildable[c] for c in op_children[o]):
                usable.append(o)
                for c in op_children[o]:
                    on_plan[c] = True
    usable.sort()
    inside = [0] * n_nodes  # the operations some build tree of the node carries out
    is_usable = set(usable)
    for n in range(n_nodes):
        for o in node_ops[n]:
            if o in is_usable:
                inside[n] |= 1 << o
                for c in op_children[o]:
                    inside[n] |= inside[c]
    under = [0] * len(op_actions)
    apart = []
    for o in usable:
        kids = [inside[c] for c in op_children[o]]
        for k in kids:
            under[o] |= k
        apart += [(a, b) for i, a in enumerate(kids) for b in kids[i + 1:]]
    bits: dict[str, int] = {}
    for o, action in enumerate(op_actions):
        bits[action] = bits.get(action, 0) | 1 << o
    return OrderReach(tuple(usable), tuple(under), tuple(apart), FrozenDict(bits))


def may_precede(reach: OrderReach, first: str, then: str) -> bool:
    """Some complete plan can carry out an operation of action ``first`` before one of action ``then``."""
    x, y = reach.action_bits.get(first, 0), reach.action_bits.get(then, 0)
    return any(y >> op & 1 and reach.under[op] & x for op in reach.usable) or any(
        (a & x and b & y) or (a & y and b & x) for a, b in reach.apart)


def free_order_groups(actions: Sequence[str],
                      precede: Callable[[str, str], bool]) -> tuple[tuple[str, ...], ...]:
    """``actions`` in groups of linked actions (each ``precede``-s the other), in action order."""
    group = {a: i for i, a in enumerate(actions)}

    def root(a: str) -> str:
        while actions[group[a]] != a:
            a = actions[group[a]]
        return a

    for i, x in enumerate(actions):
        for y in actions[i + 1:]:
            if root(x) != root(y) and precede(x, y) and precede(y, x):
                group[root(y)] = group[root(x)]
    out: dict[str, list[str]] = {}
    for a in actions:
        out.setdefault(root(a), []).append(a)
    return tuple(tuple(v) for v in out.values())
