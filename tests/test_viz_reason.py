"""The one wording of why an action went to an agent (allocation log, loop and tests share it)."""

from __future__ import annotations

import numpy as np

from ergosim.twin.allocator import Basis, Decision
from ergosim.viz import allocation_reason, reason_text

V_TH = np.full(5, 0.8)  # shoulder, elbow, wrist, trunk, neck
COSTS = {("a1", "human"): 0.9, ("a1", "robot"): 50.0, ("a2", "human"): 100.83, ("a2", "robot"): 50.0}
V_HAT = {"a1": np.array([0.42, 0.1, 0.3, 0.05, 0.03]), "a2": np.array([0.83, 0.1, 0.2, 0.1, 0.05])}


def reason(chosen, v_hat=V_HAT, costs=COSTS, v_th=V_TH) -> str:
    return allocation_reason(chosen, v_hat=v_hat, costs=costs, v_th=v_th)


def test_robot_because_a_joint_reaches_its_threshold():
    assert reason(("a2", "robot")) == (
        "a2 → robot: predicted shoulder KWear 0.83 ≥ V_th 0.80; cost robot 50.00 < human 100.83")


def test_human_when_every_joint_stays_below():
    assert reason(("a1", "human")) == (
        "a1 → human: predicted KWear below V_th on every joint (closest: shoulder 0.42 < 0.80); "
        "cost human 0.90 < robot 50.00")


def test_the_joint_named_is_the_one_furthest_past_its_own_threshold():
    v_th = np.array([0.9, 0.5, 0.8, 0.8, 0.8])
    v_hat = {"a2": np.array([0.95, 0.75, 0.81, 0.1, 0.1])}  # elbow exceeds by 0.25, shoulder by 0.05
    assert reason(("a2", "robot"), v_hat=v_hat, v_th=v_th).startswith(
        "a2 → robot: predicted elbow KWear 0.75 ≥ V_th 0.50 (+2 more joints);")
    v_hat = {"a2": np.array([0.1, 0.75, 0.2, 0.1, 0.1])}
    assert "predicted elbow KWear 0.75 ≥ V_th 0.50; " in reason(("a2", "robot"), v_hat=v_hat, v_th=v_th)


def test_a_single_candidate_and_missing_predictions():
    costs = {("a5", "human"): 3.0}
    assert reason(("a5", "human"), v_hat={}, costs=costs) == "a5 → human: only human can do a5"
    costs = {("a3", "human"): 50.0, ("a3", "robot"): 50.0}
    assert reason(("a3", "human"), v_hat={}, costs=costs) == "a3 → human: cost human 50.00 = robot 50.00"


def _decision(index, v_th=None, scale=1.0, agent="robot", **kw):
    basis = Basis("m", index, v_th, scale, "human", ("robot",))
    return Decision(0.0, 1, np.zeros(5), V_HAT, COSTS, "a2", agent, "op2", True, basis, **kw)


def test_a_decision_is_data_and_viz_words_it():
    """The allocator records why (v_hat, costs, the basis); reason_text says it, per risk index."""
    assert reason_text(_decision(None)) == "a2 → robot: m mode"
    assert reason_text(_decision("kwear", 0.8)) == reason(("a2", "robot"))
    rula = _decision("rula-static", 0.8, scale=9.0)
    assert reason_text(rula).startswith(f"a2 → robot: RULA G={V_HAT['a2'][0] * 9:g} ")
    other = _decision("someone-elses", 0.8)  # an index without its own words: the threshold sentence
    assert reason_text(other) == reason(("a2", "robot"))
    team = _decision(None, excess=1.5, early=True, part="S1")
    assert reason_text(team) == ("a2 → robot: m mode; the robot is idle: best ready operation, plan +1.50; "
                                 "fetches S1 while the rest goes on")


def test_kwear_on_reba_part_scores_names_the_legs():
    v_th = np.full(6, 0.8)  # KWear on REBA's part scores: the five joints and the legs
    v_hat = {"a2": np.array([0.1, 0.1, 0.2, 0.1, 0.05, 0.85])}
    assert reason(("a2", "robot"), v_hat=v_hat, v_th=v_th).startswith(
        "a2 → robot: predicted legs KWear 0.85 ≥ V_th 0.80;")
    reba = _decision("reba-static", 0.8 * 8 / 15, scale=15.0)  # the static REBA baseline, G_th 8 of 15
    assert reason_text(reba).startswith(f"a2 → robot: REBA G={V_HAT['a2'][0] * 15:g} ")
