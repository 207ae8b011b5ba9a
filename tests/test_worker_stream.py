"""Mocap stream: seeded noise and dropouts, bit-for-bit reproducibility, playback into the scene."""

from __future__ import annotations

from types import SimpleNamespace

import mujoco
import numpy as np
import pytest
from worker_scene import PointScene

from ergosim.worker import MocapStream, MotionPlayback, Subject, Worker, make_subject, make_subjects

GEOM = SimpleNamespace(action="a", part="part", kind="place", target="target")


@pytest.fixture(scope="module")
def planned():
    subject = make_subject(np.random.default_rng(11), "S01")
    worker = Worker(subject)
    scene = PointScene(subject, (0.5, -0.3, 1.0), (0.4, 0.1, 0.95))
    return subject, scene, worker.plan(scene, GEOM, np.random.default_rng(2))


def _record(subject, motion, seed, **kw):
    stream = MocapStream(subject, np.random.default_rng(seed), **kw)
    a = stream.measure(motion.angles)
    b = stream.measure(motion.angles, t0=motion.duration)
    return stream, a, b


def test_same_seed_same_stream_bit_for_bit(planned):
    subject, _, motion = planned
    _, a1, b1 = _record(subject, motion, 7, dropout_rate=0.02)
    _, a2, b2 = _record(subject, motion, 7, dropout_rate=0.02)
    _, a3, _ = _record(subject, motion, 8, dropout_rate=0.02)
    assert a1.angles.tobytes() == a2.angles.tobytes() and b1.angles.tobytes() == b2.angles.tobytes()
    assert a1.angles.tobytes() != a3.angles.tobytes()


def test_noise_is_a_few_degrees_with_drifting_bias(planned):
    subject, _, motion = planned
    _, a, _ = _record(subject, motion, 1)
    err = a.angles - motion.angles
    assert 0.3 < np.std(err) < 5.0
    assert np.abs(err).max() < 20.0
    # the bias drifts slowly: neighbouring frames' errors are strongly correlated through it
    d = np.diff(err, axis=0)
    assert np.std(d) < np.std(err) * 1.6
    clean = MocapStream(subject, np.random.default_rng(1), noise=False).measure(motion.angles)
    np.testing.assert_array_equal(clean.angles, motion.angles)


def test_dropouts_are_nan_frames_and_counted(planned):
    subject, _, motion = planned
    stream, a, b = _record(subject, motion, 3, dropout_rate=0.03, dropout_frames=4)
    nan_rows = np.isnan(a.angles).all(axis=1)
    assert np.array_equal(nan_rows, ~a.valid)
    assert not np.isnan(a.angles[a.valid]).any()
    assert stream.dropouts == a.dropouts + b.dropouts > 0
    assert stream.frames == 2 * len(motion.t)
    assert a.t[1] - a.t[0] == pytest.approx(1 / 60)


def test_rate_is_configurable(planned):
    subject, _, _ = planned
    frames = MocapStream(subject, np.random.default_rng(0), rate=120.0).measure(np.zeros((5, 22)))
    assert frames.t[1] == pytest.approx(1 / 120)


def test_playback_moves_the_hand_along_the_motion(planned):
    _, scene, motion = planned
    play = MotionPlayback(scene.model)
    play.load(motion.t, motion.angles, motion.stances)
    site = scene.model.site("human_hand_right").id
    for k in (0, len(motion.t) // 3, len(motion.t) // 2, len(motion.t) - 1):
        play.apply(scene.data, motion.t[k], kinematics=True)
        np.testing.assert_allclose(scene.data.site_xpos[site], motion.hand_pos[k], atol=1e-9)
    # between frames, physics steps keep the human where the playback put it (gravity-compensated)
    play.apply(scene.data, 1.0)
    mujoco.mj_step(scene.model, scene.data)
    assert np.all(np.isfinite(scene.data.qpos))


def test_subjects_are_seeded_and_varied():
    a, b = make_subjects(12, seed=4), make_subjects(12, seed=4)
    assert a == b
    assert make_subjects(3, seed=4) == a[:3]
    statures = [s.stature for s in a]
    assert 1.5 <= min(statures) and max(statures) <= 2.0 and np.std(statures) > 0.03
    assert len({s.speed for s in a}) == 12 and len({s.trunk_use for s in a}) == 12
    assert make_subject(np.random.default_rng(0), stature=1.62).stature == 1.62
    assert Subject("x").spec().compile().nq == 22 + 5 + 6  # posture, stance, the joints following the legs


def test_the_drifting_bias_is_lfilters_first_order_recursion_bit_for_bit():
    """The OU bias recursion written frame by frame (ergosim.worker.stream._ou_bias) gives the bits of
    scipy.signal.lfilter, which the stream used before (its import cost every process two seconds)."""
    from scipy.signal import lfilter  # noqa: PLC0415

    from ergosim.worker.stream import _ou_bias  # noqa: PLC0415

    rng = np.random.default_rng(11)
    for n in (0, 1, 2, 37, 900):
        a = float(np.exp(-1.0 / (60.0 * rng.uniform(1.0, 100.0))))
        last = rng.normal(0.0, 2.0, 22)
        w = rng.normal(0.0, rng.uniform(1e-3, 1.0), (n, 22))
        ref, _ = lfilter([1.0], [1.0, -a], w, axis=0, zi=(a * last)[None, :])
        assert _ou_bias(w, a, last).tobytes() == ref.tobytes(), n
