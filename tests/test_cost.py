"""Cost model (paper eq. 10-11), the robot-cost range warning, and the static RULA baseline rule."""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pytest

from ergosim.ergonomics.cost import (
    G_MAX_PAPER,
    CostParams,
    CostRangeWarning,
    gamma_terms,
    human_cost,
    hyperarc_costs,
    risk_costs,
    rula_baseline_agent,
    rula_baseline_params,
)
from ergosim.ergonomics.kwear import KWearParams
from ergosim.ergonomics.risk_index import KWearIndex, StaticRulaIndex
from ergosim.errors import ConfigError


def quiet(**kw) -> CostParams:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return CostParams(**kw)


PAPER_1 = quiet(gamma=100.0, v_th=0.8, robot_cost=50.0)
PAPER_2 = quiet(gamma=100.0, v_th=0.8, robot_cost=2.5)


def test_gamma_terms_eq11_threshold_edge():
    v = np.array([0.0, 0.79999, 0.8, 0.95, 0.993])
    np.testing.assert_allclose(gamma_terms(v, PAPER_1), [0.0, 0.79999, 100.8, 100.95, 100.993])
    assert human_cost(v, PAPER_1) == pytest.approx(v.sum() + 300.0)
    # (n_actions, m) -> (n_actions,)
    out = human_cost(np.array([[0.1] * 5, [0.1, 0.1, 0.1, 0.1, 0.85]]), PAPER_1)
    np.testing.assert_allclose(out, [0.5, 0.4 + 0.85 + 100.0])


def test_per_joint_thresholds():
    params = quiet(v_th=(0.5, 0.8, 0.8, 0.9, 0.9), robot_cost=50.0)
    v = np.array([0.6, 0.6, 0.6, 0.6, 0.6])
    np.testing.assert_allclose(gamma_terms(v, params), [100.6, 0.6, 0.6, 0.6, 0.6])
    assert params.v_th == (0.5, 0.8, 0.8, 0.9, 0.9)
    with pytest.raises(ConfigError, match="channels"):
        gamma_terms(np.ones(3) * 0.1, params)


def test_mapping_for_the_planner():
    v_hat = {"a1": np.full(5, 0.1), "a2": np.array([0.1, 0.1, 0.1, 0.1, 0.9])}
    costs = hyperarc_costs(v_hat, "human", ["panda"], PAPER_1)
    assert costs == {("a1", "human"): pytest.approx(0.5), ("a1", "panda"): 50.0,
                     ("a2", "human"): pytest.approx(101.3), ("a2", "panda"): 50.0}
    two = hyperarc_costs(v_hat, ["h1", "h2"], [], PAPER_1)
    assert set(two) == {("a1", "h1"), ("a1", "h2"), ("a2", "h1"), ("a2", "h2")}
    assert hyperarc_costs({}, "human", ["panda"], PAPER_1) == {}
    assert all(type(c) is float for c in costs.values())


def test_warning_when_robot_cost_outside_the_paper_range():
    for kw in [dict(robot_cost=0.5), dict(robot_cost=0.8), dict(robot_cost=150.0),
               dict(robot_cost=2.0, v_th=(0.5, 0.5, 3.0, 0.5, 0.5))]:
        with pytest.warns(CostRangeWarning, match="c_r") as rec:
            CostParams(**kw)
        assert str(kw["robot_cost"]) in str(rec[0].message)
    with pytest.warns(CostRangeWarning, match="Gamma"):
        CostParams(gamma=0.5, robot_cost=1.0)
    quiet(robot_cost=100.9)  # just below V_max + Gamma = 100.993: fine


def test_invalid_cost_parameters():
    for kw in [dict(gamma=-1.0), dict(v_th=0.0), dict(robot_cost=float("nan")), dict(v_max=1.5),
               dict(v_th=())]:
        with pytest.raises(ConfigError):
            CostParams(**kw)


def test_kwear_index_costs_switch_to_the_robot_when_wear_is_high():
    idx = KWearIndex(KWearParams(), {"reach": [0.6, 0.95, 0.95, 0.95, 0.95]})
    costs = risk_costs(idx, ["reach"], "human", ["robot"], PAPER_2)
    assert costs[("reach", "human")] < costs[("reach", "robot")]
    for _ in range(600):  # 30 s at the worst shoulder score: V = 0.71, V_hat = 0.83
        idx.update(np.array([6.0, 1, 1, 1, 1]), 0.05)
    costs = risk_costs(idx, ["reach"], "human", ["robot"], PAPER_2)
    assert idx.predict("reach")[0] >= 0.8 and costs[("reach", "human")] > costs[("reach", "robot")]


def test_rula_baseline_follows_the_paper_by_default():
    params = rula_baseline_params(robot_cost=50.0)
    assert params.v_th == pytest.approx(0.8) and 0.8 * G_MAX_PAPER == pytest.approx(7.2)
    # paper Table 1: RULA scores 5, 3, 3, 4, 4 -> every action to the human
    idx = StaticRulaIndex({"a1": 5, "a2": 3, "a3": 3, "a4": 4, "a5": 4})
    costs = risk_costs(idx, ["a1", "a2", "a3", "a4", "a5"], "human", ["robot"], params)
    assert all(costs[(a, "human")] < costs[(a, "robot")] for a in idx.g_actions)
    # grand scores stop at 7 < 7.2: with the paper's G_max the baseline never picks the robot
    assert all(rula_baseline_agent(g) == "human" for g in range(1, 8))


@pytest.mark.parametrize(("g_th", "g_max", "robot_cost"),
                         [(None, 9.0, 50.0), (5.0, 7.0, 2.5), (6.0, 9.0, 10.0), (4.0, 7.0, 50.0)])
def test_rula_baseline_costs_reproduce_the_rule(g_th, g_max, robot_cost):
    params = rula_baseline_params(robot_cost=robot_cost, g_th=g_th, g_max=g_max)
    threshold = 0.8 * g_max if g_th is None else g_th
    scores = {f"a{g}": float(g) for g in range(1, 10)} | {"edge": threshold}
    idx = StaticRulaIndex(scores, g_max=g_max)
    costs = risk_costs(idx, scores, "human", ["robot"], params)
    for a, g in scores.items():
        cheaper = "robot" if costs[(a, "robot")] < costs[(a, "human")] else "human"
        assert cheaper == rula_baseline_agent(g, threshold), (a, g)
    assert rula_baseline_agent(threshold, threshold) == "robot"  # G >= G_th goes to the robot


def test_cost_is_monotone_in_predicted_risk():
    grid = np.linspace(0.0, 0.99, 34)
    for a, b in itertools.pairwise(grid):
        assert human_cost(np.full(5, a), PAPER_1) <= human_cost(np.full(5, b), PAPER_1)
