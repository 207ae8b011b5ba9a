"""Calibrating a synthetic subject in a workcell with one call, and storing its parameters (paper §5).

A consistent subject (no sensor noise, no trial-to-trial variation) repeats every action exactly, so its
α are known after the first η_0 = 2 executions (Ṽ_des = 1e-3). A default subject's executions differ, and the
adaptive η reports honestly how far it got: the test checks the report, not that it converges.
"""

from __future__ import annotations

import numpy as np
import pytest

from ergosim.ergonomics.kwear import KWearParams
from ergosim.ergonomics.param_store import ParamStore
from ergosim.errors import ConfigError
from ergosim.twin.calibration import calibrate_subject
from ergosim.worker import make_subject, make_subjects

SCENES = ("kwear-validation", "multi-subject")
ACTIONS = ("a1", "a2", "a3", "a4", "a5")


def _consistent(**kw):
    return make_subject(np.random.default_rng(0), "C01", noise_deg=0.0, bias_deg=0.0, variability_deg=0.0,
                        timing_variability=0.0, **kw)


@pytest.mark.parametrize("scene", SCENES)
def test_consistent_subject_reaches_v_des_with_eta0(scene):
    cal = calibrate_subject(scene, _consistent(), eta0=2, v_des=1e-3)
    assert tuple(cal.actions) == ACTIONS
    for action, c in cal.actions.items():
        assert c.eta == 2 and c.converged, action
        assert c.errors.shape == (2, 5) and np.all(c.errors < 1e-3), (action, c.errors)
        # α = exp(-∫G/C) (eq. 4, 9): some wear on every joint, never a full one
        assert np.all((c.alpha > 0.5) & (c.alpha < 1.0)), (action, c.alpha)
        assert c.duration > 2.0 and c.dropouts == 0 and 1 <= c.rula_grand <= 7


@pytest.mark.slow
@pytest.mark.parametrize("scene", SCENES)
def test_default_subject_reports_eta_and_errors(scene):
    subject = make_subjects(1, seed=0)[0]
    cal = calibrate_subject(scene, subject, eta0=2, eta_max=6, v_des=1e-3, seed=3)
    for action, c in cal.actions.items():
        assert 2 <= c.eta <= 6
        assert c.alphas.shape == (c.eta, 5) and c.errors.shape == (c.eta, 5)
        np.testing.assert_allclose(c.alpha, c.alphas.mean(axis=0))
        np.testing.assert_allclose(c.errors, np.abs(c.alphas - c.alpha))  # |V̂ - V_l| from zero wear
        assert c.converged == bool(np.all(c.errors < 1e-3))
        if not c.converged:
            assert c.eta == 6, action  # stopped at eta_max, and says so
        assert np.isfinite(c.errors).all() and np.all((c.alpha > 0) & (c.alpha <= 1))


@pytest.mark.slow
def test_same_seed_same_calibration():
    subject = make_subjects(1, seed=0)[0]
    a = calibrate_subject("kwear-validation", subject, eta_max=3, seed=5)
    b = calibrate_subject("kwear-validation", subject, eta_max=3, seed=5)
    c = calibrate_subject("kwear-validation", subject, eta_max=3, seed=6)
    for action in ACTIONS:
        assert a.actions[action].alphas.tobytes() == b.actions[action].alphas.tobytes()
    assert any(a.actions[x].alphas.tobytes() != c.actions[x].alphas.tobytes() for x in ACTIONS)


def test_store_round_trip(tmp_path):
    subject = _consistent(kwear={"t_max": 180.0})
    cal = calibrate_subject("multi-subject", subject, store=tmp_path / "store", worker_id="W-1")
    stored = ParamStore(tmp_path / "store").load("W-1")
    assert stored.kwear == KWearParams(t_max=180.0) == cal.params
    assert set(stored.alphas) == set(ACTIONS)
    for action, c in cal.actions.items():
        np.testing.assert_array_equal(stored.alpha(action), c.alpha)
        assert stored.eta[action] == c.eta == 2
        assert stored.rula_scores[action] == c.rula_grand
    # a store object, and the subject's name as the default worker id
    store = ParamStore(tmp_path / "other")
    calibrate_subject("kwear-validation", subject, store=store, eta_max=2)
    assert store.workers() == ["C01"]


@pytest.mark.slow
def test_dropouts_are_counted_and_contribute_no_wear():
    cal = calibrate_subject("kwear-validation", _consistent(), dropout_rate=0.05, eta_max=3)
    assert sum(c.dropouts for c in cal.actions.values()) > 0
    for c in cal.actions.values():
        assert np.isfinite(c.alphas).all() and np.all((c.alphas > 0) & (c.alphas <= 1))
    # a dropout removes that tick's wear, so the α of a pass with dropouts is never below the clean one
    clean = calibrate_subject("kwear-validation", _consistent(), eta_max=2)
    for action in ACTIONS:
        assert np.all(cal.actions[action].alphas >= clean.actions[action].alpha - 1e-12)


def test_bad_settings_fail_before_recording(tmp_path):
    with pytest.raises(ConfigError, match="whole multiple"):
        calibrate_subject("kwear-validation", _consistent(), mocap_rate=50.0, ergonomics_rate=20.0)
    with pytest.raises(ConfigError, match="worker id"):
        calibrate_subject("kwear-validation", _consistent(), store=tmp_path, worker_id="../x")
    with pytest.raises(ConfigError, match="unknown scene"):
        calibrate_subject("no-such-scene", _consistent())
    with pytest.raises(ConfigError, match="shelf_hieght"):
        calibrate_subject("kwear-validation", _consistent(), shelf_hieght=1.6)
    assert not any(tmp_path.iterdir())
