"""Calibration (paper §5): alpha from zero-wear executions, adaptive eta, online update, parameter store."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from ergosim.ergonomics.calibration import (
    Execution,
    calibrate,
    calibrate_action,
    execution_from_angles,
    online_alpha,
)
from ergosim.ergonomics.kwear import KWearParams, kwear_trajectory
from ergosim.ergonomics.param_store import ParamStore, WorkerParams
from ergosim.errors import ConfigError, RecordingError
from ergosim.posture import ANGLE_NAMES

P = KWearParams()
DT = 0.05


def const_execution(g: list[float], n: int, grand: float = 4.0) -> Execution:
    return Execution(np.tile(g, (n, 1)), DT, np.full(n, grand))


def test_alpha_is_one_minus_final_wear():
    rng = np.random.default_rng(0)
    g = rng.integers(1, 7, size=(300, 5)).astype(float)
    cal = calibrate_action(lambda run: Execution(g, DT), P, v_des=1e-9)
    v_end = kwear_trajectory(np.zeros(5), g, DT, P)[-1]
    np.testing.assert_allclose(cal.alpha, 1.0 - v_end, atol=1e-12)
    assert cal.eta == 2 and cal.converged and np.all(cal.errors == 0.0)
    assert cal.duration == pytest.approx(300 * DT)


def test_recovers_known_alpha_from_noisy_synthetic_executions():
    """Executions jitter integer RULA scores around a nominal profile; the mean alpha converges to the
    nominal exp(-int G / C) as eta grows (eta_max reached: the spread exceeds V_des)."""
    nominal = np.array([5.0, 2.0, 3.0, 3.0, 2.0])
    n = 200  # 10 s
    known = np.exp(-nominal * n * DT / P.C)
    rng = np.random.default_rng(42)

    def execute(run: int) -> Execution:
        g = nominal + rng.choice([-1.0, 0.0, 1.0], size=(n, 5), p=[0.2, 0.6, 0.2])
        return Execution(g, DT)

    cal = calibrate_action(execute, P, v_des=1e-4, eta0=2, eta_max=60)
    assert cal.eta == 60 and not cal.converged and cal.alphas.shape == (60, 5)
    np.testing.assert_allclose(cal.alpha, known, atol=1.5e-3)
    np.testing.assert_allclose(cal.errors, np.abs(cal.alphas - cal.alpha))
    assert np.all(cal.max_error >= 1e-4)


def test_adaptive_eta_stops_when_every_error_is_below_target():
    # alpha_l from constant G = 3 over n_l ticks; durations chosen so that eta = 3 fails and eta = 4 passes.
    a = math.exp(-3 * 100 * DT / P.C)
    n_for = [100, 100, 101, 101, 500]
    d = a - math.exp(-3 * 101 * DT / P.C)
    v_des = 0.6 * d  # d/2 < v_des < 2d/3
    calls = []

    def execute(run: int) -> Execution:
        calls.append(run)
        return const_execution([3.0] * 5, n_for[run])

    cal = calibrate_action(execute, P, v_des=v_des, eta0=3, eta_max=5)
    assert cal.eta == 4 and cal.converged and calls == [0, 1, 2, 3]
    assert np.all(cal.errors < v_des)
    # the same data from eta0 = 2 stops at once: two identical executions
    calls.clear()
    assert calibrate_action(execute, P, v_des=v_des, eta0=2).eta == 2


def test_inconsistent_executions_run_to_eta_max_and_say_so():
    durations = [100, 200]
    cal = calibrate_action(lambda run: const_execution([4.0] * 5, durations[run % 2]), P, v_des=1e-3,
                           eta_max=7)
    assert cal.eta == 7 and not cal.converged
    assert np.all(cal.max_error > 1e-3)


def test_rula_grand_statistic_and_dropouts():
    # G(a_k): the grand score held for the most ticks (the posture held longest); NaN frames ignored.
    g = np.tile([3.0, 2.0, 2.0, 2.0, 1.0], (100, 1))
    g[10:15] = np.nan
    grand = np.full(100, 5.0)
    grand[:40] = 3.0  # 40 ticks at 3
    grand[40:44] = 7.0  # a short spike does not set the score
    grand[10:15] = np.nan
    cal = calibrate_action(lambda run: Execution(g, DT, grand), P)
    assert cal.rula_grand == 5.0 and cal.dropouts == 10
    np.testing.assert_allclose(cal.alpha, np.exp(-np.array([3.0, 2, 2, 2, 1]) * 95 * DT / P.C))
    assert math.isnan(calibrate_action(lambda run: Execution(g, DT), P).rula_grand)


def test_execution_from_angles_and_calibrate_many():
    n = 40
    angles = np.zeros((n, len(ANGLE_NAMES)))
    angles[:, ANGLE_NAMES.index("shoulder_flexion")] = 100.0  # upper arm 4
    angles[:, ANGLE_NAMES.index("elbow_flexion")] = 80.0
    angles[5] = np.nan
    ex = execution_from_angles(angles, DT)
    assert ex.g.shape == (n, 5) and np.isnan(ex.g[5]).all() and ex.g[0].tolist() == [4, 1, 1, 1, 1]
    assert ex.grand[0] == 3.0  # Table A[4][1][1][1] = 4, Table B = 1 -> Table C[4][1] = 3
    other = const_execution([1.0] * 5, 10)
    cal = calibrate(["a1", "a2"], lambda action, run: ex if action == "a1" else other, P, eta0=2)
    assert set(cal.alphas) == {"a1", "a2"} and cal.eta == {"a1": 2, "a2": 2}
    assert cal.rula_scores["a1"] == 3.0
    assert cal.alphas["a1"][0] == pytest.approx(math.exp(-4 * (n - 1) * DT / P.C))


def test_bad_inputs_are_clear_errors():
    with pytest.raises(ConfigError):
        calibrate_action(lambda run: const_execution([1.0] * 5, 5), P, eta0=1)
    with pytest.raises(ConfigError):
        calibrate_action(lambda run: const_execution([1.0] * 5, 5), P, eta0=3, eta_max=2)
    with pytest.raises(ConfigError):
        calibrate_action(lambda run: const_execution([1.0] * 5, 5), P, v_des=0.0)
    with pytest.raises(RecordingError, match="shape"):
        calibrate_action(lambda run: Execution(np.ones((5, 4)), DT), P, action="a1", joints=5)
    with pytest.raises(RecordingError, match="shape"):  # every execution with the same joints
        calibrate_action(lambda run: Execution(np.ones((5, 5 + run)), DT), P, action="a1")
    six = calibrate_action(lambda run: Execution(np.ones((5, 6)), DT), P, joints=6)  # REBA's six joints
    assert six.alpha.shape == (6,)
    with pytest.raises(RecordingError, match="dt"):
        calibrate_action(lambda run: Execution(np.ones((5, 5)), 0.0), P)
    with pytest.raises(RecordingError, match="dropout"):
        calibrate_action(lambda run: Execution(np.full((5, 5), np.nan), DT), P)
    with pytest.raises(RecordingError, match="must return"):
        calibrate_action(lambda run: None, P)


def test_online_alpha_weighted_average():
    old, last = np.full(5, 0.9), np.full(5, 0.7)
    np.testing.assert_allclose(online_alpha(old, last, 0.0), old)
    np.testing.assert_allclose(online_alpha(old, last, 1.0), last)
    np.testing.assert_allclose(online_alpha(old, last, 0.25), 0.85)
    with pytest.raises(ConfigError):
        online_alpha(old, last, 1.5)


# -- parameter store ------------------------------------------------------------------------------------
def test_store_round_trip(tmp_path):
    cal = calibrate(["a1", "a2"], lambda action, run: const_execution([2.0, 1, 3, 2, 1], 50, grand=4.0), P)
    params = WorkerParams.from_calibration("S01", cal)
    store = ParamStore(tmp_path / "workers")
    path = store.save(params)
    assert path == tmp_path / "workers" / "S01.json" and store.workers() == ["S01"] and store.exists("S01")
    back = store.load("S01")
    assert back == params
    np.testing.assert_array_equal(back.alpha("a1"), cal.alphas["a1"])
    assert back.rula_scores == {"a1": 4.0, "a2": 4.0} and back.eta == {"a1": 2, "a2": 2}
    other = WorkerParams("S02", KWearParams(t_max=180.0), {"a1": [0.9] * 5})
    store.save(other)
    assert store.load("S02").kwear.t_max == 180.0 and store.workers() == ["S01", "S02"]
    updated = back.with_alpha("a1", np.full(5, 0.5))
    store.save(updated)
    assert store.load("S01").alphas["a1"] == (0.5,) * 5
    assert not list((tmp_path / "workers").glob("*.tmp"))  # atomic writes leave no temporaries


def test_store_errors(tmp_path):
    store = ParamStore(tmp_path)
    with pytest.raises(ConfigError, match="no parameters for worker 'S09'"):
        store.load("S09")
    (tmp_path / "S01.json").write_text('{"format": "ergosim-worker-params",\n "version": 1,,}')
    with pytest.raises(ConfigError, match=r"S01.json:2"):
        store.load("S01")
    good = WorkerParams("S01", alphas={"a1": [0.9] * 5}).to_dict()
    for mutate, entry in [(lambda d: d.update(version=99), "version"),
                          (lambda d: d.update(joints=["neck"]), "joints"),
                          (lambda d: d["actions"]["a1"].update(alpha=[0.9] * 4), "alphas.a1"),
                          (lambda d: d["actions"]["a1"].update(alpha=[1.5] * 5), "alphas.a1"),
                          (lambda d: d["kwear"].update(v_max=2.0), "v_max"),
                          (lambda d: d.update(worker_id="S02"), "worker_id")]:
        data = json.loads(json.dumps(good))
        mutate(data)
        (tmp_path / "S01.json").write_text(json.dumps(data))
        with pytest.raises(ConfigError, match=entry) as err:
            store.load("S01")
        assert "S01.json" in str(err.value) and "\n" not in str(err.value)
    for bad_id in ["../x", "a/b", "", ".hidden", "x" * 65]:
        with pytest.raises(ConfigError):
            store.path(bad_id)
    with pytest.raises(ConfigError, match="no calibrated alpha"):
        WorkerParams("S01").alpha("a1")


def test_action_grand_score_rules_on_worked_cases():
    from ergosim.ergonomics.rula_action import G_RULE, action_grand_score, grand_scores_by_rule  # noqa: PLC0415

    assert G_RULE == "held-1s"
    # 20 ticks per second: a 6 for 0.5 s, then a 5 for 1.2 s, then a 3 for 3 s
    g = np.array([6.0] * 10 + [5.0] * 24 + [3.0] * 60)
    assert grand_scores_by_rule(g) == {"held-longest": 3.0, "quarter": 5.0, "held-1s": 5.0, "worst": 6.0}
    assert action_grand_score(np.array([3, 3, 6, 6.0]), "held-longest") == 6.0  # a tie: the higher score
    # a dropout breaks a hold; executions are scored apart and their median taken
    broken = np.array([5.0] * 15 + [np.nan] + [5.0] * 15 + [3.0] * 40)
    assert action_grand_score(broken) == 3.0
    assert action_grand_score([g, broken, g]) == 5.0
    assert math.isnan(action_grand_score(np.array([np.nan, np.nan])))
    with pytest.raises(ValueError, match="unknown G rule"):
        action_grand_score(g, "median")
