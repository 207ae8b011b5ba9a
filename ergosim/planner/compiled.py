"""The compiled AND/OR graph: the frozen indices and arrays that every planner reads (paper §2).

A task (parts, agents, operations) is compiled once. Nodes are sub-assemblies, each a bit mask over the
parts; they are indexed in topological order (by number of parts, then by part indices), so a child's
index is always below its father's, and the root (the full assembly, Θ_f) is last. Operations keep the
task's order. Hyper-arcs (one per operation and allowed agent) are laid out for the bottom-up pass
(:mod:`ergosim.planner.layout`); the per-operation table (:mod:`ergosim.planner.op_table`), the paper
search's edge lists and the free-order groups (:mod:`ergosim.planner.free_order`) are derived on first
use, by the graph itself.

The planners (:mod:`~ergosim.planner.bottom_up`, :mod:`~ergosim.planner.paper_search`,
:mod:`~ergosim.planner.outside`, :mod:`~ergosim.planner.team`) take a :class:`CompiledGraph` and read only
its public attributes; they never import :mod:`ergosim.planner.graph`, whose :class:`AndOrGraph` is a
compiled graph with the planners' entry point on top.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from ergosim.errors import ConfigError, InfeasiblePlanError, TaskFileError
from ergosim.planner import free_order
from ergosim.planner.agents import Agent, Operation
from ergosim.planner.frozen import FrozenDict, read_only
from ergosim.planner.layout import Layout, build_layout
from ergosim.planner.op_table import OperationTable, build_operation_table
from ergosim.planner.validation import check_agents, check_operation, check_parts, format_parts

__all__ = ["CompiledGraph"]


class CompiledGraph:
    """An assembly task compiled into the arrays its planners read; frozen once built.

    Args:
        name: task name, used in messages.
        parts: the atomic parts p_1..p_M; their order is the order of every part tuple.
        agents: the team W.
        operations: the assembly operations with their allowed agents and fixed costs.
        actions: the action labels in display order (default: order of first use by ``operations``).
        source: where the task came from (a file path), for messages.
        origins: operation name -> entry text for messages, e.g. ``"operations[3]"``.

    Raises:
        TaskFileError: a malformed operation (duplicate, unknown part or agent, unusable).
        InfeasiblePlanError: no operation joins the full assembly, or a part can never be joined.

    Attributes (all read-only):
        parts, agents, operations, actions, name, source: as given (tuples).
        part_index, agent_index, op_index: name -> index.
        node_masks: per node, its parts as a bit mask (bit i = ``parts[i]``), in topological order.
        op_father, op_children: per operation, its father node and its child nodes.
        node_ops: per node, the operations that form it (its OR branches).
        root: the full assembly's node; leaves: per part, its node.
        layout: the hyper-arc arrays of the bottom-up pass (:class:`~ergosim.planner.layout.Layout`).
        key_hyperarcs: (action, agent) -> the hyper-arc indices of that pair.
    """

    def __init__(
        self,
        name: str,
        parts: Sequence[str],
        agents: Sequence[Agent],
        operations: Sequence[Operation],
        *,
        actions: Sequence[str] | None = None,
        source: str | None = None,
        origins: Mapping[str, str] | None = None,
    ) -> None:
        put = functools.partial(object.__setattr__, self)
        put("name", name)
        put("source", source or name)
        put("origins", FrozenDict(dict(origins or {})))
        put("parts", tuple(parts))
        put("agents", tuple(agents))
        put("operations", tuple(operations))
        put("part_index", FrozenDict(check_parts(self.parts, self.source + ":")))
        put("agent_index", FrozenDict(check_agents(self.agents, self.source + ":")))
        for key, value in _nodes(self).items():
            put(key, value)
        put("actions", _action_order(self.operations, actions))
        layout = build_layout(
            np.array([m.bit_count() for m in self.node_masks], dtype=np.int64),
            self.op_father,
            self.op_children,
            [tuple(self.agent_index[a] for a in op.agents) for op in self.operations],
            [op.costs for op in self.operations],
        )
        put("layout", _read_only_layout(layout))
        put("key_hyperarcs", FrozenDict(_index_keys(self)))
        self._check_compiled()

    def _check_compiled(self) -> None:
        """Called once compiled: a subclass checks more here (:class:`~ergosim.planner.graph.AndOrGraph`
        checks that a plan exists)."""

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError(f"a compiled graph is frozen: cannot set {name!r}")

    def __delattr__(self, name: str) -> None:
        raise AttributeError(f"a compiled graph is frozen: cannot delete {name!r}")

    def __reduce__(self):
        """Pickled as its task and compiled again on load (a spawned worker gets the same graph)."""
        return (_rebuild, (type(self), self.name, self.parts, self.agents, self.operations, self.actions,
                           self.source, dict(self.origins)))

    # ------------------------------------------------------------------------------------------- names
    def where(self, operation: str | None = None, part: str | None = None) -> str:
        """``where`` text for a message about an operation or part of this task."""
        if operation is not None:
            return f"{self.source}: {self.origins.get(operation, f'operation {operation!r}')}"
        if part is not None:
            return f"{self.source}: parts[{self.part_index[part]}] {part!r}"
        return self.source

    @property
    def n_nodes(self) -> int:
        """Number of sub-assembly nodes, leaves and root included."""
        return len(self.node_masks)

    @property
    def n_hyperarcs(self) -> int:
        """Number of hyper-arcs, counted per agent (an operation two agents may do counts twice)."""
        return len(self.layout.op)

    @property
    def nodes(self) -> tuple[tuple[str, ...], ...]:
        """Every node as a tuple of part names, in topological (size) order; the root is last."""
        return tuple(self.node_parts(i) for i in range(self.n_nodes))

    def node_parts(self, node: int) -> tuple[str, ...]:
        """The part names of ``node``, in part order."""
        return tuple(self.parts[i] for i in _bits(self.node_masks[node]))

    def operation(self, name: str) -> Operation:
        """The operation called ``name``; ConfigError if there is none."""
        try:
            return self.operations[self.op_index[name]]
        except KeyError:
            raise ConfigError(f"unknown operation {name!r} in task {self.name!r}", where="done") from None

    # ------------------------------------------------------------------------------------ structure
    def part_bit(self, part: str, where: str = "part") -> int:
        """The bit of ``part`` in the node masks; ConfigError (at ``where``) for an unknown part."""
        try:
            return 1 << self.part_index[part]
        except KeyError:
            raise ConfigError(f"unknown part {part!r} in task {self.name!r}", where=where) from None

    def node_with(self, nodes: Iterable[int], part: str, where: str = "part") -> int:
        """The node of ``nodes`` (a configuration: disjoint sub-assemblies) that contains ``part``."""
        bit = self.part_bit(part, where)
        nodes = list(nodes)
        for n in nodes:
            if self.node_masks[n] & bit:
                return int(n)
        raise ConfigError(f"part {part!r} is in none of the nodes {nodes}", where=where)

    def children(self, op: int) -> tuple[int, ...]:
        """The child nodes operation ``op`` joins."""
        return self.op_children[op]

    def father(self, op: int) -> int:
        """The node operation ``op`` makes."""
        return self.op_father[op]

    def ready(self, present: np.ndarray) -> np.ndarray:
        """The operations that can start now, ascending: those whose children are all ``present``, a
        (n_nodes + 1,) bool mask over the nodes (the last entry, the padding node, True) -- the current
        configuration Θ less what is held."""
        return np.flatnonzero(present[self.op_table.op_children].all(axis=1))

    def may_precede(self, first: str, then: str) -> bool:
        """Some complete plan can carry out an operation of action ``first`` before one of action ``then``:
        inside a sub-assembly that ``then`` joins, or in a separate sub-assembly (either order)."""
        return free_order.may_precede(self._reach, first, then)

    @functools.cached_property
    def free_order_groups(self) -> tuple[tuple[str, ...], ...]:
        """The actions in groups whose order is free (:mod:`ergosim.planner.free_order`), in action order.
        (In the corner joint, a2, a3 and a4 form one group: L, S1 and S2 go into J in any order.)"""
        return free_order.free_order_groups(self.actions, self.may_precede)

    @functools.cached_property
    def _reach(self) -> free_order.OrderReach:
        return free_order.order_reach(self.node_masks, self.node_ops, self.op_children,
                                      [op.action for op in self.operations], self.root)

    @functools.cached_property
    def parents(self) -> tuple[tuple[int, ...], ...]:
        """Per node, the operations that take it as a child (empty for the root)."""
        out: list[list[int]] = [[] for _ in self.node_masks]
        for op, children in enumerate(self.op_children):
            for c in children:
                out[c].append(op)
        return tuple(tuple(p) for p in out)

    @functools.cached_property
    def op_table(self) -> OperationTable:
        """The :class:`~ergosim.planner.op_table.OperationTable`, built on first use (the team decision and
        the outside pass)."""
        return build_operation_table(self.layout, self.op_father, self.op_children,
                                     [op.action for op in self.operations], self.n_nodes)

    @functools.cached_property
    def node_edges(self) -> tuple[tuple[tuple[int, int], ...], ...]:
        """Per node: (hyper-arc index, bit set of its children's nodes) of the hyper-arcs forming it, built on
        first use (the paper search, :mod:`ergosim.planner.paper_search`)."""
        lay = self.layout
        child_bits = [sum(1 << c for c in set(children)) for children in self.op_children]
        ops = lay.op.tolist()
        return tuple(
            tuple((h, child_bits[ops[h]]) for h in range(int(lay.seg_start[n]), int(lay.seg_end[n])))
            for n in range(self.n_nodes)
        )

    def __repr__(self) -> str:
        return (
            f"{type(self).__name__}({self.name!r}, parts={len(self.parts)}, agents={len(self.agents)}, "
            f"nodes={self.n_nodes}, hyperarcs={self.n_hyperarcs})"
        )


def _rebuild(cls, name, parts, agents, operations, actions, source, origins):
    return cls(name, parts, agents, operations, actions=actions, source=source, origins=origins)


def _nodes(g: CompiledGraph) -> dict[str, object]:
    """The nodes reachable from the root through the operations, and each operation's father and children
    as node indices."""
    masks_of = []
    structure: dict[frozenset[int], str] = {}
    op_index: dict[str, int] = {}
    for i, op in enumerate(g.operations):
        if op.name in op_index:
            raise TaskFileError(f"duplicate operation name {op.name!r}", where=g.where(op.name))
        op_index[op.name] = i
        father, children = check_operation(op, g.part_index, g.agent_index, g.where)
        key = frozenset(children)
        if key in structure:
            raise TaskFileError(
                f"operation {op.name!r} joins the same children as operation {structure[key]!r}",
                where=g.where(op.name),
            )
        structure[key] = op.name
        masks_of.append((father, children))
    root = (1 << len(g.parts)) - 1
    joined = 0
    by_father: dict[int, list[int]] = {}
    for i, (father, _) in enumerate(masks_of):
        joined |= father
        by_father.setdefault(father, []).append(i)
    if len(g.parts) > 1 and root not in by_father:
        for part, index in g.part_index.items():
            if g.operations and not joined >> index & 1:
                raise InfeasiblePlanError(
                    f"no feasible plan: part {part!r} can never be joined: no operation includes it",
                    where=g.where(part=part),
                )
        raise InfeasiblePlanError(
            f"no feasible plan: no operation joins the full assembly {format_parts(g.parts)}",
            where=g.source,
        )
    reached = {root} | {1 << i for i in range(len(g.parts))}
    stack = [root]
    while stack:
        for i in by_father.get(stack.pop(), ()):
            for child in masks_of[i][1]:
                if child not in reached:
                    reached.add(child)
                    stack.append(child)
    for i, (father, _) in enumerate(masks_of):
        if father not in reached:
            op = g.operations[i]
            raise TaskFileError(
                f"operation {op.name!r} can never be used: its father {format_parts(op.father)} is not "
                "a child of any operation on the way to the full assembly",
                where=g.where(op.name),
            )
    node_masks = tuple(sorted(reached, key=lambda m: (m.bit_count(), _bits(m))))
    node_of = {m: i for i, m in enumerate(node_masks)}
    op_father = tuple(node_of[f] for f, _ in masks_of)
    node_ops: list[list[int]] = [[] for _ in node_masks]
    for i, father in enumerate(op_father):
        node_ops[father].append(i)
    return {
        "op_index": FrozenDict(op_index),
        "node_masks": node_masks,
        "op_father": op_father,
        "op_children": tuple(tuple(node_of[c] for c in ch) for _, ch in masks_of),
        "node_ops": tuple(tuple(ops) for ops in node_ops),
        "root": node_of[root],
        "leaves": tuple(node_of[1 << i] for i in range(len(g.parts))),
    }


def _action_order(operations: Sequence[Operation], actions: Sequence[str] | None) -> tuple[str, ...]:
    used = dict.fromkeys(op.action for op in operations)
    order = list(actions) if actions is not None else list(used)
    listed = set(order)  # a set: the reader stays linear in the operations (scripts/bench_taskfile.py)
    missing = [a for a in used if a not in listed]
    return tuple(a for a in order if a in used) + tuple(missing)


def _index_keys(g: CompiledGraph) -> dict[tuple[str, str], np.ndarray]:
    lay = g.layout
    keys: dict[tuple[str, str], list[int]] = {}
    for h, (op, agent) in enumerate(zip(lay.op.tolist(), lay.agent.tolist(), strict=True)):
        keys.setdefault((g.operations[op].action, g.agents[agent].name), []).append(h)
    return {k: read_only(np.array(v, dtype=np.int64)) for k, v in keys.items()}


def _read_only_layout(layout: Layout) -> Layout:
    """``layout`` with its arrays read-only, but for each level's ``starts`` that every replan hands to
    ``np.minimum.reduceat`` (:mod:`ergosim.planner.frozen` says why)."""
    for a in (layout.op, layout.agent, layout.father, layout.cost, layout.seg_start, layout.seg_end):
        read_only(a)
    for level in layout.levels:
        for a in (level.children, level.op_of, level.fathers):
            read_only(a)
    return layout


def _bits(mask: int) -> tuple[int, ...]:
    """Indices of the set bits of ``mask``, ascending."""
    out = []
    while mask:
        low = mask & -mask
        out.append(low.bit_length() - 1)
        mask ^= low
    return tuple(out)
