"""Team decisions: outside costs against a brute force over every plan, and team_assign's invariants."""

from __future__ import annotations

import math

import pytest
from aog_strategies import calls, explicit_graphs, liaison_graphs
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_planner_search import every_plan

from ergosim.errors import ConfigError, InfeasiblePlanError
from ergosim.planner import bottom_up, bundled_task, generate_task
from ergosim.planner.call_inputs import configuration, hyperarc_costs
from ergosim.planner.outside import outside_costs, through_costs
from ergosim.planner.team import team_assign

SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _through_by_key(graph, done, costs, pruned):
    """(operation, agent) -> J(h) from the outside pass, and J*."""
    config = configuration(graph, done)
    cost = hyperarc_costs(graph, costs, pruned)
    value, totals = bottom_up.node_costs(graph, config, cost)
    j = through_costs(graph, totals, outside_costs(graph, value, cost))
    lay = graph.layout
    keys = {(graph.operations[int(o)].name, graph.agents[int(a)].name): float(x)
            for o, a, x in zip(lay.op, lay.agent, j, strict=True)}
    return keys, float(value[graph.root])


def check_through(graph, done, costs, pruned):
    plans = every_plan(graph, done, costs, pruned)
    through, best = _through_by_key(graph, done, costs, pruned)
    for key, j in through.items():
        containing = [c for c, steps in plans if key in steps]
        if containing:
            assert j == pytest.approx(min(containing), rel=1e-9, abs=1e-9), key
        else:
            assert math.isinf(j), key
    if plans:
        assert best == pytest.approx(min(c for c, _ in plans), rel=1e-9, abs=1e-9)
    if any(steps for _, steps in plans):  # some step is left: the optimal plan goes through a hyper-arc
        assert min(through.values()) == pytest.approx(best, rel=1e-9, abs=1e-9)


@SETTINGS
@given(st.data())
def test_outside_costs_match_brute_force_on_random_graphs(data):
    graph = data.draw(explicit_graphs())
    check_through(graph, *data.draw(calls(graph)))


@SETTINGS
@given(st.data())
def test_outside_costs_match_brute_force_on_random_liaison_graphs(data):
    graph = data.draw(liaison_graphs())
    check_through(graph, *data.draw(calls(graph)))


def check_assignment(graph, done, costs, pruned, idle):
    try:
        out = team_assign(graph, idle=idle, done=done, costs=costs, pruned=pruned)
    except InfeasiblePlanError:
        with pytest.raises(InfeasiblePlanError):
            graph.plan(done=done, costs=costs, pruned=pruned)
        return
    plan = graph.plan(done=done, costs=costs, pruned=pruned)
    tol = 2 * bottom_up.tolerance(plan.cost)  # plans within the planner's tie tolerance are equally optimal
    assert out.cost == pytest.approx(plan.cost, abs=tol)
    config = set(graph.configuration(done))
    agents = [s.agent for s in out.steps]
    assert len(agents) == len(set(agents)) and set(agents) <= set(idle)
    claimed = [c for s in out.steps for c in graph.operation(s.operation).children]
    assert len(claimed) == len(set(claimed)), "a sub-assembly is held by two agents"
    assert set(claimed) <= config, "an operation started before its children exist"
    for s in out.steps:
        assert (s.action, s.agent) not in pruned
    if plan.steps and plan.next.agent in idle:
        assert out.steps, "an idle agent was not given the optimal plan's next step"
        assert out.steps[0].through == pytest.approx(plan.cost, abs=tol)
    # the picks together still leave a feasible plan
    graph.plan(done=list(done) + [s.operation for s in out.steps], costs=costs, pruned=pruned)


@SETTINGS
@given(st.data())
def test_team_assign_invariants_on_random_graphs(data):
    graph = data.draw(explicit_graphs())
    names = [a.name for a in graph.agents]
    idle = data.draw(st.lists(st.sampled_from(names), min_size=1, unique=True))
    check_assignment(graph, *data.draw(calls(graph)), idle)


@SETTINGS
@given(st.data())
def test_team_assign_invariants_on_random_liaison_graphs(data):
    graph = data.draw(liaison_graphs())
    check_assignment(graph, *data.draw(calls(graph)), ["human", "robot"])


def test_two_sub_assemblies_start_together_in_the_gearbox():
    graph = bundled_task("gearbox")
    out = team_assign(graph, idle=["human", "robot"])
    assert [(s.action, s.agent) for s in out.steps] == [("g1", "human"), ("g3", "robot")]


def test_running_operations_hold_their_children():
    graph = bundled_task("gearbox")
    out = team_assign(graph, idle=["robot"], running=["fixture+housing"])
    assert [s.action for s in out.steps] == ["g3"]  # g2 needs the housing the worker is placing


def test_early_hyperarc_fetches_while_the_host_is_being_made():
    graph = bundled_task("corner-joint:multi-subject")
    early = {(a, "robot"): p for a, p in (("a1", "J"), ("a2", "L"), ("a3", "S1"), ("a4", "S2"))}
    out = team_assign(graph, idle=["human", "robot"], early=early)
    first, second = out.steps
    assert (first.action, first.agent, first.early) == ("a1", "human", False)
    assert second.agent == "robot" and second.early and second.action in ("a2", "a3", "a4")
    # while the robot fetches, the worker may insert another profile into J: J is not held
    reserved = {second.action: ("robot", second.part)}
    later = team_assign(graph, idle=["human"], done=["area+J"], reserved=reserved, early=early)
    assert later.steps and later.steps[0].action not in (second.action, "a5")


def test_margin_keeps_an_agent_waiting_for_the_planned_one():
    graph = bundled_task("corner-joint:multi-subject")
    costs = {("a1", "human"): 0.5, ("a1", "robot"): 200.0}
    assert not team_assign(graph, idle=["robot"], costs=costs, margin=100.0).steps
    assert team_assign(graph, idle=["robot"], costs=costs).steps[0].agent == "robot"


def test_thirty_agents_share_a_long_chain_without_overlap():
    graph = generate_task("sequential:12", agents=30, seed=1)
    idle = [a.name for a in graph.agents]
    out = team_assign(graph, idle=idle)
    claimed = [c for s in out.steps for c in graph.operation(s.operation).children]
    assert len(claimed) == len(set(claimed))
    assert 4 <= len(out.steps) <= 6  # a maximal set of disjoint neighbour pairs along 12 parts


def test_unknown_names_are_config_errors():
    graph = bundled_task("gearbox")
    with pytest.raises(ConfigError, match="unknown agent"):
        team_assign(graph, idle=["nobody"])
    with pytest.raises(ConfigError, match="unknown agent or part"):
        team_assign(graph, idle=["robot"], early={("g2", "robot"): "nothing"})
    parts = graph.parts[:2]
    with pytest.raises(ConfigError, match="an action hands over one part"):
        team_assign(graph, idle=["robot"], early={("g2", "robot"): parts[0], ("g2", "human"): parts[1]})


def test_added_costs_shift_the_plan():
    graph = bundled_task("gearbox")
    base = graph.plan()
    timed = graph.plan(added={(a, "robot"): 10.0 for a in graph.actions})
    assert all(s.agent == "human" for s in timed.steps)
    assert timed.cost == pytest.approx(base.cost) if all(s.agent == "human" for s in base.steps) else True
    with pytest.raises(ConfigError, match="added"):
        graph.plan(added={("g2", "robot"): -1.0})
