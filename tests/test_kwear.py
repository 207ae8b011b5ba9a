"""KWear (paper eq. 3-9): constants, exact tick vs scipy ODE, invariants, prediction vs simulation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from ergosim.ergonomics.kwear import V_CEIL, KWearParams, alpha_of, kwear_step, kwear_trajectory, predict
from ergosim.errors import ConfigError

P = KWearParams()
V01 = st.floats(0.0, 0.999, allow_nan=False)
G = st.floats(0.0, 9.0, allow_nan=False)
DT = st.floats(0.0, 30.0, allow_nan=False)


def test_paper_constants():
    assert P.C == pytest.approx(145.107, abs=1e-3)
    assert P.r == pytest.approx(2.9958, abs=1e-4)
    assert P.C == pytest.approx(-3 * 240 / math.log(0.007), rel=1e-12)
    # eq. 6-7 consistency: V reaches v_max at t_max from 0 at G_avg, and recovers from v_max to 1 - v_max.
    v = kwear_step(np.zeros(1), np.full(1, 3.0), 240.0, P)
    assert v[0] == pytest.approx(0.993, abs=1e-12)
    assert kwear_step(v, np.zeros(1), 240.0, P, resting=True)[0] == pytest.approx(0.007, abs=1e-12)


def test_subject_overrides_and_validation():
    q = KWearParams(t_max=120.0)
    assert q.C == pytest.approx(P.C / 2) and q.r == pytest.approx(P.r)
    for bad in [dict(t_max=0.0), dict(v_max=1.0), dict(v_max=0.4), dict(g_avg=-1.0), dict(t_max=math.nan),
                dict(t_max="240")]:
        with pytest.raises(ConfigError):
            KWearParams(**bad)
    with pytest.raises(ValueError):
        kwear_step(np.zeros(5), np.ones(5), -0.1, P)


@settings(max_examples=200, deadline=None)
@given(st.lists(V01, min_size=5, max_size=5), st.lists(G, min_size=5, max_size=5), DT,
       st.lists(st.booleans(), min_size=5, max_size=5))
def test_v_stays_in_unit_interval(v, g, dt, rest):
    for resting in (False, True, np.array(rest)):
        out = kwear_step(np.array(v), np.array(g), dt, P, resting=resting)
        assert out.shape == (5,) and np.all(out >= 0.0) and np.all(out < 1.0)


def test_v_below_one_even_after_very_long_wear():
    v = kwear_step(np.zeros(5), np.full(5, 9.0), 1e5, P)
    assert np.all(v < 1.0) and np.all(v == V_CEIL)


@settings(max_examples=100, deadline=None)
@given(V01, G, G, DT, DT)
def test_wear_monotone_in_g_and_time(v0, g1, g2, t1, t2):
    v = np.array([v0])
    lo_g, hi_g = sorted((g1, g2))
    lo_t, hi_t = sorted((t1, t2))
    assert kwear_step(v, [lo_g], hi_t, P)[0] <= kwear_step(v, [hi_g], hi_t, P)[0]
    assert kwear_step(v, [hi_g], lo_t, P)[0] <= kwear_step(v, [hi_g], hi_t, P)[0]
    assert kwear_step(v, [hi_g], hi_t, P)[0] >= v0  # wear never lowers V


@settings(max_examples=100, deadline=None)
@given(V01, DT, DT)
def test_recovery_decays_towards_zero(v0, t1, t2):
    lo_t, hi_t = sorted((t1, t2))
    v = np.array([v0])
    a = kwear_step(v, [5.0], lo_t, P, resting=True)[0]
    b = kwear_step(v, [5.0], hi_t, P, resting=True)[0]
    assert 0.0 <= b <= a <= v0
    assert kwear_step(v, [0.0], 20 * P.C / P.r, P, resting=True)[0] <= v0 * math.exp(-20) + 1e-300


@settings(max_examples=15, deadline=None)
@given(st.lists(st.tuples(G, st.floats(0.01, 5.0), st.booleans()), min_size=1, max_size=8), V01)
def test_closed_form_matches_scipy_ode(segments, v0):
    """Piecewise-constant G: the exact tick agrees with an accurate numerical solution of eq. 3."""
    v_exact = np.array([v0])
    v_ode = v0
    for g, dt, rest in segments:
        v_exact = kwear_step(v_exact, [g], dt, P, resting=rest)

        def rhs(_t, y, g=g, rest=rest):
            return -y * P.r / P.C if rest else (1.0 - y) * abs(g) / P.C

        sol = solve_ivp(rhs, (0.0, dt), [v_ode], method="DOP853", rtol=1e-12, atol=1e-14)
        v_ode = float(sol.y[0, -1])
        assert abs(v_exact[0] - v_ode) < 1e-6


def test_trajectory_equals_steps_and_mixed_resting():
    rng = np.random.default_rng(3)
    g = rng.integers(1, 7, size=(50, 5)).astype(float)
    rest = rng.random(50) < 0.3
    traj = kwear_trajectory(np.zeros(5), g, 0.05, P, resting=rest)
    v = np.zeros(5)
    for k in range(50):
        v = kwear_step(v, g[k], 0.05, P, resting=bool(rest[k]))
        np.testing.assert_array_equal(traj[k], v)
    per_joint = np.zeros((50, 5), dtype=bool)
    per_joint[:, 2] = True
    t2 = kwear_trajectory(np.full(5, 0.5), g, 0.05, P, resting=per_joint)
    assert t2[-1, 2] == pytest.approx(0.5 * math.exp(-P.r * 2.5 / P.C)) and np.all(t2[-1, [0, 1, 3, 4]] > 0.5)


@settings(max_examples=50, deadline=None)
@given(st.lists(V01, min_size=5, max_size=5), st.lists(G, min_size=5, max_size=5), st.integers(1, 400))
def test_prediction_equals_simulation_for_constant_g(v0, g, n):
    """eq. 9 with alpha = exp(-int G/C) reproduces the tick-by-tick simulation of a constant-G action."""
    g_traj = np.tile(g, (n, 1))
    alpha = alpha_of(g_traj, 0.05, P)
    np.testing.assert_allclose(alpha, np.exp(-np.array(g) * n * 0.05 / P.C), rtol=1e-12)
    sim = kwear_trajectory(np.array(v0), g_traj, 0.05, P)[-1]
    np.testing.assert_allclose(predict(np.array(v0), alpha), sim, atol=1e-12)
    # from zero wear alpha = 1 - V_end (the calibration identity)
    np.testing.assert_allclose(1.0 - kwear_trajectory(np.zeros(5), g_traj, 0.05, P)[-1], alpha, atol=1e-12)


def test_predict_broadcasts_over_actions():
    v = np.array([0.1, 0.2, 0.3, 0.4, 0.5])
    alpha = np.array([[1.0] * 5, [0.5] * 5])
    out = predict(v, alpha)
    assert out.shape == (2, 5)
    np.testing.assert_allclose(out[0], v)
    np.testing.assert_allclose(out[1], 1 - 0.5 * (1 - v))


def test_nan_scores_hold_v_and_out_buffer():
    v = np.array([0.1, 0.2, 0.3, 0.4, 0.5])
    g = np.array([3.0, np.nan, 3.0, np.inf, 3.0])
    new = kwear_step(v, g, 1.0, P)
    assert new[1] == 0.2 and new[3] == 0.4 and np.all(new[[0, 2, 4]] > v[[0, 2, 4]])
    assert alpha_of(np.array([[np.nan] * 5, [3.0] * 5]), 1.0, P)[0] == pytest.approx(math.exp(-3 / P.C))
    buf = v.copy()
    res = kwear_step(buf, np.full(5, 2.0), 0.05, P, out=buf)
    assert res is buf and np.all(buf > v)
    res = kwear_step(buf, np.full(5, 2.0), 0.05, P, resting=True, out=buf)
    assert res is buf
