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
from ergosim.planner.lookahead_team import TeamState, lookahead_team
from ergosim.planner.transitions import transitions
from ergosim.planner.wear_chain import WearModel, next_cost, price_sequence

KW = KWearParams()


def _model(graph, rng, *, robot_cost=2.5, takt=math.inf, takt_weight=0.0, time_weight=0.0, alpha_low=0.6,
           gamma=100.0, v_th=0.8, takes=None, next_weight=0.0):
    names = [a.name for a in graph.agents]
    human = next(a.name for a in graph.agents if a.kind == "human")
    alphas = {a: rng.uniform(alpha_low, 1.0, 5) for a in graph.actions}
    durations = {(a, n): float(rng.uniform(1.0, 20.0)) for a in graph.actions for n in names}
    return WearModel.build(graph.actions, names, human, alphas=alphas, kwear=KW,
                           cost=CostParams(gamma=gamma, v_th=v_th, robot_cost=robot_cost),
                           durations=durations, takt=takt, takt_weight=takt_weight, time_weight=time_weight,
                           takes=takes, next_weight=next_weight,
                           robot_actions=[a for a in graph.actions if rng.random() < 0.8])


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
                   v_th=float(rng.uniform(0.4, 0.85)), next_weight=float(rng.choice([0.0, 1.0])))
    v = rng.uniform(0.0, 0.7, 5)
    elapsed = float(rng.uniform(0.0, 10.0))
    best = _brute_force(graph, model, v, done, pruned, elapsed)
    if not math.isfinite(best):
        with pytest.raises(InfeasiblePlanError):
            lookahead_plan(graph, model, v, done=done, pruned=pruned, elapsed=elapsed)
        return
    exact = lookahead_plan(graph, model, v, done=done, pruned=pruned, elapsed=elapsed,
                           limits=SearchLimits(exact_sequences=10**9, max_expansions=10**7))
    assert exact.exact and exact.cost == pytest.approx(best, rel=1e-9, abs=1e-9)
    steps = [(s.action, s.agent) for s in exact.steps]
    assert price_sequence(model, v, elapsed, steps).total == pytest.approx(exact.cost, rel=1e-9, abs=1e-9)
    assert sum(s.cost for s in exact.steps) <= exact.cost + 1e-9  # the step prices, without the time terms
    for width in (1, 3):
        beam = lookahead_plan(graph, model, v, done=done, pruned=pruned, elapsed=elapsed,
                              limits=SearchLimits(exact_sequences=0, beam_width=width))
        assert beam.cost >= best - 1e-9 * max(1.0, best)
        assert beam.lower_bound <= best + 1e-9 * max(1.0, best)  # the bound holds for every sequence
        assert beam.cost - beam.gap <= best + 1e-9 * max(1.0, best)


@pytest.mark.slow
@SETTINGS
@given(st.data())
def test_exact_search_matches_brute_force_on_random_graphs(data):
    _check(data.draw(explicit_graphs()), data)


@pytest.mark.slow
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
    plan = lookahead_plan(graph, model, v, limits=SearchLimits(exact_sequences=10**9, max_expansions=10**7))
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


def _free_group(order, parts=("L", "S1", "S2")):
    """J into the area, then three free insertions (any order), listed in ``order`` in the file (the parts
    list in ``parts``)."""
    listed = ", ".join(f'"{p}"' for p in ("area", "J", *parts))
    lines = ['name = "free"', f"parts = [{listed}]", "[agents.human]", 'kind = "human"',
             "[agents.robot]", 'kind = "robot"', "[[liaisons]]", 'parts = ["area", "J"]', 'action = "a1"']
    for part in order:
        lines += ["[[liaisons]]", f'parts = ["J", "{part}"]', f'action = "{ACTION_OF[part]}"']
    lines += ["[[precedence]]", 'before = "a1"', 'after = ["a2", "a3", "a4"]']
    return parse_task("\n".join(lines), source="free.toml")


def _free_plan(order, parts=("L", "S1", "S2"), a3=0.95):
    graph = _free_group(order, parts)
    alphas = {"a1": np.full(5, 0.97), "a2": np.full(5, 0.80), "a3": np.full(5, a3), "a4": np.full(5, 0.93)}
    durations = {(a, "human"): 5.0 for a in alphas} | {(a, "robot"): 15.0 for a in alphas}
    durations[("a2", "robot")] = 17.0
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


def test_equal_cost_orders_do_not_follow_the_file():
    """Two actions that both go to the robot cost the same in either order (the worker rests through both):
    the tie is broken by name, not by where the task file lists them."""
    orders = (("L", "S1", "S2"), ("S2", "S1", "L"), ("S1", "L", "S2"))
    plans = {(order, parts): [(s.action, s.agent) for s in _free_plan(order, parts, a3=0.80).steps]
             for order in orders for parts in orders}
    first = plans[orders[0], orders[0]]
    assert all(plan == first for plan in plans.values())
    assert sorted(a for a, agent in first if agent == "robot") == ["a2", "a3"]


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


# -- parallel: schedules ------------------------------------------------------------------------------------
def _schedule_cost(graph, model, team, steps):
    """A scalar list scheduler (the module docstring of lookahead_team, step by step): the cost of a
    priority list of (operation, agent)."""
    human = next(a.name for a in graph.agents if a.kind == "human")
    free = {a.name: team.now for a in graph.agents} | dict(team.free)
    free[human] = max(team.worker_free, team.now)
    ready = {p: team.now for p in graph.parts}
    begun = {p: team.now for p in graph.parts}
    for name, t in team.running.items():
        for p in graph.operation(name).father:
            ready[p] = max(t, team.now)
    v, w_last = np.array(team.v, dtype=float), free[human]
    end = max([team.now, *free.values(), *ready.values()])
    total = 0.0
    for op_name, agent in steps:
        op = graph.operation(op_name)
        a, j = model.action_index[op.action], model.agent_index[agent]
        d = model.duration[a, j]
        reserved = team.reserved.get(op.action) == agent
        take = 0.0 if agent == human else d - model.rest[a, j]
        fetch = 0.0 if reserved else d - take
        if reserved:
            d = take
        t_ready = max(ready[p] for p in op.father)
        if agent == human:
            start = max(free[agent], t_ready)
            v = v * math.exp(-model.rest_rate * max(0.0, start - w_last))
            v = 1.0 - model.alpha[a] * (1.0 - v)
            total += float(model.price(v))
            finish = w_last = free[agent] = start + d
        elif take > 0:
            part = team.moving.get((op.action, agent))
            start = max(free[agent], ready[part] if part else max(begun[p] for p in op.father))
            at = max(start + fetch, free[human], t_ready)
            v = v * math.exp(-model.rest_rate * max(0.0, at - w_last))
            finish = w_last = free[human] = free[agent] = at + take
            total += 0.0 if reserved else float(model.agent_cost[j])
        else:
            start = max(free[agent], t_ready)
            finish = free[agent] = start + d
            total += 0.0 if reserved else float(model.agent_cost[j])
        for p in op.father:
            ready[p], begun[p] = finish, start
        new_end = max(end, finish)
        total += model.takt_weight * (max(0.0, new_end - model.takt) - max(0.0, end - model.takt))
        total += model.time_weight * (new_end - end)
        end = new_end
    return total + float(next_cost(model, v * math.exp(-model.rest_rate * max(0.0, end - w_last))))


def _team_brute_force(graph, model, team, done, pruned):
    view = transitions(graph)
    ops, agents = graph.operations, graph.agents
    best = math.inf
    stack = [(view.start(list(done) + list(team.running)), [])]
    while stack:
        cid, path = stack.pop()
        if view.complete(cid):
            best = min(best, _schedule_cost(graph, model, team, path))
            continue
        s = view.successors(cid)
        for k, j, nxt in zip(s.op.tolist(), s.agent.tolist(), s.next.tolist(), strict=True):
            key = (ops[k].action, agents[j].name)
            holder = team.reserved.get(ops[k].action)
            if (holder is None and key in pruned) or holder not in (None, key[1]):  # a reservation holds
                continue
            stack.append((nxt, path + [(ops[k].name, agents[j].name)]))
    return best


@pytest.mark.slow
@SETTINGS
@given(st.data())
def test_team_search_matches_brute_force_on_random_liaison_graphs(data):
    graph = data.draw(liaison_graphs())
    done, _, pruned = data.draw(calls(graph))
    rng = np.random.default_rng(data.draw(st.integers(0, 2**16)))
    takes = {(a, "robot"): float(rng.uniform(0.5, 3.0)) for a in graph.actions if rng.random() < 0.5}
    model = _model(graph, rng, robot_cost=float(rng.uniform(0.9, 4.0)), takt=float(rng.uniform(5.0, 60.0)),
                   takt_weight=float(rng.choice([0.0, 0.3])), time_weight=float(rng.choice([0.0, 0.05, 0.3])),
                   takes=takes, next_weight=float(rng.choice([0.0, 1.0])))
    now = float(rng.uniform(0.0, 5.0))
    config = set(graph.configuration(done))
    ready = [op for op in graph.operations if op.name not in done and set(op.children) <= config]
    running = {}
    if ready and data.draw(st.booleans()):  # one operation under way, held until its predicted end
        running[data.draw(st.sampled_from(ready)).name] = now + float(rng.uniform(0.0, 4.0))
    made = {graph.operation(o).action for o in done + list(running)}
    reserved = {}
    left = sorted({a for a, agent in takes if a not in made})
    if left and data.draw(st.booleans()):  # a robot fetching a part to hand it over
        reserved[data.draw(st.sampled_from(left))] = "robot"
    moving = {key: data.draw(st.sampled_from(graph.parts)) for key in takes if data.draw(st.booleans())}
    team = TeamState(now, rng.uniform(0.0, 0.6, 5), now + float(rng.choice([0.0, 2.0])),
                     {"robot": now + float(rng.choice([0.0, 3.0]))}, running, reserved, moving)
    best = _team_brute_force(graph, model, team, done, pruned)
    if not math.isfinite(best):
        with pytest.raises(InfeasiblePlanError):
            lookahead_team(graph, model, team, done=done, pruned=pruned)
        return
    got = lookahead_team(graph, model, team, done=done, pruned=pruned, idle=["human", "robot"],
                         limits=SearchLimits(exact_sequences=10**9, max_expansions=10**7))
    assert got.plan.exact and got.plan.cost == pytest.approx(best, rel=1e-9, abs=1e-9)
    beam = lookahead_team(graph, model, team, done=done, pruned=pruned,
                          limits=SearchLimits(exact_sequences=0, beam_width=2))
    assert beam.plan.cost >= best - 1e-9 * max(1.0, best)
    assert beam.plan.lower_bound <= best + 1e-9 * max(1.0, best)
    assert all(s.agent in ("human", "robot") for s in got.starts) and len(got.starts) <= 2
