"""Planners against each other and against a brute force over every complete plan, on random AOGs."""

from __future__ import annotations

import itertools
import math

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from ergosim.errors import InfeasiblePlanError
from ergosim.planner import Agent, AndOrGraph, Operation, generate_task
from ergosim.planner.liaisons import Liaison, generate_operations

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


def effective_cost(graph, op, agent, costs, pruned):
    if (op.action, agent) in pruned:
        return math.inf
    return costs.get((op.action, agent), op.cost_of(agent))


def every_plan(graph, done, costs, pruned):
    """Brute force: every complete plan tree from the configuration after ``done``, as (cost, steps)."""
    config = set(graph.configuration(done))
    by_father = {}
    for op in graph.operations:
        by_father.setdefault(op.father, []).append(op)

    def trees(node):
        if node in config:
            return [(0.0, frozenset())]
        out = []
        for op in by_father.get(node, ()):
            for agent in op.agents:
                c = effective_cost(graph, op, agent, costs, pruned)
                if math.isinf(c):
                    continue
                for combo in itertools.product(*(trees(child) for child in op.children)):
                    out.append(
                        (
                            c + sum(t[0] for t in combo),
                            frozenset().union(*(t[1] for t in combo)) | {(op.name, agent)},
                        )
                    )
        return out

    return trees(graph.parts)


def check_plan(graph, plan, done, costs, pruned):
    """The steps run in order from the current configuration to the full assembly at the stated costs."""
    config = set(graph.configuration(done))
    for step in plan.steps:
        op = graph.operation(step.operation)
        assert op.action == step.action and set(op.children) <= config
        assert step.cost == effective_cost(graph, op, step.agent, costs, pruned)
        config = (config - set(op.children)) | {op.father}
    assert config == {graph.parts}
    assert plan.cost == math.fsum(s.cost for s in plan.steps)


def compare(graph, done, costs, pruned):
    plans = every_plan(graph, done, costs, pruned)
    results = {}
    for name in ("fast", "paper"):
        try:
            results[name] = graph.plan(done=done, costs=costs, pruned=pruned, planner=name)
        except InfeasiblePlanError as err:
            assert str(err).count("no feasible plan: ") == 1
            results[name] = None
    if not plans:
        assert results == {"fast": None, "paper": None}
        return
    best = min(c for c, _ in plans)
    for name, plan in results.items():
        assert plan is not None, name
        assert plan.cost == pytest.approx(best, rel=1e-9, abs=1e-9), name
        check_plan(graph, plan, done, costs, pruned)
        assert graph.plan(done=done, costs=costs, pruned=pruned, planner=name) == plan  # deterministic
        assert frozenset((s.operation, s.agent) for s in plan.steps) in {t for _, t in plans}


@SETTINGS
@given(st.data())
def test_planners_match_brute_force_on_random_graphs(data):
    graph = data.draw(explicit_graphs())
    compare(graph, *data.draw(calls(graph)))


@SETTINGS
@given(st.data())
def test_planners_match_brute_force_on_random_liaison_graphs(data):
    graph = data.draw(liaison_graphs())
    compare(graph, *data.draw(calls(graph)))


@pytest.mark.parametrize("spec", ["sequential:7", "scarce:7"])
@pytest.mark.parametrize("agents", [1, 3])
def test_planners_agree_on_generated_tasks(spec, agents):
    for seed in range(3):
        g = generate_task(spec, agents=agents, seed=seed)
        fast, paper = g.plan(planner="fast"), g.plan(planner="paper")
        assert fast.cost == pytest.approx(paper.cost, rel=1e-12)
        assert min(c for c, _ in every_plan(g, (), {}, set())) == pytest.approx(fast.cost, rel=1e-12)
        # replanning after the first step of the plan keeps the rest optimal (Bellman)
        later = g.plan(done=[fast.next.operation], planner="paper")
        assert later.cost == pytest.approx(fast.cost - fast.next.cost, rel=1e-9)


def test_sequential_plan_count_is_catalan():
    # every binary bracketing of a chain is a plan: Catalan(n - 1) trees, times agents^(n - 1)
    g = generate_task("sequential:6", agents=2, seed=0)
    assert len(every_plan(g, (), {}, set())) == math.comb(10, 5) // 6 * 2**5
