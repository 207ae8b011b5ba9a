"""The standalone model of the paper's equations (eq. 3-11, Algorithm 2) that answers what-if questions."""

from __future__ import annotations

import numpy as np
import pytest

from ergosim.ergonomics.cost import CostParams
from ergosim.ergonomics.kwear import KWearParams
from ergosim.fidelity.paper_model import SubjectInputs, scaled, simulate

ACTIONS = ("a1", "a2", "a3", "a4", "a5")


def _subject(wear=0.06, a2=1.0, robot_s=12.0) -> SubjectInputs:
    """Every joint worn by ``wear`` per action (a2 ``a2`` times as much), 4 s a worker action."""
    alpha = {a: np.full(5, 1.0 - wear) ** (a2 if a == "a2" else 1.0) for a in ACTIONS}
    return SubjectInputs(alpha, dict.fromkeys(ACTIONS, 4.0), dict.fromkeys(ACTIONS[:4], robot_s),
                         {a: np.full(5, 0.99) for a in ACTIONS[:4]})


def test_a_worker_who_barely_wears_does_everything():
    shares = simulate([_subject(wear=0.001)])
    assert shares.total == 0.0 and shares.repetition_s == pytest.approx(5 * 4.0)


def test_the_robot_takes_over_once_the_predicted_wear_crosses_the_robots_cost():
    """Five equal joints: the worker's cost sum V̂ exceeds c_r = 2.5 once V̂ > 0.5 on each; with a takt slot
    of 20 s the worker recovers between repetitions, back to back it does not."""
    worn = simulate([_subject(wear=0.12)], takt_paced=False)
    rested = simulate([_subject(wear=0.12)], takt_paced=True, takt=60.0)
    assert 0.0 < rested.total < worn.total <= 1.0


def test_one_decision_by_hand_eq_9_to_11():
    """Rep 1 of a subject whose a1 alone lifts V to 0.45 on every joint (V̂(a1) = 0.45, 5 x 0.45 < 2.5: the
    worker's): V̂(a2) = 1 - 0.9 (1 - 0.45) = 0.505, 5 x 0.505 > 2.5 = c_r, so a2 goes to the robot, while
    V̂(a3) = V̂(a4) = 0.4505 keep theirs with the worker."""
    s = _subject(wear=0.45)
    s = SubjectInputs({**s.alpha, "a2": np.full(5, 0.9), "a3": np.full(5, 0.999), "a4": np.full(5, 0.999)},
                      s.worker_s, s.robot_s, s.handover_alpha)
    shares = simulate([s], repetitions=1, cost=CostParams(robot_cost=2.5), kwear=KWearParams())
    assert shares.by_action == {"a1": 0.0, "a2": 1.0, "a3": 0.0, "a4": 0.0}


def test_scaling_an_action_raises_its_wear_and_its_time():
    s = _subject()
    big = scaled(s, {"a2": 2.0})
    assert 1.0 - big.alpha["a2"][0] == pytest.approx(1.0 - (1.0 - 0.06) ** 2)
    assert big.worker_s["a2"] == 8.0 and big.worker_s["a3"] == 4.0


@pytest.mark.parametrize("tie", ["costliest-first", "task-order", "cheapest-first"])
def test_the_tie_rule_only_orders_equal_cost_plans(tie):
    """Deciding the riskiest action last raises its share (the worker is more worn by then)."""
    subjects = [_subject(wear=0.05, a2=2.0)]
    shares = simulate(subjects, tie=tie)
    assert 0.0 <= shares.by_action["a2"] <= 1.0
    if tie == "cheapest-first":
        assert shares.by_action["a2"] >= simulate(subjects, tie="costliest-first").by_action["a2"]
