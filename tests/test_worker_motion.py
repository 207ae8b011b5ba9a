"""Worker motion: IK reaches where the part lies, priors make risk follow geometry, timing, determinism."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from worker_scene import PointScene

from ergosim.human import HumanModel
from ergosim.posture import HUMAN_JOINTS, STANCE
from ergosim.worker import StandingArea, Subject, Worker, interpolate_keyframes, make_subject, min_jerk

IDX = {n: i for i, n in enumerate(HUMAN_JOINTS)}
GEOM = SimpleNamespace(action="a", part="part", kind="insert", target="target")


@pytest.fixture(scope="module")
def worker():
    return Worker(Subject("T", variability_deg=0.0))


def _plan(worker, part_pos, target_pos=(0.45, 0.0, 0.95), seed=0, **kw):
    scene = PointScene(worker.subject, part_pos, target_pos, **kw)
    return scene, worker.plan(scene, GEOM, np.random.default_rng(seed))


@pytest.mark.parametrize(
    "part_pos",
    [(0.35, -0.15, 0.95), (0.7, 0.0, 0.95), (0.25, -0.5, 1.75), (0.4, 0.55, 1.0), (-0.1, -0.6, 1.2)],
)
def test_hand_reaches_the_part_in_the_scene_within_2cm(worker, part_pos):
    scene, motion = _plan(worker, part_pos, worker_pos=(0.2, 0.3, 0.0), yaw=0.4)
    human = HumanModel(scene.model)
    k = int(np.searchsorted(motion.t, motion.t_grasp)) - 1  # last frame of the grasp phase
    human.set_body(scene.data, motion.angles[k], motion.stances[k])
    part = scene.body_pose("part")[0]
    assert np.linalg.norm(human.hand_pos(scene.data) - part) < 0.02
    assert np.linalg.norm(motion.hand_pos[k] - part) < 0.02
    # and the part is carried to the target
    k = int(np.searchsorted(motion.t, motion.t_release)) - 1
    human.set_body(scene.data, motion.angles[k], motion.stances[k])
    assert np.linalg.norm(human.hand_pos(scene.data) - scene.site_pose("target")[0]) < 0.02


def test_motion_starts_and_ends_at_rest_and_is_smooth(worker):
    _, motion = _plan(worker, (0.5, -0.2, 1.0))
    np.testing.assert_allclose(motion.angles[0], worker.rest, atol=1e-9)
    np.testing.assert_allclose(motion.angles[-1], worker.rest, atol=1e-9)
    assert np.all(np.diff(motion.t) > 0) and motion.t[1] == pytest.approx(1 / 60)
    speed = np.abs(np.diff(motion.angles, axis=0)).max() * 60.0
    assert speed < 400.0  # deg/s: no jumps between frames
    names = [p.name for p in motion.phases]
    assert names == ["reach", "grasp", "carry", "insert", "release", "return"]
    assert 0 < motion.t_grasp < motion.t_release < motion.duration


def test_higher_shelf_raises_the_arm(worker):
    _, low = _plan(worker, (0.3, -0.45, 1.25))
    _, high = _plan(worker, (0.3, -0.45, 1.80))

    def peak_elevation(m):
        f = np.deg2rad(m.angles[:, IDX["shoulder_flexion"]])
        a = np.deg2rad(m.angles[:, IDX["shoulder_abduction"]])
        return np.rad2deg(np.arccos(np.cos(f) * np.cos(a))).max()  # humerus angle from the vertical

    assert peak_elevation(high) > peak_elevation(low) + 25.0


PLANTED = StandingArea.planted()


def test_farther_piece_bends_the_trunk_with_the_feet_planted_and_steps_when_free(worker):
    _, near = _plan(worker, (0.4, -0.2, 0.95), standing_area=PLANTED)
    _, far = _plan(worker, (0.85, -0.2, 0.95), standing_area=PLANTED)
    assert near.angles[:, IDX["trunk_flexion"]].max() < 20.0
    assert far.angles[:, IDX["trunk_flexion"]].max() > near.angles[:, IDX["trunk_flexion"]].max() + 20.0
    assert not far.stances[:, :3].any()  # the feet stay on the spot (the knees and ankles may move)
    _, stepping = _plan(worker, (0.85, -0.2, 0.95))
    assert stepping.stances[:, STANCE.index("pelvis_x")].max() > 0.1  # a step towards the piece
    assert stepping.angles[:, IDX["trunk_flexion"]].max() < far.angles[:, IDX["trunk_flexion"]].max() - 10.0


def test_target_to_the_side_turns_trunk_and_body_and_near_low_flexes_the_neck(worker):
    _, ledge = _plan(worker, (0.45, 0.0, 0.95), target_pos=(-0.1, -0.6, 1.2), standing_area=PLANTED)
    assert ledge.angles[:, IDX["trunk_rotation"]].min() < -10.0
    assert ledge.angles[:, IDX["neck_rotation"]].min() < -20.0
    _, turning = _plan(worker, (0.45, 0.0, 0.95), target_pos=(-0.1, -0.6, 1.2))
    assert turning.stances[:, STANCE.index("pelvis_rotation")].min() < -45.0  # the body turns to the ledge
    assert "TBC1" in turning.mtm
    _, close = _plan(worker, (0.3, -0.1, 0.9), target_pos=(0.35, 0.0, 0.9))
    assert close.angles[:, IDX["neck_flexion"]].max() > 25.0


def test_a_low_target_bends_the_knees_and_times_bend_and_arise(worker):
    _, low = _plan(worker, (0.45, 0.0, 0.95), target_pos=(0.4, 0.0, 0.25), standing_area=PLANTED)
    assert low.stances[:, STANCE.index("knee_flexion")].max() > 30.0
    assert " B " in f" {low.mtm} " and " AB" in f" {low.mtm}"


def test_same_seed_same_motion(worker):
    subject = make_subject(np.random.default_rng(5))
    w = Worker(subject)
    a = w.plan(PointScene(subject, (0.5, -0.3, 1.1), (0.4, 0.0, 0.95)), GEOM, np.random.default_rng(9))
    b = w.plan(PointScene(subject, (0.5, -0.3, 1.1), (0.4, 0.0, 0.95)), GEOM, np.random.default_rng(9))
    c = w.plan(PointScene(subject, (0.5, -0.3, 1.1), (0.4, 0.0, 0.95)), GEOM, np.random.default_rng(10))
    assert np.array_equal(a.angles, b.angles) and np.array_equal(a.t, b.t)
    assert not np.array_equal(a.angles, c.angles)


def test_min_jerk():
    tau = np.linspace(0, 1, 101)
    s = min_jerk(tau)
    assert s[0] == 0 and s[-1] == pytest.approx(1) and s[50] == pytest.approx(0.5)
    assert np.all(np.diff(s) >= 0)
    keys = np.array([[0.0], [10.0], [10.0]])
    v = interpolate_keyframes(np.array([0.0, 1.0, 2.0]), keys, np.array([0.5, 1.5]))
    np.testing.assert_allclose(v[:, 0], [5.0, 10.0])
