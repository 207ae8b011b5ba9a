"""The look-ahead planner: the wear chain against KWear itself, the searches against a brute force over
every sequence on random AND/OR graphs, the beam's bound, and the order of the task file."""

from __future__ import annotations

import math

import numpy as np
import pytest
from aog_strategies import SETTINGS, calls, explicit_graphs, liaison_graphs
from hypothesis import given
from hypothesis import strategies as st

from ergosim.ergonomics.cost import CostParams, human_cost
from ergosim.ergonomics.kwear import KWearParams, kwear_step
from ergosim.errors import ConfigError, InfeasiblePlanError
from ergosim.planner import Agent, AndOrGraph, Operation, bundled_task, generate_task, parse_task
from ergosim.planner.lookahead import SearchLimits, lookahead_plan
from ergosim.planner.transitions import transitions
from ergosim.planner.wear_chain import WearModel, price_sequence

KW = KWearParams()


def _model(graph, rng, *, robot_cost=2.5, takt=math.inf, takt_weight=0.0, time_weight=0.0, alpha_low=0.6,
           gamma=100.0, v_th=0.8):
    names = [a.name for a in graph.agents]
    human = next(a.name for a in graph.agents if a.kind == "human")
    alphas = {a: rng.uniform(alpha_low, 1.0, 5) for a in graph.actions}
    durations = {(a, n): float(rng.uniform(1.0, 20.0)) for a in graph.actions for n in names}
    return WearModel.build(graph.actions, names, human, alphas=alphas, kwear=KW,
                           cost=CostParams(gamma=gamma, v_th=v_th, robot_cost=robot_cost),
                           durations=durations, takt=takt, takt_weight=takt_weight, time_weight=time_weight)


def _brute_force(graph, model, v, done, pruned, elapsed):
    """The cheapest sequence over every order of every plan: every path of ready hyper-arcs to the root."""
    view = transitions(graph)
    ops, agents = graph.operations, graph.agents
    best = math.inf
    stack = [(view.start(done), [])]
    while stack:
        cid, path = stack.pop()
        if view.complete(cid):
            best = min(best, price_sequence(model, v, elapsed, path).total)
            continue
        s = view.successors(cid)
        for k, j, nxt in zip(s.op.tolist(), s.agent.tolist(), s.next.tolist(), strict=True):
            key = (ops[k].action, agents[j].name)
            if key not in pruned:
                stack.append((nxt, path + [key]))
    return best


# -- the chain is KWear -------------------------------------------------------------------------------------
def test_chain_equals_kwear_ticks():
    """A worker action with constant G over d seconds and a rest of s seconds, simulated tick by tick with
    kwear_step (eq. 4-5), end at the V the chain predicts (eq. 9 with α = e^{-G d/C}, then eq. 5)."""
    g = np.array([3.0, 1.0, 2.0, 4.0, 1.0])
    d, s, dt = 6.0, 11.0, 0.05
    alpha = np.exp(-g * d / KW.C)
    graph = bundled_task("corner-joint:multi-subject")
    names = [a.name for a in graph.agents]
    model = WearModel.build(graph.actions, names, "human", alphas={a: alpha for a in graph.actions},
                            kwear=KW, cost=CostParams(robot_cost=2.5),
                            durations={("a1", "human"): d, ("a2", "robot"): s})
    v = np.array([0.1, 0.2, 0.0, 0.4, 0.05])
    ticks = v.copy()
    for _ in range(round(d / dt)):
        ticks = kwear_step(ticks, g, dt, KW)
    for _ in range(round(s / dt)):
        ticks = kwear_step(ticks, g, dt, KW, resting=True)
    chain = price_sequence(model, v, 0.0, [("a1", "human"), ("a2", "robot")])
    np.testing.assert_allclose(chain.v_end, ticks, rtol=1e-9, atol=1e-12)
    assert chain.ergonomic == pytest.approx(float(human_cost(chain.v_hat[0], CostParams(robot_cost=2.5))))
    assert chain.robot == 2.5 and chain.end == pytest.approx(d + s)


def test_chain_prices_order_where_the_paper_does_not():
    """Two worker actions: the paper's costs are the same in both orders; the chain's are not, and the
    action that wears more is cheaper last (its V̂ is paid once instead of raising the other's)."""
    graph = AndOrGraph("two", ["A", "B", "C"], [Agent("human", "human")], [
        Operation("AB", "ab", ("A", "B"), (("A",), ("B",)), ("human",), (1.0,)),
        Operation("AB+C", "c", ("A", "B", "C"), (("A", "B"), ("C",)), ("human",), (1.0,)),
        Operation("AC", "c", ("A", "C"), (("A",), ("C",)), ("human",), (1.0,)),
        Operation("AC+B", "ab", ("A", "B", "C"), (("A", "C"), ("B",)), ("human",), (1.0,)),
    ])
    model = WearModel.build(graph.actions, ["human"], "human", kwear=KW, cost=CostParams(robot_cost=2.5),
                            alphas={"ab": np.full(5, 0.7), "c": np.full(5, 0.95)})
    v = np.zeros(5)
    heavy_first = price_sequence(model, v, 0.0, [("ab", "human"), ("c", "human")]).total
    light_first = price_sequence(model, v, 0.0, [("c", "human"), ("ab", "human")]).total
    assert light_first < heavy_first
    plan = lookahead_plan(graph, model, v)
    assert [s.action for s in plan.steps] == ["c", "ab"] and plan.exact
    assert plan.cost == pytest.approx(light_first)


def test_takt_and_time_terms():
    graph = bundled_task("corner-joint:kwear-validation")
    model = _model(graph, np.random.default_rng(3), takt=20.0, takt_weight=0.5, time_weight=0.1)
    steps = [(a, "human") for a in graph.actions]
    p = price_sequence(model, np.zeros(5), 5.0, steps)
    assert p.takt == pytest.approx(0.5 * max(0.0, p.end - 20.0))
    late = price_sequence(model, np.zeros(5), 25.0, steps)  # an overrun already incurred is not the plan's
    assert late.takt == pytest.approx(0.5 * (late.end - 25.0))
    assert p.time == pytest.approx(0.1 * (p.end - 5.0))
    assert p.total == pytest.approx(p.ergonomic + p.robot + p.takt + p.time)


# -- the searches against a brute force -------------------------------------------------------------------
def _check(graph, data):
    done, _, pruned = data.draw(calls(graph))
    seed = data.draw(st.integers(0, 2**16))
    rng = np.random.default_rng(seed)
    model = _model(graph, rng, robot_cost=float(rng.uniform(0.9, 4.0)), takt=float(rng.uniform(5.0, 60.0)),
                   takt_weight=float(rng.choice([0.0, 0.3])), time_weight=float(rng.choice([0.0, 0.05])),
                   v_th=float(rng.uniform(0.4, 0.85)))
    v = rng.uniform(0.0, 0.7, 5)
    elapsed = float(rng.uniform(0.0, 10.0))
    best = _brute_force(graph, model, v, done, pruned, elapsed)
    if not math.isfinite(best):
        with pytest.raises(InfeasiblePlanError):
            lookahead_plan(graph, model, v, done=done, pruned=pruned, elapsed=elapsed)
        return
    exact = lookahead_plan(graph, model, v, done=done, pruned=pruned, elapsed=elapsed,
                           limits=SearchLimits(exact_actions=99, max_expansions=10**7))
    assert exact.exact and exact.cost == pytest.approx(best, rel=1e-9, abs=1e-9)
    steps = [(s.action, s.agent) for s in exact.steps]
    assert price_sequence(model, v, elapsed, steps).total == pytest.approx(exact.cost, rel=1e-9, abs=1e-9)
    assert sum(s.cost for s in exact.steps) <= exact.cost + 1e-9  # the step prices, without the time terms
    for width in (1, 3):
        beam = lookahead_plan(graph, model, v, done=done, pruned=pruned, elapsed=elapsed,
                              limits=SearchLimits(exact_actions=0, beam_width=width))
        assert beam.cost >= best - 1e-9 * max(1.0, best)
        assert beam.lower_bound <= best + 1e-9 * max(1.0, best)  # the bound holds for every sequence
        assert beam.cost - beam.gap <= best + 1e-9 * max(1.0, best)


@SETTINGS
@given(st.data())
def test_exact_search_matches_brute_force_on_random_graphs(data):
    _check(data.draw(explicit_graphs()), data)


@SETTINGS
@given(st.data())
def test_exact_search_matches_brute_force_on_random_liaison_graphs(data):
    _check(data.draw(liaison_graphs()), data)


def test_without_wear_or_recovery_the_optimum_is_the_papers():
    """α = 1 (no wear), no recovery and no time terms: the chain's prices are the paper's order-free
    prices, so the look-ahead's optimum equals AO*'s (bottom-up DP) with the same costs."""
    graph = generate_task("sequential:7", agents=3, seed=2)
    names = [a.name for a in graph.agents]
    rng = np.random.default_rng(4)
    v = rng.uniform(0.0, 0.5, 5)
    model = WearModel.build(graph.actions, names, "human", alphas={a: np.ones(5) for a in graph.actions},
                            kwear=KW, cost=CostParams(robot_cost=2.5),
                            robot_costs={n: float(rng.uniform(0.5, 3.0)) for n in names[1:]})
    costs = {(a, "human"): float(model.price(v)) for a in graph.actions}
    costs |= {(a, n): float(model.agent_cost[j]) for a in graph.actions for j, n in enumerate(names) if j}
    plan = lookahead_plan(graph, model, v, limits=SearchLimits(exact_actions=99, max_expansions=10**7))
    assert plan.exact and plan.cost == pytest.approx(graph.plan(costs=costs).cost, rel=1e-12)


@pytest.mark.parametrize("width", [1, 4, 8])
def test_beam_on_a_large_chain_stays_within_its_reported_gap(width):
    graph = generate_task("sequential:21", agents=2, seed=0)
    model = _model(graph, np.random.default_rng(5), takt=150.0, takt_weight=0.1, alpha_low=0.85)
    plan = lookahead_plan(graph, model, np.full(5, 0.1), limits=SearchLimits(beam_width=width))
    assert not plan.exact and len(plan.steps) == 20
    assert 0.0 < plan.lower_bound <= plan.cost and plan.gap == pytest.approx(plan.cost - plan.lower_bound)
    steps = [(s.action, s.agent) for s in plan.steps]
    assert price_sequence(model, np.full(5, 0.1), 0.0, steps).total == pytest.approx(plan.cost)


# -- the file's order does not decide -----------------------------------------------------------------------
ACTION_OF = {"L": "a2", "S1": "a3", "S2": "a4"}


def _free_group(order):
    """J into the area, then three free insertions (any order), listed in ``order`` in the file."""
    lines = ['name = "free"', 'parts = ["area", "J", "L", "S1", "S2"]', "[agents.human]", 'kind = "human"',
             "[agents.robot]", 'kind = "robot"', "[[liaisons]]", 'parts = ["area", "J"]', 'action = "a1"']
    for part in order:
        lines += ["[[liaisons]]", f'parts = ["J", "{part}"]', f'action = "{ACTION_OF[part]}"']
    lines += ["[[precedence]]", 'before = "a1"', 'after = ["a2", "a3", "a4"]']
    return parse_task("\n".join(lines), source="free.toml")


def _free_plan(order):
    graph = _free_group(order)
    alphas = {"a1": np.full(5, 0.97), "a2": np.full(5, 0.80), "a3": np.full(5, 0.95), "a4": np.full(5, 0.93)}
    durations = {(a, "human"): 5.0 for a in alphas} | {(a, "robot"): 15.0 for a in alphas}
    model = WearModel.build(graph.actions, ["human", "robot"], "human", alphas=alphas, kwear=KW,
                            cost=CostParams(robot_cost=2.5), durations=durations)
    done = [op.name for op in graph.operations if op.action == "a1"]
    return lookahead_plan(graph, model, np.full(5, 0.35), done=done)


def test_the_file_order_does_not_change_the_plan():
    """The insertions listed in any order: the same plan, and the action that wears most is the robot's."""
    plans = [[(s.action, s.agent) for s in _free_plan(order).steps]
             for order in (("L", "S1", "S2"), ("S2", "S1", "L"), ("S1", "L", "S2"))]
    assert plans[0] == plans[1] == plans[2]
    assert ("a2", "robot") in plans[0] and ("a3", "human") in plans[0]


# -- contract ---------------------------------------------------------------------------------------------
def test_errors_and_the_complete_assembly():
    graph = bundled_task("corner-joint:multi-subject")
    model = _model(graph, np.random.default_rng(0))
    with pytest.raises(ConfigError, match="pruned"):
        lookahead_plan(graph, model, np.zeros(5), pruned=[("a9", "robot")])
    with pytest.raises(ConfigError, match="unknown operation"):
        lookahead_plan(graph, model, np.zeros(5), done=["nope"])
    with pytest.raises(InfeasiblePlanError, match="no feasible plan"):
        lookahead_plan(graph, model, np.zeros(5), pruned=[("a1", "human"), ("a1", "robot")])
    done = [s.operation for s in graph.plan().steps]
    assert lookahead_plan(graph, model, np.zeros(5), done=done).next is None
    with pytest.raises(ConfigError, match="beam_width"):
        SearchLimits(beam_width=0)
    other = generate_task("sequential:4", agents=2)
    with pytest.raises(ConfigError, match="wear model has no"):
        lookahead_plan(other, model, np.zeros(5))


def test_action_once_detection():
    assert transitions(bundled_task("gearbox")).action_once
    assert transitions(bundled_task("corner-joint:multi-subject")).action_once
    assert transitions(generate_task("scarce:6", agents=2)).action_once
