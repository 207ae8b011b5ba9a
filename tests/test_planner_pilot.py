"""The beam's estimate (ergosim/planner/pilot.py) against its definition: the cheapest split of a concrete
completion, each split priced step by step."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ergosim.ergonomics.cost import CostParams
from ergosim.ergonomics.kwear import KWearParams
from ergosim.planner import generate_task
from ergosim.planner.chain_pricing import SequentialPricing
from ergosim.planner.pilot import PilotTable
from ergosim.planner.wear_chain import WearModel


def _completion(pr, need, v, t):
    """The module docstring, one split at a time: the r − m needed actions that wear most go to the robots
    (the worker rests over them), then the worker does the m others, least wear first."""
    model = pr.model
    robot_ok = np.isfinite(pr.robot_min)
    wear = (1.0 - pr.alpha).sum(axis=1) + np.where(robot_ok, 0.0, -1e9) + np.where(pr.human_ok, 0.0, 1e9)
    needed = np.flatnonzero(need)
    ranked = needed[np.argsort(wear[needed])]
    best = math.inf
    for m in range(len(ranked) + 1):
        worker, robots = ranked[:m], ranked[m:]
        if not (pr.human_ok[worker].all() and robot_ok[robots].all()):
            continue
        x = v * math.exp(-pr.k * pr.max_rest[robots].sum())
        cost = pr.robot_min[robots].sum()
        unrested = v.copy()
        for a in worker:  # eq. 9 along the chain, priced by eq. 10-11 (Γ on the chain without the rest)
            x = 1.0 - pr.alpha[a] * (1.0 - x)
            unrested = 1.0 - pr.alpha[a] * (1.0 - unrested)
            cost += x.sum() + model.cost.gamma * (unrested >= model.v_th).sum()
        cost += model.next_weight * (pr.next_flat - (pr.next_alpha * (1.0 - x)).sum())
        seconds = pr.duration[worker, pr.human].sum() + pr.robot_duration[robots].sum()
        cost += model.takt_weight * (max(0.0, t + seconds - model.takt) - max(0.0, t - model.takt))
        best = min(best, cost + model.time_weight * seconds)
    return best


@pytest.mark.parametrize(("seed", "gamma"), [(0, 100.0), (1, 2.0), (2, 1.8)])
def test_estimate_is_the_cheapest_split_of_its_completion(seed, gamma):
    """Γ of 100 (as the paper) keeps the cheapest split away from V_th; lower ones let it cross."""
    rng = np.random.default_rng(seed)
    graph = generate_task("sequential:9", agents=2, rng=rng)
    names = [a.name for a in graph.agents]
    human = next(a.name for a in graph.agents if a.kind == "human")
    model = WearModel.build(
        graph.actions, names, human, alphas={a: rng.uniform(0.8, 1.0, 5) for a in graph.actions},
        kwear=KWearParams(), cost=CostParams(gamma=gamma, v_th=0.8, robot_cost=2.5),
        durations={(a, n): float(rng.uniform(2.0, 20.0)) for a in graph.actions for n in names},
        takt=60.0, takt_weight=100.0 / 60.0, time_weight=0.3, next_weight=1.0,
        robot_actions=graph.actions[1:])  # the first action is the worker's alone
    pruned = [(graph.actions[-1], human)]  # the last action is the robot's alone
    pr = SequentialPricing(graph, model, pruned)
    cids, frontier = [], [pr.view.start(())]
    while frontier:  # every configuration the task can reach
        cid = frontier.pop()
        if cid not in cids and not pr.view.complete(cid):
            cids.append(cid)
            frontier += pr.view.successors(cid).next.tolist()
    cids = np.array(cids)
    need = np.array([pr.view.needed(c) for c in cids])
    v = rng.uniform(0.0, 0.9, (len(cids), 5))
    v[0, 2] = 1.0  # a joint already at the top: at V_th from the first step
    t = rng.uniform(0.0, 90.0, len(cids))
    table = PilotTable(pr)
    got = table.estimate(pr, cids, need, v, t)
    want = [_completion(pr, n, x, s) for n, x, s in zip(need, v, t, strict=True)]
    assert len(cids) > 20 and np.all(np.isfinite(got))
    np.testing.assert_allclose(got, want, rtol=1e-12)
    again = table.estimate(pr, cids[::-1], need[::-1], v[::-1], t[::-1])  # rows now read from the table
    np.testing.assert_allclose(again, got[::-1], rtol=1e-12)
