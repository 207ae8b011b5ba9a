"""The AND/OR graph as a state space of configurations, for searches over the *order* of a plan's actions.

A configuration Θ is the set of sub-assemblies that exist (§2.1); an operation is ready in Θ when all its
children are in Θ, and doing it replaces them by its father. A sequential plan is then a path of ready
operations from Θ to {root}: the searches of :mod:`ergosim.planner.lookahead` walk these paths, which the
order-free planners never enumerate.

Built from the graph's public records (parts, agents, operations, actions), once per graph, and cached:
successors per configuration are computed the first time a configuration is reached and kept (a run reaches
the same configurations every repetition). Sub-assemblies are part bitmasks (bit i = ``graph.parts[i]``).

*Action-once* tasks: every plan makes each of the root's actions exactly once (the corner joint, the
gearbox, ``sequential:N``, ``scarce:N``). There the actions a configuration still needs are known without a
search, which gives the searches their bounds; :attr:`Transitions.action_once` says whether a graph is one.
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Iterable

import numpy as np

__all__ = ["Transitions", "Successors", "transitions"]


class Successors:
    """The hyper-arcs ready in one configuration, flattened per agent: ``op``, ``action``, ``agent`` (k,)
    indices (operation in ``graph.operations``, action in ``graph.actions``, agent in ``graph.agents``),
    ``next`` (k,) the configuration id each leads to, ``done`` (k,) whether that is the full assembly and
    ``need`` (k, A) the actions still needed there (:meth:`Transitions.needed`); ``tie`` (k,) the pair's
    place in (action name, operation name, agent name) order, the searches' tie-break. ``table`` (6, k) holds
    op, action, agent, next, done and tie as rows, so a search joins many configurations' successors with
    one concatenation."""

    __slots__ = ("op", "action", "agent", "next", "done", "need", "tie", "table")

    def __init__(self, op, action, agent, nxt, done, need, tie) -> None:
        self.table = np.array([op, action, agent, nxt, done, tie], dtype=np.int64).reshape(6, len(op))
        self.op, self.action, self.agent, self.next, _, self.tie = self.table
        self.done = np.asarray(done, dtype=bool)
        self.need = np.asarray(need, dtype=bool)


class Transitions:
    """Configurations of ``graph`` as integer ids, their ready hyper-arcs, and (action-once tasks) the
    actions each still needs. Configuration ids are stable for the life of the object."""

    def __init__(self, graph) -> None:
        self.graph = graph
        bit = {p: 1 << i for i, p in enumerate(graph.parts)}
        action_of = {a: i for i, a in enumerate(graph.actions)}
        agent_of = {a.name: i for i, a in enumerate(graph.agents)}
        self.n_actions = len(graph.actions)
        self.children: list[tuple[int, ...]] = []
        self.father: list[int] = []
        self.op_action = np.empty(len(graph.operations), dtype=np.int64)
        self.op_agents: list[np.ndarray] = []
        self._by_child: dict[int, list[int]] = {}
        for k, op in enumerate(graph.operations):
            kids = tuple(_mask(c, bit) for c in op.children)
            self.children.append(kids)
            self.father.append(_mask(op.father, bit))
            self.op_action[k] = action_of[op.action]
            self.op_agents.append(np.array([agent_of[a] for a in op.agents], dtype=np.int64))
            for c in kids:
                self._by_child.setdefault(c, []).append(k)
        self.allowed = np.zeros((self.n_actions, len(graph.agents)), dtype=bool)
        for k, agents in enumerate(self.op_agents):
            self.allowed[self.op_action[k], agents] = True
        """(A, N) bool: the agent has a hyper-arc for some operation of the action."""
        self.op_rank = _name_rank([(op.action, op.name) for op in graph.operations])
        """(operations,) each operation's place in (action name, operation name) order: the searches' ties
        are broken by names, never by the order of the task file."""
        self.agent_rank = _name_rank([a.name for a in graph.agents])
        """(N,) each agent's place in name order."""
        nodes = {m for kids in self.children for m in kids} | set(self.father)
        self._node_bit = {m: 1 << i for i, m in enumerate(sorted(nodes))}
        self._op_bits = [sum(self._node_bit[c] for c in kids) for kids in self.children]
        self.root = (1 << len(graph.parts)) - 1
        self.father_parts = np.array([[f >> i & 1 for i in range(len(graph.parts))] for f in self.father],
                                     dtype=bool).reshape(len(self.father), len(graph.parts))
        """(operations, P) bool: the parts of each operation's father."""
        self._ids: dict[frozenset[int], int] = {}
        self.configs: list[frozenset[int]] = []
        self._succ: list[Successors | None] = []
        self.made = self._actions_made()
        self.action_once = self.made is not None
        self._needed: list[np.ndarray | None] = []
        self._counts: dict[int, float] = {}
        self.pilots: dict[bytes, object] = {}
        """The beam's per-configuration tables by model (:func:`~ergosim.planner.pilot.pilot_table`)."""

    # -------------------------------------------------------------------------------------------- build
    def _actions_made(self) -> dict[int, int] | None:
        """sub-assembly -> bitmask of the actions that made it, when every way of making it makes the same
        actions once each (else None: the graph is not action-once)."""
        made: dict[int, int] = {}
        order = sorted(range(len(self.father)), key=lambda k: self.father[k].bit_count())
        for k in order:
            if any(c.bit_count() > 1 and c not in made for c in self.children[k]):
                continue  # a child nothing makes: the operation is never ready
            acts = 1 << int(self.op_action[k])
            for c in self.children[k]:
                below = made.get(c, 0)
                if acts & below:
                    return None
                acts |= below
            if made.setdefault(self.father[k], acts) != acts:
                return None
        return made

    def config_id(self, config: Iterable[int]) -> int:
        """The id of a configuration given as sub-assembly bitmasks."""
        key = frozenset(config)
        cid = self._ids.get(key)
        if cid is None:
            cid = self._ids[key] = len(self.configs)
            self.configs.append(key)
            self._succ.append(None)
            self._needed.append(None)
        return cid

    def start(self, done: Iterable[str]) -> int:
        """The id of the configuration after the operations ``done`` (validated by the graph)."""
        bit = {p: 1 << i for i, p in enumerate(self.graph.parts)}
        return self.config_id(_mask(node, bit) for node in self.graph.configuration(list(done)))

    # ----------------------------------------------------------------------------------------- queries
    def complete(self, cid: int) -> bool:
        """True when configuration ``cid`` is the full assembly alone."""
        return self.configs[cid] == {self.root}

    def successors(self, cid: int) -> Successors:
        """Every (operation, agent) ready in configuration ``cid``, in (operation, agent) order."""
        succ = self._succ[cid]
        if succ is not None:
            return succ
        config = self.configs[cid]
        bits = 0
        for c in config:
            bits |= self._node_bit[c]
        candidates = set().union(*(self._by_child.get(c, ()) for c in config))
        op_bits = self._op_bits
        ops = sorted(k for k in candidates if bits & op_bits[k] == op_bits[k])
        rows: list[tuple[int, int, int, int]] = []
        for k in ops:
            nxt = self.config_id((config - set(self.children[k])) | {self.father[k]})
            rows += [(k, int(self.op_action[k]), int(j), nxt) for j in self.op_agents[k]]
        cols = list(zip(*rows, strict=True)) if rows else ([], [], [], [])
        done = [self.complete(c) for c in cols[3]]
        need = np.array([self.needed(c) for c in cols[3]], dtype=bool).reshape(len(rows), self.n_actions)
        tie = self.op_rank[list(cols[0])] * len(self.agent_rank) + self.agent_rank[list(cols[2])]
        succ = self._succ[cid] = Successors(*cols, done, need, tie)
        return succ

    def sequences(self, cid: int, cap: int, budget: int = 2000) -> float:
        """How many sequences of (operation, agent) lead from ``cid`` to the full assembly (pruning ignored,
        so an upper bound for a call that prunes), or inf once that number passes ``cap`` or counting would
        visit more than ``budget`` new configurations. Counts are kept per configuration."""
        self._budget = budget
        try:
            return self._count(cid, cap)
        except _TooMany:
            self._counts[cid] = math.inf
            return math.inf

    def _count(self, cid: int, cap: int) -> float:
        count = self._counts.get(cid)
        if count is not None:
            return count
        if self.complete(cid):
            total = 1.0
        else:
            self._budget -= 1
            if self._budget < 0:
                raise _TooMany
            total = 0.0
            for nxt in self.successors(cid).next.tolist():
                total += self._count(nxt, cap)
                if total > cap:
                    total = math.inf
                    break
        self._counts[cid] = total
        return total

    def needed(self, cid: int) -> np.ndarray:
        """(A,) bool: the actions every plan from ``cid`` still makes (action-once tasks; else all False)."""
        need = self._needed[cid]
        if need is None:
            need = np.zeros(self.n_actions, dtype=bool)
            if self.made is not None:
                left = self.made.get(self.root, 0)
                for c in self.configs[cid]:
                    left &= ~self.made.get(c, 0)
                need[[i for i in range(self.n_actions) if left >> i & 1]] = True
            self._needed[cid] = need
        return need


class _TooMany(Exception):
    pass


_CACHE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def transitions(graph) -> Transitions:
    """The cached :class:`Transitions` of ``graph`` (built on first use)."""
    view = _CACHE.get(graph)
    if view is None:
        view = _CACHE[graph] = Transitions(graph)
    return view


def _name_rank(names: list) -> np.ndarray:
    rank = np.empty(len(names), dtype=np.int64)
    rank[sorted(range(len(names)), key=names.__getitem__)] = np.arange(len(names))
    return rank


def _mask(parts: Iterable[str], bit: dict[str, int]) -> int:
    out = 0
    for p in parts:
        out |= bit[p]
    return out
