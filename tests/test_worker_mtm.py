"""MTM-1 element times and the worker's action timing built from them."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from worker_scene import PointScene

from ergosim.errors import ConfigError
from ergosim.worker import Worker, action_timing, make_subject
from ergosim.worker.action_timing import N_SEGMENTS
from ergosim.worker.mtm import INCH_M, TMU_S, move_tmu, reach_tmu, tmu_to_s, turn_tmu


@pytest.mark.parametrize(("inches", "case", "tmu"), [
    (10, "A", 8.7), (10, "B", 11.5), (10, "C", 12.9), (10, "E", 10.5),
    (20, "B", 18.6), (30, "B", 25.8), (4, "E", 6.8), (0.5, "B", 2.0),
])
def test_reach_table_at_tabulated_distances(inches, case, tmu):
    assert reach_tmu(inches * INCH_M, case) == pytest.approx(tmu)


@pytest.mark.parametrize(("inches", "case", "tmu"), [(10, "A", 11.3), (10, "B", 12.2), (20, "C", 22.1),
                                                      (30, "B", 24.3), (6, "C", 10.3)])
def test_move_table_at_tabulated_distances(inches, case, tmu):
    assert move_tmu(inches * INCH_M, case) == pytest.approx(tmu)


def test_tables_continue_beyond_30_inches_and_interpolate_between():
    assert reach_tmu(40 * INCH_M, "B") == pytest.approx(25.8 + 10 * 0.7)
    assert move_tmu(36 * INCH_M, "C") == pytest.approx(30.7 + 6 * 0.85)
    assert reach_tmu(11 * INCH_M, "B") == pytest.approx((11.5 + 12.9) / 2)
    d = np.linspace(0.0, 1.2, 200)
    assert np.all(np.diff([reach_tmu(x, "B") for x in d]) >= 0)  # farther is never quicker
    assert tmu_to_s(1.0) == TMU_S == 0.036


def test_turns_and_unknown_cases():
    assert turn_tmu(90) == pytest.approx(5.4) and turn_tmu(360) == pytest.approx(2 * 9.4)
    with pytest.raises(ConfigError, match="unknown MTM-1 reach case 'Z'"):
        reach_tmu(0.3, "Z")


def _hands(reach=0.5, move=0.4, back=0.45) -> np.ndarray:
    """Key-pose hand positions whose reach, move and return paths have the given lengths [m]."""
    steps = [reach * 0.8, reach * 0.2, 0.0, move * 0.2, move * 0.6, move * 0.2, 0.0, 0.0,
             back * 0.3, back * 0.7]
    x = np.concatenate([[0.0], np.cumsum(steps)])
    return np.stack([x, np.zeros_like(x), np.zeros_like(x)], axis=1)


def test_action_timing_follows_the_elements():
    place = action_timing(_hands(), seats=False)
    insert = action_timing(_hands(), seats=True)
    fasten = action_timing(_hands(), seats=True, turn_time=2.0)
    taken = action_timing(_hands(), seats=True, handover=True)
    assert place.durations.shape == (N_SEGMENTS,)
    # P2SS + AP2 against P1SS; the move is case C (exact location) instead of B
    assert insert.durations[6] - place.durations[6] == pytest.approx(tmu_to_s(19.7 + 10.6 - 9.1))
    assert insert.durations[3:6].sum() == pytest.approx(tmu_to_s(move_tmu(0.4, "C")))
    assert place.durations[3:6].sum() == pytest.approx(tmu_to_s(move_tmu(0.4, "B")))
    assert fasten.durations[6] == pytest.approx(tmu_to_s(16.2 + 10.6) + 2.0)
    # a part held out by the robot: reach case A
    assert taken.durations[:2].sum() == pytest.approx(tmu_to_s(reach_tmu(0.5, "A")))
    assert taken.total < insert.total
    assert place.durations[8:].sum() == pytest.approx(tmu_to_s(reach_tmu(0.45, "E")))
    assert insert.analysis == "R20B G1A M16C P2SS AP2 RL1 R18E"
    # segments share their element's time in proportion to their path length
    assert place.durations[0] / place.durations[1] == pytest.approx(4.0)


def test_action_timing_checks_its_input():
    with pytest.raises(ValueError, match="11, 3"):
        action_timing(np.zeros((5, 3)), seats=False)


def test_worker_actions_take_mtm_time_at_the_subjects_pace():
    geom = SimpleNamespace(action="a", part="part", kind="insert", target="target")
    base = make_subject(np.random.default_rng(5), timing_variability=0.0, speed=1.0)
    fast = make_subject(np.random.default_rng(5), timing_variability=0.0, speed=2.0)
    scene = PointScene(base, (0.5, -0.3, 1.1), (0.4, 0.0, 0.95))
    a = Worker(base).plan(scene, geom, np.random.default_rng(1))
    scene_fast = PointScene(fast, (0.5, -0.3, 1.1), (0.4, 0.0, 0.95))
    b = Worker(fast).plan(scene_fast, geom, np.random.default_rng(1))
    # twice as fast wherever MTM-1 sets the time (segments slowed by the joint-speed cap stay as they are)
    assert b.duration < 0.75 * a.duration
    assert a.mtm.startswith("R") and "P2SS AP2" in a.mtm
    assert 1.5 < a.duration < 6.0  # a reach-insert-return of a trained worker takes seconds, not tens


def test_body_motions_are_mtm1_table_x():
    from ergosim.worker.mtm import BODY_TMU, sidestep_tmu, turn_body_tmu  # noqa: PLC0415

    assert sidestep_tmu(11 * 0.0254) == 0.0  # under 12 in: the step goes with the Reach or Move
    assert sidestep_tmu(12 * 0.0254) == pytest.approx(17.0)
    assert sidestep_tmu(20 * 0.0254) == pytest.approx(17.0 + 0.6 * 8)
    assert turn_body_tmu(40.0) == 0.0 and turn_body_tmu(-60.0) == pytest.approx(18.6)
    assert turn_body_tmu(120.0) == pytest.approx(2 * 18.6)
    assert BODY_TMU["B"] == 29.0 and BODY_TMU["AB"] == 31.9


def test_a_body_motion_and_its_hand_motion_take_the_longer_time_and_a_regrasp_adds_its_own():
    from ergosim.worker.action_timing import action_timing, body_motion  # noqa: PLC0415
    from ergosim.worker.mtm import reach_tmu, tmu_to_s, turn_tmu  # noqa: PLC0415

    hands = np.zeros((11, 3))
    hands[1:9] = [0.1, 0.0, 0.0]  # a 10 cm reach, no move, a 10 cm return
    stances = np.zeros((11, 4))
    stances[1:9] = [0.0, 0.5, 80.0, 40.0]  # a 50 cm sidestep, an 80 deg turn, a bend
    still = action_timing(hands, seats=False)
    moving = action_timing(hands, seats=False, stances=stances)
    tmu, words = body_motion(stances[0], stances[2])
    assert words == ["SS20C1", "TBC1", "B"]
    assert tmu == pytest.approx(17.0 + 0.6 * (0.5 / 0.0254 - 12) + 18.6 + 29.0)
    assert moving.durations[:2].sum() == pytest.approx(tmu_to_s(max(reach_tmu(0.1, "B"), tmu)))
    assert still.durations[:2].sum() == pytest.approx(tmu_to_s(reach_tmu(0.1, "B")))
    assert "SS20C1 TBC1 B" in moving.analysis and moving.analysis.endswith("SS20C1 TBC1 AB")
    turned = action_timing(hands, seats=True, regrasp_deg=120.0)
    assert "T120S G2" in turned.analysis
    plain = action_timing(hands, seats=True)
    extra = turned.durations[3:6].sum() - plain.durations[3:6].sum()
    assert extra == pytest.approx(tmu_to_s(max(turn_tmu(120.0), 2.0) - 2.0 + 5.6), abs=0.05)
