"""Time scaling: the trapezoid and the piecewise-capped fastest profile, against each other and the caps."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ergosim.robot.time_scaling import speed_profile, trapezoid

DT = 0.002


@pytest.mark.parametrize("distance", [0.004, 0.05, 0.1, 1.0])
def test_one_piece_is_the_trapezoid(distance):
    a = trapezoid(distance, 0.05, 0.25, DT) * distance
    b = speed_profile(np.array([distance]), np.array([0.05]), np.array([0.25]), DT)
    assert len(a) == len(b)
    np.testing.assert_allclose(a, b, atol=1e-5)


def _speeds(x: np.ndarray) -> np.ndarray:
    return np.diff(np.concatenate([[0.0], x])) / DT


def test_a_slow_last_piece_is_entered_at_its_speed_without_stopping():
    # 5 cm at 0.25 m/s (1 m/s^2), then 5 cm at 0.05 m/s (0.25 m/s^2): the contact-critical end of an approach
    x = speed_profile(np.array([0.05, 0.05]), np.array([0.25, 0.05]), np.array([1.0, 0.25]), DT)
    v = _speeds(x)
    assert x[-1] == 0.1 and np.all(np.diff(x) >= 0)
    assert v[x > 0.05 + 1e-9].max() <= 0.05 * 1.01  # the slow piece never runs faster than its cap
    assert v.max() > 0.2  # the fast piece does use its speed
    assert v[np.argmin(np.abs(x - 0.05))] > 0.045  # it does not stop at the boundary
    # faster than the whole 10 cm at the slow speed, slower than the whole at the fast one
    assert trapezoid(0.1, 0.25, 1.0, DT).size < x.size < trapezoid(0.1, 0.05, 0.25, DT).size


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.floats(1e-3, 0.3), st.floats(0.02, 0.5), st.floats(0.1, 2.0)),
                min_size=1, max_size=6))
def test_every_piece_keeps_its_cap_and_the_motion_ends_at_rest(pieces):
    steps, caps, accels = (np.array(c) for c in zip(*pieces, strict=True))
    x = speed_profile(steps, caps, accels, DT)
    edges = np.concatenate([[0.0], np.cumsum(steps)])
    assert x[-1] == pytest.approx(edges[-1], abs=1e-12)
    assert np.all(np.diff(x) >= -1e-15)
    v = _speeds(x)
    prev = np.concatenate([[0.0], x[:-1]])
    for i in range(len(steps)):  # a step wholly inside piece i runs at most at its cap
        inside = (prev >= edges[i]) & (x <= edges[i + 1])
        if inside.any():
            assert v[inside].max() <= caps[i] * (1 + 1e-6) + 1e-9
    # the fastest profile is no slower than the slowest single cap over the whole length
    assert x.size <= trapezoid(edges[-1], caps.min(), accels.min(), DT).size + 1
