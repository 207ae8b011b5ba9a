"""Structural checks of agents and operations before an AND/OR graph is built from them.

Each check raises :class:`~ergosim.errors.TaskFileError` whose ``where`` names the source and the entry
(``task.toml: operations[2] 'AB'``), so a bad task file gives one clear line.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from ergosim.errors import TaskFileError
from ergosim.planner.agents import AGENT_KINDS, Agent, Operation, check_cost, check_name
from ergosim.planner.limits import check_part_count

__all__ = ["check_parts", "check_agents", "check_operation", "format_parts"]


def format_parts(parts: Sequence[str]) -> str:
    """A sub-assembly as text: ``[A B C]``."""
    return "[" + " ".join(parts) + "]"


def check_parts(parts: Sequence[str], where: str) -> dict[str, int]:
    """Validate the part list; return part name -> index."""
    if not parts:
        raise TaskFileError("a task needs at least one part", where=where)
    check_part_count(len(parts), f"{where} parts", TaskFileError)
    index: dict[str, int] = {}
    for i, part in enumerate(parts):
        problem = check_name(part, "a part name")
        if problem:
            raise TaskFileError(problem, where=f"{where} parts[{i}]")
        if part in index:
            raise TaskFileError(f"duplicate part name {part!r}", where=f"{where} parts[{i}]")
        index[part] = i
    return index


def check_agents(agents: Sequence[Agent], where: str) -> dict[str, int]:
    """Validate the agent list; return agent name -> index."""
    if not agents:
        raise TaskFileError("a task needs at least one agent", where=where)
    index: dict[str, int] = {}
    for i, agent in enumerate(agents):
        at = f"{where} agents.{agent.name}"
        problem = check_name(agent.name, "an agent name") or check_cost(agent.cost, "the agent's cost")
        if problem:
            raise TaskFileError(problem, where=at)
        if agent.kind not in AGENT_KINDS:
            raise TaskFileError(f"agent kind must be 'human' or 'robot', got {agent.kind!r}", where=at)
        if agent.name in index:
            raise TaskFileError(f"duplicate agent name {agent.name!r}", where=at)
        index[agent.name] = i
    return index


def check_operation(
    op: Operation,
    part_index: dict[str, int],
    agent_index: dict[str, int],
    locate: Callable[[str], str],
) -> tuple[int, tuple[int, ...]]:
    """Validate one operation; return (father part mask, child part masks).

    ``locate(name)`` gives the ``where`` text for the operation.
    """
    at = locate(op.name)
    for label, text in (("name", op.name), ("action", op.action)):
        if not isinstance(text, str) or not text.strip() or "," in text or text != text.strip():
            raise TaskFileError(
                f"operation {label} must be a non-empty string without commas or surrounding spaces, "
                f"got {text!r}",
                where=at,
            )
    if len(op.children) < 2:
        raise TaskFileError(f"an operation joins two or more children, got {len(op.children)}", where=at)
    masks = []
    union = 0
    for k, child in enumerate(op.children):
        if not child:
            raise TaskFileError(f"child {k} is empty", where=at)
        mask = 0
        for part in child:
            if part not in part_index:
                raise TaskFileError(
                    f"unknown part {part!r} in child {k}; parts are {list(part_index)}", where=at
                )
            bit = 1 << part_index[part]
            if mask & bit:
                raise TaskFileError(f"part {part!r} appears twice in child {k}", where=at)
            mask |= bit
        if union & mask:
            shared = [p for p in child if union & (1 << part_index[p])]
            raise TaskFileError(
                f"children overlap: part(s) {format_parts(shared)} belong to more than one child", where=at
            )
        union |= mask
        masks.append(mask)
    father = 0
    for part in op.father:
        if part not in part_index:
            raise TaskFileError(f"unknown part {part!r} in the father", where=at)
        father |= 1 << part_index[part]
    if father != union or len(op.father) != union.bit_count():
        order = sorted(part_index, key=part_index.__getitem__)
        expected = [p for p in order if union >> part_index[p] & 1]
        raise TaskFileError(
            f"father {format_parts(op.father)} is not the union of the children {format_parts(expected)}",
            where=at,
        )
    if len(op.costs) != len(op.agents):
        raise TaskFileError(f"{len(op.agents)} agents but {len(op.costs)} costs", where=at)
    seen = set()
    for agent, cost in zip(op.agents, op.costs, strict=True):
        if agent not in agent_index:
            raise TaskFileError(f"unknown agent {agent!r}; agents are {list(agent_index)}", where=at)
        if agent in seen:
            raise TaskFileError(f"agent {agent!r} listed twice", where=at)
        seen.add(agent)
        problem = check_cost(cost, f"the cost for agent {agent!r}")
        if problem:
            raise TaskFileError(problem, where=at)
    return father, tuple(masks)
