"""Team decisions: give every idle agent the best operation that is ready now (parallel execution).

The paper dispatches one action at a time (Algorithm 2). A team works in parallel: while one agent is busy,
another may start an operation whose children already exist and are not held by anyone. At a decision the
configuration has three kinds of operations besides the ones ``done``:

- ``running`` operations hold all their children until they end; the plan treats their fathers as made;
- ``reserved`` actions were started *early* by an agent (a robot fetching a part to hand it over): the
  agent holds only the child containing the moving part, and the operation that joins it is chosen when it
  joins; the plan gives the action to that agent at no further cost;
- everything else is free.

An operation is *ready* when its children are all in the configuration and none is held. A hyper-arc listed
in ``early`` ((action, agent) -> moving part) is ready as soon as the child containing the part is free and
its other children exist or are being made by a running operation.

Each ready hyper-arc h is priced by the cheapest complete plan through it, J(h) (outside costs,
:mod:`ergosim.planner.outside`), and the idle agents are served best first: the cheapest (J, agent order,
operation order) pair whose agent is still idle and whose held children are still free is taken, and so on.
A candidate at least ``margin`` above the plan optimum J* is skipped: the agent then waits for the agent
the optimal plan chose (the twin passes the threshold penalty Γ of eq. 11, so the worker is never handed
an over-threshold action because it happens to be free). Picks that open early hyper-arcs for agents still
idle (the worker starts J, so a robot may fetch L) lead to another round; a round of several picks is
checked to leave the assembly feasible.

One decision is one bottom-up pass, one outside pass and one check, whatever the team size
(``scripts/bench_planner.py``: 30 agents on ``sequential:40``).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ergosim.errors import ConfigError, InfeasiblePlanError
from ergosim.planner import bottom_up, diagnose
from ergosim.planner.call_inputs import configuration, hyperarc_costs
from ergosim.planner.compiled import CompiledGraph
from ergosim.planner.outside import outside_costs

__all__ = ["TeamStep", "TeamAssignment", "team_assign"]


@dataclass(frozen=True)
class TeamStep:
    """``agent`` starts ``operation`` (action ``action``) now at hyper-arc cost ``cost``; ``through``: the
    cost of the cheapest complete plan through it, J(h). ``early``: it holds only the child containing
    ``part`` until it joins (a handover)."""

    operation: str
    action: str
    agent: str
    cost: float
    through: float
    early: bool = False
    part: str | None = None


@dataclass(frozen=True)
class TeamAssignment:
    """The steps to start now (at most one per idle agent) and ``cost``, the optimal plan cost J* from the
    configuration with the running and reserved operations committed."""

    steps: tuple[TeamStep, ...]
    cost: float


@dataclass
class _State:
    done_nodes: np.ndarray
    commit_nodes: np.ndarray
    cost: np.ndarray
    value: np.ndarray
    totals: np.ndarray
    held: np.ndarray


def _costs(graph: CompiledGraph, done: list[str], reserved: Mapping[str, tuple[str, str]], costs, pruned,
           added) -> np.ndarray:
    """The call's hyper-arc costs, with every reserved action given to its agent at no further cost on the
    operations it can join: those with the moving part's sub-assembly, as it is now, for a child. (An
    action label that recurs later in a plan, on a larger sub-assembly, keeps its prices there.)"""
    cost = hyperarc_costs(graph, costs, pruned, added)
    if not reserved:
        return cost
    nodes = configuration(graph, done).tolist()
    lay = graph.layout
    for action, (agent, part) in reserved.items():
        joins = graph.node_with(nodes, part, where="team_assign")
        for other in graph.agents:
            index = graph.key_hyperarcs.get((action, other.name))
            if index is None:
                continue
            index = index[[joins in graph.op_children[int(op)] for op in lay.op[index]]]
            cost[index] = 0.0 if other.name == agent else np.inf
    return cost


def _evaluate(graph: CompiledGraph, done: list[str], running: list[str],
              reserved: Mapping[str, tuple[str, str]], cost: np.ndarray) -> _State:
    """Node costs from the configuration with ``running`` and ``reserved`` committed; raises
    InfeasiblePlanError when the assembly can no longer be finished."""
    done_nodes = configuration(graph, done)
    commit_nodes = configuration(graph, done + running) if running else done_nodes
    value, totals = bottom_up.node_costs(graph, commit_nodes, cost)
    if not np.isfinite(value[graph.root]):
        reason, op_name, part = diagnose.explain(graph, commit_nodes, cost, value)
        raise InfeasiblePlanError(f"no feasible plan: {reason}", where=graph.where(op_name, part))
    held = np.zeros(graph.n_nodes + 1, dtype=bool)
    tl = graph.op_table
    for name in running:
        held[tl.op_children[graph.op_index[name]]] = True
    done_list = done_nodes.tolist()
    for _, (_, part) in reserved.items():
        held[graph.node_with(done_list, part, where="team_assign")] = True
    held[-1] = False
    return _State(done_nodes, commit_nodes, cost, value, totals, held)


def _candidates(graph: CompiledGraph, state: _State, free: Sequence[str],
                early: Mapping[tuple[str, str], str],
                reserved: Mapping[str, tuple[str, str]]) -> tuple[np.ndarray, np.ndarray, list]:
    """The ready hyper-arcs of the ``free`` agents: (hyper-arcs, their operations, per hyper-arc the
    moving part of an early hyper-arc or None)."""
    tl, lay = graph.op_table, graph.layout
    free_ids = np.zeros(len(graph.agents), dtype=bool)
    free_ids[[graph.agent_index[a] for a in free]] = True
    ok = np.zeros(graph.n_nodes + 1, dtype=bool)
    ok[state.done_nodes] = True
    ok &= ~state.held
    ok[-1] = True
    ready = graph.ready(ok)
    excluded = np.zeros(len(lay.op), dtype=bool)  # reserved actions
    for action in reserved:
        for other in graph.agents:
            index = graph.key_hyperarcs.get((action, other.name))
            if index is not None:
                excluded[index] = True
    keys = [k for k in early if k[1] in free]
    counts = tl.op_start[ready + 1] - tl.op_start[ready]
    offsets = np.repeat(tl.op_start[ready] - np.cumsum(counts) + counts, counts) + np.arange(counts.sum())
    hyperarcs = tl.op_perm[offsets]
    ops = np.repeat(ready, counts)
    keep = free_ids[lay.agent[hyperarcs]] & np.isfinite(state.cost[hyperarcs]) & ~excluded[hyperarcs]
    for key in keys:  # an early key's hyper-arcs start early (below) where a child holds the moving part
        index = graph.key_hyperarcs.get(key)
        if index is None:
            continue
        bit = graph.part_bit(early[key])
        for i in np.flatnonzero(np.isin(hyperarcs, index)).tolist():
            if any(graph.node_masks[c] & bit for c in graph.op_children[int(ops[i])]):
                keep[i] = False
    hyperarcs, ops = hyperarcs[keep], ops[keep]
    parts: list = [None] * len(hyperarcs)
    if keys:
        commit_ok = np.zeros(graph.n_nodes + 1, dtype=bool)
        commit_ok[state.commit_nodes] = True
        commit_ok &= ~state.held
        commit_ok[-1] = True
        extra_h, extra_op = [], []
        for key in keys:
            action, part = key[0], early[key]
            if action in reserved or action not in tl.action_ops:
                continue
            bit = graph.part_bit(part)
            mine = set(graph.key_hyperarcs.get(key, np.zeros(0, np.int64)).tolist())
            for op in tl.action_ops[action].tolist():
                children = graph.op_children[op]
                moving = [c for c in children if graph.node_masks[c] & bit]
                if not moving or not ok[moving[0]] or not commit_ok[tl.op_children[op]].all():
                    continue
                for h in tl.hyperarcs(op).tolist():
                    if h in mine and np.isfinite(state.cost[h]):
                        extra_h.append(h)
                        extra_op.append(op)
                        parts.append(part)
        hyperarcs = np.concatenate([hyperarcs, np.array(extra_h, dtype=np.int64)])
        ops = np.concatenate([ops, np.array(extra_op, dtype=np.int64)])
    return hyperarcs, ops, parts


def _pick(graph: CompiledGraph, state: _State, free: Sequence[str], early, reserved, margin: float | None,
          outside: np.ndarray) -> list[TeamStep]:
    hyperarcs, ops, parts = _candidates(graph, state, free, early, reserved)
    if not len(hyperarcs):
        return []
    lay = graph.layout
    through = state.totals[hyperarcs] + outside[lay.father[hyperarcs]]
    rank = np.full(len(graph.agents), len(graph.agents))
    rank[[graph.agent_index[a] for a in free]] = np.arange(len(free))
    agents = lay.agent[hyperarcs]
    best = float(state.value[graph.root])
    limit = np.inf if margin is None else best + margin - bottom_up.tolerance(best)
    order = np.lexsort((ops, rank[agents], through))
    order = order[np.isfinite(through[order]) & (through[order] < limit)]
    used_agents: set[int] = set()
    used_nodes: set[int] = set()
    picks: list[TeamStep] = []
    n_free = len(free)
    op_children, masks = graph.op_children, graph.node_masks
    for i, agent, op in zip(order.tolist(), agents[order].tolist(), ops[order].tolist(), strict=True):
        if agent in used_agents:
            continue
        part = parts[i]
        children = op_children[op]
        if part is not None:
            bit = graph.part_bit(part)
            children = tuple(c for c in children if masks[c] & bit)
        if not used_nodes.isdisjoint(children):
            continue
        used_agents.add(agent)
        used_nodes.update(children)
        operation = graph.operations[op]
        h = int(hyperarcs[i])
        picks.append(TeamStep(operation.name, operation.action, graph.agents[agent].name,
                              float(state.cost[h]), float(through[i]), early=part is not None, part=part))
        if len(used_agents) == n_free:
            break
    return picks


def team_assign(
    graph: CompiledGraph,
    *,
    idle: Sequence[str],
    done: Iterable[str] = (),
    running: Iterable[str] = (),
    reserved: Mapping[str, tuple[str, str]] | None = None,
    costs: Mapping[tuple[str, str], float] | None = None,
    pruned: Iterable[tuple[str, str]] = (),
    added: Mapping[tuple[str, str], float] | None = None,
    early: Mapping[tuple[str, str], str] | None = None,
    margin: float | None = None,
) -> TeamAssignment:
    """The operations the ``idle`` agents (in tie-breaking order) start now; see the module docstring.

    Args:
        done: operations finished; ``running``: operations in progress (they hold all their children).
        reserved: action -> (agent, moving part) of early hyper-arcs in progress.
        costs, pruned, added: as :meth:`~ergosim.planner.graph.AndOrGraph.plan`.
        early: (action, agent) -> moving part: hyper-arcs that start early and hold only that part's child.
        margin: skip a candidate whose J(h) is at least this much above the optimum J* (None: never).

    Raises:
        InfeasiblePlanError: the assembly cannot be finished with the running and reserved operations.
        ConfigError: unknown agents, operations or parts.
    """
    for a in idle:
        if a not in graph.agent_index:
            raise ConfigError(f"unknown agent {a!r}; agents are {list(graph.agent_index)}", where="idle")
    done, running = list(done), list(running)
    reserved = dict(reserved or {})
    early = dict(early or {})
    moving: dict[str, str] = {}
    for (action, agent), part in early.items():
        if agent not in graph.agent_index or part not in graph.part_index:
            raise ConfigError(f"early hyper-arc ({action!r}, {agent!r}) names an unknown agent or part "
                              f"{part!r}", where="early")
        if moving.setdefault(action, part) != part:  # a reservation is keyed by its action
            raise ConfigError(f"early hyper-arcs of action {action!r} move {moving[action]!r} and {part!r}; "
                              "an action hands over one part", where="early")
    state = _evaluate(graph, done, running, reserved, _costs(graph, done, reserved, costs, pruned, added))
    optimum = float(state.value[graph.root])
    free = list(idle)
    steps: list[TeamStep] = []
    while free:
        picks = _pick(graph, state, free, early, reserved, margin,
                      outside_costs(graph, state.value, state.cost))
        if not picks:
            break
        # a round of several picks, each priced alone, must leave the assembly feasible together
        while True:
            run = running + [p.operation for p in picks if not p.early]
            res = {**reserved, **{p.action: (p.agent, p.part) for p in picks if p.early}}
            more = [a for a in free if a not in {p.agent for p in picks}]
            if len(picks) == 1 and not (more and any(k[1] in more for k in early)):
                break
            try:
                cost = state.cost if len(res) == len(reserved) else _costs(graph, done, res, costs,
                                                                                   pruned, added)
                state = _evaluate(graph, done, run, res, cost)
                break
            except InfeasiblePlanError:
                picks = picks[:-1]  # the first pick alone is feasible: J(h) is finite
                if not picks:  # ... but not with its reservation (an action of several operations)
                    break
        if not picks:
            break
        steps += picks
        running, reserved, free = run, res, more
        if not (free and any(k[1] in free for k in early)):
            break
    return TeamAssignment(tuple(steps), optimum)
