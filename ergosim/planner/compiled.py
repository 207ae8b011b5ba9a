"""The compiled AND/OR graph: the frozen indices and arrays that every planner reads (paper §2).

A task (parts, agents, operations) is compiled once. Nodes are sub-assemblies, each a bit mask over the
parts; they are indexed in topological order (by number of parts, then by part indices), so a child's
index is always below its father's, and the root (the full assembly, Θ_f) is last. Operations keep the
task's order. Hyper-arcs (one per operation and allowed agent) are laid out for the bottom-up pass
(:mod:`ergosim.planner.layout`); the per-operation table (:class:`OperationTable`) and the paper search's
edge lists are derived on first use, by the graph itself.

The planners (:mod:`~ergosim.planner.bottom_up`, :mod:`~ergosim.planner.paper_search`,
:mod:`~ergosim.planner.outside`, :mod:`~ergosim.planner.team`) take a :class:`CompiledGraph` and read only
its public attributes; they never import :mod:`ergosim.planner.graph`, whose :class:`AndOrGraph` is a
compiled graph with the planners' entry point on top.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ergosim.errors import ConfigError, InfeasiblePlanError, TaskFileError
from ergosim.planner.agents import Agent, Operation
from ergosim.planner.layout import Layout, build_layout
from ergosim.planner.validation import check_agents, check_operation, check_parts, format_parts

__all__ = ["CompiledGraph", "OperationTable"]


@dataclass(frozen=True)
class OperationTable:
    """Per-operation arrays of a compiled graph (read-only).

    ``op_perm`` (n_hyperarcs,) hyper-arc indices grouped by operation, ``op_start`` (n_ops + 1,) where each
    operation's group starts; ``op_children`` (n_ops, k) child nodes padded with the dummy node
    ``n_nodes``; ``op_father`` (n_ops,); ``levels``: per father size, largest first, (operation indices,
    their fathers, their child columns (k, m)); ``others``: for each child slot j, the other slots;
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
        put("origins", _FrozenDict(dict(origins or {})))
        put("parts", tuple(parts))
        put("agents", tuple(agents))
        put("operations", tuple(operations))
        put("part_index", _FrozenDict(check_parts(self.parts, self.source + ":")))
        put("agent_index", _FrozenDict(check_agents(self.agents, self.source + ":")))
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
        put("layout", _read_only(layout))
        put("key_hyperarcs", _FrozenDict(_index_keys(self)))
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
        reach = self._reach
        x, y = reach.action_bits.get(first, 0), reach.action_bits.get(then, 0)
        return any(y >> op & 1 and reach.under[op] & x for op in reach.usable) or any(
            (a & x and b & y) or (a & y and b & x) for a, b in reach.apart)

    @functools.cached_property
    def free_order_groups(self) -> tuple[tuple[str, ...], ...]:
        """The actions in groups whose order is free: two actions are linked when each may come before the
        other (:meth:`may_precede`), and a group is a set of linked actions; in action order. (In the
        corner joint, a2, a3 and a4 form one group: L, S1 and S2 go into J in any order.)"""
        group = {a: i for i, a in enumerate(self.actions)}

        def root(a: str) -> str:
            while self.actions[group[a]] != a:
                a = self.actions[group[a]]
            return a

        for i, x in enumerate(self.actions):
            for y in self.actions[i + 1:]:
                if root(x) != root(y) and self.may_precede(x, y) and self.may_precede(y, x):
                    group[root(y)] = group[root(x)]
        out: dict[str, list[str]] = {}
        for a in self.actions:
            out.setdefault(root(a), []).append(a)
        return tuple(tuple(v) for v in out.values())

    @functools.cached_property
    def _reach(self) -> _OrderReach:
        return _order_reach(self)

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
        """The :class:`OperationTable`, built on first use (the team decision and the outside pass)."""
        return _operation_table(self)

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


@dataclass(frozen=True)
class _OrderReach:
    """What may come before what: ``usable`` the operations of some complete plan; ``under[op]`` the bit set
    of the operations some plan carries out inside ``op``'s children; ``apart``: per usable operation and
    pair of its children, the bit sets of the operations inside each; ``action_bits``: action -> bit set
    of its operations."""

    usable: tuple[int, ...]
    under: tuple[int, ...]
    apart: tuple[tuple[int, int], ...]
    action_bits: Mapping[str, int]


def _order_reach(g: CompiledGraph) -> _OrderReach:
    buildable = [m.bit_count() == 1 for m in g.node_masks]
    for n in range(g.n_nodes):  # topological order: children first
        buildable[n] = buildable[n] or any(all(buildable[c] for c in g.op_children[o]) for o in g.node_ops[n])
    on_plan = [False] * g.n_nodes
    on_plan[g.root] = buildable[g.root]
    usable = []
    for n in reversed(range(g.n_nodes)):
        for o in g.node_ops[n] if on_plan[n] else ():
            if all(buildable[c] for c in g.op_children[o]):
                usable.append(o)
                for c in g.op_children[o]:
                    on_plan[c] = True
    usable.sort()
    inside = [0] * g.n_nodes  # the operations some build tree of the node carries out
    is_usable = set(usable)
    for n in range(g.n_nodes):
        for o in g.node_ops[n]:
            if o in is_usable:
                inside[n] |= 1 << o
                for c in g.op_children[o]:
                    inside[n] |= inside[c]
    under = [0] * len(g.operations)
    apart = []
    for o in usable:
        kids = [inside[c] for c in g.op_children[o]]
        for k in kids:
            under[o] |= k
        apart += [(a, b) for i, a in enumerate(kids) for b in kids[i + 1:]]
    bits: dict[str, int] = {}
    for o, op in enumerate(g.operations):
        bits[op.action] = bits.get(op.action, 0) | 1 << o
    return _OrderReach(tuple(usable), tuple(under), tuple(apart), _FrozenDict(bits))


class _FrozenDict(dict):
    """A dict that cannot change once built (a subclass of dict keeps the planners' lookups at C speed)."""

    def _refuse(self, *args, **kwargs):
        raise TypeError("a compiled graph is frozen: its mappings cannot change")

    __setitem__ = __delitem__ = __ior__ = clear = pop = popitem = setdefault = update = _refuse


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
        "op_index": _FrozenDict(op_index),
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
    return {k: _frozen(np.array(v, dtype=np.int64)) for k, v in keys.items()}


def _operation_table(g: CompiledGraph) -> OperationTable:
    lay = g.layout
    n_ops = len(g.operations)
    perm = np.argsort(lay.op, kind="stable")
    start = np.searchsorted(lay.op[perm], np.arange(n_ops + 1), side="left")
    width = max((len(c) for c in g.op_children), default=2)
    children = np.full((n_ops, width), g.n_nodes, dtype=np.int64)
    for i, ch in enumerate(g.op_children):
        children[i, : len(ch)] = ch
    father = np.asarray(g.op_father, dtype=np.int64).reshape(-1)
    levels = []
    for level in reversed(lay.levels):
        ops = np.unique(lay.op[level.lo : level.hi])
        levels.append((_frozen(ops), _frozen(father[ops]), _frozen(np.ascontiguousarray(children[ops].T))))
    others = tuple(tuple(c for c in range(width) if c != j) for j in range(width))
    by_action: dict[str, list[int]] = {}
    for i, op in enumerate(g.operations):
        by_action.setdefault(op.action, []).append(i)
    action_ops = _FrozenDict({a: _frozen(np.array(v, dtype=np.int64)) for a, v in by_action.items()})
    return OperationTable(_frozen(perm), _frozen(start), _frozen(children), _frozen(father), tuple(levels),
                          others, action_ops)


def _frozen(a: np.ndarray) -> np.ndarray:
    a.flags.writeable = False
    return a


def _read_only(layout: Layout) -> Layout:
    for a in (layout.op, layout.agent, layout.father, layout.cost, layout.seg_start, layout.seg_end):
        _frozen(a)
    for level in layout.levels:
        for a in (level.children, level.op_of, level.starts, level.fathers):
            _frozen(a)
    return layout


def _bits(mask: int) -> tuple[int, ...]:
    """Indices of the set bits of ``mask``, ascending."""
    out = []
    while mask:
        low = mask & -mask
        out.append(low.bit_length() - 1)
        mask ^= low
    return tuple(out)
