"""The tie rule among equal-cost plans: the paper's Algorithm 1 dispatches the costliest ready step first."""

from __future__ import annotations

import numpy as np
import pytest

from ergosim.errors import ConfigError
from ergosim.experiment.scenario import load_scenario
from ergosim.planner import bundled_task, call_inputs, paper_search
from ergosim.planner.tie_break import PAPER_TIE_RULE, TIE_RULES, next_step, optimal_next_steps

FREE = ("a2", "a3", "a4")


@pytest.fixture(scope="module")
def graph():
    return bundled_task("corner-joint:multi-subject")


def _after_a1(graph) -> list[str]:
    return [op.name for op in graph.operations if op.action == "a1"]


def _costs(rng: np.random.Generator) -> dict[tuple[str, str], float]:
    # multiples of 1/8: every sum of them is exact, so no plan's score differs from another's by rounding
    costs = {(a, "human"): float(rng.integers(2, 24)) / 8 for a in FREE}
    costs.update({(a, "robot"): 2.5 for a in FREE})
    costs[("a5", "human")] = float(rng.integers(1, 16)) / 8
    return costs


def test_the_free_actions_are_the_candidates_after_a1(graph):
    done = _after_a1(graph)
    _, steps = optimal_next_steps(graph, done)  # the task file's fixed costs: 1 human, 2.5 robot
    assert [(s.action, s.agent) for s in steps] == [(a, "human") for a in FREE]
    _, first = optimal_next_steps(graph, [])
    assert [s.action for s in first] == ["a1"]


def test_the_papers_search_dispatches_the_costliest_ready_step_first(graph):
    """Algorithm 1's own path, read as Algorithm 2 reads it (the edge next to the goal), against the rule."""
    rng = np.random.default_rng(1)
    done = _after_a1(graph)
    config = call_inputs.configuration(graph, done)
    checked = 0
    for _ in range(120):
        costs = _costs(rng)
        effective = [min(costs[(a, "human")], costs[(a, "robot")]) for a in FREE]
        if len(set(effective)) < len(FREE):
            continue  # an exact tie of step costs: the rule falls back to the task order
        path = paper_search.solve(graph, config, call_inputs.hyperarc_costs(graph, costs, [], None))
        first = graph.operations[int(graph.layout.op[path[0]])].action
        step = next_step(graph, done, costs, planner="paper", rule=PAPER_TIE_RULE)
        assert step.action == first == FREE[int(np.argmax(effective))], costs
        checked += 1
    assert checked > 60


def test_each_rule_orders_the_ready_steps(graph):
    done = _after_a1(graph)
    costs = {("a2", "human"): 1.5, ("a3", "human"): 0.5, ("a4", "human"): 1.0, ("a5", "human"): 0.2}
    costs.update({(a, "robot"): 2.5 for a in FREE})
    picked = {rule: next_step(graph, done, costs, rule=rule).action for rule in TIE_RULES}
    assert picked == {"costliest-first": "a2", "task-order": "a2", "cheapest-first": "a3"}
    costs[("a4", "human")] = 3.0  # above the robot's 2.5: a4 goes to the robot, at 2.5 the costliest step
    step = next_step(graph, done, costs, rule="costliest-first")
    assert (step.action, step.agent) == ("a4", "robot")
    assert next_step(graph, done, costs, rule="task-order").action == "a2"
    costs[("a2", "human")] = costs[("a3", "human")] = 0.5  # an exact tie goes to the task order
    assert next_step(graph, done, costs, rule="cheapest-first").action == "a2"


def test_a_bad_rule_is_one_clear_error(graph):
    with pytest.raises(ConfigError, match="unknown tie rule"):
        next_step(graph, [], rule="first-come")
    with pytest.raises(ConfigError, match="tie_break='first-come' is not one of costliest-first"):
        load_scenario("multi-subject", {"tie_break": "first-come"})
