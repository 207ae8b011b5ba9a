"""Risk indices: KWear state per tick with dropouts, eq. 9 prediction, online alpha, static RULA baseline,
and the extension point (a user-defined index driving the cost model)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ergosim.ergonomics.calibration import Execution, calibrate
from ergosim.ergonomics.cost import CostParams, risk_costs
from ergosim.ergonomics.features import FEATURES, feature
from ergosim.ergonomics.kwear import KWearParams, kwear_step, kwear_trajectory
from ergosim.ergonomics.param_store import WorkerParams
from ergosim.ergonomics.reba import REBA_JOINTS
from ergosim.ergonomics.risk_index import REBA_G_MAX, KWearIndex, RiskIndex, StaticRebaIndex, StaticRulaIndex
from ergosim.errors import ConfigError

P = KWearParams()
DT = 0.05
ALPHAS = {"a1": [0.5, 0.9, 0.9, 0.8, 0.95], "a2": [0.99, 0.99, 0.7, 0.9, 0.6]}


def test_kwear_index_follows_kwear_step_and_predicts_eq9():
    idx = KWearIndex(P, ALPHAS)
    rng = np.random.default_rng(1)
    v = np.zeros(5)
    for k in range(200):
        g = rng.integers(1, 7, 5).astype(float)
        rest = k % 50 > 40
        idx.update(g, DT, resting=rest)
        v = kwear_step(v, g, DT, P, resting=rest)
    np.testing.assert_allclose(idx.value, v, rtol=0, atol=0)
    np.testing.assert_allclose(idx.predict("a1"), 1 - np.array(ALPHAS["a1"]) * (1 - v))
    both = idx.predict_many(["a1", "a2"])
    assert both.shape == (2, 5) and np.array_equal(both[1], idx.predict("a2"))
    assert idx.ticks == 200 and idx.dropouts == 0
    with pytest.raises(ValueError):
        idx.value[0] = 1.0  # read-only view
    with pytest.raises(ConfigError, match="a3"):
        idx.predict("a3")


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 2), st.booleans(), st.floats(0.0, 6.0)), min_size=1, max_size=80))
def test_dropouts_never_reach_v(ticks):
    """A non-finite G row is counted; while acting V holds its value; V is never NaN."""
    idx = KWearIndex(P, ALPHAS)
    expected_dropouts = 0
    for kind, resting, score in ticks:
        g = np.full(5, score)
        if kind == 1:
            g[2] = np.nan
        elif kind == 2:
            g[:] = np.inf if score > 3 else -np.inf
        before = idx.value.copy()
        idx.update(g, DT, resting=resting)
        if kind:
            expected_dropouts += 1
            if not resting:
                np.testing.assert_array_equal(idx.value, before)
        assert np.all(np.isfinite(idx.value)) and np.all((idx.value >= 0) & (idx.value < 1))
        assert np.all(np.isfinite(idx.predict("a1")))
    assert idx.dropouts == expected_dropouts and idx.ticks == len(ticks)


def test_prediction_matches_simulation_after_calibration():
    """Calibrate a constant-G action, then from any current V the index's prediction equals what
    actually happens when the action is executed tick by tick."""
    g_action = np.tile([5.0, 2.0, 3.0, 4.0, 2.0], (120, 1))
    cal = calibrate(["reach"], lambda a, run: Execution(g_action, DT), P)
    idx = KWearIndex(P, cal.alphas)
    for g in np.tile([3.0, 3.0, 3.0, 3.0, 3.0], (300, 1)):
        idx.update(g, DT)
    v_hat = idx.predict("reach")
    for g in g_action:
        idx.update(g, DT)
    np.testing.assert_allclose(idx.value, v_hat, atol=1e-12)
    np.testing.assert_allclose(v_hat, kwear_trajectory(np.full(5, 1 - math.exp(-3 * 15 / P.C)), g_action, DT,
                                                       P)[-1], atol=1e-12)


def test_online_alpha_update_is_selectable():
    g = np.full(5, 4.0)
    measured = math.exp(-4 * 100 * DT / P.C)
    for weight, expect in [(0.0, ALPHAS["a1"]), (1.0, [measured] * 5),
                           (0.5, [0.5 * a + 0.5 * measured for a in ALPHAS["a1"]])]:
        idx = KWearIndex(P, ALPHAS, online_weight=weight)
        idx.update(g, DT, resting=True)  # before the action: not part of its alpha
        idx.start_action("a1")
        for _ in range(100):
            idx.update(g, DT)
        idx.update(np.full(5, np.nan), DT)  # a dropout adds no wear to the measured alpha either
        got = idx.finish_action()
        np.testing.assert_allclose(got, measured, rtol=1e-12)
        np.testing.assert_allclose(idx.alphas["a1"], expect, rtol=1e-12)
        np.testing.assert_allclose(idx.alphas["a2"], ALPHAS["a2"])
    assert KWearIndex(P, ALPHAS).finish_action() is None
    with pytest.raises(ConfigError):
        KWearIndex(P, ALPHAS, online_weight=2.0)
    with pytest.raises(ConfigError):
        KWearIndex(P, {"a1": [0.0] * 5})


def test_reset_and_from_worker():
    worker = WorkerParams("S01", P, ALPHAS, {"a1": 5.0, "a2": 3.0})
    idx = KWearIndex.from_worker(worker)
    idx.update(np.full(5, 6.0), 10.0)
    idx.update(np.full(5, np.nan), DT)
    assert idx.value.max() > 0 and idx.dropouts == 1
    idx.reset()
    assert np.all(idx.value == 0) and idx.ticks == 0 and idx.dropouts == 0
    idx.reset(np.full(5, 0.3))
    assert np.all(idx.value == 0.3)
    rula_idx = StaticRulaIndex.from_worker(worker)
    assert rula_idx.predict("a1").tolist() == [5.0 / 9.0]


def test_static_rula_index_is_history_free():
    idx = StaticRulaIndex({"a1": 5.0, "a2": 3.0, "a3": 7.2})
    first = idx.predict_many(["a1", "a2", "a3"])
    assert first.shape == (3, 1)
    np.testing.assert_allclose(first[:, 0], [5 / 9, 3 / 9, 0.8])
    for _ in range(1000):
        idx.update(np.full(5, 6.0), DT)
    idx.update(np.array([2.0, 1.0, np.nan, 1.0, 1.0]), DT)
    np.testing.assert_array_equal(idx.predict_many(["a1", "a2", "a3"]), first)
    assert idx.value.tolist() == [6.0] * 5 and idx.dropouts == 1
    assert StaticRulaIndex({"a1": 5.0}, g_max=7.0).predict("a1")[0] == pytest.approx(5 / 7)
    with pytest.raises(ConfigError):
        StaticRulaIndex({"a1": math.nan})
    with pytest.raises(ConfigError):
        StaticRulaIndex({"a1": 5.0}, g_max=0.0)
    with pytest.raises(ConfigError, match="a9"):
        idx.predict("a9")


class PeakIndex(RiskIndex):
    """A user-defined index: the running peak of the part scores, normalised by 6 (one channel)."""

    channels = ("peak",)

    def __init__(self, extra: dict[str, float]) -> None:
        super().__init__()
        self.extra = extra

    def _advance(self, g, dt, resting):
        if not resting:
            np.maximum(self._v, g / 6.0, out=self._v)

    def predict(self, action):
        return np.array([max(self._v.max(), self.extra[action])])


def test_a_new_risk_index_plugs_into_the_cost_model():
    idx = PeakIndex({"a1": 0.2, "a2": 0.5})
    params = CostParams(gamma=100.0, v_th=0.8, robot_cost=2.0, v_max=1.0)
    costs = risk_costs(idx, ["a1", "a2"], "human", ["robot"], params)
    assert costs == {("a1", "human"): 0.2, ("a1", "robot"): 2.0, ("a2", "human"): 0.5, ("a2", "robot"): 2.0}
    idx.update(np.full(5, 6.0), DT)
    costs = risk_costs(idx, ["a1"], "human", ["robot"], params)
    assert costs[("a1", "human")] == pytest.approx(101.0)
    with pytest.raises(TypeError):
        RiskIndex()  # abstract


def test_kwear_on_reba_part_scores_has_six_joints_and_the_same_law():
    """The REBA-driven variant: the same eq. 3-9 on REBA's six part scores (legs included)."""
    alphas = {"a1": [0.5, 0.9, 0.9, 0.8, 0.95, 0.97]}
    idx = KWearIndex(P, alphas, features="reba", joints=REBA_JOINTS)
    assert idx.features == "reba" and idx.joints == REBA_JOINTS and idx.channels == REBA_JOINTS
    g = np.array([4.0, 2.0, 3.0, 2.0, 1.0, 2.0])
    v = np.zeros(6)
    for _ in range(100):
        idx.update(g, DT)
        v = kwear_step(v, g, DT, P)
    np.testing.assert_allclose(idx.value, v, rtol=1e-12)
    np.testing.assert_allclose(idx.predict("a1"), 1 - np.array(alphas["a1"]) * (1 - v))
    with pytest.raises(ConfigError, match="6 values"):
        KWearIndex(P, ALPHAS, features="reba", joints=REBA_JOINTS)  # RULA's five alphas do not fit
    six = calibrate(["a1"], lambda a, run: Execution(np.tile(g, (40, 1)), DT), P, joints=6)
    np.testing.assert_allclose(six.alphas["a1"], np.exp(-g * 40 * DT / P.C))


def test_static_reba_index():
    idx = StaticRebaIndex({"a1": 9.0, "a2": 4.0})
    assert idx.features == "reba" and idx.channels == ("reba",) and idx.g_max == REBA_G_MAX == 15.0
    np.testing.assert_allclose(idx.predict_many(["a1", "a2"])[:, 0], [9 / 15, 4 / 15])
    idx.update(np.full(6, 3.0), DT)
    assert idx.value.shape == (6,)
    with pytest.raises(ConfigError, match="no REBA score"):
        idx.predict("a9")
    assert {"rula", "reba", "angles"} <= set(FEATURES) and FEATURES["reba"].joints == REBA_JOINTS
    with pytest.raises(ConfigError, match="features: rula, reba, angles"):
        feature("owas")
