"""AND/OR graph model: counts, the corner-joint tasks, replanning calls, overrides, pruning, ties."""

from __future__ import annotations

import math
from itertools import permutations

import numpy as np
import pytest

import ergosim.planner as planner
from ergosim.errors import ConfigError, InfeasiblePlanError
from ergosim.planner import (
    Agent,
    AndOrGraph,
    Operation,
    PlanStep,
    bundled_task,
    generate_task,
    replan_until_done,
)


@pytest.fixture(scope="module")
def multi():
    return bundled_task("corner-joint:multi-subject")


@pytest.fixture(scope="module")
def kwear():
    return bundled_task("corner-joint:kwear-validation")


def test_public_api_names_exist():
    for name in planner.__all__:
        assert hasattr(planner, name), name


@pytest.mark.parametrize("n", [2, 3, 5, 10, 20])
@pytest.mark.parametrize("agents", [1, 2, 7])
def test_sequential_counts_follow_the_chain(n, agents):
    g = generate_task(f"sequential:{n}", agents=agents, seed=0)
    assert g.n_nodes == n * (n + 1) // 2  # every interval of the chain
    assert len(g.operations) == math.comb(n + 1, 3)  # every cut of every interval
    assert g.n_hyperarcs == agents * math.comb(n + 1, 3)


@pytest.mark.parametrize("n", [2, 3, 10, 20])
def test_scarce_counts(n):
    g = generate_task(f"scarce:{n}", agents=2, seed=0)
    assert (g.n_nodes, g.n_hyperarcs) == (2 * n - 1, 2 * (n - 1))


def test_paper_sizes_for_twenty_pieces():
    sequential, scarce = generate_task("sequential:20", agents=2), generate_task("scarce:20", agents=2)
    assert (sequential.n_nodes, sequential.n_hyperarcs) == (210, 2660)
    assert (scarce.n_nodes, scarce.n_hyperarcs) == (39, 38)


def test_generated_agents_and_costs_are_seeded():
    g = generate_task("sequential:6", agents=3, seed=4)
    assert [(a.name, a.kind) for a in g.agents] == [
        ("human", "human"),
        ("robot1", "robot"),
        ("robot2", "robot"),
    ]
    costs = np.array([op.costs for op in g.operations])
    assert costs.shape == (35, 3) and costs.min() >= 0.0 and costs.max() < 1.0
    np.testing.assert_array_equal(costs.ravel(), np.random.default_rng(4).random(35 * 3))
    again = generate_task("sequential:6", agents=3, seed=4)
    assert again.plan() == g.plan()
    assert generate_task("sequential:6", agents=3, seed=5).plan().cost != g.plan().cost


@pytest.mark.parametrize("spec", ["chain:4", "sequential:1", "sequential:x", "scarce"])
def test_bad_generator_specs(spec):
    with pytest.raises(ConfigError, match="sequential:N or scarce:N"):
        generate_task(spec)


def test_multi_subject_structure(multi):
    assert multi.actions == ("a1", "a2", "a3", "a4", "a5")
    assert [(a.name, a.kind, a.cost) for a in multi.agents] == [
        ("human", "human", 1.0),
        ("robot", "robot", 2.5),
    ]
    handover = multi.operation("handover")
    assert handover.agents == ("human",) and handover.father == multi.parts
    # a1 first, then a2..a4 in any order, a5 last: walk every order through `done`
    for op in multi.operations:  # precedence: nothing goes into J before J is in the area
        assert op.action == "a1" or "area" in op.father
    assert [op.father for op in multi.operations if op.action == "a1"] == [("area", "J")]
    for middle in permutations(("a2", "a3", "a4")):
        done = [_doable(multi, [], "a1")]
        for action in middle:
            done.append(_doable(multi, done, action))
            assert multi.plan(done=done).next.action in (set(middle[len(done) - 1 :]) or {"a5"})
        last = multi.plan(done=done).next
        assert (last.action, last.agent) == ("a5", "human")
        assert multi.plan(done=done + [last.operation]).next is None


def _doable(g, done, action):
    """The operation of ``action`` whose children are all separate in the configuration after ``done``."""
    config = set(g.configuration(done))
    found = [op.name for op in g.operations if op.action == action and set(op.children) <= config]
    assert len(found) == 1, (action, done, found)
    return found[0]


def test_multi_subject_a5_is_human_only(multi):
    costs = {("a5", "human"): 100.0}
    plan = multi.plan(costs=costs)
    assert plan.steps[-1] == PlanStep("handover", "a5", "human", 100.0)
    with pytest.raises(
        InfeasiblePlanError, match=r"no feasible plan: every agent allowed to do operation 'handover'"
    ):
        multi.plan(pruned={("a5", "human")})


def test_kwear_validation_is_a_fixed_sequence(kwear):
    assert kwear.n_nodes == 11 and len(kwear.operations) == 5 and kwear.n_hyperarcs == 10
    steps = kwear.plan().steps
    assert [s.action for s in steps] == ["a1", "a2", "a3", "a4", "a5"]
    assert {s.agent for s in steps} == {"human"}  # human 1 < robot 50
    plan = kwear.plan(costs={("a2", "human"): 100.8})  # eq. 2: V >= V_th adds Gamma = 100
    assert [s.agent for s in plan.steps] == ["human", "robot", "human", "human", "human"]
    assert plan.cost == pytest.approx(4 * 1.0 + 50.0)


def test_replanning_from_done_operations(multi):
    full = multi.plan()
    done = [full.steps[0].operation, full.steps[1].operation]
    later = multi.plan(done=done)
    assert later.steps == full.steps[2:]
    assert later.cost == pytest.approx(full.cost - 2.0)
    assert multi.configuration(done) == (("S1",), ("S2",), ("away",), ("area", "J", "L"))
    assert multi.configuration(reversed(done)) == multi.configuration(done)  # any order


def test_costs_override_every_operation_of_an_action():
    g = generate_task("sequential:6", agents=2, seed=1)
    plan = g.plan(costs={(a, "human"): 0.0 for a in g.actions})
    assert plan.cost == 0.0 and {s.agent for s in plan.steps} == {"human"}
    plan = g.plan(pruned={(a, "human") for a in g.actions})
    assert {s.agent for s in plan.steps} == {"robot1"}
    # a pruned pair wins over its override, and the graph is unchanged afterwards
    assert g.plan(costs={("l1", "human"): 0.0}, pruned={("l1", "human")}).cost >= g.plan().cost - 1e-12
    assert g.plan() == generate_task("sequential:6", agents=2, seed=1).plan()


def test_ties_break_on_agent_then_operation_order():
    parts = ["A", "B", "C"]
    agents = [Agent("h", "human"), Agent("r", "robot")]
    ops = [
        Operation("x", "x", ("A", "B", "C"), (("A",), ("B", "C")), ("r", "h"), (1.0, 1.0)),
        Operation("y", "y", ("A", "B", "C"), (("A", "B"), ("C",)), ("h", "r"), (1.0, 1.0)),
        Operation("bc", "bc", ("B", "C"), (("B",), ("C",)), ("h", "r"), (1.0, 1.0)),
        Operation("ab", "ab", ("A", "B"), (("A",), ("B",)), ("h", "r"), (1.0, 1.0)),
    ]
    g = AndOrGraph("ties", parts, agents, ops)
    for name in ("fast", "paper"):
        plan = g.plan(planner=name)
        assert plan.cost == 2.0
        assert [(s.operation, s.agent) for s in plan.steps] == [("bc", "h"), ("x", "h")]
    # within the float tolerance, still a tie
    assert [(s.operation, s.agent) for s in g.plan(costs={("x", "h"): 1.0 + 1e-12}).steps] == [
        ("bc", "h"),
        ("x", "h"),
    ]
    assert [(s.operation, s.agent) for s in g.plan(costs={("x", "h"): 1.0 + 1e-6}).steps] == [
        ("ab", "h"),
        ("y", "h"),
    ]


def test_execution_order_is_by_operation_order():
    parts = ("A", "B", "C", "D")
    agents = [Agent("h", "human")]

    def op(name, *children, cost=1.0):
        father = tuple(p for p in parts if any(p in c for c in children))
        return Operation(name, name, father, children, ("h",), (cost,))

    ops = [
        op("root", ("A", "B"), ("C", "D"), cost=0.0),  # the balanced tree is the only optimum
        op("root2", ("A",), ("B", "C", "D")),
        op("bcd", ("B",), ("C", "D")),
        op("cd", ("C",), ("D",)),
        op("ab", ("A",), ("B",)),
    ]
    g = AndOrGraph("order", parts, agents, ops)
    for name in ("fast", "paper"):
        plan = g.plan(planner=name)
        # "cd" and "ab" are both ready at the start; "cd" comes first in the operation order
        assert [s.operation for s in plan.steps] == ["cd", "ab", "root"]
        assert plan.next == plan.steps[0] and plan.cost == 2.0
    assert [s.operation for s in g.plan(done=["cd"]).steps] == ["ab", "root"]


def test_plan_call_errors(multi):
    with pytest.raises(ConfigError, match="unknown operation 'nope'"):
        multi.plan(done=["nope"])
    with pytest.raises(ConfigError, match="listed twice"):
        multi.plan(done=["area+J", "area+J"])
    with pytest.raises(ConfigError, match="cannot have been done"):
        multi.plan(done=["handover"])
    with pytest.raises(ConfigError, match="unknown action 'a9'"):
        multi.plan(costs={("a9", "human"): 1.0})
    with pytest.raises(ConfigError, match="unknown agent 'cobot'"):
        multi.plan(pruned={("a1", "cobot")})
    with pytest.raises(ConfigError, match="pairs"):
        multi.plan(pruned=("a1", "robot"))
    for bad in (-1.0, math.inf, math.nan):
        with pytest.raises(ConfigError, match="must be finite, >= 0"):
            multi.plan(costs={("a1", "human"): bad})
    with pytest.raises(ConfigError, match="unknown planner"):
        multi.plan(planner="astar")
    # robot may not do a5: overriding its cost is allowed and changes nothing
    assert multi.plan(costs={("a5", "robot"): 0.0}) == multi.plan()


def test_infeasible_after_pruning_names_the_reason():
    g = generate_task("scarce:4", agents=2, seed=0)
    with pytest.raises(InfeasiblePlanError) as err:
        g.plan(pruned={("l2", "human"), ("l2", "robot1")})
    assert "no feasible plan: every agent allowed to do operation 'p1-p2+p3' (action 'l2') is pruned" in str(
        err.value
    )


def test_complete_assembly_has_no_next(kwear):
    done = [s.operation for s in kwear.plan().steps]
    plan = kwear.plan(done=done)
    assert plan.next is None and plan.steps == () and plan.cost == 0.0


def test_algorithm_2_replans_after_every_action(kwear):
    seen = []

    def update(done):
        seen.append(done)
        # the human is worn out after two actions: eq. 2 adds Gamma from then on
        return {(a, "human"): (1.0 if len(done) < 2 else 101.0) for a in kwear.actions}, ()

    steps = replan_until_done(kwear, update, planner="paper")
    assert [(s.action, s.agent) for s in steps] == [
        ("a1", "human"),
        ("a2", "human"),
        ("a3", "robot"),
        ("a4", "robot"),
        ("a5", "robot"),
    ]
    assert [len(d) for d in seen] == [0, 1, 2, 3, 4, 5]
