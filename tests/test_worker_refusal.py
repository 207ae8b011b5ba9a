"""The simulated worker's refusal model (negotiation): monotone in V̂, per-subject tolerance, seeded."""

from __future__ import annotations

import numpy as np
import pytest

from ergosim.experiment.protocol import ScenarioConfig
from ergosim.twin.negotiation import Negotiator
from ergosim.twin.team_setup import refusal_model
from ergosim.worker.refusal import RefusalModel


def test_probability_rises_with_the_most_loaded_joint():
    m = RefusalModel(tolerance=0.6, slope=0.05)
    assert m.probability([0.6, 0.1, 0.0, 0.0, 0.0]) == pytest.approx(0.5)
    ps = [m.probability([v, 0, 0, 0, 0]) for v in np.linspace(0, 1, 21)]
    assert all(b > a for a, b in zip(ps, ps[1:]))
    assert m.probability([0.2, 0.9, 0, 0, 0]) == m.probability([0.9, 0, 0, 0, 0])  # the most-loaded joint
    assert m.probability([-100.0]) == 0.0


def test_tolerance_per_subject_and_seeded():
    cfg = ScenarioConfig.of("cell", "task", subjects=1, repetitions=1, modes=("hrc",), robot_cost=2.5)
    a, b = refusal_model(cfg, 0, 0), refusal_model(cfg, 0, 1)
    assert a == refusal_model(cfg, 0, 0) and a.tolerance != b.tolerance
    taus = [refusal_model(cfg, s, 0).tolerance for s in range(200)]
    assert np.mean(taus) == pytest.approx(cfg.team.refusal_tolerance, abs=0.02)
    assert np.std(taus) == pytest.approx(cfg.team.refusal_tolerance_sd, rel=0.25)


class _Index:
    def __init__(self, v):
        self.v = v

    def predict(self, action):
        return np.array(self.v[action])


def test_refusals_follow_the_predicted_wear():
    model = RefusalModel(0.5, 0.05)
    v = {"low": [0.3, 0.1, 0, 0, 0], "high": [0.1, 0.1, 0, 0, 0.7]}
    neg = Negotiator(model, _Index(v), np.random.default_rng(0))
    offers = [neg.offer(0.0, 1, a) for a in ("low", "high") * 200]
    rate = {a: np.mean([o.refused for o in offers if o.action == a]) for a in v}
    assert rate["high"] > 0.9 and rate["low"] < 0.05
    assert offers[1].joint == "neck" and offers[1].action in offers[1].message
    again = Negotiator(model, _Index(v), np.random.default_rng(0))
    assert [again.offer(0.0, 1, a).refused for a in ("low", "high") * 200] == [o.refused for o in offers]
