"""Posture features are registered, each with its score hook: a new index with a feature of its own is one
module (tests/extension_trunk.py), run here through a real session."""

from __future__ import annotations

import extension_trunk
import numpy as np
import pytest

from ergosim.ergonomics.features import FEATURES, Frames, feature
from ergosim.experiment.runner import run_subject
from ergosim.experiment.scenario import load_scenario
from ergosim.experiment.subject import calibrate_subject
from ergosim.posture import ANGLE_NAMES
from ergosim.twin.features import FeatureScorer


def test_the_trunk_zone_hook_on_hand_made_frames():
    flexion = np.array([10.0, 20.0, 30.0, 60.0, 70.0, -5.0, np.nan])
    angles = np.zeros((len(flexion), len(ANGLE_NAMES)))
    angles[:, ANGLE_NAMES.index("trunk_flexion")] = flexion
    got = extension_trunk.trunk_zone(Frames(angles, np.zeros(len(flexion)), 0))
    np.testing.assert_array_equal(got.whole, [1, 1, 2, 2, 3, 3, np.nan])
    assert got.g.shape == got.columns.shape == (len(flexion), 1)


def test_a_registered_feature_is_scored_by_its_hook_and_rula_by_the_track():
    assert {"rula", "reba", "angles", "iso-trunk"} <= set(FEATURES)
    assert feature("rula").score is None and FeatureScorer.of(["rula"], cell=None) is None
    scorer = FeatureScorer(["rula", "reba", "iso-trunk"])
    assert [f.name for f in scorer.features] == ["reba", "iso-trunk"]
    assert scorer.columns == (*feature("reba").columns, "iso_trunk_zone")


@pytest.mark.slow
def test_an_index_with_its_own_feature_runs_through_a_real_session():
    """The mode's calibration, its tick column and its costs all come from the new feature: the worker's
    hyper-arc of an action costs its zone G(a_k) / 3 (plus Γ at zone 3, eq. 11 with the static rule)."""
    sc = load_scenario("multi-subject", {"repetitions": "1", "modes": "iso-trunk"})
    _, calibrations, _ = calibrate_subject(sc, 0, 0)
    zones = calibrations["iso-trunk"].grand_scores
    assert set(zones) == set(sc.task().actions) and set(zones.values()) <= {1.0, 2.0, 3.0}
    run = run_subject(sc, 0, 0, ("iso-trunk",)).runs["iso-trunk"]
    assert run.ticks.columns[-1] == "iso_trunk_zone"
    acting = run.ticks.column("acting") == 1
    logged = run.ticks.column("iso_trunk_zone")[acting]
    angles = np.zeros((acting.sum(), len(ANGLE_NAMES)))
    angles[:, ANGLE_NAMES.index("trunk_flexion")] = run.ticks.column("trunk_flexion")[acting]
    np.testing.assert_array_equal(logged, extension_trunk.trunk_zone(Frames(angles, angles[:, 0], 0)).whole)
    gamma = sc.protocol.cost.gamma
    done = [a for a in run.allocations if a.done]
    assert len(done) == len(sc.task().actions)
    for a in done:
        g = zones[a.action]
        assert a.human_cost == pytest.approx(g / 3 + (gamma if g >= 3 else 0.0))
        assert (a.agent == "robot") == (a.had_choice and g >= 3)
