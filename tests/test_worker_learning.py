"""The learning-curve pace and where the bundled scenarios take their pace from."""

from __future__ import annotations

import pytest

from ergosim.errors import ConfigError
from ergosim.twin.scenariofile import load_scenario
from ergosim.worker.learning import learning_curve_pace


def test_wright_curve_halves_time_per_doubling_at_the_learning_rate():
    assert learning_curve_pace(1000) == pytest.approx(1.0)
    # one doubling fewer executions: the time is one learning rate slower
    assert learning_curve_pace(500) == pytest.approx(0.9)
    assert learning_curve_pace(250, learning_rate=0.8) == pytest.approx(0.64)
    with pytest.raises(ConfigError, match="executions"):
        learning_curve_pace(0)


def test_multi_subject_pace_is_the_learning_curve_at_the_sessions_middle():
    """§7.2: η = 3 calibration executions and 10 repetitions of the first condition: execution 13."""
    assert load_scenario("multi-subject").protocol.pace == pytest.approx(round(learning_curve_pace(13), 2))
