"""The AND/OR graph of an assembly task with per-agent hyper-arcs (paper §2).

Nodes are sub-assemblies (sets of parts); an operation joins two or more disjoint children into their
union, the father; each operation is duplicated once per agent allowed to do it, and each copy is a
hyper-arc with cost c_{h,w}. The root is the full assembly (configuration Θ_f); the leaves are the
parts (Θ_i). The graph holds exactly the nodes reachable from the root through the operations.

A graph is built once; :meth:`AndOrGraph.plan` then re-plans from any current configuration with any
costs, which is the call the twin makes after every completed action.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from ergosim.errors import ConfigError, InfeasiblePlanError, TaskFileError
from ergosim.planner import bottom_up, call_inputs, diagnose, paper_search
from ergosim.planner.agents import Agent, Operation
from ergosim.planner.layout import build_layout
from ergosim.planner.plan import Plan, assemble_plan
from ergosim.planner.validation import check_agents, check_operation, check_parts, format_parts

__all__ = ["AndOrGraph", "PLANNERS"]

PLANNERS = ("fast", "paper")


class AndOrGraph:
    """An assembly task as an AND/OR graph.

    Args:
        name: task name, used in messages.
        parts: the atomic parts p_1..p_M; their order is the order of every part tuple.
        agents: the team W.
        operations: the assembly operations with their allowed agents and fixed costs.
        actions: the action labels in display order (default: order of first use by ``operations``).
        source: where the task came from (a file path), for messages.
        origins: operation name -> entry text for messages, e.g. ``"operations[3]"``.
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
        self.name = name
        self.source = source or name
        self._origins = dict(origins or {})
        self.parts = tuple(parts)
        self.agents = tuple(agents)
        self.operations = tuple(operations)
        self._part_index = check_parts(self.parts, self.source + ":")
        self._agent_index = check_agents(self.agents, self.source + ":")
        self._build_nodes()
        self._build_actions(actions)
        self._layout = build_layout(
            np.array([m.bit_count() for m in self._node_masks], dtype=np.int64),
            self._op_father,
            self._op_children,
            [tuple(self._agent_index[a] for a in op.agents) for op in self.operations],
            [op.costs for op in self.operations],
        )
        self._key_hyperarcs = self._index_keys()
        self._paper_cache: object | None = None
        self._team_cache: object | None = None
        self._check_feasible()

    # ----------------------------------------------------------------------------------------- build
    def where(self, operation: str | None = None, part: str | None = None) -> str:
        """``where`` text for a message about an operation or part of this task."""
        if operation is not None:
            return f"{self.source}: {self._origins.get(operation, f'operation {operation!r}')}"
        if part is not None:
            return f"{self.source}: parts[{self._part_index[part]}] {part!r}"
        return self.source

    def _build_nodes(self) -> None:
        masks_of = []
        structure: dict[frozenset[int], str] = {}
        self._op_index: dict[str, int] = {}
        for i, op in enumerate(self.operations):
            if op.name in self._op_index:
                raise TaskFileError(f"duplicate operation name {op.name!r}", where=self.where(op.name))
            self._op_index[op.name] = i
            father, children = check_operation(op, self._part_index, self._agent_index, self.where)
            key = frozenset(children)
            if key in structure:
                raise TaskFileError(
                    f"operation {op.name!r} joins the same children as operation {structure[key]!r}",
                    where=self.where(op.name),
                )
            structure[key] = op.name
            masks_of.append((father, children))
        root = (1 << len(self.parts)) - 1
        joined = 0
        by_father: dict[int, list[int]] = {}
        for i, (father, _) in enumerate(masks_of):
            joined |= father
            by_father.setdefault(father, []).append(i)
        if len(self.parts) > 1 and root not in by_father:
            for part, index in self._part_index.items():
                if self.operations and not joined >> index & 1:
                    raise InfeasiblePlanError(
                        f"no feasible plan: part {part!r} can never be joined: no operation includes it",
                        where=self.where(part=part),
                    )
            raise InfeasiblePlanError(
                f"no feasible plan: no operation joins the full assembly {format_parts(self.parts)}",
                where=self.source,
            )
        reached = {root} | {1 << i for i in range(len(self.parts))}
        stack = [root]
        while stack:
            for i in by_father.get(stack.pop(), ()):
                for child in masks_of[i][1]:
                    if child not in reached:
                        reached.add(child)
                        stack.append(child)
        for i, (father, _) in enumerate(masks_of):
            if father not in reached:
                op = self.operations[i]
                raise TaskFileError(
                    f"operation {op.name!r} can never be used: its father {format_parts(op.father)} is not "
                    "a child of any operation on the way to the full assembly",
                    where=self.where(op.name),
                )
        self._node_masks = sorted(reached, key=lambda m: (m.bit_count(), _bits(m)))
        self._node_of = {m: i for i, m in enumerate(self._node_masks)}
        self._op_father = [self._node_of[f] for f, _ in masks_of]
        self._op_children = [tuple(self._node_of[c] for c in ch) for _, ch in masks_of]
        self._node_ops: list[list[int]] = [[] for _ in self._node_masks]
        for i, father in enumerate(self._op_father):
            self._node_ops[father].append(i)
        self._root = self._node_of[root]
        self._leaf = [self._node_of[1 << i] for i in range(len(self.parts))]

    def _build_actions(self, actions: Sequence[str] | None) -> None:
        used = dict.fromkeys(op.action for op in self.operations)
        order = list(actions) if actions is not None else list(used)
        listed = set(order)  # a set: the reader stays linear in the operations (scripts/bench_taskfile.py)
        missing = [a for a in used if a not in listed]
        self.actions = tuple(a for a in order if a in used) + tuple(missing)

    def _index_keys(self) -> dict[tuple[str, str], np.ndarray]:
        lay = self._layout
        keys: dict[tuple[str, str], list[int]] = {}
        for h, (op, agent) in enumerate(zip(lay.op.tolist(), lay.agent.tolist(), strict=True)):
            keys.setdefault((self.operations[op].action, self.agents[agent].name), []).append(h)
        return {k: np.array(v, dtype=np.int64) for k, v in keys.items()}

    def _check_feasible(self) -> None:
        config = np.array(self._leaf, dtype=np.int64)
        node_cost, _ = bottom_up.node_costs(self, config, self._layout.cost)
        if not np.isfinite(node_cost[self._root]):
            reason, op_name, part = diagnose.explain(self, config, self._layout.cost, node_cost)
            raise InfeasiblePlanError(f"no feasible plan: {reason}", where=self.where(op_name, part))

    # ---------------------------------------------------------------------------------------- public
    @property
    def n_nodes(self) -> int:
        """Number of sub-assembly nodes, leaves and root included."""
        return len(self._node_masks)

    @property
    def n_hyperarcs(self) -> int:
        """Number of hyper-arcs, counted per agent (an operation two agents may do counts twice)."""
        return len(self._layout.op)

    @property
    def nodes(self) -> tuple[tuple[str, ...], ...]:
        """Every node as a tuple of part names, in topological (size) order; the root is last."""
        return tuple(self.node_parts(i) for i in range(self.n_nodes))

    def node_parts(self, node: int) -> tuple[str, ...]:
        return tuple(self.parts[i] for i in _bits(self._node_masks[node]))

    def operation(self, name: str) -> Operation:
        """The operation called ``name``; ConfigError if there is none."""
        try:
            return self.operations[self._op_index[name]]
        except KeyError:
            raise ConfigError(f"unknown operation {name!r} in task {self.name!r}", where="done") from None

    def configuration(self, done: Iterable[str] = ()) -> tuple[tuple[str, ...], ...]:
        """The current configuration Θ after the operations ``done``: its sub-assemblies as part tuples."""
        return tuple(self.node_parts(n) for n in call_inputs.configuration(self, done))

    def plan(
        self,
        done: Iterable[str] = (),
        costs: Mapping[tuple[str, str], float] | None = None,
        pruned: Iterable[tuple[str, str]] = (),
        planner: str = "fast",
        *,
        added: Mapping[tuple[str, str], float] | None = None,
        time_budget: float | None = None,
        max_states: int | None = None,
    ) -> Plan:
        """Optimal plan from the configuration reached by ``done`` to the full assembly.

        Args:
            done: names of the operations already carried out (any order).
            costs: (action label, agent name) -> cost for this call, overriding the fixed cost of every
                hyper-arc of that action and agent.
            pruned: (action label, agent name) pairs whose hyper-arcs are removed for this call.
            added: (action label, agent name) -> a cost added to every hyper-arc of that action and agent
                after ``costs`` (e.g. ``w_time`` × expected duration).
            planner: ``"fast"`` (bottom-up dynamic programming on the graph) or ``"paper"`` (Algorithm 1,
                search over configurations). Both return an optimal plan.
            time_budget: seconds the ``paper`` search may take before raising
                :class:`~ergosim.planner.paper_search.SearchBudgetExceeded` (default: unlimited).
            max_states: configurations the ``paper`` search may create before raising
                :class:`~ergosim.planner.paper_search.SearchMemoryExceeded`, a ConfigError (default
                :data:`~ergosim.planner.limits.MAX_PAPER_STATES`).

        Raises:
            InfeasiblePlanError: ``"no feasible plan: <reason>"``.
            ConfigError: unknown operation/action/agent, inconsistent ``done``, bad cost.
        """
        if planner not in PLANNERS:
            raise ConfigError(f"unknown planner {planner!r}; expected one of {PLANNERS}", where="planner")
        config = call_inputs.configuration(self, done)
        cost = call_inputs.hyperarc_costs(self, costs, pruned, added)
        if planner == "fast":
            hyperarcs = bottom_up.solve(self, config, cost)
        else:
            hyperarcs = paper_search.solve(self, config, cost, time_budget=time_budget, max_states=max_states)
        return assemble_plan(self, hyperarcs, config, cost)

    def __repr__(self) -> str:
        return (
            f"AndOrGraph({self.name!r}, parts={len(self.parts)}, agents={len(self.agents)}, "
            f"nodes={self.n_nodes}, hyperarcs={self.n_hyperarcs})"
        )


def _bits(mask: int) -> tuple[int, ...]:
    """Indices of the set bits of ``mask``, ascending."""
    out = []
    while mask:
        low = mask & -mask
        out.append(low.bit_length() - 1)
        mask ^= low
    return tuple(out)
