"""AND/OR graph generation from liaisons and precedence constraints (Homem de Mello & Sanderson).

A liaison is a pair of parts that connect, made by one action. Starting from the full assembly, every
connected sub-assembly is a node, and every split of a node into two connected sub-assemblies that
respects precedence is an operation. The operation *makes* the liaisons its split cuts; it respects
precedence when every liaison that must come before one of them is already inside a child, and none
that must come after one of them is.

Splits are enumerated as the connected part sets S holding the node's first part whose complement is
connected too, growing S one neighbour at a time (each connected set exactly once); a branch stops as
soon as the parts it has excluded from S can no longer end up in one connected complement.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from ergosim.errors import TaskFileError
from ergosim.planner.agents import Operation
from ergosim.planner.limits import MAX_OPERATIONS, check_operation_count

__all__ = ["Liaison", "generate_operations", "child_label", "precedence_masks", "liaison_groups"]


@dataclass(frozen=True)
class Liaison:
    """Parts ``a`` and ``b`` connect through ``action``; ``agents`` may make it at ``costs`` (aligned)."""

    a: str
    b: str
    action: str
    agents: tuple[str, ...]
    costs: tuple[float, ...]


def child_label(parts: Sequence[str], mask: int) -> str:
    """Compact sub-assembly name: parts joined by '-', runs of four or more as 'first..last'."""
    idx = [i for i in range(len(parts)) if mask >> i & 1]
    out, start = [], 0
    while start < len(idx):
        end = start
        while end + 1 < len(idx) and idx[end + 1] == idx[end] + 1:
            end += 1
        if end - start >= 3:
            out.append(f"{parts[idx[start]]}..{parts[idx[end]]}")
        else:
            out.extend(parts[i] for i in idx[start : end + 1])
        start = end + 1
    return "-".join(out)


def precedence_masks(
    liaisons: Sequence[Liaison], precedence: Sequence[tuple[str, str]], where: str
) -> tuple[list[int], list[int]]:
    """Transitively closed (must-precede, must-follow) liaison bit sets for each liaison."""
    n = len(liaisons)
    by_action: dict[str, int] = {}
    for i, liaison in enumerate(liaisons):
        by_action[liaison.action] = by_action.get(liaison.action, 0) | 1 << i
    pred = [0] * n
    for before, after in precedence:
        for j in range(n):
            if by_action[after] >> j & 1:
                pred[j] |= by_action[before]
    for k in range(n):  # Warshall's transitive closure on bit sets
        for j in range(n):
            if pred[j] >> k & 1:
                pred[j] |= pred[k]
    for j in range(n):
        if pred[j] >> j & 1:
            raise TaskFileError(
                f"precedence constraints form a cycle through action {liaisons[j].action!r}", where=where
            )
    succ = [0] * n
    for j in range(n):
        for k in range(n):
            if pred[j] >> k & 1:
                succ[k] |= 1 << j
    return pred, succ


def liaison_groups(parts: Sequence[str], liaisons: Sequence[Liaison]) -> list[list[str]]:
    """The parts grouped into the connected components of the liaison graph, in part order."""
    index = {p: i for i, p in enumerate(parts)}
    adj = [0] * len(parts)
    for liaison in liaisons:
        adj[index[liaison.a]] |= 1 << index[liaison.b]
        adj[index[liaison.b]] |= 1 << index[liaison.a]
    groups, left = [], (1 << len(parts)) - 1
    while left:
        group = _reach(left & -left, left, adj)
        groups.append([p for i, p in enumerate(parts) if group >> i & 1])
        left &= ~group
    return groups


def _reach(start: int, within: int, adj: Sequence[int]) -> int:
    seen = frontier = start
    while frontier:
        low = frontier & -frontier
        frontier ^= low
        new = adj[low.bit_length() - 1] & within & ~seen
        seen |= new
        frontier |= new
    return seen


def _connected(mask: int, adj: Sequence[int]) -> bool:
    return mask != 0 and _reach(mask & -mask, mask, adj) == mask


def _splits(father: int, adj: Sequence[int]) -> list[int]:
    """Connected S ∋ first part of ``father`` with a connected, non-empty complement; in search order (a
    depth-first growth of S, kept on an explicit stack: a chain of a thousand parts is a thousand levels)."""
    found: list[int] = []

    def enter(s: int) -> None:
        rest = father & ~s
        if rest and _connected(rest, adj):
            found.append(s)

    first = father & -father
    enter(first)
    # a frame: [S, candidates left, parts excluded from S, the candidate whose branch is open]
    stack = [[first, adj[first.bit_length() - 1] & father, 0, 0]]
    while stack:
        frame = stack[-1]
        if frame[3]:  # back from the branch that added frame[3]: it stays out of S from now on
            frame[2] |= frame[3]
            frame[3] = 0
        s, candidates, excluded = frame[0], frame[1], frame[2]
        if not candidates:
            stack.pop()
            continue
        v = candidates & -candidates
        frame[1] = candidates ^ v
        s2 = s | v
        if excluded and _reach(excluded & -excluded, father & ~s2, adj) & excluded != excluded:
            frame[2] = excluded | v
            continue
        frame[3] = v
        enter(s2)
        stack.append([s2, (frame[1] | adj[v.bit_length() - 1]) & father & ~s2 & ~excluded, excluded, 0])
    return found


def generate_operations(
    parts: Sequence[str],
    liaisons: Sequence[Liaison],
    precedence: Sequence[tuple[str, str]],
    agent_order: Sequence[str],
    *,
    explicit_children: Mapping[int, Sequence[Sequence[int]]] | None = None,
    where: str = "",
) -> list[tuple[Operation, int]]:
    """Operations generated from the liaisons, each with the index of the first liaison it makes.

    Args:
        parts: part names; bit i of a mask is ``parts[i]``.
        liaisons: the liaisons, resolved to per-agent costs.
        precedence: (action before, action after) pairs over liaison actions.
        agent_order: all agent names, which orders each operation's agents.
        explicit_children: father mask -> child masks of hand-written operations, followed so that
            liaisons also expand the nodes those operations reach (mixed task files).

    Returns:
        Operations in order of their father (size, then parts), then of the split search.
    """
    index = {p: i for i, p in enumerate(parts)}
    adj = [0] * len(parts)
    ends = []
    for liaison in liaisons:
        a, b = index[liaison.a], index[liaison.b]
        adj[a] |= 1 << b
        adj[b] |= 1 << a
        ends.append((1 << a, 1 << b))
    pred, succ = precedence_masks(liaisons, precedence, where)
    constrained = any(pred) or any(succ)
    explicit_children = explicit_children or {}
    root = (1 << len(parts)) - 1
    splits_of: dict[int, list[tuple[int, list[int]]]] = {}
    made = 0  # operations generated so far, bounded by MAX_OPERATIONS
    stack, seen = [root], {root}
    while stack:
        father = stack.pop()
        following = [c for children in explicit_children.get(father, ()) for c in children]
        if father.bit_count() > 1 and _connected(father, adj):
            inside = [k for k, (a, b) in enumerate(ends) if father & a and father & b]
            valid = []
            for s in _splits(father, adj):
                if made + len(valid) >= MAX_OPERATIONS:
                    check_operation_count(made + len(valid) + 1, where or "liaisons", TaskFileError)
                cut = [k for k in inside if bool(s & ends[k][0]) != bool(s & ends[k][1])]
                if constrained and not _respects(cut, inside, pred, succ):
                    continue
                valid.append((s, cut))
                following += [s, father & ~s]
            splits_of[father] = valid
            made += len(valid)
        for child in following:
            if child not in seen:
                seen.add(child)
                stack.append(child)
    out = []
    for father in sorted(
        splits_of, key=lambda m: (m.bit_count(), [i for i in range(len(parts)) if m >> i & 1])
    ):
        for s, cut in splits_of[father]:
            out.append((_operation(parts, liaisons, cut, father, s, agent_order), cut[0]))
    return out


def _respects(cut: list[int], inside: list[int], pred: Sequence[int], succ: Sequence[int]) -> bool:
    """Every predecessor of a cut liaison is already made inside a child; no successor is made yet."""
    made = 0
    for k in inside:
        made |= 1 << k
    now = 0
    for k in cut:
        now |= 1 << k
    made &= ~now
    return not any(pred[k] & ~made or succ[k] & (made | now) for k in cut)


def _operation(
    parts: Sequence[str],
    liaisons: Sequence[Liaison],
    cut: list[int],
    father: int,
    s: int,
    agent_order: Sequence[str],
) -> Operation:
    made = [liaisons[k] for k in cut]
    action = "+".join(dict.fromkeys(liaison.action for liaison in made))
    agents = [a for a in agent_order if all(a in liaison.agents for liaison in made)]
    costs = tuple(sum(liaison.costs[liaison.agents.index(a)] for liaison in made) for a in agents)
    t = father & ~s
    return Operation(
        name=f"{child_label(parts, s)}+{child_label(parts, t)}",
        action=action,
        father=tuple(p for i, p in enumerate(parts) if father >> i & 1),
        children=(
            tuple(p for i, p in enumerate(parts) if s >> i & 1),
            tuple(p for i, p in enumerate(parts) if t >> i & 1),
        ),
        agents=tuple(agents),
        costs=costs,
    )
