"""The fast paths of a replay give the bits of the plain ones: Euler matrices and constant products against
np.matmul, KWear over all ticks against tick-by-tick steps, the mapping of a sample of frames against the
whole mapping, and replay_ticks against replay."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from ergosim.ergonomics.kwear import KWearParams, kwear_step, kwear_trajectory
from ergosim.posture import ANGLE_NAMES
from ergosim.worker import replay, replay_ticks, tick_indices
from ergosim.worker.bvh import recording_from_data
from ergosim.worker.bvh_chains import CHAINS, HeldFrame, decompose
from ergosim.worker.bvh_euler import axis_rotation, euler_to_matrix
from ergosim.worker.bvh_export import export_skeleton, format_bvh
from ergosim.worker.bvh_mapping import map_skeleton, recording_angles
from ergosim.worker.bvh_parse import parse_bvh_text
from ergosim.worker.bvh_products import const_times, times_const

SPECIAL = np.deg2rad([0.0, -0.0, 90.0, -90.0, 180.0, -180.0, 45.0, 1e-7, 360.0])


def _bits(x) -> np.ndarray:
    return np.ascontiguousarray(x, dtype=float).view(np.uint64)


def _matmul_chain(angles: np.ndarray, order: str) -> np.ndarray:
    """The plain product I @ R_1 @ R_2 @ R_3, one np.matmul per rotation."""
    r = np.broadcast_to(np.eye(3), angles.shape[:-1] + (3, 3)).copy()
    for k, ax in enumerate(order):
        r = r @ axis_rotation("XYZ".index(ax), angles[..., k])
    return r


@pytest.mark.parametrize("order", ["".join(p) for n in (1, 2, 3) for p in itertools.product("XYZ", repeat=n)])
def test_euler_matrices_have_the_bits_of_the_matmul_chain(order):
    rng = np.random.default_rng(len(order) * 100 + sum(map(ord, order)))
    n = 3000
    cases = [rng.uniform(-np.pi, np.pi, (n, len(order))), rng.choice(SPECIAL, (n, len(order)))]
    whole_zero = rng.uniform(-np.pi, np.pi, (n, len(order)))
    whole_zero[:, -1] = rng.choice([0.0, -0.0], n)  # an angle that is zero in every frame
    cases += [whole_zero, rng.uniform(-np.pi, np.pi, len(order))]  # and a single frame
    for a in cases:
        assert np.array_equal(_bits(euler_to_matrix(a, order)), _bits(_matmul_chain(a, order)))


def test_constant_products_have_the_bits_of_matmul():
    rng = np.random.default_rng(0)
    g = rng.choice([0.0, -0.0, 1.0, -1.0, 0.3, -2.5], (2000, 3, 3))
    g[1000:] = rng.normal(size=(1000, 3, 3))
    turn = np.array([[0, 1.0, 0], [0, 0, 1], [1, 0, 0]])
    for c in (rng.normal(size=(3, 3)), np.diag([1.0, -1.0, 1.0]), turn):
        assert np.array_equal(_bits(const_times(c, g)), _bits(c @ g))
        assert np.array_equal(_bits(times_const(g, c)), _bits(g @ c))
        assert np.array_equal(_bits(times_const(g[3], c)), _bits(g[3] @ c))


def _kwear_steps(v0, g, dt, params, resting):
    n, m = g.shape
    dts = np.broadcast_to(np.asarray(dt, dtype=float), (n,))
    rest = np.broadcast_to(np.asarray(resting, dtype=bool), (n,) if np.ndim(resting) <= 1 else (n, m))
    v, out = np.array(v0, dtype=float), np.empty((n, m))
    for k in range(n):
        r = rest[k]
        v = kwear_step(v, g[k], float(dts[k]), params, resting=bool(r) if np.ndim(r) == 0 else r)
        out[k] = v
    return out


@pytest.mark.parametrize("case", range(8))
def test_kwear_trajectory_has_the_bits_of_its_steps(case):
    rng = np.random.default_rng(case)
    n = 2000
    g = rng.integers(0, 8, (n, 5)).astype(float)
    g[rng.random(n) < 0.05] = np.nan  # dropouts
    if case % 2:
        g[rng.random((n, 5)) < 0.01] = np.inf
    dt = 0.05 if case < 4 else rng.uniform(0.0, 0.2, n)
    resting = [False, True, rng.random(n) < 0.3, rng.random((n, 5)) < 0.3][case % 4]
    v0 = rng.random(5) * 0.9
    params = KWearParams(t_max=5.0) if case == 7 else KWearParams()  # case 7 reaches the ceiling
    got = kwear_trajectory(v0, g, dt, params, resting)
    assert np.array_equal(_bits(got), _bits(_kwear_steps(v0, g, dt, params, resting)))


def test_kwear_trajectory_refuses_a_negative_tick():
    with pytest.raises(ValueError, match="dt must be >= 0 s, got -0.1"):
        kwear_trajectory(np.zeros(5), np.ones((3, 5)), np.array([0.05, -0.1, 0.05]), KWearParams())


@pytest.fixture(scope="module")
def stress_recording():
    """Random rotations on every channel of the project's skeleton, T-pose frames (gimbal lock at the
    shoulders) at the start and in the middle of the second batch of frames."""
    rng = np.random.default_rng(7)
    joints = export_skeleton()
    n = 20000
    motion = rng.uniform(-180.0, 180.0, (n, sum(len(j.channels) for j in joints)))
    mask = rng.random(motion.shape) < 0.15
    motion[mask] = rng.choice([0.0, -0.0, 90.0, -90.0, 180.0, 45.0], mask.sum())
    motion[:40] = 0.0
    motion[9000:9007] = 0.0
    return parse_bvh_text(format_bvh(joints, 1 / 60, motion), "stress.bvh")


@pytest.mark.slow
@pytest.mark.parametrize("reference", ["vertical", "pelvis"])
def test_a_sample_of_frames_maps_to_the_bits_of_the_whole_mapping(stress_recording, reference):
    data = stress_recording
    smap = map_skeleton(data)
    whole = recording_angles(data, smap, reference)
    rng = np.random.default_rng(1)
    for frames in (tick_indices(data.n_frames, 60.0, 20.0), np.sort(rng.choice(data.n_frames, 500, False)),
                   np.arange(9000, 9010), np.array([], dtype=int)):
        part = recording_angles(data, smap, reference, frames)
        assert set(part) == set(whole)
        for name, values in part.items():
            assert np.array_equal(_bits(values), _bits(whole[name][frames])), name


def test_a_frame_in_gimbal_lock_among_a_sample_asks_for_its_frames(stress_recording):
    smap = map_skeleton(stress_recording)
    from ergosim.worker.bvh_mapping import segment_frames  # noqa: PLC0415

    seg = segment_frames(stress_recording, smap, np.arange(0, 30, 3))
    r = np.swapaxes(seg["right_clavicle"], -1, -2) @ seg["right_upper_arm"]
    with pytest.raises(HeldFrame):
        decompose(CHAINS["shoulder"], r, consecutive=False)
    assert decompose(CHAINS["shoulder"], r)["shoulder_abduction"].shape == (10,)


def test_replay_ticks_of_a_sampled_recording_is_the_replay_of_the_whole(stress_recording):
    data = stress_recording
    whole = recording_from_data(data)
    idx = tick_indices(data.n_frames, data.rate_hz, 20.0)
    sampled = recording_from_data(data, frames=idx)
    assert np.array_equal(sampled.frames, idx)
    assert np.array_equal(sampled.t, whole.t[idx])
    a = replay(whole.array(ANGLE_NAMES), data.rate_hz)
    b = replay_ticks(sampled.array(ANGLE_NAMES), sampled.frames)
    assert np.array_equal(_bits(a.table()), _bits(b.table()))
    assert np.array_equal(a.frame, b.frame)
