"""The inputs of one replanning call: the current configuration Θ and the hyper-arc cost vector.

These are the only per-call allocations of the fast planner besides its level passes: one copy of the
fixed costs (n_hyperarcs,) with the overrides written into it through index arrays built once.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping

import numpy as np

from ergosim.errors import ConfigError
from ergosim.planner.agents import COST_MAX
from ergosim.planner.compiled import CompiledGraph
from ergosim.planner.validation import format_parts

__all__ = ["configuration", "hyperarc_costs"]

_EMPTY = np.zeros(0, dtype=np.int64)


def configuration(graph: CompiledGraph, done: Iterable[str]) -> np.ndarray:
    """Node indices (ascending) of the sub-assemblies of Θ after the operations ``done``.

    Θ starts as the parts (Θ_i); each done operation replaces its children by its father. The
    operations may be given in any order: they are applied smallest father first, which is a valid
    order whenever one exists.
    """
    if isinstance(done, str):
        raise ConfigError(
            f"done must be a sequence of operation names, not the string {done!r}", where="done"
        )
    indices = []
    for name in done:
        index = graph.op_index.get(name)
        if index is None:
            raise ConfigError(f"unknown operation {name!r} in task {graph.name!r}", where="done")
        if index in indices:
            raise ConfigError(f"operation {name!r} is listed twice", where="done")
        indices.append(index)
    current = set(graph.leaves)
    masks = graph.node_masks
    for index in sorted(indices, key=lambda i: (masks[graph.op_father[i]].bit_count(), i)):
        for child in graph.op_children[index]:
            if child not in current:
                op = graph.operations[index]
                raise ConfigError(
                    f"operation {op.name!r} cannot have been done: its child "
                    f"{format_parts(graph.node_parts(child))} is not a separate sub-assembly after the "
                    "other done operations",
                    where="done",
                )
            current.remove(child)
        current.add(graph.op_father[index])
    return np.array(sorted(current), dtype=np.int64)


def _key_indices(graph: CompiledGraph, key: tuple[str, str], where: str) -> np.ndarray:
    if not (isinstance(key, tuple) and len(key) == 2):
        raise ConfigError(f"keys are (action, agent) pairs, got {key!r}", where=where)
    found = graph.key_hyperarcs.get(key)
    if found is not None:
        return found
    action, agent = key
    if action not in graph.actions:
        raise ConfigError(f"unknown action {action!r}; actions are {list(graph.actions)}", where=where)
    if agent not in graph.agent_index:
        raise ConfigError(f"unknown agent {agent!r}; agents are {list(graph.agent_index)}", where=where)
    return _EMPTY  # a known agent that may not do this action: nothing to override


def _number(key: tuple[str, str], value: object, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise ConfigError(f"cost of {key!r} must be a number, got {value!r}", where=where)
    number = float(value)
    if not (math.isfinite(number) and 0.0 <= number <= COST_MAX):
        raise ConfigError(f"cost of {key!r} must be finite, >= 0 and <= {COST_MAX:g}, got {value!r}",
                          where=where)
    return number


def hyperarc_costs(
    graph: CompiledGraph,
    costs: Mapping[tuple[str, str], float] | None,
    pruned: Iterable[tuple[str, str]],
    added: Mapping[tuple[str, str], float] | None = None,
) -> np.ndarray:
    """(n_hyperarcs,) costs for this call: fixed costs, overridden by ``costs``, plus ``added`` (e.g. a time
    term), +inf where ``pruned``."""
    cost = graph.layout.cost.copy()
    if costs:
        for key, value in costs.items():
            cost[_key_indices(graph, key, "costs")] = _number(key, value, "costs")
    if added:
        for key, value in added.items():
            index = _key_indices(graph, key, "added")
            cost[index] = np.minimum(cost[index] + _number(key, value, "added"), COST_MAX)
    for key in pruned:
        cost[_key_indices(graph, key, "pruned")] = np.inf
    return cost
