"""Planners against each other and against a brute force over every complete plan, on random AOGs."""

from __future__ import annotations

import itertools
import math

import pytest
from aog_strategies import SETTINGS, calls, explicit_graphs, liaison_graphs
from hypothesis import given
from hypothesis import strategies as st

from ergosim.errors import InfeasiblePlanError
from ergosim.planner import generate_task


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


@pytest.mark.slow
@SETTINGS
@given(st.data())
def test_planners_match_brute_force_on_random_graphs(data):
    graph = data.draw(explicit_graphs())
    compare(graph, *data.draw(calls(graph)))


@pytest.mark.slow
@SETTINGS
@given(st.data())
def test_planners_match_brute_force_on_random_liaison_graphs(data):
    graph = data.draw(liaison_graphs())
    compare(graph, *data.draw(calls(graph)))


@pytest.mark.slow
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
