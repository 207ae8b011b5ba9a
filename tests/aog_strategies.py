"""Hypothesis strategies for random AND/OR graphs and replanning calls, shared by the planner tests."""

from __future__ import annotations

from hypothesis import HealthCheck, assume, settings
from hypothesis import strategies as st

from ergosim.errors import InfeasiblePlanError
from ergosim.planner import Agent, AndOrGraph, Operation
from ergosim.planner.liaisons import Liaison, generate_operations

__all__ = ["COSTS", "SETTINGS", "explicit_graphs", "liaison_graphs", "calls"]

COSTS = st.one_of(st.sampled_from([0.0, 0.5, 1.0, 1.0, 2.0]), st.floats(0.0, 10.0))
SETTINGS = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _bits(mask):
    return [i for i in range(mask.bit_length()) if mask >> i & 1]


@st.composite
def explicit_graphs(draw):
    """Random AND/OR graphs: each reached node gets 1-3 random splits into 2-3 children."""
    n = draw(st.integers(2, 6))
    parts = [f"P{i}" for i in range(n)]
    agents = [Agent("human", "human")] + [Agent(f"r{k}", "robot") for k in range(1, draw(st.integers(1, 3)))]
    names = [a.name for a in agents]
    ops, seen_splits, stack, reached = [], set(), [(1 << n) - 1], set()
    while stack:
        mask = stack.pop()
        if mask in reached or mask.bit_count() < 2:
            continue
        reached.add(mask)
        members = _bits(mask)
        for split in range(draw(st.integers(1, 3))):
            k = draw(st.integers(2, min(3, len(members))))
            owner = draw(st.lists(st.integers(0, k - 1), min_size=len(members), max_size=len(members)))
            owner[:k] = range(k)  # no empty child
            children = [sum(1 << p for p, o in zip(members, owner, strict=True) if o == c) for c in range(k)]
            if frozenset(children) in seen_splits:
                continue
            seen_splits.add(frozenset(children))
            allowed = [a for a in names if (split == 0 and a == "human") or draw(st.booleans())]
            ops.append(
                Operation(
                    name=f"o{len(ops)}",
                    action=draw(st.sampled_from(["x", "y", "z", f"o{len(ops)}"])),
                    father=tuple(parts[i] for i in members),
                    children=tuple(tuple(parts[i] for i in _bits(c)) for c in children),
                    agents=tuple(allowed),
                    costs=tuple(draw(COSTS) for _ in allowed),
                )
            )
            stack.extend(children)
    try:
        return AndOrGraph("random", parts, agents, ops)
    except InfeasiblePlanError:
        assume(False)


@st.composite
def liaison_graphs(draw):
    """Random connected liaison graphs with random precedence between their actions."""
    n = draw(st.integers(2, 6))
    parts = [f"P{i}" for i in range(n)]
    pairs = [(draw(st.integers(0, i - 1)), i) for i in range(1, n)]  # a random spanning tree
    extra = draw(st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)), max_size=4))
    pairs += [(min(a, b), max(a, b)) for a, b in extra if a != b and (min(a, b), max(a, b)) not in pairs]
    pairs = list(dict.fromkeys(pairs))
    names = ("human", "robot")
    liaisons = [
        Liaison(parts[a], parts[b], f"l{k}", names, (draw(COSTS), draw(COSTS)))
        for k, (a, b) in enumerate(pairs)
    ]
    order = draw(st.permutations(range(len(liaisons))))
    precedence = [
        (f"l{order[i]}", f"l{order[j]}")
        for i, j in draw(
            st.lists(st.tuples(st.integers(0, len(order) - 1), st.integers(0, len(order) - 1)), max_size=3)
        )
        if i < j
    ]
    generated = generate_operations(parts, liaisons, precedence, names)
    try:
        return AndOrGraph(
            "liaisons", parts, [Agent("human", "human"), Agent("robot", "robot")], [o for o, _ in generated]
        )
    except InfeasiblePlanError:
        assume(False)


@st.composite
def calls(draw, graph):
    """A replanning call: a random walk of done operations, random overrides and pruning."""
    done = []
    for _ in range(draw(st.integers(0, len(graph.parts) - 1))):
        config = set(graph.configuration(done))
        doable = [op.name for op in graph.operations if op.name not in done and set(op.children) <= config]
        if not doable:
            break
        done.append(draw(st.sampled_from(doable)))
    keys = [(a, ag.name) for a in graph.actions for ag in graph.agents]
    costs = {k: draw(COSTS) for k in keys if draw(st.booleans())}
    pruned = {k for k in keys if draw(st.integers(0, 5)) == 0}
    return done, costs, pruned
